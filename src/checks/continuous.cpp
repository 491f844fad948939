// SPDX-License-Identifier: MIT
// Conservative advancement by bisection. On a sub-interval [ta, tb] with exact
// distances Da, Db at its ends and a bound M on how much any pair's distance
// can change over it (MotionBound: every point's path is at most that long,
// and a distance between two sets moves by at most the sum of their points'
// displacements), D(t) >= max(Da - M l, Db - M (1 - l)) for t = ta + l (tb -
// ta), so min D >= (Da + Db - M) / 2 (and <= Da, Db). A sub-interval whose
// bound clears the target is certified; otherwise its midpoint is checked
// exactly and both halves are taken in turn, left first. Halving shrinks M
// linearly while the ends stay above target + tolerance, so every segment
// ends in a certificate or a witness.
#include "src/checks/continuous.h"

#include "src/base/parallel.h"
#include "src/checks/swept_clusters.h"
#include "src/checks/regolith.h"
#include "src/scene/plan.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <optional>
#include <span>

namespace plancheck {

namespace {

struct Sample {
  double t = 0.0;
  double d = std::numeric_limits<double>::infinity();  // exact minimum distance (m); 0 when colliding
  bool collision = false;
  int a = -1, b = -1;  // pair at d (or the first contact)
  double tolerance = kDistanceTolerance;  // the state's rounding guard (StateResult::distance_tolerance)
  bool bound = false;  // d is only a certified lower bound (a verdict-only check)
};

Sample to_sample(double t, const StateResult& s) {
  Sample out;
  out.t = t;
  out.collision = s.collision;
  out.tolerance = s.distance_tolerance;
  out.bound = s.distance_is_bound;
  out.d = s.collision ? 0.0 : s.min_distance;
  if (s.collision) {
    out.a = s.contacts[0].part_a;
    out.b = s.contacts[0].part_b;
  } else {
    out.a = s.part_a;
    out.b = s.part_b;
  }
  return out;
}

// The two passes both algorithms run: against the margin (when there is
// one), then, where it found a witness (or without a margin), against
// contact; certify(target, limit, contact, lower) returns the pass's first
// witness (t, a, b) or nothing, and sets gave_up when the budget ran out.
// first_violation: a witness against the margin ends it (no contact pass).
template <class Certify>
void two_passes(double margin, const ContinuousOptions& options, const bool& gave_up, SegmentResult& out,
                Certify&& certify, bool first_violation = false) {
  double lower = std::numeric_limits<double>::infinity();
  auto witness = decltype(certify(0.0, 0.0, false, lower)){};
  bool check_contact = true;
  bool cut_short = false;  // stopped at a margin witness (first_violation)
  if (margin > 0.0) {
    witness = certify(margin, margin + options.tolerance, false, lower);
    check_contact = witness.has_value();
    if (check_contact && first_violation) check_contact = false, cut_short = true;
  }
  bool collision = false;
  if (check_contact && !gave_up) {
    // Touching anywhere on the segment, or within contact_tolerance of it?
    lower = std::numeric_limits<double>::infinity();
    const auto contact = certify(0.0, options.contact_tolerance, true, lower);
    if (contact) {
      collision = true;
      witness = contact;
      lower = 0.0;
    }
  }
  if (witness) {
    out.collision = collision;
    out.clearance = margin > 0.0;
    out.witness_t = witness->t;
    out.part_a = witness->a;
    out.part_b = witness->b;
  }
  if (gave_up && !out.clearance && !out.collision) {
    // Not certified: a violation (counted as clearance), naming no pair.
    out.clearance = true;
    out.part_a = out.part_b = -1;
    out.witness_t = -1.0;
  }
  // Cut short, the pass's bound covers only what it certified before its
  // witness: no bound over the whole segment was made.
  out.lower_bound = cut_short ? std::numeric_limits<double>::quiet_NaN() : lower;
  out.unresolved = gave_up;
}

}  // namespace

SegmentChecker::SegmentChecker(const Checker& checker, const Scene& scene, const ContinuousOptions& options)
    : checker_(checker),
      bound_(checker.motion_bound()),
      pairs_(checker.pairs()),
      plan_(bound_.pair_plan(pairs_)),
      margin_(scene.safety_margin),
      options_(options) {
  for (const auto& [a, b] : pairs_)
    for (int p : {a, b})
      if (static_cast<std::size_t>(p) < scene.parts.size() && scene.parts[static_cast<std::size_t>(p)].moving() &&
          std::find(moving_.begin(), moving_.end(), p) == moving_.end())
        moving_.push_back(p);
  const int n_parts = static_cast<int>(checker_.part_count());
  still_.assign(static_cast<std::size_t>(n_parts), 1);
  for (int p : moving_)
    if (p >= 0 && p < n_parts) still_[static_cast<std::size_t>(p)] = 0;
  auto still = [&](int x) {
    return x >= 0 && x < n_parts && x != checker_.terrain_index() && still_[static_cast<std::size_t>(x)];
  };
  for (const auto& [a, b] : pairs_) {
    const bool a_still = still(a), b_still = still(b);
    if (a_still != b_still)
      swept_.emplace_back(a_still ? b : a, a_still ? a : b);
    else
      swept_.emplace_back(-1, -1);
  }
  for (const Action& a : scene.actions) {
    if (a.type == ActionType::kRotate) {
      const bool mimic = a.mimic >= 0;
      const int parameter = mimic ? scene.actions[static_cast<std::size_t>(a.mimic)].first_parameter : a.first_parameter;
      turns_.emplace_back(parameter, (mimic ? std::abs(a.multiplier) : 1.0) * a.unit_to_si);
    } else if (a.type == ActionType::kScale) {
      for (int k = 0; k < a.parameter_count; ++k) scale_parameters_.push_back(a.first_parameter + k);
    }
  }
}

double SegmentChecker::turning(const std::vector<double>& qa, const std::vector<double>& qb) const {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  for (const int k : scale_parameters_)
    if (!(qa[static_cast<std::size_t>(k)] == qb[static_cast<std::size_t>(k)])) return kInf;
  double sum = 0.0;
  for (const auto& [k, factor] : turns_) sum += factor * std::abs(qb[static_cast<std::size_t>(k)] - qa[static_cast<std::size_t>(k)]);
  // Padded for the rounding of the sum (a mimic's multiplier is applied to
  // the difference, not to each value).
  return std::isfinite(sum) ? sum * (1.0 + 1e-9) : kInf;
}

double piece_lower_bound(double t1, double v1, double t2, double v2, double rate, double accel) {
  const double length = t2 - t1;
  const double first = std::min({v1, v2, 0.5 * (v1 + v2 - rate * length)});
  if (!(first > 0.0) || !(accel >= 0.0) || !(length > 0.0)) return first;
  // |y|'' <= K over the piece, padded for the rounding of what follows.
  const double k = (rate * rate / first + accel) * (1.0 + 1e-9);
  const double c = 0.5 * k * length * length;  // the chord less c s (1 - s), s in [0, 1]
  if (!(c < std::numeric_limits<double>::infinity())) return first;
  const double s = c > 0.0 ? std::clamp(0.5 - 0.5 * (v2 - v1) / c, 0.0, 1.0) : (v1 <= v2 ? 0.0 : 1.0);
  const double second = v1 + (v2 - v1) * s - c * s * (1.0 - s);
  // Rounding: a few ulps of the largest term, far inside the guards the
  // callers add.
  const double pad = 1e-12 * (std::abs(v1) + std::abs(v2) + c);
  return std::max(first, second - pad);
}

double SegmentChecker::pair_bound(const std::vector<double>& qa, const std::vector<double>& qb) const {
  thread_local std::vector<double> part;
  part.assign(checker_.part_count(), 0.0);
  for (int p : moving_) part[static_cast<std::size_t>(p)] = bound_.part_bound(p, qa, qb);
  double m = 0.0;
  for (const auto& [a, b] : pairs_) {
    const double s = part[static_cast<std::size_t>(a)] + part[static_cast<std::size_t>(b)];
    if (!(s <= m)) m = s;  // NaN or infinity propagates: nothing is certified
  }
  return m;
}

SegmentResult SegmentChecker::check(const std::vector<double>& qa, const std::vector<double>& qb,
                                    const StateResult& sa, const StateResult& sb, const Heightfield* terrain,
                                    bool sb_on_terrain) const {
  if (terrain && !sb_on_terrain) {
    // sb shows qb after its own dig; the motion meets the terrain before it.
    // Its other pairs are as sb shows them: when sb's closest pair is not a
    // terrain pair (exact, no contact), sb's distance, pair and guard are
    // theirs (check_terrain left them), so only the terrain pairs are
    // checked again; else the whole state is.
    StateResult sb_before;
    const int tr = checker_.terrain_index();
    if (!sb.collision && !sb.distance_is_bound && sb.part_a >= 0 && sb.part_a != tr && sb.part_b != tr)
      sb_before = sb;
    else
      checker_.check_state_without_terrain(qb, sb_before, row_request());
    checker_.check_terrain(qb, *terrain, sb_before);
    return run_pairs(qa, qb, sa, sb_before, nullptr, terrain);
  }
  return run_pairs(qa, qb, sa, sb, nullptr, terrain);
}

SegmentResult SegmentChecker::check_reference(const std::vector<double>& qa, const std::vector<double>& qb,
                                              const StateResult& sa, const StateResult& sb,
                                              const Heightfield* terrain, bool sb_on_terrain) const {
  return run(qa, qb, sa, sb, terrain, sb_on_terrain, false);
}

SegmentChecker::PoseRates::PoseRates(const SegmentChecker& segments, const std::vector<double>& qa,
                                     const std::vector<double>& qb, const PosedParts& posed, Storage& storage,
                                     const SweptClusters* swept)
    : segments_(segments), qa_(qa), qb_(qb), posed_(posed), swept_(swept), lo_(storage.lo), hi_(storage.hi),
      mid_(storage.mid), parts_(storage.parts) {}

const SegmentChecker::PoseRates::PartMove& SegmentChecker::PoseRates::part(int x) {
  static const PartMove kStill{};
  const Checker& checker = segments_.checker_;
  if (x < 0 || static_cast<std::size_t>(x) >= checker.part_count()) return kStill;  // no such part
  if (!ready_) {
    box_ = &checker.box_motion();  // built the first time a segment asks
    lo_.resize(qa_.size());
    hi_.resize(qa_.size());
    mid_.resize(qa_.size());
    for (std::size_t i = 0; i < qa_.size(); ++i) {
      lo_[i] = std::min(qa_[i], qb_[i]);
      hi_[i] = std::max(qa_[i], qb_[i]);
      mid_[i] = std::clamp(qa_[i] + 0.5 * (qb_[i] - qa_[i]), lo_[i], hi_[i]);
    }
    // Every part unknown again; a part's balls keep their capacity.
    parts_.resize(checker.part_count());
    for (PartMove& m : parts_) m.known = false;
    ready_ = true;
  }
  PartMove& m = parts_[static_cast<std::size_t>(x)];
  if (!m.known) {
    m.known = true;
    const std::vector<BoxMotion::Ball>* known = swept_ ? swept_->balls(x) : nullptr;
    if (known) {
      m.balls = true;
      m.ball = *known;
    } else {
      m.balls = box_->balls(x, lo_, hi_, mid_, m.ball);
    }
    if (m.balls) {
      m.reach = 0.0;
      for (const BoxMotion::Ball& b : m.ball) m.reach = std::max(m.reach, b.move);
    } else {
      m.reach = box_->reach(x, lo_, hi_, mid_);  // 0 for a static part
    }
    if (std::isnan(m.reach)) m.reach = std::numeric_limits<double>::infinity();
  }
  return m;
}

SegmentChecker::PoseRates::Rate SegmentChecker::PoseRates::of(std::size_t k, double far_need) {
  const auto [a, b] = segments_.pairs_[k];
  const PartMove& ma = part(a);
  const PartMove& mb = part(b);
  Rate out;
  out.rate = 2.0 * (ma.reach + mb.reach);
  // One moving part against a static mesh or the terrain: only the moving
  // part's clusters that can come near the other's box count. Every point
  // of a cluster lies within radius + move of its centre posed at the
  // midpoint over the whole segment, so a cluster that far clear of the
  // static box keeps its points at least that far from the static part;
  // the pair's distance is then at least the least of the others' and
  // that, and the others' moves bound how fast it can change.
  const Checker& checker = segments_.checker_;
  const std::size_t n = segments_.still_.size();
  auto still = [&](int x) { return x >= 0 && static_cast<std::size_t>(x) < n && segments_.still_[static_cast<std::size_t>(x)]; };
  const PartMove* moving = nullptr;
  int other = -1;
  if (ma.balls && still(b)) moving = &ma, other = b;
  if (mb.balls && still(a)) moving = &mb, other = a;
  if (!moving) return out;
  Vec3 lo, hi;
  if (other == checker.terrain_index()) {
    if (!checker.terrain_box(posed_.terrain, lo, hi)) return out;
  } else {
    lo = posed_.box[static_cast<std::size_t>(other)].first;
    hi = posed_.box[static_cast<std::size_t>(other)].second;
  }
  const std::size_t nb = moving->ball.size();
  out.moving = moving == &ma ? a : b;
  out.counted = nb > 64 ? 0 : nb == 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << nb) - 1;
  double rate = 0.0, far = std::numeric_limits<double>::infinity();
  std::uint64_t counted = 0;
  for (std::size_t i = 0; i < nb; ++i) {
    const BoxMotion::Ball& ball = moving->ball[i];
    const Vec3 d = (lo - ball.centre).cwiseMax(ball.centre - hi).cwiseMax(Vec3::Zero());
    const double reach = ball.radius + ball.move;
    const double pad = 1e-9 * (ball.centre.cwiseAbs().maxCoeff() + reach + 1.0);
    const double gap = d.norm() - reach - pad;
    if (gap >= far_need) {
      far = std::min(far, gap);
    } else {
      rate = std::max(rate, 2.0 * ball.move);
      if (i < 64) counted |= std::uint64_t{1} << i;
    }
  }
  if (rate < out.rate) {
    out.rate = rate;
    out.far = far;
    if (out.counted) out.counted = counted;
  }
  return out;
}

