// SPDX-License-Identifier: MIT
// The ESRI ASCII grid reader: header variants, NODATA holes, errors naming
// the line; the writer round trip; the surface height between samples.
#include "src/base/error.h"
#include "src/scene/terrain.h"

#include "tests/support/fixtures.h"

#include <gtest/gtest.h>

#include <sys/resource.h>

#include <sstream>
#include <string>

namespace plancheck {
namespace {

using testing::TempDir;
using testing::write_text;

class DemTest : public ::testing::Test {
 protected:
  std::filesystem::path file(const std::string& text) {
    const auto f = dir_ / ("g" + std::to_string(++count_) + ".asc");
    write_text(f, text);
    return f;
  }
  // The message of the InputError load_dem throws (empty if none).
  std::string error_of(const std::string& text) {
    const auto f = file(text);
    try {
      load_dem(f, 1.0);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }
  TempDir dir_{"dem_test"};
  int count_ = 0;
};

TEST_F(DemTest, CornerHeaderPutsSamplesAtCellCentresRowZeroSouth) {
  const Dem d = load_dem(file("ncols 3\nnrows 2\nxllcorner 10\nyllcorner 20\ncellsize 0.5\n1 2 3\n4 5 6\n"), 1.0);
  EXPECT_EQ(d.ncols, 3);
  EXPECT_EQ(d.nrows, 2);
  EXPECT_DOUBLE_EQ(d.x0, 0.25);
  EXPECT_DOUBLE_EQ(d.y0, 0.25);
  EXPECT_DOUBLE_EQ(d.height(0, 0), 4.0);  // the file's last row is the south row
  EXPECT_DOUBLE_EQ(d.height(2, 1), 3.0);
  EXPECT_DOUBLE_EQ(d.xll, 10.0);
}

TEST_F(DemTest, CentreHeaderMixedCaseScaledAndBlankLines) {
  const Dem d = load_dem(file("NCOLS 2\r\nNRows 2\r\nXLLCENTER 0\r\nyllcenter 0\r\nCellSize 10\r\n\r\n1 2\r\n\r\n3 +4\r\n"), 0.01);
  EXPECT_DOUBLE_EQ(d.x0, 0.0);
  EXPECT_DOUBLE_EQ(d.cellsize, 0.1);
  EXPECT_DOUBLE_EQ(d.height(1, 0), 0.04);
  EXPECT_DOUBLE_EQ(d.height(0, 1), 0.01);
}

TEST_F(DemTest, NodataSamplesAreHolesInTheMesh) {
  const Dem d = load_dem(file("ncols 3\nnrows 3\nxllcorner 0\nyllcorner 0\ncellsize 1\nNODATA_value -9999\n"
                              "0 0 0\n0 -9999 0\n0 0 0\n"),
                         1.0);
  EXPECT_FALSE(d.is_valid(1, 1));
  EXPECT_TRUE(d.is_valid(0, 0));
  // Every one of the four cells touches the centre sample: no triangles.
  EXPECT_TRUE(dem_mesh(d, Vec3::Zero()).triangles.empty());
  EXPECT_FALSE(dem_surface(d, Vec3::Zero(), 1.0, 1.0).has_value());
}

TEST_F(DemTest, NodataValueOnlyMatchesWhenDeclared) {
  const Dem d = load_dem(file("ncols 1\nnrows 1\nxllcorner 0\nyllcorner 0\ncellsize 1\n-9999\n"), 1.0);
  EXPECT_TRUE(d.is_valid(0, 0));
  EXPECT_DOUBLE_EQ(d.height(0, 0), -9999.0);
}

TEST_F(DemTest, ErrorsNameTheFileAndLine) {
  const std::string head = "ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n";
  EXPECT_NE(error_of(head + "1 2\n3\n").find(":7: expected 2 values, found 1"), std::string::npos);
  EXPECT_NE(error_of(head + "1 2\n3 x\n").find(":7:2: 'x' is not a finite number"), std::string::npos);
  EXPECT_NE(error_of(head + "1 2\n3 4 5\n").find(":7: more than ncols"), std::string::npos);
  EXPECT_NE(error_of(head + "1 2\n3 4\n5 6\n").find(":8: more data rows"), std::string::npos);
  EXPECT_NE(error_of(head + "1 2\n").find("expected 2 data rows, found 1"), std::string::npos);
  EXPECT_NE(error_of(head + "1 nan\n3 4\n").find("'nan' is not a finite number"), std::string::npos);
  EXPECT_NE(error_of("ncols 2\nnrows 2\nxllcorner 0\ncellsize 1\n1 2\n3 4\n").find("yllcorner or yllcenter missing"),
            std::string::npos);
  EXPECT_NE(error_of("ncols 2.5\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2\n3 4\n").find("ncols"),
            std::string::npos);
  EXPECT_NE(error_of("ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 0\n1 2\n3 4\n").find("cellsize"),
            std::string::npos);
  EXPECT_NE(error_of("ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\nfoo 3\n1 2\n3 4\n").find(":6: unknown header key 'foo'"),
            std::string::npos);
  EXPECT_NE(error_of("ncols 2\nnrows 2\nxllcorner 0 1\n").find(":3: expected 'key value'"), std::string::npos);
  EXPECT_NE(error_of(head).find("no data rows"), std::string::npos);
  EXPECT_NE(error_of("").find("ncols missing"), std::string::npos);
  EXPECT_THROW(load_dem(dir_ / "missing.asc", 1.0), InputError);
}

// Seen while writing the DEM fuzz target: the grid was allocated from the header's
// counts before any row was read, so a 40-byte file claiming 100000 x 10000
// samples made load_dem zero-fill 9 GB (or die with bad_alloc). Now it is an
// error on the first short row, with memory following the data.
TEST_F(DemTest, HeaderClaimingMoreSamplesThanTheFileHoldsAllocatesNothingLarge) {
  const std::string text = "ncols 100000\nnrows 10000\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2\n";
  EXPECT_NE(error_of(text).find(":6: expected 100000 values, found 2"), std::string::npos);
  rusage usage{};
  ASSERT_EQ(getrusage(RUSAGE_SELF, &usage), 0);
  EXPECT_LT(usage.ru_maxrss, 1024L * 1024L) << "peak resident set (KiB) of this test process";
  std::istringstream in("ncols 2\nnrows 1\nxllcenter 0\nyllcenter 0\ncellsize 1\n7 8\n");
  const Dem dem = read_dem(in, "memory.asc", 1.0);
  EXPECT_EQ(dem.height(1, 0), 8.0);
}

TEST_F(DemTest, WriterRoundTripsSamplesHolesAndRegistration) {
  const auto f = file("ncols 3\nnrows 2\nxllcenter 5\nyllcorner 7\ncellsize 0.02\nNODATA_value -1\n"
                      "0.1 0.2 -1\n0.123456789012345 0.5 0.6\n");
  const Dem a = load_dem(f, 0.5);
  const auto g = dir_ / "out.asc";
  write_dem(g, a, 0.5);
  const Dem b = load_dem(g, 0.5);
  EXPECT_EQ(b.ncols, 3);
  EXPECT_DOUBLE_EQ(b.x0, a.x0);
  EXPECT_DOUBLE_EQ(b.y0, a.y0);
  EXPECT_DOUBLE_EQ(b.cellsize, a.cellsize);
  EXPECT_EQ(b.valid, a.valid);
  for (std::size_t i = 0; i < a.z.size(); ++i) {
    if (a.valid[i]) {
      EXPECT_DOUBLE_EQ(b.z[i], a.z[i]);
    }
  }
}

TEST_F(DemTest, SurfaceFollowsTheMeshTriangles) {
  // One cell, heights 0 (sw), 1 (se), 2 (nw), 5 (ne); split along sw-ne.
  const Dem d = load_dem(file("ncols 2\nnrows 2\nxllcenter 0\nyllcenter 0\ncellsize 1\n2 5\n0 1\n"), 1.0);
  const Vec3 o(10, 20, 1);
  EXPECT_DOUBLE_EQ(*dem_surface(d, o, 10.0, 20.0), 1.0);
  EXPECT_DOUBLE_EQ(*dem_surface(d, o, 11.0, 21.0), 6.0);
  // South-east triangle (sw, se, ne): z = a*(1-0) + b*(5-1) at a = 0.75, b = 0.25.
  EXPECT_DOUBLE_EQ(*dem_surface(d, o, 10.75, 20.25), 1.0 + 0.75 + 1.0);
  // North-west triangle (sw, ne, nw): z = b*2 + a*(5-2) at a = 0.25, b = 0.75.
  EXPECT_DOUBLE_EQ(*dem_surface(d, o, 10.25, 20.75), 1.0 + 1.5 + 0.75);
  EXPECT_FALSE(dem_surface(d, o, 9.99, 20.5).has_value());
  EXPECT_FALSE(dem_surface(d, o, 10.5, 21.01).has_value());
}

}  // namespace
}  // namespace plancheck
