// SPDX-License-Identifier: MIT
// Files from other people (issue "Hostile files"): plan names that are
// paths, links planted in --out, devices and FIFOs as inputs, lines and
// records that lie about their size, names with commas, quotes, escape
// sequences and bytes that are not UTF-8. Each case runs the plancheck
// executable as a user would, or the engine it calls.
#include "src/base/error.h"
#include "src/base/files.h"
#include "src/base/text.h"
#include "support/fixtures.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace plancheck {
namespace {

namespace fs = std::filesystem;
using testing::TempDir;
using testing::read_text;
using testing::write_text;

struct CliRun {
  int status = -1;
  std::string out, err;
};

std::string quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// `plancheck ARGS` (each quoted for the shell), stdout and stderr captured;
// at most `seconds` (timeout(1) kills it: a hang is a failure, not a stall).
CliRun plancheck(const TempDir& dir, const std::vector<std::string>& args, int seconds = 120) {
  std::string cmd = "timeout " + std::to_string(seconds) + " " + std::string(PLANCHECK_BINARY_DIR) + "/plancheck";
  for (const auto& a : args) cmd += " " + quote(a);
  cmd += " >" + quote((dir / "stdout.txt").string()) + " 2>" + quote((dir / "stderr.txt").string()) + " </dev/null";
  const int raw = std::system(cmd.c_str());
  CliRun r;
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  r.out = read_text(dir / "stdout.txt");
  r.err = read_text(dir / "stderr.txt");
  return r;
}

// A base box and an arm box turned by J1 about z; `arm` names the arm part.
fs::path write_scene(const TempDir& dir, const std::string& arm = "arm", const std::string& joint = "J1",
                     const std::string& file = "scene.json", const std::string& moved = "") {
  testing::write_obj(dir / "model.obj", {{"base", testing::box_mesh({-1, -1, -0.5}, {1, 1, 0})},
                                         {arm, testing::box_mesh({-0.1, -0.1, 0.5}, {2, 0.1, 0.7})}});
  nlohmann::json scene = {{"format", "plancheck-scene/1"},
                          {"model", "model.obj"},
                          {"safety_margin", 0.01},
                          {"actions", {{{"name", joint}, {"node", moved.empty() ? arm : moved}, {"type", "rotate"},
                                        {"pivot", {0, 0, 0}}, {"axis", {0, 0, 1}}, {"limits", {-180, 180}}}}}};
  write_text(dir / file, scene.dump());
  return dir / file;
}

fs::path write_plan(const TempDir& dir, const std::string& file, const std::string& name_line,
                    const std::string& header = "J1") {
  write_text(dir / file, name_line + header + "\n0\n10\n20\n");
  return dir / file;
}

std::vector<std::string> files_in(const fs::path& dir) {
  std::vector<std::string> names;
  if (!fs::exists(dir)) return names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  return names;
}

// ---- 1. A plan's name is no path -------------------------------------------

TEST(HostileFiles, PlanNamesNeverNameAPathOutsideOut) {
  TempDir dir("hostile");
  const auto scene = write_scene(dir);
  fs::create_directories(dir / "deep" / "er");
  write_text(dir / "victim.csv", "precious\n");
  write_text(dir / "abs.csv", "precious\n");
  const auto up = write_plan(dir, "up.csv", "# name: ../../victim\n");
  const auto abs = write_plan(dir, "abs-plan.csv", "# name: " + (dir / "abs").string() + "\n");
  const auto dots = write_plan(dir, "dots.csv", "# name: ..\n");
  const fs::path out = dir / "deep" / "er" / "out";
  const CliRun r = plancheck(dir, {"verify", scene.string(), up.string(), abs.string(), dots.string(), "--out", out.string()});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(read_text(dir / "victim.csv"), "precious\n");
  EXPECT_EQ(read_text(dir / "abs.csv"), "precious\n");
  EXPECT_FALSE(fs::exists(dir / "deep" / "victim.csv"));
  // Every CSV is a plain file in --out, and report.json says which is whose.
  const nlohmann::json report = nlohmann::json::parse(read_text(out / "report.json"));
  ASSERT_EQ(report["plans"].size(), 3u);
  for (const auto& p : report["plans"]) {
    const std::string csv = p["csv"].get<std::string>();
    EXPECT_EQ(csv.find('/'), std::string::npos) << csv;
    EXPECT_NE(csv.front(), '.') << csv;
    EXPECT_TRUE(fs::is_regular_file(out / csv)) << csv;
  }
  EXPECT_EQ(files_in(out).size(), 4u);  // three CSVs and report.json, nothing else
}

TEST(HostileFiles, TwoPlansWritingOneCsvAreRefusedBeforeAnyCheck) {
  TempDir dir("hostile");
  const auto scene = write_scene(dir);
  const auto a = write_plan(dir, "a.csv", "# name: x/y\n");
  const auto b = write_plan(dir, "b.csv", "# name: x_y\n");
  const CliRun r = plancheck(dir, {"verify", scene.string(), a.string(), b.string(), "--out", (dir / "out").string()});
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find(a.string()), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(b.string()), std::string::npos) << r.err;
  EXPECT_TRUE(files_in(dir / "out").empty()) << r.err;
  // The same name twice (a plan given twice) likewise.
  const CliRun twice = plancheck(dir, {"verify", scene.string(), a.string(), a.string(), "--out", (dir / "out").string()});
  EXPECT_EQ(twice.status, 2);
  EXPECT_TRUE(files_in(dir / "out").empty());
}

