// SPDX-License-Identifier: MIT
// A 3ds file written by the project's own writer (datasets/tds_writer.h), read
// back through the real loader: names, parents, and every triangle's vertices.
#include "src/scene/model_loader.h"
#include "datasets/tds_writer.h"
#include "support/fixtures.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>

namespace plancheck {
namespace {

using Triangle9 = std::array<double, 9>;

TdsMesh grid_mesh(int n, float x0, float z) {
  // An n x n vertex grid with a gentle bump, so no two triangles coincide.
  TdsMesh m;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      m.vertices.push_back({x0 + 0.01f * i, 0.01f * j, z + 0.001f * static_cast<float>((i * 7 + j * 13) % 17)});
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const auto v = static_cast<std::uint32_t>(j * n + i);
      const auto w = static_cast<std::uint32_t>(n);
      m.faces.push_back({v, v + 1, v + w + 1});
      m.faces.push_back({v, v + w + 1, v + w});
    }
  return m;
}

TdsMesh box(float x0, float y0, float z0, float s) {
  TdsMesh m;
  for (int i = 0; i < 8; ++i) m.vertices.push_back({x0 + (i & 1 ? s : 0), y0 + (i & 2 ? s : 0), z0 + (i & 4 ? s : 0)});
  m.faces = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
             {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  return m;
}

std::vector<Triangle9> triangles_of(const TdsMesh& m) {
  std::vector<Triangle9> out;
  for (const auto& f : m.faces) {
    Triangle9 t;
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c) t[static_cast<std::size_t>(3 * k + c)] = m.vertices[f[static_cast<std::size_t>(k)]][static_cast<std::size_t>(c)];
    out.push_back(t);
  }
  return out;
}

std::vector<Triangle9> triangles_of(const Mesh& m) {
  std::vector<Triangle9> out;
  for (const Tri& f : m.triangles) {
    Triangle9 t;
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c) t[static_cast<std::size_t>(3 * k + c)] = m.vertices[f[static_cast<std::size_t>(k)]][c];
    out.push_back(t);
  }
  return out;
}

