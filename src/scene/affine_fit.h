// SPDX-License-Identifier: MIT
// How far one affine map y = A x + t can take points x to points y, in the
// least-squares sense: the 3ds loader accepts a match of the file's faces to
// assimp's mesh only when that fit is within a tolerance (model_loader.cpp).
#pragma once

#include "src/scene/scene.h"

#include <vector>

namespace plancheck {

// The largest |A x_i + t - y_i| over i for the least-squares (A, t), from the
// 3x3 moments about the means (no n x 4 system: two passes over the points,
// no allocation beyond the inputs). Directions in which the x spread less
// than 1e-6 of their widest spread (a flat or linear object) are left out of
// the fit: the points do not tell the map there. Infinity when x and y differ
// in length, are empty, or anything is not finite.
double affine_fit_residual(const std::vector<Vec3>& x, const std::vector<Vec3>& y);

}  // namespace plancheck
