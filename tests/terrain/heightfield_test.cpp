// SPDX-License-Identifier: MIT
// The heightfield against the terrain mesh path (a CollisionModel over
// dem_mesh: same working frame, same kernels, so answers must be equal) and
// against all-pairs brute force; before and after digs with refit.
#include "src/geometry/heightfield.h"
#include "src/scene/terrain.h"

#include "kernels/leaf_bounds.h"

#include "tests/support/brute_force.h"
#include "tests/support/fixtures.h"
#include "tests/support/same_answer.h"
#include "tests/support/test_meshes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>

namespace plancheck {
namespace {

Dem bumpy_dem(std::uint64_t seed, int n, double cell, bool holes) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Dem d;
  d.ncols = n + 3;  // not square, not a multiple of the leaf size
  d.nrows = n;
  d.cellsize = cell;
  d.x0 = d.y0 = 0.5 * cell;
  d.z.resize(static_cast<std::size_t>(d.ncols) * d.nrows);
  d.valid.assign(d.z.size(), 1);
  for (double& z : d.z) z = 0.2 * u(rng);
  if (holes) {
    d.valid[static_cast<std::size_t>(4) * d.ncols + 6] = 0;
    d.valid[static_cast<std::size_t>(9) * d.ncols + 2] = 0;
  }
  return d;
}

const Vec3 kOrigin(-0.3, 0.2, 0.05);

Affine random_pose(std::mt19937_64& rng, const Dem& d, double z_lo, double z_hi) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const Vec3 axis = Vec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5).normalized();
  Affine t = Affine::Identity();
  t.linear() = Eigen::AngleAxisd(6.3 * u(rng), axis).toRotationMatrix();
  t.translation() = kOrigin + Vec3(u(rng) * d.cellsize * (d.ncols - 1), u(rng) * d.cellsize * (d.nrows - 1),
                                   z_lo + (z_hi - z_lo) * u(rng));
  return t;
}

std::set<std::pair<std::uint32_t, std::uint32_t>> as_set(const std::vector<std::pair<std::uint32_t, std::uint32_t>>& v) {
  return {v.begin(), v.end()};
}

// Heightfield and mesh path must agree exactly; brute force (world frame)
// within rounding.
void expect_same(const CollisionModel& part, const Mesh& part_mesh, const Affine& pose, const Heightfield& hf,
                 const Mesh& terrain, bool brute, const std::string& what, int* collided = nullptr) {
  SCOPED_TRACE(what);
  const CollisionModel mesh_model(terrain);
  const Affine id = Affine::Identity();
  CollideResult a, b;
  collide(part, pose, hf, CollideRequest{1u << 20}, a);
  collide(part, pose, mesh_model, id, CollideRequest{1u << 20}, b);
  ASSERT_EQ(a.collide, b.collide);
  EXPECT_EQ(as_set(a.triangle_pairs), as_set(b.triangle_pairs));
  DistanceResult da, db;
  collide(part, pose, hf, CollideRequest{0}, a);
  EXPECT_EQ(a.collide, b.collide);
  distance(part, pose, hf, DistanceRequest{}, da);
  distance(part, pose, mesh_model, id, DistanceRequest{}, db);
  ASSERT_EQ(da.found, db.found);
  EXPECT_EQ(da.distance, db.distance);
  {
    // A collision test's contact answer is distance()'s, bit for bit.
    DistanceResult contact;
    contact.distance = -1.0;
    CollideResult c;
    CollideRequest request{0};
    request.contact = &contact;
    collide(part, pose, hf, request, c);
    EXPECT_EQ(c.collide, b.collide);
    if (!c.collide) {
      EXPECT_EQ(contact.distance, -1.0);
    } else {
      EXPECT_TRUE(testing::same_answer(contact, da));
    }
  }
  // A reported terrain point lies in the plane of its reported triangle.
  auto on_triangle_b = [&](const DistanceResult& d) {
    double t[9];
    int c, r, k;
    hf.triangle_cell(d.triangle_b, c, r, k);
    hf.cell_triangle(c, r, k, t);
    const Vec3 q[3] = {Vec3(t[0], t[1], t[2]), Vec3(t[3], t[4], t[5]), Vec3(t[6], t[7], t[8])};
    return std::abs(((q[1] - q[0]).cross(q[2] - q[0])).normalized().dot(d.point_b - q[0]));
  };
  if (da.found && da.distance > 0.0) {
    // The reported points are on the reported triangles and that far apart.
    EXPECT_NEAR((da.point_a - da.point_b).norm(), da.distance, 1e-12);
    EXPECT_LT(on_triangle_b(da), 1e-12);
    // Seeded with its own pair and asked only whether something lies
    // below: the seed itself answers (its corners rebuilt from the slots).
    DistanceRequest seeded;
    seeded.upper_bound = 1.5 * da.distance + 1e-9;
    seeded.first_below = true;
    seeded.seed_slot_a = static_cast<std::int64_t>(da.slot_a);
    seeded.seed_slot_b = static_cast<std::int64_t>(da.slot_b);
    DistanceResult ds;
    distance(part, pose, hf, seeded, ds);
    ASSERT_TRUE(ds.found);
    EXPECT_EQ(ds.triangle_b, da.triangle_b);
    EXPECT_EQ(ds.distance, da.distance);
    EXPECT_LT(on_triangle_b(ds), 1e-12);
  } else if (da.found) {
    // In contact: the common point lies on the terrain triangle too.
    EXPECT_LT(on_triangle_b(da), 1e-9);
  }
  if (collided) *collided += a.collide ? 1 : 0;
  if (!brute) return;
  const auto vp = testing::posed_vertices(part_mesh, pose);
  const bool expect = !testing::brute_force_collide(part_mesh, vp, terrain, terrain.vertices, true).empty();
  EXPECT_EQ(b.collide, expect);
  if (!expect) {
    const auto ref = testing::brute_force_distance(part_mesh, vp, terrain, terrain.vertices);
    EXPECT_NEAR(da.distance, ref.distance, 1e-9);
  }
}

