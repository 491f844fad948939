// SPDX-License-Identifier: MIT
// Plan CSV: comments and keys, units, missing columns, line endings, and every
// error with file:line(:column) in the message.
#include "src/scene/plan.h"

#include "src/scene/scene_loader.h"
#include "tests/foundation/fixtures.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace plancheck {
namespace {

class PlanTest : public ::testing::Test {
 protected:
  void SetUp() override {
    testing::write_arm_model(dir_ / "arm.gltf", 1000.0);
    scene_ = load_scene(dir_.write("s.json", R"({"format": "plancheck-scene/1", "model": "arm.gltf",
        "length_unit": "mm", "angle_unit": "deg", "actions": [
        {"name": "J1", "node": "arm1", "type": "rotate", "pivot": [0, 0, 0], "axis": [0, 0, 1]},
        {"name": "J2", "node": "arm2", "type": "rotate", "pivot": [1000, 0, 0], "axis": [0, 1, 0]},
        {"name": "Slide", "node": "tip", "type": "translate"},
        {"name": "Grow", "node": "tip", "type": "scale", "fixed_point": [2000, 0, 0]}]})"));
  }

  void expect_error(const std::string& name, const std::string& text, std::initializer_list<std::string> parts) {
    const auto file = dir_.write(name, text);
    testing::expect_input_error([&] { load_plan(scene_, file); }, parts);
  }

