// SPDX-License-Identifier: MIT
// Our own reader of 3ds chunks, private to src/scene: the drawn pose of a 3ds
// file's trimesh objects (model_loader.cpp matches assimp's meshes to them)
// and the guard on keyframer tracks ahead of assimp (assimp_import.cpp).
#pragma once

#include "src/scene/scene.h"

#include <array>
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace plancheck {

// True when the file name ends in ".3ds", in any case.
bool is_3ds(const std::filesystem::path& file);

// Each face's material name ("" if none), read like a vector of names. A
// name is kept once and a face holds its index: a string per face made
// hundreds of thousands of empty strings on a large model (32 bytes each,
// built, touched and freed on the way to the first answer).
class FaceMaterials {
 public:
  std::size_t size() const { return index_.size(); }
  const std::string& operator[](std::size_t face) const { return names_[index_[face]]; }
  // n faces, none with a material.
  void assign_unassigned(std::size_t n) { index_.assign(n, 0); }
  // The index of `name` (added if new), for set().
  std::uint32_t intern(const std::string& name);
  void set(std::size_t face, std::uint32_t name_index) { index_[face] = name_index; }
  friend bool operator==(const FaceMaterials& a, const FaceMaterials& b);

 private:
  std::vector<std::string> names_{std::string()};  // names_[0] is "": no material
  std::map<std::string, std::uint32_t> lookup_{{std::string(), 0}};
  std::vector<std::uint32_t> index_;  // per face, into names_
};

// One trimesh object of a 3ds file as drawn (editor section): its points in
// the file's frame, its faces, and each face's material name ("" if none).
struct TdsObject {
  std::string name;
  std::vector<Vec3> points;
  std::vector<std::array<unsigned, 3>> faces;
  FaceMaterials face_material;
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
