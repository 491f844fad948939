// SPDX-License-Identifier: MIT
// Per-part collision structure and exact pair queries (collision, distance).
// A model is built once in the part's reference frame; a query takes the two
// parts' current transforms and works in a relative frame, so no vertex is
// rewritten per state. Models are immutable after build and safe to query
// from many threads at once.
#pragma once

#include "src/scene/scene.h"

#include <cstdint>
#include <limits>
#include <memory>
#include <utility>
#include <vector>

namespace plancheck {

struct CollisionModelData;  // BVH and triangles; defined in bvh.h

class CollisionModel {
 public:
  explicit CollisionModel(const Mesh& mesh);  // builds the BVH (reference frame)
  // Takes a structure build_collision_data made (shared, never changed).
  explicit CollisionModel(std::shared_ptr<const CollisionModelData> data);
  ~CollisionModel();
  CollisionModel(const CollisionModel&) = default;  // shares the structure
  CollisionModel(CollisionModel&&) noexcept;
  CollisionModel& operator=(CollisionModel&&) noexcept;

  std::size_t triangle_count() const;
  std::size_t memory_bytes() const;     // all collision structures of this part
  const CollisionModelData& data() const { return *data_; }
  const std::shared_ptr<const CollisionModelData>& shared_data() const { return data_; }

