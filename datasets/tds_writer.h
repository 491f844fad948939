// SPDX-License-Identifier: MIT
// A small 3ds (Autodesk 3D Studio) writer for the synthetic datasets: a node
// tree with triangle meshes, written as editor objects (0x3D3D/0x4000/0x4100)
// plus a keyframer hierarchy (0xB000/0xB002) so the tree survives the trip
// through assimp. Every vertex is written in the reference frame with
// identity local axes, pivots and tracks, so the file's pose is the reference
// pose and no transform has to be applied on reading.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace plancheck {

struct TdsMesh {
  std::vector<std::array<float, 3>> vertices;      // reference frame
  std::vector<std::array<std::uint32_t, 3>> faces;  // indices into vertices
};

struct TdsNode {
  std::string name;  // unique in the tree; becomes the 3ds object / dummy instance name
  int parent = -1;   // index into the node list; must precede the node; -1 for a root
  TdsMesh mesh;      // empty: a group node ("$$$DUMMY" in the keyframer)
};

// 3ds stores counts as 16 bits, so one object holds at most this many
// vertices and faces. A larger mesh becomes a group node of the same name with
// child objects "<name>.1", "<name>.2", ... (each under both limits).
inline constexpr std::size_t kTdsMaxObjectElements = 65535;

// The objects one node is written as: {name} or {name.1, name.2, ...}.
std::vector<std::string> tds_object_names(const TdsNode& node);

// Serialises the tree. Nodes must be listed parents first (any order that
// puts a parent before its children); they are written depth first.
// Throws std::invalid_argument on a bad parent index, a duplicate or empty
// name, a face index out of range or a non-finite vertex.
std::vector<std::uint8_t> tds_serialize(const std::vector<TdsNode>& nodes);

// tds_serialize() written to `file`; throws std::runtime_error on I/O failure.
void tds_write(const std::filesystem::path& file, const std::vector<TdsNode>& nodes);

}  // namespace plancheck
