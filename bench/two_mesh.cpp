// SPDX-License-Identifier: MIT
// One ~200-triangle object at N random rigid poses over one ~2,000-triangle
// environment, as FCL's mesh-mesh tests set them up (there: env.obj and
// rob.obj, random transforms within an extent box): each pose is collided
// and, unless the meshes collide, distanced exactly, by plancheck's
// CollisionModel (src/geometry/collision_model.h, the pair query a state
// check runs per part pair) and by FCL 0.7 OBBRSS. Both meshes are made here,
// deterministically. Answers are compared pose by pose before anything is
// timed (collision flags equal, distances within 1e-9 m); 1 thread.
#include "bench/two_mesh.h"

#include "bench/fcl_peer/fcl_peer.h"
#include "bench/random_states.h"
#include "bench/timing.h"
#include "src/base/error.h"
#include "src/base/files.h"
#include "src/checks/verify.h"
#include "src/geometry/collision_model.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <memory>
#include <numbers>
#include <random>
#include <string>
#include <vector>

namespace plancheck::bench {

namespace {

using reference::FclAnswer;
using reference::FclMeshPair;

constexpr double kAgreeTolerance = 1e-9;  // m, distances plancheck vs FCL
constexpr double kPi = std::numbers::pi;

// A fixed value in [-1, 1) per index (splitmix64), so the noise is the same
// everywhere without a random engine.
double noise(std::uint64_t i) {
  std::uint64_t z = i + 0x9e3779b97f4a7c15ull;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  z ^= z >> 31;
  return static_cast<double>(z >> 11) * 0x1.0p-52 - 1.0;
}

// A uniformly distributed rotation (Shoemake's method, three uniforms) and a
// translation uniform in the box [lo, hi].
Affine random_pose(std::mt19937_64& rng, const Vec3& lo, const Vec3& hi) {
  const double u1 = unit_uniform(rng), u2 = unit_uniform(rng), u3 = unit_uniform(rng);
  const double s1 = std::sqrt(1.0 - u1), s2 = std::sqrt(u1);
  const Eigen::Quaterniond q(s2 * std::cos(2 * kPi * u3), s1 * std::sin(2 * kPi * u2), s1 * std::cos(2 * kPi * u2),
                             s2 * std::sin(2 * kPi * u3));
  Affine t = Affine::Identity();
  t.linear() = q.normalized().toRotationMatrix();
  for (int k = 0; k < 3; ++k) t.translation()[k] = uniform_between(rng, lo[k], hi[k]);
  return t;
}

struct PoseAnswer {
  bool collision = false;
  double distance = 0.0;  // m; 0 when colliding, inf when not asked
};

// plancheck's answer for one pose, as Checker::check_state asks it of one
// part pair: collide (first contact only), then the exact distance unless
// they collide (DistanceRequest with verify's tie tolerance, 1e-12 m; the
// search told the pair is disjoint, as the collision test just proved).
PoseAnswer plancheck_check(const CollisionModel& object, const Affine& pose, const CollisionModel& env,
                           bool with_distance) {
  static const Affine kIdentity = Affine::Identity();
  PoseAnswer a;
  CollideResult c;
  collide(object, pose, env, kIdentity, CollideRequest{0}, c);
  a.collision = c.collide;
  a.distance = c.collide ? 0.0 : std::numeric_limits<double>::infinity();
  if (c.collide || !with_distance) return a;
  DistanceResult d;
  DistanceRequest request{std::numeric_limits<double>::infinity(), 0.0, kDistanceTieTolerance};
  request.known_disjoint = true;
  distance(object, pose, env, kIdentity, request, d);
  a.distance = d.distance;
  return a;
}

}  // namespace

Mesh bumpy_torus() {
  constexpr int kU = 50, kV = 20;  // around the axis, around the tube
  constexpr double kMajor = 3.0, kMinor = 1.0;
  Mesh m;
  for (int i = 0; i < kU; ++i)
    for (int j = 0; j < kV; ++j) {
      const double u = 2 * kPi * i / kU, v = 2 * kPi * j / kV;
      const double r = kMinor * (1.0 + 0.18 * std::sin(5 * u + 1.0) * std::cos(3 * v) +
                                 0.08 * std::sin(13 * u) * std::sin(7 * v + 0.5) +
                                 0.03 * noise(static_cast<std::uint64_t>(i * kV + j)));
      m.vertices.emplace_back((kMajor + r * std::cos(v)) * std::cos(u), (kMajor + r * std::cos(v)) * std::sin(u),
                              r * std::sin(v));
    }
  auto at = [&](int i, int j) { return static_cast<std::uint32_t>((i % kU) * kV + (j % kV)); };
  for (int i = 0; i < kU; ++i)
    for (int j = 0; j < kV; ++j) {
      m.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      m.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  return m;
}

Mesh dented_ellipsoid() {
  constexpr int kSlices = 12, kStacks = 9;
  const Vec3 axes(0.7, 0.4, 0.3);
  Mesh m;
  m.vertices.emplace_back(0.0, 0.0, axes.z());  // top pole: 0
  for (int k = 1; k < kStacks; ++k)
    for (int j = 0; j < kSlices; ++j) {
      const double theta = kPi * k / kStacks, phi = 2 * kPi * j / kSlices;
      // Dents three times around and a waist along x: not convex.
      const double r = 1.0 - 0.22 * std::pow(std::sin(theta), 2) * (0.5 + 0.5 * std::cos(3 * phi)) -
                       0.15 * std::pow(std::sin(theta) * std::cos(phi), 2) * std::pow(std::sin(theta), 2);
      m.vertices.emplace_back(r * axes.x() * std::sin(theta) * std::cos(phi),
                              r * axes.y() * std::sin(theta) * std::sin(phi), r * axes.z() * std::cos(theta));
    }
  m.vertices.emplace_back(0.0, 0.0, -axes.z());  // bottom pole
  const auto bottom = static_cast<std::uint32_t>(m.vertices.size() - 1);
  auto at = [&](int k, int j) { return static_cast<std::uint32_t>(1 + (k - 1) * kSlices + j % kSlices); };
  for (int j = 0; j < kSlices; ++j) {
    m.triangles.push_back({0u, at(1, j), at(1, j + 1)});
    for (int k = 1; k + 1 < kStacks; ++k) {
      m.triangles.push_back({at(k, j), at(k + 1, j), at(k + 1, j + 1)});
      m.triangles.push_back({at(k, j), at(k + 1, j + 1), at(k, j + 1)});
    }
    m.triangles.push_back({at(kStacks - 1, j), bottom, at(kStacks - 1, j + 1)});
  }
  return m;
}

namespace {

// A mesh as Wavefront OBJ, coordinates to the last bit (%.17g).
std::string obj_text(const Mesh& m, const char* name) {
  std::string out = std::string("o ") + name + "\n";
  char line[128];
  for (const Vec3& v : m.vertices) {
    std::snprintf(line, sizeof line, "v %.17g %.17g %.17g\n", v.x(), v.y(), v.z());
    out += line;
  }
  for (const auto& t : m.triangles) {
    std::snprintf(line, sizeof line, "f %u %u %u\n", static_cast<unsigned>(t[0]) + 1, static_cast<unsigned>(t[1]) + 1,
                  static_cast<unsigned>(t[2]) + 1);
    out += line;
  }
  return out;
}

// The two meshes as a robot: the torus fixed to the world link, the object
// on a free-floating chain (prismatic x, y, z over the poses' box, then
// revolute z, y, x through all of [-pi, pi]), so that `plancheck bench
// DIR/two_mesh.urdf --random N` draws poses of this case and runs them
// through the state path: as a cold batch and written as one plan through
// verify_plans. Its rotations are uniform Euler angles, not Shoemake's
// uniform rotations: the same kind of case, not the same poses.
void write_urdf(const std::filesystem::path& dir, const Mesh& env, const Mesh& object, const Vec3& lo,
                const Vec3& hi) {
  std::filesystem::create_directories(dir);
  write_file_atomically(dir / "env.obj", obj_text(env, "env"));
  write_file_atomically(dir / "object.obj", obj_text(object, "object"));
  std::string u = "<?xml version=\"1.0\"?>\n<robot name=\"two_mesh\">\n";
  u += "  <link name=\"env\"><collision><geometry><mesh filename=\"env.obj\"/></geometry></collision></link>\n";
  const char* links[] = {"tx", "ty", "tz", "rz", "ry", "rx"};
  for (const char* l : links) u += std::string("  <link name=\"") + l + "_link\"/>\n";
  u += "  <link name=\"object\"><collision><geometry><mesh filename=\"object.obj\"/></geometry></collision></link>\n";
  const char* axes[] = {"1 0 0", "0 1 0", "0 0 1", "0 0 1", "0 1 0", "1 0 0"};
  char buf[512];
  for (int j = 0; j < 6; ++j) {
    const std::string parent = j == 0 ? "env" : std::string(links[j - 1]) + "_link";
    const bool slide = j < 3;
    const double lower = slide ? lo[j] : -kPi, upper = slide ? hi[j] : kPi;
    std::snprintf(buf, sizeof buf,
                  "  <joint name=\"%s\" type=\"%s\"><parent link=\"%s\"/><child link=\"%s_link\"/>"
                  "<axis xyz=\"%s\"/><limit lower=\"%.17g\" upper=\"%.17g\" effort=\"1\" velocity=\"1\"/></joint>\n",
                  links[j], slide ? "prismatic" : "revolute", parent.c_str(), links[j], axes[j], lower, upper);
    u += buf;
  }
  u += "  <joint name=\"fixed\" type=\"fixed\"><parent link=\"rx_link\"/><child link=\"object\"/></joint>\n";
  u += "</robot>\n";
  write_file_atomically(dir / "two_mesh.urdf", u);
}

}  // namespace

int run_two_mesh(int argc, char** argv) {
  CLI::App app{"plancheck_bench two_mesh: one small mesh at random rigid poses over another, beside FCL"};
  std::string json_file;
  std::size_t poses_count = 1000;
  std::uint64_t seed = 1;
  int reps = 5, fcl_reps = 3;
  bool fcl_flag = false;
  app.add_option("--poses", poses_count, "random rigid poses of the object")->check(CLI::PositiveNumber);
  app.add_option("--seed", seed, "seed of the poses (std::mt19937_64)");
  app.add_option("--repetitions", reps, "timed repetitions of plancheck (median)")->check(CLI::PositiveNumber);
  app.add_option("--fcl-repetitions", fcl_reps, "timed repetitions of FCL (median)")->check(CLI::PositiveNumber);
  app.add_option("--json", json_file, "also write the results as JSON here");
  app.add_flag("--fcl", fcl_flag, "accepted for symmetry with table3: FCL always runs here");
  std::string urdf_dir;
  app.add_option("--write-urdf", urdf_dir,
                 "write the two meshes as DIR/two_mesh.urdf (a free-floating object over the fixed torus) and stop; "
                 "`plancheck bench DIR/two_mesh.urdf --random N --fcl` then times the state and plan paths");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }

  try {
    const Mesh env_mesh = bumpy_torus();
    const Mesh object_mesh = dented_ellipsoid();
    // Poses over the torus's box grown by the object's reach, as FCL's tests
    // draw theirs within an extent box around the environment.
    const Vec3 lo(-4.6, -4.6, -1.8), hi(4.6, 4.6, 1.8);
    if (!urdf_dir.empty()) {
      write_urdf(urdf_dir, env_mesh, object_mesh, lo, hi);
      std::cerr << "two_mesh: wrote " << (std::filesystem::path(urdf_dir) / "two_mesh.urdf").string() << "\n";
      return 0;
    }
    std::mt19937_64 rng(seed);
    std::vector<Affine> poses;
    for (std::size_t i = 0; i < poses_count; ++i) poses.push_back(random_pose(rng, lo, hi));

    std::cerr << "two_mesh: building\n";
    std::unique_ptr<CollisionModel> env, object;
    const double pc_build = seconds_of([&] {
      env = std::make_unique<CollisionModel>(env_mesh);
      object = std::make_unique<CollisionModel>(object_mesh);
    });
    std::unique_ptr<FclMeshPair> fcl;
    const double fcl_build = seconds_of([&] { fcl = std::make_unique<FclMeshPair>(object_mesh, env_mesh); });
    const Affine identity = Affine::Identity();

    // 1. Answers first, pose by pose.
    std::cerr << "two_mesh: checking answers on " << poses.size() << " poses\n";
    int mismatches = 0, colliding = 0;
    double max_diff = 0.0, min_distance = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < poses.size(); ++i) {
      const PoseAnswer p = plancheck_check(*object, poses[i], *env, true);
      const PoseAnswer pc = plancheck_check(*object, poses[i], *env, false);
      const FclAnswer f = fcl->check(poses[i], identity, true);
      const FclAnswer fc = fcl->check(poses[i], identity, false);
      colliding += p.collision ? 1 : 0;
      bool bad = p.collision != f.collision || pc.collision != p.collision || fc.collision != f.collision;
      if (!p.collision && !f.collision) {
        const double d = std::abs(p.distance - f.distance);
        max_diff = std::max(max_diff, d);
        min_distance = std::min(min_distance, p.distance);
        bad = bad || !(d <= kAgreeTolerance);
      }
      if (bad) {
        ++mismatches;
        std::cerr << "MISMATCH pose " << i << ": plancheck collision " << p.collision << " distance " << p.distance
                  << ", FCL collision " << f.collision << " distance " << f.distance << "\n";
      }
    }
    if (mismatches > 0) {
      std::cerr << "two_mesh: " << mismatches << " poses disagree; nothing timed\n";
      return 3;
    }
    std::cerr << "two_mesh: answers agree with FCL (max distance difference " << fmt(max_diff, "%.3g") << " m)\n";

    // 2. Timing, 1 thread.
    std::cerr << "two_mesh: timing (" << reps << " / " << fcl_reps << " repetitions, median)\n";
    auto pc_all = [&](bool with_distance) {
      return median_seconds(reps, [&] {
        for (const Affine& t : poses) plancheck_check(*object, t, *env, with_distance);
      });
    };
    auto fcl_all = [&](bool with_distance) {
      return median_seconds(fcl_reps, [&] {
        for (const Affine& t : poses) fcl->check(t, identity, with_distance);
      });
    };
    const double pc_1 = pc_all(true), pc_collide_1 = pc_all(false);
    const double fcl_s = fcl_all(true), fcl_collide = fcl_all(false);

    const std::size_t n = poses.size();
    auto us = [&](double s) { return fmt(1e6 * s / static_cast<double>(n), "%.2f"); };
    std::ostream& out = std::cout;
    out << "Two meshes at random rigid poses: object " << object_mesh.triangles.size()
        << " triangles (dented ellipsoid) over environment " << env_mesh.triangles.size()
        << " triangles (bumpy torus); " << n << " poses (seed " << seed << "), " << colliding << " colliding\n";
    out << "machine: " << cpu_model() << "; 1 thread; plancheck CollisionModel collide (+ exact distance unless "
           "colliding), FCL 0.7 OBBRSS fcl::collide (+ fcl::distance); medians of "
        << reps << " (plancheck) and " << fcl_reps << " (FCL) runs\n\n";
    out << "| query | plancheck s | plancheck us/pose | FCL s | FCL us/pose | FCL/plancheck |\n|---|---|---|---|---|---|\n";
    out << "| collision + distance | " << fmt(pc_1, "%.4f") << " | " << us(pc_1) << " | " << fmt(fcl_s, "%.4f") << " | "
        << us(fcl_s) << " | " << fmt(fcl_s / pc_1, "%.2f") << " |\n";
    out << "| collision only | " << fmt(pc_collide_1, "%.4f") << " | " << us(pc_collide_1) << " | "
        << fmt(fcl_collide, "%.4f") << " | " << us(fcl_collide) << " | " << fmt(fcl_collide / pc_collide_1, "%.2f")
        << " |\n";
    out << "\nanswers: collision flags equal on every pose, distances within " << fmt(max_diff, "%.3g")
        << " m of FCL's; build: plancheck " << fmt(pc_build, "%.4f") << " s, FCL " << fmt(fcl_build, "%.4f") << " s\n";

    if (!json_file.empty()) {
      nlohmann::json j;
      j["format"] = "plancheck-bench-two-mesh/1";
      j["machine"] = cpu_model();
      j["threads"] = 1;
      j["seed"] = seed;
      j["repetitions"] = reps;
      j["fcl_repetitions"] = fcl_reps;
      j["triangles"] = {{"environment", env_mesh.triangles.size()}, {"object", object_mesh.triangles.size()}};
      j["build_seconds"] = {{"plancheck", pc_build}, {"fcl", fcl_build}};
      j["answers_checked_against_fcl"] = true;
      j["max_distance_difference_vs_fcl"] = max_diff;
      j["total"] = {{"poses", n},
                    {"colliding_poses", colliding},
                    {"min_distance", std::isfinite(min_distance) ? nlohmann::json(min_distance) : nlohmann::json()},
                    {"plancheck_seconds_1_thread", pc_1},
                    {"plancheck_collide_seconds_1_thread", pc_collide_1},
                    {"fcl_seconds", fcl_s},
                    {"fcl_collide_seconds", fcl_collide},
                    {"fcl_over_plancheck_1_thread", fcl_s / pc_1},
                    {"fcl_over_plancheck_collide", fcl_collide / pc_collide_1}};
      write_json_text(json_file, j.dump(2));
    }
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "plancheck bench: " << e.what() << "\n";
    return 2;
  }
}

}  // namespace plancheck::bench
