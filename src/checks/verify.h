// SPDX-License-Identifier: MIT
// Plan verification: every state of every plan against every checked pair.
// Collision is exact; the minimum distance is computed in double with the
// closest points; a distance that falls within kDistanceTolerance of the
// safety margin cannot be settled in double and is reported as a violation.
#pragma once

#include "src/geometry/collision_model.h"
#include "src/checks/dig.h"
#include "src/geometry/heightfield.h"
#include "src/geometry/box_motion.h"
#include "src/geometry/motion_bound.h"
#include "src/checks/probes.h"
#include "src/scene/kinematics.h"
#include "src/scene/plan.h"
#include "src/scene/scene.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace plancheck {

class BuiltAhead;  // src/checks/built_ahead.h

// Relative error of the double distance routines (closest points of two
// triangles in a relative frame) is a few ulps of the coordinates; a margin
// comparison closer than this (metres) is treated as a violation.
inline constexpr double kDistanceTolerance = 1e-9;

// Distance searches skip pairs whose lower bound is within this (m) of the
// best so far (DistanceRequest::abs_tolerance), so a reported minimum is at
// most this much above the exact minimum over triangle pairs: a thousand
// times below kDistanceTolerance, so no margin decision can change, and it
// halves the check time on models with parallel faces tied at the minimum.
inline constexpr double kDistanceTieTolerance = 1e-12;

// Most colliding states listed per plan, and triangle pairs per part pair
// (the contract's report limits).
inline constexpr std::size_t kMaxCollisionStatesListed = 100;
inline constexpr std::size_t kMaxTrianglePairsListed = 16;

struct PairContact {
  int part_a = -1;  // index into the checker's part list (Scene::parts, then terrain)
  int part_b = -1;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> triangles;
};

// What one state shows.
struct StateResult {
  bool collision = false;
  std::vector<PairContact> contacts;  // colliding pairs (empty unless collision)
  double min_distance = std::numeric_limits<double>::infinity();  // m; 0 when colliding
  int part_a = -1;                    // pair at the minimum distance (-1: no checked pair)
  int part_b = -1;
  Vec3 point_a = Vec3::Zero();        // closest points, reference frame (m)
  Vec3 point_b = Vec3::Zero();
  int limit_action = -1;              // first action outside its limits, or -1
  // How close to the margin min_distance may be and still not settle it (m):
  // kDistanceTolerance, or more for coordinates so large that the double
  // distance's error bound (16 eps times the largest coordinate, see
  // tests/stability) exceeds it: 64 eps times the largest coordinate of the
  // closest pair's boxes, in the world and in their own frames; for a
  // distance_is_bound state, the largest such guard of any checked pair.
  double distance_tolerance = kDistanceTolerance;
  // true when min_distance is only a certified lower bound (a verdict-only
  // check, CheckRequest::exact_below, proved every pair beyond the margin
  // without an exact distance); part_a/part_b are then -1.
  bool distance_is_bound = false;
};

// What the motion from state s to state s + 1 shows (verify --continuous,
// src/checks/continuous.h). The segment is closed: it includes both states.
struct SegmentResult {
  bool checked = false;    // false on a plan's last state (no segment) or without --continuous
  bool collision = false;  // parts touch somewhere on it (or come within ContinuousOptions::contact_tolerance)
  bool clearance = false;  // some configuration on it is closer than margin + ContinuousOptions::tolerance
  // Certified: no configuration on the segment is closer than this (m); 0 on collision.
  double lower_bound = std::numeric_limits<double>::infinity();
  // The smallest exact distance at the configurations checked (m), an upper
  // bound on the segment's minimum; its pair below.
  double min_sampled = std::numeric_limits<double>::infinity();
  int part_a = -1;         // pair of the first violation witness, else at min_sampled
  int part_b = -1;
  double witness_t = -1.0;  // first violation witness as a fraction of the segment; -1: none
  std::size_t steps = 0;    // exact configuration checks run on the segment (its states not counted)
  bool unresolved = false;  // the step budget ran out: reported as a violation without a witness
};

