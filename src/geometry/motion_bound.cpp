// SPDX-License-Identifier: MIT
// The bound: a point x of a part under actions A1 (root) ... Ak is posed at
// p(q) = A1(A2(...Ak(x))). Along q(t) = qa + t (qb - qa) its path length is
// at most sum_i |dq_i| sup |dp/dq_i|, and dp/dq_i = L_{<i} A_i'(y_i) with
// y_i = A_{i+1}(...Ak(x)) the point action i sees and L_{<i} the linear
// part of A1 ... A_{i-1} (norm 1 for rotations and translations, max |s| for
// a scale). A sphere (z, rho) that holds y_i for every parameter in the
// segment's box is carried outwards from the part's own extent:
//   rotate about p, axis u: |A_i'(y)| = dist(y, axis) <= dist(z, axis) + rho
//       and |A_i(y) - p| = |y - p| <= |z - p| + rho  (new sphere about p);
//   translate by d in a box: |A_i'| = |u| per unit; the sphere moves by the
//       box centre and grows by its half diagonal;
//   scale about f by s in a box: |A_i'(y) ds| <= max|ds_j| |y - f| and
//       |A_i(y) - f| <= max|s_j| |y - f|  (new sphere about f).
// Every bound holds for every parameter in the box spanned by qa and qb,
// hence along the whole linear segment between them.
#include "src/geometry/motion_bound.h"

#include "src/scene/kinematics.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace plancheck {

namespace {

double line_distance(const Vec3& x, const Vec3& p, const Vec3& u) {
  // u need not be exactly unit: divide by its norm.
  const double n = u.norm();
  return n > 0.0 ? (x - p).cross(u).norm() / n : (x - p).norm();
}

}  // namespace

MotionBound::MotionBound(const Scene& scene) : scene_(scene) {
  extents_.resize(scene.parts.size());
  for (std::size_t i = 0; i < scene.parts.size(); ++i) {
    const Part& part = scene.parts[i];
    PartExtent& e = extents_[i];
    if (!part.moving()) continue;
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());
    Vec3 hi = -lo;
    for (const Tri& t : part.mesh.triangles)
      for (std::uint32_t v : t) {
        lo = lo.cwiseMin(part.mesh.vertices[v]);
        hi = hi.cwiseMax(part.mesh.vertices[v]);
      }
    if (part.mesh.triangles.empty()) continue;
    e.centre = 0.5 * (lo + hi);
    const Action& inner = scene.actions[static_cast<std::size_t>(part.chain.back())];
    const Vec3 c = inner.type == ActionType::kScale ? inner.fixed_point : inner.pivot;
    // Each vertex a triangle uses, once (a vertex is shared by about six).
    std::vector<char> used(part.mesh.vertices.size(), 0);
    for (const Tri& t : part.mesh.triangles)
      for (std::uint32_t v : t) used[v] = 1;
    for (std::size_t v = 0; v < used.size(); ++v)
      if (used[v]) {
        const Vec3& x = part.mesh.vertices[v];
        e.radius = std::max(e.radius, (x - e.centre).norm());
        e.inner_radius = std::max(e.inner_radius, (x - c).norm());
        if (inner.type == ActionType::kRotate)
          e.inner_arm = std::max(e.inner_arm, line_distance(x, inner.pivot, inner.axis));
      }
  }
}

double MotionBound::part_bound(int part, std::span<const double> qa, std::span<const double> qb) const {
  return bound_from(part, 0, qa, qb);
}

double MotionBound::pair_bound(int a, int b, std::span<const double> qa, std::span<const double> qb) const {
  const std::size_t common = shared_actions(a, b);
  return bound_from(a, common, qa, qb) + bound_from(b, common, qa, qb);
}

void MotionBound::pair_bounds(const std::vector<std::pair<int, int>>& pairs, std::span<const double> qa,
                              std::span<const double> qb, std::vector<double>& out) const {
  pair_bounds(pair_plan(pairs), qa, qb, out);
}

MotionBound::PairPlan MotionBound::pair_plan(const std::vector<std::pair<int, int>>& pairs) const {
  PairPlan plan;
  auto key = [&](int part, std::size_t common) {
    const std::pair<int, std::size_t> k{part, common};
    const auto it = std::find(plan.keys.begin(), plan.keys.end(), k);
    if (it != plan.keys.end()) return static_cast<std::uint32_t>(it - plan.keys.begin());
    plan.keys.push_back(k);
    return static_cast<std::uint32_t>(plan.keys.size() - 1);
  };
  for (const auto& [a, b] : pairs) {
    const std::size_t common = shared_actions(a, b);
    plan.of.emplace_back(key(a, common), key(b, common));
  }
  return plan;
}

