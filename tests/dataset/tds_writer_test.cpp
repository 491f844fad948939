// SPDX-License-Identifier: MIT
// Round trip of datasets/tds_writer through assimp 5.2's own 3DS importer, read raw
// (no post-processing), so what the loader sees is what the writer meant.
#include "datasets/tds_writer.h"
#include "support/fixtures.h"

#include <assimp/Importer.hpp>
#include <assimp/scene.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <map>
#include <string>


namespace plancheck {
namespace {

// A strip of `n` triangles, each with its own three vertices unless `shared`,
// in which case consecutive triangles share an edge (a fan over a zig-zag).
TdsMesh strip(float x0, int n, bool shared) {
  TdsMesh m;
  if (!shared) {
    for (int i = 0; i < n; ++i) {
      float x = x0 + 0.001f * static_cast<float>(i);
      auto b = static_cast<std::uint32_t>(m.vertices.size());
      m.vertices.push_back({x, 0.25f, -1.5f});
      m.vertices.push_back({x + 0.5f, 1.0f / 3.0f, 0.0f});
      m.vertices.push_back({x, 2.0f, 7.125f + static_cast<float>(i % 7)});
      m.faces.push_back({b, b + 1, b + 2});
    }
  } else {
    for (int i = 0; i < n + 2; ++i)
      m.vertices.push_back({x0 + 0.01f * static_cast<float>(i / 2), static_cast<float>(i % 2), 0.1f * static_cast<float>(i % 5)});
    for (int i = 0; i < n; ++i) {
      auto k = static_cast<std::uint32_t>(i);
      m.faces.push_back({k, k + 1, k + 2});
    }
  }
  return m;
}

struct ReadBack {
  Assimp::Importer importer;
  const aiScene* scene = nullptr;
  std::map<std::string, const aiNode*> by_name;
};

void index_nodes(const aiNode* n, std::map<std::string, const aiNode*>& out) {
  out[n->mName.C_Str()] = n;
  for (unsigned i = 0; i < n->mNumChildren; ++i) index_nodes(n->mChildren[i], out);
}

void read_back(const std::vector<TdsNode>& nodes, const std::string& file_name, ReadBack& rb) {
  // assimp keeps what it read: the file goes with the folder.
  const testing::TempDir dir("tds_writer");
  const std::filesystem::path file = dir / file_name;
  tds_write(file, nodes);
  rb.scene = rb.importer.ReadFile(file.string(), 0);
  ASSERT_NE(rb.scene, nullptr) << rb.importer.GetErrorString();
  index_nodes(rb.scene->mRootNode, rb.by_name);
}

// The tree used by most tests: two roots (like the paper's probe and arm),
// groups, mesh nodes with children, and one object too big for one 3ds object.
std::vector<TdsNode> sample_tree() {
  std::vector<TdsNode> t;
  t.push_back({"probe", -1, {}});
  t.push_back({"lander", 0, {}});
  t.push_back({"Deck", 1, strip(0.0f, 40, true)});
  t.push_back({"Leg", 1, strip(1.0f, 12, false)});
  t.push_back({"Antenna", 2, strip(2.0f, 3, false)});  // a mesh node under a mesh node
  t.push_back({"ascender", 0, {}});
  t.push_back({"AscBody", 5, strip(3.0f, 25, false)});
  t.push_back({"arm", -1, {}});
  t.push_back({"J1", 7, {}});
  t.push_back({"ArmJ1", 8, strip(4.0f, 9, true)});
  t.push_back({"J2", 8, {}});
  t.push_back({"Huge", 10, strip(5.0f, 30000, false)});  // 90,000 vertices: split
  t.push_back({"ArmJ2", 10, strip(6.0f, 7, false)});
  return t;
}

TEST(TdsWriter, SplitsOnlyObjectsOverSixteenBits) {
  auto t = sample_tree();
  EXPECT_EQ(tds_object_names(t[2]), std::vector<std::string>{"Deck"});
  EXPECT_TRUE(tds_object_names(t[0]).empty());
  EXPECT_EQ(tds_object_names(t[11]), (std::vector<std::string>{"Huge.1", "Huge.2"}));
}

TEST(TdsWriter, AssimpRebuildsNamesAndParents) {
  auto t = sample_tree();
  ReadBack rb;
  read_back(t, "tree.3ds", rb);
  // Every node comes back under its own name (groups through $$$DUMMY + 0xB011).
  for (const TdsNode& n : t) {
    ASSERT_TRUE(rb.by_name.count(n.name)) << n.name;
    const aiNode* got = rb.by_name[n.name];
    ASSERT_NE(got->mParent, nullptr);
    std::string want_parent = n.parent < 0 ? std::string("<3DSRoot>") : t[static_cast<std::size_t>(n.parent)].name;
    EXPECT_EQ(std::string(got->mParent->mName.C_Str()), want_parent) << n.name;
  }
  // The split pieces hang under the node of the object's name, which owns no mesh.
  const aiNode* huge = rb.by_name["Huge"];
  EXPECT_EQ(huge->mNumMeshes, 0u);
  ASSERT_EQ(huge->mNumChildren, 2u);
  EXPECT_STREQ(huge->mChildren[0]->mName.C_Str(), "Huge.1");
  EXPECT_STREQ(huge->mChildren[1]->mName.C_Str(), "Huge.2");
  // 13 tree nodes + 2 pieces + the importer's own root.
  EXPECT_EQ(rb.by_name.size(), t.size() + 2 + 1);
}

TEST(TdsWriter, AssimpRootConvertsZUpToYUpAndEveryOtherTransformIsIdentity) {
  auto t = sample_tree();
  ReadBack rb;
  read_back(t, "transforms.3ds", rb);
  // assimp's 3DS importer rotates its root by -90 deg about x (z-up to y-up).
  // A loader that wants the file's own z-up frame must not apply it.
  const aiMatrix4x4& r = rb.scene->mRootNode->mTransformation;
  aiMatrix4x4 y_up(1, 0, 0, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1);
  EXPECT_TRUE(r.Equal(y_up, 0.0f));
  for (const auto& [name, node] : rb.by_name) {
    if (node == rb.scene->mRootNode) continue;
    EXPECT_TRUE(node->mTransformation.IsIdentity()) << name;
  }
}

TEST(TdsWriter, EveryTriangleComesBackExactlyOnItsNode) {
  auto t = sample_tree();
  ReadBack rb;
  read_back(t, "meshes.3ds", rb);
  std::size_t total_faces = 0;
  for (const TdsNode& n : t) {
    if (n.mesh.faces.empty()) {
      EXPECT_EQ(rb.by_name[n.name]->mNumMeshes, 0u) << n.name;
      continue;
    }
    // Gather the node's triangles from its meshes, or from its pieces' meshes.
    std::vector<const aiNode*> holders;
    for (const std::string& obj : tds_object_names(n)) holders.push_back(rb.by_name[obj]);
    std::vector<std::array<aiVector3D, 3>> got;
    for (const aiNode* h : holders) {
      ASSERT_NE(h, nullptr);
      for (unsigned m = 0; m < h->mNumMeshes; ++m) {
        const aiMesh* mesh = rb.scene->mMeshes[h->mMeshes[m]];
        for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
          ASSERT_EQ(mesh->mFaces[f].mNumIndices, 3u);
          got.push_back({mesh->mVertices[mesh->mFaces[f].mIndices[0]], mesh->mVertices[mesh->mFaces[f].mIndices[1]],
                         mesh->mVertices[mesh->mFaces[f].mIndices[2]]});
        }
      }
    }
    ASSERT_EQ(got.size(), n.mesh.faces.size()) << n.name;
    total_faces += got.size();
    // Same order, same winding, bit-identical floats.
    for (std::size_t f = 0; f < got.size(); ++f) {
      for (int k = 0; k < 3; ++k) {
        const auto& want = n.mesh.vertices[n.mesh.faces[f][static_cast<std::size_t>(k)]];
        ASSERT_EQ(got[f][k].x, want[0]) << n.name << " face " << f;
        ASSERT_EQ(got[f][k].y, want[1]) << n.name << " face " << f;
        ASSERT_EQ(got[f][k].z, want[2]) << n.name << " face " << f;
      }
    }
  }
  std::size_t all = 0;
  for (unsigned m = 0; m < rb.scene->mNumMeshes; ++m) all += rb.scene->mMeshes[m]->mNumFaces;
  EXPECT_EQ(all, total_faces);
}

TEST(TdsWriter, SameTreeSameBytes) {
  auto t = sample_tree();
  EXPECT_EQ(tds_serialize(t), tds_serialize(t));
}

TEST(TdsWriter, RejectsBadInput) {
  std::vector<TdsNode> t{{"a", -1, {}}, {"a", 0, {}}};
  EXPECT_THROW(tds_serialize(t), std::invalid_argument);
  std::vector<TdsNode> order{{"a", 1, {}}, {"b", -1, {}}};
  EXPECT_THROW(tds_serialize(order), std::invalid_argument);
  TdsNode bad{"m", -1, strip(0.0f, 1, false)};
  bad.mesh.faces[0][2] = 99;
  EXPECT_THROW(tds_serialize({bad}), std::invalid_argument);
}

}  // namespace
}  // namespace plancheck
