// SPDX-License-Identifier: MIT
// Certified regions (src/checks/sweep_certify.h).
#include "src/checks/sweep_certify.h"

#include "src/geometry/crossing.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

namespace plancheck {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Boxes of at most this many configurations are answered one by one, in
// order, each answer carrying its proven separations and closest triangle
// pairs to the next (as a plan's states do): on the default 5-degree grid
// that beats halving further (1.2 s against 2.8 s for 105,280
// configurations with 2, against 1.8 s with 4, 1.4 s with 16, 1.2 s with 64).
constexpr std::size_t kSmallBox = 32;

constexpr std::int32_t kNone = std::numeric_limits<std::int32_t>::max();

// Intersecting triangle pairs listed at a box centre to look for a crossing
// witness among (the first that holds certifies the box).
constexpr std::size_t kWitnesses = 16;
// Small boxes (answered point by point) of at least this many
// configurations first try one crossing witness for the first pair that
// was in contact at the last centre.
constexpr std::size_t kWitnessBox = 2;
// A part-scale witness that failed on a small box is asked again on its
// halves only when its best candidate cleared this share of the moves.
constexpr double kWitnessShare = 0.1;

// clear_point's lower bounds: coarse searches within this factor
// (pair_distance's rel_tolerance), so a configuration certified closer than
// the margin gets at least half its exact distance (less the tolerances)
// unless a carried separation is as good. A factor 5 (a fifth of the
// distance) saved about 6% more of the check on 2.5-degree slabs
// (docs/sweeps.md).
constexpr double kClearTolerance = 1.0;

}  // namespace

// One group's answers over its projection of a block, in C order over the
// group's axes.
struct SweepCertifier::Answers {
  std::vector<std::size_t> size;    // per group axis
  std::vector<double> lower;        // m: exact or certified lower bound; 0 in contact
  std::vector<std::uint8_t> exact;  // lower is the group's minimum
  std::vector<std::uint8_t> collision;
  std::vector<std::int32_t> pair;   // first colliding pair, or the closest when exact; -1
  std::vector<double> guard;        // the closest pair's guard, when exact
  std::vector<std::uint8_t> witnessed;  // the contact is a crossing witness's (no test here)
  std::vector<std::uint8_t> below;  // no contact, and some pair certainly below the margin (clear_point)
  std::size_t contact_boxes = 0;
  std::size_t pair_checks = 0;

  std::size_t index(const std::vector<std::size_t>& at) const {
    std::size_t i = 0;
    for (std::size_t k = 0; k < size.size(); ++k) i = i * size[k] + at[k];
    return i;
  }
};

// A pair not yet certified in a box. What its last search found (at a box
// centre c.pool[at]) bounds its distance anywhere else, moved by the parts'
// relative path (Checker::pair_path): a box it cannot reach the need in is
// not searched, and the points answered one by one start from it.
struct SweepCertifier::Pending {
  std::size_t pair = 0;
  // The pair's distance at configuration c.pool[at] lies in [lb, ub] (at -1: nothing known).
  int at = -1;
  double lb = 0.0, ub = kInf;
};

// One group's work in one block: where the block starts, the answers, and
// per pair the last triangle pair found (a seed for the next search).
struct SweepCertifier::Context {
  const Group& group;
  const std::vector<std::size_t>& first;
  Answers& out;
  std::vector<PairAnswer>& seeds;
  int last_best = -1;  // the group's closest pair at the last point answered
  // Per pair, a proven lower bound on its distance at the configuration
  // carried_at[k] (empty: none): less how far the parts can have moved
  // since, still a bound (as StateSeed's separations in check_pairs).
  std::vector<double>& carried;
  std::vector<std::vector<double>>& carried_at;
  // Per point of the projection: every configuration there already has a
  // contact (groups answered before) with a pair before this index, so no
  // pair of the group from it on can change what they show; kNone: some
  // configuration there has no contact yet.
  const std::vector<std::int32_t>& relevant;
  // Per point: a pair a crossing witness proved in contact at every
  // configuration there (kNone: none), so no later pair matters there and
  // the earlier ones need only be proven apart.
  std::vector<std::int32_t> cert = {};
  std::vector<std::array<Vec3, 6>> crossings = {};  // scratch
  std::vector<SolidHint> solid_hints = {};  // per pair: its last part-scale witness
  std::vector<double> params = {};  // scratch
  PosedParts posed = {};
  std::vector<double> since = {};
  std::vector<std::vector<double>> pool = {};  // box centres asked (Pending::at)
  // Per pair: the last triangle pair a point's search found (clear_point's
  // probe starts there), kept when later searches find none (seeds are not).
  std::vector<PairAnswer> hints = {};
  // The last point answered without contact was in clearance (its exact
  // minimum below margin - 4G - tie, or clear_point's): only then does
  // clear_point probe (in free space a probe that misses costs a search).
  bool last_clear = false;
};

