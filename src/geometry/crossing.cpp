// SPDX-License-Identifier: MIT
// Robust crossing witness (src/geometry/crossing.h).
#include "src/geometry/crossing.h"

#include <cmath>
#include <limits>

namespace plancheck {

namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();
// Relative pad for the bounds' own rounding (a handful of operations on
// positive terms, each within eps).
constexpr double kPad = 1.0 + 1e-12;

// The sign det(u, v, w) keeps whatever motion moves the vectors by at most
// eu, ev, ew: +1 or -1, 0 when it is not certain.
int certain_sign(const Vec3& u, const Vec3& v, const Vec3& w, double eu, double ev, double ew) {
  const double nu = u.norm() * kPad, nv = v.norm() * kPad, nw = w.norm() * kPad;
  // The computed differences are within eps of their norms of the exact ones.
  eu += kEps * nu;
  ev += kEps * nv;
  ew += kEps * nw;
  // (|u| + eu)(|v| + ev)(|w| + ew) - |u| |v| |w|, expanded (no cancellation).
  const double motion = eu * nv * nw + nu * ev * nw + nu * nv * ew + eu * ev * nw + eu * nv * ew + nu * ev * ew +
                        eu * ev * ew;
  const double slack = (motion + 128.0 * kEps * nu * nv * nw) * kPad;
  const double d = u.dot(v.cross(w));
  if (!std::isfinite(d) || !std::isfinite(slack)) return 0;
  if (d > slack) return 1;
  if (d < -slack) return -1;
  return 0;
}

// Edge pq (corners moving by at most dp) through the interior of triangle
// t (corners moving by at most dt), for every such motion.
bool edge_crosses(const Vec3& p, const Vec3& q, double dp, const Vec3* t, double dt) {
  const Vec3 u = t[1] - t[0], v = t[2] - t[0];
  const int sp = certain_sign(u, v, p - t[0], 2.0 * dt, 2.0 * dt, dp + dt);
  if (sp == 0) return false;
  const int sq = certain_sign(u, v, q - t[0], 2.0 * dt, 2.0 * dt, dp + dt);
  if (sq != -sp) return false;
  const Vec3 e = q - p;
  int side = 0;
  for (int i = 0; i < 3; ++i) {
    const int s = certain_sign(e, t[i] - p, t[(i + 1) % 3] - t[i], 2.0 * dp, dp + dt, 2.0 * dt);
    if (s == 0 || (side != 0 && s != side)) return false;
    side = s;
  }
  return true;
}

}  // namespace

bool crossing_certain(const std::array<Vec3, 6>& corners, double da, double db) {
  if (!(da >= 0.0) || !(db >= 0.0)) return false;  // NaN or negative moves prove nothing
  for (const Vec3& c : corners)
    if (!c.allFinite()) return false;
  const Vec3* a = corners.data();
  const Vec3* b = corners.data() + 3;
  for (int i = 0; i < 3; ++i)
    if (edge_crosses(a[i], a[(i + 1) % 3], da, b, db) || edge_crosses(b[i], b[(i + 1) % 3], db, a, da)) return true;
  return false;
}

}  // namespace plancheck