// ---- 2. Links planted in --out are never written through --------------------

TEST(HostileFiles, LinksPlantedInOutAreReplacedNeverFollowed) {
  TempDir dir("hostile");
  const auto scene = write_scene(dir);
  const auto plan = write_plan(dir, "p.csv", "");
  const fs::path out = dir / "out";
  fs::create_directories(out);
  std::vector<fs::path> targets;
  for (const char* name : {".plancheck-journal", "report.json", "report.json.tmp", "p.csv", "p.csv.tmp", "report.html"}) {
    const fs::path target = dir / ("target-" + std::string(name[0] == '.' ? name + 1 : name));
    write_text(target, "precious\n");
    fs::create_symlink(target, out / name);
    targets.push_back(target);
  }
  const CliRun r = plancheck(dir, {"verify", scene.string(), plan.string(), "--out", out.string()});
  ASSERT_EQ(r.status, 0) << r.err;
  for (const fs::path& t : targets) EXPECT_EQ(read_text(t), "precious\n") << t;
  EXPECT_TRUE(fs::is_regular_file(fs::symlink_status(out / "report.json")));
  EXPECT_TRUE(fs::is_regular_file(fs::symlink_status(out / "p.csv")));
  EXPECT_FALSE(fs::exists(fs::symlink_status(out / ".plancheck-journal")));

  // sweep's outputs and their temporaries, and --resume's journal.
  const fs::path sweep_out = dir / "sweep";
  fs::create_directories(sweep_out);
  for (const char* name : {"sweep.json", "sweep.json.tmp", "verdict.npy", "verdict.npy.partial", "sweep.csv.tmp",
                           ".plancheck-journal"}) {
    const fs::path target = dir / ("sweep-target-" + std::string(name[0] == '.' ? name + 1 : name));
    write_text(target, "precious\n");
    fs::create_symlink(target, sweep_out / name);
    targets.push_back(target);
  }
  const CliRun s = plancheck(dir, {"sweep", scene.string(), "--steps", "5", "--csv", "--resume", "--out", sweep_out.string()});
  ASSERT_EQ(s.status, 0) << s.err;
  for (const fs::path& t : targets) EXPECT_EQ(read_text(t), "precious\n") << t;
  EXPECT_TRUE(fs::is_regular_file(fs::symlink_status(sweep_out / "verdict.npy")));
}

