// SPDX-License-Identifier: MIT
#include "src/verify.h"

#include "src/kinematics.h"
#include "src/parallel.h"
#include "src/terrain.h"

#include <algorithm>
#include <chrono>
#include <numeric>

namespace plancheck {

namespace {

struct Box {
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 hi = Vec3::Constant(-std::numeric_limits<double>::infinity());
};

Box mesh_box(const Mesh& mesh) {
  Box b;
  for (const Tri& t : mesh.triangles)
    for (std::uint32_t v : t) {
      b.lo = b.lo.cwiseMin(mesh.vertices[v]);
      b.hi = b.hi.cwiseMax(mesh.vertices[v]);
    }
  return b;
}

// The world box of a posed local box, widened by a relative epsilon so that
// rounding in the transform never separates boxes whose contents touch.
Box posed_box(const Box& local, const Affine& t) {
  const Vec3 c = 0.5 * (local.lo + local.hi);
  const Vec3 h = 0.5 * (local.hi - local.lo);
  const Vec3 wc = t * c;
  const Vec3 wh = t.linear().cwiseAbs() * h;
  const double pad = 1e-9 * (wc.cwiseAbs().maxCoeff() + wh.maxCoeff() + 1.0);
  return {wc - wh - Vec3::Constant(pad), wc + wh + Vec3::Constant(pad)};
}

double box_distance(const Box& a, const Box& b) {
  const Vec3 gap = (a.lo - b.hi).cwiseMax(b.lo - a.hi).cwiseMax(0.0);
  return gap.norm();
}

}  // namespace

const char* verdict_name(Verdict v) {
  switch (v) {
    case Verdict::kSafe: return "safe";
    case Verdict::kCollision: return "collision";
    case Verdict::kClearance: return "clearance";
    case Verdict::kLimits: return "limits";
    case Verdict::kTarget: return "target";
  }
  return "?";
}

Checker::Checker(const Scene& scene, int threads) : scene_(scene) {
  std::vector<const Mesh*> meshes;
  for (const Part& p : scene.parts) {
    names_.push_back(p.name);
    meshes.push_back(&p.mesh);
    chain_of_.push_back(p.moving() ? p.chain_id : -1);
  }
  Mesh terrain_mesh;
  const bool terrain = scene.terrain && scene.terrain->collide;
  if (terrain) {
    terrain_mesh = dem_mesh(load_dem(scene.terrain->dem, scene.length_scale), scene.terrain->origin);
    names_.push_back("terrain");
    meshes.push_back(&terrain_mesh);
    chain_of_.push_back(-1);
  }

  // Build the per-part structures in parallel: parts are independent.
  std::vector<std::optional<CollisionModel>> built(meshes.size());
  parallel_for(meshes.size(), threads, 1, [&](std::size_t begin, std::size_t end, int) {
    for (std::size_t i = begin; i < end; ++i) built[i].emplace(*meshes[i]);
  });
  for (auto& m : built) models_.push_back(std::move(*m));
  for (const Mesh* m : meshes) {
    const Box b = mesh_box(*m);
    local_boxes_.emplace_back(b.lo, b.hi);
  }

  // The moving part first in each pair, as reports name them (arm part, then what it meets).
  for (const CheckedPair& p : scene.checked_pairs) {
    if (chain_of_[static_cast<std::size_t>(p.a)] < 0 && chain_of_[static_cast<std::size_t>(p.b)] >= 0)
      pairs_.push_back({p.b, p.a});
    else
      pairs_.push_back({p.a, p.b});
  }
  if (terrain) {
    const int t = static_cast<int>(names_.size()) - 1;
    for (std::size_t i = 0; i < scene.parts.size(); ++i) {
      if (!scene.parts[i].moving()) continue;
      const auto& allowed = scene.terrain_allowed_parts;
      if (std::find(allowed.begin(), allowed.end(), static_cast<int>(i)) != allowed.end()) continue;
      pairs_.push_back({static_cast<int>(i), t});
    }
  }
}

std::size_t Checker::triangle_count() const {
  std::size_t n = 0;
  for (const auto& m : models_) n += m.triangle_count();
  return n;
}

std::size_t Checker::memory_bytes() const {
  std::size_t n = 0;
  for (const auto& m : models_) n += m.memory_bytes();
  return n;
}

void Checker::check_state(const std::vector<double>& params, StateResult& out) const {
  out = StateResult{};
  std::vector<Affine> chains;
  chain_transforms(scene_, params, chains);
  const std::size_t n = models_.size();
  std::vector<Affine> pose(n, Affine::Identity());
  std::vector<Box> box(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (chain_of_[i] >= 0) pose[i] = chains[static_cast<std::size_t>(chain_of_[i])];
    box[i] = posed_box({local_boxes_[i].first, local_boxes_[i].second}, pose[i]);
  }

  // Collision: every checked pair whose part boxes meet.
  std::vector<double> lower(pairs_.size());
  for (std::size_t k = 0; k < pairs_.size(); ++k) {
    const auto [a, b] = pairs_[k];
    lower[k] = box_distance(box[a], box[b]);
    if (lower[k] > 0.0) continue;
    CollideResult r;
    collide(models_[a], pose[a], models_[b], pose[b], CollideRequest{kMaxTrianglePairsListed}, r);
    if (r.collide) out.contacts.push_back({a, b, std::move(r.triangle_pairs)});
  }
  out.collision = !out.contacts.empty();

  // Minimum distance: pairs in order of their box lower bound, the best so
  // far pruning the rest; a colliding state needs only a common point.
  std::vector<std::size_t> order;
  if (out.collision) {
    for (std::size_t k = 0; k < pairs_.size(); ++k)
      if (pairs_[k].a == out.contacts[0].part_a && pairs_[k].b == out.contacts[0].part_b) order.push_back(k);
  } else {
    order.resize(pairs_.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) { return lower[x] < lower[y]; });
  }
  for (std::size_t k : order) {
    if (lower[k] >= out.min_distance) break;
    const auto [a, b] = pairs_[k];
    DistanceResult r;
    distance(models_[a], pose[a], models_[b], pose[b], DistanceRequest{out.min_distance}, r);
    if (r.found && r.distance < out.min_distance) {
      out.min_distance = r.distance;
      out.part_a = a;
      out.part_b = b;
      out.point_a = r.point_a;
      out.point_b = r.point_b;
    }
  }
  if (out.collision) out.min_distance = 0.0;
  out.limit_action = first_limit_violation(scene_, params);
}

