// SPDX-License-Identifier: MIT
// Real meshes nobody here made: the KUKA KR5 and Barrett WAM link meshes of
// Debian's dart-doc, assembled by this fixture into one scene (KR5 links
// static in a row, WAM links moving over them on free translations and
// rotations), checked state by state against FCL 0.7.
#include "src/scene/model_loader.h"
#include "src/scene/scene_loader.h"
#include "src/checks/verify.h"
#include "bench/fcl_peer/fcl_peer.h"
#include "support/fixtures.h"

#include <gtest/gtest.h>

#include <random>
#include <sstream>

namespace plancheck {
namespace {

const std::filesystem::path kKr5 = "/usr/share/doc/dart/data/urdf/KR5/meshes";
const std::filesystem::path kWam = "/usr/share/doc/dart/data/urdf/wam/meshes/wam";

// A mesh file's triangles, moved so its box centre sits at `at`.
Mesh centred(const std::filesystem::path& file, const Vec3& at) {
  Scene s;
  load_model(file, 1.0, s);
  Mesh m;
  for (const Part& p : s.parts) {
    const auto base = static_cast<std::uint32_t>(m.vertices.size());
    m.vertices.insert(m.vertices.end(), p.mesh.vertices.begin(), p.mesh.vertices.end());
    for (Tri t : p.mesh.triangles) m.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  }
  Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
  for (const Vec3& v : m.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  const Vec3 shift = at - 0.5 * (lo + hi);
  for (Vec3& v : m.vertices) v += shift;
  return m;
}

TEST(RealMeshes, Kr5AndWamLinksAgreeWithFcl) {
  ASSERT_TRUE(std::filesystem::exists(kKr5 / "base_link.STL")) << "needs Debian's dart-doc";
  testing::TempDir dir("real-meshes");
  std::vector<std::pair<std::string, Mesh>> parts;
  const char* kr5[] = {"base_link", "shoulder", "bicep", "elbow", "forearm", "wrist", "palm"};
  for (int i = 0; i < 7; ++i) parts.emplace_back(kr5[i], centred(kKr5 / (std::string(kr5[i]) + ".STL"), Vec3(0.35 * i, 0, 0)));
  std::ostringstream actions;
  for (int i = 1; i <= 6; ++i) {
    const std::string name = "wam" + std::to_string(i);
    const Vec3 at(0.4 * (i - 1), 0.45, 0.0);
    parts.emplace_back(name, centred(kWam / (name + ".STL"), at));
    // Each WAM link turns about a tilted axis through its centre, then slides
    // freely: far enough to reach the KR5 row and its neighbours.
    actions << (i > 1 ? ",\n" : "") << R"(    {"name": "R)" << i << R"(", "node": ")" << name
            << R"(", "type": "rotate", "pivot": [)" << at.x() << ", " << at.y() << R"(, 0], "axis": [0.3, 1, )"
            << 0.2 * i << R"(], "limits": [-180, 180]},)" << "\n"
            << R"(    {"name": "T)" << i << R"(", "node": ")" << name
            << R"(", "type": "translate", "limits": [-0.45, 0.45]})";
  }
  testing::write_obj(dir / "model.obj", parts);
  testing::write_text(dir / "scene.json", "{\"format\": \"plancheck-scene/1\", \"model\": \"model.obj\",\n"
                                           "  \"actions\": [\n" + actions.str() + "\n  ]\n}\n");
  const Scene scene = load_scene(dir / "scene.json");
  ASSERT_EQ(scene.parts.size(), 13u);
  const Checker checker(scene);
  std::vector<const Mesh*> meshes;
  for (const Part& p : scene.parts) meshes.push_back(&p.mesh);
  const reference::FclPeer fcl(scene, meshes, checker.pairs());

  std::mt19937_64 rng(650);
  auto uniform = [&](double lo, double hi) { return lo + (hi - lo) * static_cast<double>(rng() >> 11) * 0x1.0p-53; };
  int collisions = 0;
  constexpr int kStates = 400;
  for (int i = 0; i < kStates; ++i) {
    std::vector<double> state = scene.reference_parameters;
    for (const Action& a : scene.actions)
      for (int k = 0; k < a.parameter_count; ++k)
        state[static_cast<std::size_t>(a.first_parameter + k)] = uniform(a.lower, a.upper);
    StateResult ours;
    checker.check_state(state, ours);
    const auto ref = fcl.check(state);
    ASSERT_EQ(ours.collision, ref.collision) << "state " << i;
    if (ours.collision) ++collisions;
    else EXPECT_NEAR(ours.min_distance, ref.distance, 1e-9) << "state " << i;
  }
  EXPECT_GT(collisions, kStates / 20);
  EXPECT_LT(collisions, kStates - kStates / 20);
}

}  // namespace
}  // namespace plancheck
