// SPDX-License-Identifier: MIT
// A driver for callgrind (issue 33 item 1): the verdict-only check of N
// random states of a scene (bench/random_states.h, as `plancheck bench
// --random N` draws them), cold as the batch runs them or as one plan
// through verify_plans, and FCL's collide on the same states (FclPeer, as
// the bench times it). Each workload is one function (noinline) so that
// `valgrind --tool=callgrind --toggle-collect=<its name>` counts it alone:
//   plancheck_verdict_profile SCENE --random N MODE...
// MODE: cold, plan, fcl, stats; collide-plans: the states of the plans
// in the scene's plans/ folder (the ten default plans: Table 3's states),
// cold, collision only as the bench's collide row (N unused). stats prints, for a one-pair scene, the
// node pairs and triangle pairs each side's collision traversal runs per
// state (plancheck's CollideResult counters; FCL's traversal node with its
// statistics on), averaged over all states (boxes apart or not).
#include "bench/fcl_peer/fcl_peer.h"
#include "bench/random_states.h"
#include "src/checks/verify.h"
#include "src/geometry/collision_model.h"
#include "src/scene/kinematics.h"
#include "src/scene/plan.h"
#include "src/scene/scene_loader.h"

#include <fcl/fcl.h>
#include <fcl/narrowphase/detail/traversal/collision/mesh_collision_traversal_node.h>
#include <fcl/narrowphase/detail/traversal/collision_node.h>

#include <cstdio>
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

namespace pc = plancheck;

