// SPDX-License-Identifier: MIT
#include "src/geometry/exact.h"

#include <gmp.h>

#include <algorithm>
#include <climits>
#include <cmath>

namespace plancheck {
namespace {

thread_local unsigned long long fallback_count = 0;

// Splits x = m * 2^k with m an integer of at most 53 bits (k is the exponent
// of the last mantissa bit). Zero gets k = INT_MAX so it never sets the scale.
void split(double x, double& m, int& k) {
  if (x == 0.0) {
    m = 0.0;
    k = INT_MAX;
    return;
  }
  int e = 0;
  const double f = std::frexp(x, &e);  // x = f * 2^e, 0.5 <= |f| < 1
  m = std::ldexp(f, 53);               // exact: an integer below 2^53
  k = e - 53;
}

// Holds n doubles as GMP integers X_i = x_i * 2^-kmin (exact).
template <int N>
struct ScaledInts {
  mpz_t v[N];
  explicit ScaledInts(const double* const* x, const int* dims, int points) {
    double m[N];
    int k[N];
    int kmin = INT_MAX;
    int n = 0;
    for (int p = 0; p < points; ++p)
      for (int d = 0; d < dims[p]; ++d, ++n) {
        split(x[p][d], m[n], k[n]);
        kmin = std::min(kmin, k[n]);
      }
    for (int i = 0; i < N; ++i) {
      mpz_init_set_d(v[i], m[i]);
      if (m[i] != 0.0) mpz_mul_2exp(v[i], v[i], static_cast<unsigned long>(k[i] - kmin));
    }
  }
  ~ScaledInts() {
    for (int i = 0; i < N; ++i) mpz_clear(v[i]);
  }
  ScaledInts(const ScaledInts&) = delete;
  ScaledInts& operator=(const ScaledInts&) = delete;
};

}  // namespace

int exact_orient2d(const double* a, const double* b, const double* c) noexcept {
  ++fallback_count;
  const double* pts[3] = {a, b, c};
  const int dims[3] = {2, 2, 2};
  ScaledInts<6> s(pts, dims, 3);
  mpz_t bx, by, cx, cy, t;
  mpz_inits(bx, by, cx, cy, t, nullptr);
  mpz_sub(bx, s.v[2], s.v[0]);
  mpz_sub(by, s.v[3], s.v[1]);
  mpz_sub(cx, s.v[4], s.v[0]);
  mpz_sub(cy, s.v[5], s.v[1]);
  mpz_mul(t, bx, cy);
  mpz_submul(t, by, cx);
  const int sign = mpz_sgn(t);
  mpz_clears(bx, by, cx, cy, t, nullptr);
  return sign;
}

int exact_orient3d(const double* a, const double* b, const double* c, const double* d) noexcept {
  ++fallback_count;
  const double* pts[4] = {a, b, c, d};
  const int dims[4] = {3, 3, 3, 3};
  ScaledInts<12> s(pts, dims, 4);
  // Rows u = b-a, v = c-a, w = d-a; det = u . (v x w).
  mpz_t u[3], v[3], w[3], t, acc;
  for (int i = 0; i < 3; ++i) {
    mpz_init(u[i]);
    mpz_init(v[i]);
    mpz_init(w[i]);
    mpz_sub(u[i], s.v[3 + i], s.v[i]);
    mpz_sub(v[i], s.v[6 + i], s.v[i]);
    mpz_sub(w[i], s.v[9 + i], s.v[i]);
  }
  mpz_inits(t, acc, nullptr);
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    mpz_mul(t, v[j], w[k]);
    mpz_submul(t, v[k], w[j]);
    mpz_addmul(acc, u[i], t);
  }
  const int sign = mpz_sgn(acc);
  for (int i = 0; i < 3; ++i) {
    mpz_clear(u[i]);
    mpz_clear(v[i]);
    mpz_clear(w[i]);
  }
  mpz_clears(t, acc, nullptr);
  return sign;
}

unsigned long long exact_fallback_count() noexcept { return fallback_count; }

}  // namespace plancheck
