// SPDX-License-Identifier: MIT
// Forward kinematics against poses computed by hand, the composition order of
// the contract, units (m/cm/mm, deg/rad) and limits.
#include "src/scene/kinematics.h"

#include "src/scene/scene_loader.h"
#include "tests/foundation/fixtures.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <limits>
#include <string>
#include <vector>

namespace plancheck {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The arm with J1 (z through the origin) on arm1, J2 (y through x = 1) on
// arm2, and on tip a translation along x (Ext, listed first) and a scale about
// (2, 0, 0) (Grow); lengths multiplied by `unit`, angles given in `angle_unit`.
std::filesystem::path write_arm_scene(const testing::TempDir& dir, const std::string& length_unit, double unit,
                                      const std::string& angle_unit) {
  const std::string model = "arm_" + length_unit + ".gltf";
  testing::write_arm_model(dir / model, unit);
  const double limit = angle_unit == "deg" ? 90.0 : kPi / 2;
  auto n = [&](double v) { return std::to_string(v * unit); };
  return dir.write("arm_" + length_unit + "_" + angle_unit + ".json",
                   R"({"format": "plancheck-scene/1", "model": ")" + model + R"(", "length_unit": ")" + length_unit +
                       R"(", "angle_unit": ")" + angle_unit + R"(", "actions": [
      {"name": "J1", "node": "arm1", "type": "rotate", "pivot": [0, 0, 0], "axis": [0, 0, 1], "limits": [)" +
                       std::to_string(-limit) + ", " + std::to_string(limit) + R"(]},
      {"name": "J2", "node": "arm2", "type": "rotate", "pivot": [)" + n(1) + R"(, 0, 0], "axis": [0, 1, 0]},
      {"name": "Ext", "node": "tip", "type": "translate", "axis": [2, 0, 0], "limits": [0, )" + n(0.5) + R"(]},
      {"name": "Grow", "node": "tip", "type": "scale", "fixed_point": [)" + n(2) + R"(, 0, 0]}]})");
}

// Parameters as a plan writes them: J1, J2 (the scene's angle unit), Ext
// (its length unit), Grow.x/y/z.
std::vector<double> params(double j1, double j2, double ext, Vec3 grow) {
  return {j1, j2, ext, grow.x(), grow.y(), grow.z()};
}

TEST(Kinematics, HandComputedPoseOfTheTip) {
  testing::TempDir dir;
  const Scene s = load_scene(write_arm_scene(dir, "m", 1.0, "deg"));
  ASSERT_EQ(s.parameter_names, (std::vector<std::string>{"J1", "J2", "Ext", "Grow.x", "Grow.y", "Grow.z"}));
  const auto p = params(90, 90, 0.5, {2, 1, 1});
  const Affine t = part_transform(s, s.find_part("tip"), p);
  // Tip corner (2.25, 0.125, 0.25):
  //   Grow about (2,0,0) by (2,1,1)       -> (2.5, 0.125, 0.25)
  //   Ext +0.5 along x                    -> (3.0, 0.125, 0.25)
  //   J2 +90 deg about y through (1,0,0)  -> (1,0,0) + (0.25, 0.125, -2.0) = (1.25, 0.125, -2.0)
  //   J1 +90 deg about z through origin   -> (-0.125, 1.25, -2.0)
  EXPECT_LT((t * Vec3(2.25, 0.125, 0.25) - Vec3(-0.125, 1.25, -2.0)).norm(), 1e-12);
  // arm2's far corner (2, 0.125, 0.25) only sees J2 then J1.
  const Affine t2 = part_transform(s, s.find_part("arm2"), p);
  EXPECT_LT((t2 * Vec3(2, 0.125, 0.25) - Vec3(-0.125, 1.25, -1.0)).norm(), 1e-12);
  // Static parts do not move.
  EXPECT_TRUE(part_transform(s, s.find_part("base"), p).matrix().isIdentity(0.0));
}

