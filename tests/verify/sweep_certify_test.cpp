// SPDX-License-Identifier: MIT
// plancheck sweep's certified regions (src/checks/sweep_certify.h): the
// verdict of every configuration equals checking it on its own
// (--exact-distance, and Checker::check_state, verify's state check, on a
// random sample), distance.npy never exceeds that check's distance, and
// the outputs do not depend on the number of threads. On the default
// scene, on the bar over a slab, and on a thin wall that a box of the grid
// centred far from it could jump over.
#include "support/bar_scene.h"
#include "support/fixtures.h"
#include "support/sanitized.h"

#include "src/checks/sweep_certify.h"
#include "src/checks/sweep_grid.h"
#include "src/scene/kinematics.h"
#include "src/checks/verify.h"
#include "src/scene/scene_loader.h"

#include <cstdio>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstring>
#include <random>

namespace plancheck {
namespace {

using testing::read_text;
using testing::run_command;
using testing::TempDir;
using testing::write_text;

const std::string kPlancheck = std::string(PLANCHECK_BINARY_DIR) + "/plancheck";
const std::filesystem::path kChange5 = std::filesystem::path(PLANCHECK_SOURCE_DIR) / "datasets/change5";

struct SweepRun {
  std::string verdict_bytes, distance_bytes;  // the arrays' data
  std::vector<std::uint8_t> verdict;
  std::vector<float> distance;
  nlohmann::json summary;
};

std::string npy_data(const std::filesystem::path& file) {
  const std::string b = read_text(file);
  if (b.size() < 10) return {};
  const std::size_t len = static_cast<unsigned char>(b[8]) | static_cast<std::size_t>(static_cast<unsigned char>(b[9])) << 8;
  return b.substr(10 + len);
}

SweepRun sweep(const std::filesystem::path& scene, const std::string& options, const std::filesystem::path& out) {
  SweepRun r;
  const int status = run_command(kPlancheck + " sweep " + scene.string() + " " + options + " --quiet --out " +
                                 out.string() + " >/dev/null 2>" + (out.string() + ".err"));
  EXPECT_EQ(status, 0) << read_text(out.string() + ".err");
  if (status != 0) return r;
  r.verdict_bytes = npy_data(out / "verdict.npy");
  r.distance_bytes = npy_data(out / "distance.npy");
  r.verdict.assign(r.verdict_bytes.begin(), r.verdict_bytes.end());
  r.distance.resize(r.distance_bytes.size() / 4);
  std::memcpy(r.distance.data(), r.distance_bytes.data(), r.distance.size() * 4);
  r.summary = nlohmann::json::parse(read_text(out / "sweep.json"));
  return r;
}

// sweep.json without what may differ between runs of the same grid.
nlohmann::json without_timing(nlohmann::json j) {
  j.erase("seconds");
  j.erase("threads");
  return j;
}

// The certified sweep of `grid` against checking every configuration on its
// own, and against itself on one thread. Returns the certified run.
SweepRun expect_certified_equals_exact(const std::filesystem::path& scene, const std::string& grid,
                                       const TempDir& dir) {
  const SweepRun certified = sweep(scene, "--grid " + grid + " --threads 2", dir / "certified");
  const SweepRun exact = sweep(scene, "--grid " + grid + " --threads 2 --exact-distance", dir / "exact");
  const SweepRun one = sweep(scene, "--grid " + grid + " --threads 1", dir / "one");
  EXPECT_EQ(certified.verdict.size(), exact.verdict.size());
  EXPECT_GT(certified.verdict.size(), 0u);
  std::size_t mismatches = 0, above = 0, exact_equal = 0;
  for (std::size_t i = 0; i < std::min(certified.verdict.size(), exact.verdict.size()); ++i) {
    if (certified.verdict[i] != exact.verdict[i] && ++mismatches <= 5)
      ADD_FAILURE() << "configuration " << i << ": certified verdict " << int(certified.verdict[i])
                    << ", checked alone " << int(exact.verdict[i]);
    if (!(certified.distance[i] <= exact.distance[i]) && ++above <= 5)
      ADD_FAILURE() << "configuration " << i << ": certified distance " << certified.distance[i]
                    << " above the exact " << exact.distance[i];
    exact_equal += certified.distance[i] == exact.distance[i];
  }
  EXPECT_EQ(mismatches, 0u);
  EXPECT_EQ(above, 0u);
  // Where sweep.json says distances are exact, they are (at least that many
  // agree with the exact run's float, up to the tie tolerance's rare step).
  const std::size_t checked = certified.summary["checked"];
  EXPECT_GE(exact_equal + checked / 1000 + 1, checked);
  EXPECT_EQ(certified.summary["counts"], exact.summary["counts"]);
  EXPECT_EQ(certified.summary["colliding_pairs"], exact.summary["colliding_pairs"]);
  EXPECT_EQ(exact.summary["checked"], exact.summary["configurations"]);
  // Fixed blocks: the same files on one thread as on two.
  EXPECT_EQ(one.verdict_bytes, certified.verdict_bytes);
  EXPECT_EQ(one.distance_bytes, certified.distance_bytes);
  EXPECT_EQ(without_timing(one.summary), without_timing(certified.summary));
  return certified;
}

// The default scene on a 10/20-degree grid around the lander (16,320
// configurations: collisions, clearance and free space), and a random
// sample of it against Checker::check_state (verify's state check).
TEST(SweepCertify, DefaultSceneEqualsCheckingEachConfiguration) {
  ASSERT_TRUE(std::filesystem::exists(kChange5 / "scene.json")) << "run `make dataset` first";
  TempDir dir("sweep-certify-change5");
  // Under the sanitizers (5-20x slower) J3 every 20 degrees: 8,640 configurations.
  const std::string grid = testing::kSanitized ? "J1=-20:20:10,J2=-20:130:10,J3=-160:0:20,J4=-80:140:20"
                                               : "J1=-20:20:10,J2=-20:130:10,J3=-160:0:10,J4=-80:140:20";
  const SweepRun run = expect_certified_equals_exact(kChange5 / "scene.json", grid, dir);
  const std::size_t total = run.summary["configurations"];
  ASSERT_EQ(total, 5u * 16u * (testing::kSanitized ? 9u : 17u) * 12u);
  EXPECT_GT(run.summary["counts"]["collision"].get<std::size_t>(), 1000u);
  EXPECT_GT(run.summary["counts"]["clearance"].get<std::size_t>(), 100u);
  EXPECT_GT(run.summary["counts"]["safe"].get<std::size_t>(), 1000u);
  // The certificate did its work: most safe configurations got no exact distance.
  EXPECT_LT(run.summary["checked"].get<std::size_t>(), total * 3 / 4);

  const Scene scene = load_scene(kChange5 / "scene.json");
  const Checker checker(scene, 2);
  SweepGrid g;
  g.axes = sweep_axes_from_grid(scene, grid);
  g.reference = scene.reference_parameters;
  std::mt19937_64 rng(17);
  std::vector<double> params;
  for (int n = 0; n < 400; ++n) {
    const std::size_t i = std::uniform_int_distribution<std::size_t>(0, total - 1)(rng);
    g.decode(i, params, nullptr);
    StateResult st;
    checker.check_state(params, st);
    const Verdict v = state_verdict(st, scene.safety_margin);
    const int code = v == Verdict::kSafe ? 0 : v == Verdict::kClearance ? 1 : v == Verdict::kCollision ? 2 : 3;
    EXPECT_EQ(int(run.verdict[i]), code) << "configuration " << i;
    if (st.collision)
      EXPECT_EQ(run.distance[i], 0.0f) << "configuration " << i;
    else
      EXPECT_LE(static_cast<double>(run.distance[i]), st.min_distance) << "configuration " << i;
  }
}

// The bar over the slab: one axis, distances in closed form near contact.
TEST(SweepCertify, BarOverSlabEqualsCheckingEachConfiguration) {
  TempDir dir("sweep-certify-bar");
  testing::write_bar_scene(dir);
  const SweepRun run = expect_certified_equals_exact(dir / "scene.json", "J1=-90:30:0.05", dir);
  EXPECT_GT(run.summary["counts"]["collision"].get<std::size_t>(), 0u);
  EXPECT_LT(run.summary["checked"].get<std::size_t>(), run.summary["configurations"].get<std::size_t>());
}

// A two-link arm (a URDF robot) and one fixed link in its way, `obstacle`
// (a <link> named as the test needs, fixed to the base).
void write_arm_scene(const TempDir& dir, const std::string& obstacle, const std::string& name) {
  write_text(dir / "arm.urdf", R"(<robot name="arm">
  <link name="base"/>
  )" + obstacle + R"(
  <joint name="obstacle_mount" type="fixed"><parent link="base"/><child link=")" + name + R"("/></joint>
  <link name="upper"><collision><origin xyz="0.5 0 0"/><geometry><box size="1.0 0.1 0.1"/></geometry></collision></link>
  <joint name="J1" type="revolute"><parent link="base"/><child link="upper"/><origin xyz="0 0 0.5"/>
    <axis xyz="0 0 1"/><limit lower="-3.1" upper="3.1" effort="1" velocity="1"/></joint>
  <link name="fore"><collision><origin xyz="0.56 0 0"/><geometry><box size="0.9 0.08 0.08"/></geometry></collision></link>
  <joint name="J2" type="revolute"><parent link="upper"/><child link="fore"/><origin xyz="1.0 0 0"/>
    <axis xyz="0 1 0"/><limit lower="-1.5" upper="1.5" effort="1" velocity="1"/></joint>
</robot>
)");
  write_text(dir / "scene.json", R"({
  "format": "plancheck-scene/1", "length_unit": "m", "angle_unit": "rad",
  "robot": {"urdf": "arm.urdf"}, "safety_margin": 0.02
})");
}

// A 2 mm wall in the arm's way.
void write_wall_scene(const TempDir& dir) {
  write_arm_scene(
      dir,
      R"(<link name="wall"><collision><origin xyz="1.2 0.9 0.5"/><geometry><box size="1.6 0.002 1.6"/></geometry></collision></link>)",
      "wall");
}

// Whether sweep.json lists a colliding pair with this part.
bool collides_with(const SweepRun& run, const std::string& part) {
  for (const auto& p : run.summary["colliding_pairs"])
    for (const auto& name : p["parts"])
      if (name == part) return true;
  return false;
}

// Configurations touching the wall lie between others far from it: a box
// of the grid around a far configuration that certified past the wall
// would call them safe.
TEST(SweepCertify, ThinWallIsNotCertifiedAway) {
  TempDir dir("sweep-certify-wall");
  write_wall_scene(dir);
  const SweepRun run = expect_certified_equals_exact(dir / "scene.json", "J1=-3.1:3.1:0.02,J2=-1.5:1.5:0.05", dir);
  EXPECT_GT(run.summary["counts"]["collision"].get<std::size_t>(), 0u);
  EXPECT_GT(run.summary["counts"]["safe"].get<std::size_t>(), 0u);
  EXPECT_LT(run.summary["checked"].get<std::size_t>(), run.summary["configurations"].get<std::size_t>() / 2);
  EXPECT_TRUE(collides_with(run, "wall")) << run.summary["colliding_pairs"].dump();
}

// The motion bounds boxes are certified with (SweepCertifier::pair_reach,
// from a box's centre, and pair_path, between two configurations) against
// the parts as posed: on the wall arm, no vertex of a checked pair's two
// parts moves farther, summed over both, than the bound, from the centre
// of random boxes to their corners and random points, and from one random
// configuration to another. The samples come within half of the bounds, so
// a bound halved (or taken from the centre where it is not) fails here.
TEST(SweepCertify, MotionBoundsHoldOnTheWallArm) {
  TempDir dir("sweep-certify-bounds");
  write_wall_scene(dir);
  const Scene scene = load_scene(dir / "scene.json");
  const Checker checker(scene, 1);
  SweepGrid grid;
  grid.axes = sweep_axes_from_grid(scene, "J1=-3.1:3.1:0.02,J2=-1.5:1.5:0.05");
  grid.reference = scene.reference_parameters;
  for (const SweepAxis& a : grid.axes) grid.total *= a.values.size();
  const SweepCertifier certifier(checker, scene, grid);
  auto moved = [&](int part, const std::vector<double>& from, const std::vector<double>& to) {
    if (part < 0 || static_cast<std::size_t>(part) >= scene.parts.size()) return 0.0;
    const Affine ta = part_transform(scene, part, from), tb = part_transform(scene, part, to);
    double m = 0.0;
    for (const Vec3& v : scene.parts[static_cast<std::size_t>(part)].mesh.vertices) m = std::max(m, (tb * v - ta * v).norm());
    return m;
  };
  std::mt19937_64 rng(33);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double reach_ratio = 0.0, path_ratio = 0.0;
  std::size_t moving_pairs = 0;
  for (std::size_t k = 0; k < checker.pairs().size(); ++k) {
    const auto [a, b] = checker.pairs()[k];
    (void)b;
    for (int trial = 0; trial < 40; ++trial) {
      std::vector<double> lo = grid.reference, hi = lo, c = lo, q = lo, from = lo, to = lo;
      for (const SweepAxis& ax : grid.axes) {
        const std::size_t p = static_cast<std::size_t>(ax.parameter);
        const double width = std::pow(10.0, -3.0 * u(rng));
        lo[p] = -3.0 + u(rng) * (6.0 - width);
        hi[p] = lo[p] + width;
        c[p] = lo[p] + 0.5 * (hi[p] - lo[p]);
        from[p] = -3.0 + 6.0 * u(rng);
        to[p] = from[p] + (u(rng) - 0.5) * width;
      }
      const double reach = certifier.pair_reach(k, lo, hi, c);
      for (int s = 0; s < 12; ++s) {
        std::size_t i = 0;
        for (const SweepAxis& ax : grid.axes) {
          const std::size_t p = static_cast<std::size_t>(ax.parameter);
          const double t = s < 4 ? static_cast<double>((s >> i) & 1) : u(rng);  // corners first
          q[p] = lo[p] + t * (hi[p] - lo[p]);
          ++i;
        }
        const double d = moved(a, c, q) + moved(b, c, q);
        ASSERT_LE(d, reach) << "pair " << k << " trial " << trial;
        if (d > 0.0 && s == 0 && trial == 0) ++moving_pairs;
        reach_ratio = std::max(reach_ratio, d / reach);
      }
      const double path = certifier.pair_path(k, from, to);
      const double d = moved(a, from, to) + moved(b, from, to);
      ASSERT_LE(d, path) << "pair " << k << " trial " << trial;
      path_ratio = std::max(path_ratio, d / path);
    }
  }
  EXPECT_GT(moving_pairs, 0u);
  EXPECT_GT(reach_ratio, 0.5);
  EXPECT_GT(path_ratio, 0.5);
}

// Contact regions certified by crossing witnesses, on the 2 mm wall: a
// link through it is in deep contact, bounded by grazing contacts (a
// corner on a face, an edge along the wall's 2 mm rim) where no witness
// may hold. Every verdict, colliding-pair count and distance as checking
// each configuration alone, with part of the contacts never tested one by
// one and the rim tested.
TEST(SweepCertify, ContactRegionsEqualCheckingEachConfiguration) {
  TempDir dir("sweep-certify-contact");
  write_wall_scene(dir);
  // Under the sanitizers half of J1's range at the same steps: a coarser
  // grid has boxes too wide for any witness's room (120 of 11,460 contacts
  // witnessed at twice the steps), which is not what this test is about.
  const std::string grid = testing::kSanitized ? "J1=0:0.75:0.004,J2=-1.5:1.5:0.01" : "J1=0:1.5:0.004,J2=-1.5:1.5:0.01";
  const SweepRun run = expect_certified_equals_exact(dir / "scene.json", grid, dir);
  const std::size_t collisions = run.summary["counts"]["collision"];
  const std::size_t witnessed = run.summary["certified"].value("witnessed", std::size_t{0});
  std::printf("[ wall ] %zu configurations, %zu collisions, %zu witnessed\n",
              run.summary["configurations"].get<std::size_t>(), collisions, witnessed);
  EXPECT_GT(collisions, run.summary["configurations"].get<std::size_t>() / 10);
  EXPECT_GT(witnessed, collisions / 20) << run.summary["certified"].dump();
  EXPECT_LT(witnessed, collisions);  // the contact region's rim got its own tests
  EXPECT_GT(run.summary["certified"].value("contact_boxes", std::size_t{0}), 0u);
  EXPECT_TRUE(collides_with(run, "wall")) << run.summary["colliding_pairs"].dump();
}

// Contact regions certified at the parts' scale: the fore link's end
// deep inside a closed drum (a URDF cylinder, 64 long thin side
// triangles: no triangle has room for a crossing witness), its other end
// outside. Every verdict and distance as checking each configuration
// alone; most contacts never tested one by one.
TEST(SweepCertify, DeepContactsInAClosedPartAreWitnessedAtThePartsScale) {
  TempDir dir("sweep-certify-drum");
  write_arm_scene(
      dir,
      R"(<link name="drum"><collision><origin xyz="1.9 0 0.5"/><geometry><cylinder radius="0.3" length="0.6"/></geometry></collision></link>)",
      "drum");
  const std::string grid = testing::kSanitized ? "J1=-0.5:0.5:0.01,J2=-0.6:0.6:0.02" : "J1=-0.5:0.5:0.005,J2=-0.6:0.6:0.005";
  const SweepRun run = expect_certified_equals_exact(dir / "scene.json", grid, dir);
  const std::size_t collisions = run.summary["counts"]["collision"];
  const std::size_t witnessed = run.summary["certified"].value("witnessed", std::size_t{0});
  std::printf("[ drum ] %zu configurations, %zu collisions, %zu witnessed\n",
              run.summary["configurations"].get<std::size_t>(), collisions, witnessed);
  EXPECT_GT(collisions, run.summary["configurations"].get<std::size_t>() / 10);
  // (9,661 of 14,341 at these steps, 855 of 1,817 at the sanitizers' coarser
  // ones: a witness has less room in a wider box.)
  EXPECT_GT(witnessed, collisions / 3) << run.summary["certified"].dump();
  EXPECT_LT(witnessed, collisions);  // the contact region's rim got its own tests
  EXPECT_TRUE(collides_with(run, "drum")) << run.summary["colliding_pairs"].dump();
}

// The certified blocks on one and two threads (also run under
// ThreadSanitizer: the name says Thread): the same files.
TEST(SweepCertify, OneAndTwoThreadsWriteTheSameFiles) {
  TempDir dir("sweep-certify-threads");
  write_wall_scene(dir);
  const std::string grid = "--grid J1=-3.1:3.1:0.05,J2=-1.5:1.5:0.1";
  const SweepRun one = sweep(dir / "scene.json", grid + " --threads 1", dir / "one");
  const SweepRun two = sweep(dir / "scene.json", grid + " --threads 2", dir / "two");
  EXPECT_FALSE(one.verdict_bytes.empty());
  EXPECT_EQ(one.verdict_bytes, two.verdict_bytes);
  EXPECT_EQ(one.distance_bytes, two.distance_bytes);
  EXPECT_EQ(without_timing(one.summary), without_timing(two.summary));
  EXPECT_GT(one.summary["counts"]["collision"].get<std::size_t>(), 0u);
}

}  // namespace
}  // namespace plancheck
