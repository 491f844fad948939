// SPDX-License-Identifier: MIT
// Kernel-level stability: tri_tri_overlap and tri_distance against the exact
// CGAL reference on stiff and extreme configurations (issue 6, part 2).
//
// What is asserted, for every case, for all 72 vertex orders (6 rotations and
// reflections of each triangle, both argument orders):
//  - tri_tri_overlap and tri_distance().intersecting equal the exact flag;
//  - an exactly touching or intersecting pair has distance exactly 0;
//  - |distance - exact| <= kDistanceBound * eps * M, where M is the largest
//    coordinate magnitude of the pair (the bound of a double computation on
//    coordinates of that size; see stated_bound below);
//  - a disjoint pair never reports 0 (that would be a wrong flag in a
//    distance-only query) unless the exact distance is below the bound;
//  - the pair translated by the lunar radius (1,737.4 km, along x and along a
//    generic direction) gives the exact flag of the translated doubles, the
//    same distance as untranslated to 1e-6 m, and the same flags whenever the
//    translation was exact for every coordinate.
#include "kernels/tri_distance.h"
#include "kernels/tri_tri_overlap.h"
#include "stability/cases.h"
#include "stability/exact_reference.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace plancheck::stability {
namespace {

constexpr double kLunarRadius = 1737400.0;  // m
// Distance error bound in units of eps * M (eps = 2^-52, M = largest |coordinate|).
// Observed: under 1 eps * M over every case here; the stated bound leaves a
// factor of 16 for configurations not generated.
constexpr double kDistanceBound = 16.0;

double magnitude(const T9& p, const T9& q) {
  double m = 0.0;
  for (int k = 0; k < 9; ++k) m = std::max({m, std::abs(p[k]), std::abs(q[k])});
  return m;
}

double stated_bound(const T9& p, const T9& q) { return kDistanceBound * DBL_EPSILON * magnitude(p, q); }

// The 6 vertex orders of a triangle.
T9 permuted(const T9& t, int perm) {
  static const int kOrders[6][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1}, {0, 2, 1}, {2, 1, 0}, {1, 0, 2}};
  T9 out;
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) out[3 * i + k] = t[3 * kOrders[perm][i] + k];
  return out;
}

struct Tally {
  std::size_t cases = 0, evaluations = 0, wrong_flags = 0, overlapping = 0;
  double max_error = 0.0;        // m, over the untranslated evaluations
  double max_error_far = 0.0;    // m, over the translated ones
  double max_error_units = 0.0;  // in eps * M, over all
  std::size_t far_cases = 0, far_rounded = 0;
  double max_far_shift = 0.0;    // |distance far - distance near|, m
};

// One pair in all 72 orders; returns the distance of the first order.
double check_orders(const std::string& where, const T9& p, const T9& q, const ExactAnswer& exact, bool far,
                    Tally& t) {
  const double bound = stated_bound(p, q);
  const double m = magnitude(p, q);
  double first = -1.0;
  for (int pp = 0; pp < 6; ++pp)
    for (int qq = 0; qq < 6; ++qq)
      for (int swap = 0; swap < 2; ++swap) {
        const T9 a = permuted(swap ? q : p, pp), b = permuted(swap ? p : q, qq);
        const bool overlap = tri_tri_overlap(&a[0], &a[3], &a[6], &b[0], &b[3], &b[6]);
        const TriDistance d = tri_distance(a.data(), b.data());
        ++t.evaluations;
        const bool flags_ok = overlap == exact.overlap && d.intersecting == exact.overlap;
        if (!flags_ok) ++t.wrong_flags;
        EXPECT_TRUE(flags_ok) << where << " order " << pp << qq << swap << ": overlap " << overlap
                              << " intersecting " << d.intersecting << " exact " << exact.overlap;
        if (exact.overlap) {
          EXPECT_EQ(d.distance, 0.0) << where;
        } else if (exact.distance > bound) {
          EXPECT_GT(d.distance, 0.0) << where;
        }

        const double err = std::abs(d.distance - exact.distance);
        double& max_error = far ? t.max_error_far : t.max_error;
        max_error = std::max(max_error, err);
        if (m > 0) t.max_error_units = std::max(t.max_error_units, err / (DBL_EPSILON * m));
        EXPECT_LE(err, bound) << where << " order " << pp << qq << swap << ": distance " << d.distance
                              << " exact " << exact.distance;
        if (!exact.overlap) {
          Eigen::Vector3d pa, qb;
          const double d2 = tri_distance_disjoint2(a.data(), b.data(), pa, qb);
          EXPECT_LE(std::abs(std::sqrt(d2) - exact.distance), bound) << where << " (disjoint2)";
        }
        if (first < 0) first = d.distance;
      }
  return first;
}