TEST(Heightfield, CornersAndIndicesAreDemMeshs) {
  const Dem d = bumpy_dem(1, 13, 0.1, true);
  const Heightfield hf(d, kOrigin);
  const Mesh m = dem_mesh(d, kOrigin);
  ASSERT_EQ(hf.triangle_count(), m.triangles.size());
  for (std::uint32_t t = 0; t < m.triangles.size(); ++t) {
    int c, r, k;
    hf.triangle_cell(t, c, r, k);
    EXPECT_EQ(hf.cell_first_tri(c, r) + static_cast<std::uint32_t>(k), t);
    double v[9];
    hf.cell_triangle(c, r, k, v);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) EXPECT_EQ(v[3 * i + j], m.vertices[m.triangles[t][i]][j]) << t;
  }
  // The root block bounds every valid height exactly.
  double lo[3], hi[3];
  ASSERT_TRUE(hf.block_box(static_cast<int>(hf.levels().size()) - 1, 0, 0, lo, hi));
  double zmin = 1e300, zmax = -1e300;
  for (const Tri& t : m.triangles)
    for (std::uint32_t v : t) zmin = std::min(zmin, m.vertices[v].z()), zmax = std::max(zmax, m.vertices[v].z());
  EXPECT_EQ(lo[2], zmin);
  EXPECT_EQ(hi[2], zmax);
}

TEST(Heightfield, CollideAndDistanceEqualTheMeshPath) {
  const Dem d = bumpy_dem(2, 16, 0.1, true);
  const Heightfield hf(d, kOrigin);
  const Mesh terrain = dem_mesh(d, kOrigin);
  const Mesh ball = testing::make_sphere(Vec3::Zero(), 0.15, 6, 9);
  const Mesh soup = testing::make_soup(3, 40, Vec3::Zero(), 0.2, 0.15);
  const CollisionModel ball_model(ball), soup_model(soup);
  std::mt19937_64 rng(7);
  int collided = 0, poses = 0;
  for (int k = 0; k < 60; ++k) {
    const Affine pose = random_pose(rng, d, kOrigin.z() - 0.1, kOrigin.z() + 0.5);
    expect_same(ball_model, ball, pose, hf, terrain, true, "ball " + std::to_string(k), &collided);
    expect_same(soup_model, soup, pose, hf, terrain, true, "soup " + std::to_string(k), &collided);
    poses += 2;
  }
  EXPECT_GT(collided, 10);
  EXPECT_LT(collided, poses - 10);
  // A scaled (non-rigid) pose: the mesh path's other working frame.
  for (int k = 0; k < 10; ++k) {
    Affine pose = random_pose(rng, d, kOrigin.z(), kOrigin.z() + 0.4);
    pose.linear() *= Eigen::DiagonalMatrix<double, 3>(1.3, 0.7, 1.0);
    expect_same(ball_model, ball, pose, hf, terrain, true, "scaled " + std::to_string(k));
  }
}