// The primitives themselves: a fresh temporary each time, a link at the final
// name replaced, a link at a journal refused or replaced.
TEST(HostileFiles, WriteFileAtomicallyReplacesALinkAndLeavesNoTemporary) {
  TempDir dir("hostile");
  write_text(dir / "target", "precious\n");
  fs::create_symlink(dir / "target", dir / "out.txt");
  write_file_atomically(dir / "out.txt", "new\n");
  EXPECT_EQ(read_text(dir / "target"), "precious\n");
  EXPECT_EQ(read_text(dir / "out.txt"), "new\n");
  EXPECT_FALSE(fs::is_symlink(dir / "out.txt"));
  EXPECT_EQ(files_in(dir.path()).size(), 2u);  // no temporary left
  fs::create_symlink(dir / "target", dir / "journal");
  EXPECT_THROW(close(open_for_append(dir / "journal", 10)), InputError);  // continue through a link: no
  EXPECT_EQ(read_text(dir / "target"), "precious\n");
  const int fd = open_for_append(dir / "journal", 0);  // start anew: the link goes, a file comes
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::write(fd, "j", 1), 1);
  ::close(fd);
  EXPECT_FALSE(fs::is_symlink(dir / "journal"));
  EXPECT_EQ(read_text(dir / "target"), "precious\n");
  // What a killed run leaves is cleared by the next; nothing else is.
  fs::create_directories(dir / "out");
  for (const char* name : {".report.json.0123456789abcdef.tmp", ".keep.tmp", "mine.0123456789abcdef.tmp",
                           ".x.0123456789ABCDEF.tmp", ".p.csv.00000000000000zz.tmp"})
    write_text(dir / "out" / name, "x");
  fs::create_symlink(dir / "target", dir / "out" / ".verdict.npy.fedcba9876543210.tmp");
  remove_stale_temporaries(dir / "out");
  std::vector<std::string> left = files_in(dir / "out");
  std::sort(left.begin(), left.end());
  EXPECT_EQ(left, (std::vector<std::string>{".keep.tmp", ".p.csv.00000000000000zz.tmp", ".x.0123456789ABCDEF.tmp",
                                            "mine.0123456789abcdef.tmp"}));
  EXPECT_EQ(read_text(dir / "target"), "precious\n");
}

// ---- 3 (page escaping) is tested with the page writer -----------------------

// ---- 4. Records and headers that lie about sizes: tests/cli/distribute_test.cpp

// ---- 5. Devices, FIFOs and folders as inputs ---------------------------------

TEST(HostileFiles, DevicesFifosAndFoldersAreRefusedAtOnce) {
  TempDir dir("hostile");
  const auto scene = write_scene(dir);
  const auto plan = write_plan(dir, "p.csv", "");
  ASSERT_EQ(::mkfifo((dir / "fifo").c_str(), 0600), 0);
  fs::create_directories(dir / "folder.json");
  for (const std::string& bad : {std::string("/dev/zero"), (dir / "fifo").string(), (dir / "folder.json").string()}) {
    const CliRun s = plancheck(dir, {"scene", bad}, 30);
    EXPECT_EQ(s.status, 2) << bad << ": " << s.err;
    EXPECT_NE(s.err.find(bad), std::string::npos) << s.err;
    EXPECT_TRUE(s.err.find("regular file") != std::string::npos || s.err.find("folder") != std::string::npos) << s.err;
    const CliRun v = plancheck(dir, {"verify", scene.string(), bad, "--out", (dir / "out").string()}, 30);
    EXPECT_EQ(v.status, 2) << bad << ": " << v.err;
    EXPECT_NE(v.err.find(bad), std::string::npos) << v.err;
  }
  EXPECT_THROW(read_regular_file("/dev/zero", 1 << 20, "scene file"), InputError);
}

// ---- 6. Long lines fail early, in bounded memory ----------------------------

[[maybe_unused]] long peak_child_kb() {  // (read by Release runs only)
  rusage u{};
  getrusage(RUSAGE_CHILDREN, &u);
  return u.ru_maxrss;
}

