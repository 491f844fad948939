// SPDX-License-Identifier: MIT
// The generator's own forward kinematics (independent of src/scene/kinematics.cpp,
// so tests can compare the two) and the synthetic regolith DEM.
#include "datasets/change5.h"

#include <cmath>
#include <cstdint>
#include <random>

namespace plancheck::dataset {
namespace {

constexpr double kPi = 3.14159265358979323846;

Affine rotation_about(const Vec3& pivot, const Vec3& axis, double deg) {
  Affine t = Affine::Identity();
  t.translate(pivot);
  t.rotate(Eigen::AngleAxisd(deg * kPi / 180.0, axis.normalized()));
  t.translate(-pivot);
  return t;
}

// Uniform double in [0, 1) from the raw 64-bit engine output: std's
// distributions differ between standard libraries, this does not.
double unit(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * (1.0 / 9007199254740992.0); }

struct Crater {
  double x, y, radius, depth;
};
struct Rock {
  double x, y, radius, height;
};

// Smoothstep-interpolated lattice noise on a 0.1 m lattice (value noise).
class ValueNoise {
 public:
  ValueNoise(std::mt19937_64& rng, int n, double spacing) : n_(n), spacing_(spacing) {
    values_.resize(static_cast<std::size_t>(n * n));
    for (double& v : values_) v = 2.0 * unit(rng) - 1.0;
  }
  double operator()(double x, double y) const {
    double fx = x / spacing_, fy = y / spacing_;
    int ix = static_cast<int>(std::floor(fx)), iy = static_cast<int>(std::floor(fy));
    double tx = fx - ix, ty = fy - iy;
    tx = tx * tx * (3 - 2 * tx);
    ty = ty * ty * (3 - 2 * ty);
    auto at = [&](int i, int j) {
      i = ((i % n_) + n_) % n_;
      j = ((j % n_) + n_) % n_;
      return values_[static_cast<std::size_t>(j * n_ + i)];
    };
    double a = at(ix, iy) + tx * (at(ix + 1, iy) - at(ix, iy));
    double b = at(ix, iy + 1) + tx * (at(ix + 1, iy + 1) - at(ix, iy + 1));
    return a + ty * (b - a);
  }

 private:
  int n_;
  double spacing_;
  std::vector<double> values_;
};

}  // namespace

std::array<Affine, 4> chain_poses(const Joints& q) {
  const Affine a1 = rotation_about({kShoulderPivot.x(), kShoulderPivot.y(), 0.0}, Vec3::UnitZ(), q[0]);
  const Affine a2 = rotation_about(kShoulderPivot, kPitchAxis, q[1]);
  const Affine a3 = rotation_about(kElbowPivot, kPitchAxis, q[2]);
  const Affine a4 = rotation_about(kWristPivot, kPitchAxis, q[3]);
  std::array<Affine, 4> out;
  out[0] = a1;
  out[1] = out[0] * a2;
  out[2] = out[1] * a3;
  out[3] = out[2] * a4;
  return out;
}

Vec3 scoop_bottom(const Joints& q) { return chain_poses(q)[3] * kScoopBottom; }

std::vector<double> build_terrain() {
  std::mt19937_64 rng(0xC4A46E5u);  // fixed seed: the same site every run
  const double size = kDemSize * kDemCell;
  // Local coordinates (u, v) from the grid's lower-left corner, metres.
  std::vector<Crater> craters{{0.55, 2.35, 0.28, 0.06}, {2.45, 0.60, 0.40, 0.08}, {2.60, 2.55, 0.18, 0.03},
                              {1.15, 0.35, 0.15, 0.025}};
  std::vector<Rock> rocks{{0.40, 0.55, 0.07, 0.05}, {2.75, 1.55, 0.10, 0.07}, {1.85, 2.80, 0.06, 0.04},
                          {0.95, 2.85, 0.05, 0.035}, {2.20, 1.95, 0.045, 0.03}};
  // Small random jitter so the site is not hand-placed looking; still fixed.
  for (Crater& c : craters) c.depth *= 0.8 + 0.4 * unit(rng);
  for (Rock& r : rocks) r.height *= 0.8 + 0.4 * unit(rng);
  ValueNoise coarse(rng, 16, 0.25), fine(rng, 64, 0.06);

  std::vector<double> h(static_cast<std::size_t>(kDemSize * kDemSize));
  for (int row = 0; row < kDemSize; ++row) {
    for (int col = 0; col < kDemSize; ++col) {
      // Cell centres (ESRI: xllcorner is the corner, values sit at centres).
      double u = (col + 0.5) * kDemCell;
      double v = size - (row + 0.5) * kDemCell;
      // A gentle slope down and away from the lander (about 1.5 degrees).
      double z = -0.026 * (u - 0.3) + 0.006 * (v - 1.5);
      z += 0.012 * coarse(u, v) + 0.004 * fine(u, v);
      for (const Crater& c : craters) {
        double d = std::hypot(u - c.x, v - c.y) / c.radius;
        // Bowl inside, raised rim that fades out by 1.6 radii.
        if (d < 1.0) z += c.depth * (d * d - 1.0) + 0.15 * c.depth;
        else if (d < 1.6) z += 0.15 * c.depth * (1.0 - (d - 1.0) / 0.6) * (1.0 - (d - 1.0) / 0.6);
      }
      for (const Rock& r : rocks) {
        double d2 = ((u - r.x) * (u - r.x) + (v - r.y) * (v - r.y)) / (r.radius * r.radius);
        if (d2 < 1.0) z += r.height * std::sqrt(1.0 - d2);
      }
      // Stored rounded to 0.1 mm, as written to site.asc.
      h[static_cast<std::size_t>(row * kDemSize + col)] = std::round(z * 1e4) / 1e4;
    }
  }
  return h;
}

double terrain_height(const std::vector<double>& dem, double x, double y) {
  const double size = kDemSize * kDemCell;
  double u = x - kDemOrigin.x(), v = y - kDemOrigin.y();
  double fc = u / kDemCell - 0.5, fr = (size - v) / kDemCell - 0.5;
  auto clampi = [](int i) { return i < 0 ? 0 : (i > kDemSize - 1 ? kDemSize - 1 : i); };
  int c0 = static_cast<int>(std::floor(fc)), r0 = static_cast<int>(std::floor(fr));
  double tc = fc - c0, tr = fr - r0;
  auto at = [&](int r, int c) { return dem[static_cast<std::size_t>(clampi(r) * kDemSize + clampi(c))]; };
  double a = at(r0, c0) + tc * (at(r0, c0 + 1) - at(r0, c0));
  double b = at(r0 + 1, c0) + tc * (at(r0 + 1, c0 + 1) - at(r0 + 1, c0));
  return a + tr * (b - a) + kDemOrigin.z();
}

}  // namespace plancheck::dataset