TEST(Heightfield, TouchingGrazingAndBuriedPartsEqualTheMeshPath) {
  const Dem d = bumpy_dem(4, 12, 0.1, false);
  const Heightfield hf(d, kOrigin);
  const Mesh terrain = dem_mesh(d, kOrigin);
  // A small box whose bottom face sits exactly at a sample's height (touching),
  // just above it (grazing), and far below the surface (buried).
  const Mesh box = testing::box_mesh(Vec3(-0.02, -0.02, 0.0), Vec3(0.02, 0.02, 0.03));
  const CollisionModel model(box);
  for (int c : {3, 7}) {
    const int r = 5;
    const double top = hf.z(c, r);
    Affine pose = Affine::Identity();
    for (double dz : {0.0, 1e-12, 1e-9, 1e-3, -0.5}) {
      // Translation only: identity rotation, so the frame is the part's own.
      pose.translation() = Vec3(hf.x(c), hf.y(r), top + dz);
      expect_same(model, box, pose, hf, terrain, dz != 0.0 && dz != 1e-12, "dz " + std::to_string(dz));
    }
    // The same above a sample with the part rotated a quarter turn.
    pose.linear() = Eigen::AngleAxisd(0.5 * 3.14159265358979323846, Vec3::UnitZ()).toRotationMatrix();
    pose.translation() = Vec3(hf.x(c), hf.y(r), top + 1e-12);
    expect_same(model, box, pose, hf, terrain, false, "rotated");
  }
}

// Random digs (pits and raised rims) applied to the DEM, refit over the
// changed rectangle: the pyramid equals a fresh build, queries equal a fresh
// mesh path and brute force.
TEST(Heightfield, RefitAfterRandomDigsEqualsAFreshBuild) {
  Dem d = bumpy_dem(5, 20, 0.05, true);
  Heightfield hf(d, kOrigin);
  const Mesh ball = testing::make_sphere(Vec3::Zero(), 0.08, 6, 9);
  const CollisionModel ball_model(ball);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int dig = 0; dig < 12; ++dig) {
    SampleRect rect;
    rect.c0 = static_cast<int>(u(rng) * (d.ncols - 3));
    rect.r0 = static_cast<int>(u(rng) * (d.nrows - 3));
    rect.c1 = std::min(d.ncols - 1, rect.c0 + static_cast<int>(u(rng) * 5));
    rect.r1 = std::min(d.nrows - 1, rect.r0 + static_cast<int>(u(rng) * 5));
    for (int r = rect.r0; r <= rect.r1; ++r)
      for (int c = rect.c0; c <= rect.c1; ++c) {
        const std::size_t i = static_cast<std::size_t>(r) * d.ncols + c;
        const bool edge = r == rect.r0 || r == rect.r1 || c == rect.c0 || c == rect.c1;
        d.z[i] += edge ? 0.05 * u(rng) : -0.1 * u(rng);  // rim up, pit down
      }
    hf.refit(d, rect);
    const Heightfield fresh(d, kOrigin);
    ASSERT_EQ(hf.levels().size(), fresh.levels().size());
    for (std::size_t l = 0; l < hf.levels().size(); ++l)
      for (std::size_t b = 0; b < hf.levels()[l].blocks.size(); ++b) {
        EXPECT_EQ(hf.levels()[l].blocks[b].zmin, fresh.levels()[l].blocks[b].zmin) << l << " " << b;
        EXPECT_EQ(hf.levels()[l].blocks[b].zmax, fresh.levels()[l].blocks[b].zmax) << l << " " << b;
      }
    const Mesh terrain = dem_mesh(d, kOrigin);
    for (int k = 0; k < 8; ++k) {
      // Poses over the dug rectangle, from above the rim to inside the pit.
      Affine pose = random_pose(rng, d, kOrigin.z() - 0.05, kOrigin.z() + 0.3);
      pose.translation().x() = hf.x(rect.c0) + u(rng) * (hf.x(rect.c1) - hf.x(rect.c0) + 0.05);
      pose.translation().y() = hf.y(rect.r0) + u(rng) * (hf.y(rect.r1) - hf.y(rect.r0) + 0.05);
      expect_same(ball_model, ball, pose, hf, terrain, true, "dig " + std::to_string(dig) + " pose " + std::to_string(k));
    }
  }
}