  testing::TempDir dir_;
  Scene scene_;
};

TEST_F(PlanTest, ReadsKeysUnitsAndMissingColumns) {
  const auto file = dir_.write("p.csv",
                               "# a plan for the tests\n"
                               "# name: plan03\n"
                               "# target: 3100, 0.00, 20\n"
                               "# tolerance: 20\n"
                               "\n"
                               "time, J2 ,J1,Slide.z,Grow.y\n"
                               "0,10,-20,5,1\n"
                               " 0.5 , 10.5,-20.25,  +6 ,2.5\n");
  const Plan p = load_plan(scene_, file);
  EXPECT_EQ(p.name, "plan03");
  EXPECT_EQ(p.file, file);
  ASSERT_TRUE(p.target.has_value());
  EXPECT_TRUE(p.target->isApprox(Vec3(3.1, 0, 0.02)));
  EXPECT_DOUBLE_EQ(p.tolerance, 0.02);
  EXPECT_EQ(p.times, (std::vector<double>{0, 0.5}));
  EXPECT_EQ(p.lines, (std::vector<long>{7, 8}));
  ASSERT_EQ(p.states.size(), 2u);
  // Order: J1, J2, Slide.x/y/z, Grow.x/y/z; missing ones keep reference
  // values. Every value as written (degrees, millimetres): only the pose
  // converts them.
  const std::vector<double> s1 = {-20.25, 10.5, 0, 0, 6, 1, 2.5, 1};
  EXPECT_EQ(p.states[1], s1);
  EXPECT_EQ(p.states[0][0], -20.0);
}

// The in-memory entry point (used by the fuzz targets) reads what the file
// reader reads, byte order mark included, and names the given path.
TEST_F(PlanTest, ParsePlanFromMemoryMatchesTheFile) {
  const std::string text = "\xEF\xBB\xBF# name: m\ntime,J1\n0,10\n1,20\n";
  const Plan from_file = load_plan(scene_, dir_.write("m.csv", text));
  const Plan from_text = parse_plan(scene_, text, "memory/m.csv");
  EXPECT_EQ(from_text.name, "m");
  EXPECT_EQ(from_text.file, std::filesystem::path("memory/m.csv"));
  EXPECT_EQ(from_text.states, from_file.states);
  EXPECT_EQ(from_text.times, from_file.times);
  EXPECT_EQ(from_text.lines, (std::vector<long>{3, 4}));
  testing::expect_input_error([&] { parse_plan(scene_, "J1\n1,2\n", "memory/bad.csv"); },
                              {"memory/bad.csv:2:", "expected 1 fields, found 2"});
}

TEST_F(PlanTest, DefaultsCrlfAndTrailingBlankLines) {
  const auto file = dir_.write("plan07.csv", "# target: 1000, 0, 0\r\nJ1\r\n1\r\n2\r\n\r\n\r\n");
  const Plan p = load_plan(scene_, file);
  EXPECT_EQ(p.name, "plan07");
  EXPECT_TRUE(p.times.empty());
  ASSERT_EQ(p.states.size(), 2u);
  EXPECT_EQ(p.states[1][0], 2.0);
  EXPECT_DOUBLE_EQ(p.tolerance, 0.01 * 0.001);  // default: 0.01 length units
  const Plan no_newline = load_plan(scene_, dir_.write("q.csv", "J1,J2\n1,2"));
  EXPECT_EQ(no_newline.states.size(), 1u);
  EXPECT_EQ(no_newline.tolerance, 0.0);  // no target: no tolerance
  EXPECT_EQ(no_newline.name, "q");
  EXPECT_EQ(load_plan(scene_, dir_.write("r.plan.txt", "J1\n0\n")).name, "r.plan.txt");
}

// The contract's motion between states: each parameter goes linearly from its
// value as written to the next value as written. 200 is 200, 720 is two
// turns, 170 -> -170 turns 340 degrees through 0, 1e300 stays 1e300.
TEST_F(PlanTest, StatesHoldTheWrittenValuesAndMoveLinearlyBetweenThem) {
  const Plan p = load_plan(scene_, dir_.write("turns.csv",
                                              "J1,Slide.x,Grow.z\n"
                                              "0,0,1\n"
                                              "200,-5,2\n"
                                              "720,1000,0.5\n"
                                              "170,0,1\n"
                                              "-170,0,1\n"
                                              "-200,2.5,3\n"
                                              "1e300,0,1\n"
                                              "-1080.5,0,1\n"));
  const std::vector<double> j1 = {0, 200, 720, 170, -170, -200, 1e300, -1080.5};
  const std::vector<double> slide = {0, -5, 1000, 0, 0, 2.5, 0, 0};
  const std::vector<double> grow = {1, 2, 0.5, 1, 1, 3, 1, 1};
  ASSERT_EQ(p.states.size(), j1.size());
  for (std::size_t s = 0; s < j1.size(); ++s) {
    EXPECT_EQ(p.states[s][0], j1[s]) << s;  // J1 (deg)
    EXPECT_EQ(p.states[s][1], 0.0) << s;    // J2: not a column, reference value
    EXPECT_EQ(p.states[s][2], slide[s]) << s;  // Slide.x (mm)
    EXPECT_EQ(p.states[s][7], grow[s]) << s;   // Grow.z (factor)
  }
  // Interpolation at t = 0, 1/2, 1: the written ends, bit for bit, and the
  // midpoints of the written values (never of reduced ones).
  std::vector<double> q;
  for (std::size_t s = 0; s + 1 < p.states.size(); ++s) {
    const std::vector<double>& a = p.states[s];
    const std::vector<double>& b = p.states[s + 1];
    state_between(a, b, 0.0, q);
    EXPECT_EQ(q, a);
    state_between(a, b, 1.0, q);
    EXPECT_EQ(q, b);
    state_between(a, b, 0.5, q);
    ASSERT_EQ(q.size(), a.size());
    for (std::size_t i = 0; i < q.size(); ++i) EXPECT_EQ(q[i], a[i] + 0.5 * (b[i] - a[i])) << s << " " << i;
  }
  state_between(p.states[0], p.states[1], 0.5, q);
  EXPECT_EQ(q[0], 100.0);  // 0 -> 200 passes 100, not -80
  EXPECT_EQ(q[2], -2.5);
  EXPECT_EQ(q[7], 1.5);
  state_between(p.states[1], p.states[2], 0.5, q);
  EXPECT_EQ(q[0], 460.0);  // 200 -> 720: the long way, through a whole turn
  state_between(p.states[3], p.states[4], 0.5, q);
  EXPECT_EQ(q[0], 0.0);  // 170 -> -170 turns 340 degrees through 0, never through 180
  state_between(p.states[4], p.states[5], 0.25, q);
  EXPECT_EQ(q[0], -177.5);
}

TEST_F(PlanTest, HeaderErrors) {
  expect_error("unknown.csv", "# c\nJ1,J9\n1,2\n", {"unknown.csv:2:2: unknown column 'J9'"});
  expect_error("repeat.csv", "J1,J2,J1\n1,2,3\n", {"repeat.csv:1:3: column 'J1' given twice"});
  expect_error("time.csv", "J1,time\n1,2\n", {"time.csv:1:2: column 'time' must be the first column"});
  expect_error("slide.csv", "Slide\n1\n", {"slide.csv:1:1: unknown column 'Slide'"});  // needs .x/.y/.z
  expect_error("empty.csv", "", {"empty.csv:1: no header line"});
  expect_error("comments.csv", "# name: x\n\n", {"comments.csv:2: no header line"});
  expect_error("nostates.csv", "# c\nJ1,J2\n\n", {"nostates.csv:2: the plan has no states"});
  expect_error("target.csv", "# target: 1, 2\nJ1\n0\n", {"target.csv:1: target: expected three finite numbers"});
  expect_error("tol.csv", "# tolerance: -1\nJ1\n0\n", {"tol.csv:1: tolerance"});
  testing::expect_input_error([&] { load_plan(scene_, dir_ / "absent.csv"); }, {"absent.csv", "cannot open"});
}

TEST_F(PlanTest, RowErrors) {
  expect_error("count.csv", "J1,J2\n1,2\n1,2,3\n", {"count.csv:3: expected 2 fields, found 3"});
  expect_error("few.csv", "J1,J2\n1\n", {"few.csv:2: expected 2 fields, found 1"});
  expect_error("text.csv", "J1,J2\n1,abc\n", {"text.csv:2:2: column 'J2': 'abc' is not a finite number"});
  expect_error("garbage.csv", "J1,J2\n1.5x,2\n", {"garbage.csv:2:1: column 'J1': '1.5x' is not a finite number"});
  expect_error("inf.csv", "J1,J2\n1,inf\n", {"inf.csv:2:2", "'inf' is not a finite number"});
  expect_error("nan.csv", "time,J1\n0,1\n1,nan\n", {"nan.csv:3:2", "'nan' is not a finite number"});
  expect_error("huge.csv", "J1\n1e999\n", {"huge.csv:2:1", "not a finite number"});
  expect_error("blank.csv", "J1,J2\n1,\n", {"blank.csv:2:2", "'' is not a finite number"});
  expect_error("scale.csv", "Grow.x\n0\n", {"scale.csv:2:1: column 'Grow.x': scale factor must be positive"});
  expect_error("late.csv", "J1\n1\n# note\n", {"late.csv:3:1"});  // comments only before the header
}

// RFC 4180 fields: quoted names (commas, doubled quotes, a line break in a
// quoted header field), quoted numbers, blanks around quotes.
TEST_F(PlanTest, QuotedFieldsAsRfc4180) {
  const Plan p = load_plan(scene_, dir_.write("q.csv", "\"J1\", \"Slide.x\" ,J2\n\"10\",2, 3\n"));
  ASSERT_EQ(p.states.size(), 1u);
  EXPECT_EQ(p.states[0][0], 10.0);
  EXPECT_EQ(p.states[0][2], 2.0);  // J1, J2, Slide.x, ...: Slide.x is the third parameter
  EXPECT_EQ(p.states[0][1], 3.0);
  expect_error("open.csv", "\"J1\n0\n", {"open.csv:1", "quoted field is not closed"});
  expect_error("after.csv", "\"J1\"x,J2\n0,0\n", {"after.csv:1:1", "text after a closing quote"});
  // A line break inside a quoted field keeps the record going: one unknown column, named.
  expect_error("multi.csv", "J1,\"a\nb\"\n0,0\n", {"multi.csv:1:2", "unknown column 'a\nb'"});
  // A state row's line numbers stay the file's.
  const Plan m = load_plan(scene_, dir_.write("m.csv", "J1,\"J2\"\n1,\"2\"\n\n3,4\n"));
  EXPECT_EQ(m.lines, (std::vector<long>{2, 4}));
}

// Below double's range a number is its nearest double, as in the scene file
// and strtod; above it, an error that says so.
TEST_F(PlanTest, NumbersBelowAndAboveTheRangeOfADouble) {
  const Plan p = load_plan(scene_, dir_.write("tiny.csv", "J1,J2\n1e-400,-1e-330\n"));
  EXPECT_EQ(p.states[0][0], 0.0);
  EXPECT_EQ(p.states[0][1], 0.0);
  const Plan sub = load_plan(scene_, dir_.write("sub.csv", "J1\n4e-320\n"));
  EXPECT_EQ(sub.states[0][0], 4e-320);
  expect_error("huge.csv", "J1\n1e400\n", {"huge.csv:2:1", "'1e400' is not a finite number (beyond the range of a double)"});
  expect_error("nan.csv", "J1\nnan\n", {"nan.csv:2:1", "is not a finite number"});
}

// A row whose pose overflows (a factor of 1e308 about a point 2 m away moves
// the node 2e308 m) cannot be checked: an error at its line. Far-apart
// finite values (1e308 degrees to -1e308) still interpolate finitely.
TEST_F(PlanTest, PosesBeyondTheRangeOfADoubleAreErrorsAtTheirLine) {
  expect_error("far.csv", "J1,Grow.x\n0,1\n0,1e308\n", {"far.csv:3: ", "node 'tip'", "beyond the range of doubles"});
  const Plan p = load_plan(scene_, dir_.write("wide.csv", "J1,Slide.x\n1e308,1e308\n-1e308,-1e308\n"));
  ASSERT_EQ(p.states.size(), 2u);
  std::vector<double> q;
  for (double t : {0.25, 0.5, 0x1p-30, 1 - 0x1p-30}) {
    state_between(p.states[0], p.states[1], t, q);
    for (double v : q) EXPECT_TRUE(std::isfinite(v)) << t;
  }
  state_between(p.states[0], p.states[1], 0.5, q);
  EXPECT_EQ(q[0], 0.0);
  EXPECT_EQ(q[2], 0.0);
  state_between(p.states[0], p.states[1], 0.25, q);
  EXPECT_EQ(q[0], 5e307);
}

// A plan's name names its report file and lines: text, one line, bounded.
TEST_F(PlanTest, NamesAreShortUtf8TextOnOneLine) {
  expect_error("long.csv", "# name: " + std::string(kMaxPlanNameBytes + 1, 'n') + "\nJ1\n0\n", {"long.csv:1", "name", "longer than"});
  expect_error("bin.csv", "# name: a\x01b\nJ1\n0\n", {"bin.csv:1", "control character"});
  expect_error("utf.csv", "# name: caf\xe9\nJ1\n0\n", {"utf.csv:1", "not valid UTF-8"});
  EXPECT_EQ(load_plan(scene_, dir_.write("ok.csv", "# name: 着陆 plan\nJ1\n0\n")).name, "着陆 plan");
  EXPECT_EQ(load_plan(scene_, dir_.write("max.csv", "# name: " + std::string(kMaxPlanNameBytes, 'n') + "\nJ1\n0\n")).name.size(),
            kMaxPlanNameBytes);
}

}  // namespace
}  // namespace plancheck