SweepCertifier::SweepCertifier(const Checker& checker, const Scene& scene, const SweepGrid& grid)
    : checker_(checker), scene_(scene), grid_(grid), blocks_(grid.shape()), motion_(scene), box_motion_(scene) {
  // Groups: pairs by the swept axes their distance depends on.
  std::map<std::vector<std::size_t>, std::vector<std::size_t>> by_axes;
  const std::size_t pairs = checker.pairs().size();
  for (std::size_t k = 0; k < pairs; ++k) {
    const std::vector<int> params = checker.pair_parameters(k);
    std::vector<std::size_t> axes;
    for (std::size_t a = 0; a < grid.axes.size(); ++a)
      if (std::binary_search(params.begin(), params.end(), grid.axes[a].parameter)) axes.push_back(a);
    by_axes[axes].push_back(k);
  }
  for (auto& [axes, ks] : by_axes) {
    Group g{axes, ks, {}};
    for (std::size_t k : ks) {
      const auto [a, b] = checker.pairs()[k];
      g.parts.push_back(a);
      if (b != checker.terrain_index()) g.parts.push_back(b);
    }
    std::sort(g.parts.begin(), g.parts.end());
    g.parts.erase(std::unique(g.parts.begin(), g.parts.end()), g.parts.end());
    groups_.push_back(std::move(g));
  }
  // Groups over fewer axes first: they are cheap, and a contact they find
  // spares the later groups every pair after it at those configurations.
  std::stable_sort(groups_.begin(), groups_.end(),
                   [](const Group& x, const Group& y) { return x.axes.size() < y.axes.size(); });

  // G: every pair's guard over the grid. Its parts stay within `reach` of
  // their reference pose: the motion bound over the box of every axis's
  // values and the reference.
  std::vector<double> lo = grid.reference, hi = grid.reference;
  for (const SweepAxis& a : grid.axes) {
    const std::size_t p = static_cast<std::size_t>(a.parameter);
    for (double v : a.values) {
      lo[p] = std::min(lo[p], v);
      hi[p] = std::max(hi[p], v);
    }
  }
  double reach = 0.0;
  for (std::size_t i = 0; i < scene.parts.size(); ++i)
    reach = std::max(reach, motion_.part_bound(static_cast<int>(i), lo, hi));
  guard_ = checker.guard_bound(reach);
  cutoff_ = std::max(scene.safety_margin, 0.0) + 4.0 * guard_ + kDistanceTieTolerance;
  below_ = scene.safety_margin - 4.0 * guard_ - kDistanceTieTolerance;
  contact_cutoff_ = 4.0 * guard_ + kDistanceTieTolerance;
  // Crossing witnesses: pairs of two meshes (the terrain lists no
  // triangles) whose chains are rigid, so the exact test's working frame
  // (collision_model.h) is an isometry of the world the motion bound and
  // the witness are measured in.
  for (std::size_t k = 0; k < pairs; ++k) {
    const auto [a, b] = checker.pairs()[k];
    bool rigid = b != checker.terrain_index();
    for (int part : {a, b}) {
      if (part < 0 || static_cast<std::size_t>(part) >= scene.parts.size()) continue;
      for (int act : scene.parts[static_cast<std::size_t>(part)].chain)
        if (scene.actions[static_cast<std::size_t>(act)].type == ActionType::kScale) rigid = false;
    }
    crossable_.push_back(rigid ? 1 : 0);
  }
  pair_parts_ = checker.pairs();
  // Part-scale witnesses: the pieces of every part a rigid mesh pair
  // meets, when the checker keeps all of its triangles (a left-out one
  // could be where the surfaces meet).
  // Each is found the first time a box asks for it.
  solids_ = std::make_unique<Solids[]>(scene.parts.size());
  for (const Part& part : scene.parts) {
    double r = 0.0, e = 0.0;
    for (const Tri& t : part.mesh.triangles) {
      const Vec3& x = part.mesh.vertices[t[0]];
      const Vec3& y = part.mesh.vertices[t[1]];
      const Vec3& z = part.mesh.vertices[t[2]];
      const double perimeter = (y - x).norm() + (z - y).norm() + (x - z).norm();
      if (perimeter > 0.0) r = std::max(r, (y - x).cross(z - x).norm() / perimeter);  // 2 area / perimeter
      e = std::max({e, (y - x).norm(), (z - y).norm(), (x - z).norm()});
    }
    inradius_.push_back(r * (1.0 + 1e-9));
    longest_edge_.push_back(e * (1.0 + 1e-9));
  }

  // Limits as first_limit_violation reads them: each parameter an action
  // with limits drives directly, against that action's limits.
  std::vector<std::vector<std::pair<double, double>>> limits(scene.parameter_names.size());
  for (const Action& a : scene.actions) {
    if (!a.has_limits) continue;
    for (int k = 0; k < a.parameter_count; ++k)
      limits[static_cast<std::size_t>(a.first_parameter + k)].push_back({a.lower, a.upper});
  }
  auto outside = [&](std::size_t p, double v) {
    for (const auto& [l, u] : limits[p])
      if (!(v >= l && v <= u)) return true;
    return false;
  };
  std::vector<char> swept(scene.parameter_names.size(), 0);
  for (const SweepAxis& a : grid.axes) swept[static_cast<std::size_t>(a.parameter)] = 1;
  for (std::size_t p = 0; p < swept.size(); ++p)
    if (!swept[p] && outside(p, grid.reference[p])) fixed_outside_limits_ = true;
  for (const SweepAxis& a : grid.axes) {
    std::vector<std::uint8_t> o;
    for (double v : a.values) o.push_back(outside(static_cast<std::size_t>(a.parameter), v) ? 1 : 0);
    outside_limits_.push_back(std::move(o));
  }
}

