// SPDX-License-Identifier: MIT
// Small fixtures for the foundation tests (the temporary folder is
// tests/support's TempDir): a glTF writer for node trees of boxes (glTF
// keeps a hierarchy and node translations, which OBJ cannot), and an
// InputError matcher.
#pragma once

#include "src/base/error.h"
#include "src/scene/scene.h"
#include "tests/support/fixtures.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <string>
#include <unistd.h>
#include <vector>

namespace plancheck::testing {

inline const std::filesystem::path kAssimpModels = "/usr/share/assimp/models";

// One node of a generated glTF model: an optional axis-aligned box mesh.
struct BoxNode {
  std::string name;
  int parent = -1;           // index into the node list; -1 for the single top node
  Vec3 translation = Vec3::Zero();
  bool box = false;
  Vec3 lo = Vec3::Zero();    // box corners in the node's local frame
  Vec3 hi = Vec3::Ones();
};

inline std::string base64(const std::vector<unsigned char>& data) {
  static const char* kDigits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (std::size_t i = 0; i < data.size(); i += 3) {
    unsigned v = data[i] << 16;
    if (i + 1 < data.size()) v |= data[i + 1] << 8;
    if (i + 2 < data.size()) v |= data[i + 2];
    out += kDigits[(v >> 18) & 63];
    out += kDigits[(v >> 12) & 63];
    out += i + 1 < data.size() ? kDigits[(v >> 6) & 63] : '=';
    out += i + 2 < data.size() ? kDigits[v & 63] : '=';
  }
  return out;
}

// The 8 corners of a box, index = x bit 0, y bit 1, z bit 2.
inline std::vector<Vec3> box_corners(const Vec3& lo, const Vec3& hi) {
  std::vector<Vec3> v;
  for (int i = 0; i < 8; ++i) v.emplace_back(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(), i & 4 ? hi.z() : lo.z());
  return v;
}

inline const std::vector<Tri>& box_triangles() {
  static const std::vector<Tri> kTris = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                                         {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return kTris;
}

// One node of a glTF written by write_mesh_gltf: its parent (index into the
// node list, -1 for a top node), its translation and an optional mesh in the
// node's local frame (no triangles: no mesh).
struct MeshNode {
  std::string name;
  int parent = -1;
  Vec3 translation = Vec3::Zero();
  Mesh mesh;
};

// Writes a .gltf with an embedded buffer (float positions, uint32 indices).
inline std::filesystem::path write_mesh_gltf(const std::filesystem::path& file, const std::vector<MeshNode>& nodes) {
  using nlohmann::json;
  std::vector<unsigned char> buffer;
  auto put = [&](const void* p, std::size_t n) {
    const auto* b = static_cast<const unsigned char*>(p);
    buffer.insert(buffer.end(), b, b + n);
  };
  json j;
  j["asset"] = {{"version", "2.0"}};
  j["nodes"] = json::array();
  j["meshes"] = json::array();
  j["accessors"] = json::array();
  j["bufferViews"] = json::array();
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const MeshNode& n = nodes[i];
    json jn = {{"name", n.name}};
    if (!n.translation.isZero()) jn["translation"] = {n.translation.x(), n.translation.y(), n.translation.z()};
    std::vector<int> children;
    for (std::size_t c = 0; c < nodes.size(); ++c)
      if (nodes[c].parent == static_cast<int>(i)) children.push_back(static_cast<int>(c));
    if (!children.empty()) jn["children"] = children;
    const Mesh& m = n.mesh;
    if (!m.triangles.empty()) {
      const std::size_t pos = buffer.size();
      Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
      for (const Vec3& v : m.vertices) {
        const float f[3] = {static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z())};
        put(f, sizeof f);
        for (int k = 0; k < 3; ++k) {
          lo[k] = std::min(lo[k], static_cast<double>(f[k]));
          hi[k] = std::max(hi[k], static_cast<double>(f[k]));
        }
      }
      const std::size_t idx = buffer.size();
      for (const Tri& t : m.triangles) put(t.data(), sizeof(std::uint32_t) * 3);
      const int view = static_cast<int>(j["bufferViews"].size());
      j["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", pos}, {"byteLength", idx - pos}});
      j["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", idx}, {"byteLength", buffer.size() - idx}});
      const int acc = static_cast<int>(j["accessors"].size());
      j["accessors"].push_back({{"bufferView", view}, {"componentType", 5126}, {"count", m.vertices.size()},
                                {"type", "VEC3"}, {"min", {lo.x(), lo.y(), lo.z()}}, {"max", {hi.x(), hi.y(), hi.z()}}});
      j["accessors"].push_back(
          {{"bufferView", view + 1}, {"componentType", 5125}, {"count", 3 * m.triangles.size()}, {"type", "SCALAR"}});
      jn["mesh"] = static_cast<int>(j["meshes"].size());
      j["meshes"].push_back({{"name", n.name + "-mesh"},
                             {"primitives", {{{"attributes", {{"POSITION", acc}}}, {"indices", acc + 1}, {"mode", 4}}}}});
    }
    j["nodes"].push_back(jn);
  }
  std::vector<int> tops;
  for (std::size_t i = 0; i < nodes.size(); ++i)
    if (nodes[i].parent < 0) tops.push_back(static_cast<int>(i));
  j["scenes"] = {{{"nodes", tops}}};
  j["scene"] = 0;
  j["buffers"] = {{{"byteLength", buffer.size()},
                   {"uri", "data:application/octet-stream;base64," + base64(buffer)}}};
  std::ofstream(file, std::ios::binary) << j.dump(1);
  return file;
}

