// SPDX-License-Identifier: MIT
// expected.json is the generator's own verdict on its plans. Before the real
// verifier exists, confirm the designed violations and the reported closest
// pairs with a peer library (FCL 0.7, OBBRSS, exact distance) on the model as
// assimp reads it, posed with scene.json's kinematics.
#include <assimp/Importer.hpp>
#include <assimp/scene.h>
#include <fcl/fcl.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "dataset/generated.h"

namespace plancheck {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
constexpr double kPi = 3.14159265358979323846;

using Model = fcl::BVHModel<fcl::OBBRSSd>;

struct Fixture {
  fs::path dir;
  json scene, expected;
  Assimp::Importer importer;
  const aiScene* model = nullptr;
  std::map<std::string, const aiNode*> nodes;
  std::map<std::string, std::vector<std::vector<double>>> plans;
};

void index_nodes(const aiNode* n, std::map<std::string, const aiNode*>& out) {
  out[n->mName.C_Str()] = n;
  for (unsigned i = 0; i < n->mNumChildren; ++i) index_nodes(n->mChildren[i], out);
}

std::vector<std::vector<double>> read_rows(const fs::path& p) {
  std::vector<std::vector<double>> rows;
  std::ifstream in(p);
  std::string line;
  bool header = false;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (!header) {
      header = true;
      continue;
    }
    std::vector<double> r;
    std::stringstream ss(line);
    std::string f;
    while (std::getline(ss, f, ',')) r.push_back(std::stod(f));
    rows.push_back(r);
  }
  return rows;
}

Fixture* g_fixture = nullptr;

class ExpectedVsFcl : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    g_fixture = new Fixture;
    Fixture& f = *g_fixture;
    f.dir = testing::generated_dataset();
    if (!fs::exists(f.dir / "scene.json")) return;
    f.scene = json::parse(std::ifstream(f.dir / "scene.json"));
    f.expected = json::parse(std::ifstream(f.dir / "expected.json"));
    f.model = f.importer.ReadFile((f.dir / "change5.3ds").string(), 0);
    if (f.model) index_nodes(f.model->mRootNode, f.nodes);
    for (const auto& [name, p] : f.expected["plans"].items()) f.plans[name] = read_rows(f.dir / p["file"].get<std::string>());
  }
  static void TearDownTestSuite() { delete g_fixture; }
  void SetUp() override {
    ASSERT_NE(g_fixture->model, nullptr) << "no generated dataset (fixture DatasetFixture.Generate) or its model did not load";
  }
  Fixture& f() { return *g_fixture; }

  // Number of joints that move a part: ArmJk -> k, Scoop -> 4, lander parts -> 0.
  int chain_length(const std::string& part) {
    const char* joints[4] = {"J1", "J2", "J3", "J4"};
    for (int k = 4; k >= 1; --k) {
      const aiNode* j = f().nodes[joints[k - 1]];
      for (const aiNode* n = f().nodes[part]; n; n = n->mParent)
        if (n == j) return k;
    }
    return 0;
  }

  // The part's mesh in the reference frame, built once.
  std::shared_ptr<Model> bvh(const std::string& part) {
    auto& cached = cache_[part];
    if (cached) return cached;
    cached = std::make_shared<Model>();
    std::vector<fcl::Vector3d> v;
    std::vector<fcl::Triangle> t;
    const aiNode* n = f().nodes[part];
    for (unsigned m = 0; m < n->mNumMeshes; ++m) {
      const aiMesh* mesh = f().model->mMeshes[n->mMeshes[m]];
      std::size_t base = v.size();
      for (unsigned i = 0; i < mesh->mNumVertices; ++i)
        v.emplace_back(mesh->mVertices[i].x, mesh->mVertices[i].y, mesh->mVertices[i].z);
      for (unsigned i = 0; i < mesh->mNumFaces; ++i)
        t.emplace_back(base + mesh->mFaces[i].mIndices[0], base + mesh->mFaces[i].mIndices[1], base + mesh->mFaces[i].mIndices[2]);
    }
    cached->beginModel();
    cached->addSubModel(v, t);
    cached->endModel();
    return cached;
  }

  // scene.json's composition A1(A2(...Ak(x))) as one rigid transform.
  fcl::Transform3d pose(const std::string& part, const std::vector<double>& deg) {
    fcl::Transform3d t = fcl::Transform3d::Identity();
    int k = chains_.count(part) ? chains_[part] : chain_length(part);
    for (int a = 0; a < k; ++a) {
      const json& act = f().scene["actions"][static_cast<std::size_t>(a)];
      Eigen::Vector3d pivot(act["pivot"][0].get<double>(), act["pivot"][1].get<double>(), act["pivot"][2].get<double>());
      Eigen::Vector3d axis(act["axis"][0].get<double>(), act["axis"][1].get<double>(), act["axis"][2].get<double>());
      fcl::Transform3d step = fcl::Transform3d::Identity();
      step.translate(pivot);
      step.rotate(Eigen::AngleAxisd(deg[static_cast<std::size_t>(a)] * kPi / 180.0, axis.normalized()));
      step.translate(-pivot);
      t = t * step;
    }
    return t;
  }

  // One collision object per part, re-posed per query (building one scans every vertex).
  fcl::CollisionObjectd& object(const std::string& part, const std::vector<double>& deg) {
    auto& o = objects_[part];
    if (!o) {
      o = std::make_unique<fcl::CollisionObjectd>(bvh(part));
      chains_[part] = chain_length(part);
    }
    if (chains_[part] > 0) {
      o->setTransform(pose(part, deg));
      o->computeAABB();
    }
    return *o;
  }

  double distance(const std::string& a, const std::string& b, const std::vector<double>& deg) {
    fcl::DistanceRequestd req;
    fcl::DistanceResultd res;
    fcl::distance(&object(a, deg), &object(b, deg), req, res);
    return std::max(0.0, res.min_distance);
  }
  bool collide(const std::string& a, const std::string& b, const std::vector<double>& deg) {
    fcl::CollisionRequestd req;
    fcl::CollisionResultd res;
    fcl::collide(&object(a, deg), &object(b, deg), req, res);
    return res.isCollision();
  }

  std::map<std::string, std::unique_ptr<fcl::CollisionObjectd>> objects_;
  std::map<std::string, int> chains_;
  std::map<std::string, std::shared_ptr<Model>> cache_;
};

