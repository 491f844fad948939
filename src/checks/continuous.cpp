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
#include "src/checks/regolith.h"
#include "src/scene/plan.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>

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

}  // namespace

SegmentChecker::SegmentChecker(const Checker& checker, const Scene& scene, const ContinuousOptions& options)
    : checker_(checker), bound_(scene), pairs_(checker.pairs()), margin_(scene.safety_margin), options_(options) {
  for (const auto& [a, b] : pairs_)
    for (int p : {a, b})
      if (static_cast<std::size_t>(p) < scene.parts.size() && scene.parts[static_cast<std::size_t>(p)].moving() &&
          std::find(moving_.begin(), moving_.end(), p) == moving_.end())
        moving_.push_back(p);
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
  return run(qa, qb, sa, sb, terrain, sb_on_terrain, false);
}

double SegmentChecker::first_limit() const {
  return margin_ > 0.0 ? margin_ + options_.tolerance : options_.contact_tolerance;
}

SegmentResult SegmentChecker::check_motion(const std::vector<double>& qa, const std::vector<double>& qb,
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

  std::optional<Sample> witness;
  double lower = std::numeric_limits<double>::infinity();
  bool check_contact = true;
  if (margin_ > 0.0) {
    witness = certify(margin_, margin_ + options_.tolerance, false, lower);
    check_contact = witness.has_value();
    if (witness) {
      out.clearance = true;
      out.witness_t = witness->t;
      out.part_a = witness->a;
      out.part_b = witness->b;
    }
  }
  if (check_contact && !gave_up) {
    // Touching anywhere on the segment, or within contact_tolerance of it?
    lower = std::numeric_limits<double>::infinity();
    const auto contact = certify(0.0, options_.contact_tolerance, true, lower);
    if (contact) {
      out.collision = true;
      out.clearance = margin_ > 0.0;
      out.witness_t = contact->t;
      out.part_a = contact->a;
      out.part_b = contact->b;
      lower = 0.0;
    }
  }
  if (gave_up && !out.clearance && !out.collision) {
    // Not certified: a violation (counted as clearance), naming no pair.
    out.clearance = true;
    out.part_a = out.part_b = -1;
    out.witness_t = -1.0;
  }
  out.lower_bound = lower;
  out.unresolved = gave_up;
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
