// SPDX-License-Identifier: MIT
// plancheck inside OMPL (>= 1.5): a state space from a scene's limits, a
// state validity checker and a certified motion validator over a
// plancheck::Checker (contract: shared/spec/plan-and-report-format.md,
// "Embedding"). Header-only, over the public API only: compiled by a
// consumer that has OMPL; libplancheck itself does not link OMPL.
//
//   auto checker = std::make_shared<plancheck::Checker>(plancheck::Scene::load("scene.json"));
//   ompl::geometric::SimpleSetup ss(plancheck::ompl::make_space(checker));
//   auto si = ss.getSpaceInformation();
//   ss.setStateValidityChecker(std::make_shared<plancheck::ompl::StateValidityChecker>(si, checker));
//   si->setMotionValidator(std::make_shared<plancheck::ompl::MotionValidator>(si, checker));
//   ss.setStartAndGoalStates(start, goal);
//   ss.solve(1.0); ss.simplifySolution();   // every motion of the path is certified
//
// States are in plan units, one dimension per parameter name in order, so
// a path's states written as CSV rows under the parameter names are a plan
// that `plancheck verify --continuous` passes. A state is valid when its
// verdict is safe (no contact, clearance at least the safety margin, within
// limits); a motion is valid when Checker::check_motion (verdict-only,
// first_violation) says safe: certified for every configuration on the
// straight line in plan units, not at sampled points (a few states on it
// are checked first, only to reject a motion sooner).
#pragma once

#include <plancheck/plancheck.h>

#include <ompl/base/MotionValidator.h>
#include <ompl/base/SpaceInformation.h>
#include <ompl/base/StateValidityChecker.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/config.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <utility>
#include <vector>

#if OMPL_MAJOR_VERSION < 1 || (OMPL_MAJOR_VERSION == 1 && OMPL_MINOR_VERSION < 5)
#error "<plancheck/ompl.h> needs OMPL 1.5 or later"
#endif

namespace plancheck {
namespace ompl {

namespace detail {

inline std::vector<double> values(const ::ompl::base::State* state, std::size_t n) {
  const auto* s = state->as<::ompl::base::RealVectorStateSpace::StateType>();
  return std::vector<double>(s->values, s->values + n);
}

}  // namespace detail

// A RealVectorStateSpace with the scene's limits, plan units, one dimension
// per parameter name in order (named after it). Throws plancheck::Error
// when a parameter has no limits (a continuous joint, a free translation):
// a RealVectorStateSpace needs finite bounds.
inline ::ompl::base::StateSpacePtr make_space(const std::shared_ptr<const Checker>& checker) {
  const Scene scene = checker->scene();
  const std::vector<std::string>& names = scene.parameter_names();
  const std::vector<double> lo = scene.lower_limits(), hi = scene.upper_limits();
  auto space = std::make_shared<::ompl::base::RealVectorStateSpace>(static_cast<unsigned int>(names.size()));
  ::ompl::base::RealVectorBounds bounds(static_cast<unsigned int>(names.size()));
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (!std::isfinite(lo[i]) || !std::isfinite(hi[i]))
      throw Error("make_space: parameter '" + names[i] +
                  "' has no limits; a RealVectorStateSpace needs finite bounds (set limits in the scene)");
    bounds.setLow(static_cast<unsigned int>(i), lo[i]);
    bounds.setHigh(static_cast<unsigned int>(i), hi[i]);
    space->setDimensionName(static_cast<unsigned int>(i), names[i]);
  }
  space->setBounds(bounds);
  return space;
}

// Valid: the state's verdict is safe (verdict-only check: the same verdict
// as the full one, faster). clearance(): the exact minimum distance
// (length_unit; 0 in contact).
class StateValidityChecker : public ::ompl::base::StateValidityChecker {
 public:
  StateValidityChecker(const ::ompl::base::SpaceInformationPtr& si, std::shared_ptr<const Checker> checker)
      : ::ompl::base::StateValidityChecker(si), checker_(std::move(checker)) {
    specs_.clearanceComputationType = ::ompl::base::StateValidityCheckerSpecs::EXACT;
  }

  bool isValid(const ::ompl::base::State* state) const override {
    return checker_->check(detail::values(state, checker_->parameter_count()), CheckOptions{true}).verdict ==
           Verdict::kSafe;
  }

  double clearance(const ::ompl::base::State* state) const override {
    return checker_->check(detail::values(state, checker_->parameter_count())).min_distance;
  }