TEST(HostileFiles, AHugeLineFailsAtItsLineInBoundedMemory) {
  TempDir dir("hostile");
  const auto scene = write_scene(dir);
  const std::size_t huge = std::size_t{96} << 20;  // 96 MiB on one line
  {
    std::ofstream f(dir / "long.csv", std::ios::binary);
    f << "J1\n0\n# name: ";
    std::string block(std::size_t{1} << 20, 'a');
    for (std::size_t k = 0; k < huge >> 20; ++k) f << block;
    f << "\n";
  }
  const CliRun r = plancheck(dir, {"verify", scene.string(), (dir / "long.csv").string(), "--out", (dir / "out").string()});
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find("long.csv:3"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("longer than"), std::string::npos) << r.err;
#ifndef PLANCHECK_SANITIZED  // ASan's shadow and quarantine hold memory of their own: the Release run checks it
  EXPECT_LT(peak_child_kb(), 80 * 1024) << "the line was held whole";
#endif
  // The reader itself: the same limit on any line, before it is held.
  EXPECT_THROW(
      {
        LineReader in(dir / "long.csv", "plan file");
        std::string line;
        while (in.next(line)) {
        }
      },
      InputError);
}

// ---- 7. RFC 4180 in and out --------------------------------------------------

// A minimal RFC 4180 reader for the assertions (one record per call).
std::vector<std::string> parse_record(const std::string& text, std::size_t& at) {
  std::vector<std::string> fields(1);
  bool quoted = false;
  for (; at < text.size(); ++at) {
    const char c = text[at];
    if (quoted) {
      if (c == '"' && at + 1 < text.size() && text[at + 1] == '"') {
        fields.back() += '"';
        ++at;
      } else if (c == '"') {
        quoted = false;
      } else {
        fields.back() += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      fields.emplace_back();
    } else if (c == '\n') {
      ++at;
      return fields;
    } else {
      fields.back() += c;
    }
  }
  return fields;
}

TEST(HostileFiles, CsvFieldsAreQuotedAndPlanHeadersReadTheSameWay) {
  TempDir dir("hostile");
  const std::string arm = "arm,\"the\"one";  // (an OBJ name ends at a blank)
  const std::string joint = "J,1 \"x\"";
  const auto scene = write_scene(dir, arm, joint);
  write_text(dir / "p.csv", "\"J,1 \"\"x\"\"\"\n0\n90\n");
  const fs::path out = dir / "out";
  const CliRun r = plancheck(dir, {"verify", scene.string(), (dir / "p.csv").string(), "--out", out.string()});
  ASSERT_LE(r.status, 1) << r.err;
  const std::string csv = read_text(out / "p.csv");
  std::size_t at = 0;
  const auto header = parse_record(csv, at);
  const std::size_t part_a = std::find(header.begin(), header.end(), "part_a") - header.begin();
  ASSERT_LT(part_a, header.size());
  for (int row = 0; row < 2; ++row) {
    const auto fields = parse_record(csv, at);
    ASSERT_EQ(fields.size(), header.size()) << csv;
    EXPECT_TRUE(fields[part_a] == arm || fields[part_a + 1] == arm) << csv;
  }
  // sweep.csv's header names the joint as one field.
  const CliRun s = plancheck(dir, {"sweep", scene.string(), "--steps", "3", "--csv", "--out", (dir / "sweep").string()});
  ASSERT_EQ(s.status, 0) << s.err;
  const std::string sweep = read_text(dir / "sweep" / "sweep.csv");
  at = 0;
  const auto sweep_header = parse_record(sweep, at);
  EXPECT_EQ(sweep_header.front(), joint) << sweep;
  const auto first = parse_record(sweep, at);
  EXPECT_EQ(first.size(), sweep_header.size()) << sweep;
}

// ---- 8, 9. Names that are not text ------------------------------------------

TEST(HostileFiles, NamesThatAreNotUtf8AreRefusedBeforeAnyCheck) {
  TempDir dir("hostile");
  // (the scene's JSON cannot hold such a name: its action moves the base)
  const auto scene = write_scene(dir, std::string("arm\xff\xfe"), "J1", "scene.json", "base");
  const auto plan = write_plan(dir, "p.csv", "");
  const CliRun r = plancheck(dir, {"verify", scene.string(), plan.string(), "--out", (dir / "out").string()});
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find("model.obj"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("UTF-8"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("\\xff"), std::string::npos) << r.err;
  EXPECT_TRUE(files_in(dir / "out").empty());

  const auto good_scene = write_scene(dir, "arm", "J1", "good.json");
  const auto bad_plan = write_plan(dir, "q.csv", "# name: q\xc3\x28\n");
  const CliRun q = plancheck(dir, {"verify", good_scene.string(), bad_plan.string(), "--out", (dir / "out").string()});
  EXPECT_EQ(q.status, 2) << q.err;
  EXPECT_NE(q.err.find("q.csv:1"), std::string::npos) << q.err;
  EXPECT_TRUE(files_in(dir / "out").empty());
}

TEST(HostileFiles, NamesReachTheTerminalEscaped) {
  TempDir dir("hostile");
  const std::string arm = "arm\x1b[2J\x07";
  const auto scene = write_scene(dir, arm);
  const CliRun r = plancheck(dir, {"scene", scene.string()});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out.find('\x1b'), std::string::npos);
  EXPECT_EQ(r.out.find('\x07'), std::string::npos);
  EXPECT_NE(r.out.find("arm\\x1b[2J\\x07"), std::string::npos) << r.out;
  // In messages too: a plan column naming it.
  write_text(dir / "p.csv", "J1,\"x\x1b[31m\ny\"\n0,0\n");
  const CliRun v =
      plancheck(dir, {"verify", scene.string(), (dir / "p.csv").string(), "--out", (dir / "out").string(), "--quiet"});
  EXPECT_EQ(v.status, 2) << v.err;
  EXPECT_EQ(v.err.find('\x1b'), std::string::npos) << v.err;
  EXPECT_EQ(std::count(v.err.begin(), v.err.end(), '\n'), 1) << v.err;
  EXPECT_EQ(printable("a\nb\x1b\xc2\x85\xff"), "a\\nb\\x1b\\u{85}\\xff");
  EXPECT_EQ(printable("Zuò \xe7\xab\x99"), "Zuò \xe7\xab\x99");  // text in any script as it is
}

// ---- 12. The smaller ones ------------------------------------------------------

TEST(HostileFiles, ParseErrorsDoNotEchoTheFile) {
  TempDir dir("hostile");
  // (an unterminated string: the parser has read all of it when it fails)
  write_text(dir / "s.json", "{\"format\": \"plancheck-scene/1\", \"model\": \"hunter2secret\n}");
  const CliRun r = plancheck(dir, {"scene", (dir / "s.json").string()});
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.err.find("hunter2"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("s.json:1:"), std::string::npos) << r.err;
}

TEST(HostileFiles, OptionValuesAreCheckedWithShortMessages) {
  TempDir dir("hostile");
  const auto scene = write_scene(dir);
  const auto plan = write_plan(dir, "p.csv", "");
  const CliRun threads = plancheck(dir, {"verify", scene.string(), plan.string(), "--threads", "-1"});
  EXPECT_EQ(threads.status, 2);
  EXPECT_LT(threads.err.size(), 200u) << threads.err;
  EXPECT_NE(threads.err.find("4096"), std::string::npos) << threads.err;
  const CliRun nan = plancheck(dir, {"verify", scene.string(), plan.string(), "--continuous", "--continuous-tolerance", "nan"});
  EXPECT_EQ(nan.status, 2) << nan.err;
  const CliRun comma = plancheck(dir, {"sweep", scene.string(), "--grid", "J1=0:10:5,", "--out", (dir / "s").string()});
  EXPECT_EQ(comma.status, 2) << comma.err;
  EXPECT_NE(comma.err.find("--grid"), std::string::npos) << comma.err;
}

}  // namespace
}  // namespace plancheck