double SegmentChecker::first_limit() const {
  return margin_ > 0.0 ? margin_ + options_.tolerance : options_.contact_tolerance;
}

double SegmentChecker::end_reach() const {
  // Half the margin, not all of it: check_motion's verdict-only ends are
  // exact up to first_limit() + end_reach(), and their searches cost by how
  // far they reach (URDF arm planner states, margin 5 cm: 22.9 us a state
  // exact below 10 cm, 5.9 us below 6.25 cm). Callgrind over the OMPL
  // bench's planner motions (verdict-only, first violation): the URDF arm
  // 2.57 -> 2.11 G instructions (6% more pair samples), the default arm
  // 1.99 -> 1.95 G; a quarter of the margin gained little more on the URDF
  // arm and lost on the default one.
  return 0.5 * std::max(margin_, options_.tolerance);
}

double SegmentChecker::end_limit(const std::vector<double>& bounds) const {
  double m = 0.0;
  for (const double s : bounds)
    if (!(s <= m)) m = s;  // NaN or infinity propagates
  // At most half the margin (the tolerance without one) beyond the first
  // limit (end_reach): an end state's exact distances far beyond the margin
  // cost dearly (at a metre, a search explores thousands of terrain
  // triangles) and certify little that the pairs' own bounded searches do
  // not.
  const double e = first_limit() + std::min(0.5 * m, end_reach());
  return e < std::numeric_limits<double>::infinity() ? e : std::numeric_limits<double>::infinity();
}