std::vector<PairContact> Checker::reference_contacts() const {
  StateResult r;
  check_state(scene_.reference_parameters, r);
  return r.contacts;
}

Vec3 Checker::target_point(const std::vector<double>& params) const {
  if (scene_.scoop) {
    const int p = scene_.scoop->part_index;
    return part_transform(scene_, p, params) * scene_.scoop->bottom_point;
  }
  if (scene_.actions.empty()) return Vec3::Zero();
  // Without a scoop: the origin of the last action's node, moved by its chain.
  const Action& last = scene_.actions.back();
  const Node& node = scene_.nodes[static_cast<std::size_t>(last.node)];
  Affine t = Affine::Identity();
  std::vector<int> chain;
  for (int n = last.node; n >= 0; n = scene_.nodes[static_cast<std::size_t>(n)].parent)
    for (auto it = scene_.nodes[static_cast<std::size_t>(n)].actions.rbegin();
         it != scene_.nodes[static_cast<std::size_t>(n)].actions.rend(); ++it)
      chain.push_back(*it);
  std::reverse(chain.begin(), chain.end());
  for (int a : chain) {
    const Action& act = scene_.actions[static_cast<std::size_t>(a)];
    t = t * action_transform(act, params.data() + act.first_parameter);
  }
  return t * node.origin;
}

std::vector<PlanResult> verify_plans(const Checker& checker, const Scene& scene,
                                     const std::vector<Plan>& plans, const VerifyOptions& options) {
  std::vector<PlanResult> results(plans.size());
  std::vector<std::pair<std::size_t, std::size_t>> items;  // (plan, state)
  std::vector<std::vector<double>> state_seconds(plans.size());
  for (std::size_t p = 0; p < plans.size(); ++p) {
    results[p].plan = &plans[p];
    results[p].states.resize(plans[p].states.size());
    state_seconds[p].resize(plans[p].states.size());
    for (std::size_t s = 0; s < plans[p].states.size(); ++s) items.emplace_back(p, s);
  }

  // States are independent: shard them; each writes only its own slot.
  parallel_for(items.size(), options.threads, 4, [&](std::size_t begin, std::size_t end, int) {
    for (std::size_t i = begin; i < end; ++i) {
      const auto [p, s] = items[i];
      const auto t0 = std::chrono::steady_clock::now();
      checker.check_state(plans[p].states[s], results[p].states[s]);
      state_seconds[p][s] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    }
  });

  const double margin = scene.safety_margin;
  for (std::size_t p = 0; p < plans.size(); ++p) {
    PlanResult& r = results[p];
    r.seconds = std::accumulate(state_seconds[p].begin(), state_seconds[p].end(), 0.0);
    for (std::size_t s = 0; s < r.states.size(); ++s) {
      const StateResult& st = r.states[s];
      if (st.part_a >= 0 && st.min_distance < r.min_distance) {
        r.min_distance = st.min_distance;
        r.min_distance_state = s;
        r.min_part_a = st.part_a;
        r.min_part_b = st.part_b;
        r.min_point_a = st.point_a;
        r.min_point_b = st.point_b;
      }
      if (r.first_violation) continue;
      Violation v;
      v.state = s;
      if (st.collision) {
        v.kind = Verdict::kCollision;
        v.part_a = st.contacts[0].part_a;
        v.part_b = st.contacts[0].part_b;
      } else if (margin > 0.0 && st.part_a >= 0 && st.min_distance < margin + kDistanceTolerance) {
        // Below the margin, or too close to it to settle in double: a violation.
        v.kind = Verdict::kClearance;
        v.part_a = st.part_a;
        v.part_b = st.part_b;
      } else if (st.limit_action >= 0) {
        v.kind = Verdict::kLimits;
        v.action = st.limit_action;
      } else {
        continue;
      }
      r.first_violation = v;
    }
    const Plan& plan = plans[p];
    if (plan.target && !plan.states.empty()) {
      const Vec3 reached = checker.target_point(plan.states.back());
      r.target_error = (reached - *plan.target).norm();
      if (!r.first_violation && *r.target_error > plan.tolerance) {
        Violation v;
        v.state = plan.states.size() - 1;
        v.kind = Verdict::kTarget;
        r.first_violation = v;
      }
    }
    r.verdict = r.first_violation ? r.first_violation->kind : Verdict::kSafe;
  }
  dig_and_probe(scene, plans, results, options);
  return results;
}

}  // namespace plancheck
