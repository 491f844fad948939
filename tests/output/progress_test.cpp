// SPDX-License-Identifier: MIT
// Progress lines (src/base/progress.h) and the command line's --quiet.
#include "src/base/progress.h"

#include "support/fixtures.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <sstream>
#include <thread>
#include <vector>

namespace plancheck {
namespace {

namespace fs = std::filesystem;

TEST(Progress, PlainLinesWhenNotATerminal) {
  std::ostringstream err;
  {
    Progress p("verify", 40, "states", ProgressOptions{.terminal = 0, .interval = 0.05}, &err);
    for (int i = 0; i < 4; ++i) {
      p.add(10);
      std::this_thread::sleep_for(std::chrono::milliseconds(30));
    }
    p.finish();
    p.finish();  // once only
  }
  const std::string text = err.str();
  EXPECT_EQ(text.find('\r'), std::string::npos);  // no redrawing off a terminal
  std::istringstream lines(text);
  std::string line, last;
  int count = 0;
  while (std::getline(lines, line)) {
    // "verify: D/40 states (P%), R/s, ETA T" while running, "..., T s" at the end.
    std::size_t done = 0, pct = 0;
    double rate = 0;
    char tail[64] = {};
    ASSERT_EQ(std::sscanf(line.c_str(), "verify: %zu/40 states (%zu%%), %lf/s, %63[^\n]", &done, &pct, &rate, tail), 4) << line;
    EXPECT_EQ(pct, (100 * done + 20) / 40) << line;  // rounded
    const std::string t = tail;
    EXPECT_TRUE(t.rfind("ETA ", 0) == 0 || (t.size() > 2 && t.substr(t.size() - 2) == " s")) << line;
    last = line;
    ++count;
  }
  EXPECT_GE(count, 2);  // some while it ran, then the final one
  EXPECT_EQ(last.rfind("verify: 40/40 states (100%), ", 0), 0u) << last;
  EXPECT_EQ(last.find("ETA"), std::string::npos) << last;
}

TEST(Progress, RedrawsInPlaceOnATerminal) {
  std::ostringstream err;
  {
    Progress p("sweep", 100, "configurations", ProgressOptions{.terminal = 1}, &err);
    p.add(100);
  }
  const std::string text = err.str();
  EXPECT_EQ(text.rfind("\r\x1b[K", 0), 0u);
  EXPECT_EQ(text.back(), '\n');
  EXPECT_NE(text.find("100/100 configurations (100%)"), std::string::npos);
}

TEST(Progress, QuietPrintsNothing) {
  std::ostringstream err;
  {
    Progress p("verify", 10, "states", ProgressOptions{.quiet = true}, &err);
    p.add(10);
  }
  EXPECT_EQ(err.str(), "");
}

TEST(Progress, LineGivesRateAndEta) {
  Progress p("dig", 1000, "states", ProgressOptions{.quiet = true});
  EXPECT_EQ(p.line(250, 10.0), "dig: 250/1000 states (25%), 25/s, ETA 30.0 s");
  EXPECT_EQ(p.line(1000, 20.0), "dig: 1000/1000 states (100%), 50/s, 20.0 s");
  EXPECT_EQ(format_duration(125), "2 min 05 s");
  EXPECT_EQ(format_duration(3 * 3600 + 60 * 7), "3 h 07 min");
}

TEST(Progress, ThreadsAddWithoutLosingCounts) {
  std::ostringstream err;
  Progress p("verify", 40000, "states", ProgressOptions{.terminal = 0, .interval = 0.01}, &err);
  std::vector<std::thread> workers;
  for (int t = 0; t < 4; ++t)
    workers.emplace_back([&] {
      for (int i = 0; i < 10000; ++i) p.add();
    });
  for (auto& w : workers) w.join();
  p.finish();
  EXPECT_EQ(p.done(), 40000u);
  EXPECT_NE(err.str().find("40000/40000 states (100%)"), std::string::npos);
}

// The command line: stderr holds the progress line off a terminal, nothing with --quiet.
TEST(Progress, VerifyQuietLeavesStderrEmpty) {
  const fs::path data = fs::path(PLANCHECK_SOURCE_DIR) / "datasets/change5";
  if (!fs::exists(data / "scene.json")) GTEST_SKIP() << "run make dataset";
  testing::TempDir dir("progress_cli");
  const std::string exe = (fs::path(PLANCHECK_BINARY_DIR) / "plancheck").string();
  const std::string cmd = exe + " verify " + (data / "scene.json").string() + " " + (data / "plans/plan01.csv").string() +
                          " --out " + dir.path().string();
  ASSERT_EQ(testing::run_command(cmd + " > /dev/null 2> " + (dir / "err.txt").string()), 0);
  // Off a terminal: the status lines, then the final progress line.
  const std::string err = testing::read_text(dir / "err.txt");
  const std::size_t at = err.find("\nverify: 381/381 states (100%), ");
  ASSERT_NE(at, std::string::npos) << err;
  EXPECT_EQ(err.find('\r'), std::string::npos);
  ASSERT_EQ(testing::run_command(cmd + " --quiet > /dev/null 2> " + (dir / "quiet.txt").string()), 0);
  EXPECT_EQ(testing::read_text(dir / "quiet.txt"), "");
  // dig and sweep too.
  ASSERT_EQ(testing::run_command(exe + " dig " + (data / "scene.json").string() + " " + (data / "plans/plan01.csv").string() +
                                 " --quiet --out " + (dir / "dig").string() + " > /dev/null 2> " + (dir / "dig.txt").string()),
            0);
  EXPECT_EQ(testing::read_text(dir / "dig.txt"), "");
}

}  // namespace
}  // namespace plancheck