// Writes a .gltf of boxes. Every coordinate (translations, box corners) is
// multiplied by `unit` so one tree can be written in m, cm or mm.
inline std::filesystem::path write_box_gltf(const std::filesystem::path& file, const std::vector<BoxNode>& nodes,
                                            double unit = 1.0) {
  std::vector<MeshNode> out;
  for (const BoxNode& n : nodes) {
    MeshNode m{n.name, n.parent, n.translation * unit, {}};
    if (n.box) {
      m.mesh.vertices = box_corners(n.lo * unit, n.hi * unit);
      m.mesh.triangles = box_triangles();
    }
    out.push_back(std::move(m));
  }
  return write_mesh_gltf(file, out);
}

// The arm used by the scene, kinematics, plan and CLI tests, in metres when
// unit = 1 (unit = 1000 writes the same arm in millimetres):
//   world
//   |- base   box (-1,-1,-0.5)..(1,1,0)            static
//   |- mast   box (2,2,0)..(2.25,2.25,2)           static
//   `- arm1   box x 0..1                            (J1 in the scenes)
//      |- arm2   at x = 1, box x 1..2 (world)      (J2)
//      |  `- tip at x = 2, box x 2..2.25 (world)
//      `- arm1b  box beside arm1 (same chain as arm1)
inline std::filesystem::path write_arm_model(const std::filesystem::path& file, double unit = 1.0) {
  return write_box_gltf(
      file,
      {{.name = "world"},
       {.name = "base", .parent = 0, .box = true, .lo = {-1, -1, -0.5}, .hi = {1, 1, 0}},
       {.name = "mast", .parent = 0, .box = true, .lo = {2, 2, 0}, .hi = {2.25, 2.25, 2}},
       {.name = "arm1", .parent = 0, .box = true, .lo = {0, -0.125, 0}, .hi = {1, 0.125, 0.25}},
       {.name = "arm2", .parent = 3, .translation = {1, 0, 0}, .box = true, .lo = {0, -0.125, 0}, .hi = {1, 0.125, 0.25}},
       {.name = "tip", .parent = 4, .translation = {1, 0, 0}, .box = true, .lo = {0, -0.125, 0}, .hi = {0.25, 0.125, 0.25}},
       {.name = "arm1b", .parent = 3, .box = true, .lo = {0, -0.5, 0}, .hi = {0.25, -0.25, 0.25}}},
      unit);
}

// Runs f, expects an InputError whose message contains every one of `parts`.
inline void expect_input_error(const std::function<void()>& f, std::initializer_list<std::string> parts) {
  try {
    f();
    ADD_FAILURE() << "no InputError thrown";
  } catch (const InputError& e) {
    const std::string message = e.what();
    for (const std::string& p : parts)
      EXPECT_NE(message.find(p), std::string::npos) << "message '" << message << "' lacks '" << p << "'";
  }
}

}  // namespace plancheck::testing
