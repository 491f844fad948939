// SPDX-License-Identifier: MIT
// The one descent over pairs of bounding-volume nodes, written once for every
// pair query: part vs part (two BVHs) and part vs terrain (a BVH and the
// heightfield's block pyramid), for collision and for distance. What happens
// at a node pair (cull, bound, split) and at a leaf pair (exact kernels) is
// the caller's, given as a query object; the order in which pairs are visited
// is this file's, so every query walks the same way.
//
// Depth first on an explicit stack that the caller owns and reuses (a
// thread_local vector), so the hot loop does not allocate once the stack has
// grown to the tree depth. No I/O, no threads, no exceptions.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

namespace plancheck {

// Most children a split yields (two for a binary BVH node, four for a
// pyramid block).
inline constexpr int kMaxPairChildren = 4;

// Overlap descent: stops at the first leaf pair that asks to stop.
// The query Q provides
//   using Pair;                          a node pair, trivially copyable
//   using Cull;                          what the cull test leaves for split()
//   void visited();                      counts a popped pair
//   bool disjoint(const Pair&, Cull&);   true: proven apart, the pair is dropped
//   bool leaf_pair(const Pair&);         both sides are leaves
//   bool leaves(const Pair&);            exact tests; false: stop the descent
//   int split(const Pair&, const Cull&, Pair* kids);  children, first visited first
template <class Q>
void overlap_descent(Q& q, std::vector<typename Q::Pair>& stack, const typename Q::Pair& root) {
  using Pair = typename Q::Pair;
  stack.clear();
  stack.push_back(root);
  while (!stack.empty()) {
    const Pair p = stack.back();
    stack.pop_back();
    q.visited();
    typename Q::Cull cull;
    if (q.disjoint(p, cull)) continue;
    if (q.leaf_pair(p)) {
      if (!q.leaves(p)) return;
      continue;
    }
    Pair kids[kMaxPairChildren];
    const int n = q.split(p, cull, kids);
    for (int k = n - 1; k >= 0; --k) stack.push_back(kids[k]);
  }
}

// Items ordered farthest first by key (insertion sort), so the nearest is
// pushed last and popped first. At most four items; std::sort on such a
// small array trips GCC 12's -Warray-bounds.
template <class T, class Key>
void farthest_first(T* items, int n, Key key) noexcept {
  for (int i = 1; i < n; ++i)
    for (int j = i; j > 0 && key(items[j - 1]) < key(items[j]); --j) std::swap(items[j - 1], items[j]);
}

// Distance descent, nearest child first, pruned by the query's current
// bound: a pair is expanded only while its squared lower bound (Pair::lower2)
// is below q.best2(), which the leaves lower as they find closer pairs.
// The query Q provides
//   using Pair;                          a node pair with a double lower2
//   double best2() const;                the current pruning bound, squared
//   void visited();                      counts an expanded pair
//   bool leaf_pair(const Pair&);         both sides are leaves
//   bool leaves(const Pair&);            exact kernels; false: nothing can beat
//                                        the best any more, stop
//   int split(const Pair&, Pair* kids);  children with their lower2, any order
// The descent from the pairs on `stack` (nearest on top).
// A query with `void pruned(double lower2)` is told the bound of every pair
// it drops without visiting (the least of them bounds what it did not look
// at: DescentFloor).
// What a distance descent that found nothing proved (DistanceResult::
// beyond): the pairs it dropped unvisited (pruned) and, where it visited
// leaf pairs or dropped pairs by another test (at_cut), its cut (each of
// those triangle pairs was kept from the best by a bound at least that)
// bound the distance from below. beyond() is 0 when nothing is known. A
// query that drops a pair by any test other than its lower2 against the
// cut (an infinite lower2 standing for "settled") must set at_cut: an
// infinite bound passed to pruned() counts as nothing there.
struct DescentFloor {
  double floor2 = std::numeric_limits<double>::infinity();
  bool at_cut = false;
  void pruned(double l2) noexcept {
    if (!(l2 >= floor2)) floor2 = l2;  // a NaN stays
  }
  double beyond(double cut) const noexcept {
    double b = std::sqrt(floor2) * (1.0 - 1e-15);
    if (at_cut) b = std::min(b, cut);
    return b >= 0.0 && b < std::numeric_limits<double>::infinity() ? b : 0.0;
  }
};

template <class Q>
void distance_descent_from(Q& q, std::vector<typename Q::Pair>& stack) {
  using Pair = typename Q::Pair;
  constexpr bool kTell = requires(Q& x) { x.pruned(0.0); };
  while (!stack.empty()) {
    const Pair p = stack.back();
    stack.pop_back();
    if (!(p.lower2 < q.best2())) {
      if constexpr (kTell) q.pruned(p.lower2);
      continue;
    }
    q.visited();
    if (q.leaf_pair(p)) {
      if (!q.leaves(p)) return;
      continue;
    }
    Pair kids[kMaxPairChildren];
    const int n = q.split(p, kids);
    // Closest pair on top of the stack: visited first, it tightens the bound.
    farthest_first(kids, n, [](const Pair& c) { return c.lower2; });
    for (int k = 0; k < n; ++k) {
      if (kids[k].lower2 < q.best2())
        stack.push_back(kids[k]);
      else if constexpr (kTell)
        q.pruned(kids[k].lower2);
    }
  }
}

template <class Q>
void distance_descent(Q& q, std::vector<typename Q::Pair>& stack, const typename Q::Pair& root) {
  stack.clear();
  stack.push_back(root);
  distance_descent_from(q, stack);
}

// For a search with no bound to start from (no seed, no upper bound): depth
// first, its first leaves lie wherever the nearest child led, and their
// loose best makes the rest of the descent expand more. So pairs are popped
// best-first (a binary heap, nearest lower bound first) until a leaf gives
// the search its first bound; then the pairs left, nearest on top, go on
// depth first, which needs no heap and is as good from a bound. Two-mesh
// bench, distance on the poses apart: depth first 123 node pairs and 88
// triangle distances a pose, best-first throughout 104 and 70 (-14% time),
// best-first until the first bound 107 and 64 (-4% more); from the answer's
// own pair as the seed, 104 and 40.
template <class Q>
void distance_best_first(Q& q, std::vector<typename Q::Pair>& work, const typename Q::Pair& root) {
  using Pair = typename Q::Pair;
  const auto farther = [](const Pair& x, const Pair& y) { return x.lower2 > y.lower2; };
  constexpr double kNone = std::numeric_limits<double>::infinity();
  work.clear();
  work.push_back(root);
  while (!work.empty()) {
    std::pop_heap(work.begin(), work.end(), farther);
    const Pair p = work.back();
    work.pop_back();
    if (!(p.lower2 < q.best2())) return;  // the nearest left: none can improve
    q.visited();
    if (q.leaf_pair(p)) {
      if (!q.leaves(p)) return;
      if (q.best2() < kNone) {
        std::sort(work.begin(), work.end(), farther);  // nearest last: on top
        distance_descent_from(q, work);
        return;
      }
      continue;
    }
    Pair kids[kMaxPairChildren];
    const int n = q.split(p, kids);
    for (int k = 0; k < n; ++k)
      if (kids[k].lower2 < q.best2()) {
        work.push_back(kids[k]);
        std::push_heap(work.begin(), work.end(), farther);
      }
  }
}

}  // namespace plancheck
