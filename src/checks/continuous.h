// SPDX-License-Identifier: MIT
// verify --continuous: certifies the motion between consecutive states, which
// the contract defines as linear in driving-parameter space, by conservative
// advancement (Schwarzer, Saha and Latombe 2005) with adaptive bisection.
//
// On a segment [state s, state s + 1] (closed: both states included), with D
// the exact minimum distance over the checked pairs and m the safety margin:
//  * Never a false safe. If some configuration on the segment has D < m (a
//    collision included), the segment is a violation; if parts touch
//    anywhere on it, it is a collision.
//  * Clearance tolerance. A clearance violation is reported only with a
//    witness: a configuration on the segment whose exact D < m + tolerance.
//    A segment whose true minimum is at least m + tolerance is never flagged.
//  * Collision tolerance. A collision is reported with a witness that
//    intersects (exact test), or one whose exact D < contact_tolerance that
//    could not be resolved further (a near miss that close counts as contact).
//  * lower_bound <= true minimum over the segment <= min_sampled. On a safe
//    segment lower_bound >= m (certified); it is a proof, not an estimate, and
//    is loose where the segment is far from the margin.
// Results do not depend on the thread count.
#pragma once

#include "src/geometry/motion_bound.h"
#include "src/scene/plan.h"
#include "src/scene/scene.h"
#include "src/checks/verify.h"

#include <cstddef>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

namespace plancheck {

class SweptClusters;

struct ContinuousOptions {
  // Clearance witness tolerance (m): a violation needs a configuration with
  // exact distance below margin + tolerance. Must exceed kDistanceTolerance.
  double tolerance = 1e-5;
  // Contact tolerance (m): a configuration closer than this, where no exact
  // intersection was found, is reported as a collision. Must exceed kDistanceTolerance.
  double contact_tolerance = 1e-7;
  // Pair samples (one pair's search at one configuration; the reference:
  // whole configurations) per segment before it is given up on: the segment is then
  // a violation without a witness (SegmentResult::unresolved: "not
  // certified", a clearance violation naming no pair, never a contact).
  // The bound needs about one check per (clearance - margin) / reach
  // radians of a joint: motions of thousands of turns.
  std::size_t max_steps = 200000;
  int threads = 0;  // 0: all hardware threads
  // check_motion on threads: its pairs are handed to them only when at
  // least this many need samples (a planner's motion costs about 100 us,
  // and TBB's workers, asleep between motions, take about 25 us to wake: on
  // the OMPL bench's replayed motions 2 was slower than one thread, 16
  // about 8% faster on the default arm, no faster on the URDF arm).
  std::size_t parallel_pairs = 16;
  // Digging scenes: as VerifyOptions::dig_carry of the verify_plans run
  // whose results verify_segments extends (the terrain each segment sees).
  bool dig_carry = false;
};

// A lower bound of a pair's distance D(t) over a piece [t1, t2] of a
// segment (t in segment units, 0 to 1) from lower bounds v1 <= D(t1), v2 <=
// D(t2), `rate` bounding the speed of every point of either part relative
// to the other and `accel` their relative acceleration (per unit of t, and
// of t squared). First order (conservative advancement): D(t) >= max(v1 -
// rate (t - t1), v2 - rate (t2 - t)), at least g = min(v1, v2, (v1 + v2 -
// rate (t2 - t1)) / 2) over the piece. Second order, when g > 0: for the
// closest point pair at any t of the piece, y(t) their difference, |y| is
// at least g over the whole piece and |y|'' = (|y'|^2 - (u . y')^2) / |y|
// + u . y'' <= rate^2 / g + accel = K (u = y / |y|), so |y| lies above its
// chord less K (t - t1) (t2 - t) / 2; D(t) = |y(t)| and D(t1,2) <= |y(t1,2)|
// give D(t) >= the chord of v1, v2 less the same. Where a pair runs along
// the margin (v - target small against the distance g), the second order
// certifies pieces about sqrt(2 g / (v - target)) times longer.
// Returns the larger of the two (NaN in, NaN or less out).
double piece_lower_bound(double t1, double v1, double t2, double v2, double rate, double accel);

// Segment checks on one Checker; immutable, shared by threads.
class SegmentChecker {
 public:
  SegmentChecker(const Checker& checker, const Scene& scene, const ContinuousOptions& options);