SegmentResult SegmentChecker::check_motion(const std::vector<double>& qa, const std::vector<double>& qb,
                                           bool verdict_only, StateResult& sa, StateResult& sb,
                                           double* certified_until, bool first_violation, int threads) const {
  // The pairs' bounds once: for the verdict-only ends' limit and the march.
  std::vector<double> bounds;
  bound_.pair_bounds(plan_, qa, qb, bounds);
  CheckRequest request = row_request();
  if (verdict_only) {
    // Exact up to the largest end_limit any segment can have (first limit
    // plus end_reach), not this segment's: the ends' floors, min(distance,
    // end_limit), are the full check's all the same (a bound at least this
    // limit is at least end_limit), and one state is asked the same
    // question whichever motion it ends, so that the memo below can answer
    // it. A non-finite end_limit (non-finite bounds) asks exact ends.
    request.exact_below = end_limit(bounds) < std::numeric_limits<double>::infinity()
                              ? first_limit() + end_reach()
                              : std::numeric_limits<double>::infinity();
  }
  // A planner checks many motions from one state (RRTConnect's connect
  // steps go on from the last state added, and a tree's states are the
  // nearest of many samples; a path's edges share their ends; simplifying a
  // path checks motions between its few states again and again): the end
  // states this thread checked last (up to kKept, the least recently used
  // replaced) are kept, keyed by the checker (each world version is a
  // checker of its own), the state's bits and the request's limit, and
  // taken instead of checking again. check_state without a seed is a
  // function of exactly these, so a state taken is bit for bit the one
  // checked. 256: on the OMPL bench's planner runs 8 kept states missed
  // 3,694 of 5,724 ends (URDF arm), 256 missed 2,361 (2,331 distinct).
  struct EndMemo {
    std::uint64_t checker = 0;  // Checker::instance_id(); 0: empty
    std::uint64_t used = 0;     // when last taken or kept (the thread's count)
    std::uint64_t hash = 0;     // of the state's bits, compared first
    std::vector<double> q;
    double exact_below = 0.0;
    StateResult result;
  };
  constexpr int kKept = 256;
  thread_local std::vector<EndMemo> memo(kKept);
  thread_local std::uint64_t clock = 0;
  auto same_bits = [](const std::vector<double>& x, const std::vector<double>& y) {
    return x.size() == y.size() && (x.empty() || std::memcmp(x.data(), y.data(), x.size() * sizeof(double)) == 0);
  };
  auto hash_of = [](const std::vector<double>& x) {
    std::uint64_t h = 1469598103934665603ull;  // FNV-1a over the bytes
    const auto* bytes = reinterpret_cast<const unsigned char*>(x.data());
    for (std::size_t i = 0; i < x.size() * sizeof(double); ++i) h = (h ^ bytes[i]) * 1099511628211ull;
    return h;
  };
  const std::uint64_t id = checker_.instance_id();
  // The entry kept for q (taken: out set, its use noted), or -1.
  auto find = [&](const std::vector<double>& q, std::uint64_t h, StateResult& out) {
    for (int i = 0; i < kKept; ++i) {
      EndMemo& m = memo[static_cast<std::size_t>(i)];
      if (m.hash == h && m.checker == id && std::memcmp(&m.exact_below, &request.exact_below, sizeof(double)) == 0 &&
          same_bits(m.q, q)) {
        out = m.result;
        m.used = ++clock;
        return i;
      }
    }
    return -1;
  };
  // Keeps a state checked, in the least recently used entry but `other`.
  auto keep = [&](const std::vector<double>& q, std::uint64_t h, const StateResult& result, int other) {
    int slot = other == 0 ? 1 : 0;
    for (int i = 0; i < kKept; ++i)
      if (i != other && memo[static_cast<std::size_t>(i)].used < memo[static_cast<std::size_t>(slot)].used) slot = i;
    EndMemo& m = memo[static_cast<std::size_t>(slot)];
    m.checker = id;
    m.used = ++clock;
    m.hash = h;
    m.q = q;
    m.exact_below = request.exact_below;
    m.result = result;
    return slot;
  };
  const std::uint64_t ha = hash_of(qa), hb = hash_of(qb);
  int slot_a = find(qa, ha, sa);
  const int slot_b = find(qb, hb, sb);
  if (slot_a < 0) {
    checker_.check_state(qa, sa, request);
    slot_a = keep(qa, ha, sa, slot_b);
  }
  if (slot_b < 0) {
    checker_.check_state(qb, sb, request);
    keep(qb, hb, sb, slot_a);
  }
  return run_pairs(qa, qb, sa, sb, certified_until, nullptr, &bounds, first_violation, threads, verdict_only);
}

SegmentResult SegmentChecker::check_motion_reference(const std::vector<double>& qa, const std::vector<double>& qb,
                                                     bool verdict_only, StateResult& sa, StateResult& sb) const {
  CheckRequest request = row_request();
  if (verdict_only) {
    // Ends exact up to half the segment's motion beyond the first pass's
    // limit: two ends that far clear certify the whole segment at once.
    const double m = pair_bound(qa, qb);
    request.exact_below = first_limit() + 0.5 * m;
    if (!(request.exact_below < std::numeric_limits<double>::infinity())) request.exact_below = std::numeric_limits<double>::infinity();
  }
  checker_.check_state(qa, sa, request);
  checker_.check_state(qb, sb, request);
  return run(qa, qb, sa, sb, nullptr, false, verdict_only);
}

SegmentResult SegmentChecker::run(const std::vector<double>& qa, const std::vector<double>& qb,
                                  const StateResult& sa, const StateResult& sb, const Heightfield* terrain,
                                  bool sb_on_terrain, bool verdict_only) const {
  SegmentResult out;
  out.checked = true;
  std::map<double, Sample> samples;  // by t; dyadic midpoints repeat exactly between stages
  StateSeed seed;
  StateSeed terrain_seed;  // the dug terrain's pairs, as the dig pass seeds them apart
  std::vector<double> q, q2;
  StateResult r;
  bool gave_up = false;
  verdict_only = verdict_only && !terrain;  // the dug terrain's pairs are always exact

  // One exact check of a configuration into r: the state's semantics on
  // the segment's terrain; distances exact below exact_below (verdict-only
  // samples), a certified bound beyond it.
  auto exact = [&](const std::vector<double>& at, double exact_below) {
    CheckRequest request = row_request();
    if (verdict_only) request.exact_below = exact_below;
    if (terrain) {
      checker_.check_state_without_terrain(at, r, request, &seed);
      checker_.check_terrain(at, *terrain, r, &terrain_seed);
    } else {
      checker_.check_state(at, r, request, &seed);
    }
    ++out.steps;
  };
  auto point = [&](double t, std::vector<double>& at) -> const std::vector<double>& {
    if (t == 0.0) return qa;
    if (t == 1.0) return qb;
    state_between(qa, qb, t, at);
    return at;
  };
  samples[0.0] = to_sample(0.0, sa);
  if (terrain && !sb_on_terrain) {
    // sb shows qb after its own dig; the motion meets the terrain before it.
    exact(qb, std::numeric_limits<double>::infinity());
    samples[1.0] = to_sample(1.0, r);
  } else {
    samples[1.0] = to_sample(1.0, sb);
  }

  auto sample_at = [&](double t, double exact_below) -> Sample& {
    auto it = samples.find(t);
    if (it != samples.end()) return it->second;
    exact(point(t, q), exact_below);
    return samples.emplace(t, to_sample(t, r)).first->second;
  };
  // A verdict-only sample whose bound cannot decide a step: checked again
  // exactly, so every step decides as the full check's does.
  auto make_exact = [&](Sample& s) {
    if (!s.bound) return;
    exact(point(s.t, q), std::numeric_limits<double>::infinity());
    s = to_sample(s.t, r);
  };

  // One certification pass against `target`: returns the first witness
  // found (left to right, ends first), or nothing when every sub-interval's
  // bound exceeds the target by the ends' rounding guard (the one a state's
  // margin test uses), or when the step budget runs out (gave_up); `lower`
  // gets the least certified bound. A witness lies below `limit` (and
  // touches, for contact).
  auto certify = [&](double target, double limit, bool contact, double& lower) -> std::optional<Sample> {
    auto is_witness = [&](Sample& s) {
      if (s.bound && s.d < limit) make_exact(s);
      return (contact && s.collision) || s.d < limit;
    };
    for (double t : {0.0, 1.0})
      if (is_witness(samples.at(t))) return samples.at(t);
    auto interval_bound = [&](double ta, double tb, double& m) {
      const Sample& a = samples.at(ta);
      const Sample& b = samples.at(tb);
      m = pair_bound(point(ta, q), point(tb, q2));
      return std::min({a.d, b.d, 0.5 * (a.d + b.d - m)});
    };
    auto guard = [&](double ta, double tb) { return std::max(samples.at(ta).tolerance, samples.at(tb).tolerance); };
    std::vector<std::pair<double, double>> stack{{0.0, 1.0}};
    while (!stack.empty()) {
      const auto [ta, tb] = stack.back();
      stack.pop_back();
      double m = 0.0;
      double lb = interval_bound(ta, tb, m);
      if (!(lb >= target + guard(ta, tb)) && (samples.at(ta).bound || samples.at(tb).bound)) {
        make_exact(samples.at(ta));
        make_exact(samples.at(tb));
        lb = interval_bound(ta, tb, m);
      }
      if (lb >= target + guard(ta, tb)) {
        lower = std::min(lower, lb);
        continue;
      }
      const double tm = 0.5 * (ta + tb);
      if (out.steps >= options_.max_steps || !(tm > ta && tm < tb)) {
        // Cannot be settled: a violation without a witness, never a false
        // safe. What is left unsettled is bounded as it stands.
        gave_up = true;
        stack.emplace_back(ta, tb);
        for (const auto& [ua, ub] : stack) {
          double mu = 0.0;
          const double b = interval_bound(ua, ub, mu);
          lower = std::min(lower, std::isfinite(b) ? std::max(b, 0.0) : 0.0);
        }
        return std::nullopt;
      }
      // The midpoint exact up to where it would certify either half (motion
      // bound about m / 2) beside an end that is no witness: beyond it, its
      // bound decides them; a half whose bound is larger makes it exact.
      Sample& mid = sample_at(tm, std::max(target, limit) + 0.5 * m);
      if (is_witness(mid)) return mid;
      stack.emplace_back(tm, tb);
      stack.emplace_back(ta, tm);
    }
    return std::nullopt;
  };

  two_passes(margin_, options_, gave_up, out, certify);
  for (const auto& [t, s] : samples) {
    if (s.bound || !(s.d < out.min_sampled)) continue;
    out.min_sampled = s.d;
    if (!out.clearance && !out.collision) {
      out.part_a = s.a;
      out.part_b = s.b;
    }
  }
  return out;
}

