// SPDX-License-Identifier: MIT
#include "src/scene/affine_fit.h"

#include <Eigen/Core>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

namespace plancheck {

double affine_fit_residual(const std::vector<Vec3>& x, const std::vector<Vec3>& y) {
  const double infinity = std::numeric_limits<double>::infinity();
  const std::size_t n = x.size();
  if (n == 0 || y.size() != n) return infinity;
  // Centring first keeps the moments well conditioned (the fit's translation
  // is then mean_y - C^T mean_x).
  Eigen::Vector3d mean_x = Eigen::Vector3d::Zero(), mean_y = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    if (!x[i].allFinite() || !y[i].allFinite()) return infinity;
    mean_x += x[i];
    mean_y += y[i];
  }
  mean_x /= static_cast<double>(n);
  mean_y /= static_cast<double>(n);
  Eigen::Matrix3d g = Eigen::Matrix3d::Zero(), b = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d xc = x[i] - mean_x, yc = y[i] - mean_y;
    g.noalias() += xc * xc.transpose();
    b.noalias() += xc * yc.transpose();
  }
  // Least squares: G C = B with G = sum xc xc^T, B = sum xc yc^T; G is
  // symmetric, so its pseudo-inverse from its eigen-decomposition, without
  // the directions of (relatively) no spread.
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(g);
  if (eig.info() != Eigen::Success) return infinity;
  const Eigen::Vector3d lambda = eig.eigenvalues();
  const double largest = lambda.cwiseAbs().maxCoeff();
  Eigen::Vector3d inverse = Eigen::Vector3d::Zero();
  for (int k = 0; k < 3; ++k)
    if (lambda[k] > 1e-12 * largest) inverse[k] = 1.0 / lambda[k];
  const Eigen::Matrix3d c = eig.eigenvectors() * inverse.asDiagonal() * eig.eigenvectors().transpose() * b;
  if (!c.allFinite()) return infinity;
  // The largest squared residual, one square root at the end (the root is
  // monotone: the same maximum).
  const Eigen::Matrix3d ct = c.transpose();
  double worst2 = 0.0;
  for (std::size_t i = 0; i < n; ++i) worst2 = std::max(worst2, (mean_y + ct * (x[i] - mean_x) - y[i]).squaredNorm());
  return std::sqrt(worst2);
}

}  // namespace plancheck