 private:
  std::shared_ptr<const CollisionModelData> data_;
};

struct DistanceResult;

struct CollideRequest {
  // Intersecting triangle pairs to list; 0: stop at the first (it is listed).
  std::size_t max_triangle_pairs = 16;
  // When set and the sets touch: filled exactly as distance() at this pose
  // would fill it (distance 0, a common point of the first pair listed), so
  // a caller that wants both needs one traversal, not two. Untouched when
  // they do not touch. nullptr: not wanted.
  DistanceResult* contact = nullptr;
  // The rigid-rigid descent's axis-aligned cull of child node pairs before
  // their oriented-box test (collision_model.cpp). It drops only pairs that
  // hold no contact, so the listing, its order and the contact are the same
  // either way; false only for the tests that show it.
  bool box_cull = true;
  // The same descent's cull of a leaf against the other side's node box by
  // the leaf's triangles' planes and the box's face axes (collision_model.cpp):
  // the same guarantee as box_cull; false only for the tests that show it.
  bool leaf_cull = true;
  // Whether two rigid parts whose root boxes (roots_apart) are apart in the
  // world (by more than near_below, when asked) are answered there, before
  // the working frame is set up: apart, not near, one node pair visited.
  // The descent's first test would prove the same; false only for the
  // tests that show it changes no answer.
  bool root_cull = true;
  // When > 0: also whether the sets come closer than this (m), in the
  // same traversal (CollideResult::near). The descent's culls are widened
  // by it until the answer is known, so they keep the node pairs that may
  // hold a triangle pair that close; they keep every pair that may touch
  // as before, in the same order, so the collision answer, the listing,
  // its order and the contact are the same as without it. 0: not asked.
  double near_below = 0.0;
};

struct CollideResult {
  bool collide = false;                 // true when the sets touch or intersect (exact)
  std::vector<std::pair<std::uint32_t, std::uint32_t>> triangle_pairs;  // (index in a, index in b)
  // near_below asked and the sets apart: true when some triangle pair may be
  // closer than near_below; false proves that distance() at this pose, with
  // an upper_bound of at most near_below, finds nothing (every triangle
  // pair's distance as its kernel computes it is at least near_below).
  // Also true when the sets touch.
  bool near = false;
  std::uint64_t node_pairs_visited = 0;   // statistics: BVH node pairs popped
  std::uint64_t triangle_pairs_tested = 0;  // statistics: exact triangle tests run
};

struct DistanceRequest {
  // Only distances strictly below this are searched for (m); the best distance
  // found so far across a state's pairs goes here so it prunes the rest.
  double upper_bound = std::numeric_limits<double>::infinity();
  // Relative tolerance (like FCL's rel_err): a node or triangle pair is
  // skipped when its lower bound times (1 + rel_tolerance) reaches the best
  // distance, so the answer is within that factor of the exact one. 0: exact.
  double rel_tolerance = 0.0;
  // Absolute tolerance (m): node and triangle pairs whose lower bound is
  // within this of the best so far are skipped, so the answer is at most
  // this much above the minimum of the triangle-pair kernel values. Without
  // it, pairs tied at the minimum (parallel faces at one distance, common in
  // CAD models) must all run the full kernel, since rounding slack keeps
  // their lower bounds just under the best. 0: exact.
  double abs_tolerance = 0.0;
  // Coherence seed: model slots (CollisionModelData::triangles order) of a
  // triangle pair, usually the previous state's closest pair. Its distance at
  // this pose is computed first and bounds the search; the answer is the
  // same as without it. -1: no seed.
  std::int64_t seed_slot_a = -1;
  std::int64_t seed_slot_b = -1;
  // A yes/no question: stop at the first triangle pair found below
  // upper_bound. found then says only that the distance is below it, and
  // distance is that pair's (an upper bound on the minimum); not found
  // proves it as without this flag.
  bool first_below = false;
  // The caller's exact collision test (collide) found no contact: the
  // search skips its own. Only set it after such a test at this very pose.
  bool known_disjoint = false;
  // The descent's cull of a leaf against the other side's node box
  // (CollideRequest::leaf_cull), here beyond the best distance: the same
  // answer either way; false only for the tests that show it.
  bool leaf_cull = true;
  // The descent's cull, once a pair is found, of node pairs whose every
  // triangle pair the leaves' own triangle-box test would skip (tight node
  // boxes, collision_model.cpp): what keeps ties of parallel faces cheap.
  // The same answer either way; false only for the tests that show it.
  bool tie_cull = true;
  // Rigid parts whose root boxes are apart in the world by more than
  // upper_bound (roots_apart) hold no pair below it: nothing found, before
  // the working frame is set up (one node pair visited). The same answer
  // either way; false for a caller whose bounds seldom clear the root
  // boxes (a state's exact pass, bounded by its best so far), where the
  // test would cost more than it saves, and for the tests that show it.
  bool root_cull = true;
  // Fill DistanceResult::beyond where nothing is found (the motion checks'
  // samples read it); off, nothing is spent on it.
  bool beyond = false;
};

struct DistanceResult {
  bool found = false;                   // a distance below upper_bound was found
  double distance = std::numeric_limits<double>::infinity();  // m, world frame; 0 when touching
  Vec3 point_a = Vec3::Zero();          // closest point on a, world frame (m)
  Vec3 point_b = Vec3::Zero();          // closest point on b, world frame (m)
  std::uint32_t triangle_a = 0;          // triangle index in a's mesh (valid when found)
  std::uint32_t triangle_b = 0;          // triangle index in b's mesh (valid when found)
  std::uint32_t slot_a = 0;              // the same triangles as model slots (a seed for the next state)
  std::uint32_t slot_b = 0;
  std::uint64_t node_pairs_visited = 0;   // statistics: BVH node pairs expanded or tested
  std::uint64_t triangle_pairs_tested = 0;  // statistics: triangle distance kernels run
  // Where nothing was found below upper_bound: a lower bound of the
  // distance that the search proved on its way, often well beyond what the
  // request's tolerance alone proves (upper_bound / (1 + rel_tolerance) -
  // abs_tolerance). From the root boxes where they ended it (root_cull: at
  // least upper_bound), else the least bound of the node pairs the descent
  // dropped unvisited, and its cut where it visited leaf pairs. 0 where
  // nothing is known, where something was found, and where the request did
  // not ask (DistanceRequest::beyond).
  double beyond = 0.0;
};

// Transforms are affine in general (scale actions); distances are Euclidean
// in the world frame. Intersection is decided exactly on the posed double
// coordinates: touching counts as colliding.
// "Posed" means the query's working frame (collision_model.cpp): a's own
// frame when ta is rigid (b's vertices mapped once by ta^-1 tb and rounded),
// b's frame when only tb is rigid, else the world frame. The exact decision
// is on those doubles; a world-frame rounding of the same pose can differ
// only for contacts within a few ulps of touching.
// Both are thread-safe (a small thread_local stack; no shared mutable state).
void collide(const CollisionModel& a, const Affine& ta, const CollisionModel& b, const Affine& tb,
             const CollideRequest& request, CollideResult& result);

void distance(const CollisionModel& a, const Affine& ta, const CollisionModel& b, const Affine& tb,
              const DistanceRequest& request, DistanceResult& result);

// True when two parts posed by rigid ta and tb are proven more than `reach`
// (m) apart by their root boxes posed in the world (the axis-aligned boxes
// of their own frames, then their oriented boxes): the first test of
// collide() and of distance() below a bound (CollideRequest::root_cull,
// DistanceRequest::root_cull). False for scaled or non-finite poses and
// empty parts: nothing is proven then.
bool roots_apart(const CollisionModel& a, const Affine& ta, const CollisionModel& b, const Affine& tb,
                 double reach);

}  // namespace plancheck
