// SPDX-License-Identifier: MIT
// affine_fit_residual (the 3ds loader's match test, from 3x3 moments) against
// the plain least squares it replaced: a column-pivoted QR of the n x 4
// system [x 1] A = y, on random point sets, exact and noisy maps, singular
// maps, and degenerate point sets (one point, collinear, coplanar).
#include "src/scene/affine_fit.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <Eigen/QR>
#include <Eigen/SVD>

#include <cmath>
#include <limits>
#include <random>

namespace plancheck {
namespace {

double qr_residual(const std::vector<Vec3>& x, const std::vector<Vec3>& y) {
  const Eigen::Index n = static_cast<Eigen::Index>(x.size());
  Eigen::MatrixXd a(n, 4), b(n, 3);
  for (Eigen::Index i = 0; i < n; ++i) {
    a.row(i) << x[static_cast<std::size_t>(i)].transpose(), 1.0;
    b.row(i) = y[static_cast<std::size_t>(i)].transpose();
  }
  const Eigen::MatrixXd m = a.colPivHouseholderQr().solve(b);
  return (a * m - b).rowwise().norm().maxCoeff();
}

// The same least squares by another road: an SVD of the centred points,
// directions below 1e-6 of the largest singular value left out.
double svd_residual(const std::vector<Vec3>& x, const std::vector<Vec3>& y) {
  const Eigen::Index n = static_cast<Eigen::Index>(x.size());
  Eigen::MatrixXd a(n, 3), b(n, 3);
  Vec3 mx = Vec3::Zero(), my = Vec3::Zero();
  for (std::size_t i = 0; i < x.size(); ++i) {
    mx += x[i];
    my += y[i];
  }
  mx /= static_cast<double>(n);
  my /= static_cast<double>(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    a.row(i) = (x[static_cast<std::size_t>(i)] - mx).transpose();
    b.row(i) = (y[static_cast<std::size_t>(i)] - my).transpose();
  }
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(a, Eigen::ComputeThinU | Eigen::ComputeThinV);
  svd.setThreshold(1e-6);
  const Eigen::MatrixXd c = svd.solve(b);
  return (a * c - b).rowwise().norm().maxCoeff();
}

double spread(const std::vector<Vec3>& y) {
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const Vec3& p : y) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  return std::max(1.0, (hi - lo).norm());
}

TEST(AffineFit, AgreesWithQrOnRandomAndDegenerateSets) {
  std::mt19937_64 rng(20261126);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_int_distribution<int> count(1, 300), kind(0, 4), map_kind(0, 2);
  const double noises[] = {0.0, 1e-9, 1e-6, 3e-5, 1e-3, 1e-1};
  int compared = 0, accepted = 0, refused = 0;
  for (int trial = 0; trial < 600; ++trial) {
    const int n = count(rng);
    const double scale = std::pow(10.0, 3.0 * u(rng));  // 1e-3 .. 1e3
    const Vec3 offset(100 * u(rng), 100 * u(rng), 100 * u(rng));
    const Vec3 d1 = Vec3(u(rng), u(rng), u(rng)).normalized(), d2 = Vec3(u(rng), u(rng), u(rng)).normalized();
    const int k = kind(rng);
    std::vector<Vec3> x(static_cast<std::size_t>(n));
    for (Vec3& p : x) {
      switch (k) {
        case 0: p = offset; break;                                             // one point, repeated
        case 1: p = offset + scale * u(rng) * d1; break;                       // collinear
        case 2: p = offset + scale * (u(rng) * d1 + u(rng) * d2); break;       // coplanar
        default: p = offset + scale * Vec3(u(rng), u(rng), u(rng)); break;    // general
      }
    }
    Eigen::Matrix3d a;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) a(i, j) = u(rng);
    if (map_kind(rng) == 0) a = Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized().toRotationMatrix();
    if (map_kind(rng) == 0) a.col(0) = a.col(1);  // singular
    const Vec3 t(10 * u(rng), 10 * u(rng), 10 * u(rng));
    const double noise = noises[trial % 6];
    std::vector<Vec3> y(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) y[i] = a * x[i] + t + noise * scale * Vec3(u(rng), u(rng), u(rng));
    const double ours = affine_fit_residual(x, y), reference = qr_residual(x, y), svd = svd_residual(x, y);
    const double size = spread(y), tolerance = 1e-4 * size;
    SCOPED_TRACE(testing::Message() << "trial " << trial << " n " << n << " kind " << k << " noise " << noise
                                    << " scale " << scale);
    ASSERT_TRUE(std::isfinite(ours));
    // Least-squares residuals: equal up to rounding (relative to the points'
    // size). On degenerate sets the QR, without a centring, may take a
    // rounding-level column for a direction and fit some of the noise; the
    // SVD of the centred points, like the moments, leaves such directions out.
    EXPECT_NEAR(ours, svd, 1e-6 * size + 1e-6 * svd);
    if (k >= 3) {
      EXPECT_NEAR(ours, reference, 1e-6 * size + 1e-6 * reference);
    }
    // The loader's decision, away from the tolerance itself.
    if (std::abs(reference - tolerance) > 0.05 * tolerance) {
      EXPECT_EQ(ours <= tolerance, reference <= tolerance);
      ++compared;
      (reference <= tolerance ? accepted : refused)++;
    }
  }
  EXPECT_GT(compared, 500);
  EXPECT_GT(accepted, 100);
  EXPECT_GT(refused, 100);
}

TEST(AffineFit, RefusesWhatItCannotFit) {
  const double inf = std::numeric_limits<double>::infinity();
  const std::vector<Vec3> three = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  EXPECT_EQ(affine_fit_residual({}, {}), inf);
  EXPECT_EQ(affine_fit_residual(three, {{0, 0, 0}}), inf);
  std::vector<Vec3> bad = three;
  bad[1].x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(affine_fit_residual(bad, three), inf);
  EXPECT_EQ(affine_fit_residual(three, bad), inf);
  bad[1].x() = inf;
  EXPECT_EQ(affine_fit_residual(three, bad), inf);
  // An exact map fits to rounding; a bent one does not.
  std::vector<Vec3> x = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}}, y;
  for (const Vec3& p : x) y.push_back(Vec3(2 * p.x() + p.y(), -p.z(), 3 * p.y()) + Vec3(5, 6, 7));
  EXPECT_LT(affine_fit_residual(x, y), 1e-12);
  y[4].z() += 1.0;
  EXPECT_GT(affine_fit_residual(x, y), 0.1);
}

}  // namespace
}  // namespace plancheck