// The per-pair algorithm. The reference above bisects the whole segment
// until the largest motion of any pair is below the least distance of any
// pair: a slow part near the lander is bisected for the scoop's speed, and
// every midpoint costs a whole configuration's check. Here each checked pair
// k carries its own certificate: on a sub-interval [ta, tb] with lower
// bounds la, lb on its distance at the ends and M_k bounding how much that
// distance can change over it (MotionBound::pair_bound: its two parts'
// motion relative to each other, times the sub-interval's share of the
// segment), its distance stays at least min(la, lb, (la + lb - M_k) / 2);
// and, with a bound on the parts' relative acceleration, above the chord
// of la, lb less a parabola (piece_lower_bound: the second order, which
// certifies far longer pieces where a pair runs along the margin).
// Each pair marches along the segment on its own, left to right: a piece
// whose bound clears the target is certified; otherwise one sample (only
// that pair's two parts posed) goes where the pieces' ends stop covering it,
// placed and asked by the pair's estimated distance (see kAsk below), each
// search started from that pair's closest triangles found before on the
// segment. Halving the whole segment instead asked every pair, at the
// midpoint of every long span, for far more than its distance: the dearest
// searches, certifying nothing. The witness is the least t any pair finds.
//
// Local speeds: a pair of a moving part and a static one whose rate was
// read from the poses also knows, at each end and each sample, how fast
// the counted clusters' points move right there (the part's velocity field
// at that pose, part_transform_velocity); between two of them no faster
// than either's speed grown by the acceleration bound, so a short piece's
// rate is about the speed the part really has there, not the segment's
// fastest. Where a pair runs along the margin (short pieces, the second
// order) the OMPL bench's 1,001 default-arm edges took 115,956 -> 96,840
// pair samples, 1.444 -> 1.315 G instructions (docs/planning.md).
//
// At the ends every pair is at least its box gap and min(its state's least
// distance, end_limit): the same numbers whether the end states were checked
// fully or verdict-only, so both modes take the same steps and find the
// same witness. Samples are asked the same questions in both modes.
namespace {
// The relative tolerance of the motion checks' pair searches: at most kRel,
// at least kMinRel. 0.35 since the second order (1.0 before): a bound
// found a factor 2 below a distance often fell under the limit, and an
// exact search followed; the OMPL bench's planned segments, replayed,
// 0.25 / 0.35 / 0.5 / 0.75 / 1.0: 116 / 115 / 114-127 / 119-121 / 125-131
// us (default arm), 41 / 40-43 / 39-44 / 42-43 / 44-45 us (URDF arm).
// 0.1 since samples take what a search proved on its way
// (PairAnswer::beyond): a search that finds something within a tighter
// factor proves more where it is. Instructions an edge (callgrind, the
// same edges on one thread), kRel 0.5 / 0.35 / 0.25 / 0.2 / 0.15 / 0.1 /
// 0.05 / 0.03: 0.888 / 0.846 / 0.818 / 0.812 / 0.806 / 0.802 / 0.809 /
// 0.817 M (default arm), 0.436 / 0.416 / 0.402 / 0.394 / 0.375 / 0.354 /
// 0.345 / 0.342 M (URDF arm); times, four alternating runs: 98-104 ->
// 84-99 us (default arm), 46-57 -> 41-48 us (URDF arm).
constexpr double kRel = 0.1;
constexpr double kMinRel = 0.01;
// A sample asks for kAsk of the way from the target to the pair's estimated
// distance, searched up to kCap of it (kRel at most). Estimates: at an end,
// its lower bound (the state's least distance or the pair's box gap; asking
// beyond it finds something and costs most); where a search found
// something, that distance; where it found nothing, twice what it searched.
// 0.35 since the second order (0.5 before; a step grows only with the
// square root of what a sample is asked there): the OMPL bench's planned
// segments, replayed, 0.3 / 0.35 / 0.4 / 0.45 / 0.5 / 0.6: 104-106 /
// 98-105 / 100-108 / 103-109 / 114-125 / 135-138 us (default arm),
// 39-40 / 37-40 / 37-40 / 38-40 / 39-42 / 40-41 us (URDF arm).
constexpr double kAsk = 0.35;
constexpr double kCap = 0.85;
constexpr double kGrow = 2.0;
// A gap that samples placed by the estimate would need more than kProbe of
// is probed in its middle first, asked only what the estimate allows: a
// pair on its way into a violation meets it there (as halving would) rather
// than creeping towards it in ever shorter steps.
constexpr double kProbe = 4.0;
// A pair whose motion bound exceeds kTight times the room its ends leave
// reads its rate from the poses (PoseRates) before it marches. On the OMPL
// bench's planned segments 1, 2 and 4 gave the same times within the
// noise; on the ten default plans 2 leaves most of their short segments on
// the bounds alone (docs/planning.md).
constexpr double kTight = 2.0;
}  // namespace

