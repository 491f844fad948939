// SPDX-License-Identifier: MIT
// A contact certificate that survives motion: two triangles that cross with
// room to spare still intersect after every corner of one moves by up to
// da and every corner of the other by up to db (any motion, rigid or not).
// The sweep uses it to call a whole box of configurations "in contact"
// from one pose at its centre (src/checks/sweep_certify.h).
//
// The witness is an edge pq of one triangle through the interior of the
// other, T = (t0, t1, t2), read from five signed volumes (orientation
// determinants, as in Moller's and Guigue-Devillers' triangle tests):
//   det(t1 - t0, t2 - t0, p - t0) and det(t1 - t0, t2 - t0, q - t0) of
//   opposite signs (p and q on either side of T's plane), and
//   det(q - p, ti - p, t(i+1) - ti) for i = 0, 1, 2 of one sign (the line
//   pq passes inside T's three edges),
// all strict. Each volume det(u, v, w) moves by at most
//   (|u| + eu)(|v| + ev)(|w| + ew) - |u| |v| |w|
// when its vectors move by at most eu, ev, ew (expand the trilinear form:
// every other term is a triple product bounded by the product of norms); a
// difference of corners moves by at most the sum of their moves. So each
// volume whose magnitude exceeds that bound keeps its sign under every such
// motion, and the edge still crosses T's interior: the triangles intersect.
// Rounding: the differences are computed in double (each within eps of its
// norm, added to the moves) and a volume in double errs by far less than
// 128 eps |u| |v| |w| (the sum of its six products' magnitudes is at most
// 3^(3/2) |u| |v| |w|; a few roundings each); the bounds are padded
// relatively for their own rounding. A non-finite input gives false.
#pragma once

#include "src/scene/scene.h"

#include <array>

namespace plancheck {

// True when triangles a = corners[0..2] and b = corners[3..5] (m) are
// certain to intersect whenever each corner of a is moved by at most da
// and each corner of b by at most db (m). False proves nothing.
bool crossing_certain(const std::array<Vec3, 6>& corners, double da, double db);

}  // namespace plancheck
