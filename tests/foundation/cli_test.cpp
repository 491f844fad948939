// SPDX-License-Identifier: MIT
// The plancheck executable: `scene` output and the exit-status contract.
#include "tests/foundation/fixtures.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <sys/wait.h>

namespace plancheck {
namespace {

struct CliRun {
  int status = -1;
  std::string out;
  std::string err;
};

CliRun run_plancheck(const testing::TempDir& dir, const std::string& args) {
  const auto out = dir / "stdout.txt";
  const auto err = dir / "stderr.txt";
  const std::string command = std::string(PLANCHECK_BINARY_DIR) + "/plancheck " + args + " >" + out.string() +
                              " 2>" + err.string();
  const int raw = std::system(command.c_str());
  CliRun r;
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  auto slurp = [](const std::filesystem::path& p) {
    std::ifstream in(p);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  };
  r.out = slurp(out);
  r.err = slurp(err);
  return r;
}

class CliTest : public ::testing::Test {
 protected:
  void SetUp() override { testing::write_arm_model(dir_ / "arm.gltf"); }
  testing::TempDir dir_;
};

TEST_F(CliTest, SceneListsPartsActionsAndPairs) {
  const auto scene = dir_.write("s.json", R"({"format": "plancheck-scene/1", "model": "arm.gltf",
      "actions": [{"name": "J1", "node": "arm1", "type": "rotate", "pivot": [0, 0, 0], "axis": [0, 0, 1],
                   "limits": [-170, 170]}],
      "allowed_collisions": [["arm1", "base"]]})");
  const CliRun r = run_plancheck(dir_, "scene " + scene.string());
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;
  for (const char* part : {"base", "mast", "arm1", "arm2", "tip", "arm1b"})
    EXPECT_NE(r.out.find("  " + std::string(part) + "  "), std::string::npos) << part << "\n" << r.out;
  EXPECT_NE(r.out.find("arm1  12 triangles  moving  chain: J1"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("base  12 triangles  static"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("J1  rotate  node arm1  limits [-170, 170] deg"), std::string::npos) << r.out;
  // Moving: arm1, arm2, tip, arm1b (one chain); static: base, mast. 8 pairs, minus
  // the 4 allowed against base.
  EXPECT_NE(r.out.find("checked pairs (4):"), std::string::npos) << r.out;
  const std::size_t contacts = r.out.find("contacts at reference pose (");
  ASSERT_NE(contacts, std::string::npos) << r.out;
  const std::string pairs = r.out.substr(0, contacts);
  EXPECT_NE(pairs.find("mast - arm1"), std::string::npos) << r.out;
  EXPECT_EQ(pairs.find("base - arm1"), std::string::npos) << r.out;
}

TEST_F(CliTest, BadSceneExitsTwoWithOneLineNamingTheFile) {
  const auto scene = dir_.write("broken.json", R"({"format": "plancheck-scene/1", "model": "arm.gltf", "actoins": []})");
  const CliRun r = run_plancheck(dir_, "scene " + scene.string());
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(r.out.empty()) << r.out;
  EXPECT_EQ(r.err, "plancheck: " + scene.string() + ": actoins: unknown key\n");
}

TEST_F(CliTest, MissingFilesAndUsageErrorsExitTwo) {
  const CliRun missing = run_plancheck(dir_, "scene " + (dir_ / "nothere.json").string());
  EXPECT_EQ(missing.status, 2);
  EXPECT_NE(missing.err.find("nothere.json"), std::string::npos);
  EXPECT_EQ(std::count(missing.err.begin(), missing.err.end(), '\n'), 1) << missing.err;
  const auto bad_model = dir_.write("m.json", R"({"format": "plancheck-scene/1", "model": "garbage.obj"})");
  dir_.write("garbage.obj", "not a model at all\n");
  const CliRun model = run_plancheck(dir_, "scene " + bad_model.string());
  EXPECT_EQ(model.status, 2);
  EXPECT_NE(model.err.find("plancheck: "), std::string::npos);
  EXPECT_NE(model.err.find("garbage.obj"), std::string::npos) << model.err;
  for (const char* args : {"", "scene", "frobnicate x", "scene a.json b.json"}) {
    const CliRun usage = run_plancheck(dir_, args);
    EXPECT_EQ(usage.status, 2) << args;
    EXPECT_EQ(usage.err.rfind("plancheck: ", 0), 0u) << usage.err;
    EXPECT_EQ(std::count(usage.err.begin(), usage.err.end(), '\n'), 1) << usage.err;
  }
  const CliRun help = run_plancheck(dir_, "--help");
  EXPECT_EQ(help.status, 0);
  EXPECT_NE(help.out.find("scene"), std::string::npos);
}

}  // namespace
}  // namespace plancheck
