// SPDX-License-Identifier: MIT
// Two distance answers equal bit for bit: what a fast path must give when it
// claims to return the slow path's own answer (not merely a close one).
#pragma once

#include "src/geometry/collision_model.h"

#include <gtest/gtest.h>

namespace plancheck::testing {

inline ::testing::AssertionResult same_answer(const DistanceResult& got, const DistanceResult& want) {
  auto differs = [](const char* field) { return ::testing::AssertionFailure() << "answers differ in " << field; };
  if (got.found != want.found) return differs("found");
  if (got.distance != want.distance) return differs("distance");
  if (got.triangle_a != want.triangle_a || got.triangle_b != want.triangle_b) return differs("triangles");
  if (got.slot_a != want.slot_a || got.slot_b != want.slot_b) return differs("slots");
  for (int k = 0; k < 3; ++k)
    if (got.point_a[k] != want.point_a[k] || got.point_b[k] != want.point_b[k]) return differs("points");
  return ::testing::AssertionSuccess();
}

}  // namespace plancheck::testing