  // Checks the segment from qa to qb whose end states were checked as sa and
  // sb (Checker::check_state with distances). Thread-safe.
  //
  // terrain (digging scenes): the terrain as it stands during the motion,
  // dug through qa's state; sa must have been checked against it, as the
  // dig pass does (check_state_without_terrain, then check_terrain). Every
  // configuration after qa is checked against it, its terrain pairs with
  // check_terrain; qb too unless sb_on_terrain says sb was (qb's own dig
  // changed nothing), since sb shows the terrain after qb's dig and the
  // motion reaches qb before that dig. The segment is then certified
  // against `terrain` up to and including qb; qb's state result stays its
  // own. nullptr: check_state's undisturbed terrain throughout.
  SegmentResult check(const std::vector<double>& qa, const std::vector<double>& qb, const StateResult& sa,
                      const StateResult& sb, const Heightfield* terrain = nullptr,
                      bool sb_on_terrain = false) const;

  // One segment on its own, on the scene's initial terrain (the API's
  // check_motion): checks its end states too, into sa and sb. verdict_only:
  // the same verdict, witness and pair (the bisection takes the same steps:
  // a bound that cannot decide a step is made exact first), with exact
  // distances only where they decide something; sa, sb and lower_bound may
  // then be certified bounds (StateResult::distance_is_bound) and
  // min_sampled counts only exact samples. Thread-safe.
  // certified_until (optional): the segment is certified clear of the
  // first pass's target (the margin; contact without one) from qa up to this
  // fraction of it: 1 when nothing is found, else where the certificate
  // stopped before the first witness (0 at an end).
  // The end states a thread checked last (256) are kept (per thread) and
  // taken for a later motion with an end of the same bits on this checker
  // in the same mode: a planner's chained motions check each state once.
  // first_violation: stop at the first witness against the margin (no
  // contact pass after it): the same safe or not, the same certified_until;
  // a witness found so is a clearance witness and lower_bound is NaN.
  // threads (not 1): the first pass's pairs march on that many threads (0:
  // all); the answer is the same whatever the threads.
  SegmentResult check_motion(const std::vector<double>& qa, const std::vector<double>& qb, bool verdict_only,
                             StateResult& sa, StateResult& sb, double* certified_until = nullptr,
                             bool first_violation = false, int threads = 1) const;

  // The previous algorithm, kept as the slow reference of the tests: one
  // bound for all pairs (pair_bound) against the least distance of any pair,
  // a whole configuration checked at each bisection midpoint. Same
  // contract, the same arguments as check and check_motion.
  SegmentResult check_reference(const std::vector<double>& qa, const std::vector<double>& qb, const StateResult& sa,
                                const StateResult& sb, const Heightfield* terrain = nullptr,
                                bool sb_on_terrain = false) const;
  SegmentResult check_motion_reference(const std::vector<double>& qa, const std::vector<double>& qb,
                                       bool verdict_only, StateResult& sa, StateResult& sb) const;

  // Upper bound (m) on how much any checked pair's distance can change while
  // the parameters go linearly from qa to qb: the largest sum of the two
  // parts' motion bounds over the checked pairs.
  double pair_bound(const std::vector<double>& qa, const std::vector<double>& qb) const;

  const ContinuousOptions& options() const { return options_; }

 private:
  // The reference algorithm (check_reference).
  SegmentResult run(const std::vector<double>& qa, const std::vector<double>& qb, const StateResult& sa,
                    const StateResult& sb, const Heightfield* terrain, bool sb_on_terrain, bool verdict_only) const;
  // The per-pair algorithm (check, check_motion on the scene's terrain).
  // bounds: the pairs' motion bounds from qa to qb (MotionBound::pair_bounds
  // over plan_) when the caller has them; nullptr: computed here.
  // threads: as check_motion's. verdict_only: lower_bound may be looser
  // (SweptClusters proves far pairs by one test, not by each ball).
  SegmentResult run_pairs(const std::vector<double>& qa, const std::vector<double>& qb, const StateResult& sa,
                          const StateResult& sb, double* certified_until = nullptr,
                          const Heightfield* terrain = nullptr, const std::vector<double>* bounds = nullptr,
                          bool first_violation = false, int threads = 1, bool verdict_only = false) const;
  // Where the end states' distances count (m): every pair at least
  // min(its state's distance, this) at an end in both modes, so that both
  // modes take the same steps (check_motion's verdict-only ends are exact
  // below the largest it can be, first limit plus end_reach, when it is
  // finite; a bound beyond that lies beyond it). First limit plus half the largest pair motion:
  // two ends that far clear certify the whole segment at once. From the
  // pairs' bounds (MotionBound::pair_bounds).
  double end_limit(const std::vector<double>& bounds) const;
  // The most end_limit lies beyond first_limit (half the margin, or of the
  // tolerance without one).
  double end_reach() const;
  // The distance a violation witness lies below: the first pass's.
  double first_limit() const;
  // Per pair k of one segment, a rate for the march from the poses
  // themselves: twice the two parts' BoxMotion reach from the segment's
  // midpoint over the box qa and qb span. Along the straight motion every
  // point of a part moves at most sum_i |qb_i - qa_i| L_i per unit of t,
  // L_i bounding its lever about action i anywhere in that box, and
  // BoxMotion's reach is sum_i h_i L_i with h_i = |qb_i - qa_i| / 2 from
  // the midpoint: so twice the reach bounds the path over every piece
  // [ta, tb] by its share (tb - ta), as MotionBound::pair_bound does with
  // levers read for any pose (an arm folded back counted as stretched
  // out). Against a static part or the terrain only the moving part's
  // clusters that can come near it count (of). Each part's reach and
  // clusters are computed when a pair first asks for them.
  class PoseRates {
    struct PartMove;

