// SPDX-License-Identifier: MIT
// The default dataset as files: runs build/generate_change5 and checks what
// it wrote against the paper (Tables 2 and 3) and the contracts
// (scene-format.md, plan-and-report-format.md), reading the model back with
// assimp directly and re-deriving the plan targets from scene.json alone.
#include <assimp/Importer.hpp>
#include <assimp/scene.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "dataset/generated.h"

namespace plancheck {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr double kPi = 3.14159265358979323846;

// ctest runs each test in its own process, possibly in parallel: one folder per process.
fs::path temp_dir(const std::string& name) {
  fs::path d = fs::temp_directory_path() /
               ("plancheck_dataset_test_" + std::to_string(static_cast<long>(getpid())) + "_" + name);
  fs::remove_all(d);
  return d;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The dataset this build's fixture generated (generated.h).
class Dataset : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(fs::exists(dir() / "scene.json")) << "no generated dataset in " << dir()
                                                  << ": run the suite through ctest (fixture DatasetFixture.Generate)";
  }
  static fs::path dir() { return testing::generated_dataset(); }
  static json read_json(const std::string& name) { return json::parse(slurp(dir() / name)); }
};

// ---------------------------------------------------------------- model ----
struct ModelView {
  Assimp::Importer importer;
  const aiScene* scene = nullptr;
  std::map<std::string, const aiNode*> nodes;
};

void index_nodes(const aiNode* n, std::map<std::string, const aiNode*>& out) {
  out[n->mName.C_Str()] = n;
  for (unsigned i = 0; i < n->mNumChildren; ++i) index_nodes(n->mChildren[i], out);
}

std::size_t subtree_triangles(const aiScene* s, const aiNode* n) {
  std::size_t total = 0;
  for (unsigned i = 0; i < n->mNumMeshes; ++i) total += s->mMeshes[n->mMeshes[i]]->mNumFaces;
  for (unsigned i = 0; i < n->mNumChildren; ++i) total += subtree_triangles(s, n->mChildren[i]);
  return total;
}

void load(const fs::path& file, ModelView& v) {
  v.scene = v.importer.ReadFile(file.string(), 0);
  ASSERT_NE(v.scene, nullptr) << v.importer.GetErrorString();
  index_nodes(v.scene->mRootNode, v.nodes);
}

// A second run of the generator writes the fixture's bytes again. Checked in
// the Release build; the sanitizer builds skip it (it only repeats the run,
// at 1-4 minutes there, and the fixture already ran the generator under them).
TEST_F(Dataset, SameBytesOnEveryRun) {
#ifdef PLANCHECK_SANITIZED
  GTEST_SKIP() << "byte-for-byte rerun is checked in the Release build";
#endif
  fs::path b = temp_dir("b");
  ASSERT_EQ(testing::run_generator(b), 0);
  // Every file the second run wrote, against the fixture's: listed from the
  // second run's folder, since tests running beside this one (ApiDataset,
  // python's) put a short-lived scene file of their own into the fixture's.
  std::vector<std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(b))
    if (e.is_regular_file()) files.push_back(fs::relative(e.path(), b).string());
  EXPECT_GE(files.size(), 14u);  // model, scene, DEM, expected, 10 plans
  for (const std::string& f : files) {
    ASSERT_TRUE(fs::is_regular_file(dir() / f)) << f << " missing from the first run";
    EXPECT_TRUE(slurp(dir() / f) == slurp(b / f)) << f << " differs between runs";
  }
  fs::remove_all(b);
}

TEST_F(Dataset, TriangleCountsFollowTable2) {
  ModelView v;
  load(dir() / "change5.3ds", v);
  auto count = [&](const std::string& name) {
    EXPECT_TRUE(v.nodes.count(name)) << name;
    return v.nodes.count(name) ? subtree_triangles(v.scene, v.nodes[name]) : 0;
  };
  // Each joint's own link: its subtree minus the next joint's subtree.
  const std::map<std::string, std::size_t> table2{{"lander", 268730}, {"ascender", 120676}, {"J1", 5970},
                                                 {"J2", 8723},       {"J3", 8952},        {"J4", 7060},
                                                 {"Scoop", 2164}};
  std::map<std::string, std::size_t> got{{"lander", count("lander")},
                                         {"ascender", count("ascender")},
                                         {"J1", count("J1") - count("J2")},
                                         {"J2", count("J2") - count("J3")},
                                         {"J3", count("J3") - count("J4")},
                                         {"J4", count("J4") - count("Scoop")},
                                         {"Scoop", count("Scoop")}};
  std::size_t total = 0;
  for (const auto& [name, want] : table2) {
    EXPECT_NEAR(static_cast<double>(got[name]), static_cast<double>(want), 0.01 * static_cast<double>(want)) << name;
    total += got[name];
  }
  EXPECT_NEAR(static_cast<double>(total), 422275.0, 4222.75);
  std::size_t all = 0;
  for (unsigned m = 0; m < v.scene->mNumMeshes; ++m) all += v.scene->mMeshes[m]->mNumFaces;
  EXPECT_EQ(all, total) << "triangles outside the lander, ascender and arm groups";
}