// The configuration of group axis values `at` (block-relative) with every
// other parameter at its reference value: the pairs of the group see the
// same relative poses whatever the other axes are. As check_pairs does:
// contacts first (the first in checked-pair order ends it), then, unless
// clear_point certifies the point in clearance, distances below the
// cutoff, each search below the best so far (the group's closest pair at
// its last point first), so only the group's minimum is exact.
void SweepCertifier::answer_point(Context& c, const std::vector<std::size_t>& at, const std::vector<Pending>& pending,
                                  double floor) const {
  const Group& g = c.group;
  Answers& out = c.out;
  c.params = grid_.reference;
  for (std::size_t k = 0; k < g.axes.size(); ++k) {
    const SweepAxis& a = grid_.axes[g.axes[k]];
    c.params[static_cast<std::size_t>(a.parameter)] = a.values[c.first[g.axes[k]] + at[k]];
  }
  const std::size_t i = out.index(at);
  const std::int32_t cert = c.cert[i];
  const std::int32_t limit = std::min(c.relevant[i], cert);
  // No pair before `limit` touches: the certified contact, or (every
  // configuration here in contact through an earlier group) nothing to add.
  auto settled = [&] {
    const bool contact = cert < c.relevant[i];
    out.collision[i] = contact ? 1 : 0;
    out.exact[i] = contact ? 1 : 0;
    out.lower[i] = contact ? 0.0 : kInf;
    out.pair[i] = contact ? cert : -1;
    out.witnessed[i] = contact ? 1 : 0;
  };
  bool any = false;
  for (const Pending& p : pending) any = any || static_cast<std::int32_t>(p.pair) < limit;
  if (!any) {
    settled();
    return;
  }
  checker_.pose_parts(c.params, c.posed, g.parts);
  // What the pairs' last answers still prove here.
  std::vector<double>& since = c.since;
  since.assign(pending.size(), 0.0);
  for (std::size_t n = 0; n < pending.size(); ++n) {
    const std::size_t k = pending[n].pair;
    double b = 0.0;
    if (!c.carried_at[k].empty()) b = c.carried[k] - checker_.pair_path(k, c.carried_at[k], c.params);
    const Pending& p = pending[n];
    if (p.at >= 0 && p.lb > b)
      b = std::max(b, p.lb - checker_.pair_path(k, c.pool[static_cast<std::size_t>(p.at)], c.params));
    if (b > 0.0) since[n] = b;  // NaN and infinite motion carry nothing
  }
  for (std::size_t n = 0; n < pending.size(); ++n) {
    const Pending& p = pending[n];
    if (static_cast<std::int32_t>(p.pair) >= limit) break;  // pairs go in order
    if (since[n] > 0.0) continue;  // apart
    ++out.pair_checks;
    if (checker_.pair_collides(c.posed, p.pair)) {
      out.collision[i] = 1;
      out.exact[i] = 1;
      out.lower[i] = 0.0;
      out.pair[i] = static_cast<std::int32_t>(p.pair);
      return;
    }
  }
  if (limit != kNone) {  // all in contact: no distance matters here
    settled();
    return;
  }
  if (clear_point(c, i, pending, floor)) return;
  double best = kInf, bound = floor, guard = kDistanceTolerance;
  std::int32_t best_pair = -1;
  auto ask = [&](std::size_t n) {
    const std::size_t k = pending[n].pair;
    const double need = std::min(cutoff_, best);
    if (since[n] >= need) {  // beyond the need by what an earlier answer proved
      bound = std::min(bound, since[n]);
      return;
    }
    PairAnswer& ans = c.seeds[k];
    checker_.pair_distance(c.posed, k, need, ans);
    if (ans.seeded) c.hints[k] = ans;
    // What this answer proves for the next point (as check_pairs' separations).
    c.carried[k] = ans.exact ? std::max(since[n], ans.distance - kDistanceTieTolerance - ans.guard)
                             : std::max(since[n], ans.distance);
    c.carried_at[k] = c.params;
    if (ans.exact) {
      if (ans.distance < best) {
        best = ans.distance;
        best_pair = static_cast<std::int32_t>(k);
        guard = ans.guard;
      }
    } else {
      bound = std::min(bound, ans.distance);
    }
  };
  const int last = c.last_best;
  std::size_t first = pending.size();
  for (std::size_t n = 0; n < pending.size(); ++n)
    if (static_cast<int>(pending[n].pair) == last) first = n;
  if (first < pending.size()) ask(first);
  for (std::size_t n = 0; n < pending.size(); ++n)
    if (n != first) ask(n);
  out.collision[i] = 0;
  // A pair pruned below the best holds a bound at least best less the
  // tolerances: the best is the group's minimum there.
  if (best_pair >= 0 && best <= bound + kDistanceTieTolerance + guard) {
    out.lower[i] = best;
    out.exact[i] = 1;
    out.pair[i] = best_pair;
    out.guard[i] = guard;
    c.last_best = best_pair;
    c.last_clear = best < below_;
  } else {
    out.lower[i] = std::min(best, bound);
    out.exact[i] = 0;
    out.pair[i] = -1;
    c.last_clear = false;
  }
}

