// SPDX-License-Identifier: MIT
#include "src/scene/dem_gdal.h"

#include "src/base/error.h"

#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_vsi.h>
#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <mutex>

namespace plancheck {

namespace {

void register_gdal() {
  static std::once_flag once;
  std::call_once(once, [] { GDALAllRegister(); });
}

// GDAL's messages go to our exceptions, never to stderr (the handler stack
// is per thread).
struct QuietGdal {
  QuietGdal() {
    CPLPushErrorHandler(CPLQuietErrorHandler);
    CPLErrorReset();
  }
  ~QuietGdal() { CPLPopErrorHandler(); }
  QuietGdal(const QuietGdal&) = delete;
  QuietGdal& operator=(const QuietGdal&) = delete;
  static std::string last() {
    const char* m = CPLGetLastErrorMsg();
    return m && *m ? std::string(": ") + m : std::string();
  }
};

struct CloseDataset {
  void operator()(GDALDataset* d) const { GDALClose(GDALDataset::ToHandle(d)); }
};
using DatasetPtr = std::unique_ptr<GDALDataset, CloseDataset>;

const char* kReproject =
    "reproject it to a north-up projected CRS in metres first, e.g. gdalwarp -t_srs \"+proj=eqc +R=1737400 "
    "+units=m\" -r bilinear IN OUT.tif (polar sites: +proj=stere +lat_0=-90)";

class GdalReader final : public DemReader {
 public:
  GdalReader(const std::filesystem::path& file, int band) {
    register_gdal();
    QuietGdal quiet;
    DemSource& s = header_.source;
    s.file = file;
    s.band = band;
    data_.reset(static_cast<GDALDataset*>(
        GDALOpenEx(file.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY, nullptr, nullptr, nullptr)));
    if (!data_) fail(file, "GDAL cannot open it as a raster" + QuietGdal::last());
    s.driver = data_->GetDriverName();
    const int bands = data_->GetRasterCount();
    if (band < 1 || band > bands)
      fail(file, "band " + std::to_string(band) + " out of range (the raster has " + std::to_string(bands) + ")");
    s.raster_cols = data_->GetRasterXSize();
    s.raster_rows = data_->GetRasterYSize();
    if (s.raster_cols < 1 || s.raster_rows < 1) fail(file, "the raster has no pixels");
    double g[6];
    if (data_->GetGeoTransform(g) != CE_None)
      fail(file, "no georeferencing (no geotransform: the cell size is unknown); add it, e.g. gdal_translate -a_ullr "
                 "ULX ULY LRX LRY IN OUT.tif");
    for (double v : g)
      if (!std::isfinite(v)) fail(file, "the geotransform is not finite");
    if (g[2] != 0.0 || g[4] != 0.0) fail(file, std::string("rotated or sheared geotransform; ") + kReproject);
    if (!(g[1] > 0.0) || !(g[5] < 0.0))
      fail(file, std::string("not a north-up grid (pixel size ") + std::to_string(g[1]) + ", " + std::to_string(g[5]) +
                     "); " + kReproject);
    if (std::abs(g[1] + g[5]) > 1e-9 * g[1])
      fail(file, "pixels are not square (" + std::to_string(g[1]) + " x " + std::to_string(-g[5]) +
                     "); resample them, e.g. gdalwarp -tr S S IN OUT.tif");
    std::copy(g, g + 6, s.geotransform.begin());
    header_.cellsize = g[1];
    if (const OGRSpatialReference* srs = data_->GetSpatialRef()) {
      if (srs->IsGeographic()) fail(file, std::string("the CRS is geographic (degrees); ") + kReproject);
      if (srs->IsGeocentric()) fail(file, std::string("the CRS is geocentric; ") + kReproject);
      const char* unit_name = nullptr;
      header_.linear_unit_m = srs->GetLinearUnits(&unit_name);
      if (!(header_.linear_unit_m > 0.0) || !std::isfinite(header_.linear_unit_m))
        fail(file, std::string("the CRS's linear unit is unknown (") + (unit_name ? unit_name : "none") + "); " + kReproject);
      header_.projected = srs->IsProjected();
      char* wkt = nullptr;
      if (srs->exportToWkt(&wkt) == OGRERR_NONE && wkt) s.crs_wkt = wkt;
      CPLFree(wkt);
    }
    GDALRasterBand* b = data_->GetRasterBand(band);
    int ok = 0;
    const double nodata = b->GetNoDataValue(&ok);
    s.has_nodata = ok != 0;
    s.nodata = s.has_nodata ? nodata : 0.0;
    header_.scale = b->GetScale(&ok);
    if (!ok) header_.scale = 1.0;
    header_.offset = b->GetOffset(&ok);
    if (!ok) header_.offset = 0.0;
    if (!std::isfinite(header_.scale) || !std::isfinite(header_.offset) || header_.scale == 0.0)
      fail(file, "band " + std::to_string(band) + ": scale or offset not finite, or zero scale");
    header_.height_unit = b->GetUnitType() ? b->GetUnitType() : "";
  }