enum class Verdict { kSafe, kCollision, kClearance, kLimits, kTarget };
const char* verdict_name(Verdict v);

struct StateResult;
// What one state shows on its own, ranked as verify reports it: collision,
// then clearance (a distance below the margin, or within the state's
// distance_tolerance of it: too close to settle in double), then limits;
// kSafe otherwise.
Verdict state_verdict(const StateResult& state, double safety_margin);

struct Violation {
  std::size_t state = 0;
  Verdict kind = Verdict::kSafe;
  int part_a = -1;  // for collision/clearance
  int part_b = -1;
  int action = -1;  // for limits
  bool between = false;
};

struct PlanResult {
  const Plan* plan = nullptr;
  std::vector<StateResult> states;
  Verdict verdict = Verdict::kSafe;
  std::optional<Violation> first_violation;
  double min_distance = std::numeric_limits<double>::infinity();  // m
  std::size_t min_distance_state = 0;
  int min_part_a = -1;
  int min_part_b = -1;
  Vec3 min_point_a = Vec3::Zero();
  Vec3 min_point_b = Vec3::Zero();
  std::optional<double> target_error;  // m
  double seconds = 0.0;                // summed over the states' check time
  // Scooping (scenes with a scoop block): per state, and the plan's summary.
  std::vector<DigStep> dig_steps;
  std::optional<DigSummary> dig;
  // Probes (scenes with probes): probes[s][p]; a reading's hit indexes probe_targets.
  std::vector<std::vector<ProbeReading>> probes;
  std::vector<std::string> probe_targets;
  // --continuous: segments[s] is the motion from state s to s + 1 (empty otherwise).
  std::vector<SegmentResult> segments;
};

// What one state's check computes (the bench also times the parts alone).
struct CheckRequest {
  bool distance = true;        // false: collision only; min_distance stays infinity
  // Relative distance tolerance (like FCL's rel_err): the minimum distance
  // reported is at most (1 + rel_tolerance) times the exact one. 0: exact.
  // Only the bench uses it; verify always checks exactly.
  double rel_tolerance = 0.0;
  // Intersecting triangle pairs listed per colliding part pair; 0: the
  // first one found only, which lets the search stop there.
  std::size_t max_triangle_pairs = kMaxTrianglePairsListed;
  // false: stop at the first colliding part pair (in checked-pair order), so
  // contacts lists that one only. The verdict is the same.
  bool all_contacts = true;
  // With all_contacts false: the pairs after the first contact still get
  // their lower bounds (box gap, carried separation), only not their
  // collision test, so a seed carries to the next state what it carries
  // with all_contacts (verify_plans' first pass, see listed_collisions).
  bool bounds_after_contact = false;
  // Distances need be exact only below this (m; infinity: always exact). A
  // pair proven at least this far apart (plus the guard that settles a margin
  // comparison in double) gets no exact distance; when no pair comes closer,
  // the state reports a certified lower bound (StateResult::distance_is_bound).
  // Below it, distances and the verdict are those of the full check.
  double exact_below = std::numeric_limits<double>::infinity();
};

// The verdict-only request (verify --verdict-only, the API's and Python's
// verdict_only): the first contact only (first colliding pair in checked-pair
// order, first triangle pair), and exact distances only below the margin.
// The verdicts are those of the full request.
CheckRequest verdict_only_request(double safety_margin);

// What a state's row needs (a plan CSV row, the API's and Python's full
// check): everything the full request gives but the listing of intersecting
// triangle pairs, which only verify's report.json uses. The first colliding
// pair in checked-pair order and its contact point are the full request's
// (the collision test walks the same way and stops at its first hit), the
// minimum distance, its pair and points too; `contacts` holds that first
// pair with one triangle pair.
CheckRequest row_request();

