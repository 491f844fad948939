// SPDX-License-Identifier: MIT
// The ESRI ASCII grid reader: header variants, NODATA holes, errors naming
// the line; the writer round trip; the surface height between samples.
#include "src/base/error.h"
#include "src/scene/terrain.h"

#include "tests/support/fixtures.h"

#include <gtest/gtest.h>

#include <sys/resource.h>
#include <sys/stat.h>

#include <fstream>
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
  EXPECT_NE(error_of("").find(": empty file, not a DEM"), std::string::npos);
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

// Issue 31, item 12: a data value that is not finite named the header
// ("unknown header key 'nan'") when it began a row; it is a bad cell, named
// by its line, column and (row, column).
TEST_F(DemTest, NonFiniteDataIsABadCellNotABadHeader) {
  const std::string head = "ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n";
  for (const char* bad : {"nan", "NaN", "inf", "-inf", "Infinity", "1e400"}) {
    SCOPED_TRACE(bad);
    // Starting the first data row (the old reader took it for a header key) ...
    const std::string first = error_of(head + bad + " 2\n3 4\n");
    EXPECT_EQ(first.find("header"), std::string::npos) << first;
    EXPECT_NE(first.find(":6:1: '" + std::string(bad) + "' is not a finite number (cell row 1, column 1)"),
              std::string::npos) << first;
    // ... or a later one.
    const std::string e = error_of(head + "1 2\n" + bad + " 4\n");
    EXPECT_NE(e.find(":7:1: '" + std::string(bad) + "' is not a finite number (cell row 2, column 1)"), std::string::npos) << e;
  }
}

// Issue 31, item 12: "1e-400" was called not a finite number; it is below
// double's range, so it is the nearest double (0), as JSON reads it.
TEST_F(DemTest, NumbersBelowDoublesRangeAreTheirNearestDouble) {
  const Dem d = load_dem(file("ncols 2\nnrows 1\nxllcorner 0\nyllcorner 0\ncellsize 1\n1e-400 -1e-400\n"), 1.0);
  EXPECT_EQ(d.height(0, 0), 0.0);
  EXPECT_EQ(d.height(1, 0), 0.0);
  EXPECT_TRUE(d.is_valid(0, 0));
}

// Issue 31, item 12: a repeated header key silently won (the last cellsize
// counted). GDAL's AAIGrid driver silently keeps the first one; both are
// wrong for a file whose author meant one of them.
TEST_F(DemTest, RepeatedHeaderKeyIsRefused) {
  const std::string e = error_of("ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\ncellsize 2\n1 2\n3 4\n");
  EXPECT_NE(e.find(":6: header key 'cellsize' repeats the one on line 5"), std::string::npos) << e;
  // xllcenter and xllcorner say the same thing two ways: also a repeat.
  const std::string f = error_of("ncols 2\nnrows 2\nxllcorner 0\nxllcenter 1\nyllcorner 0\ncellsize 1\n1 2\n3 4\n");
  EXPECT_NE(f.find(":4: header key 'xllcenter' repeats the one on line 3"), std::string::npos) << f;
}

// Issue 31, item 11: finite but huge heights (1e154) gave false collisions
// outside the terrain and a 50x slower run. Heights beyond kMaxDemHeight
// (1e7 m: planetary radius DEMs fit) are refused naming the cell.
TEST_F(DemTest, HeightsNoRealTerrainHasAreRefusedNamingTheCell) {
  const std::string head = "ncols 3\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n";
  const std::string e = error_of(head + "1 2 3\n4 5 -1e154\n");
  EXPECT_NE(e.find("cell (row 2, column 3"), std::string::npos) << e;
  EXPECT_NE(e.find("beyond what any real terrain has"), std::string::npos) << e;
  // The limit is in metres: 2e6 m passes, 2e9 mm (2e6 m) too, 2e10 mm does not.
  EXPECT_NO_THROW(load_dem(file(head + "1 2 3\n4 5 2e6\n"), 1.0));
  EXPECT_NO_THROW(load_dem(file(head + "1 2 3\n4 5 2e9\n"), 0.001));
  EXPECT_THROW(load_dem(file(head + "1 2 3\n4 5 2e10\n"), 0.001), InputError);
}

// Issue 31, items 5 and 12: a DEM path that is a directory, a device or a
// FIFO is refused before it is opened (a FIFO would block, /dev/zero grow).
TEST_F(DemTest, NonRegularPathsAreRefusedBeforeOpening) {
  const auto fifo = dir_ / "fifo.asc";
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  for (const std::filesystem::path& p : {dir_.path(), std::filesystem::path("/dev/zero"), fifo}) {
    SCOPED_TRACE(p.string());
    try {
      load_dem(p, 1.0);
      ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(p.string() + ": not a regular file"), std::string::npos) << e.what();
    }
  }
}

// Issue 31, item 6: a zero-filled DEM was held whole (1 GB took 3.4 GB).
// Now no token may outgrow kMaxToken, and a file that is not ESRI ASCII goes
// to GDAL, which reads its first bytes only: a 256 MB sparse file of zeros
// fails at once, naming the file, without growing the process.
TEST_F(DemTest, ZeroFilledFileFailsEarlyWithoutBeingHeld) {
  const auto f = dir_ / "zeros.asc";
  { std::ofstream(f, std::ios::binary); }
  std::filesystem::resize_file(f, 256u << 20);
  rusage before{};
  ASSERT_EQ(getrusage(RUSAGE_SELF, &before), 0);
  try {
    load_dem(f, 1.0);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(f.string() + ": GDAL cannot open it as a raster"), std::string::npos) << e.what();
  }
  // An ESRI header followed by one endless run of zeros: the token limit.
  const auto g = dir_ / "zeros2.asc";
  {
    std::ofstream o(g, std::ios::binary);
    o << "ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n1";
  }
  std::filesystem::resize_file(g, 64u << 20);
  try {
    load_dem(g, 1.0);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(g.string() + ":6: a value longer than 64 characters"), std::string::npos)
        << e.what();
  }
  rusage after{};
  ASSERT_EQ(getrusage(RUSAGE_SELF, &after), 0);
  EXPECT_LT(after.ru_maxrss - before.ru_maxrss, 32L * 1024L) << "peak resident set growth (KiB)";
}

// Issue 31, item 2: dig's grids were written through std::ofstream, so a
// link planted at DIR/after.asc made the run overwrite its target.
TEST_F(DemTest, WriterReplacesAPlantedLinkNeverWritesThroughIt) {
  const Dem a = load_dem(file("ncols 2\nnrows 1\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2\n"), 1.0);
  const auto victim = dir_ / "victim.txt";
  write_text(victim, "keep me\n");
  const auto out = dir_ / "after.asc";
  std::filesystem::create_symlink(victim, out);
  write_dem(out, a, 1.0);
  EXPECT_EQ(testing::read_text(victim), "keep me\n");
  EXPECT_FALSE(std::filesystem::is_symlink(out));
  EXPECT_EQ(load_dem(out, 1.0).z, a.z);
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