 protected:
  void read_raw(const PixelWindow& w, std::vector<double>& raw, std::vector<unsigned char>& hole) override {
    QuietGdal quiet;
    if (static_cast<double>(w.cols) * w.rows > kMaxDemWindowPixels)
      fail(header_.source.file, "the window to read is " + std::to_string(w.cols) + " x " + std::to_string(w.rows) +
                                    " pixels, more than the limit of " + number_text(kMaxDemWindowPixels) +
                                    " (cut the raster with gdal_translate -srcwin, or give the moving parts a bounded reach)");
    const std::size_t count = static_cast<std::size_t>(w.cols) * static_cast<std::size_t>(w.rows);
    raw.assign(count, 0.0);
    GDALRasterBand* b = data_->GetRasterBand(header_.source.band);
    if (b->RasterIO(GF_Read, w.col_off, w.row_off, w.cols, w.rows, raw.data(), w.cols, w.rows, GDT_Float64, 0, 0,
                    nullptr) != CE_None)
      fail(header_.source.file, "GDAL cannot read the window" + QuietGdal::last());
    hole.assign(count, 0);
    if (!header_.source.has_nodata) return;
    const double nd = header_.source.nodata;
    for (std::size_t i = 0; i < count; ++i)
      hole[i] = std::isnan(nd) ? std::isnan(raw[i]) : raw[i] == nd;
  }

 private:
  DatasetPtr data_;
};

}  // namespace

std::unique_ptr<DemReader> open_gdal_dem(const std::filesystem::path& file, int band) {
  return std::make_unique<GdalReader>(file, band);
}

std::string geotiff_bytes(const Dem& dem, double length_scale, double nodata) {
  register_gdal();
  QuietGdal quiet;
  static std::atomic<unsigned long> serial{0};
  char name[96];
  std::snprintf(name, sizeof name, "/vsimem/plancheck-out-%lu.tif", serial.fetch_add(1));
  GDALDriver* gtiff = GetGDALDriverManager()->GetDriverByName("GTiff");
  if (!gtiff) throw std::runtime_error("GDAL has no GTiff driver");
  const char* options[] = {"COMPRESS=DEFLATE", "PREDICTOR=3", nullptr};
  {
    DatasetPtr out(gtiff->Create(name, dem.ncols, dem.nrows, 1, GDT_Float64, const_cast<char**>(options)));
    if (!out) throw std::runtime_error("GDAL cannot create a GeoTIFF" + QuietGdal::last());
    std::array<double, 6> g = dem.source.window_geotransform();
    out->SetGeoTransform(g.data());
    if (!dem.source.crs_wkt.empty()) out->SetProjection(dem.source.crs_wkt.c_str());
    if (dem.source.has_nodata) nodata = dem.source.nodata;
    GDALRasterBand* b = out->GetRasterBand(1);
    b->SetNoDataValue(nodata);
    std::vector<double> row(static_cast<std::size_t>(dem.ncols));
    for (int r = 0; r < dem.nrows; ++r) {  // GDAL's row r is the Dem's row nrows-1-r (north first)
      for (int c = 0; c < dem.ncols; ++c)
        row[static_cast<std::size_t>(c)] =
            dem.is_valid(c, dem.nrows - 1 - r) ? dem.height(c, dem.nrows - 1 - r) / length_scale : nodata;
      if (b->RasterIO(GF_Write, 0, r, dem.ncols, 1, row.data(), dem.ncols, 1, GDT_Float64, 0, 0, nullptr) != CE_None)
        throw std::runtime_error("GDAL cannot write a GeoTIFF" + QuietGdal::last());
    }
  }
  vsi_l_offset size = 0;
  GByte* bytes = VSIGetMemFileBuffer(name, &size, TRUE);
  if (!bytes) throw std::runtime_error("GDAL wrote no GeoTIFF");
  std::string result(reinterpret_cast<const char*>(bytes), static_cast<std::size_t>(size));
  CPLFree(bytes);
  VSIUnlink((std::string(name) + ".aux.xml").c_str());
  return result;
}

}  // namespace plancheck