TEST_F(Dataset, HierarchyFollowsFigure9AndTheSceneNamesExist) {
  ModelView v;
  load(dir() / "change5.3ds", v);
  auto parent_of = [&](const std::string& n) -> std::string {
    if (!v.nodes.count(n) || !v.nodes[n]->mParent) return "<missing>";
    return v.nodes[n]->mParent->mName.C_Str();
  };
  const std::string root = v.scene->mRootNode->mName.C_Str();
  EXPECT_EQ(parent_of("probe"), root);
  EXPECT_EQ(parent_of("arm"), root);
  EXPECT_EQ(parent_of("lander"), "probe");
  EXPECT_EQ(parent_of("ascender"), "probe");
  EXPECT_EQ(parent_of("J1"), "arm");
  EXPECT_EQ(parent_of("J2"), "J1");
  EXPECT_EQ(parent_of("J3"), "J2");
  EXPECT_EQ(parent_of("J4"), "J3");
  EXPECT_EQ(parent_of("ArmJ1"), "J1");
  EXPECT_EQ(parent_of("ArmJ2"), "J2");
  EXPECT_EQ(parent_of("ArmJ3"), "J3");
  EXPECT_EQ(parent_of("ArmJ4"), "J4");
  EXPECT_EQ(parent_of("Scoop"), "J4");
  // Joint nodes are groups: no mesh of their own, so no part shares a joint's name.
  for (const char* j : {"J1", "J2", "J3", "J4"}) EXPECT_EQ(v.nodes[j]->mNumMeshes, 0u) << j;

  json scene = read_json("scene.json");
  for (const json& a : scene["actions"]) EXPECT_TRUE(v.nodes.count(a["node"].get<std::string>())) << a["node"];
  for (const json& pair : scene["allowed_collisions"])
    for (const json& n : pair) {
      std::string name = n.get<std::string>();
      EXPECT_TRUE(name == "terrain" || v.nodes.count(name)) << name;
    }
  EXPECT_TRUE(v.nodes.count(scene["scoop"]["part"].get<std::string>()));
  for (const json& p : scene["probes"]) EXPECT_TRUE(v.nodes.count(p["part"].get<std::string>()));
  // Every non-root node carries an identity transform: the file is drawn at the reference pose.
  for (const auto& [name, node] : v.nodes)
    if (node != v.scene->mRootNode) {
      EXPECT_TRUE(node->mTransformation.IsIdentity()) << name;
    }
}

TEST_F(Dataset, MeshesAreFiniteNonDegenerateAndStandOnTheGround) {
  ModelView v;
  load(dir() / "change5.3ds", v);
  float min_z = 1e9f, deck_top = -1e9f;
  for (unsigned m = 0; m < v.scene->mNumMeshes; ++m) {
    const aiMesh* mesh = v.scene->mMeshes[m];
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      ASSERT_EQ(mesh->mFaces[f].mNumIndices, 3u);
      Eigen::Vector3d p[3];
      for (int k = 0; k < 3; ++k) {
        const aiVector3D& a = mesh->mVertices[mesh->mFaces[f].mIndices[k]];
        ASSERT_TRUE(std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z));
        p[k] = {a.x, a.y, a.z};
        min_z = std::min(min_z, a.z);
      }
      double area = 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).norm();
      ASSERT_GT(area, 1e-9) << "degenerate triangle " << f << " in mesh " << m;
    }
  }
  const aiNode* deck = nullptr;
  ModelView dv;
  deck = v.nodes["TopDeck"];
  ASSERT_NE(deck, nullptr);
  const aiMesh* dm = v.scene->mMeshes[deck->mMeshes[0]];
  for (unsigned i = 0; i < dm->mNumVertices; ++i) deck_top = std::max(deck_top, dm->mVertices[i].z);
  EXPECT_NEAR(min_z, 0.0, 1e-6);          // footpads on the ground
  EXPECT_GE(deck_top, 1.2f);              // deck about 1.2-1.5 m up
  EXPECT_LE(deck_top, 1.5f);
}

