// SPDX-License-Identifier: MIT
// Exact signs of the orientation determinants on double inputs. These are the
// slow path behind the filtered predicates of kernels/predicates.h: called
// only when the floating-point filter cannot certify a sign. Every double is
// an exact dyadic rational, so scaling all inputs by one power of two turns
// them into integers and the determinant sign is computed in GMP integers
// (no rounding anywhere). Out of line so the header-only kernels stay free of
// allocation themselves; GMP allocates here.
#pragma once

namespace plancheck {

// Sign (-1, 0, +1) of det[b-a, c-a] for 2D points given as (x, y).
int exact_orient2d(const double* a, const double* b, const double* c) noexcept;

// Sign (-1, 0, +1) of det[b-a, c-a, d-a] for 3D points: positive when d lies
// on the side of plane (a, b, c) that (b-a) x (c-a) points to.
int exact_orient3d(const double* a, const double* b, const double* c, const double* d) noexcept;

// How many times the exact fallbacks ran in this thread (for tests and
// measurements of filter efficiency).
unsigned long long exact_fallback_count() noexcept;

}  // namespace plancheck