namespace {

using States = std::vector<std::vector<double>>;

[[gnu::noinline]] int profile_cold(const pc::Checker& checker, const pc::Scene& scene, const States& states) {
  const pc::CheckRequest request = pc::verdict_only_request(scene.safety_margin);
  pc::StateResult r;
  int colliding = 0;
  for (const auto& s : states) {
    checker.check_state(s, r, request);
    colliding += r.collision;
  }
  return colliding;
}

[[gnu::noinline]] int profile_collide(const pc::Checker& checker, const States& states) {
  pc::CheckRequest request{false, 0.0};
  request.max_triangle_pairs = 0;
  pc::StateResult r;
  int colliding = 0;
  for (const auto& s : states) {
    checker.check_state(s, r, request);
    colliding += r.collision;
  }
  return colliding;
}

[[gnu::noinline]] int profile_plan(const pc::Checker& checker, const pc::Scene& scene, const std::vector<pc::Plan>& plans) {
  pc::VerifyOptions o{1, false, false};
  o.verdict_only = true;
  o.listed_collisions = pc::kMaxCollisionStatesListed;
  const auto results = pc::verify_plans(checker, scene, plans, o);
  int colliding = 0;
  for (const auto& st : results[0].states) colliding += st.collision;
  return colliding;
}

[[gnu::noinline]] int profile_fcl(const pc::reference::FclPeer& fcl, const States& states) {
  int colliding = 0;
  for (const auto& s : states) colliding += fcl.check(s, false).collision;
  return colliding;
}

// The one pair's collision test alone on every state, with the descent's
// switches: the ablations of the profile (mode pair:BOX,LEAF,NEAR, each 0/1).
[[gnu::noinline]] int profile_pair(const std::vector<std::pair<pc::Affine, pc::Affine>>& poses,
                                   const pc::CollisionModel& ma, const pc::CollisionModel& mb, bool box_cull,
                                   bool leaf_cull, bool near) {
  int colliding = 0;
  pc::CollideResult r;
  for (const auto& [ta, tb] : poses) {
    pc::CollideRequest q{0};
    q.box_cull = box_cull;
    q.leaf_cull = leaf_cull;
    if (near) q.near_below = 4.0 * pc::kDistanceTolerance + pc::kDistanceTieTolerance;
    pc::collide(ma, ta, mb, tb, q, r);
    colliding += r.collide;
  }
  return colliding;
}

fcl::Transform3d to_fcl(const pc::Affine& t) {
  fcl::Transform3d f = fcl::Transform3d::Identity();
  f.linear() = t.linear();
  f.translation() = t.translation();
  return f;
}

std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>> fcl_model(const pc::Mesh& mesh) {
  auto m = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
  std::vector<fcl::Vector3d> v(mesh.vertices.begin(), mesh.vertices.end());
  std::vector<fcl::Triangle> t;
  for (const auto& tri : mesh.triangles) t.emplace_back(tri[0], tri[1], tri[2]);
  m->beginModel();
  m->addSubModel(v, t);
  m->endModel();
  return m;
}

// Per-state traversal counts of the one checked pair, both libraries.
void stats(const pc::Checker& checker, const pc::Scene& scene, const States& states) {
  const auto pairs = checker.pairs();
  if (pairs.size() != 1) {
    std::cerr << "stats: a scene with one checked pair only\n";
    return;
  }
  const int a = pairs[0].first, b = pairs[0].second;
  const pc::CollisionModel ma(scene.parts[a].mesh), mb(scene.parts[b].mesh);
  const auto fa = fcl_model(scene.parts[a].mesh), fb = fcl_model(scene.parts[b].mesh);
  // The verdict-only cutoff of a scene without a margin and of metre scale
  // (check_pairs: exact_below + 4 G + the tie tolerance, G = 1e-9 m).
  const double near_below = 4.0 * pc::kDistanceTolerance + pc::kDistanceTieTolerance;
  double pc_nodes = 0, pc_tris = 0, f_bv = 0, f_leaf = 0, pc_plain_nodes = 0, pc_plain_tris = 0;
  int met = 0, hits = 0, fhits = 0, nears = 0;
  for (const auto& s : states) {
    const pc::Affine ta = pc::part_transform(scene, a, s), tb = pc::part_transform(scene, b, s);
    pc::CollideRequest q{0};
    q.near_below = near_below;
    pc::CollideResult r;
    pc::collide(ma, ta, mb, tb, q, r);
    pc::CollideResult plain;
    pc::collide(ma, ta, mb, tb, pc::CollideRequest{0}, plain);
    fcl::CollisionRequestd creq;
    fcl::CollisionResultd cres;
    fcl::detail::MeshCollisionTraversalNodeOBBRSS<double> node;
    fcl::detail::initialize(node, *fa, to_fcl(ta), *fb, to_fcl(tb), creq, cres);
    node.enable_statistics = true;
    fcl::detail::collide(&node, nullptr);
    ++met;
    pc_nodes += static_cast<double>(r.node_pairs_visited);
    pc_tris += static_cast<double>(r.triangle_pairs_tested);
    pc_plain_nodes += static_cast<double>(plain.node_pairs_visited);
    pc_plain_tris += static_cast<double>(plain.triangle_pairs_tested);
    f_bv += node.num_bv_tests;
    f_leaf += node.num_leaf_tests;
    hits += r.collide;
    nears += r.near && !r.collide;
    fhits += cres.isCollision();
  }
  std::printf("states %d, colliding %d (FCL %d), near but apart %d\n", met, hits, fhits, nears);
  std::printf("plancheck verdict-only (near_below %.3g m): node pairs %.1f, exact triangle tests %.2f a state\n",
              near_below, pc_nodes / met, pc_tris / met);
  std::printf("plancheck collide only: node pairs %.1f, exact triangle tests %.2f a state\n", pc_plain_nodes / met,
              pc_plain_tris / met);
  std::printf("FCL collide: BV tests %.1f, leaf (triangle) tests %.2f a state\n", f_bv / met, f_leaf / met);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4) {
    std::cerr << "usage: plancheck_verdict_profile SCENE N MODE... (cold, plan, fcl, stats)\n";
    return 2;
  }
  const pc::Scene scene = pc::load_scene(argv[1]);
  const std::size_t n = std::strtoull(argv[2], nullptr, 10);
  const States states = pc::bench::random_states(scene, n, 1);
  const pc::Checker checker(scene, 1);
  std::vector<pc::Plan> plans(1);
  plans[0].name = "random";
  plans[0].states = states;
  for (int i = 3; i < argc; ++i) {
    const std::string mode = argv[i];
    if (mode == "cold") {
      std::printf("cold: %d colliding\n", profile_cold(checker, scene, states));
    } else if (mode == "collide") {
      std::printf("collide: %d colliding\n", profile_collide(checker, states));
    } else if (mode == "collide-plans") {
      std::vector<std::filesystem::path> csvs;
      for (const auto& e : std::filesystem::directory_iterator(std::filesystem::path(argv[1]).parent_path() / "plans"))
        if (e.path().extension() == ".csv") csvs.push_back(e.path());
      std::sort(csvs.begin(), csvs.end());
      States plan_states;
      for (const auto& csv : csvs)
        for (const auto& st : pc::load_plan(scene, csv).states) plan_states.push_back(st);
      std::printf("collide-plans: %zu states, %d colliding\n", plan_states.size(), profile_collide(checker, plan_states));
    } else if (mode == "plan") {
      std::printf("plan: %d colliding\n", profile_plan(checker, scene, plans));
    } else if (mode == "fcl") {
      std::vector<const pc::Mesh*> meshes;
      for (const auto& p : scene.parts) meshes.push_back(&p.mesh);
      if (checker.terrain()) {
        std::cerr << "fcl: scenes without terrain only\n";
        return 2;
      }
      const pc::reference::FclPeer fcl(scene, meshes, checker.pairs());
      std::printf("fcl: %d colliding\n", profile_fcl(fcl, states));
    } else if (mode.rfind("pair:", 0) == 0 && mode.size() == 10) {
      const auto pairs = checker.pairs();
      const int a = pairs.at(0).first, b = pairs.at(0).second;
      const pc::CollisionModel ma(scene.parts[a].mesh), mb(scene.parts[b].mesh);
      std::vector<std::pair<pc::Affine, pc::Affine>> poses;
      for (const auto& s : states) poses.emplace_back(pc::part_transform(scene, a, s), pc::part_transform(scene, b, s));
      std::printf("%s: %d colliding\n", mode.c_str(),
                  profile_pair(poses, ma, mb, mode[5] == '1', mode[7] == '1', mode[9] == '1'));
    } else if (mode == "stats") {
      stats(checker, scene, states);
    } else {
      std::cerr << "unknown mode " << mode << "\n";
      return 2;
    }
  }
  return 0;
}