bool SweepCertifier::clear_point(Context& c, std::size_t i, const std::vector<Pending>& pending,
                                 double floor) const {
  // Asked of the pair closest at the last point answered, from its seed:
  // while the closest pair stays, the seed's triangle pair is below the
  // margin here too, and one triangle distance says so.
  if (!(below_ > 0.0) || !c.last_clear) return false;
  std::size_t first = pending.size();
  for (std::size_t n = 0; n < pending.size(); ++n)
    if (static_cast<int>(pending[n].pair) == c.last_best) first = n;
  if (first == pending.size() || !c.hints[pending[first].pair].seeded) return false;
  Answers& out = c.out;
  const std::vector<double>& since = c.since;
  PairAnswer probe = c.hints[pending[first].pair];
  ++out.pair_checks;
  checker_.pair_distance(c.posed, pending[first].pair, below_, probe, /*decide=*/true);
  // probe.upper is the distance of a triangle pair of the two parts as
  // posed here: the exact minimum, as any check poses them (within 4G) and
  // searches (within the tie tolerance), is below the margin. With every
  // pair apart (answer_point tested the contacts), every check of this
  // configuration reads clearance, or collision through another group.
  if (!(probe.upper < below_)) return false;
  // A lower bound of the group's minimum, per pair: what an earlier answer
  // carries when it is as good as a coarse search could give (the
  // smallest distance found / (1 + kClearTolerance)), else a coarse search
  // up to that distance.
  double lower = floor, upper = probe.upper;
  int closest = c.last_best;
  c.seeds[pending[first].pair] = probe;
  c.hints[pending[first].pair] = probe;
  const std::size_t count = pending.size();
  for (std::size_t j = 0; j < count; ++j) {
    const std::size_t n = j == 0 ? first : j <= first ? j - 1 : j;  // the probed pair first
    const std::size_t k = pending[n].pair;
    if (since[n] >= upper / (1.0 + kClearTolerance)) {
      lower = std::min(lower, since[n]);
      continue;
    }
    ++out.pair_checks;
    PairAnswer& ans = c.seeds[k];
    const PairAnswer seed = ans;
    checker_.pair_distance(c.posed, k, std::min(cutoff_, upper), ans, /*decide=*/false, kClearTolerance);
    const double bound = std::max(since[n], ans.distance);
    c.carried[k] = bound;
    c.carried_at[k] = c.params;
    if (ans.upper < upper) {
      upper = ans.upper;
      closest = static_cast<int>(k);
    }
    if (ans.seeded) c.hints[k] = ans;
    if (!ans.seeded) {  // nothing below the need: the old seed stays a good start
      ans.seeded = seed.seeded;
      ans.slot_a = seed.slot_a;
      ans.slot_b = seed.slot_b;
    }
    lower = std::min(lower, bound);
  }
  out.collision[i] = 0;
  out.exact[i] = 0;
  out.lower[i] = lower;
  out.pair[i] = -1;
  out.below[i] = 1;
  c.last_best = closest;
  return true;
}

double SweepCertifier::pair_reach(std::size_t k, const std::vector<double>& lo, const std::vector<double>& hi,
                                  const std::vector<double>& c) const {
  const auto [a, b] = pair_parts_[k];
  const double tight = box_motion_.reach(a, lo, hi, c) + box_motion_.reach(b, lo, hi, c);
  return std::min(checker_.pair_motion(k, lo, hi), tight);  // both bound it
}

double SweepCertifier::pair_path(std::size_t k, const std::vector<double>& from, const std::vector<double>& to) const {
  thread_local std::vector<double> lo, hi;
  lo.resize(from.size());
  hi.resize(from.size());
  for (std::size_t i = 0; i < from.size(); ++i) {
    lo[i] = std::min(from[i], to[i]);
    hi[i] = std::max(from[i], to[i]);
  }
  // Not pair_reach: Checker::pair_motion halves the path, from the box's
  // centre only; `from` is a corner of this box.
  const auto [a, b] = pair_parts_[k];
  const double tight = box_motion_.reach(a, lo, hi, from) + box_motion_.reach(b, lo, hi, from);
  return std::min(checker_.pair_path(k, from, to), tight);
}

bool SweepCertifier::witness_moves(std::size_t k, const std::vector<double>& lo, const std::vector<double>& hi,
                                   double& da, double& db) const {
  return moves(k, lo, hi, da, db) && room(k, da, db);
}

bool SweepCertifier::room(std::size_t k, double da, double db) const {
  // An edge pq through triangle T certifies only when p and q stay more
  // than da + db from T's plane, on either side (crossing.h: the volume of
  // T's edges with p moves by at least |u| |v| (da + db)), so |pq| must
  // exceed 2 (da + db); and when the line pq stays farther than da + db
  // from each of T's edge lines (the volume against edge i moves by at
  // least |pq| |edge i| (da + db)), so T's inradius must exceed da + db.
  const auto [a, b] = pair_parts_[k];
  auto of = [](const std::vector<double>& v, int part) {
    return part >= 0 && static_cast<std::size_t>(part) < v.size() ? v[static_cast<std::size_t>(part)] : 0.0;
  };
  const double m = da + db;
  return (of(longest_edge_, a) > 2.0 * m && of(inradius_, b) > m) ||
         (of(longest_edge_, b) > 2.0 * m && of(inradius_, a) > m);
}