TEST(Heightfield, RefitTouchesOnlyTheBlocksOverChangedSamples) {
  Dem d = bumpy_dem(6, 40, 0.05, false);  // 42 x 39 cells: 11 x 10 leaf blocks
  Heightfield hf(d, kOrigin);
  ASSERT_EQ(hf.levels()[0].nx, 11);
  ASSERT_EQ(hf.levels()[0].ny, 10);
  const std::size_t levels = hf.levels().size();
  // One sample inside a leaf block: its 4 cells are in that block alone; one
  // block per level.
  d.z[static_cast<std::size_t>(6) * d.ncols + 6] += 0.3;
  EXPECT_EQ(hf.refit(d, {6, 6, 6, 6}), levels);
  // A sample on a block corner (c = r = 8): its cells (7..8) x (7..8) span
  // four leaf blocks (1..2 per axis), whose parents are four too (0..1), then one per level.
  d.z[static_cast<std::size_t>(8) * d.ncols + 8] -= 0.3;
  EXPECT_EQ(hf.refit(d, {8, 8, 8, 8}), 4 + 4 + (levels - 2));
  // Nothing changed: nothing refit.
  EXPECT_EQ(hf.refit(d, SampleRect{}), 0u);
  const Heightfield fresh(d, kOrigin);
  for (std::size_t l = 0; l < levels; ++l)
    for (std::size_t b = 0; b < hf.levels()[l].blocks.size(); ++b)
      EXPECT_EQ(hf.levels()[l].blocks[b].zmax, fresh.levels()[l].blocks[b].zmax);
}

TEST(Heightfield, PartNearTheRimCollidesOnlyAfterTheDig) {
  Dem d = bumpy_dem(8, 20, 0.05, false);
  for (double& z : d.z) z = 0.1;  // flat ground
  Heightfield hf(d, kOrigin);
  const Mesh box = testing::box_mesh(Vec3(-0.03, -0.03, 0.0), Vec3(0.03, 0.03, 0.05));
  const CollisionModel model(box);
  Affine pose = Affine::Identity();
  pose.translation() = Vec3(hf.x(10), hf.y(10), kOrigin.z() + 0.1 + 0.02);  // 2 cm above the ground
  CollideResult before, after;
  collide(model, pose, hf, {}, before);
  DistanceResult dist_before, dist_after;
  distance(model, pose, hf, {}, dist_before);
  EXPECT_FALSE(before.collide);
  EXPECT_NEAR(dist_before.distance, 0.02, 1e-12);
  // A rim 3 cm high raised under the part.
  for (int r = 9; r <= 11; ++r)
    for (int c = 9; c <= 11; ++c) d.z[static_cast<std::size_t>(r) * d.ncols + c] += 0.03;
  hf.refit(d, {9, 9, 11, 11});
  collide(model, pose, hf, {}, after);
  EXPECT_TRUE(after.collide);
  // Near it, not on it: closer than before.
  pose.translation().x() = hf.x(13) + 0.031;
  distance(model, pose, hf, {}, dist_after);
  EXPECT_LT(dist_after.distance, 0.02);
}