TEST(Kinematics, CompositionOrderIsRootFirst) {
  // A1(A2(x)) and A2(A1(x)) differ for J1 then J2: check the contract's order
  // on a generic pose against an explicit Rodrigues rotation.
  testing::TempDir dir;
  const Scene s = load_scene(write_arm_scene(dir, "m", 1.0, "rad"));
  auto rodrigues = [](const Vec3& u, double a, const Vec3& pivot, const Vec3& x) {
    const Vec3 v = x - pivot;
    return Vec3(v * std::cos(a) + u.cross(v) * std::sin(a) + u * u.dot(v) * (1 - std::cos(a)) + pivot);
  };
  const double j1 = 0.7, j2 = -1.1, ext = 0.3;
  const Vec3 grow(1.5, 0.5, 2.0);
  const Vec3 x(2.2, -0.1, 0.2);
  Vec3 expected = Vec3(2, 0, 0) + (x - Vec3(2, 0, 0)).cwiseProduct(grow);  // Grow (innermost)
  expected += Vec3(ext, 0, 0);                                            // Ext
  expected = rodrigues(Vec3::UnitY(), j2, Vec3(1, 0, 0), expected);       // J2
  expected = rodrigues(Vec3::UnitZ(), j1, Vec3::Zero(), expected);        // J1 (outermost)
  const auto p = params(j1, j2, ext, grow);
  EXPECT_LT((part_transform(s, s.find_part("tip"), p) * x - expected).norm(), 1e-12);
  std::vector<Affine> chains;
  chain_transforms(s, p, chains);
  ASSERT_EQ(chains.size(), s.chains.size());
  for (const Part& part : s.parts)
    EXPECT_TRUE(chains[part.chain_id].isApprox(part_transform(s, static_cast<int>(&part - s.parts.data()), p)))
        << part.name;
}

// One action of a random type about random points and axes (half of the
// rotations in degrees), its parameters from `first` on.
Action random_action(std::mt19937& rng, int first) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Action a;
  a.type = static_cast<ActionType>(rng() % 4);
  a.pivot = Vec3(u(rng), u(rng), u(rng)) * 3.0;
  a.axis = Vec3(u(rng), u(rng), u(rng)).normalized();
  a.fixed_point = Vec3(u(rng), u(rng), u(rng));
  a.first_parameter = first;
  a.parameter_count = a.type == ActionType::kTranslateFree || a.type == ActionType::kScale ? 3 : 1;
  if (a.type == ActionType::kRotate && rng() % 2 == 0) {
    a.unit_to_si = kPi / 180.0;
    a.whole_turn = 360.0;
  }
  return a;
}

// count random actions into s.actions (random_action's), a third of the
// one-parameter ones after the first made mimics of an earlier
// one-parameter action (multiplier and offset random); scales: keep
// random_action's scales (else three in four become rotations). Returns
// how many parameters they read.
int random_actions(std::mt19937& rng, int count, bool scales, Scene& s) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int parameters = 0;
  for (int i = 0; i < count; ++i) {
    Action a = random_action(rng, parameters);
    if (!scales && a.type == ActionType::kScale && rng() % 4 != 0) a.type = ActionType::kRotate, a.parameter_count = 1;
    parameters += a.parameter_count;
    if (i > 0 && a.parameter_count == 1 && rng() % 3 == 0) {  // a mimic of an earlier one-parameter action
      const int master = static_cast<int>(rng() % static_cast<unsigned>(i));
      const Action& m = s.actions[static_cast<std::size_t>(master)];
      if (m.parameter_count == 1 && m.mimic < 0) {
        a.mimic = master;
        a.multiplier = u(rng) * 2.0;
        a.offset = u(rng);
        parameters -= 1;
        a.parameter_count = 0;
      }
    }
    s.actions.push_back(a);
  }
  return parameters;
}

// chain_transforms continues the product of an earlier chain that begins
// a chain; every chain must still be exactly (bit for bit) the product of
// its own actions from the first, root first (compose), whatever the order of the
// chains: prefixes before and after their extensions, branches, repeats, the
// empty chain, and chains that share actions but not as a prefix.
TEST(Kinematics, ChainTransformsEqualEachChainComposedAlone) {
  std::mt19937 rng(16);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    Scene s;
    const int action_count = 6;
    int parameters = 0;
    for (int i = 0; i < action_count; ++i) {
      Action a = random_action(rng, parameters);
      parameters += a.parameter_count;
      s.actions.push_back(a);
    }
    // Chains: random prefixes of a few random root-first sequences, in random order.
    std::vector<std::vector<int>> roots(3);
    for (auto& r : roots)
      for (int i = 0; i < 5; ++i) r.push_back(static_cast<int>(rng() % action_count));
    const int chain_count = 1 + static_cast<int>(rng() % 8);
    for (int c = 0; c < chain_count; ++c) {
      const auto& r = roots[rng() % roots.size()];
      s.chains.emplace_back(r.begin(), r.begin() + static_cast<long>(rng() % (r.size() + 1)));
    }
    std::vector<double> p(static_cast<std::size_t>(parameters));
    for (double& v : p) v = u(rng) * (trial % 2 == 0 ? 4.0 : 400.0);
    std::vector<Affine> chains;
    chain_transforms(s, p, chains);
    ASSERT_EQ(chains.size(), s.chains.size());
    for (std::size_t c = 0; c < s.chains.size(); ++c) {
      Affine t = Affine::Identity();
      for (int a : s.chains[c]) t = t * action_transform_at(s, s.actions[static_cast<std::size_t>(a)], p);
      EXPECT_EQ(std::memcmp(t.matrix().data(), chains[c].matrix().data(), sizeof(double) * 16), 0)
          << "trial " << trial << " chain " << c;
    }
  }
}