// ---------------------------------------------------------------- scene ----
TEST_F(Dataset, SceneHasTheContractKeys) {
  json s = read_json("scene.json");
  const std::set<std::string> known{"format", "model", "length_unit", "angle_unit", "actions", "allowed_collisions",
                                    "safety_margin", "terrain", "scoop", "probes"};
  for (const auto& [k, _] : s.items()) EXPECT_TRUE(known.count(k)) << "unknown key " << k;
  EXPECT_EQ(s["format"], "plancheck-scene/1");
  EXPECT_EQ(s["model"], "change5.3ds");
  EXPECT_EQ(s["length_unit"], "m");
  EXPECT_EQ(s["angle_unit"], "deg");
  EXPECT_DOUBLE_EQ(s["safety_margin"].get<double>(), 0.05);
  ASSERT_EQ(s["actions"].size(), 4u);
  for (int k = 0; k < 4; ++k) {
    const json& a = s["actions"][static_cast<std::size_t>(k)];
    const char* names[4] = {"J1", "J2", "J3", "J4"};
    EXPECT_EQ(a["name"], names[k]);
    EXPECT_EQ(a["type"], "rotate");
    ASSERT_EQ(a["pivot"].size(), 3u);
    ASSERT_EQ(a["axis"].size(), 3u);
    ASSERT_EQ(a["limits"].size(), 2u);
    EXPECT_LT(a["limits"][0].get<double>(), a["limits"][1].get<double>());
  }
  // J1 is the azimuth (vertical axis), J2-J4 pitch (horizontal axes).
  EXPECT_DOUBLE_EQ(std::abs(s["actions"][0]["axis"][2].get<double>()), 1.0);
  for (int k = 1; k < 4; ++k) EXPECT_DOUBLE_EQ(s["actions"][static_cast<std::size_t>(k)]["axis"][2].get<double>(), 0.0);
  EXPECT_EQ(s["terrain"]["dem"], "site.asc");
  EXPECT_EQ(s["terrain"]["origin"].size(), 3u);
  EXPECT_EQ(s["terrain"]["collide"], true);
  for (const char* k : {"part", "bottom_point", "width", "template", "capacity", "bulk_density"})
    EXPECT_TRUE(s["scoop"].contains(k)) << k;
  EXPECT_DOUBLE_EQ(s["scoop"]["width"].get<double>(), 0.10);
  EXPECT_GE(s["probes"].size(), 2u);
  for (const json& pair : s["allowed_collisions"]) EXPECT_EQ(pair.size(), 2u);
}

TEST_F(Dataset, ScoopBottomPointIsTheLowestPointOfTheScoop) {
  ModelView v;
  load(dir() / "change5.3ds", v);
  json s = read_json("scene.json");
  const aiNode* scoop = v.nodes[s["scoop"]["part"].get<std::string>()];
  ASSERT_NE(scoop, nullptr);
  float lowest = 1e9f;
  for (unsigned m = 0; m < scoop->mNumMeshes; ++m) {
    const aiMesh* mesh = v.scene->mMeshes[scoop->mMeshes[m]];
    for (unsigned i = 0; i < mesh->mNumVertices; ++i) lowest = std::min(lowest, mesh->mVertices[i].z);
  }
  EXPECT_NEAR(lowest, s["scoop"]["bottom_point"][2].get<double>(), 1e-6);
}

// ------------------------------------------------------------------ DEM ----
TEST_F(Dataset, DemIsA150By150GridOfFiniteHeights) {
  std::ifstream in(dir() / "site.asc");
  std::map<std::string, double> header;
  std::string key;
  for (int i = 0; i < 6 && in >> key; ++i) in >> header[key];
  EXPECT_EQ(header["ncols"], 150);
  EXPECT_EQ(header["nrows"], 150);
  EXPECT_DOUBLE_EQ(header["cellsize"], 0.02);
  EXPECT_TRUE(header.count("xllcorner") && header.count("yllcorner") && header.count("NODATA_value"));
  std::vector<double> values;
  double z;
  while (in >> z) values.push_back(z);
  ASSERT_EQ(values.size(), 150u * 150u);
  double lo = 1e9, hi = -1e9;
  for (double h : values) {
    ASSERT_TRUE(std::isfinite(h));
    ASSERT_NE(h, header["NODATA_value"]);
    lo = std::min(lo, h);
    hi = std::max(hi, h);
  }
  // Regolith near z = 0: centimetres of relief, not a flat plate, no cliffs.
  EXPECT_GT(hi - lo, 0.05);
  EXPECT_LT(hi - lo, 0.40);
  EXPECT_LT(std::abs(lo), 0.3);
  EXPECT_LT(std::abs(hi), 0.3);
}