SegmentResult SegmentChecker::run_pairs(const std::vector<double>& qa, const std::vector<double>& qb,
                                        const StateResult& sa, const StateResult& sb,
                                        double* certified_until, const Heightfield* terrain,
                                        const std::vector<double>* given_bounds, bool first_violation,
                                        int threads, bool verdict_only) const {
  SegmentResult out;
  double until = 0.0;
  out.checked = true;
  const std::size_t np = pairs_.size();
  // What a segment needs, kept per thread and reused: allocated anew for
  // every segment (about eleven blocks), verify --continuous on two
  // threads spent more time in the one malloc arena's lock (src/cli/main.cpp
  // keeps one) than on one thread: the ten plans' continuous pass 0.025 s
  // on 2 threads against 0.020 s on 1.
  struct Workspace {
    std::vector<double> own_bounds, gap, guard, q;
    PosedParts posed;
    PoseRates::Storage rates;
    SweptClusters swept;
    // Local speeds: the parameters' rates (qb - qa), each moving part's
    // cluster spheres (BoxMotion::spheres) and its velocity field at the
    // two ends, computed when a pair first asks.
    std::vector<double> dq;
    std::vector<std::vector<BoxMotion::Sphere>> spheres;
    std::vector<char> spheres_known;
    struct EndMove {
      bool known = false, ok = false;
      Affine pose;
      Vec3 w, u;
    };
    std::vector<EndMove> end_move;  // per part: [2 part] at qa, [2 part + 1] at qb
    PosedParts end_posed;
  };
  thread_local Workspace ws;
  std::vector<double>& own_bounds = ws.own_bounds;
  if (!given_bounds) bound_.pair_bounds(plan_, qa, qb, own_bounds);
  const std::vector<double>& bounds = given_bounds ? *given_bounds : own_bounds;
  const double e_limit = end_limit(bounds);
  // Per pair: how much its distance can change per unit of t (padded for
  // the product with a sub-interval's length), its ends' box gaps and
  // guards, and its closest triangles found so far.
  struct PairData {
    double rate = 0.0;
    // With a rate from the moving part's clusters near the other part only
    // (PoseRates): a lower bound, above the first pass's target, of the
    // distance of the clusters left out, over the whole segment.
    double far = std::numeric_limits<double>::infinity();
    double gap_a = 0.0, gap_b = 0.0, guard_a = kDistanceTolerance, guard_b = kDistanceTolerance;
    // Its parts' relative acceleration per unit of t squared (at most twice
    // the turning times the rate: SegmentChecker::turning), for the second
    // order of piece_lower_bound; +infinity: first order only.
    double accel = std::numeric_limits<double>::infinity();
    // Proven by SweptClusters over the whole segment (a moving part far
    // from a static one): a lower bound of its distance, at least what the
    // first piece asks; -infinity: none.
    double clear = -std::numeric_limits<double>::infinity();
    // Local speeds (PoseRates::Rate::moving, counted): at each sample, the
    // counted clusters' fastest point's speed there, from the moving
    // part's velocity field; -1: none (the rate alone).
    int moving = -1;
    std::uint64_t counted = 0;
    double s_a = 0.0, s_b = 0.0;  // the speeds at the ends (the rate without local speeds)
    bool live = false;  // checked at all (not an empty part, not a missing terrain)
    bool seeded = false;
    std::uint32_t slot_a = 0, slot_b = 0;
  };
  thread_local std::vector<PairData> pd_kept;
  pd_kept.assign(np, PairData{});
  std::vector<PairData>& pd = pd_kept;
  PosedParts& posed = ws.posed;
  posed.terrain = terrain;
  std::vector<double>& gap = ws.gap;
  std::vector<double>& guard = ws.guard;
  checker_.pose_parts(qa, posed);
  checker_.pair_gaps(posed, gap, guard);  // pair_distance's answers to need 0, all at once
  for (std::size_t k = 0; k < np; ++k) {
    pd[k].gap_a = gap[k];
    pd[k].guard_a = guard[k];
    pd[k].live = gap[k] != std::numeric_limits<double>::infinity();  // NaN stays live
  }
  checker_.pose_parts(qb, posed);
  checker_.pair_gaps(posed, gap, guard);
  for (std::size_t k = 0; k < np; ++k) {
    pd[k].gap_b = gap[k];
    pd[k].guard_b = guard[k];
    pd[k].live = pd[k].live || gap[k] != std::numeric_limits<double>::infinity();
    pd[k].rate = bounds[k] * (1.0 + 1e-12);
  }
  std::vector<double>& q = ws.q;
  auto point = [&](double t, std::vector<double>& buf) -> const std::vector<double>& {
    if (t == 0.0) return qa;
    if (t == 1.0) return qb;
    state_between(qa, qb, t, buf);
    return buf;
  };
  auto note_sample = [&](double d, int a, int b) {
    if (d < out.min_sampled) {
      out.min_sampled = d;
      out.part_a = a;
      out.part_b = b;
    }
  };
  // The end states as samples; a verdict-only bound below a limit (never,
  // as end_limit lies above both limits) would be made exact.
  StateResult exact_end;
  auto end_sample = [&](double t, const StateResult& st) {
    Sample smp = to_sample(t, st);
    if (smp.bound && !(smp.d >= first_limit())) {
      checker_.check_state(point(t, q), exact_end, row_request());  // (never with a dug terrain: ends exact)
      smp = to_sample(t, exact_end);
    }
    return smp;
  };
  const Sample end0 = end_sample(0.0, sa), end1 = end_sample(1.0, sb);
  for (const Sample* e : {&end0, &end1})
    if (!e->bound) note_sample(e->d, e->a, e->b);
  const double floor_a = std::min(end0.d, e_limit), floor_b = std::min(end1.d, e_limit);
  // A moving part's pair with a static mesh that its ends do not certify
  // is first tried whole by SweptClusters (no search; most such pairs pass
  // far apart). Else a pair whose bound would leave it sampling more than
  // a few times (kTight: its motion bound beyond that many times the room
  // its ends leave above the first pass's target) marches at the rate read
  // from the poses themselves (PoseRates) when that is lower: fewer
  // samples for the same certificate. Decided per pair from its own data,
  // so on any number of threads; e_limit and the ends' floors stay the
  // bounds'.
  {
    const double target = margin_ > 0.0 ? margin_ : 0.0;
    PoseRates poses(*this, qa, qb, posed, ws.rates, &ws.swept);
    ws.swept.start(checker_, qa, qb, !verdict_only);
    for (std::size_t k = 0; k < np; ++k) {
      PairData& p = pd[k];
      const double va = std::max(p.gap_a, floor_a), vb = std::max(p.gap_b, floor_b);
      const double guard = std::max(p.guard_a, p.guard_b);
      const double room = va + vb - 2.0 * (target + guard);
      if (!p.live || p.rate <= room) continue;  // the ends certify it (first order)
      if (const auto [moving, other] = swept_[k]; moving >= 0) {
        const auto& box = posed.box[static_cast<std::size_t>(other)];  // a static part's, as at either end
        p.clear = ws.swept.clear(moving, box.first, box.second, target + guard);
        if (p.clear >= target + guard) continue;
      }
      if (p.rate <= kTight * room) continue;
      // Clusters left out must stay a micrometre clear of what any piece
      // asks (target plus its guard), so that they never hold up a piece.
      const PoseRates::Rate r = poses.of(k, target + 4.0 * guard + 1e-6);
      if (r.rate * (1.0 + 1e-12) < p.rate) {
        p.rate = r.rate * (1.0 + 1e-12);
        p.far = r.far;
        p.counted = r.counted;
      } else if (r.counted) {
        p.counted = ~std::uint64_t{0};  // the pair's own bound: every point
      }
      if (p.counted && r.moving >= 0) p.moving = r.moving;
    }
  }

  // Each pair's relative acceleration, from its final rate (a rate read from
  // the poses bounds the speed of the clusters it counts, and those
  // clusters' accelerations are bounded by the same turning).
  {
    const double turn = turning(qa, qb);
    for (PairData& p : pd) {
      const double accel = 2.0 * turn * p.rate * (1.0 + 1e-12);
      p.accel = accel >= 0.0 ? accel : std::numeric_limits<double>::infinity();
    }
  }

  // One pair's samples on the segment: a lower bound v on its distance at t,
  // that bound's guard g, and e, an estimate of its distance near t (where
  // the next sample is placed; never a bound).
  // s: a bound, at most the pair's rate, of the speed of every point its
  // rate counts, at t itself (the rate where there are no local speeds).
  struct Point {
    double t, v, g, e, s;
  };
  // Local speeds. A point of the pair's counted clusters moves at most at
  // speed s (a Point's) at t and accelerates by at most accel (per unit of
  // t squared: SegmentChecker::turning), so on a piece [x.t, y.t] of
  // length l at most at min(x.s + accel (t - x.t), y.s + accel (y.t - t)),
  // never more than (x.s + y.s + accel l) / 2: the piece's rate in both
  // orders of piece_lower_bound (its points' speed bound over the piece).
  auto piece_rate = [](const PairData& p, double xs, double ys, double l) {
    if (p.moving < 0) return p.rate;
    const double s = 0.5 * (xs + ys + p.accel * l) * (1.0 + 1e-12);
    return s < p.rate ? s : p.rate;  // NaN (an infinite accel times 0): the rate
  };
  // The counted clusters' fastest point's speed with the moving part posed
  // at `pose` and moving by (w, u): at most |w x c + u| + |w| r for a
  // cluster sphere (c posed, r), padded for the rounding of its terms.
  // (The workspace's vectors bound here, on this thread: the marches on
  // other threads read them, filled before, never written.)
  std::vector<double>& dq = ws.dq;
  dq.resize(qa.size());
  for (std::size_t i = 0; i < qa.size(); ++i) dq[i] = qb[i] - qa[i];
  std::vector<std::vector<BoxMotion::Sphere>>& spheres = ws.spheres;
  std::vector<char>& spheres_known = ws.spheres_known;
  spheres.resize(checker_.part_count());
  spheres_known.assign(checker_.part_count(), 0);
  auto speed = [&](const PairData& p, const Affine& pose, const Vec3& w, const Vec3& u) {
    const std::vector<BoxMotion::Sphere>& sp = spheres[static_cast<std::size_t>(p.moving)];
    // In the part's own frame: the point posed at pose * x moves at
    // R (wl x x + ul), R the pose's rotation, wl = R^T w and ul = R^T (w x
    // t + u) (t its translation): the same speeds, no centre posed.
    const Mat3 rt = pose.linear().transpose();
    const Vec3 wl = rt * w, ul = rt * (w.cross(pose.translation()) + u);
    const double wn = wl.norm();
    double best = 0.0, size2 = 0.0, rmax = 0.0;
    for (std::size_t i = 0; i < sp.size() && i < 64; ++i) {
      if (!(p.counted >> i & 1)) continue;
      best = std::max(best, (wl.cross(sp[i].centre) + ul).norm() + wn * sp[i].radius);
      size2 = std::max(size2, sp[i].centre.squaredNorm());
      rmax = std::max(rmax, sp[i].radius);
    }
    // Padded for the rounding of the frame change (R orthonormal within
    // rounding) and of the sums.
    const double s = best * (1.0 + 1e-9) + 1e-9 * (wn * (std::sqrt(size2) + rmax) + ul.norm()) + 1e-300;
    return s < p.rate ? s : p.rate;  // NaN: the rate
  };
  // Each pair's speeds at the ends (serially, before any march).
  auto& end_move = ws.end_move;
  end_move.resize(2 * checker_.part_count());
  for (auto& e : end_move) e.known = false;
  PosedParts& end_posed = ws.end_posed;
  auto end_speed = [&](const PairData& p, int end) {
    if (p.moving < 0) return p.rate;
    const std::size_t x = static_cast<std::size_t>(p.moving);
    if (!spheres_known[x]) {
      spheres_known[x] = 1;
      checker_.box_motion().spheres(p.moving, spheres[x]);
    }
    auto& e = end_move[2 * x + static_cast<std::size_t>(end)];
    if (!e.known) {
      e.known = true;
      const int one = p.moving;
      e.ok = checker_.pose_parts_moving(end == 0 ? qa : qb, end_posed, std::span<const int>(&one, 1), p.moving, dq,
                                        e.w, e.u);
      if (e.ok) e.pose = *end_posed.pose[static_cast<std::size_t>(p.moving)];
    }
    return e.ok ? speed(p, e.pose, e.w, e.u) : p.rate;
  };
  for (PairData& p : pd) {
    p.s_a = end_speed(p, 0);
    p.s_b = end_speed(p, 1);
  }
  bool gave_up = false;

  struct Witness {
    double t;
    int a, b;
  };
  // Where the first pass's certificate from t = 0 stops: the least prefix
  // any pair certified before its witness, or before the budget ran out (0
  // at a witness at an end).
  double reached = 0.0;
  bool first_pass = true;
  // A piece's bound; the second order only where the first falls short of
  // `enough` (most pieces are certified by their first order at once, and
  // the second order's divisions cost more than the rest of the test).
  auto piece_bound = [&](const Point& x, const Point& y, const PairData& p, double enough) {
    const double rate = piece_rate(p, x.s, y.s, y.t - x.t);
    const double first = std::min({x.v, y.v, 0.5 * (x.v + y.v - rate * (y.t - x.t))});
    if (!(first < enough) || p.clear >= enough) return std::max(std::min(first, p.far), p.clear);
    return std::max(std::min(piece_lower_bound(x.t, x.v, y.t, y.v, rate, p.accel), p.far), p.clear);
  };
  constexpr double kAll = std::numeric_limits<double>::infinity();
  // What one pair's march needs of its own (one per thread when pairs march
  // in parallel).
  struct Scratch {
    std::vector<Point> rights;  // the pair's samples right of the certified prefix, nearest last
    PosedParts posed;           // only the pair's two parts posed at each sample
    PairAnswer answer;
    std::vector<double> q;
    std::vector<int> two = std::vector<int>(2);
  };
  // What one pair's march over one pass found.
  struct March {
    double lower = std::numeric_limits<double>::infinity();  // its least certified piece bound
    std::size_t steps = 0;
    double min_d = std::numeric_limits<double>::infinity();  // its least exact distance sampled (the first such)
    int min_a = -1, min_b = -1;
    bool witness = false;
    double t = 0.0;      // the witness's
    double until = 1.0;  // where its certificate stopped before the witness
    bool budget = false;  // stopped where may_sample said no (or t could not be split): cur and rights as they stand
    Point cur{};
  };
  thread_local Scratch serial_kept;
  Scratch& serial = serial_kept;
  serial.posed.terrain = terrain;
  // Pair k's march against `target` (the piece bounds must clear it), no
  // further than `stop`: each piece whose bound clears the target is
  // certified; otherwise one sample goes where the pieces' ends stop
  // covering it, unless may_sample(steps so far) says no.
  auto march = [&](std::size_t k, double target, double limit, double stop, Scratch& s, March& m,
                   auto&& may_sample) {
    PairData& p = pd[k];
    const int a = pairs_[k].first, b = pairs_[k].second;  // (not a binding: the lambdas below capture them)
    const double va = std::max(p.gap_a, floor_a), vb = std::max(p.gap_b, floor_b);
    Point& cur = m.cur;
    cur = Point{0.0, va, p.guard_a, va, p.s_a};
    std::vector<Point>& rights = s.rights;
    // The piece [cur, r] certified: its bound taken and cur moved to r.
    auto take = [&](const Point& r) {
      const double g = std::max(cur.g, r.g);
      const double lb = piece_bound(cur, r, p, target + g);
      if (!(lb >= target + g)) return false;
      m.lower = std::min(m.lower, lb);
      cur = r;
      return true;
    };
    // Most pairs: the whole segment certified by its ends at once (the
    // loop's first step, without its set-up).
    if (cur.t < stop && take(Point{1.0, vb, p.guard_b, vb, p.s_b})) {
      rights.clear();
      return;
    }
    rights.assign(1, Point{1.0, vb, p.guard_b, vb, p.s_b});
    while (!rights.empty() && cur.t < stop) {
      const Point& r = rights.back();
      if (take(r)) {
        rights.pop_back();
        continue;
      }
      const double g = std::max(cur.g, r.g);
      // Where the piece is not covered: each end's bound certifies the
      // pair for (v - target) / rate either side of it. One sample in the
      // middle of that gap when the pair's estimated distance would cover
      // it; else one that covers only what that estimate allows from the
      // left, so that its search is likely to prove what it is asked (a
      // search asked beyond the pair's distance costs most and certifies
      // nothing; halving spans asks that on every long one).
      const double T = target + g;
      // The pieces' rate: the whole span's here (a sample splits it into
      // pieces whose rates are at most about this; placement, not proof).
      const double rate = piece_rate(p, cur.s, r.s, r.t - cur.t);
      const double ra = std::max(0.0, (cur.v - T) / rate), rb = std::max(0.0, (r.v - T) / rate);
      const double gap_lo = cur.t + ra, gap_hi = r.t - rb;
      const double est = std::min(cur.e, r.e);
      const double x_est = T + kAsk * (est - T);
      // Second order (piece_lower_bound): a piece of length l whose two
      // ends are at least v clears T when v - curve(l) l^2 / 8 does, where
      // curve(l) = rate^2 / (its first-order bound) + accel; the first-order
      // bound from ends at v is about v - rate l / 2.
      auto curve = [&](double v, double l) {
        const double first = v - 0.5 * rate * l;
        return first > 0.0 ? rate * rate / first + p.accel : std::numeric_limits<double>::infinity();
      };
      // The longest piece from cur that a sample at x_est would certify so
      // (two rounds from l = 0; 0 when there is no second order). The OMPL
      // bench's planned segments, replayed: 0.6, 0.8, 0.9, 1.3 and 1.6 of
      // it took 1-45% more time (default arm) and up to 16% (URDF arm).
      double reach2 = 0.0;
      {
        const double v = std::min(cur.v, x_est);
        if (v > T && p.accel < std::numeric_limits<double>::infinity()) {
          double l = 0.0;
          for (int round = 0; round < 2; ++round) l = std::sqrt(8.0 * (v - T) / curve(v, l));
          reach2 = l;
        }
      }
      double tm = 0.5 * (gap_lo + gap_hi);
      bool probe = false;
      if (T + 0.5 * rate * (gap_hi - gap_lo) > x_est && cur.t + reach2 < tm) {
        if (rate * (gap_hi - gap_lo) > kProbe * std::max(2.0 * (x_est - T), rate * reach2))
          probe = true;
        else
          tm = std::min(tm, std::max(gap_lo + (x_est - T) / rate, cur.t + reach2));
      }
      if (!(tm > cur.t && tm < r.t)) tm = 0.5 * (cur.t + r.t);
      if (!may_sample(m.steps) || !(tm > cur.t && tm < r.t)) {
        m.budget = true;
        return;
      }
      ++m.steps;
      // The pair posed there, with its moving part's speed where it has
      // local speeds.
      const std::vector<double>& at = point(tm, s.q);
      s.two[0] = a;
      s.two[1] = b;
      double sm = p.rate;
      if (p.moving >= 0) {
        Vec3 w, u;
        if (checker_.pose_parts_moving(at, s.posed, s.two, p.moving, dq, w, u))
          sm = speed(p, *s.posed.pose[static_cast<std::size_t>(p.moving)], w, u);
      } else {
        checker_.pose_parts(at, s.posed, s.two);
      }
      // Its bound must certify [cur, tm] (the slack covers what
      // pair_distance takes off a bound it proves); one in the gap's
      // middle, [tm, r] too.
      // (either order: the second where its v - T covers the piece's curve;
      // each at the rate of the piece the sample ends, its speed there now
      // known).
      auto needed = [&](double v, double sv, double l) {
        const double pr = piece_rate(p, sv, sm, l);
        const double first = 2.0 * T + pr * l - v;
        const double f = v - 0.5 * pr * l;
        const double second = f > 0.0 ? T + (pr * pr / f + p.accel) * l * l / 8.0 : first;
        return second <= v ? std::min(first, second) : first;
      };
      double need = std::max(limit, needed(cur.v, cur.s, tm - cur.t));
      if (tm - gap_lo >= 0.5 * (gap_hi - gap_lo)) need = std::max(need, needed(r.v, r.s, r.t - tm));
      if (probe) need = std::max(limit, x_est);
      need += 2.0 * (g + kDistanceTieTolerance) + 1e-12 * std::abs(need);
      // Searched within a factor of the need up to a little short of the
      // estimate, so that a pair as far as estimated is proven at once.
      const double cap = T + kCap * (est - T);
      const double rel = std::clamp(cap / need - 1.0, kMinRel, kRel);
      // Proven apart here by either neighbour: no collision test needed.
      const double apart = std::max(cur.v - piece_rate(p, cur.s, sm, tm - cur.t) * (tm - cur.t),
                                    r.v - piece_rate(p, sm, r.s, r.t - tm) * (r.t - tm)) - g;
      auto note = [&](double d) {
        if (d < m.min_d) {
          m.min_d = d;
          m.min_a = a;
          m.min_b = b;
        }
      };
      if (!(apart > 0.0) && checker_.pair_collides(s.posed, k)) {
        note(0.0);
        m.witness = true;
        m.t = tm;
        m.until = cur.t;
        return;
      }
      PairAnswer& answer = s.answer;
      answer = PairAnswer{};
      answer.seeded = p.seeded;
      answer.slot_a = p.slot_a;
      answer.slot_b = p.slot_b;
      if (cap / need - 1.0 < kMinRel) {
        // The pair runs along the target (its estimate within kMinRel of
        // the need): searched exactly below need (1 + kMinRel) at once.
        // Searched within the factor first, a distance found near the
        // estimate leaves a bound below the limit, and the exact search
        // below followed anyway. The OMPL bench's 1,001 planned segments
        // of the default arm: 199 -> 164 us a segment (medians of three
        // runs; the URDF arm's the same, 69 us: docs/planning.md).
        checker_.pair_distance(s.posed, k, need * (1.0 + kMinRel), answer, false, 0.0, true);
      } else {
        checker_.pair_distance(s.posed, k, need * (1.0 + rel), answer, false, rel, true);
        if (answer.distance < limit) {
          // Something within the factor of the limit was found (a bound
          // proven from nothing found lies above it): exact, below it,
          // from the triangles it found.
          checker_.pair_distance(s.posed, k, answer.upper * (1.0 + 1e-12) + 1e-15, answer);
        }
      }
      if (answer.seeded) {
        p.seeded = true;
        p.slot_a = answer.slot_a;
        p.slot_b = answer.slot_b;
      }
      if (answer.exact) {
        note(answer.distance);
        if (answer.distance < limit) {
          m.witness = true;
          m.t = tm;
          m.until = cur.t;
          return;
        }
      }
      // Found something: the pair is about that far here; nothing found:
      // perhaps much farther, and at least what the search proved on its
      // way (PairAnswer::beyond, often far beyond the need: on the OMPL
      // bench's default-arm edges over 95% of the samples find nothing,
      // and the scoop's against LegD lie 3-10x farther than asked at most
      // of them; taking it as the sample's bound, instructions per edge
      // -16%, URDF arm -6%).
      const double e = answer.upper < std::numeric_limits<double>::infinity() ? answer.upper
                                                                               : std::max(kGrow * need * (1.0 + rel), answer.beyond);
      rights.push_back(Point{tm, answer.beyond, answer.guard, e, sm});
    }
  };
  // One pass against `target` (as the reference's certify): the witness of
  // least t found, or nothing when every pair is certified on the whole
  // segment (or the budget ran out: gave_up); `lower` gets the least bound.
  // Pairs [0, reused_count) of the first pass as a parallel attempt
  // marched them, which the serial pass would have marched the same way
  // (certify_parallel says when).
  std::vector<March> reused;
  std::size_t reused_count = 0;
  auto certify = [&](double target, double limit, bool contact, double& lower) -> std::optional<Witness> {
    const std::size_t reuse = reused_count;
    reused_count = 0;
    for (const Sample* e : {&end0, &end1})
      if ((contact && e->collision) || e->d < limit) return Witness{e->t, e->a, e->b};
    std::optional<Witness> best;
    double until_here = 1.0;
    for (std::size_t k = 0; k < np; ++k) {
      if (!pd[k].live) continue;
      const auto [a, b] = pairs_[k];
      // A pair marches no further than the least witness found so far.
      March m;
      if (k < reuse)
        m = reused[k];
      else
        march(k, target, limit, best ? best->t : 2.0, serial, m,
              [&](std::size_t local) { return out.steps + local < options_.max_steps; });
      out.steps += m.steps;
      lower = std::min(lower, m.lower);
      note_sample(m.min_d, m.min_a, m.min_b);
      if (m.budget) {
        // Cannot be settled: a violation without a witness, never a false
        // safe; what is left unsettled is bounded as it stands.
        gave_up = true;
        auto settle = [&](double l) { lower = std::min(lower, std::isfinite(l) ? std::max(l, 0.0) : 0.0); };
        Point cur = m.cur;
        const std::vector<Point>& rights = serial.rights;
        for (std::size_t i = rights.size(); i-- > 0;) {
          settle(piece_bound(cur, rights[i], pd[k], kAll));
          cur = rights[i];
        }
        until_here = std::min(until_here, rights.empty() ? cur.t : 0.0);
        for (std::size_t j = k + 1; j < np; ++j) {
          if (!pd[j].live) continue;
          const Point x{0.0, std::max(pd[j].gap_a, floor_a), pd[j].guard_a, 0.0, pd[j].s_a};
          const Point y{1.0, std::max(pd[j].gap_b, floor_b), pd[j].guard_b, 0.0, pd[j].s_b};
          const double l = piece_bound(x, y, pd[j], kAll);
          settle(l);
          if (!(l >= target + std::max(x.g, y.g))) until_here = 0.0;
        }
        if (first_pass) reached = std::min(until_here, best ? best->t : 1.0);
        return best;
      }
      if (m.witness) {
        if (!best || m.t < best->t) best = Witness{m.t, a, b};
        until_here = std::min(until_here, m.until);
      }
    }
    if (first_pass) reached = best ? std::min(until_here, best->t) : 1.0;
    return best;
  };
  // The first pass with the pairs marching on `threads` threads: every pair
  // marches the whole segment (no witness is known to stop at), as the
  // serial pass does when it finds none. Taken only when no pair finds a
  // witness and all the samples stay within the budget: then the serial
  // pass would have taken exactly these samples (each pair's march reads
  // only its own data), and the bound (a minimum), the step count (a sum)
  // and the least distance sampled (merged in pair order) are its, bit for
  // bit. Otherwise the pairs' seeds are put back and the serial pass runs:
  // the answer never depends on the threads.
  auto certify_parallel = [&](double target, double limit, bool contact, double& lower) -> bool {
    for (const Sample* e : {&end0, &end1})
      if ((contact && e->collision) || e->d < limit) return false;
    // The pairs to sample (the others are certified by their ends at
    // once, here): worth it only with options_.parallel_pairs or more.
    std::vector<std::size_t> sampled;
    for (std::size_t k = 0; k < np; ++k) {
      const PairData& p = pd[k];
      if (!p.live) continue;
      const Point x{0.0, std::max(p.gap_a, floor_a), p.guard_a, 0.0, p.s_a};
      const Point y{1.0, std::max(p.gap_b, floor_b), p.guard_b, 0.0, p.s_b};
      if (!(piece_bound(x, y, p, target + std::max(x.g, y.g)) >= target + std::max(x.g, y.g))) sampled.push_back(k);
    }
    if (sampled.size() < std::max<std::size_t>(2, options_.parallel_pairs)) return false;
    const std::vector<PairData> kept = pd;
    std::vector<March> marches(np);
    std::vector<char> marched(np, 0);
    std::atomic<bool> stop{false};
    std::atomic<std::size_t> total{0};
    const int workers = threads > 0 ? threads : hardware_threads();
    std::vector<Scratch> scratch(static_cast<std::size_t>(std::max(workers, 1)));
    for (Scratch& s : scratch) s.posed.terrain = terrain;
    parallel_for(sampled.size(), workers, 1, [&](std::size_t begin, std::size_t end, int slot) {
      Scratch& s = scratch[static_cast<std::size_t>(slot)];
      for (std::size_t i = begin; i < end; ++i) {
        const std::size_t k = sampled[i];
        if (stop.load(std::memory_order_relaxed)) continue;
        March& m = marches[k];
        march(k, target, limit, 2.0, s, m, [&](std::size_t local) {
          return !stop.load(std::memory_order_relaxed) &&
                 total.load(std::memory_order_relaxed) + local < options_.max_steps;
        });
        marched[k] = 1;
        total.fetch_add(m.steps, std::memory_order_relaxed);
        if (m.witness || m.budget) stop.store(true, std::memory_order_relaxed);
      }
    });
    // The rest: one piece each, certified (no sample), here.
    {
      std::size_t next = 0;
      for (std::size_t k = 0; k < np; ++k) {
        if (next < sampled.size() && sampled[next] == k) {
          ++next;
          continue;
        }
        if (pd[k].live) march(k, target, limit, 2.0, serial, marches[k], [](std::size_t) { return false; });
        marched[k] = 1;
      }
    }
    // The serial pass marches pair k with no witness to stop at while no
    // pair before it found one: as here. So the pairs up to the first that
    // found a witness (it included), all marched to their end here and
    // within the budget as the serial pass counts it, are the serial
    // pass's; it takes them and goes on from there (the later pairs' seeds
    // put back). All of them, none with a witness: the pass is done.
    std::size_t prefix = 0, running = out.steps;
    bool witness = false;
    for (; prefix < np && !witness; ++prefix) {
      const March& m = marches[prefix];
      if (!pd[prefix].live) continue;
      if (!marched[prefix] || m.budget || !(running + m.steps < options_.max_steps)) break;
      running += m.steps;
      witness = m.witness;
    }
    if (prefix < np || witness) {
      for (std::size_t k = prefix; k < np; ++k) pd[k] = kept[k];
      reused = std::move(marches);
      reused_count = prefix;
      return false;
    }
    for (std::size_t k = 0; k < np; ++k) {
      out.steps += marches[k].steps;
      lower = std::min(lower, marches[k].lower);
      note_sample(marches[k].min_d, marches[k].min_a, marches[k].min_b);
    }
    reached = 1.0;
    return true;
  };

  two_passes(margin_, options_, gave_up, out, [&](double target, double limit, bool contact, double& lower) {
    if (first_pass && threads != 1 && certify_parallel(target, limit, contact, lower)) {
      until = 1.0;
      first_pass = false;
      return std::optional<Witness>{};
    }
    const std::optional<Witness> w = certify(target, limit, contact, lower);
    if (first_pass) until = w || gave_up ? reached : 1.0;
    first_pass = false;
    return w;
  }, first_violation);
  if (certified_until) *certified_until = until;
  return out;
}