// ChainCache against each chain composed alone, bit for bit (memcmp): random
// actions of every type, some of them mimic joints of an earlier action,
// chains of random actions, and parameter vectors in a row that change a
// random suffix, a random single parameter, nothing, or flip a value's sign
// bit at 0 (-0 and 0 pose differently), or hold a NaN; the cache's first
// call and calls after every kind of change.
TEST(Kinematics, ChainCacheEqualsTheChainComposedAlone) {
  std::mt19937 rng(33);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int reused = 0;
  for (int trial = 0; trial < 100; ++trial) {
    Scene s;
    const int action_count = 7;
    const int parameters = random_actions(rng, action_count, true, s);
    std::vector<int> chain;
    for (int i = 0; i < 1 + static_cast<int>(rng() % 6); ++i) chain.push_back(static_cast<int>(rng() % action_count));
    ChainCache cache(s, chain);
    std::vector<double> p(static_cast<std::size_t>(parameters));
    for (double& v : p) v = u(rng) * 40.0;
    for (int step = 0; step < 60; ++step) {
      const int kind = static_cast<int>(rng() % 5);
      if (kind == 0) {  // a random suffix
        for (std::size_t k = rng() % p.size(); k < p.size(); ++k) p[k] = u(rng) * 40.0;
      } else if (kind == 1) {  // one parameter
        p[rng() % p.size()] = u(rng) * 40.0;
      } else if (kind == 2) {  // a zero, then its sign flipped
        double& v = p[rng() % p.size()];
        v = v == 0.0 ? -v : 0.0;
      } else if (kind == 3 && rng() % 4 == 0) {  // a NaN
        p[rng() % p.size()] = std::numeric_limits<double>::quiet_NaN();
      }  // else nothing changes
      // The chain composed alone, as compose does it: from its first action.
      Affine t = action_transform_at(s, s.actions[static_cast<std::size_t>(chain[0])], p);
      for (std::size_t k = 1; k < chain.size(); ++k) t = t * action_transform_at(s, s.actions[static_cast<std::size_t>(chain[k])], p);
      const Affine& c = cache(p);
      ASSERT_EQ(std::memcmp(t.matrix().data(), c.matrix().data(), sizeof(double) * 16), 0)
          << "trial " << trial << " step " << step << " kind " << kind;
      reused += kind == 4;
    }
  }
  EXPECT_GT(reused, 100);
}