// ---------------------------------------------------------------- plans ----
struct PlanFile {
  std::map<std::string, std::string> comments;
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;
};

PlanFile read_plan(const fs::path& p) {
  PlanFile out;
  std::ifstream in(p);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    if (line[0] == '#') {
      auto colon = line.find(':');
      if (colon != std::string::npos) {
        std::string k = line.substr(1, colon - 1), v = line.substr(colon + 1);
        k.erase(0, k.find_first_not_of(' '));
        v.erase(0, v.find_first_not_of(' '));
        out.comments[k] = v;
      }
      continue;
    }
    std::vector<std::string> fields;
    std::stringstream ss(line);
    std::string f;
    while (std::getline(ss, f, ',')) fields.push_back(f);
    if (out.header.empty()) {
      out.header = fields;
      continue;
    }
    std::vector<double> row;
    for (const std::string& x : fields) {
      std::size_t used = 0;
      double d = std::stod(x, &used);
      EXPECT_EQ(used, x.size()) << p << ": '" << x << "'";
      row.push_back(d);
    }
    out.rows.push_back(row);
  }
  return out;
}

// The scene contract's composition A1(A2(...Ak(x))), from scene.json alone.
Eigen::Vector3d pose_point(const json& scene, const std::vector<double>& deg, const Eigen::Vector3d& x) {
  Eigen::Vector3d p = x;
  for (int k = 3; k >= 0; --k) {
    const json& a = scene["actions"][static_cast<std::size_t>(k)];
    Eigen::Vector3d pivot(a["pivot"][0].get<double>(), a["pivot"][1].get<double>(), a["pivot"][2].get<double>());
    Eigen::Vector3d axis(a["axis"][0].get<double>(), a["axis"][1].get<double>(), a["axis"][2].get<double>());
    p = Eigen::AngleAxisd(deg[static_cast<std::size_t>(k)] * kPi / 180.0, axis.normalized()) * (p - pivot) + pivot;
  }
  return p;
}

TEST_F(Dataset, PlansHaveTable3StateCountsAndParse) {
  const int states[10] = {381, 264, 345, 249, 276, 238, 294, 323, 286, 326};
  for (int i = 0; i < 10; ++i) {
    char name[16];
    std::snprintf(name, sizeof name, "plan%02d", i + 1);
    PlanFile p = read_plan(dir() / "plans" / (std::string(name) + ".csv"));
    EXPECT_EQ(p.comments["name"], name);
    EXPECT_EQ(p.header, (std::vector<std::string>{"J1", "J2", "J3", "J4"})) << name;
    EXPECT_EQ(static_cast<int>(p.rows.size()), states[i]) << name;
    EXPECT_DOUBLE_EQ(std::stod(p.comments["tolerance"]), 0.02);
    for (const auto& r : p.rows) {
      ASSERT_EQ(r.size(), 4u) << name;
      for (double x : r) ASSERT_TRUE(std::isfinite(x)) << name;
    }
  }
}

TEST_F(Dataset, TargetsAreWhereTheSceneKinematicsPutTheScoop) {
  json scene = read_json("scene.json");
  const json& m = scene["scoop"]["bottom_point"];
  Eigen::Vector3d bottom(m[0].get<double>(), m[1].get<double>(), m[2].get<double>());
  for (int i = 1; i <= 10; ++i) {
    char name[16];
    std::snprintf(name, sizeof name, "plan%02d", i);
    PlanFile p = read_plan(dir() / "plans" / (std::string(name) + ".csv"));
    Eigen::Vector3d target;
    ASSERT_EQ(std::sscanf(p.comments["target"].c_str(), "%lf, %lf, %lf", &target.x(), &target.y(), &target.z()), 3) << name;
    Eigen::Vector3d end = pose_point(scene, p.rows.back(), bottom);
    EXPECT_LT((end - target).norm(), 1e-5) << name;
    // Plans start stowed and move smoothly: no jump above 10 deg per state on any joint.
    for (std::size_t s = 1; s < p.rows.size(); ++s)
      for (std::size_t k = 0; k < 4; ++k)
        ASSERT_LT(std::abs(p.rows[s][k] - p.rows[s - 1][k]), 10.0) << name << " state " << s;
  }
}