void MotionBound::pair_bounds(const PairPlan& plan, std::span<const double> qa, std::span<const double> qb,
                              std::vector<double>& out) const {
  thread_local std::vector<double> value;
  value.resize(plan.keys.size());
  for (std::size_t i = 0; i < plan.keys.size(); ++i) value[i] = bound_from(plan.keys[i].first, plan.keys[i].second, qa, qb);
  out.resize(plan.of.size());
  for (std::size_t k = 0; k < plan.of.size(); ++k) out[k] = value[plan.of[k].first] + value[plan.of[k].second];
}

std::size_t MotionBound::shared_actions(int a, int b) const {
  auto chain = [&](int part) -> const std::vector<int>* {
    if (part < 0 || static_cast<std::size_t>(part) >= scene_.parts.size()) return nullptr;
    return &scene_.parts[static_cast<std::size_t>(part)].chain;
  };
  const std::vector<int>* ca = chain(a);
  const std::vector<int>* cb = chain(b);
  // Chains run from the root: shared actions are a common prefix. Only a
  // rigid one (an isometry for every parameter value) keeps distances.
  std::size_t common = 0;
  if (ca && cb)
    while (common < ca->size() && common < cb->size() && (*ca)[common] == (*cb)[common] &&
           scene_.actions[static_cast<std::size_t>((*ca)[common])].type != ActionType::kScale)
      ++common;
  return common;
}

double MotionBound::sphere_bound(int part, const Vec3& centre, double radius, std::span<const double> qa,
                                 std::span<const double> qb) const {
  if (part < 0 || static_cast<std::size_t>(part) >= scene_.parts.size()) return 0.0;
  const Part& p = scene_.parts[static_cast<std::size_t>(part)];
  if (!p.moving()) return 0.0;
  // The extent's innermost radius and arm from the sphere itself: every
  // point x of it has |x - c| <= |centre - c| + radius, and so for its
  // distance from the innermost rotation's axis.
  const Action& inner = scene_.actions[static_cast<std::size_t>(p.chain.back())];
  const Vec3 c = inner.type == ActionType::kScale ? inner.fixed_point : inner.pivot;
  PartExtent e;
  e.centre = centre;
  e.radius = radius;
  e.inner_radius = (centre - c).norm() + radius;
  if (inner.type == ActionType::kRotate) e.inner_arm = line_distance(centre, inner.pivot, inner.axis) + radius;
  return bound_from(part, e, 0, qa, qb);
}

bool MotionBound::sphere_levers(int part, const Vec3& centre, double radius, std::vector<double>& levers) const {
  levers.clear();
  if (part < 0 || static_cast<std::size_t>(part) >= scene_.parts.size()) return false;
  const Part& p = scene_.parts[static_cast<std::size_t>(part)];
  if (!p.moving()) return false;
  for (const int a : p.chain)
    if (scene_.actions[static_cast<std::size_t>(a)].type != ActionType::kRotate) return false;
  // bound_from's arms for the sphere's extent (sphere_bound), innermost
  // first: with rotations only, z and rho do not read the parameters.
  levers.resize(p.chain.size());
  Vec3 z = centre;
  double rho = radius;
  for (std::size_t n = p.chain.size(); n-- > 0;) {
    const Action& a = scene_.actions[static_cast<std::size_t>(p.chain[n])];
    const bool innermost = n + 1 == p.chain.size();
    levers[n] = innermost ? line_distance(centre, a.pivot, a.axis) + radius : line_distance(z, a.pivot, a.axis) + rho;
    rho = innermost ? (centre - a.pivot).norm() + radius : (z - a.pivot).norm() + rho;
    z = a.pivot;
  }
  return true;
}

double MotionBound::levers_bound(int part, std::span<const double> levers, std::span<const double> qa,
                                 std::span<const double> qb) const {
  const Part& p = scene_.parts[static_cast<std::size_t>(part)];
  // bound_from's sum for rotations (every linear norm 1), in its order.
  double total = 0.0;
  for (std::size_t n = 0; n < p.chain.size(); ++n) {
    const Action& a = scene_.actions[static_cast<std::size_t>(p.chain[n])];
    total += 1.0 * (std::abs(driving_value(scene_, a, qb) - driving_value(scene_, a, qa)) * a.unit_to_si * levers[n]);
  }
  if (!std::isfinite(total)) return std::numeric_limits<double>::infinity();
  return total * (1.0 + 1e-9) + 1e-12;
}