// part_transform_velocity against the pose itself: its transform is
// part_transform's bit for bit, and its velocity field (w, u) is the
// derivative of the posed points along the motion p + h r: against a
// central difference of part_transform at h = +-1e-6 (error about h^2
// times the third derivative, far below the tolerance), for random chains
// of rotations (radians and degrees past a whole turn), translations
// along an axis and free ones, mimics of earlier actions with their
// multipliers; false where the chain has a scale action.
TEST(Kinematics, PartVelocityIsTheDerivativeOfThePose) {
  std::mt19937 rng(71);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int checked = 0, scaled = 0;
  for (int trial = 0; trial < 300; ++trial) {
    Scene s;
    const int action_count = 6;
    const int parameters = random_actions(rng, action_count, false, s);
    Part part;
    for (int i = 0; i < 1 + static_cast<int>(rng() % 6); ++i) part.chain.push_back(static_cast<int>(rng() % action_count));
    s.parts.push_back(part);
    std::vector<double> p(static_cast<std::size_t>(parameters)), r(p.size());
    for (std::size_t k = 0; k < p.size(); ++k) {
      p[k] = u(rng) * (trial % 2 == 0 ? 2.0 : 400.0);
      r[k] = u(rng) * 1.5;
    }
    bool has_scale = false;
    for (int a : part.chain) has_scale = has_scale || s.actions[static_cast<std::size_t>(a)].type == ActionType::kScale;
    Affine t;
    Vec3 w(7, 7, 7), v(7, 7, 7);
    const bool ok = part_transform_velocity(s, 0, p, r, t, w, v);
    const Affine want = part_transform(s, 0, p);
    ASSERT_EQ(std::memcmp(t.matrix().data(), want.matrix().data(), sizeof(double) * 16), 0) << "trial " << trial;
    ASSERT_EQ(ok, !has_scale) << "trial " << trial;
    if (!ok) {
      ++scaled;
      continue;
    }
    const double h = 1e-6;
    std::vector<double> plus(p), minus(p);
    for (std::size_t k = 0; k < p.size(); ++k) {
      plus[k] = p[k] + h * r[k];
      minus[k] = p[k] - h * r[k];
    }
    const Affine tp = part_transform(s, 0, plus), tm = part_transform(s, 0, minus);
    for (int k = 0; k < 5; ++k) {
      const Vec3 x = Vec3(u(rng), u(rng), u(rng)) * 2.0;
      const Vec3 numeric = (tp * x - tm * x) / (2.0 * h);
      const Vec3 field = w.cross(t * x) + v;
      EXPECT_LT((numeric - field).norm(), 1e-5 * (1.0 + field.norm())) << "trial " << trial << " point " << k;
      ++checked;
    }
  }
  EXPECT_GT(checked, 1000);
  EXPECT_GT(scaled, 5);
}

// A rotation's transform is built without Eigen's products by the
// identity (src/scene/kinematics.cpp): it must be the very transform that
// Identity().translate(p).rotate(R).translate(-p) gives, bit for bit (a
// zero's sign aside), or every distance downstream could move by an ulp.
// Pivots from 1e-6 to 1e6 m and zero coordinates of either sign, axes
// random and along the frame's, angles in radians and in degrees past a
// whole turn.
TEST(Kinematics, RotationIsEigensIdentityTranslateRotateTranslateBitForBit) {
  std::mt19937_64 rng(20261202);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::size_t compared = 0;
  for (int n = 0; n < 200000; ++n) {
    Action a;
    a.type = ActionType::kRotate;
    const double scale = std::pow(10.0, 6.0 * u(rng));
    a.pivot = Vec3(u(rng), u(rng), u(rng)) * scale;
    if (n % 5 == 0) a.pivot[n % 3] = n % 2 ? 0.0 : -0.0;
    a.axis = n % 7 == 0 ? Vec3::Unit(n % 3) : Vec3(u(rng), u(rng), u(rng)).normalized();
    double value = 4.0 * u(rng);
    if (n % 3 == 0) {
      a.unit_to_si = std::acos(-1.0) / 180.0;
      a.whole_turn = 360.0;
      value *= 300.0;
    }
    Affine expected = Affine::Identity();
    expected.translate(a.pivot);
    expected.rotate(Eigen::AngleAxisd(pose_value(a, value), a.axis));
    expected.translate(-a.pivot);
    const Affine got = action_transform(a, &value);
    for (int i = 0; i < 16; ++i) {
      const double x = got.matrix().data()[i], y = expected.matrix().data()[i];
      ASSERT_TRUE(std::memcmp(&x, &y, sizeof x) == 0 || (x == 0.0 && y == 0.0))
          << "case " << n << ", coefficient " << i << ": " << x << " against " << y;
      ++compared;
    }
  }
  EXPECT_EQ(compared, 16u * 200000u);
}

TEST(Kinematics, RightHandedRotation) {
  Action a;
  a.type = ActionType::kRotate;
  a.axis = Vec3::UnitZ();
  a.pivot = Vec3(1, 1, 0);
  const double angle = kPi / 2;
  // Counter-clockwise looking down -z: +x turns into +y.
  EXPECT_LT((action_transform(a, &angle) * Vec3(2, 1, 0) - Vec3(1, 2, 0)).norm(), 1e-15);
}

