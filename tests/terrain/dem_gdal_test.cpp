// SPDX-License-Identifier: MIT
// Rasters through GDAL (src/scene/dem_gdal.cpp) and the window read
// (src/scene/terrain_window.cpp): one synthetic site, written as ESRI ASCII
// by the test and converted with gdal_translate to GeoTIFF (tiled,
// compressed, float32; int16 with scale and offset), PDS4 and ISIS3, gives
// the same grid and the same answers state by state and dig by dig; the
// window gives the whole raster's answers; map_origin equals the equivalent
// origin; holes stay holes; the GeoTIFF outputs reopen with the input's
// georeference; bad rasters are refused naming the file.
#include "src/base/error.h"
#include "src/checks/verify.h"
#include "src/scene/plan.h"
#include "src/scene/scene_loader.h"
#include "src/scene/terrain.h"

#include "tests/support/fixtures.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <string>

namespace plancheck {
namespace {

namespace fs = std::filesystem;
using testing::TempDir;
using testing::write_text;

// The site: kN x kN cells of kCell m, heights raw / 1024 m (exact in
// float32 and in int16 with scale 1/1024), a nodata block under the arm's
// sweep and a pillar just beyond its reach (only the distance widening of
// the window keeps it: it is the terrain nearest the arm in some states).
constexpr int kN = 240;
constexpr double kCell = 0.05;
constexpr double kXll = 20000.0, kYll = -40000.0;  // map corner (polar stereographic metres)
constexpr int kNodata = -32768;
const char* kSrs = "+proj=stere +lat_0=-90 +lon_0=0 +k=1 +x_0=0 +y_0=0 +R=1737400 +units=m +no_defs";

int raw_height(int col, int south_row) {
  const double x = col * kCell - 1.5, y = south_row * kCell - 1.5;  // the frame, origin below
  if (x > 0.55 && x < 0.8 && y > 0.2 && y < 0.45) return kNodata;   // a hole the scoop passes over
  if (std::hypot(x, y - 1.4) < 0.12) return 900;                     // the pillar, 0.88 m high
  return static_cast<int>(std::lround(1024.0 * (0.04 * std::sin(1.7 * x) + 0.03 * std::cos(2.3 * y) + 0.01 * x)));
}

std::string esri(bool raw) {
  std::string t = "ncols " + std::to_string(kN) + "\nnrows " + std::to_string(kN) + "\nxllcorner " +
                  std::to_string(kXll) + "\nyllcorner " + std::to_string(kYll) + "\ncellsize 0.05\nNODATA_value " +
                  std::string(raw ? "-32768" : "-9999") + "\n";
  char buf[40];
  for (int fr = 0; fr < kN; ++fr) {
    for (int c = 0; c < kN; ++c) {
      const int v = raw_height(c, kN - 1 - fr);
      if (raw || v == kNodata) std::snprintf(buf, sizeof buf, "%s%d", c ? " " : "", raw ? v : -9999);
      else std::snprintf(buf, sizeof buf, "%s%.17g", c ? " " : "", v / 1024.0);
      t += buf;
    }
    t += "\n";
  }
  return t;
}

std::string scene_json(const std::string& dem, const std::string& placement) {
  return R"({"format": "plancheck-scene/1", "model": "m.obj", "length_unit": "m", "angle_unit": "deg",
    "actions": [{"name": "J1", "node": "Arm", "type": "rotate", "pivot": [0, 0, 0.6], "axis": [0, 0, 1], "limits": [-180, 180]},
                {"name": "S", "node": "Scoop", "type": "rotate", "pivot": [0.6, 0, 0.6], "axis": [0, 1, 0], "limits": [-40, 70]}],
    "allowed_collisions": [["Arm", "Lander"], ["Scoop", "terrain"]],
    "safety_margin": 0.02,
    "terrain": {"dem": ")" + dem + "\", " + placement + R"(},
    "scoop": {"part": "Scoop", "bottom_point": [1.0, 0, 0.05], "width": 0.1, "capacity": 0.001, "bulk_density": 1240},
    "probes": [{"name": "down", "part": "Arm", "origin": [0.8, 0, 0.55], "direction": [0, 0, -1], "max_range": 0.3},
               {"name": "tip", "part": "Scoop", "origin": [1.0, 0, 0.05], "direction": [0, 0, -1], "max_range": 0.3}]})";
}

const char* kOrigin = R"("origin": [-1.5, -1.5, -0.05])";

// Three plans of random states within the limits (the same for every scene).
std::vector<Plan> plans_for(const Scene& s) {
  std::mt19937_64 rng(35);
  std::vector<Plan> out(3);
  for (std::size_t p = 0; p < out.size(); ++p) {
    out[p].name = "p" + std::to_string(p);
    for (int k = 0; k < 40; ++k) out[p].states.push_back(testing::random_state(s, rng, 0.0));
  }
  return out;
}

class GdalSite : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir("dem_gdal");
    const TempDir& d = *dir_;
    testing::write_obj(d / "m.obj",
                       {{"Lander", testing::box_mesh(Vec3(-0.3, -0.3, 0.0), Vec3(0.3, 0.3, 0.6))},
                        {"Arm", testing::box_mesh(Vec3(0.0, -0.05, 0.55), Vec3(1.0, 0.05, 0.65))},
                        {"Scoop", testing::box_mesh(Vec3(0.95, -0.05, 0.05), Vec3(1.05, 0.05, 0.25))}});
    write_text(d / "site.asc", esri(false));
    write_text(d / "raw.asc", esri(true));
    const std::string in = (d / "site.asc").string(), raw = (d / "raw.asc").string();
    const std::string srs = std::string(" -a_srs '") + kSrs + "' ";
    const std::string q = "gdal_translate -q ";
    const std::string cmds[] = {
        q + "-ot Float32 -co TILED=YES -co BLOCKXSIZE=64 -co BLOCKYSIZE=64 -co COMPRESS=DEFLATE" + srs + in + " " +
            (d / "f32.tif").string(),
        q + "-ot Int16 -a_scale 0.0009765625 -a_offset 0 -co TILED=YES -co COMPRESS=LZW" + srs + raw + " " +
            (d / "i16.tif").string(),
        q + "-of PDS4" + srs + (d / "f32.tif").string() + " " + (d / "site.xml").string(),
        q + "-of ISIS3" + srs + (d / "f32.tif").string() + " " + (d / "site.cub").string(),
    };
    for (const std::string& c : cmds) ASSERT_EQ(testing::run_command(c + " >/dev/null 2>&1"), 0) << c;
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static Scene scene(const std::string& dem, const std::string& placement = kOrigin) {
    const fs::path f = *dir_ / ("s-" + std::to_string(++count_) + ".json");
    write_text(f, scene_json(dem, placement));
    return load_scene(f);
  }
  static std::string error_of(const std::string& dem, const std::string& placement = kOrigin) {
    try {
      scene(dem, placement);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }
  static TempDir* dir_;
  static int count_;
};
TempDir* GdalSite::dir_ = nullptr;
int GdalSite::count_ = 0;

// Same grid: every sample, hole and placement equal as doubles.
::testing::AssertionResult same_grid(const Dem& a, const Dem& b) {
  if (a.ncols != b.ncols || a.nrows != b.nrows) return ::testing::AssertionFailure() << "sizes differ";
  if (a.x0 != b.x0 || a.y0 != b.y0 || a.cellsize != b.cellsize) return ::testing::AssertionFailure() << "placement differs";
  if (a.valid != b.valid) return ::testing::AssertionFailure() << "holes differ";
  for (std::size_t i = 0; i < a.z.size(); ++i)
    if (a.valid[i] && a.z[i] != b.z[i]) return ::testing::AssertionFailure() << "height " << i << " differs";
  return ::testing::AssertionSuccess();
}

// Same answers, state by state and dig by dig: exactly (tolerance 0) or
// within `tol` for distances and dig figures.
void expect_same_answers(const Scene& a, const Scene& b, double tol) {
  const Checker ca(a, 2), cb(b, 2);
  const std::vector<Plan> pa = plans_for(a);
  const auto ra = verify_plans(ca, a, pa, VerifyOptions{2});
  const auto rb = verify_plans(cb, b, pa, VerifyOptions{2});
  ASSERT_EQ(ra.size(), rb.size());
  int collisions = 0, terrain_nearest = 0, probe_hits = 0;
  for (std::size_t p = 0; p < ra.size(); ++p) {
    ASSERT_EQ(ra[p].states.size(), rb[p].states.size());
    EXPECT_EQ(ra[p].verdict, rb[p].verdict) << p;
    for (std::size_t s = 0; s < ra[p].states.size(); ++s) {
      const StateResult& x = ra[p].states[s];
      const StateResult& y = rb[p].states[s];
      EXPECT_EQ(x.collision, y.collision) << p << "/" << s;
      EXPECT_NEAR(x.min_distance, y.min_distance, tol) << p << "/" << s;
      if (x.min_distance > 0.0) {  // in contact, which pair is named first is the traversal's choice
        EXPECT_EQ(ca.part_name(x.part_a), cb.part_name(y.part_a)) << p << "/" << s;
        EXPECT_EQ(ca.part_name(x.part_b), cb.part_name(y.part_b)) << p << "/" << s;
      }
      collisions += x.collision;
      terrain_nearest += x.part_b >= 0 && ca.part_name(x.part_b) == "terrain" && x.min_distance > 0.05;
      ASSERT_EQ(ra[p].probes[s].size(), rb[p].probes[s].size());
      for (std::size_t k = 0; k < ra[p].probes[s].size(); ++k) probe_hits += ra[p].probes[s][k].hit >= 0;
      for (std::size_t k = 0; k < ra[p].probes[s].size(); ++k)
        EXPECT_NEAR(ra[p].probes[s][k].distance, rb[p].probes[s][k].distance, tol) << p << "/" << s;
    }
    ASSERT_TRUE(ra[p].dig && rb[p].dig);
    EXPECT_EQ(ra[p].dig->dug, rb[p].dig->dug);
    EXPECT_NEAR(ra[p].dig->dug_volume, rb[p].dig->dug_volume, tol);
    EXPECT_NEAR(ra[p].dig->deepest, rb[p].dig->deepest, tol);
    EXPECT_EQ(ra[p].dig->deepest_state, rb[p].dig->deepest_state);
  }
  // The plans exercise what they compare: collisions, digging, and the
  // terrain as the nearest thing at a distance.
  EXPECT_GT(collisions, 0);
  EXPECT_GT(terrain_nearest, 0);
  EXPECT_GT(probe_hits, 0);
  EXPECT_TRUE(ra[0].dig->dug || ra[1].dig->dug || ra[2].dig->dug);
}

TEST_F(GdalSite, EveryFormatGivesTheEsriGridAndItsAnswers) {
  const Scene esri_scene = scene("site.asc");
  const Dem& e = *esri_scene.terrain->grid;
  EXPECT_EQ(e.source.driver, "ESRI ASCII");
  EXPECT_FALSE(e.source.whole);  // the site sits in a corner of the raster
  for (const char* f : {"f32.tif", "i16.tif", "site.xml", "site.cub"}) {
    SCOPED_TRACE(f);
    const Scene s = scene(f);
    EXPECT_TRUE(same_grid(*s.terrain->grid, e));
    EXPECT_EQ(s.terrain->grid->source.col_off, e.source.col_off);
    EXPECT_EQ(s.terrain->grid->source.row_off, e.source.row_off);
  }
  EXPECT_EQ(scene("f32.tif").terrain->grid->source.driver, "GTiff");
  EXPECT_EQ(scene("site.xml").terrain->grid->source.driver, "PDS4");
  EXPECT_EQ(scene("site.cub").terrain->grid->source.driver, "ISIS3");
  // The int16 file holds raw counts: without its scale the heights would be 1024 times larger.
  expect_same_answers(esri_scene, scene("i16.tif"), 0.0);
  expect_same_answers(esri_scene, scene("site.cub"), 0.0);
}

// The window (the reach of the moving parts, widened for the terrain
// distance) gives the answers of the whole raster: a Checker over the same
// scene with the whole grid is the reference. Samples differ from the
// whole grid's by the rounding of their offsets only (x0 + c * cell).
TEST_F(GdalSite, TheWindowGivesTheWholeRastersAnswers) {
  const Scene windowed = scene("f32.tif");
  const Dem& w = *windowed.terrain->grid;
  Scene whole = windowed;
  whole.terrain->grid = std::make_shared<const Dem>(load_dem(*dir_ / "f32.tif", 1.0));
  ASSERT_TRUE(whole.terrain->grid->source.whole);
  EXPECT_LT(w.ncols * w.nrows * 4, kN * kN) << "the window is a small part of the raster";
  // A first window of reach + margin, then the one widened for the terrain
  // distance (the ground 0.6 m below the pivot), nothing else.
  EXPECT_GT(w.source.pixels_read, static_cast<double>(w.ncols) * w.nrows);
  EXPECT_LE(w.source.pixels_read, 2.0 * w.ncols * w.nrows);
  EXPECT_EQ(w.source.col_off, 0);               // the raster's west edge is within reach
  EXPECT_EQ(w.source.row_off + w.nrows, kN);    // and its south edge
  expect_same_answers(windowed, whole, 1e-12);
}

// map_origin on a projected raster places it as the origin it stands for:
// the grid's lower-left corner (kXll, kYll) at (-1.5, -1.5, -0.05) means
// the map point (kXll + 1.5, kYll + 1.5, 0.05) at the frame's origin.
TEST_F(GdalSite, MapOriginEqualsTheEquivalentOrigin) {
  const std::string m = R"("map_origin": [20001.5, -39998.5, 0.05])";
  const Scene by_map = scene("f32.tif", m);
  const Scene by_origin = scene("site.asc");
  EXPECT_EQ(by_map.terrain->origin, by_origin.terrain->origin);
  EXPECT_TRUE(same_grid(*by_map.terrain->grid, *by_origin.terrain->grid));
  expect_same_answers(by_origin, by_map, 0.0);
  // Map coordinates of a frame point: the frame origin is the map origin.
  const auto p = map_point(*by_map.terrain->grid, by_map.terrain->origin, 1.0, Vec3(1.0, 2.0, 3.0));
  ASSERT_TRUE(p);
  EXPECT_NEAR(p->x(), 20002.5, 1e-9);
  EXPECT_NEAR(p->y(), -39996.5, 1e-9);
  EXPECT_NEAR(p->z(), 3.05, 1e-12);
  // A raster without a CRS has no map frame.
  EXPECT_NE(error_of("site.asc", m).find("map_origin needs a raster with a projected CRS"), std::string::npos);
  EXPECT_NE(error_of("f32.tif", m + ", " + kOrigin).find("give origin or map_origin, not both"), std::string::npos);
}

TEST_F(GdalSite, NodataHolesStayHoles) {
  for (const char* f : {"f32.tif", "i16.tif", "site.cub"}) {
    SCOPED_TRACE(f);
    const Scene s = scene(f);
    const Dem& g = *s.terrain->grid;
    int holes = 0;
    for (int r = 0; r < g.nrows; ++r)
      for (int c = 0; c < g.ncols; ++c) {
        const int col = g.source.col_off + c, south = kN - g.source.row_off - g.nrows + r;
        EXPECT_EQ(g.is_valid(c, r), raw_height(col, south) != kNodata) << c << "," << r;
        holes += !g.is_valid(c, r);
      }
    EXPECT_GT(holes, 10);
    // The surface has a hole there: (0.65, 0.3) in the frame.
    EXPECT_FALSE(dem_surface(g, s.terrain->origin, 0.65, 0.3));
    EXPECT_TRUE(dem_surface(g, s.terrain->origin, 0.3, 0.3));
  }
}

// dig's GeoTIFF outputs: the window's geotransform, the input's CRS and
// nodata, the heights as they are; GDAL reopens them.
TEST_F(GdalSite, GeotiffOutputsReopenWithTheInputsGeoreference) {
  const Scene s = scene("f32.tif");
  const Dem& g = *s.terrain->grid;
  const fs::path out = *dir_ / "after.tif";
  {
    std::ofstream o(out, std::ios::binary);
    o << geotiff_bytes(g, 1.0);
  }
  const Dem back = load_dem(out, 1.0);
  EXPECT_EQ(back.source.driver, "GTiff");
  EXPECT_EQ(back.source.geotransform, g.source.window_geotransform());
  EXPECT_EQ(back.source.crs_wkt, g.source.crs_wkt);
  EXPECT_FALSE(back.source.crs_wkt.empty());
  EXPECT_EQ(back.source.has_nodata, g.source.has_nodata);
  EXPECT_EQ(back.source.nodata, g.source.nodata);
  EXPECT_EQ(back.valid, g.valid);
  for (std::size_t i = 0; i < g.z.size(); ++i)
    if (g.valid[i]) {
      ASSERT_EQ(back.z[i], g.z[i]) << i;
    }
  // Placed by the same map origin, the output lies where the window lay.
  const auto a = map_point(g, s.terrain->origin, 1.0, Vec3::Zero());
  EXPECT_EQ(window_extent(back), window_extent(g));
  EXPECT_TRUE(a);
}

TEST_F(GdalSite, BadRastersAreRefusedNamingTheFile) {
  const TempDir& d = *dir_;
  const std::string q = "gdal_translate -q ";
  const std::string f32 = (d / "f32.tif").string();
  ASSERT_EQ(testing::run_command(q + "-a_srs EPSG:4326 -a_ullr 10 20 10.1 19.9 " + f32 + " " + (d / "geo.tif").string()), 0);
  ASSERT_EQ(testing::run_command(q + "-a_srs '+proj=stere +lat_0=-90 +R=1737400 +units=ft' " + f32 + " " +
                                 (d / "feet.tif").string()), 0);
  ASSERT_EQ(testing::run_command(q + "-a_ullr 0 10 20 0 " + f32 + " " + (d / "nonsquare.tif").string()), 0);
  write_text(d / "rotated.vrt", "<VRTDataset rasterXSize=\"4\" rasterYSize=\"4\"><GeoTransform>0, 1, 0.1, 4, 0.1, -1"
                                "</GeoTransform><VRTRasterBand dataType=\"Float32\" band=\"1\"/></VRTDataset>\n");
  write_text(d / "junk.tif", "II*\0 not a tiff at all");
  struct Case {
    const char* dem;
    std::string extra;
    const char* says;
  } cases[] = {
      {"junk.tif", "", "junk.tif: GDAL cannot open it as a raster"},
      {"f32.tif", ", \"band\": 2", "f32.tif: band 2 out of range (the raster has 1)"},
      {"geo.tif", "", "geo.tif: the CRS is geographic (degrees); reproject it"},
      {"feet.tif", "", "feet.tif: the CRS's unit is 0.3048"},
      {"nonsquare.tif", "", "nonsquare.tif: pixels are not square"},
      {"rotated.vrt", "", "rotated.vrt: rotated or sheared geotransform"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.dem);
    const std::string e = error_of(c.dem, kOrigin + c.extra);
    EXPECT_NE(e.find(c.says), std::string::npos) << e;
  }
  EXPECT_NE(error_of("geo.tif").find("gdalwarp -t_srs"), std::string::npos);
  // A window with no data in reach: the site placed 1 km off the raster.
  const std::string far = error_of("f32.tif", R"("map_origin": [21000, -39000, 0])");
  EXPECT_NE(far.find("f32.tif: the raster has no pixel within reach of the moving parts: check terrain.map_origin"),
            std::string::npos) << far;
}

// A mosaic far larger than the site (4000 x 4000 tiled, compressed; the
// bench script bench/terrain_window.sh does 20,000 x 20,000 and times it):
// only the window's pixels are requested from GDAL, the same window as a
// copy of just that part of the mosaic gives.
TEST_F(GdalSite, LargeMosaicReadsOnlyTheWindow) {
  const TempDir& d = *dir_;
  const std::string mosaic = (d / "mosaic.tif").string();
  // The site's corner pasted into a constant 4000 x 4000 raster (compresses to almost nothing).
  ASSERT_EQ(testing::run_command(std::string("gdal_create -q -of GTiff -ot Float32 -outsize 4000 4000 -burn 0.02 "
                                             "-a_nodata -9999 -co TILED=YES -co COMPRESS=DEFLATE -a_srs '") + kSrs +
                                 "' -a_ullr 20000 -39800 20200 -40000 " + mosaic + " >/dev/null 2>&1"), 0);
  ASSERT_EQ(testing::run_command("gdalwarp -q -srcnodata None " + (d / "f32.tif").string() + " " + mosaic + " >/dev/null 2>&1"), 0);
  const Scene big = scene("mosaic.tif", R"("map_origin": [20001.5, -39998.5, 0.05])");
  const Scene small = scene("f32.tif", R"("map_origin": [20001.5, -39998.5, 0.05])");
  const Dem& b = *big.terrain->grid;
  const Dem& s = *small.terrain->grid;
  EXPECT_EQ(b.source.raster_cols, 4000);
  EXPECT_TRUE(same_grid(b, s));
  EXPECT_EQ(b.source.pixels_read, s.source.pixels_read);
  EXPECT_LE(b.source.pixels_read, 2.0 * b.ncols * b.nrows);
  EXPECT_LT(b.source.pixels_read, 1e-3 * 4000.0 * 4000.0);
}

// The command line: `plancheck scene` names the window, report.json carries
// it under "terrain", `plancheck dig` writes GeoTIFFs with the window's
// georeference and prints the map coordinates of the deepest point.
TEST_F(GdalSite, CommandLineReportsTheWindowAndWritesGeotiffs) {
  const TempDir& d = *dir_;
  const fs::path exe = fs::path(PLANCHECK_BINARY_DIR) / "plancheck";
  write_text(d / "cli.json", scene_json("f32.tif", R"("map_origin": [20001.5, -39998.5, 0.05])"));
  write_text(d / "dig.csv", "# name: dig\n# target: 1.0, 0, 0\nJ1,S\n0,0\n0,20\n0,45\n0,60\n0,20\n");
  const Scene s = load_scene(d / "cli.json");
  const Dem& g = *s.terrain->grid;
  ASSERT_EQ(testing::run_command(exe.string() + " scene " + (d / "cli.json").string() + " > " + (d / "scene.txt").string()), 0);
  const std::string text = testing::read_text(d / "scene.txt");
  const std::string says = "(GTiff, band 1, 240 x 240 pixels): read the window within reach, " + std::to_string(g.ncols) +
                           " x " + std::to_string(g.nrows) + " pixels from column 1, row " +
                           std::to_string(g.source.row_off + 1) + " (map x 20000 .. ";
  EXPECT_NE(text.find(says), std::string::npos) << text;
  const int verified = testing::run_command(exe.string() + " verify " + (d / "cli.json").string() + " " +
                                            (d / "dig.csv").string() + " --out " + (d / "v").string() +
                                            " > /dev/null 2>&1");
  ASSERT_TRUE(verified == 0 || verified == 1) << verified;  // 1: the plan is not safe, the run went through
  const auto report = nlohmann::json::parse(testing::read_text(d / "v/report.json"));
  const auto& t = report.at("terrain");
  EXPECT_EQ(t.at("driver"), "GTiff");
  EXPECT_EQ(t.at("raster_pixels"), nlohmann::json::array({240, 240}));
  EXPECT_EQ(t.at("window").at("pixels"), nlohmann::json::array({0, g.source.row_off, g.ncols, g.nrows}));
  EXPECT_EQ(t.at("window").at("whole"), false);
  const auto e = window_extent(g);
  EXPECT_EQ(t.at("window").at("map_extent"), nlohmann::json::array({e[0], e[1], e[2], e[3]}));
  ASSERT_EQ(testing::run_command(exe.string() + " dig " + (d / "cli.json").string() + " " + (d / "dig.csv").string() +
                                 " --out " + (d / "dig").string() + " > " + (d / "dig.txt").string() + " 2>/dev/null"),
            0);
  const std::string dig = testing::read_text(d / "dig.txt");
  EXPECT_NE(dig.find("before.tif, after.tif"), std::string::npos) << dig;
  EXPECT_NE(dig.find("target at map E 20002.5, N -39998.5, H 0.05 m"), std::string::npos) << dig;
  EXPECT_NE(dig.find("deepest scoop point at map E 2000"), std::string::npos) << dig;
  for (const char* f : {"dig/before.tif", "dig/after.tif"}) {
    SCOPED_TRACE(f);
    const Dem out = load_dem(d / f, 1.0);
    EXPECT_EQ(out.source.geotransform, g.source.window_geotransform());
    EXPECT_EQ(out.source.crs_wkt, g.source.crs_wkt);
    EXPECT_EQ(out.valid, g.valid);
  }
  EXPECT_EQ(load_dem(d / "dig/before.tif", 1.0).z, g.z);
  // The ESRI grid holds the window too, its lower-left corner the window's.
  const Dem asc = load_dem(d / "dig/before.asc", 1.0);
  EXPECT_EQ(asc.z, g.z);
  EXPECT_EQ(asc.valid, g.valid);
  EXPECT_EQ(asc.xll, e[0]);
  EXPECT_EQ(asc.yll, e[1]);
}

}  // namespace
}  // namespace plancheck