// Coherence between consecutive states of a plan: the previous state's
// closest pair (checked pair and triangle slots) seeds the next state's
// distance search with a tight upper bound, and the separations the previous
// state proved carry over: a pair whose proven distance exceeds how far its
// parts can have moved since (MotionBound) cannot touch, so its exact
// collision test is skipped, and its distance search starts from the bound.
// Verdicts and distances never depend on it.
struct StateSeed {
  int pair = -1;  // index into the checked pairs; -1: none
  std::uint32_t slot_a = 0, slot_b = 0;
  // Per checked pair, a proven lower bound (m) on its distance at the
  // parameters `at` (as written); empty: nothing cached.
  std::vector<double> separation;
  std::vector<double> at;
  // Per checked pair (not the terrain's), the last exact distance search
  // run on it: its inputs (both parts' transforms and the request) and its
  // answer. distance() is a deterministic function of these, so a later
  // state whose search has bitwise the same inputs (the pair's parts did not
  // move, its seed and bound are the same) takes the answer instead of
  // searching again: the same bits. A plan that holds a joint still keeps
  // the pairs of the parts before it (the arm's base over the deck) in place.
  struct Search {
    bool valid = false;
    Affine ta, tb;
    DistanceRequest request;
    DistanceResult result;
  };
  std::vector<Search> searches;

  // Back to a fresh seed (as StateSeed{}: no pair, nothing carried, no
  // search remembered), keeping the storage: verify_plans starts every run
  // of a plan's states from nothing, and a fresh seed's first searches
  // allocated (and filled) a Search per checked pair, ~400 bytes each.
  void reset() {
    pair = -1;
    slot_a = slot_b = 0;
    separation.clear();
    at.clear();
    for (Search& s : searches) s.valid = false;
  }
};

class Progress;

struct VerifyOptions {
  int threads = 0;         // 0: all hardware threads
  bool dig_carry = false;  // the terrain dug by one plan is the next plan's start
  bool regolith = true;    // run the digging and probe passes when the scene has them
  Progress* progress = nullptr;  // counts the states checked (optional; last, so {threads, carry} still reads)
  bool verdict_only = false;     // verdict_only_request for every state (verify --verdict-only)
  // Colliding states per plan whose contacts list up to
  // kMaxTrianglePairsListed triangle pairs per colliding part pair, in state
  // order (report.json lists kMaxCollisionStatesListed; report.html every
  // one). The others list the first triangle pair of each colliding part
  // pair: the first of the full listing. States are checked with that short
  // listing and the listed ones again with the full request, so a plan with
  // many colliding states lists only what its report shows.
  std::size_t listed_collisions = std::numeric_limits<std::size_t>::max();
};

// One checked pair at one configuration, asked on its own (the sweep's
// certified regions, src/checks/sweep_certify.h).
struct PairAnswer {
  bool collision = false;
  bool exact = false;      // distance is the pair's minimum distance (found below the need)
  double distance = 0.0;   // m: the exact distance, or a proven lower bound; 0 in contact
  double upper = std::numeric_limits<double>::infinity();  // m: an upper bound (a distance found)
  double guard = kDistanceTolerance;  // what settles a margin comparison of this pair in double
  // Where nothing was found below the need and the search proved more on
  // its way (DistanceResult::beyond: its root boxes, or the node pairs it
  // dropped): that lower bound less the guard, at least `distance`; equal
  // to `distance` otherwise. Kept apart from `distance` so that the callers
  // that report it (sweeps) read what they always did; the motion march
  // takes it as a sample's bound.
  double beyond = 0.0;
  // The closest triangle pair as model slots (valid when exact): read as a
  // seed when seeded is true, written when exact.
  bool seeded = false;
  std::uint32_t slot_a = 0, slot_b = 0;
};

// The parts of a scene posed at one configuration (Checker::pose_parts).
struct PosedParts {
  std::vector<Affine> chains;
  std::vector<const Affine*> pose;                // per checked part
  std::vector<std::pair<Vec3, Vec3>> box;         // per checked part: world box, padded
  // The terrain the terrain pairs meet (a dug copy of Checker::terrain(),
  // refit where digging changed it); nullptr: the undisturbed terrain.
  const Heightfield* terrain = nullptr;
};

