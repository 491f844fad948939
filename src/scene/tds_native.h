// SPDX-License-Identifier: MIT
// A strict reader of 3ds files, private to src/scene: what assimp 5.2's 3ds
// importer reads from a file, for files within a subset this reader
// understands completely, so that model_loader.cpp can build the part tree
// without starting assimp. Anything outside the subset, and any damage, is a
// decline (std::nullopt): the file then goes to assimp as before.
#pragma once

#include "src/scene/tds_reader.h"

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace plancheck {

// One node of the keyframer hierarchy as assimp places it (its
// ParseHierarchyChunk): name after the $$$DUMMY rename, and its first key of
// each track as read from the file.
struct TdsKeyNode {
  std::string name;
  int parent = -1;  // index into TdsFile::nodes; -1 only for nodes[0]
  std::vector<int> children;
  std::int16_t hierarchy_pos = -1;  // the file's parent index + 1, as assimp keeps it (mHierarchyPos)
  bool has_position = false, has_rotation = false, has_scale = false;
  std::array<float, 3> position{}, axis{}, scale{}, pivot{};
  float angle = 0.0f;
};

struct TdsFile {
  std::vector<TdsObject> objects;          // the trimesh objects in file order
  std::vector<std::array<float, 12>> axes;  // per object: its 0x4160 matrix (identity when absent)
  // nodes[0] is the keyframer's unnamed root; a file without keyframer
  // nodes has only it (assimp's flat "<3DSDummyRoot>" tree).
  std::vector<TdsKeyNode> nodes;
  float master_scale = 1.0f;
};

// The file read as assimp reads it, or nullopt when the file is outside
// the subset (see tds_native.cpp for the subset). Never throws on bad
// input, never reads out of bounds.
std::optional<TdsFile> read_3ds_strict(const std::filesystem::path& file);
std::optional<TdsFile> read_3ds_strict(const std::vector<unsigned char>& bytes);

}  // namespace plancheck
