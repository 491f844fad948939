// SPDX-License-Identifier: MIT
// Configurations the sweep certifies closer than the margin without their
// exact distance (SweepCertifier::clear_point): block by block against
// Checker::check_state (verify's state check) at every configuration: the
// same verdict, the distance never above the exact one and equal where the
// block marks it exact, and a configuration near the margin settled by an
// exact search, never by the certificate.
#include "support/bar_scene.h"
#include "support/fixtures.h"
#include "support/sanitized.h"

#include "src/checks/sweep_certify.h"
#include "src/checks/sweep_grid.h"
#include "src/checks/verify.h"
#include "src/scene/scene_loader.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace plancheck {
namespace {

using testing::TempDir;

const std::filesystem::path kChange5 = std::filesystem::path(PLANCHECK_SOURCE_DIR) / "datasets/change5";

SweepGrid grid_of(const Scene& scene, const std::string& spec) {
  SweepGrid g;
  g.axes = sweep_axes_from_grid(scene, spec);
  g.reference = scene.reference_parameters;
  for (const SweepAxis& a : g.axes) g.total *= a.values.size();
  return g;
}

struct Compared {
  std::size_t configurations = 0, cleared = 0, exact = 0, clearance = 0;
  bool exact_at_probe = false;  // whether the configuration `probe` got an exact distance
};

// Every block of the grid against check_state at each configuration.
Compared compare(const Checker& checker, const Scene& scene, const SweepGrid& grid, std::size_t probe = SIZE_MAX) {
  const SweepCertifier certifier(checker, scene, grid);
  Compared out;
  std::size_t failures = 0;
  std::vector<std::size_t> first, size, digit;
  std::vector<double> params;
  for (std::size_t b = 0; b < certifier.blocks().blocks; ++b) {
    SweepBlockResult r;
    certifier.check_block(b, r);
    certifier.blocks().block(b, first, size);
    const std::size_t d = size.size();
    digit.assign(d, 0);
    for (std::size_t i = 0; i < r.verdict.size(); ++i) {
      std::size_t index = 0;
      for (std::size_t k = 0; k < d; ++k) index = index * grid.axes[k].values.size() + first[k] + digit[k];
      grid.decode(index, params, nullptr);
      StateResult st;
      checker.check_state(params, st);
      const Verdict v = state_verdict(st, scene.safety_margin);
      const double exact = st.collision ? 0.0 : st.min_distance;
      bool ok = r.verdict[i] == v;
      if (r.exact[i])  // equal up to the search's tie tolerance
        ok = ok && std::abs(r.distance[i] - exact) <= kDistanceTieTolerance;
      else
        ok = ok && r.distance[i] <= exact;
      if (!ok && ++failures <= 5)
        ADD_FAILURE() << "configuration " << index << ": verdict " << static_cast<int>(r.verdict[i]) << " against "
                      << static_cast<int>(v) << ", distance " << r.distance[i] << (r.exact[i] ? " (exact)" : " (bound)")
                      << " against " << exact;
      ++out.configurations;
      out.exact += r.exact[i];
      out.clearance += v == Verdict::kClearance;
      out.cleared += v == Verdict::kClearance && !r.exact[i];
      if (index == probe) out.exact_at_probe = r.exact[i] != 0;
      for (std::size_t k = d; k-- > 0;) {
        if (++digit[k] < size[k]) break;
        digit[k] = 0;
      }
    }
  }
  EXPECT_EQ(failures, 0u);
  EXPECT_EQ(out.configurations, grid.total);
  return out;
}

// The default arm on a grid across the margin band (contacts, clearance
// and safe configurations side by side).
TEST(SweepClearance, DefaultArmEqualsCheckingEachConfiguration) {
  ASSERT_TRUE(std::filesystem::exists(kChange5 / "scene.json")) << "run `make dataset` first";
  const Scene scene = load_scene(kChange5 / "scene.json");
  const Checker checker(scene, 1);
  const SweepGrid grid = grid_of(scene, testing::kSanitized ? "J1=5:5:5,J2=-20:55:5,J3=-160:0:5,J4=-80:140:10"
                                                            : "J1=5:5:5,J2=-20:130:5,J3=-160:0:5,J4=-80:140:10");
  const Compared c = compare(checker, scene, grid);
  std::printf("[ arm ] %zu configurations, %zu in clearance, %zu of them certified without their distance, "
              "%zu exact\n",
              c.configurations, c.clearance, c.cleared, c.exact);
  EXPECT_GT(c.clearance, 500u);
  EXPECT_GT(c.cleared, c.clearance / 4);  // the certificate did its work
  EXPECT_LT(c.cleared, c.clearance);     // and some clearance got exact searches (the band's edges)
}

// The bar over the slab on a grid of 1e-8-degree steps across the angle
// where the distance is 5 cm (about 3e-10 m a step), the margin put 2G
// above one configuration's exact distance (G the guard bound,
// SweepCertifier::cutoff): below the margin, but closer to it than the
// certificate's slack (4G and the tie tolerance), so it gets an exact
// search, while the configurations farther below are cleared. Those
// before it are answered exactly too (at or just below the margin), so
// the certificate is asked there, with its seed.
TEST(SweepClearance, NearTheMarginIsSettledExactly) {
  TempDir dir("sweep-clearance-bar");
  testing::write_bar_scene(dir);
  Scene scene = load_scene(dir / "scene.json");
  const Checker checker(scene, 1);
  double lo = 0.0, hi = 30.0;  // degrees: bar_distance falls from 0.1 to below 0
  for (int n = 0; n < 100; ++n) (testing::bar_distance(0.5 * (lo + hi)) > 0.05 ? lo : hi) = 0.5 * (lo + hi);
  char spec[160];
  std::snprintf(spec, sizeof spec, "J1=%.12f:%.12f:0.00000001", lo - 5e-8, lo + 35.5e-8);
  const SweepGrid grid = grid_of(scene, spec);
  ASSERT_EQ(grid.total, 41u) << spec;
  const std::size_t probe = 8;
  std::vector<double> params;
  grid.decode(probe, params, nullptr);
  StateResult st;
  checker.check_state(params, st);
  ASSERT_FALSE(st.collision);
  const double d0 = st.min_distance;
  const double g = (SweepCertifier(checker, scene, grid).cutoff() - scene.safety_margin - kDistanceTieTolerance) / 4.0;
  ASSERT_GT(g, 0.0);
  scene.safety_margin = d0 + 2.0 * g;
  const Compared c = compare(checker, scene, grid, probe);
  std::printf("[ bar ] %zu configurations, %zu in clearance, %zu of them certified without their distance\n",
              c.configurations, c.clearance, c.cleared);
  EXPECT_GT(c.cleared, 10u);
  EXPECT_GT(c.clearance, c.cleared + 2);  // the probe and those before it
  EXPECT_TRUE(c.exact_at_probe) << "configuration " << probe << " at " << d0 << " m, margin "
                                << scene.safety_margin << " m: certified without its exact distance";
}

}  // namespace
}  // namespace plancheck