// Collision structures of a scene, built once; immutable and shared by threads.
class Checker {
 public:
  // `ahead`: structures built while the model was imported (built_ahead.h),
  // taken for the parts whose meshes they were built from; may be null.
  // `reuse`: a checker of an earlier version of the scene (world objects
  // changed, src/scene/objects.h): a part of the same name whose mesh is
  // bitwise the same, with the same triangles left out, shares its
  // structure instead of building it again; so does the terrain on the same grid.
  explicit Checker(const Scene& scene, int threads = 0, const BuiltAhead* ahead = nullptr,
                   const Checker* reuse = nullptr);

  // Names of the checked parts: Scene::parts, then "terrain" when present.
  const std::string& part_name(int index) const { return names_[static_cast<std::size_t>(index)]; }
  std::size_t part_count() const { return names_.size(); }
  // A number of this checker's own (never 0, never another checker's, a
  // copy's included): what per-thread caches of its answers are keyed by.
  std::uint64_t instance_id() const { return id_.value; }
  // The scene it was built from (its parts and chains: what poses them).
  const Scene& scene() const { return scene_; }
  std::size_t triangle_count() const;
  std::size_t memory_bytes() const;
  // Static triangles left out at build time: beyond the reach of every
  // moving part they are checked against (see the constructor), or in static
  // parts no checked pair uses. Such a triangle can neither touch a moving
  // part nor be closer to one than some kept pair is in every pose.
  std::size_t left_out_static_triangles() const { return left_out_; }
  // Whether every triangle of scene part `part` is checked (none left out).
  bool part_whole(int part) const { return (*kept_)[static_cast<std::size_t>(part)].empty(); }

  // The checked pairs as indices into the part list (the moving part first).
  std::vector<std::pair<int, int>> pairs() const {
    std::vector<std::pair<int, int>> out;
    for (const PairRef& p : pairs_) out.emplace_back(p.a, p.b);
    return out;
  }

  // Checks one configuration (a full parameter vector, as written) against every
  // checked pair, the terrain pairs against the undisturbed terrain.
  // seed (optional, in/out): read as the hint, then set to this state's
  // closest pair for the next state.
  void check_state(const std::vector<double>& params, StateResult& out,
                   const CheckRequest& request = {}, StateSeed* seed = nullptr) const {
    check_pairs(params, out, request, seed, terrain_.get(), kAllPairs);
  }

  // The same without the terrain pairs; check_terrain() adds them later
  // against a dug terrain. Together they give check_state's verdict inputs.
  void check_state_without_terrain(const std::vector<double>& params, StateResult& out,
                                   const CheckRequest& request = {}, StateSeed* seed = nullptr) const {
    check_pairs(params, out, request, seed, nullptr, kNonTerrainPairs);
  }

  // Checks the terrain pairs of one state against `terrain` (the undisturbed
  // terrain() or a copy of it refit where digging changed it) and merges
  // them into `out`, which holds that state's other pairs: contacts are
  // appended in pair order (so the first contact is the same as check_state
  // would list), and the minimum distance moves to a terrain pair only when
  // strictly closer (or when the terrain contact is the state's first). seed
  // as in check_state, for the terrain pairs alone.
  // With request.exact_below finite (verdict-only), as check_state would
  // with that request.
  void check_terrain(const std::vector<double>& params, const Heightfield& terrain, StateResult& out,
                     StateSeed* seed = nullptr, const CheckRequest& request = {}) const;

  // The terrain as a heightfield (nullptr: no colliding terrain) and its
  // index in the part list.
  const Heightfield* terrain() const { return terrain_.get(); }
  // The box pair_gaps bounds the terrain by (its hierarchy's root): of
  // `field` (a dug copy), or of the scene's terrain when null. False when
  // there is no terrain to check.
  bool terrain_box(const Heightfield* field, Vec3& lo, Vec3& hi) const;
  int terrain_index() const { return terrain_index_; }
  // Whether verify_plans checks the terrain pairs against the dug terrain:
  // the scene digs (scoop and terrain) and some pair involves the terrain.
  bool terrain_is_dug() const { return digger_ && terrain_ && has_terrain_pairs_; }

