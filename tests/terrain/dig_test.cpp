// SPDX-License-Identifier: MIT
// Digging: the template model against closed forms on flat ground, the swept
// model's conservation and repose, and the default plans' scoops.
#include "src/checks/dig.h"
#include "src/geometry/heightfield.h"
#include "src/scene/plan.h"
#include "src/scene/scene_loader.h"

#include "tests/support/fixtures.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>

namespace plancheck {
namespace {

constexpr double kPi = 3.14159265358979323846;

// An n x n grid of cell h at height z, samples at (c*h, r*h).
Dem flat_grid(int n, double h, double z) {
  Dem d;
  d.ncols = d.nrows = n;
  d.cellsize = h;
  d.z.assign(static_cast<std::size_t>(n) * n, z);
  d.valid.assign(d.z.size(), 1);
  return d;
}

// A scene holding just what the digger reads: terrain origin, scoop block,
// and the scoop part's mesh (a box, for the swept model).
Scene dig_scene(const ScoopTemplate& t, const std::string& model, double capacity, const Mesh& scoop = {}) {
  Scene s;
  s.terrain = TerrainConfig{};
  Part p;
  p.name = "Scoop";
  p.mesh = scoop;
  s.parts.push_back(p);
  ScoopConfig sc;
  sc.part = "Scoop";
  sc.part_index = 0;
  sc.width = 0.1;
  sc.templ = t;
  sc.model = model;
  sc.capacity = capacity;
  s.scoop = sc;
  return s;
}

double max_slope_excess(const Dem& g, double angle) {
  double worst = -1e300;
  const double lim = std::tan(angle) * g.cellsize;
  for (int r = 0; r < g.nrows; ++r)
    for (int c = 0; c < g.ncols; ++c)
      for (auto [dc, dr] : {std::pair{1, 0}, {0, 1}, {1, 1}, {-1, 1}}) {
        const int nc = c + dc, nr = r + dr;
        if (nc < 0 || nc >= g.ncols || nr >= g.nrows) continue;
        const double l = (dc && dr) ? lim * std::sqrt(2.0) : lim;
        worst = std::max(worst, std::abs(g.height(c, r) - g.height(nc, nr)) - l);
      }
  return worst;
}

TEST(TemplateF, PitInsideRimNearTheEdge) {
  const ScoopTemplate t{-1.0, 0.25, 0.7};
  EXPECT_EQ(template_f(t, 0.0), -1.0);
  EXPECT_EQ(template_f(t, 0.69), -1.0);
  EXPECT_NEAR(template_f(t, 0.7), 0.0, 1e-15);
  EXPECT_NEAR(template_f(t, 0.85), 0.25, 1e-15);
  EXPECT_NEAR(template_f(t, 1.0), 0.0, 1e-15);
  EXPECT_EQ(template_f(t, 1.01), 0.0);
}

TEST(TemplateDig, FlatGroundKnownDepthGivesTheExactPitVolume) {
  // M at sample (20, 20) = (0.2, 0.2), 3 cm under flat ground at z = 0;
  // the pit radius 0.075 m falls between lattice circles (no sample on it).
  const double h = 0.01, depth = 0.03;
  const ScoopTemplate t{-1.0, 0.0, 0.75};
  const Scene s = dig_scene(t, "template", 1.0);
  const Digger digger(s, flat_grid(41, h, 0.0));
  Dem g = digger.undisturbed();
  const Dem start = g;
  ASSERT_TRUE(digger.dig_template(g, start, Vec3(0.2, 0.2, -depth)));
  int inside = 0;
  for (int i = -10; i <= 10; ++i)
    for (int j = -10; j <= 10; ++j)
      if (i * i + j * j <= 56) ++inside;  // (7.5 cells)^2 = 56.25
  for (int r = 0; r < 41; ++r)
    for (int c = 0; c < 41; ++c) {
      const int i = c - 20, j = r - 20;
      EXPECT_EQ(g.height(c, r), i * i + j * j <= 56 ? -depth : 0.0) << c << "," << r;
    }
  const double exact = inside * depth * h * h;
  EXPECT_NEAR(pit_volume(start, g), exact, 1e-15 * exact * 200);
  // The lattice count approximates the disc: within 2 % of pi r^2 d.
  EXPECT_NEAR(pit_volume(start, g), kPi * 0.075 * 0.075 * depth, 0.02 * exact);
  // The same M again digs nothing more (pit = -1 lowers to Z_M exactly).
  const Dem once = g;
  digger.dig_template(g, start, Vec3(0.2, 0.2, -depth));
  EXPECT_EQ(g.z, once.z);
}

TEST(TemplateDig, RimRisesByTheTemplateAndOnlyBelowTheSurface) {
  const double h = 0.01, depth = 0.02;
  const ScoopTemplate t{-0.5, 0.25, 0.7};
  const Scene s = dig_scene(t, "template", 1.0);
  const Digger digger(s, flat_grid(41, h, 0.1));
  Dem g = digger.undisturbed();
  const Dem start = g;
  EXPECT_FALSE(digger.dig_template(g, start, Vec3(0.2, 0.2, 0.1 + 1e-9)));  // above the surface
  EXPECT_EQ(g.z, start.z);
  ASSERT_TRUE(digger.dig_template(g, start, Vec3(0.2, 0.2, 0.1 - depth)));
  double raised = 0.0, lowered = 0.0;
  for (int r = 0; r < 41; ++r)
    for (int c = 0; c < 41; ++c) {
      const double l = std::hypot((c - 20) * h, (r - 20) * h);
      double expect = 0.1;
      if (l <= 0.1) expect += depth * template_f(t, l / 0.1);  // d = Z_N - Z_M = depth on flat ground
      EXPECT_NEAR(g.height(c, r), expect, 1e-15) << c << "," << r;
      if (l < 0.07) lowered += depth * 0.5;
      else if (l <= 0.1) raised += depth * template_f(t, l / 0.1);
    }
  EXPECT_NEAR(pit_volume(start, g), lowered * h * h, 1e-15);
  EXPECT_NEAR(soil_volume(g) - soil_volume(start), (raised - lowered) * h * h, 1e-15);
}

TEST(SweptDig, BoxScoopCarvesItsFootprintAndConservesSoil) {
  // A box scoop 10.1 x 6.1 cm pushed 3 cm into flat ground at z = 1:
  // 11 x 7 cell centres under it, each carved by exactly 3 cm.
  const double h = 0.01, depth = 0.03;
  const Mesh box = testing::box_mesh(Vec3(-0.0505, -0.0305, 0.0), Vec3(0.0505, 0.0305, 0.05));
  const Scene s = dig_scene({}, "swept", 1.0, box);
  const Digger digger(s, flat_grid(61, h, 1.0));
  Dem g = digger.undisturbed();
  const double before = soil_volume(g);
  Affine pose = Affine::Identity();
  pose.translation() = Vec3(0.3, 0.3, 1.0 - depth);
  double taken = 0, spilled = 0;
  std::array<int, 4> w{};
  const double carved = digger.dig_swept(g, pose, 1.0, taken, spilled, &w);
  const double exact = 77 * depth * h * h;
  EXPECT_NEAR(carved, exact, 1e-6 * exact);  // Embree is single precision
  EXPECT_EQ(taken, carved);
  EXPECT_EQ(spilled, 0.0);
  EXPECT_NEAR(before - soil_volume(g), taken, 1e-9 * carved);
  // While the scoop sits in the cut it holds the walls: the cut is still flat at 3 cm.
  for (int r = 27; r <= 33; ++r)
    for (int c = 25; c <= 35; ++c) EXPECT_NEAR(g.height(c, r), 1.0 - depth, 1e-7) << c << "," << r;
  // Once it leaves, the walls relax to the angle of repose, soil still conserved.
  Digger::relax(g, s.scoop->repose_angle, w[0], w[1], w[2], w[3]);
  EXPECT_LE(max_slope_excess(g, s.scoop->repose_angle), kReposeTolerance + 1e-15);
  EXPECT_NEAR(before - soil_volume(g), taken, 1e-9 * carved);
  EXPECT_GT(g.height(25, 30), 1.0 - depth + 1e-3);  // soil slid back into the cut
}

TEST(SweptDig, OverflowIsSpilledAsARimAndSoilIsConserved) {
  const double h = 0.01, depth = 0.04;
  const Mesh box = testing::box_mesh(Vec3(-0.0505, -0.0305, 0.0), Vec3(0.0505, 0.0305, 0.05));
  const Scene s = dig_scene({}, "swept", 1e-4, box);
  const Digger digger(s, flat_grid(61, h, 1.0));
  Dem g = digger.undisturbed();
  const double before = soil_volume(g);
  Affine pose(Eigen::AngleAxisd(0.3, Vec3(0.2, 1, 0.1).normalized()));
  pose.translation() = Vec3(0.31, 0.29, 1.0 - depth);
  double taken = 0, spilled = 0;
  std::array<int, 4> w{};
  const double carved = digger.dig_swept(g, pose, 1e-4, taken, spilled, &w);
  ASSERT_GT(carved, 1e-4);
  EXPECT_EQ(taken, 1e-4);
  EXPECT_NEAR(spilled, carved - 1e-4, 1e-18);
  EXPECT_NEAR(before - soil_volume(g), taken, 1e-9 * carved);
  Digger::relax(g, s.scoop->repose_angle, w[0], w[1], w[2], w[3]);
  EXPECT_LE(max_slope_excess(g, s.scoop->repose_angle), kReposeTolerance + 1e-15);
  EXPECT_NEAR(before - soil_volume(g), taken, 1e-9 * carved);
  // Some sample now stands above the original ground: the spilled rim.
  double top = 0;
  for (double z : g.z) top = std::max(top, z);
  EXPECT_GT(top, 1.0);
}

TEST(Repose, APileRelaxesToTheAngleAndKeepsItsVolume) {
  Dem g = flat_grid(41, 0.02, 0.0);
  g.z[static_cast<std::size_t>(20 * 41 + 20)] = 0.5;  // a 50 cm spike of soil
  g.z[static_cast<std::size_t>(21 * 41 + 20)] = 0.3;
  const double before = soil_volume(g);
  const double angle = 35.0 * kPi / 180.0;
  Digger::relax(g, angle, 20, 20, 20, 21);
  EXPECT_LE(max_slope_excess(g, angle), kReposeTolerance + 1e-15);
  EXPECT_NEAR(soil_volume(g), before, 1e-12 * before);
  EXPECT_LT(g.height(20, 20), 0.5);
}

// The default dataset (build/generate_change5 datasets/change5, as `make test` does).
TEST(DefaultPlans, ScoopsReachTheSoilAndCollectWithinCapacity) {
  const std::filesystem::path dir = std::filesystem::path(PLANCHECK_SOURCE_DIR) / "datasets/change5";
  if (!std::filesystem::exists(dir / "scene.json")) GTEST_SKIP() << "run build/generate_change5 " << dir;
  Scene scene = load_scene(dir / "scene.json");
  ASSERT_TRUE(scene.scoop);
  for (const std::string model : {"template", "swept"}) {
    scene.scoop->model = model;
    const Digger digger(scene);
    for (const auto& entry : std::filesystem::directory_iterator(dir / "plans")) {
      const Plan plan = load_plan(scene, entry.path());
      Dem g = digger.undisturbed();
      std::vector<DigStep> steps;
      const DigSummary sum = digger.dig_plan(plan.states, g, steps);
      SCOPED_TRACE(model + " " + plan.name);
      if (plan.name == "plan10") {  // the can-carrying plan never touches the soil
        EXPECT_FALSE(sum.dug);
        EXPECT_EQ(sum.collected_volume, 0.0);
        continue;
      }
      // Plans 01-09 scoop 3 cm deep at their sites (datasets/README.md).
      EXPECT_TRUE(sum.dug);
      EXPECT_GT(sum.deepest, 0.025);
      EXPECT_LT(sum.deepest, 0.045);
      EXPECT_GT(sum.collected_volume, 0.1 * scene.scoop->capacity);
      EXPECT_LE(sum.collected_volume, scene.scoop->capacity);
      // What was dug beyond the capacity is flagged (template plan03's pit is
      // 1 % larger than the scoop; the swept scoop's whole body pushes soil,
      // up to 1.75 x capacity, the rest spilled), and the collected part capped.
      EXPECT_LT(sum.dug_volume, 2.0 * scene.scoop->capacity);
      EXPECT_EQ(sum.over_capacity, sum.dug_volume > scene.scoop->capacity) << sum.dug_volume;
      EXPECT_NEAR(sum.collected_mass, sum.collected_volume * scene.scoop->bulk_density, 1e-12);
      // Soil is conserved along the whole plan: grid + scoop (swept model).
      if (model == "swept") {
        EXPECT_NEAR(soil_volume(digger.undisturbed()) - soil_volume(g), sum.collected_volume,
                    1e-9 * sum.dug_volume);
      }
      // The scoop volume never shrinks along the plan (nothing is poured back in the model).
      for (std::size_t i = 1; i < steps.size(); ++i) EXPECT_GE(steps[i].volume, steps[i - 1].volume);
    }
  }
}

// Refit over each state's reported changed samples keeps the heightfield
// equal to one built fresh from the dug grid, for both dig models.
TEST(DefaultPlans, RefitOverReportedChangesEqualsAFreshHeightfield) {
  const std::filesystem::path dir = std::filesystem::path(PLANCHECK_SOURCE_DIR) / "datasets/change5";
  if (!std::filesystem::exists(dir / "scene.json")) GTEST_SKIP() << "run build/generate_change5 " << dir;
  Scene scene = load_scene(dir / "scene.json");
  ASSERT_TRUE(scene.scoop);
  for (const std::string model : {"template", "swept"}) {
    scene.scoop->model = model;
    const Digger digger(scene);
    for (const std::string name : {"plan01", "plan04"}) {
      SCOPED_TRACE(model + " " + name);
      const Plan plan = load_plan(scene, dir / "plans" / (name + ".csv"));
      Dem g = digger.undisturbed();
      Heightfield field(g, digger.origin());
      std::vector<DigStep> steps;
      int changed_states = 0;
      digger.dig_plan(plan.states, g, steps, [&](std::size_t s, const Dem& now, const SampleRect& changed) {
        changed_states += changed.empty() ? 0 : 1;
        field.refit(now, changed);
        const Heightfield fresh(now, digger.origin());
        for (int r = 0; r < now.nrows; ++r)
          for (int c = 0; c < now.ncols; ++c)
            if (field.z(c, r) != fresh.z(c, r)) {
              ADD_FAILURE() << "state " << s << " sample " << c << " " << r;
              return;
            }
        for (std::size_t l = 0; l < field.levels().size(); ++l)
          for (std::size_t b = 0; b < field.levels()[l].blocks.size(); ++b)
            if (field.levels()[l].blocks[b].zmin != fresh.levels()[l].blocks[b].zmin ||
                field.levels()[l].blocks[b].zmax != fresh.levels()[l].blocks[b].zmax) {
              ADD_FAILURE() << "state " << s << " level " << l << " block " << b;
              return;
            }
      });
      EXPECT_GT(changed_states, 5);
    }
  }
}

}  // namespace
}  // namespace plancheck