bool SweepCertifier::moves(std::size_t k, const std::vector<double>& lo, const std::vector<double>& hi, double& da,
                           double& db) const {
  if (!crossable_[k]) return false;
  // How far each part's corners move from the centre to any configuration
  // of the box: half the path over it (as Checker::pair_motion), plus
  // rounding twice (the corners as posed at the centre here, and as the
  // exact test poses them in its working frame, each within 4G of the
  // exact pose: G is 64 eps of every coordinate's magnitude over the grid,
  // posing errs by a few ulps of it).
  const auto [a, b] = pair_parts_[k];
  const double rounding = 8.0 * guard_;
  da = 0.5 * motion_.part_bound(a, lo, hi) * (1.0 + 1e-9) + 1e-12 + rounding;
  db = 0.5 * motion_.part_bound(b, lo, hi) * (1.0 + 1e-9) + 1e-12 + rounding;
  return std::isfinite(da) && std::isfinite(db);
}

const SolidPieces& SweepCertifier::pieces(int part) const {
  static const SolidPieces none;
  if (part < 0 || static_cast<std::size_t>(part) >= scene_.parts.size()) return none;
  Solids& s = solids_[static_cast<std::size_t>(part)];
  std::call_once(s.once, [&] {
    if (checker_.part_whole(part)) s.pieces = solid_pieces(scene_.parts[static_cast<std::size_t>(part)].mesh);
  });
  return s.pieces;
}

bool SweepCertifier::may_solid(std::size_t k) const {
  if (!crossable_[k]) return false;
  const auto [a, b] = pair_parts_[k];
  return pieces(a).deepest > 0.0 || pieces(b).deepest > 0.0;
}

bool SweepCertifier::solid(Context& c, std::size_t k, const std::vector<double>& lo, const std::vector<double>& hi,
                           const std::vector<double>& centre) const {
  if (c.solid_hints.size() <= k) c.solid_hints.resize(pair_parts_.size());
  c.solid_hints[k].ratio = 0.0;
  const auto [a, b] = pair_parts_[k];
  if (a < 0 || b < 0 || static_cast<std::size_t>(a) >= scene_.parts.size() ||
      static_cast<std::size_t>(b) >= scene_.parts.size())
    return false;
  const std::size_t ua = static_cast<std::size_t>(a), ub = static_cast<std::size_t>(b);
  // Each point's move from the centre over the box (BoxMotion, per point
  // for the piece, per part for the solid), plus rounding twice as in
  // witness_moves.
  const BoxMotion::Lever la = box_motion_.lever(a, lo, hi, centre), lb = box_motion_.lever(b, lo, hi, centre);
  SolidMoves m;
  m.a = &la;
  m.b = &lb;
  m.whole_a = box_motion_.reach(a, la);
  m.whole_b = box_motion_.reach(b, lb);
  m.pad = 8.0 * guard_ + 1e-12;
  return solid_crossing(scene_.parts[ua].mesh, pieces(a), *c.posed.pose[ua], scene_.parts[ub].mesh, pieces(b),
                        *c.posed.pose[ub], m, c.solid_hints[k]);
}

bool SweepCertifier::crossing(const std::vector<std::array<Vec3, 6>>& crossings, double da, double db) const {
  for (const std::array<Vec3, 6>& x : crossings)
    if (crossing_certain(x, da, db)) return true;
  return false;
}