TEST(Kinematics, FreeTranslationAndScaleActions) {
  Action t;
  t.type = ActionType::kTranslateFree;
  const double offset[3] = {1, -2, 3};
  EXPECT_LT((action_transform(t, offset) * Vec3(1, 1, 1) - Vec3(2, -1, 4)).norm(), 1e-15);
  Action s;
  s.type = ActionType::kScale;
  s.fixed_point = Vec3(1, 1, 1);
  const double factors[3] = {2, 3, 0.5};
  EXPECT_LT((action_transform(s, factors) * Vec3(1, 1, 1) - Vec3(1, 1, 1)).norm(), 1e-15);  // fixed point stays
  EXPECT_LT((action_transform(s, factors) * Vec3(2, 2, 3) - Vec3(3, 4, 2)).norm(), 1e-15);
  Action axis;
  axis.type = ActionType::kTranslateAxis;
  axis.axis = Vec3(0, 0.6, 0.8);
  const double d = 5;
  EXPECT_LT((action_transform(axis, &d) * Vec3::Zero() - Vec3(0, 3, 4)).norm(), 1e-15);
}

TEST(Kinematics, SameAnswersInMetresCentimetresAndMillimetres) {
  testing::TempDir dir;
  const Scene m = load_scene(write_arm_scene(dir, "m", 1.0, "deg"));
  const Scene cm = load_scene(write_arm_scene(dir, "cm", 100.0, "deg"));
  const Scene mm = load_scene(write_arm_scene(dir, "mm", 1000.0, "rad"));
  // The same pose written in each scene's units.
  const double deg = 180 / kPi;
  const auto p = params(0.4 * deg, -0.9 * deg, 0.2, {1.2, 0.8, 1.1});
  const auto p_cm = params(0.4 * deg, -0.9 * deg, 20, {1.2, 0.8, 1.1});
  const auto p_mm = params(0.4, -0.9, 200, {1.2, 0.8, 1.1});
  for (const Scene* other : {&cm, &mm}) {
    const auto& q = other == &cm ? p_cm : p_mm;
    for (std::size_t i = 0; i < m.parts.size(); ++i) {
      const Part& a = m.parts[i];
      const Part& b = other->parts[i];
      ASSERT_EQ(a.name, b.name);
      ASSERT_EQ(a.mesh.vertices.size(), b.mesh.vertices.size());
      const Affine ta = part_transform(m, static_cast<int>(i), p);
      const Affine tb = part_transform(*other, static_cast<int>(i), q);
      for (std::size_t v = 0; v < a.mesh.vertices.size(); ++v)
        EXPECT_LT((ta * a.mesh.vertices[v] - tb * b.mesh.vertices[v]).norm(), 1e-9) << a.name;
    }
    EXPECT_EQ(other->actions[2].upper, other == &cm ? 50.0 : 500.0);  // Ext limit as written
  }
  EXPECT_EQ(m.actions[0].upper, 90.0);
  EXPECT_NEAR(mm.actions[0].upper, kPi / 2, 1e-6);  // written with 6 decimals in rad
}

// Whole turns in degrees are removed exactly, and only for the pose: 720 poses
// exactly as 0, 1e300 by its exact remainder; radians are used as given.
TEST(Kinematics, WholeTurnsInDegreesPoseExactlyAndOnlyThePose) {
  testing::TempDir dir;
  const Scene s = load_scene(write_arm_scene(dir, "m", 1.0, "deg"));
  const int tip = s.find_part("tip");
  for (double turns : {-3.0, -1.0, 1.0, 2.0, 1e6}) {
    const Affine a = part_transform(s, tip, params(30, -45, 0.1, {1, 1, 1}));
    const Affine b = part_transform(s, tip, params(30 + 360 * turns, -45 - 360 * turns, 0.1, {1, 1, 1}));
    EXPECT_EQ(a.matrix(), b.matrix()) << turns;
  }
  EXPECT_TRUE(part_transform(s, tip, params(720, -1080, 0, {1, 1, 1})).matrix().isIdentity(0.0));
  // 1e300 = 360 k + r exactly for some integer k; r = std::remainder(1e300, 360).
  const double r = std::remainder(1e300, 360.0);
  EXPECT_EQ(part_transform(s, tip, params(1e300, 0, 0, {1, 1, 1})).matrix(),
            part_transform(s, tip, params(r, 0, 0, {1, 1, 1})).matrix());
  EXPECT_EQ(pose_value(s.actions[0], 200), std::remainder(200.0, 360.0) * kPi / 180);  // -160 deg in rad
  EXPECT_EQ(pose_value(s.actions[2], 0.25), 0.25);                                    // metres
  const Scene mm = load_scene(write_arm_scene(dir, "mm", 1000.0, "rad"));
  EXPECT_EQ(pose_value(mm.actions[0], 7.0), 7.0);     // radians: not reduced (a turn is not a double)
  EXPECT_EQ(pose_value(mm.actions[2], 250.0), 0.25);  // millimetres to metres
}

