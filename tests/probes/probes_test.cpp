// SPDX-License-Identifier: MIT
// Probes against analytic geometry (a ray down onto a flat grid, a fan
// against a box) and Embree's ray casting against a brute-force double
// precision ray-triangle reference.
#include "src/checks/probes.h"
#include "src/scene/terrain.h"
#include "src/geometry/raycast.h"

#include "tests/support/fixtures.h"
#include "tests/support/test_meshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace plancheck {
namespace {

constexpr double kPi = 3.14159265358979323846;

// A scene of static parts (probes ride on "Sensor", a far-away speck) and an
// optional flat terrain file.
Scene probe_scene(const std::vector<std::pair<std::string, Mesh>>& parts) {
  Scene s;
  Part sensor;
  sensor.name = "Sensor";
  sensor.mesh = testing::box_mesh(Vec3(100, 100, 100), Vec3(100.01, 100.01, 100.01));
  s.parts.push_back(sensor);
  for (const auto& [name, mesh] : parts) {
    Part p;
    p.name = name;
    p.mesh = mesh;
    s.parts.push_back(p);
  }
  return s;
}

ProbeConfig probe(const Vec3& origin, const Vec3& direction, int count, double half_angle, double range) {
  ProbeConfig p;
  p.name = "p";
  p.part = "Sensor";
  p.part_index = 0;
  p.origin = origin;
  p.direction = direction.normalized();
  p.fan_count = count;
  p.fan_half_angle = half_angle;
  p.max_range = range;
  return p;
}

TEST(Probes, RayStraightDownMeetsAFlatGridAtItsHeight) {
  testing::TempDir dir("probes_test");
  std::string dem = "ncols 20\nnrows 20\nxllcorner 0\nyllcorner 0\ncellsize 0.05\n";
  for (int r = 0; r < 20; ++r) {
    for (int c = 0; c < 20; ++c) dem += c ? " 0.3" : "0.3";
    dem += "\n";
  }
  testing::write_text(dir / "flat.asc", dem);
  Scene s = probe_scene({});
  s.terrain = TerrainConfig{};
  s.terrain->dem = dir / "flat.asc";
  s.terrain->origin = Vec3(1.0, -0.5, 0.1);
  s.terrain->grid = std::make_shared<const Dem>(load_dem(dir / "flat.asc", 1.0));
  s.probes.push_back(probe(Vec3(1.4, -0.1, 2.0), -Vec3::UnitZ(), 1, 0.0, 3.0));
  s.probes.push_back(probe(Vec3(1.4, -0.1, 2.0), Vec3::UnitZ(), 1, 0.0, 3.0));     // up: nothing
  s.probes.push_back(probe(Vec3(1.4, -0.1, 2.0), -Vec3::UnitZ(), 1, 0.0, 1.0));    // too short
  const ProbeCaster caster(s);
  std::vector<std::vector<ProbeReading>> out;
  caster.cast({std::vector<double>{}, std::vector<double>{}}, 2, out);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_NEAR(out[0][0].distance, 2.0 - 0.4, 1e-6);  // float hit distance
  ASSERT_GE(out[0][0].hit, 0);
  EXPECT_EQ(caster.target_name(out[0][0].hit), "terrain");
  EXPECT_EQ(out[0][1].hit, -1);
  EXPECT_EQ(out[0][1].distance, 3.0);
  EXPECT_EQ(out[0][2].hit, -1);
  EXPECT_EQ(out[0][2].distance, 1.0);
  EXPECT_EQ(out[1][0].distance, out[0][0].distance);

  // A pit dug under the probe, seen through a refit copy of the caster's
  // terrain; the undisturbed terrain still reads the surface.
  ASSERT_NE(caster.terrain(), nullptr);
  Dem dug = load_dem(dir / "flat.asc", 1.0);
  for (int r = 5; r <= 12; ++r)
    for (int c = 5; c <= 12; ++c) dug.z[static_cast<std::size_t>(r) * dug.ncols + c] -= 0.07;
  Heightfield pit = *caster.terrain();
  pit.refit(dug, {5, 5, 12, 12});
  std::vector<ProbeReading> one;
  caster.cast_state({}, one, &pit);
  EXPECT_NEAR(one[0].distance, 2.0 - 0.4 + 0.07, 1e-6);
  EXPECT_EQ(caster.target_name(one[0].hit), "terrain");
  caster.cast_state({}, one);
  EXPECT_EQ(one[0].distance, out[0][0].distance);
}

TEST(Probes, FanPatternIsPlanarEvenAndCentred) {
  const ProbeConfig p = probe(Vec3::Zero(), Vec3::UnitX(), 5, kPi / 4, 1.0);
  const auto d = ProbeCaster::fan_directions(p);
  ASSERT_EQ(d.size(), 5u);
  for (int k = 0; k < 5; ++k) {
    const double theta = -kPi / 4 + k * kPi / 8;
    EXPECT_NEAR(std::acos(std::clamp(d[k].dot(Vec3::UnitX()), -1.0, 1.0)), std::abs(theta), 1e-12);
    EXPECT_NEAR(d[k].y(), 0.0, 1e-15);  // x cross z = -y is the axis: the fan spans x and z
    EXPECT_NEAR(d[k].norm(), 1.0, 1e-15);
  }
  EXPECT_NEAR(d[2].x(), 1.0, 1e-15);
  // Straight down (parallel to z): the axis falls back to d x x = -y, so the fan spans x and z.
  const auto down = ProbeCaster::fan_directions(probe(Vec3::Zero(), -Vec3::UnitZ(), 3, 0.5, 1.0));
  EXPECT_NEAR(down[0].y(), 0.0, 1e-15);
  EXPECT_NEAR(std::abs(down[0].x()), std::sin(0.5), 1e-15);
}

TEST(Probes, FanAgainstABoxReadsTheSecantOfEachRay) {
  // Face x = 1 of a box; rays at angle theta in the x-z plane travel 1/cos(theta).
  const Mesh box = testing::box_mesh(Vec3(1, -1, -1), Vec3(2, 1, 1));
  Scene s = probe_scene({{"Box", box}});
  const ProbeConfig p = probe(Vec3::Zero(), Vec3::UnitX(), 8, 0.6, 5.0);
  s.probes.push_back(p);
  const ProbeCaster caster(s);
  RayScene rs;
  rs.add_mesh(box);
  rs.commit();
  std::vector<Ray> rays;
  for (const Vec3& d : ProbeCaster::fan_directions(p)) rays.push_back({Vec3::Zero(), d, 5.0});
  std::vector<RayHit> hits;
  rs.intersect(rays, hits);
  double shortest = 1e9;
  for (int k = 0; k < 8; ++k) {
    const double theta = -0.6 + 1.2 * k / 7;
    ASSERT_TRUE(hits[k].hit);
    EXPECT_NEAR(hits[k].distance, 1.0 / std::cos(theta), 1e-6);
    shortest = std::min(shortest, 1.0 / std::cos(theta));
  }
  std::vector<std::vector<ProbeReading>> out;
  caster.cast({std::vector<double>{}}, 1, out);
  EXPECT_NEAR(out[0][0].distance, shortest, 1e-6);  // 8 rays: the two nearest the axis, 1/cos(0.6/7)
  EXPECT_EQ(caster.target_name(out[0][0].hit), "Box");
}

// Brute force in double: the first hit over all triangles with each triangle
// grown (eps > 0) or shrunk (eps < 0) in barycentric terms, so the exact
// first hit lies between the two answers whatever rounding does at edges.
double brute_first_hit(const Mesh& m, const Vec3& o, const Vec3& d, double range, double eps) {
  double best = std::numeric_limits<double>::infinity();
  for (const Tri& t : m.triangles) {
    const Vec3 &a = m.vertices[t[0]], &b = m.vertices[t[1]], &c = m.vertices[t[2]];
    const Vec3 e1 = b - a, e2 = c - a, p = d.cross(e2);
    const double det = e1.dot(p);
    if (std::abs(det) < 1e-300) continue;
    const Vec3 s = o - a, q = s.cross(e1);
    const double u = s.dot(p) / det, v = d.dot(q) / det, dist = e2.dot(q) / det;
    if (u < -eps || v < -eps || u + v > 1 + eps || dist < 0 || dist > range) continue;
    best = std::min(best, dist);
  }
  return best;
}

TEST(Probes, EmbreeAgreesWithBruteForceOnASoup) {
  const Mesh soup = testing::make_soup(7, 400, Vec3(0, 0, 0), 1.0, 0.4);
  RayScene rs;
  rs.add_mesh(soup);
  rs.commit();
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Ray> rays;
  for (int i = 0; i < 3000; ++i) {
    const Vec3 o(1.5 * u(rng), 1.5 * u(rng), 1.5 * u(rng));
    Vec3 d(u(rng), u(rng), u(rng));
    if (d.norm() < 0.1) d = Vec3::UnitX();
    rays.push_back({o, d.normalized(), 2.5});
  }
  std::vector<RayHit> hits;
  rs.intersect(rays, hits);
  int hit_count = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const double grown = brute_first_hit(soup, rays[i].origin, rays[i].direction, 2.5, 1e-5);
    const double shrunk = brute_first_hit(soup, rays[i].origin, rays[i].direction, 2.5, -1e-5);
    const double got = hits[i].hit ? hits[i].distance : std::numeric_limits<double>::infinity();
    hit_count += hits[i].hit;
    if (std::isinf(grown)) {
      EXPECT_FALSE(hits[i].hit) << i;
    } else if (std::isinf(shrunk)) {
      EXPECT_TRUE(!hits[i].hit || got >= grown - 1e-5) << i;
    } else {
      EXPECT_TRUE(hits[i].hit) << i;
      EXPECT_GE(got, grown - 1e-5) << i;
      EXPECT_LE(got, shrunk + 1e-5) << i;
    }
  }
  EXPECT_GT(hit_count, 300);  // the sample exercises hits, not just misses
}

}  // namespace
}  // namespace plancheck
