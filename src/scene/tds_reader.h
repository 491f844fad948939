// SPDX-License-Identifier: MIT
// Our own reader of 3ds chunks, private to src/scene: the drawn pose of a 3ds
// file's trimesh objects (model_loader.cpp matches assimp's meshes to them)
// and the guard on keyframer tracks ahead of assimp (assimp_import.cpp).
#pragma once

#include "src/scene/scene.h"

#include <array>
#include <filesystem>
#include <string>
#include <vector>

namespace plancheck {

// True when the file name ends in ".3ds", in any case.
bool is_3ds(const std::filesystem::path& file);

// One trimesh object of a 3ds file as drawn (editor section): its points in
// the file's frame, its faces, and each face's material name ("" if none).
struct TdsObject {
  std::string name;
  std::vector<Vec3> points;
  std::vector<std::array<unsigned, 3>> faces;
  std::vector<std::string> face_material;
};

// The trimesh objects (0x4000 chunks holding 0x4100) in file order: assimp's
// 3ds mesh names are indices into this list. Reading stops quietly at damage:
// assimp has already judged the file, and a mismatch only means falling back
// to assimp's own pose (see Builder::match_drawn_faces in model_loader.cpp).
std::vector<TdsObject> read_tds_objects(const std::filesystem::path& file);
std::vector<TdsObject> read_tds_objects(std::vector<unsigned char> bytes);

// The whole file's bytes (empty when it cannot be read: the callers then find
// no chunks and leave the judgement to assimp).
std::vector<unsigned char> read_tds_bytes(const std::filesystem::path& file);

// A .3ds file whose keyframer track claims more keys than its chunk can hold
// is refused (InputError naming the file and byte) before assimp reads it:
// assimp 5.2 reserves the keys from that count. Other files pass untouched.
void check_3ds_tracks(const std::filesystem::path& file);

}  // namespace plancheck