TEST(TdsRoundTrip, HierarchySplitObjectsAndEveryVertexSurviveTheLoader) {
  // probe -> {Body (split: > 65,535 vertices), Leg}; arm -> J1 -> {Link1, J2 -> Tip}
  std::vector<TdsNode> nodes(8);
  nodes[0] = {"probe", -1, {}};
  nodes[1] = {"Body", 0, grid_mesh(260, 0.0f, 1.0f)};
  nodes[2] = {"Leg", 0, box(-1.0f, -1.0f, 0.0f, 0.2f)};
  nodes[3] = {"arm", -1, {}};
  nodes[4] = {"J1", 3, {}};
  nodes[5] = {"Link1", 4, box(0.5f, 0.5f, 1.5f, 0.3f)};
  nodes[6] = {"J2", 4, {}};
  nodes[7] = {"Tip", 6, box(1.0f, 0.5f, 1.5f, 0.1f)};
  ASSERT_GT(nodes[1].mesh.vertices.size(), kTdsMaxObjectElements);
  const auto body_objects = tds_object_names(nodes[1]);
  ASSERT_GE(body_objects.size(), 2u);

  testing::TempDir dir("tds-roundtrip");
  tds_write(dir / "model.3ds", nodes);
  Scene scene;
  load_model(dir / "model.3ds", 1.0, scene);

  std::map<std::string, int> node_by_name;
  for (std::size_t i = 0; i < scene.nodes.size(); ++i) node_by_name[scene.nodes[i].name] = static_cast<int>(i);
  auto parent_name = [&](const std::string& name) {
    const int n = node_by_name.at(name);
    const int p = scene.nodes[static_cast<std::size_t>(n)].parent;
    return p < 0 ? std::string("<none>") : scene.nodes[static_cast<std::size_t>(p)].name;
  };
  for (const char* name : {"probe", "Body", "Leg", "arm", "J1", "Link1", "J2", "Tip"})
    ASSERT_TRUE(node_by_name.count(name)) << name;
  EXPECT_EQ(parent_name("Body"), "probe");
  EXPECT_EQ(parent_name("Leg"), "probe");
  EXPECT_EQ(parent_name("J1"), "arm");
  EXPECT_EQ(parent_name("Link1"), "J1");
  EXPECT_EQ(parent_name("J2"), "J1");
  EXPECT_EQ(parent_name("Tip"), "J2");
  EXPECT_EQ(parent_name("probe"), parent_name("arm"));  // both under the file's root

  // The split object's pieces are parts grouped under their node, and
  // together they hold exactly the written triangles.
  std::vector<Triangle9> body;
  for (const std::string& piece : body_objects) {
    ASSERT_TRUE(node_by_name.count(piece)) << piece;
    EXPECT_EQ(parent_name(piece), "Body");
    const int part = scene.find_part(piece);
    ASSERT_GE(part, 0) << piece;
    const auto t = triangles_of(scene.parts[static_cast<std::size_t>(part)].mesh);
    body.insert(body.end(), t.begin(), t.end());
  }
  auto expected = triangles_of(nodes[1].mesh);
  std::sort(expected.begin(), expected.end());
  std::sort(body.begin(), body.end());
  EXPECT_EQ(body, expected);

  // Small objects come back triangle for triangle, in the written order.
  for (std::size_t i : {2u, 5u, 7u}) {
    const int part = scene.find_part(nodes[i].name);
    ASSERT_GE(part, 0) << nodes[i].name;
    EXPECT_EQ(triangles_of(scene.parts[static_cast<std::size_t>(part)].mesh), triangles_of(nodes[i].mesh))
        << nodes[i].name;
  }
  // Groups own no triangles.
  for (const char* group : {"probe", "arm", "J1", "J2", "Body"}) EXPECT_LT(scene.find_part(group), 0) << group;
}

TEST(TdsRoundTrip, AnObjectTheKeyframerLeavesOutIsKeptAsAStaticPart) {
  // Two objects; the keyframer's entry for "Bobj" is renamed "Xobj" (same
  // length, so every chunk size stays right): assimp then hangs Bobj's mesh on
  // no node. Dropping it would hide geometry from the collision check.
  std::vector<TdsNode> nodes(2);
  nodes[0] = {"Aobj", -1, box(0.0f, 0.0f, 0.0f, 1.0f)};
  nodes[1] = {"Bobj", -1, box(3.0f, 0.0f, 0.0f, 0.5f)};
  std::vector<std::uint8_t> bytes = tds_serialize(nodes);
  const std::string needle = "Bobj";
  std::vector<std::size_t> at;
  for (std::size_t i = 0; i + needle.size() < bytes.size(); ++i)
    if (std::equal(needle.begin(), needle.end(), bytes.begin() + static_cast<long>(i)) && bytes[i + needle.size()] == 0)
      at.push_back(i);
  ASSERT_GE(at.size(), 2u);  // the editor object, then the keyframer node
  bytes[at.back()] = 'X';
  testing::TempDir dir("tds-orphan");
  testing::write_text(dir / "model.3ds", std::string(bytes.begin(), bytes.end()));

  Scene scene;
  load_model(dir / "model.3ds", 1.0, scene);
  const int b = scene.find_part("Bobj");
  ASSERT_GE(b, 0) << "the object the keyframer leaves out must not be dropped";
  EXPECT_EQ(triangles_of(scene.parts[static_cast<std::size_t>(b)].mesh), triangles_of(nodes[1].mesh));
  EXPECT_EQ(scene.parts[static_cast<std::size_t>(b)].chain.size(), 0u);
  bool warned = false;
  for (const std::string& w : scene.warnings) warned |= w.find("kept as static parts") != std::string::npos;
  EXPECT_TRUE(warned);
}

}  // namespace
}  // namespace plancheck