double MotionBound::bound_from(int part, std::size_t first, std::span<const double> qa,
                               std::span<const double> qb) const {
  if (part < 0 || static_cast<std::size_t>(part) >= scene_.parts.size()) return 0.0;
  if (!scene_.parts[static_cast<std::size_t>(part)].moving()) return 0.0;
  return bound_from(part, extents_[static_cast<std::size_t>(part)], first, qa, qb);
}

double MotionBound::bound_from(int part, const PartExtent& e, std::size_t first, std::span<const double> qa,
                               std::span<const double> qb) const {
  const Part& p = scene_.parts[static_cast<std::size_t>(part)];

  // Innermost action first: the sphere holding the points action i sees.
  Vec3 z = e.centre;
  double rho = e.radius;
  // contribution[i] before the outer actions' linear norms; norms[i] = max |s| of action i.
  // Only [first, k) is read, all of it written below (no zeroing: it was a
  // fifth of this function on a six-joint arm).
  double contribution[64];
  double norms[64];
  const std::size_t k = p.chain.size();
  if (k > 64) return std::numeric_limits<double>::infinity();  // no scene nests that deep
  if (first >= k) return 0.0;  // every action shared with the other part
  for (std::size_t n = k; n-- > first;) {
    const Action& a = scene_.actions[static_cast<std::size_t>(p.chain[n])];
    const std::size_t f = static_cast<std::size_t>(a.first_parameter);
    const bool innermost = n + 1 == k;
    // One-parameter actions read their driving value (a mimic joint's follows its master).
    const double va = a.parameter_count == 3 ? 0.0 : driving_value(scene_, a, qa);
    const double vb = a.parameter_count == 3 ? 0.0 : driving_value(scene_, a, qb);
    norms[n] = 1.0;
    switch (a.type) {
      case ActionType::kRotate: {
        const double arm = innermost ? e.inner_arm : line_distance(z, a.pivot, a.axis) + rho;
        // The angle turned is the written difference, converted: 0 -> 720 deg
        // is two turns, never none (whole turns are removed only for the pose).
        contribution[n] = std::abs(vb - va) * a.unit_to_si * arm;
        rho = innermost ? e.inner_radius : (z - a.pivot).norm() + rho;
        z = a.pivot;
        break;
      }
      case ActionType::kTranslateAxis: {
        const double un = a.axis.norm();
        const double u = a.unit_to_si;
        contribution[n] = std::abs(vb - va) * u * un;
        z += a.axis * (0.5 * (va + vb) * u);
        rho += 0.5 * std::abs(vb - va) * u * un;
        break;
      }
      case ActionType::kTranslateFree: {
        const Vec3 da = Vec3(qa[f], qa[f + 1], qa[f + 2]) * a.unit_to_si;
        const Vec3 db = Vec3(qb[f], qb[f + 1], qb[f + 2]) * a.unit_to_si;
        contribution[n] = (db - da).norm();
        z += 0.5 * (da + db);
        rho += 0.5 * (db - da).cwiseAbs().norm();
        break;
      }
      case ActionType::kScale: {
        double ds = 0.0, smax = 0.0;
        for (std::size_t j = 0; j < 3; ++j) {
          ds = std::max(ds, std::abs(qb[f + j] - qa[f + j]));
          smax = std::max({smax, std::abs(qa[f + j]), std::abs(qb[f + j])});
        }
        const double r = innermost ? e.inner_radius : (z - a.fixed_point).norm() + rho;
        contribution[n] = ds * r;
        norms[n] = smax;
        z = a.fixed_point;
        rho = smax * r;
        break;
      }
    }
  }
  // Outer linear norms: L_{<i} = product of norms of the actions above i.
  double total = 0.0, outer = 1.0;
  for (std::size_t n = first; n < k; ++n) {
    total += outer * contribution[n];
    outer *= norms[n];
  }
  if (!std::isfinite(total)) return std::numeric_limits<double>::infinity();
  // Rounding: each term above is a handful of double operations on
  // coordinates of at most a few hundred metres; a relative pad far above
  // their error and an absolute one below any tolerance used with it.
  return total * (1.0 + 1e-9) + 1e-12;
}

}  // namespace plancheck