  // A copy of this checker in which static part `part`, a world object
  // (src/scene/objects.h) that no build left triangles out of, stands at
  // `placement` times its mesh in the scene (its structure, and every
  // other, shared; nothing is built). Answers are those of a scene whose
  // mesh of that part is posed so, up to the rounding of the posing.
  std::unique_ptr<const Checker> with_placement(int part, const Affine& placement) const;

  // The pairs in contact (touching or intersecting) at the reference pose.
  std::vector<PairContact> reference_contacts() const;

  // Pair by pair (the sweep's certified regions): pose every part once,
  // then ask single checked pairs k (indices into pairs()). pair_collides is
  // check_pairs' test (box overlap, then the exact collision test).
  // pair_distance, for a pair pair_collides cleared at this pose: its exact
  // distance when below `need` (m), else a proven lower bound (at least need
  // less the tie tolerance and the pair's guard); with `decide`, only
  // whether it is below `need` (the search stops at the first triangle pair
  // below: not exact, `upper` is that pair's distance). out's slots, when
  // seeded, start the search (the answer's distance may then differ within
  // the tie tolerance).
  // parts (optional): pose only these (and their chains); others keep what they held.
  void pose_parts(const std::vector<double>& params, PosedParts& out, std::span<const int> parts = {}) const;
  // pose_parts for a list of parts (the same poses), with the velocity
  // field of `moving` (one of them) while the parameters move at `rates`
  // (part_transform_velocity): false, w and u unset, where that part is
  // static or its chain has a scale action.
  bool pose_parts_moving(const std::vector<double>& params, PosedParts& out, std::span<const int> parts, int moving,
                         std::span<const double> rates, Vec3& w, Vec3& u) const;
  bool pair_collides(const PosedParts& posed, std::size_t k) const;
  // rel_tolerance r > 0 (the motion checks' cheap bound): a search within
  // a factor 1 + r, far cheaper than an exact one at long range; the answer
  // is then never exact: a distance found gives upper and the lower bound
  // upper / (1 + r) (less the tie tolerance and the guard), nothing found
  // the bound need / (1 + r) (less the same).
  // beyond: fill PairAnswer::beyond from what the search proved on its way
  // (DistanceRequest::beyond); else it is `distance`.
  void pair_distance(const PosedParts& posed, std::size_t k, double need, PairAnswer& out, bool decide = false,
                     double rel_tolerance = 0.0, bool beyond = false) const;
  // Every pair's answer to need 0 at once, bit for bit what
  // pair_distance(posed, k, 0.0, .) gives: gap[k] its box gap (infinity for
  // a pair never checked, or a terrain pair without terrain), guard[k] its
  // guard. Each part's magnitude and the terrain's box once, not per pair.
  // `posed` must hold every part (pose_parts without a list).
  void pair_gaps(const PosedParts& posed, std::vector<double>& gap, std::vector<double>& guard) const;
  // Up to `max` intersecting triangle pairs of pair k at this pose, as
  // collide lists them, each as its six corners in the world frame as
  // posed here (part a's three, then b's): what a contact certificate
  // (src/geometry/crossing.h) is built from. Empty when they do not touch,
  // and for a terrain pair (none listed).
  void pair_crossings(const PosedParts& posed, std::size_t k, std::size_t max,
                      std::vector<std::array<Vec3, 6>>& out) const;
  // The parameters (indices into Scene::parameter_names) the distance of
  // pair k depends on: those read by the actions of one part's chain and
  // not the other's. The relative pose of the two parts is a function of
  // these alone, so the pair's answer is the same whatever the others are.
  std::vector<int> pair_parameters(std::size_t k) const;
  // An upper bound on how far the parts of pair k can move relative to each
  // other while the parameters go from the centre of the box [lo, hi] to
  // any point of it (m, padded for rounding).
  double pair_motion(std::size_t k, std::span<const double> lo, std::span<const double> hi) const;
  // An upper bound on how far the parts of pair k move relative to each
  // other while the parameters go linearly from qa to qb (m, padded).
  double pair_path(std::size_t k, std::span<const double> qa, std::span<const double> qb) const {
    return motion_.part_bound(pairs_[k].a, qa, qb) + motion_.part_bound(pairs_[k].b, qa, qb);
  }
  // The largest margin guard of any checked pair over every configuration
  // whose moving parts stay within `reach` (m) of their reference pose: the
  // verdict-only cutoff's G, fixed for a whole sweep.
  double guard_bound(double reach) const;

