// SPDX-License-Identifier: MIT
// Plans follow the paper's tasks: from the stowed arm, scoop at a sampling
// point, lift, move over the storage can on the deck and empty the scoop into
// it; plan10 takes the can by its bail and carries it over the ascender's
// receptacle. Four plans are designed to fail in a known way (see datasets/README.md).
#include "datasets/plans.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace plancheck::dataset {
namespace {

constexpr double kPi = 3.14159265358979323846;
double deg(double r) { return r * 180.0 / kPi; }
double rad(double d) { return d * kPi / 180.0; }

// Minimum-jerk blend: zero velocity and acceleration at both ends.
double min_jerk(double t) { return t * t * t * (10.0 - 15.0 * t + 6.0 * t * t); }

// The CSV keeps 6 decimals; plans are checked as the verifier will read them.
Joints round_state(const Joints& q) {
  Joints r;
  for (int k = 0; k < 4; ++k) {
    r[static_cast<std::size_t>(k)] = std::round(q[static_cast<std::size_t>(k)] * 1e6) / 1e6;
    if (r[static_cast<std::size_t>(k)] == 0.0) r[static_cast<std::size_t>(k)] = 0.0;  // no "-0.000000"
  }
  return r;
}

// A waypoint is either a joint vector or a scoop pose (M, pitch) reached in a
// straight Cartesian line (used in the soil, where the path matters).
struct Waypoint {
  bool cartesian = false;
  Joints q{};
  Vec3 m = Vec3::Zero();
  double pitch = 0.0;
  double weight = 1.0;  // share of the plan's states spent reaching it
};

Waypoint joint(const Joints& q, double weight) { return {false, q, Vec3::Zero(), 0.0, weight}; }
Waypoint pose(const Vec3& m, double pitch, double weight, bool cartesian) {
  Waypoint w{cartesian, inverse_kinematics(m, pitch), m, pitch, weight};
  return w;
}

// States: the first waypoint, then each segment's share of the remaining
// count (largest remainder rounding, so the total is exact).
std::vector<Joints> interpolate(const std::vector<Waypoint>& wps, int total) {
  std::size_t segs = wps.size() - 1;
  double sum = 0;
  for (std::size_t k = 1; k < wps.size(); ++k) sum += wps[k].weight;
  int steps = total - 1;
  std::vector<int> n(segs);
  std::vector<std::pair<double, std::size_t>> frac;
  int used = 0;
  for (std::size_t k = 0; k < segs; ++k) {
    double exact = steps * wps[k + 1].weight / sum;
    n[k] = std::max(1, static_cast<int>(std::floor(exact)));
    used += n[k];
    frac.push_back({exact - std::floor(exact), k});
  }
  std::stable_sort(frac.begin(), frac.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  for (std::size_t i = 0; used < steps; i = (i + 1) % segs, ++used) ++n[frac[i].second];
  for (std::size_t i = 0; used > steps; i = (i + 1) % segs)
    if (n[frac[segs - 1 - i].second] > 1) {
      --n[frac[segs - 1 - i].second];
      --used;
    }
  std::vector<Joints> out{round_state(wps[0].q)};
  for (std::size_t k = 0; k < segs; ++k) {
    const Waypoint& a = wps[k];
    const Waypoint& b = wps[k + 1];
    for (int j = 1; j <= n[k]; ++j) {
      double s = min_jerk(static_cast<double>(j) / n[k]);
      Joints q;
      if (b.cartesian) {
        Vec3 ma = a.cartesian ? a.m : scoop_bottom(a.q);
        double pa = a.cartesian ? a.pitch : (a.q[1] + a.q[2] + a.q[3]);
        q = inverse_kinematics(ma + s * (b.m - ma), pa + s * (b.pitch - pa));
      } else {
        for (std::size_t i = 0; i < 4; ++i) q[i] = a.q[i] + s * (b.q[i] - a.q[i]);
      }
      out.push_back(round_state(q));
    }
  }
  if (static_cast<int>(out.size()) != total) throw std::logic_error("plan state count");
  return out;
}

// Where the scoop digs: point on the site (x, y), the soil surface there.
struct Site {
  double x, y;
};

const Joints kStow{0.0, 40.0, -100.0, 60.0};
constexpr double kPourTilt = 70.0;  // deg the scoop is tipped nose down to pour

Vec3 radial_at(const Vec3& p) {
  return Vec3(p.x() - kShoulderPivot.x(), p.y() - kShoulderPivot.y(), 0).normalized();
}

// The common sampling part of a plan: stow -> above the site -> into the soil,
// down to 3 cm over 5 cm, a 5 cm drag outwards at that depth -> out and up.
std::vector<Waypoint> scoop_at(const std::vector<double>& dem, const Site& site, const Joints& start) {
  Vec3 s{site.x, site.y, 0};
  Vec3 r = radial_at(s);
  auto ground = [&](const Vec3& p) { return terrain_height(dem, p.x(), p.y()); };
  Vec3 entry = s - 0.05 * r;
  Vec3 drag_end = s + 0.05 * r;
  std::vector<Waypoint> w;
  w.push_back(joint(start, 0));
  w.push_back(pose(Vec3(entry.x(), entry.y(), ground(entry) + 0.25), -15.0, 6.0, false));
  w.push_back(pose(Vec3(entry.x(), entry.y(), ground(entry) + 0.01), -20.0, 2.0, true));
  w.push_back(pose(Vec3(s.x(), s.y(), ground(s) - 0.03), -10.0, 1.5, true));
  w.push_back(pose(Vec3(drag_end.x(), drag_end.y(), ground(drag_end) - 0.03), 0.0, 1.5, true));
  w.push_back(pose(Vec3(drag_end.x(), drag_end.y(), ground(drag_end) + 0.30), 10.0, 2.0, true));
  return w;
}

// The scoop tipped nose down with its bottom point over the can's opening.
Waypoint pour_pose(double weight) {
  return pose(kCanCentre + Vec3(0, 0, kCanHeight + 0.30), -kPourTilt, weight, false);
}

// Over the can, then the scoop tips forward to pour.
void empty_into_can(std::vector<Waypoint>& w, double transit_j2_extra = 0.0) {
  Vec3 above = kCanCentre + Vec3(0, 0, kCanHeight + 0.32);
  Joints over = inverse_kinematics(above, 10.0);
  // A high transit: the scoop crosses the deck well above everything.
  Vec3 high = kCanCentre + 0.9 * radial_at(kCanCentre) + Vec3(0, 0, 1.25);
  Joints mid = inverse_kinematics(high, 10.0);
  mid[1] += transit_j2_extra;
  mid[3] -= transit_j2_extra;
  w.push_back(joint(mid, 5.0));
  w.push_back(joint(over, 4.0));
  w.push_back(pour_pose(2.0));
}

PlanOut make(const std::string& name, const std::string& task, const std::string& designed, const std::vector<Waypoint>& w,
             int states) {
  return {name, task, designed, interpolate(w, states)};
}

// Minimum over the states whose scoop is within `radius` of `near`
// (capped at the checker's cutoff).
double plan_min_distance(const Checker& checker, const std::vector<Joints>& states, const Vec3& near, double radius,
                         bool& collided) {
  double best = 1e9;
  collided = false;
  for (const Joints& q : states) {
    if ((scoop_bottom(q) - near).norm() > radius) continue;
    StateCheck c = checker.check(q);
    best = std::min(best, c.min_distance);
    collided = collided || c.collision;
  }
  return best;
}

}  // namespace

Joints inverse_kinematics(const Vec3& m, double pitch) {
  const Vec3 d = kScoopBottom - kWristPivot;  // (0.30, 0, -0.30) at pitch 0
  double p = rad(pitch);
  double dr = d.x() * std::cos(p) - d.z() * std::sin(p);
  double dz = d.x() * std::sin(p) + d.z() * std::cos(p);
  double j1 = std::atan2(m.y() - kShoulderPivot.y(), m.x() - kShoulderPivot.x());
  double mr = std::hypot(m.x() - kShoulderPivot.x(), m.y() - kShoulderPivot.y());
  double wr = mr - dr, wz = m.z() - dz - kShoulderPivot.z();
  double dd = wr * wr + wz * wz;
  double c = (dd - kUpperArm * kUpperArm - kForearm * kForearm) / (2.0 * kUpperArm * kForearm);
  if (c < -1.0 || c > 1.0) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "inverse kinematics: (%.3f, %.3f, %.3f) out of reach", m.x(), m.y(), m.z());
    throw std::logic_error(buf);
  }
  double q = std::acos(c);
  double j2 = std::atan2(wz, wr) + std::atan2(kForearm * std::sin(q), kUpperArm + kForearm * std::cos(q));
  double j3 = -q;
  return {deg(j1), deg(j2), deg(j3), pitch - deg(j2) - deg(j3)};
}