TEST(Heightfield, RayDownIntoAPitReadsItsDepth) {
  Dem d = bumpy_dem(9, 20, 0.05, false);
  for (double& z : d.z) z = 0.1;
  Heightfield hf(d, kOrigin);
  const double o[3] = {hf.x(10) + 0.01, hf.y(10) + 0.02, kOrigin.z() + 1.0}, down[3] = {0, 0, -1};
  double t = 5.0;
  std::uint32_t tri = 0;
  ASSERT_TRUE(hf.intersect_ray(o, down, 0.0, t, tri));
  EXPECT_NEAR(t, 0.9, 1e-12);
  for (int r = 8; r <= 12; ++r)
    for (int c = 8; c <= 12; ++c) d.z[static_cast<std::size_t>(r) * d.ncols + c] -= 0.04;
  hf.refit(d, {8, 8, 12, 12});
  t = 5.0;
  ASSERT_TRUE(hf.intersect_ray(o, down, 0.0, t, tri));
  EXPECT_NEAR(t, 0.94, 1e-12);
  // Off the grid: no hit.
  const double off[3] = {kOrigin.x() - 1.0, kOrigin.y(), kOrigin.z() + 1.0};
  t = 5.0;
  EXPECT_FALSE(hf.intersect_ray(off, down, 0.0, t, tri));
}

// The float leaf prefilters (heightfield.cpp: HfDistance::leaves,
// HfOverlap::leaves) change no answer: with every instruction set's
// kernels each distance request below gets bit for bit the answer of
// kernels that prove nothing (leaf_kernels_none: every pair of every leaf
// pair on the double path, as before the prefilters), and collide() lists
// the same pairs in the same order, on bumpy ground with holes, flat
// ground (ties everywhere under a flat face), ground far from the origin
// with large heights, a grid of 0.1 mm cells, and ground dug (refit)
// under the part between queries; rigid and scaled poses, parts far, near,
// grazing, touching and buried.
struct KernelsGuard {
  const LeafKernels& saved = leaf_kernels();
  ~KernelsGuard() { set_leaf_kernels(saved); }
};

struct PrefilterCase {
  std::string name;
  Dem dem;
  Vec3 origin;
  Mesh part;
  std::vector<Affine> poses;
  Dem dug = {};  // when it has samples: refit to it before the queries
};

// Everything the prefilters could change for one pose and request list.
struct PrefilterAnswers {
  std::vector<DistanceResult> distance;
  CollideResult all, first;
  DistanceResult contact;
};

PrefilterAnswers prefilter_answers(const CollisionModel& model, const Affine& pose, const Heightfield& hf,
                                   const std::vector<DistanceRequest>& requests) {
  PrefilterAnswers out;
  for (const DistanceRequest& r : requests) {
    out.distance.emplace_back();
    distance(model, pose, hf, r, out.distance.back());
  }
  collide(model, pose, hf, CollideRequest{1u << 20}, out.all);
  CollideRequest first{0};
  out.contact.distance = -1.0;
  first.contact = &out.contact;
  collide(model, pose, hf, first, out.first);
  return out;
}

// The requests the checks send: plain, bounded (above and below the
// answer, and the sweep's 5 cm), seeded with the answer's own pair and with
// a stranger, yes/no (first_below), tolerant, and after a collision pass.
std::vector<DistanceRequest> prefilter_requests(const DistanceResult& plain, std::uint32_t tri_b) {
  std::vector<DistanceRequest> out(1);
  DistanceRequest r;
  for (double f : {1.5, 0.5}) {
    r = DistanceRequest{};
    r.upper_bound = plain.found ? plain.distance * f + 1e-9 : 0.05;
    out.push_back(r);
  }
  r = DistanceRequest{};
  r.upper_bound = 0.05;
  out.push_back(r);
  if (plain.found) {
    r.seed_slot_a = plain.slot_a;
    r.seed_slot_b = plain.slot_b;
    out.push_back(r);
  }
  r.seed_slot_a = 0;
  r.seed_slot_b = tri_b;
  out.push_back(r);
  r = DistanceRequest{};
  r.upper_bound = plain.found ? plain.distance * 1.01 + 1e-12 : 1.0;
  r.first_below = true;
  out.push_back(r);
  r = DistanceRequest{};
  r.rel_tolerance = 0.05;
  r.abs_tolerance = 1e-12;
  out.push_back(r);
  if (plain.found && plain.distance > 0.0) {
    r = DistanceRequest{};
    r.known_disjoint = true;
    out.push_back(r);
  }
  return out;
}