   public:
    // Its vectors, kept by the caller from one segment to the next.
    struct Storage {
      std::vector<double> lo, hi, mid;
      std::vector<PartMove> parts;
    };
    // swept (optional): SweptClusters started on this segment, whose
    // parts' balls are taken where it computed them (the same values).
    PoseRates(const SegmentChecker& segments, const std::vector<double>& qa, const std::vector<double>& qb,
              const PosedParts& posed, Storage& storage, const SweptClusters* swept = nullptr);
    struct Rate {
      double rate = 0.0;
      // A lower bound of the distance of the clusters the rate leaves out
      // (at least far_need), +infinity when none is.
      double far = std::numeric_limits<double>::infinity();
      // The pair's moving part against a static one (else -1) and which of
      // its clusters (BoxMotion::spheres, bit i: cluster i) the rate counts:
      // all of them when the rate is the pair's own bound (0 when the part
      // has more than 64, none then counted: no local speeds).
      int moving = -1;
      std::uint64_t counted = 0;
    };
    // Pair k's rate; a moving part's cluster at least far_need clear of a
    // static part's box over the whole segment is left out of it.
    Rate of(std::size_t k, double far_need);

   private:
    struct PartMove {
      bool known = false;
      bool balls = false;  // ball holds the clusters (BoxMotion::balls)
      std::vector<BoxMotion::Ball> ball;
      double reach = 0.0;
    };
    const PartMove& part(int x);
    const SegmentChecker& segments_;
    const std::vector<double>& qa_;
    const std::vector<double>& qb_;
    const PosedParts& posed_;
    const SweptClusters* swept_ = nullptr;
    bool ready_ = false;
    const BoxMotion* box_ = nullptr;
    std::vector<double>& lo_;
    std::vector<double>& hi_;
    std::vector<double>& mid_;
    std::vector<PartMove>& parts_;
  };

  // How far the rotations turn from qa to qb, summed (rad); +infinity when
  // a scale action moves or an input is not finite. Every point's
  // acceleration is at most twice this times its speed bound (per unit of
  // t: the parameters move linearly, so each action's value moves at a
  // constant rate; a rotation's second derivative is at most the point's
  // lever about it, the cross terms with the rotations outside it at most
  // its lever about the inner action).
  double turning(const std::vector<double>& qa, const std::vector<double>& qb) const;

  const Checker& checker_;
  const MotionBound& bound_;  // the checker's
  std::vector<std::pair<int, int>> pairs_;
  MotionBound::PairPlan plan_;  // pairs_ for MotionBound::pair_bounds
  std::vector<int> moving_;  // parts of some pair that have a chain
  // Per pair: its moving part and its static mesh part (SweptClusters'
  // question), or (-1, -1) when not one of each (two moving parts, the terrain).
  std::vector<std::pair<int, int>> swept_;
  std::vector<char> still_;  // per part of the checker: not among moving_ (the terrain too)
  std::vector<std::pair<int, double>> turns_;  // per rotation: its parameter, rad per plan unit (a mimic's multiplier in)
  std::vector<int> scale_parameters_;          // the parameters of scale actions
  double margin_;
  ContinuousOptions options_;
};

// Fills results[p].segments for every plan (results from verify_plans) and
// merges the first violation between states into each plan's verdict: the
// order is state s's own violation, then segment s, then state s + 1.
// Digging scenes whose states saw the dug terrain (the dig pass ran:
// results[p].dig is set and Checker::terrain_is_dug()): segment s is checked
// against the terrain as dug through state s (and through the earlier plans
// with options.dig_carry, which must match the verify_plans run), walked
// again in the dig pass's order (dig_along_plans); only those scenes pay for
// it. Segments that see the same terrain are checked in parallel.
void verify_segments(const Checker& checker, const Scene& scene, const std::vector<Plan>& plans,
                     std::vector<PlanResult>& results, const ContinuousOptions& options);

}  // namespace plancheck