// pose_value skips std::remainder within half a turn (where the remainder
// is the angle itself): bit for bit the library's answer everywhere, at the
// half turns, signed zeros, the nearest doubles around them, subnormals,
// huge, infinite and NaN angles, and random ones.
TEST(Kinematics, PoseValueIsTheRemainderBitForBit) {
  testing::TempDir dir;
  const Scene s = load_scene(write_arm_scene(dir, "m", 1.0, "deg"));
  const Action& j1 = s.actions[0];
  ASSERT_EQ(j1.whole_turn, 360.0);
  const auto bits = [](double x) {
    std::uint64_t b;
    std::memcpy(&b, &x, sizeof b);
    return b;
  };
  std::vector<double> angles = {0.0, -0.0, 180.0, -180.0, 179.99999999999997, 360.0, -360.0, 540.0, -540.0,
                                1e300, -1e300, std::numeric_limits<double>::denorm_min(),
                                -std::numeric_limits<double>::denorm_min(), std::numeric_limits<double>::max(),
                                std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
                                std::numeric_limits<double>::quiet_NaN()};
  for (double h : {180.0, 360.0, 540.0, 90.0})
    for (double sign : {1.0, -1.0}) {
      const double x = sign * h;
      angles.push_back(std::nextafter(x, 0.0));
      angles.push_back(std::nextafter(x, 2 * x));
    }
  std::mt19937_64 rng(33005);
  std::uniform_real_distribution<double> near(-400.0, 400.0), far(-1e6, 1e6);
  for (int i = 0; i < 20000; ++i) angles.push_back(i % 2 ? near(rng) : far(rng));
  for (double x : angles) {
    const double want = std::remainder(x, 360.0) * j1.unit_to_si;
    EXPECT_EQ(bits(pose_value(j1, x)), bits(want)) << x;
  }
}

TEST(Kinematics, LimitsCompareAsWritten) {
  testing::TempDir dir;
  const Scene s = load_scene(write_arm_scene(dir, "m", 1.0, "deg"));
  EXPECT_EQ(first_limit_violation(s, params(90, 0, 0.5, {1, 1, 1})), -1);  // on the limit is inside
  EXPECT_EQ(first_limit_violation(s, params(-90, 0, 0, {1, 1, 1})), -1);
  EXPECT_EQ(first_limit_violation(s, params(90.001, 0, 0, {1, 1, 1})), 0);
  // 450 and -270 pose like 90, but as written they are past the limit.
  EXPECT_EQ(first_limit_violation(s, params(450, 0, 0, {1, 1, 1})), 0);
  EXPECT_EQ(first_limit_violation(s, params(-270, 0, 0, {1, 1, 1})), 0);
  const Scene cm = load_scene(write_arm_scene(dir, "cm", 100.0, "deg"));
  EXPECT_EQ(first_limit_violation(cm, params(0, 0, 50, {1, 1, 1})), -1);  // 50 cm: on the limit
  EXPECT_EQ(first_limit_violation(cm, params(0, 0, 50.001, {1, 1, 1})), 2);
  EXPECT_EQ(first_limit_violation(s, params(0, 0, 0.5001, {1, 1, 1})), 2);
  EXPECT_EQ(first_limit_violation(s, params(0, 5, -0.1, {1, 1, 1})), 2);  // J2 has no limits
  EXPECT_EQ(first_limit_violation(s, params(std::numeric_limits<double>::quiet_NaN(), 0, 0, {1, 1, 1})), 0);
}

TEST(Kinematics, RigidUnlessScaled) {
  testing::TempDir dir;
  const Scene s = load_scene(write_arm_scene(dir, "m", 1.0, "deg"));
  EXPECT_TRUE(is_rigid(part_transform(s, s.find_part("tip"), params(17, 69, 0.1, {1, 1, 1}))));
  EXPECT_FALSE(is_rigid(part_transform(s, s.find_part("tip"), params(17, 69, 0.1, {1, 1.01, 1}))));
  Affine mirror = Affine::Identity();
  mirror.linear().diagonal() << 1, 1, -1;
  EXPECT_FALSE(is_rigid(mirror));
}

}  // namespace
}  // namespace plancheck