TEST(Heightfield, DistancePrefilterChangesNoAnswer) {
  std::vector<PrefilterCase> cases;
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  auto poses = [&](const Dem& d, const Vec3& origin, double z_lo, double z_hi, int n, bool scaled) {
    std::vector<Affine> out;
    for (int k = 0; k < n; ++k) {
      Affine t = random_pose(rng, d, z_lo, z_hi);
      t.translation() += origin - kOrigin;
      if (scaled && k % 3 == 0) t.linear() *= Eigen::DiagonalMatrix<double, 3>(1.3, 0.7, 1.0);
      out.push_back(t);
    }
    return out;
  };
  {
    PrefilterCase c{"bumpy", bumpy_dem(31, 18, 0.05, true), kOrigin, testing::make_soup(5, 60, Vec3::Zero(), 0.15, 0.12), {}};
    c.poses = poses(c.dem, c.origin, c.origin.z() - 0.05, c.origin.z() + 0.45, 40, true);
    cases.push_back(std::move(c));
    PrefilterCase b{"bumpy ball", cases.back().dem, kOrigin, testing::make_sphere(Vec3::Zero(), 0.12, 8, 12), {}};
    b.poses = poses(b.dem, b.origin, b.origin.z() + 0.05, b.origin.z() + 0.4, 30, true);
    cases.push_back(std::move(b));
  }
  {
    // Flat ground 0.1 high; a box's flat bottom face parallel to it at
    // several heights (every triangle under the face is a tie), then tilted.
    Dem d = bumpy_dem(32, 16, 0.05, false);
    for (double& z : d.z) z = 0.1;
    PrefilterCase c{"flat", d, kOrigin, testing::box_mesh(Vec3(-0.07, -0.05, 0.0), Vec3(0.07, 0.05, 0.04)), {}};
    const Heightfield hf(d, kOrigin);
    for (double dz : {0.0, 1e-12, 1e-9, 1e-4, 0.02, 0.049, 0.3})
      for (int k = 0; k < 3; ++k) {
        Affine t = Affine::Identity();
        if (k == 2) t.linear() = Eigen::AngleAxisd(0.01, Vec3(1, 1, 0).normalized()).toRotationMatrix();
        if (k == 1) t.linear() = Eigen::AngleAxisd(0.7, Vec3::UnitZ()).toRotationMatrix();
        t.translation() = Vec3(hf.x(6 + 2 * k) + 0.003 * k, hf.y(7), hf.z(6, 7) + dz);
        c.poses.push_back(t);
      }
    cases.push_back(std::move(c));
  }
  {
    // Far from the origin, heights of 3 km +- 1 m: the floats carry far
    // fewer bits of the gaps.
    Dem d = bumpy_dem(33, 14, 0.5, true);
    for (double& z : d.z) z = 3000.0 + 5.0 * z;
    const Vec3 far(2.0e5, -1.5e5, 10.0);
    PrefilterCase c{"far", d, far, testing::make_soup(6, 50, Vec3::Zero(), 1.2, 0.9), {}};
    c.poses = poses(d, far, far.z() + 3000.0, far.z() + 3004.0, 30, false);
    cases.push_back(std::move(c));
  }
  {
    // 0.1 mm cells, heights of tens of microns, a 0.3 mm part.
    Dem d = bumpy_dem(34, 15, 1e-4, false);
    for (double& z : d.z) z *= 2e-4;
    PrefilterCase c{"tiny", d, Vec3(1e-3, -2e-3, 0.0), testing::make_sphere(Vec3::Zero(), 3e-4, 6, 9), {}};
    c.poses = poses(d, c.origin, -1e-4, 6e-4, 30, true);
    cases.push_back(std::move(c));
  }
  {
    // Bumpy ground queried (so its blocks are in the thread's cache), then
    // a pit dug and a rim raised under the poses and refit.
    Dem d = bumpy_dem(35, 16, 0.05, false);
    PrefilterCase c{"dug", d, kOrigin, testing::make_sphere(Vec3::Zero(), 0.1, 8, 12), {}};
    c.poses = poses(d, kOrigin, kOrigin.z() + 0.02, kOrigin.z() + 0.35, 24, false);
    for (int r = 2; r < d.nrows - 2; ++r)
      for (int col = 2; col < d.ncols - 2; ++col) d.z[static_cast<std::size_t>(r) * d.ncols + col] += (r + col) % 3 == 0 ? 0.15 : -0.2;
    c.dug = d;
    cases.push_back(std::move(c));
  }
  KernelsGuard guard;
  for (const PrefilterCase& c : cases) {
    SCOPED_TRACE(c.name);
    Heightfield hf(c.dem, c.origin);
    const CollisionModel model(c.part);
    std::uniform_int_distribution<std::uint32_t> pick(0, static_cast<std::uint32_t>(hf.triangle_count() - 1));
    if (!c.dug.z.empty()) {
      // Fill the caches with the ground before the dig, then dig.
      for (int isa = 0; isa < kIsaCount; ++isa)
        if (const LeafKernels* k = leaf_kernels_for(static_cast<Isa>(isa))) {
          set_leaf_kernels(*k);
          for (const Affine& pose : c.poses) prefilter_answers(model, pose, hf, {DistanceRequest{}});
        }
      hf.refit(c.dug, {0, 0, c.dug.ncols - 1, c.dug.nrows - 1});
    }
    // The reference answers, and the requests (from the plain answer);
    // the reference's collision listing and plain distance are the mesh
    // path's (which has its own prefilters, off here too).
    set_leaf_kernels(leaf_kernels_none());
    const CollisionModel mesh_model(dem_mesh(c.dug.z.empty() ? c.dem : c.dug, c.origin));
    std::vector<std::vector<DistanceRequest>> requests;
    std::vector<PrefilterAnswers> want;
    std::uint64_t tested_none = 0;
    int found = 0, contact = 0;
    for (const Affine& pose : c.poses) {
      DistanceResult plain;
      distance(model, pose, hf, DistanceRequest{}, plain);
      found += plain.found && plain.distance > 0.0 ? 1 : 0;
      contact += plain.found && plain.distance == 0.0 ? 1 : 0;
      requests.push_back(prefilter_requests(plain, pick(rng)));
      want.push_back(prefilter_answers(model, pose, hf, requests.back()));
      CollideResult m;
      collide(model, pose, mesh_model, Affine::Identity(), CollideRequest{1u << 20}, m);
      EXPECT_EQ(as_set(want.back().all.triangle_pairs), as_set(m.triangle_pairs));
      DistanceResult md;
      distance(model, pose, mesh_model, Affine::Identity(), DistanceRequest{}, md);
      EXPECT_EQ(plain.distance, md.distance);
      for (const DistanceResult& d : want.back().distance) tested_none += d.triangle_pairs_tested;
      tested_none += want.back().all.triangle_pairs_tested;
    }
    EXPECT_GT(found, 2);
    if (c.name != "tiny" && c.name != "far") {
      EXPECT_GT(contact, 0);
    }
    for (int isa = 0; isa < kIsaCount; ++isa) {
      const LeafKernels* k = leaf_kernels_for(static_cast<Isa>(isa));
      if (k == nullptr) continue;
      SCOPED_TRACE(k->name);
      set_leaf_kernels(*k);
      std::uint64_t tested = 0;
      for (std::size_t p = 0; p < c.poses.size(); ++p) {
        const PrefilterAnswers got = prefilter_answers(model, c.poses[p], hf, requests[p]);
        for (std::size_t q = 0; q < requests[p].size(); ++q) {
          tested += got.distance[q].triangle_pairs_tested;
          EXPECT_TRUE(testing::same_answer(got.distance[q], want[p].distance[q])) << "pose " << p << " request " << q;
        }
        tested += got.all.triangle_pairs_tested;
        EXPECT_EQ(got.all.collide, want[p].all.collide) << "pose " << p;
        EXPECT_EQ(got.all.triangle_pairs, want[p].all.triangle_pairs) << "pose " << p;
        EXPECT_EQ(got.first.triangle_pairs, want[p].first.triangle_pairs) << "pose " << p;
        EXPECT_TRUE(testing::same_answer(got.contact, want[p].contact)) << "pose " << p;
      }
      // The filters proved something: fewer pairs reached the exact tests.
      EXPECT_LT(tested, tested_none);
    }
  }
}

}  // namespace
}  // namespace plancheck