  // The point a plan's target refers to, posed: the scoop's bottom point, or
  // without a scoop the origin of the last action's node.
  Vec3 target_point(const std::vector<double>& params) const;
  // The same for many states in a row (the sweep's reach summary): `cache`
  // keeps the scoop's chain products between calls (ChainCache; made on
  // first use, one per thread), so a state that changes only the last
  // joints composes only those. The same bits as target_point(params).
  Vec3 target_point(const std::vector<double>& params, std::optional<ChainCache>& cache) const;

 private:
  // Part i's pose and box in `out` once its chain's product is there.
  void place(PosedParts& out, std::size_t i) const;
  struct PairRef {
    int a, b;
    bool empty = false;  // a part whose triangles were all left out: never checked
  };
  enum PairSet { kAllPairs, kNonTerrainPairs, kTerrainPairs };
  // The pair loop of check_state over `which` pairs, terrain pairs against
  // `terrain`; a distance search starts below `bound` (m).
  void check_pairs(const std::vector<double>& params, StateResult& out, const CheckRequest& request,
                   StateSeed* seed, const Heightfield* terrain, PairSet which,
                   double bound = std::numeric_limits<double>::infinity()) const;
  // Replaces meshes[i] of static parts by their reachable triangles (held in
  // storage), fills kept_; returns how many triangles were left out.
  std::size_t prune_static(const Scene& scene, std::vector<const Mesh*>& meshes,
                           std::vector<Mesh>& storage, int threads);
  // The largest coordinate of part i's box posed at `world` and of its own
  // frame's box (the terrain: `world` alone): what a pair's guard scales with.
  double part_magnitude(int i, const Vec3& lo, const Vec3& hi) const {
    const double w = std::max(lo.cwiseAbs().maxCoeff(), hi.cwiseAbs().maxCoeff());
    return i == terrain_index_ ? w : std::max(w, local_magnitude_[static_cast<std::size_t>(i)]);
  }
  const Scene& scene_;
  std::vector<std::string> names_;
  std::vector<CollisionModel> models_;  // one per scene part (the terrain is terrain_)
  std::shared_ptr<const Heightfield> terrain_;  // the undisturbed terrain, when it collides
  int terrain_index_ = -1;                      // its index in names_
  // Parts in some checked pair, and twice the terrain's largest coordinate
  // (0 without terrain pairs): what the verdict-only cutoff scales with.
  std::vector<int> guard_parts_;
  double terrain_magnitude_ = 0.0;
  // The same split for a state's guard: the moving parts of guard_parts_;
  // the largest magnitude of its static parts' boxes (world and own frame)
  // and terrain_magnitude_; and every part's own-frame box magnitude.
  std::vector<int> moving_guard_parts_;
  double static_magnitude_ = 0.0;
  std::vector<double> local_magnitude_;
  bool has_terrain_pairs_ = false;
  std::vector<int> chain_of_;           // chain id per checked part, -1 when static
  std::vector<int> moving_parts_;       // the parts with a chain, ascending: what a state poses
  std::vector<int> chain_prefixes_;     // chain_prefixes(scene_), once
  // A number of its own per checker, a copy drawing a new one: check_pairs'
  // per-thread scratch keeps the static parts' poses and boxes of the
  // checker numbered so (never 0).
  struct InstanceId {
    std::uint64_t value;
    InstanceId();
    InstanceId(const InstanceId&) : InstanceId() {}
    InstanceId& operator=(const InstanceId&) = delete;
  };
  InstanceId id_;
  std::vector<std::pair<Vec3, Vec3>> local_boxes_;  // (lo, hi) per part, its own frame
  std::vector<std::pair<Vec3, Vec3>> static_boxes_;  // posed (identity) boxes of static parts, once
  std::pair<Vec3, Vec3> terrain_box_;  // the undisturbed terrain's box, as check_pairs pads it, once
  // The box-gap pass of check_pairs: per moving part, its checked pairs
  // with static parts (not the terrain) and those parts' boxes in blocks of
  // two (lo x, y, z, hi x, y, z, each coordinate of both boxes side by
  // side: 12 doubles a block), so a state computes two gaps at a time from
  // one contiguous array; the other pairs (both moving, the terrain's,
  // empty ones) one by one. Set by set_gap_rows() from pairs_ and
  // static_boxes_.
  // A collision-only state needs only the pairs whose boxes meet: the rows
  // are ordered in clusters of a few spatially close partners (cluster c
  // ends at block ends[c]), each with the union of their boxes (clusters,
  // the same blocks), and the union of all (root); a moving box apart from
  // a union is apart from every box in it (check_pairs).
  // A cluster with an odd count (the last one: the splits keep the others
  // even) is padded with a box that meets nothing (lo +inf, hi -inf) and
  // the pair index pairs_.size(), a slot of check_pairs' scratch that
  // nothing reads; so is an odd count of clusters (with a union that meets
  // nothing).
  struct GapRows {
    int part = -1;
    std::vector<std::uint32_t> pairs;  // pair index per row (two a block)
    std::vector<double> boxes;         // 12 per block
    std::array<double, 6> root{};
    std::vector<std::uint32_t> ends;   // per cluster: its last block + 1
    std::vector<double> clusters;      // the unions, 12 per block of two clusters
  };
  std::vector<GapRows> gap_rows_;
  std::vector<std::uint32_t> other_gap_pairs_;
  void set_gap_rows();
  std::vector<PairRef> pairs_;
  // Per checked part: model triangle index -> mesh triangle index, when
  // triangles were left out (empty: the identity).
  // Shared, never changed after the build (copies made by with_placement share it).
  std::shared_ptr<std::vector<std::vector<std::uint32_t>>> kept_ =
      std::make_shared<std::vector<std::vector<std::uint32_t>>>();
  // Per part: where it stands beyond its chain. The identity, but for a
  // static world object moved at run time (with_placement): its structure
  // stays the one built at its pose in the scene, placed by this.
  std::vector<Affine> placement_;
  std::size_t left_out_ = 0;
  MotionBound motion_;  // how far parts can move between two states (cached separations)
  // BoxMotion (box_motion()), built on first use; with_placement's copies
  // share it (a static object's placement moves nothing it bounds).
  struct LazyBoxMotion {
    std::once_flag once;
    std::unique_ptr<const BoxMotion> box;
  };
  std::shared_ptr<LazyBoxMotion> box_motion_ = std::make_shared<LazyBoxMotion>();
  // Built once with the collision structures, only when the scene needs them.
  std::shared_ptr<const Digger> digger_;        // scoop and terrain
  std::shared_ptr<const ProbeCaster> probes_;   // probes (an Embree scene)
  Checker(const Checker&) = default;            // with_placement's copy: every structure shared

 public:
  const Digger* digger() const { return digger_.get(); }
  // How far parts can move between two configurations (the scene's, built once).
  const MotionBound& motion_bound() const { return motion_; }
  // Pose-aware bounds of the same (src/geometry/box_motion.h), built the
  // first time they are asked for, from whole triangles (12M instructions
  // on the default arm): the motion checks that sample a pair read them.
  // Thread-safe.
  const BoxMotion& box_motion() const;
  double safety_margin() const { return scene_.safety_margin; }
  const ProbeCaster* probe_caster() const { return probes_.get(); }
};

std::vector<PlanResult> verify_plans(const Checker& checker, const Scene& scene,
                                     const std::vector<Plan>& plans, const VerifyOptions& options);

}  // namespace plancheck