 private:
  std::shared_ptr<const Checker> checker_;
};

// Certified motion validation: Checker::check_motion in verdict-only mode,
// stopping at the first violation (MotionOptions::first_violation; both
// ends included). With lastValid, an invalid motion reports how far
// from s1 it was certified safe (MotionResult::safe_until: the fraction,
// and the state there), 0 and s1 when nothing beyond s1 was proven.
class MotionValidator : public ::ompl::base::MotionValidator {
 public:
  MotionValidator(const ::ompl::base::SpaceInformationPtr& si, std::shared_ptr<const Checker> checker)
      : ::ompl::base::MotionValidator(si), checker_(std::move(checker)) {}

  // Only whether the motion is safe: a few states inside it are checked
  // first (verdict-only point checks at a quarter of OMPL's resolution, in
  // its bisection order), and one that is not safe ends it: a configuration
  // on the motion below the margin or in contact, so check_motion would not
  // certify it either (the same answer, at the cost of a few point checks:
  // most motions a planner rejects are rejected here). Then check_motion.
  bool checkMotion(const ::ompl::base::State* s1, const ::ompl::base::State* s2) const override {
    if (!screen(s1, s2)) {
      ++invalid_;
      return false;
    }
    return check(s1, s2).verdict == Verdict::kSafe;
  }

  bool checkMotion(const ::ompl::base::State* s1, const ::ompl::base::State* s2,
                   std::pair<::ompl::base::State*, double>& lastValid) const override {
    const MotionResult r = check(s1, s2);
    if (r.verdict == Verdict::kSafe) return true;
    lastValid.second = r.safe_until;
    if (lastValid.first) {
      if (r.safe_until > 0.0)
        si_->getStateSpace()->interpolate(s1, s2, r.safe_until, lastValid.first);
      else
        si_->copyState(lastValid.first, s1);
    }
    return false;
  }

 private:
  // false: a state strictly inside the motion, at i / n of it, is not
  // safe, for n a quarter of the segments of OMPL's resolution (rounded
  // up). Each parameter is a + t (b - a) kept between a and b: on the
  // straight line check_motion certifies up to rounding (far inside its
  // rounding guard), never outside limits both ends keep.
  //
  // Why a quarter: a safe motion pays for every state screened and then
  // for check_motion all the same, while an obstacle that a coarser screen
  // misses is found by check_motion (at more cost, but seldom: a planner's
  // colliding motions mostly cross obstacles many resolution steps wide).
  // OMPL bench, RRTConnect + simplify against OMPL's discrete validator
  // (two runs each): the full resolution 2.16-2.22x (default arm) and
  // 2.18-2.31x (URDF arm), a third 1.82x / 1.91-2.00x, a quarter
  // 1.81-1.87x / 1.79-1.90x, an eighth 1.86-1.87x / 1.75-1.77x, no screen
  // 1.97x / 2.40x.
  bool screen(const ::ompl::base::State* s1, const ::ompl::base::State* s2) const {
    constexpr unsigned int kCoarser = 4;
    const unsigned int n = (si_->getStateSpace()->validSegmentCount(s1, s2) + kCoarser - 1) / kCoarser;
    if (n < 2) return true;
    const std::size_t dim = checker_->parameter_count();
    const double* a = s1->as<::ompl::base::RealVectorStateSpace::StateType>()->values;
    const double* b = s2->as<::ompl::base::RealVectorStateSpace::StateType>()->values;
    thread_local std::vector<double> q;
    thread_local std::vector<std::pair<unsigned int, unsigned int>> ranges;
    q.resize(dim);
    ranges.assign(1, {1u, n - 1});
    for (std::size_t h = 0; h < ranges.size(); ++h) {
      const auto [lo, hi] = ranges[h];
      if (lo > hi) continue;
      const unsigned int mid = lo + (hi - lo) / 2;
      const double t = static_cast<double>(mid) / static_cast<double>(n);
      for (std::size_t j = 0; j < dim; ++j)
        q[j] = std::clamp(a[j] + t * (b[j] - a[j]), std::min(a[j], b[j]), std::max(a[j], b[j]));
      if (checker_->check(q, CheckOptions{true}).verdict != Verdict::kSafe) return false;
      ranges.emplace_back(lo, mid - 1);  // mid >= lo >= 1
      ranges.emplace_back(mid + 1, hi);
    }
    return true;
  }

  MotionResult check(const ::ompl::base::State* s1, const ::ompl::base::State* s2) const {
    const std::size_t n = checker_->parameter_count();
    // Verdict-only, stopping at the first violation: whether the motion is
    // safe and safe_until are check_motion's; what a violation is is not asked.
    MotionResult r = checker_->check_motion(detail::values(s1, n), detail::values(s2, n), MotionOptions{true, true});
    (r.verdict == Verdict::kSafe ? valid_ : invalid_)++;
    return r;
  }

  std::shared_ptr<const Checker> checker_;
};

}  // namespace ompl
}  // namespace plancheck