TEST_F(ExpectedVsFcl, DesignedCollisionStartsWhereExpected) {
  for (const auto& [name, p] : f().expected["plans"].items()) {
    if (p["verdict"] != "collision") continue;
    int first = p["first_violation"]["state"].get<int>();
    std::string a = p["first_violation"]["parts"][0], b = p["first_violation"]["parts"][1];
    const auto& rows = f().plans[name];
    EXPECT_TRUE(collide(a, b, rows[static_cast<std::size_t>(first)])) << name << " state " << first;
    // The state before is clear of that part by more than the margin.
    EXPECT_GE(distance(a, b, rows[static_cast<std::size_t>(first - 1)]), 0.05) << name;
    int last = p["collision_states"].back()[1].get<int>();
    EXPECT_TRUE(collide(a, b, rows[static_cast<std::size_t>(last)])) << name << " state " << last;
    EXPECT_FALSE(collide(a, b, rows[static_cast<std::size_t>(last + 1)])) << name << " state " << last + 1;
  }
}

TEST_F(ExpectedVsFcl, ReportedClosestPairsHaveTheReportedDistance) {
  int compared = 0;
  for (const auto& [name, p] : f().expected["plans"].items()) {
    if (p["min_distance"].is_null() || p["min_distance"].get<double>() == 0.0) continue;
    std::string a = p["min_distance_parts"][0], b = p["min_distance_parts"][1];
    if (a == "terrain" || b == "terrain") continue;
    const auto& row = f().plans[name][p["min_distance_state"].get<std::size_t>()];
    EXPECT_NEAR(distance(a, b, row), p["min_distance"].get<double>(), 2e-6) << name << " " << a << "-" << b;
    ++compared;
  }
  EXPECT_GE(compared, 8);
}

TEST_F(ExpectedVsFcl, NearMissNeverTouches) {
  for (const auto& [name, p] : f().expected["plans"].items()) {
    if (p["verdict"] != "clearance") continue;
    std::string a = p["first_violation"]["parts"][0], b = p["first_violation"]["parts"][1];
    const auto& rows = f().plans[name];
    double lowest = 1e9;
    for (const auto& r : rows) lowest = std::min(lowest, distance(a, b, r));
    EXPECT_GT(lowest, 0.0) << name;
    EXPECT_LT(lowest, 0.05) << name;
    EXPECT_NEAR(lowest, p["min_distance"].get<double>(), 2e-6) << name;
  }
}

TEST_F(ExpectedVsFcl, SafePlansCollideWithNothingTheyMayNotTouch) {
  // Parts and the checked pairs per the scene contract, from the model and scene.json.
  std::vector<std::string> moving, fixed;
  for (const auto& [name, node] : f().nodes) {
    if (node->mNumMeshes == 0) continue;
    (chain_length(name) > 0 ? moving : fixed).push_back(name);
  }
  std::set<std::pair<std::string, std::string>> allowed;
  for (const json& p : f().scene["allowed_collisions"]) {
    allowed.insert({p[0].get<std::string>(), p[1].get<std::string>()});
    allowed.insert({p[1].get<std::string>(), p[0].get<std::string>()});
  }
  std::vector<std::pair<std::string, std::string>> pairs;
  for (std::size_t i = 0; i < moving.size(); ++i) {
    for (const std::string& s : fixed)
      if (!allowed.count({moving[i], s})) pairs.push_back({moving[i], s});
    for (std::size_t j = i + 1; j < moving.size(); ++j)
      if (chain_length(moving[i]) != chain_length(moving[j]) && !allowed.count({moving[i], moving[j]}))
        pairs.push_back({moving[i], moving[j]});
  }
  ASSERT_GT(pairs.size(), 100u);
  int checked = 0;
  for (const auto& [name, p] : f().expected["plans"].items()) {
    if (p["verdict"] != "safe") continue;
    const auto& rows = f().plans[name];
    for (std::size_t s = 0; s < rows.size(); ++s) {
      for (const auto& [a, b] : pairs) ASSERT_FALSE(collide(a, b, rows[s])) << name << " state " << s << ": " << a << "-" << b;
      ++checked;
    }
  }
  EXPECT_GT(checked, 2000);
}

}  // namespace
}  // namespace plancheck
