// SPDX-License-Identifier: MIT
// A model loaded through assimp and through the strict native 3ds reader
// (src/scene/tds_native.h): the two answers equal field by field, bit for
// bit (origins and vertices compared as bytes, so -0 and 0 differ).
#pragma once

#include "src/base/error.h"
#include "src/scene/model_loader.h"

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <string>

namespace plancheck::testing {

// load_model's outcome: the error message ("" when it loaded) and the scene.
struct ModelOutcome {
  std::string error;
  Scene scene;
};

inline ModelOutcome load_model_outcome(const std::filesystem::path& file, bool native, double scale = 0.25) {
  ModelOutcome o;
  IsolationLimits limits;
  limits.native_3ds = native;
  try {
    load_model(file, scale, o.scene, limits);
  } catch (const InputError& e) {
    o.error = e.what();
  }
  return o;
}

inline bool same_bits(const Vec3& a, const Vec3& b) { return std::memcmp(a.data(), b.data(), 3 * sizeof(double)) == 0; }

inline void expect_same_model(const ModelOutcome& assimp, const ModelOutcome& native, const std::string& label) {
  ASSERT_EQ(assimp.error, native.error) << label;
  const Scene &a = assimp.scene, &n = native.scene;
  ASSERT_EQ(a.nodes.size(), n.nodes.size()) << label;
  for (std::size_t i = 0; i < a.nodes.size(); ++i) {
    const Node &x = a.nodes[i], &y = n.nodes[i];
    EXPECT_TRUE(x.name == y.name && x.path == y.path && x.parent == y.parent && x.part == y.part &&
                x.children == y.children && same_bits(x.origin, y.origin))
        << label << " node " << i << " " << x.path << " / " << y.path;
  }
  ASSERT_EQ(a.parts.size(), n.parts.size()) << label;
  for (std::size_t i = 0; i < a.parts.size(); ++i) {
    const Part &x = a.parts[i], &y = n.parts[i];
    EXPECT_TRUE(x.name == y.name && x.node == y.node) << label << " part " << i;
    ASSERT_EQ(x.mesh.vertices.size(), y.mesh.vertices.size()) << label << " part " << i;
    for (std::size_t v = 0; v < x.mesh.vertices.size(); ++v)
      ASSERT_TRUE(same_bits(x.mesh.vertices[v], y.mesh.vertices[v])) << label << " part " << i << " vertex " << v;
    EXPECT_EQ(x.mesh.triangles, y.mesh.triangles) << label << " part " << i;
  }
  EXPECT_EQ(a.warnings, n.warnings) << label;
}

}  // namespace plancheck::testing