std::vector<PlanOut> build_plans(const std::vector<double>& dem, const Checker& checker) {
  // Sampling points on the site, spread like a real campaign's.
  const Site sites[10] = {{3.20, 0.10}, {3.60, -0.55}, {2.75, 0.65}, {2.45, 1.10}, {3.95, 0.35},
                          {2.90, -0.95}, {2.40, 1.20}, {3.35, 0.95}, {3.05, -0.30}, {0, 0}};
  std::vector<PlanOut> plans;
  auto standard = [&](int i, const std::string& task) {
    auto w = scoop_at(dem, sites[i], kStow);
    empty_into_can(w);
    char name[16];
    std::snprintf(name, sizeof name, "plan%02d", i + 1);
    return make(name, task, "safe", w, kPlanStates[static_cast<std::size_t>(i)]);
  };
  plans.push_back(standard(0, "scoop at the site centre, empty into the storage can"));
  plans.push_back(standard(1, "scoop right of centre, empty into the storage can"));
  plans.push_back(standard(2, "scoop left of centre, empty into the storage can"));

  // plan04: lifts out of the soil and swings towards the can too low: the
  // scoop cuts through the +y solar wing for a few states (a fast swing, so
  // the first bad state is already a collision).
  auto low_swing = [&](int i, double via_z, double weight) {
    auto w = scoop_at(dem, sites[i], kStow);
    Vec3 via = Vec3(kShoulderPivot.x(), kShoulderPivot.y(), 0) + 2.0 * Vec3(std::cos(rad(102)), std::sin(rad(102)), 0);
    via.z() = via_z;
    w.push_back(pose(via, 0.0, weight, false));
    empty_into_can(w);
    return w;
  };
  plans.push_back(make("plan04", "scoop at the left edge, swing low over the +y solar wing (designed collision)", "collision",
                       low_swing(3, 1.07, 2.0), kPlanStates[3]));
  plans.push_back(standard(4, "scoop far out, empty into the storage can"));
  plans.push_back(standard(5, "scoop at the right edge, empty into the storage can"));

  // plan07: the same manoeuvre with the via point raised until the closest
  // approach to the wing is about 3 cm: inside the 5 cm margin, no contact.
  {
    double lo = 1.10, hi = 1.40;  // via heights: lo too low, hi clear
    for (int it = 0; it < 12; ++it) {
      double mid = 0.5 * (lo + hi);
      bool hit = false;
      Vec3 via = Vec3(kShoulderPivot.x(), kShoulderPivot.y(), mid) + 2.0 * Vec3(std::cos(rad(102)), std::sin(rad(102)), 0);
      double d = plan_min_distance(checker, interpolate(low_swing(6, mid, 4.0), kPlanStates[6]), via, 0.8, hit);
      if (hit || d < 0.03) lo = mid;
      else hi = mid;
    }
    plans.push_back(make("plan07", "scoop at the left edge, pass 3 cm over the +y solar wing (designed clearance violation)",
                         "clearance", low_swing(6, hi, 4.0), kPlanStates[6]));
  }
  plans.push_back(standard(7, "scoop left, empty into the storage can"));
  // plan09: transit with the shoulder raised past its 115 deg limit.
  {
    auto w = scoop_at(dem, sites[8], kStow);
    Joints over = inverse_kinematics(kCanCentre + Vec3(0, 0, kCanHeight + 0.32), 10.0);
    Joints up = over;
    up[1] = kLimits[1].upper + 6.0;
    up[3] = over[3] - 6.0;
    w.push_back(joint(up, 5.0));
    w.push_back(joint(over, 4.0));
    w.push_back(pour_pose(2.0));
    plans.push_back(make("plan09", "scoop near the centre, transit with J2 past its upper limit (designed limits violation)",
                         "limits", w, kPlanStates[8]));
  }
  // plan10: take the can by its bail with the hook behind the bucket, lift it
  // and carry it over the ascender's receptacle.
  {
    Vec3 r = radial_at(kCanCentre);
    Vec3 bail_top = kCanCentre + Vec3(0, 0, kCanHeight + kHandleLift + kHandleSpan);
    // The hook's centre sits 0.10 behind and 0.10 above M at pitch 0.
    Vec3 grasp = bail_top + 0.10 * r - Vec3(0, 0, 0.10);
    std::vector<Waypoint> w;
    w.push_back(joint(kStow, 0));
    w.push_back(pose(grasp + Vec3(0, 0, 0.25), 0.0, 5.0, false));
    w.push_back(pose(grasp + Vec3(0, 0, 0.04), 0.0, 2.0, true));
    w.push_back(pose(grasp + Vec3(0.0, 0, 0.0), 0.0, 1.0, true));
    w.push_back(pose(grasp + Vec3(0, 0, 0.45), 0.0, 2.0, true));
    Vec3 place = kReceptacleCentre + Vec3(0, 0, kReceptacleHeight + 0.13);
    w.push_back(pose(place + Vec3(0, 0, 0.35), 0.0, 6.0, false));
    w.push_back(pose(place, 0.0, 2.5, true));
    plans.push_back(make("plan10", "take the storage can by its bail and carry it over the ascender's receptacle", "safe", w,
                         kPlanStates[9]));
  }
  return plans;
}

}  // namespace plancheck::dataset