TEST_F(Dataset, ScoopDigsIntoTheSiteInEverySamplingPlan) {
  json scene = read_json("scene.json");
  const json& m = scene["scoop"]["bottom_point"];
  Eigen::Vector3d bottom(m[0].get<double>(), m[1].get<double>(), m[2].get<double>());
  const json& o = scene["terrain"]["origin"];
  for (int i = 1; i <= 9; ++i) {
    char name[16];
    std::snprintf(name, sizeof name, "plan%02d", i);
    PlanFile p = read_plan(dir() / "plans" / (std::string(name) + ".csv"));
    double lowest = 1e9;
    Eigen::Vector3d at;
    for (const auto& r : p.rows) {
      Eigen::Vector3d q = pose_point(scene, r, bottom);
      if (q.z() < lowest) {
        lowest = q.z();
        at = q;
      }
    }
    // The deepest point lies inside the 3 m x 3 m site and within a few cm of z = 0.
    EXPECT_GT(at.x(), o[0].get<double>()) << name;
    EXPECT_LT(at.x(), o[0].get<double>() + 3.0) << name;
    EXPECT_GT(at.y(), o[1].get<double>()) << name;
    EXPECT_LT(at.y(), o[1].get<double>() + 3.0) << name;
    EXPECT_LT(std::abs(lowest), 0.15) << name;
  }
}

// ------------------------------------------------------------- expected ----
std::set<int> expand(const json& ranges) {
  std::set<int> out;
  for (const json& r : ranges)
    for (int s = r[0].get<int>(); s <= r[1].get<int>(); ++s) out.insert(s);
  return out;
}

TEST_F(Dataset, ExpectedSidecarHasTheDesignedViolations) {
  json e = read_json("expected.json");
  json scene = read_json("scene.json");
  ASSERT_EQ(e["plans"].size(), 10u);
  std::map<std::string, int> verdicts;
  for (const auto& [name, p] : e["plans"].items()) {
    ++verdicts[p["verdict"].get<std::string>()];
    EXPECT_EQ(p["verdict"], p["designed"]) << name;
    // Limit states re-derived from the CSV and scene.json must agree with the sidecar.
    PlanFile f = read_plan(dir() / p["file"].get<std::string>());
    std::set<int> over;
    for (std::size_t s = 0; s < f.rows.size(); ++s)
      for (std::size_t k = 0; k < 4; ++k) {
        const json& lim = scene["actions"][k]["limits"];
        if (f.rows[s][k] < lim[0].get<double>() || f.rows[s][k] > lim[1].get<double>()) over.insert(static_cast<int>(s));
      }
    EXPECT_EQ(over, expand(p["limit_states"])) << name;
    EXPECT_EQ(static_cast<int>(f.rows.size()), p["states"].get<int>());
    if (p["verdict"] == "safe") {
      EXPECT_TRUE(p["first_violation"].is_null()) << name;
      EXPECT_TRUE(p["collision_states"].empty() && p["clearance_states"].empty()) << name;
      if (!p["min_distance"].is_null()) {
        EXPECT_GE(p["min_distance"].get<double>(), 0.05) << name;
      }
    } else {
      EXPECT_EQ(p["first_violation"]["kind"], p["verdict"]) << name;
    }
    if (p["verdict"] == "collision") {
      EXPECT_FALSE(p["collision_states"].empty());
    }
    if (p["verdict"] == "clearance") {
      EXPECT_TRUE(p["collision_states"].empty());
      EXPECT_GT(p["min_distance"].get<double>(), 0.0);
      EXPECT_LT(p["min_distance"].get<double>(), 0.05);
    }
  }
  // At the reference pose the parts that touch are exactly the joint contacts
  // declared in allowed_collisions; nothing else is within the cutoff.
  std::set<std::set<std::string>> allowed;
  for (const json& pair : scene["allowed_collisions"]) allowed.insert({pair[0].get<std::string>(), pair[1].get<std::string>()});
  const json& ref = e["reference_pose"];
  EXPECT_EQ(ref["contacts"].size(), 4u);
  for (const json& c : ref["contacts"])
    EXPECT_TRUE(allowed.count({c[0].get<std::string>(), c[1].get<std::string>()})) << c;
  EXPECT_TRUE(ref["min_distance"].is_null()) << ref;
  EXPECT_GE(verdicts["collision"], 1);
  EXPECT_GE(verdicts["clearance"], 1);
  EXPECT_GE(verdicts["limits"], 1);
  EXPECT_GE(verdicts["safe"], 6);
}

}  // namespace
}  // namespace plancheck