void SweepCertifier::certify(Context& c, std::vector<std::size_t>& lo, std::vector<std::size_t>& hi,
                             std::vector<Pending>& pending, double floor) const {
  const Group& g = c.group;
  Answers& out = c.out;
  const std::size_t d = g.axes.size();
  std::size_t points = 1;
  for (std::size_t k = 0; k < d; ++k) points *= hi[k] - lo[k] + 1;
  auto each_point = [&](auto&& fn) {
    std::vector<std::size_t> at(lo);
    for (;;) {
      fn(at);
      std::size_t k = d;
      while (k > 0) {
        --k;
        if (at[k] < hi[k]) {
          ++at[k];
          break;
        }
        at[k] = lo[k];
        if (k == 0) return;
      }
      if (d == 0) return;
    }
  };
  // Pairs no configuration of the box needs (each has an earlier contact,
  // from a group answered before or a crossing witness).
  std::int32_t box_limit = 0;
  each_point([&](const std::vector<std::size_t>& at) {
    const std::size_t i = out.index(at);
    box_limit = std::max(box_limit, std::min(c.relevant[i], c.cert[i]));
  });
  if (box_limit != kNone) {
    std::vector<Pending> needed;
    for (const Pending& p : pending)
      if (static_cast<std::int32_t>(p.pair) < box_limit) needed.push_back(p);
    if (needed.size() < pending.size()) pending.swap(needed);
  }
  // Every configuration of the box in contact: its distances are 0
  // whatever the pairs left show, so they need only be proven apart.
  double cut = box_limit != kNone ? contact_cutoff_ : cutoff_;
  auto certified_all = [&](double bound) {
    each_point([&](const std::vector<std::size_t>& at) {
      const std::size_t i = out.index(at);
      const bool contact = c.cert[i] < c.relevant[i];
      out.lower[i] = contact ? 0.0 : bound;
      out.exact[i] = contact ? 1 : 0;
      out.collision[i] = contact ? 1 : 0;
      out.pair[i] = contact ? c.cert[i] : -1;
      out.witnessed[i] = contact ? 1 : 0;
    });
  };
  if (pending.empty()) {
    certified_all(floor);
    return;
  }
  // The box's corners and centre as full parameter vectors.
  auto corners = [&](std::vector<double>& qlo, std::vector<double>& qhi, std::vector<double>& qc) {
    qlo = qhi = qc = grid_.reference;
    for (std::size_t k = 0; k < d; ++k) {
      const SweepAxis& a = grid_.axes[g.axes[k]];
      const std::size_t p = static_cast<std::size_t>(a.parameter);
      double vmin = kInf, vmax = -kInf;
      for (std::size_t v = c.first[g.axes[k]] + lo[k]; v <= c.first[g.axes[k]] + hi[k]; ++v) {
        vmin = std::min(vmin, a.values[v]);
        vmax = std::max(vmax, a.values[v]);
      }
      qlo[p] = vmin;
      qhi[p] = vmax;
      qc[p] = vmin + 0.5 * (vmax - vmin);
    }
  };
  auto mark_contact = [&](std::size_t k) {
    each_point([&](const std::vector<std::size_t>& at) {
      const std::size_t i = out.index(at);
      c.cert[i] = std::min(c.cert[i], static_cast<std::int32_t>(k));
    });
    ++out.contact_boxes;
  };
  if (points <= kSmallBox) {
    // The first pair in contact at the last centre may cross with room for
    // this small box: one witness search (no distance) can spare every
    // point its contact test and every later pair. A part-scale witness
    // that fails is asked again on the box's halves, down to kWitnessBox.
    for (const Pending& p : pending) {
      if (!(p.at >= 0 && p.ub == 0.0)) continue;
      const bool solid_room = may_solid(p.pair);
      auto attempt = [&](auto&& self, std::size_t n) -> void {
        if (n < kWitnessBox) return;
        double da = 0.0, db = 0.0;
        std::vector<double> qlo, qhi, qc;
        corners(qlo, qhi, qc);
        if (!moves(p.pair, qlo, qhi, da, db)) return;
        const bool triangle_room = room(p.pair, da, db);
        if (!solid_room && !triangle_room) return;
        // The pair's two parts only: each point answered poses its own.
        const int two[2] = {pair_parts_[p.pair].first, pair_parts_[p.pair].second};
        checker_.pose_parts(qc, c.posed, std::span<const int>(two, two[1] == checker_.terrain_index() ? 1 : 2));
        ++out.pair_checks;
        if (solid_room && solid(c, p.pair, qlo, qhi, qc)) {
          mark_contact(p.pair);
          return;
        }
        if (triangle_room) {
          checker_.pair_crossings(c.posed, p.pair, kWitnesses, c.crossings);
          if (crossing(c.crossings, da, db)) {
            mark_contact(p.pair);
            return;
          }
        }
        // Halving a side at most halves the moves: not worth it when the
        // best candidate cleared less than half of them.
        if (!solid_room || n < 2 * kWitnessBox || !(c.solid_hints[p.pair].ratio >= kWitnessShare)) return;
        std::size_t split = 0;
        for (std::size_t k = 1; k < d; ++k)
          if (hi[k] - lo[k] > hi[split] - lo[split]) split = k;
        if (d == 0 || hi[split] == lo[split]) return;
        const std::size_t mid = lo[split] + (hi[split] - lo[split]) / 2;
        const std::size_t old_lo = lo[split], old_hi = hi[split];
        const std::size_t side = old_hi - old_lo + 1;
        hi[split] = mid;
        self(self, n / side * (mid - old_lo + 1));
        hi[split] = old_hi;
        lo[split] = mid + 1;
        self(self, n / side * (old_hi - mid));
        lo[split] = old_lo;
      };
      attempt(attempt, points);
      break;
    }
    each_point([&](const std::vector<std::size_t>& at) { answer_point(c, at, pending, floor); });
    return;
  }

  std::vector<double> qlo, qhi, qc;
  corners(qlo, qhi, qc);
  bool posed_done = false;
  std::size_t centre = 0;  // this centre's index in c.pool, once asked
  std::vector<Pending> still;
  std::vector<double> still_motion, still_lb;  // per pair in still: m, a lower bound at this centre
  auto keep = [&](const Pending& p, double m, double lb) {
    still.push_back(p);
    still_motion.push_back(m);
    still_lb.push_back(lb);
  };
  bool witnessed = false;
  auto pose_centre = [&] {  // once a box, kept in c.pool for the pairs' Pending::at
    if (posed_done) return;
    checker_.pose_parts(qc, c.posed, g.parts);
    c.pool.push_back(qc);
    centre = c.pool.size() - 1;
    posed_done = true;
  };
  for (const Pending& p : pending) {
    const std::size_t k = p.pair;
    const double m = pair_reach(k, qlo, qhi, qc);
    // What the pair's last answer (at c.pool[p.at]) says at this centre:
    // the distance moves by at most the parts' relative path.
    double lb = 0.0, ub = kInf;
    if (p.at >= 0) {
      const double path = pair_path(k, c.pool[static_cast<std::size_t>(p.at)], qc);
      lb = p.lb - path;
      ub = p.ub + path;
    }
    if (lb - m >= cut) {  // certified without a search
      floor = std::min(floor, lb - m);
      continue;
    }
    // A pair in contact at the last centre may cross here with room for
    // the whole box (only a pair that can bring a witness is asked): first
    // at the parts' scale, then triangle by triangle.
    double da = 0.0, db = 0.0;
    const bool movable = moves(k, qlo, qhi, da, db);
    const bool witness = movable && room(k, da, db);
    const bool in_contact = p.at >= 0 && p.ub == 0.0;
    const bool may_cross = witness && in_contact;
    if (movable && in_contact && may_solid(k)) {
      pose_centre();
      ++out.pair_checks;
      if (solid(c, k, qlo, qhi, qc)) {
        mark_contact(k);
        witnessed = true;
        break;
      }
    }
    if (!(ub >= cut + m) && !may_cross) {  // cannot be certified here (or the motion is not finite)
      keep(p, m, lb);
      continue;
    }
    pose_centre();
    ++out.pair_checks;
    Pending q = p;
    q.at = static_cast<int>(centre);
    bool hit = false;
    if (witness) {
      checker_.pair_crossings(c.posed, k, kWitnesses, c.crossings);
      hit = !c.crossings.empty();
    } else {
      hit = checker_.pair_collides(c.posed, k);
    }
    if (hit) {
      if (witness && crossing(c.crossings, da, db)) {
        // In contact at every configuration of the box: no pair after k
        // matters here, and those before it need only be proven apart.
        mark_contact(k);
        witnessed = true;
        break;
      }
      q.lb = 0.0;
      q.ub = 0.0;
      keep(q, m, 0.0);
      continue;
    }
    if (!(ub >= cut + m)) {  // apart here, but too close to certify the box
      keep(p, m, lb);
      continue;
    }
    PairAnswer& ans = c.seeds[k];
    // Certified when the distance here is at least cut + m: a search
    // told to stop at the first triangle pair below that proves it, or
    // finds one (an upper bound for the boxes inside).
    const double need = cut + m + kDistanceTieTolerance + guard_;
    checker_.pair_distance(c.posed, k, need, ans, /*decide=*/true);
    q.lb = ans.distance;
    q.ub = ans.upper;
    if (!std::isfinite(ans.upper) && q.lb - m >= cut) {
      floor = std::min(floor, q.lb - m);
      continue;
    }
    keep(q, m, q.lb);
  }
  if (witnessed) {  // the pairs before the witness's need only be apart
    std::vector<Pending> apart;
    for (std::size_t n = 0; n < still.size(); ++n) {
      if (still_lb[n] - still_motion[n] >= contact_cutoff_)
        floor = std::min(floor, still_lb[n] - still_motion[n]);
      else
        apart.push_back(still[n]);
    }
    still.swap(apart);
  }
  if (still.empty()) {
    certified_all(floor);
    return;
  }
  // Halve the box across the side that moves the pairs left most (each
  // side's share of their motion bound: the sides alone), among the sides
  // of more than one value; the longest side (in values) on a tie.
  std::size_t split = 0;
  for (std::size_t k = 1; k < d; ++k)
    if (hi[k] - lo[k] > hi[split] - lo[split]) split = k;
  if (d > 1) {
    std::vector<double> slo = qc, shi = qc;
    double most = -1.0;
    for (std::size_t k = 0; k < d; ++k) {
      if (hi[k] == lo[k]) continue;
      const std::size_t p = static_cast<std::size_t>(grid_.axes[g.axes[k]].parameter);
      slo[p] = qlo[p];
      shi[p] = qhi[p];
      double share = 0.0;
      for (const Pending& q : still) share += pair_reach(q.pair, slo, shi, qc);
      slo[p] = shi[p] = qc[p];
      if (share > most || (share == most && hi[k] - lo[k] > hi[split] - lo[split])) {
        most = share;
        split = k;
      }
    }
  }
  const std::size_t mid = lo[split] + (hi[split] - lo[split]) / 2;
  const std::size_t old_lo = lo[split], old_hi = hi[split];
  std::vector<Pending> copy = still;
  hi[split] = mid;
  certify(c, lo, hi, still, floor);
  hi[split] = old_hi;
  lo[split] = mid + 1;
  certify(c, lo, hi, copy, floor);
  lo[split] = old_lo;
}

