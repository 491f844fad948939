// SPDX-License-Identifier: MIT
// Certified regions for plancheck sweep: whole boxes of the grid proven
// clear pair by pair, exact checks only where a pair comes near the margin.
//
// Two savings, both exact:
// - A pair's distance depends only on the parameters that move one of its
//   parts relative to the other (Checker::pair_parameters): the lander's
//   deck against the second arm link sees the first two joints, not the
//   wrist. Pairs are grouped by the swept axes they see, and each group is
//   answered over its own (smaller) projection of the grid.
// - Within a group, a box of its projection is certified for a pair when
//   the pair's distance at the box's centre exceeds the cutoff by more than
//   the pair's parts can move relative to each other within the box
//   (Checker::pair_motion, a bound on every point's path). A box where some
//   pair fails is halved, and only the pairs still uncertified are asked
//   again; small boxes are answered configuration by configuration for
//   those pairs (exact distances below the cutoff), each answer's proven
//   separations carried to the next as along a plan.
// - A configuration already in contact through an earlier pair (in
//   checked-pair order, from a group answered before) needs no later pair
//   at all: the verdict and the first colliding pair are settled.
// - A configuration whose pairs are all apart (contact tests, or carried
//   separations) where the group's closest pair at the last point is still
//   found closer than margin - 4G - tie tolerance (its seed's triangle pair,
//   one triangle distance) is in clearance whatever its exact distance:
//   no exact search, a certified lower bound from coarse searches
//   (clear_point). Near the margin, within that slack, the exact search
//   decides.
// The cutoff is the verdict-only one (margin + 4G + tie tolerance, G a
// bound on every pair's margin guard over the grid): a certified bound can
// never read as a violation. So the verdicts are those of checking every
// configuration, and distance.npy holds a certified lower bound
// everywhere, exact where marked exact: in contact, and without contact
// where a pair came within the cutoff and the configuration was not
// certified in clearance (up to the distance search's tie tolerance).
#pragma once

#include "src/checks/sweep_grid.h"
#include "src/checks/verify.h"
#include "src/geometry/box_motion.h"
#include "src/geometry/motion_bound.h"
#include "src/geometry/solid_witness.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

namespace plancheck {

// What one block's configurations show, in C order within the block.
struct SweepBlockResult {
  std::vector<Verdict> verdict;
  std::vector<double> distance;       // m: exact where exact[i], else a certified lower bound; 0 in contact
  std::vector<std::uint8_t> exact;    // 1: distance is the configuration's minimum (or it collides); 0 where
                                      // the distance is beyond the cutoff or the configuration is certified
                                      // closer than the margin (clear_point)
  std::vector<std::int32_t> pair;     // the first colliding pair (checked-pair order), else the closest
                                      // pair when exact; -1 otherwise
  std::size_t pair_checks = 0;        // single-pair answers computed (statistics)
  std::size_t witnessed = 0;          // configurations in contact by a crossing witness, untested (statistics)
  std::size_t contact_boxes = 0;      // boxes certified in contact by a crossing witness (statistics)
  // Exact answers actually computed: points of each pair group's
  // projection of the block (a group that sees J1 and J2 answers a point
  // once for all of the block's J3 and J4 values) with a contact test or
  // an exact distance of their own, not a witness's (statistics).
  std::size_t point_tests = 0;
};

class SweepCertifier {
 public:
  SweepCertifier(const Checker& checker, const Scene& scene, const SweepGrid& grid);

  const SweepBlocks& blocks() const { return blocks_; }
  // Distances at or beyond this (m) are certified bounds; below it exact,
  // but where clear_point certified the configuration in clearance.
  double cutoff() const { return cutoff_; }
  // How many pair groups the checked pairs fall into, and their axes.
  std::size_t group_count() const { return groups_.size(); }

  // Checks block b (thread-safe; the answer depends on b alone).
  void check_block(std::size_t b, SweepBlockResult& out) const;

  // The motion bounds boxes are certified with (public for their tests).
  // How far any point of checked pair k's two parts can move (the sum of
  // both parts') between the box's centre c (c = lo + (hi - lo) / 2, as
  // certify takes it) and any configuration of the box [lo, hi] (m): the
  // least of Checker::pair_motion and the tighter BoxMotion bound.
  double pair_reach(std::size_t k, const std::vector<double>& lo, const std::vector<double>& hi,
                    const std::vector<double>& c) const;
  // The same between two configurations (the least of Checker::pair_path
  // and BoxMotion's reach from `from` over the box the two span).
  double pair_path(std::size_t k, const std::vector<double>& from, const std::vector<double>& to) const;