void run_category(const std::string& label, const std::vector<Case>& cases) {
  ASSERT_FALSE(cases.empty());
  std::vector<std::string> names;
  for (const Case& c : cases)
    if (std::find(names.begin(), names.end(), c.category) == names.end()) names.push_back(c.category);
  const V3 generic = V3(0.48, -0.6, 0.64).normalized();
  for (const std::string& name : names) {
    Tally t;
    std::size_t index = 0;
    for (const Case& c : cases) {
      if (c.category != name) continue;
      const std::string where = label + " / " + name + " #" + std::to_string(index++);
      const ExactAnswer exact = exact_tri_tri(c.p.data(), c.q.data());
      ++t.cases;
      t.overlapping += exact.overlap;
      const double near = check_orders(where, c.p, c.q, exact, false, t);
      for (const V3& dir : {V3(V3::UnitX()), generic}) {
        const V3 shift = kLunarRadius * dir;
        const T9 pf = shifted(c.p, shift), qf = shifted(c.q, shift);
        bool exact_shift = true;
        for (int k = 0; k < 9; ++k)
          exact_shift = exact_shift && pf[k] - shift[k % 3] == c.p[k] && qf[k] - shift[k % 3] == c.q[k];
        const ExactAnswer far_exact = exact_tri_tri(pf.data(), qf.data());
        const double far = check_orders(where + " far", pf, qf, far_exact, true, t);
        ++t.far_cases;
        if (!exact_shift) ++t.far_rounded;
        t.max_far_shift = std::max(t.max_far_shift, std::abs(far - near));
        EXPECT_LE(std::abs(far - near), 1e-6) << where << " far: " << far << " vs " << near;
        if (exact_shift) {
          EXPECT_EQ(far_exact.overlap, exact.overlap) << where;
        }
      }
    }
    std::printf("[stability] %-36s cases %4zu (overlap %4zu)  evaluations %6zu  wrong flags %zu  "
                "max |d - exact| %.2g m, far %.2g m (%.2f eps*M)  far cases %zu (%zu rounded), "
                "max |d far - d| %.2g m\n",
                (label + " / " + name).c_str(), t.cases, t.overlapping, t.evaluations, t.wrong_flags,
                t.max_error, t.max_error_far, t.max_error_units, t.far_cases, t.far_rounded, t.max_far_shift);
    EXPECT_EQ(t.wrong_flags, 0u) << name;
  }
}

TEST(KernelStability, Touching) { run_category("touching", touching_cases()); }
TEST(KernelStability, Gaps) { run_category("gaps", gap_cases()); }
TEST(KernelStability, Coplanar) { run_category("coplanar", coplanar_cases()); }
TEST(KernelStability, EdgeEdge) { run_category("edge-edge", edge_edge_cases()); }
TEST(KernelStability, Grazing) { run_category("grazing", grazing_cases()); }
TEST(KernelStability, NearParallel) { run_category("near-parallel", near_parallel_cases()); }
TEST(KernelStability, Degenerate) { run_category("degenerate", degenerate_cases()); }
TEST(KernelStability, Sliver) { run_category("sliver", sliver_cases()); }
TEST(KernelStability, MillimetreBesideMetre) { run_category("mm beside m", mm_beside_m_cases()); }
TEST(KernelStability, Random) { run_category("random", random_cases()); }

}  // namespace
}  // namespace plancheck::stability