void SweepCertifier::check_block(std::size_t b, SweepBlockResult& out) const {
  std::vector<std::size_t> first, size;
  blocks_.block(b, first, size);
  const std::size_t d = size.size();
  std::size_t n = 1;
  for (std::size_t s : size) n *= s;

  // Each group over its projection of the block.
  std::vector<Answers> answers(groups_.size());
  std::vector<std::int32_t> first_contact(n, kNone), relevant;  // per configuration of the block
  std::vector<PairAnswer> seeds(checker_.pairs().size());
  std::vector<double> carried(seeds.size(), 0.0);
  std::vector<std::vector<double>> carried_at(seeds.size());
  out.pair_checks = 0;
  out.point_tests = 0;
  out.witnessed = 0;
  out.contact_boxes = 0;
  for (std::size_t gi = 0; gi < groups_.size(); ++gi) {
    const Group& g = groups_[gi];
    Answers& a = answers[gi];
    std::size_t m = 1;
    for (std::size_t ax : g.axes) {
      a.size.push_back(size[ax]);
      m *= size[ax];
    }
    a.lower.assign(m, kInf);
    a.exact.assign(m, 0);
    a.collision.assign(m, 0);
    a.pair.assign(m, -1);
    a.guard.assign(m, kDistanceTolerance);
    a.witnessed.assign(m, 0);
    a.below.assign(m, 0);
    std::vector<std::size_t> lo(g.axes.size(), 0), hi;
    for (std::size_t s : a.size) hi.push_back(s - 1);
    std::vector<Pending> pending;
    for (std::size_t k : g.pairs) pending.push_back({k, -1, 0.0, kInf});
    // Seeds start empty in every block: its answers depend on it alone.
    // What the groups before this one leave to it (see Context::relevant).
    relevant.assign(m, std::numeric_limits<std::int32_t>::min());
    {
      std::vector<std::size_t> dg(d, 0);
      for (std::size_t i = 0; i < n; ++i) {
        std::size_t j = 0;
        for (std::size_t k = 0; k < g.axes.size(); ++k) j = j * a.size[k] + dg[g.axes[k]];
        relevant[j] = std::max(relevant[j], first_contact[i]);
        for (std::size_t k = d; k-- > 0;) {
          if (++dg[k] < size[k]) break;
          dg[k] = 0;
        }
      }
    }
    Context c{g, first, a, seeds, -1, carried, carried_at, relevant};
    c.cert.assign(m, kNone);
    c.hints.assign(seeds.size(), PairAnswer{});
    for (std::size_t k : g.pairs) {
      seeds[k] = PairAnswer{};
      carried_at[k].clear();
    }
    certify(c, lo, hi, pending, kInf);
    for (std::size_t j = 0; j < m; ++j) out.point_tests += a.exact[j] && !a.witnessed[j];
    out.pair_checks += a.pair_checks;
    out.contact_boxes += a.contact_boxes;
    {
      std::vector<std::size_t> dg(d, 0);
      for (std::size_t i = 0; i < n; ++i) {
        std::size_t j = 0;
        for (std::size_t k = 0; k < g.axes.size(); ++k) j = j * a.size[k] + dg[g.axes[k]];
        if (a.collision[j]) first_contact[i] = std::min(first_contact[i], a.pair[j]);
        for (std::size_t k = d; k-- > 0;) {
          if (++dg[k] < size[k]) break;
          dg[k] = 0;
        }
      }
    }
  }

  // Each configuration: every group at its projection.
  out.verdict.resize(n);
  out.distance.resize(n);
  out.exact.resize(n);
  out.pair.resize(n);
  const double margin = scene_.safety_margin;
  std::vector<std::size_t> digit(d, 0);
  for (std::size_t i = 0; i < n; ++i) {
    bool collision = false;
    std::int32_t first_contact = std::numeric_limits<std::int32_t>::max();
    double best = kInf, guard = kDistanceTolerance;
    bool exact = false, witnessed = false, below = false;
    std::int32_t best_pair = -1;
    for (std::size_t gi = 0; gi < groups_.size(); ++gi) {
      const Group& g = groups_[gi];
      const Answers& a = answers[gi];
      std::size_t j = 0;
      for (std::size_t k = 0; k < g.axes.size(); ++k) j = j * a.size[k] + digit[g.axes[k]];
      below = below || (!a.collision[j] && a.below[j]);
      if (a.collision[j]) {
        collision = true;
        if (a.pair[j] < first_contact) witnessed = a.witnessed[j] != 0;
        first_contact = std::min(first_contact, a.pair[j]);
      } else if (a.lower[j] < best || (a.lower[j] == best && a.exact[j] && !exact)) {
        best = a.lower[j];
        exact = a.exact[j] != 0;
        best_pair = a.pair[j];
        guard = a.guard[j];
      }
    }
    bool outside = fixed_outside_limits_;
    for (std::size_t k = 0; k < d && !outside; ++k) outside = outside_limits_[k][first[k] + digit[k]] != 0;
    if (collision) {
      out.witnessed += witnessed ? 1 : 0;
      out.verdict[i] = Verdict::kCollision;
      out.distance[i] = 0.0;
      out.exact[i] = 1;
      out.pair[i] = first_contact;
    } else {
      // As state_verdict: a distance below the margin, or too close to it
      // to settle in double, is a violation. Certified bounds are beyond
      // the cutoff, far from any such doubt, or come with a pair certainly
      // below the margin (below: clear_point).
      const bool clearance = margin > 0.0 && ((exact && best < margin + guard) || below);
      out.verdict[i] = clearance ? Verdict::kClearance : outside ? Verdict::kLimits : Verdict::kSafe;
      out.distance[i] = best;
      out.exact[i] = exact ? 1 : 0;
      out.pair[i] = exact ? best_pair : -1;
    }
    // Next configuration in C order within the block.
    for (std::size_t k = d; k-- > 0;) {
      if (++digit[k] < size[k]) break;
      digit[k] = 0;
    }
  }
}

}  // namespace plancheck