void verify_segments(const Checker& checker, const Scene& scene, const std::vector<Plan>& plans,
                     std::vector<PlanResult>& results, const ContinuousOptions& options) {
  const SegmentChecker segments(checker, scene, options);
  std::vector<std::pair<std::size_t, std::size_t>> items;  // (plan, segment)
  // Plans whose states saw the dug terrain: their segments see it too.
  std::vector<char> dug(plans.size(), 0);
  bool any_dug = false;
  for (std::size_t p = 0; p < plans.size(); ++p) {
    results[p].segments.assign(plans[p].states.size(), SegmentResult{});
    dug[p] = checker.terrain_is_dug() && results[p].dig.has_value();
    any_dug = any_dug || dug[p];
    if (dug[p]) continue;
    for (std::size_t s = 0; s + 1 < plans[p].states.size(); ++s) items.emplace_back(p, s);
  }
  // Segments are independent and each writes only its own slot; a segment's
  // result depends on nothing but its two states (and the terrain it is
  // checked against), so not on the thread count.
  parallel_for(items.size(), options.threads, 1, [&](std::size_t begin, std::size_t end, int) {
    for (std::size_t i = begin; i < end; ++i) {
      const auto [p, s] = items[i];
      const auto& st = plans[p].states;
      results[p].segments[s] = segments.check(st[s], st[s + 1], results[p].states[s], results[p].states[s + 1]);
    }
  });

  if (any_dug) {
    // The dig pass again, in its order: segment s waits in its plan's
    // pending list from state s on, while the field shows the terrain dug
    // through s, and is checked (with the other waiting segments, in
    // parallel) before a later state's dig changes the field, or at the end.
    // No snapshot is kept: one field per plan being walked.
    std::vector<std::vector<std::size_t>> pending(plans.size());
    std::vector<const Heightfield*> fields(plans.size(), nullptr);
    auto flush = [&](std::size_t p, bool last_changed) {
      auto& list = pending[p];
      if (list.empty()) return;
      const auto& st = plans[p].states;
      parallel_for(list.size(), options.threads, 1, [&](std::size_t begin, std::size_t end, int) {
        for (std::size_t i = begin; i < end; ++i) {
          const std::size_t s = list[i];
          // Only the newest waiting segment's end state dug since (the one
          // changing the field now); every other's end saw this field.
          const bool sb_on_terrain = !(last_changed && i + 1 == list.size());
          results[p].segments[s] = segments.check(st[s], st[s + 1], results[p].states[s],
                                                  results[p].states[s + 1], fields[p], sb_on_terrain);
        }
      });
      list.clear();
    };
    DigWalk walk;
    walk.before_refit = [&](std::size_t p, std::size_t, const SampleRect& changed) {
      if (dug[p] && !changed.empty()) flush(p, true);
    };
    walk.after_state = [&](std::size_t p, std::size_t s, Heightfield* field) {
      fields[p] = field;
      if (dug[p] && field && s + 1 < plans[p].states.size()) pending[p].push_back(s);
    };
    walk.after_plan = [&](std::size_t p, DigSummary, std::vector<DigStep>&) { flush(p, false); };
    walk.volumes = false;  // the terrains only: the states' volumes are verify_plans'
    dig_along_plans(*checker.digger(), checker.terrain(), plans, options.dig_carry, options.threads, walk);
  }

  for (PlanResult& r : results) {
    for (std::size_t s = 0; s < r.segments.size(); ++s) {
      const SegmentResult& g = r.segments[s];
      if (!g.collision && !g.clearance) continue;
      // State s's own violation comes first; segment s comes before state s + 1.
      if (!r.first_violation || r.first_violation->state > s) {
        Violation v;
        v.state = s;
        v.kind = g.collision ? Verdict::kCollision : Verdict::kClearance;
        v.part_a = g.part_a;
        v.part_b = g.part_b;
        v.between = true;
        r.first_violation = v;
        r.verdict = v.kind;
      }
      break;
    }
  }
}

}  // namespace plancheck