 private:
  struct Group {
    std::vector<std::size_t> axes;   // indices into grid.axes, increasing
    std::vector<std::size_t> pairs;  // checked pairs (Checker::pairs order), increasing
    std::vector<int> parts;          // their parts (not the terrain): what a configuration poses
  };
  struct Answers;   // one group's answers over its projection of a block
  struct Pending;   // a pair not yet certified in a box
  struct Context;   // one group's work in one block
  void certify(Context& c, std::vector<std::size_t>& lo, std::vector<std::size_t>& hi,
               std::vector<Pending>& pending, double floor) const;
  void answer_point(Context& c, const std::vector<std::size_t>& at, const std::vector<Pending>& pending,
                    double floor) const;
  // Point i of c, its pairs all apart (contacts tested, or carried
  // separations): when one of them is certainly below the margin there,
  // the verdict is clearance whatever the exact minimum, so the group
  // answers a certified lower bound (coarse searches) and true; false:
  // nothing settled (the exact searches follow).
  bool clear_point(Context& c, std::size_t i, const std::vector<Pending>& pending, double floor) const;
  // How far the corners of checked pair k's parts can move between the
  // centre of the box [lo, hi] and any configuration of it, as the exact
  // test poses them (m); false when no crossing witness can hold over it.
  bool witness_moves(std::size_t k, const std::vector<double>& lo, const std::vector<double>& hi, double& da,
                     double& db) const;
  // Whether one of these triangle pairs crossing at a box centre (world
  // corners as posed there) stays crossing under those moves.
  bool crossing(const std::vector<std::array<Vec3, 6>>& crossings, double da, double db) const;
  // How far the corners of checked pair k's parts can move between the
  // centre of the box [lo, hi] and any configuration of it (m), as
  // witness_moves; false when pair k can bring no witness (not rigid).
  bool moves(std::size_t k, const std::vector<double>& lo, const std::vector<double>& hi, double& da,
             double& db) const;
  // Whether pair k's parts, posed at the centre in c.posed, meet at every
  // configuration of the box [lo, hi] by a part-scale witness
  // (src/geometry/solid_witness.h).
  bool solid(Context& c, std::size_t k, const std::vector<double>& lo, const std::vector<double>& hi,
             const std::vector<double>& centre) const;
  // Whether a crossing witness may hold for pair k over moves da, db (its
  // triangles are large enough).
  bool room(std::size_t k, double da, double db) const;
  // Whether pair k can bring a part-scale witness (rigid, a closed piece).
  bool may_solid(std::size_t k) const;

  const Checker& checker_;
  const Scene& scene_;
  const SweepGrid& grid_;
  SweepBlocks blocks_;
  std::vector<Group> groups_;
  double cutoff_ = 0.0;
  double guard_ = 0.0;  // G
  // margin - 4G - tie tolerance: a triangle pair of some checked pair found
  // closer than this at a configuration (as posed here) puts its exact
  // minimum, as any exact check poses it, below the margin (clear_point).
  double below_ = 0.0;
  // Where every configuration of a box is in contact, a pair need only be
  // proven apart: this far (4G and the tie tolerance) settles it.
  double contact_cutoff_ = 0.0;
  // Per checked pair: whether a crossing witness may certify it in contact
  // (rigid chains, not the terrain), and its parts' motion bounds.
  std::vector<std::uint8_t> crossable_;
  std::vector<std::pair<int, int>> pair_parts_;  // Checker::pairs()
  // Per scene part: the largest inradius and edge of its triangles (m). A
  // witness is an edge longer than twice both parts' moves through a
  // triangle whose inradius exceeds them (witness_moves).
  std::vector<double> inradius_, longest_edge_;
  // Per scene part: its connected and closed pieces, found on first use
  // (empty for a part with triangles the checker left out).
  struct Solids {
    std::once_flag once;
    SolidPieces pieces;
  };
  const SolidPieces& pieces(int part) const;
  std::unique_ptr<Solids[]> solids_;
  MotionBound motion_;
  BoxMotion box_motion_;
  // Limits, per axis and value and for the parameters no axis sweeps.
  std::vector<std::vector<std::uint8_t>> outside_limits_;
  bool fixed_outside_limits_ = false;
};

}  // namespace plancheck
