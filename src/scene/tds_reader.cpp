// SPDX-License-Identifier: MIT
// 3ds chunks read by hand (src/scene/tds_reader.h).
#include "src/scene/tds_reader.h"

#include "src/base/error.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

namespace plancheck {
namespace {

}  // namespace

// The whole file in one read: a 3ds model runs to megabytes, and reading it
// through istreambuf_iterator, a byte and a vector growth at a time, cost
// more than walking its chunks.
std::vector<unsigned char> read_tds_bytes(const std::filesystem::path& file) {
  std::vector<unsigned char> bytes;
  std::ifstream in(file, std::ios::binary | std::ios::ate);
  if (!in) return bytes;
  const std::streamoff size = in.tellg();
  if (size <= 0) return bytes;
  bytes.resize(static_cast<std::size_t>(size));
  in.seekg(0);
  in.read(reinterpret_cast<char*>(bytes.data()), size);
  bytes.resize(static_cast<std::size_t>(std::max<std::streamsize>(0, in.gcount())));
  return bytes;
}

namespace {

// read_tds_objects' chunk walk (see the header for what it reads and why it
// stops quietly at damage).
class TdsReader {
 public:
  explicit TdsReader(std::vector<unsigned char> bytes) : b_(std::move(bytes)) {}

  std::vector<TdsObject> objects() {
    walk(0, b_.size(), nullptr);
    return std::move(objects_);
  }

 private:
  bool has(std::size_t at, std::size_t n, std::size_t end) const { return at <= end && n <= end - at; }
  unsigned u16(std::size_t at) const { return static_cast<unsigned>(b_[at] | (b_[at + 1] << 8)); }
  std::size_t u32(std::size_t at) const { return u16(at) | (static_cast<std::size_t>(u16(at + 2)) << 16); }
  double f32(std::size_t at) const {
    const auto bits = static_cast<std::uint32_t>(u32(at));
    float f;
    std::memcpy(&f, &bits, 4);
    return f;
  }
  // A zero-terminated string at `at`; `after` is set past the terminator.
  std::string cstring(std::size_t at, std::size_t end, std::size_t& after) const {
    std::size_t stop = at;
    while (stop < end && b_[stop] != 0) ++stop;
    after = std::min(stop + 1, end);
    return std::string(b_.begin() + static_cast<long>(at), b_.begin() + static_cast<long>(stop));
  }

  void walk(std::size_t at, std::size_t end, TdsObject* object) {
    while (has(at, 6, end)) {
      const unsigned id = u16(at);
      const std::size_t len = u32(at + 2);
      if (len < 6 || !has(at, len, end)) return;
      const std::size_t body = at + 6, stop = at + len;
      switch (id) {
        case 0x4D4D: case 0x3D3D: walk(body, stop, nullptr); break;
        case 0x4000: {
          std::size_t after;
          TdsObject o;
          o.name = cstring(body, stop, after);
          bool trimesh = false;
          for (std::size_t sub = after; has(sub, 6, stop) && u32(sub + 2) >= 6; sub += u32(sub + 2))
            trimesh = trimesh || u16(sub) == 0x4100;
          if (!trimesh) break;
          walk(after, stop, &o);
          objects_.push_back(std::move(o));
          break;
        }
        case 0x4100: if (object) walk(body, stop, object); break;
        case 0x4110:
          if (object && has(body, 2, stop) && has(body + 2, 12 * std::size_t{u16(body)}, stop)) {
            object->points.reserve(object->points.size() + u16(body));
            for (unsigned i = 0, n = u16(body); i < n; ++i)
              object->points.emplace_back(f32(body + 2 + 12 * i), f32(body + 6 + 12 * i), f32(body + 10 + 12 * i));
          }
          break;
        case 0x4120:
          if (object && has(body, 2, stop) && has(body + 2, 8 * std::size_t{u16(body)}, stop)) {
            const unsigned n = u16(body);
            object->faces.reserve(object->faces.size() + n);
            for (unsigned i = 0; i < n; ++i)
              object->faces.push_back({u16(body + 2 + 8 * i), u16(body + 4 + 8 * i), u16(body + 6 + 8 * i)});
            object->face_material.assign_unassigned(n);
            walk(body + 2 + 8 * std::size_t{n}, stop, object);  // material groups follow the face list
          }
          break;
        case 0x4130:
          if (object) {
            std::size_t after;
            const std::string material = cstring(body, stop, after);
            if (has(after, 2, stop) && has(after + 2, 2 * std::size_t{u16(after)}, stop)) {
              const std::uint32_t index = object->face_material.intern(material);
              for (unsigned i = 0, n = u16(after); i < n; ++i) {
                const unsigned face = u16(after + 2 + 2 * i);
                if (face < object->face_material.size()) object->face_material.set(face, index);
              }
            }
          }
          break;
        default: break;
      }
      at = stop;
    }
  }

  std::vector<unsigned char> b_;
  std::vector<TdsObject> objects_;
};

// assimp 5.2's 3ds reader reserves a keyframer track's keys from the count
// in the file before reading them (found by fuzz_model: one 38-byte position
// track claiming 1644167169 keys made it ask for 39 GB). A key takes at least
// 6 bytes (frame number and flags), so a count its chunk cannot hold is
// refused up front. Tracks are chunks 0xB020..0xB029 in the keyframer's
// node chunks 0xB001..0xB007 under 0xB000.
void check_tracks(const std::vector<unsigned char>& b, std::size_t at, std::size_t end,
                  const std::filesystem::path& file, int depth = 0) {
  auto u16 = [&](std::size_t i) { return static_cast<unsigned>(b[i] | (b[i + 1] << 8)); };
  auto u32 = [&](std::size_t i) { return u16(i) | (static_cast<std::size_t>(u16(i + 2)) << 16); };
  while (at + 6 <= end && depth < 8) {
    const unsigned id = u16(at);
    const std::size_t len = u32(at + 2);
    if (len < 6 || len > end - at) return;  // damage: assimp judges it
    if (id == 0x4D4D || id == 0xB000 || (id >= 0xB001 && id <= 0xB007)) {
      check_tracks(b, at + 6, at + len, file, depth + 1);
    } else if (id >= 0xB020 && id <= 0xB029 && len >= 20) {
      const std::size_t keys = u32(at + 16);
      if (keys > (len - 20) / 6)
        fail(file, "cannot read model: a 3ds keyframer track at byte " + std::to_string(at) + " claims " +
                       std::to_string(keys) + " keys in " + std::to_string(len) + " bytes");
    }
    at += len;
  }
}

}  // namespace

std::uint32_t FaceMaterials::intern(const std::string& name) {
  const auto [it, added] = lookup_.try_emplace(name, static_cast<std::uint32_t>(names_.size()));
  if (added) names_.push_back(name);
  return it->second;
}

bool operator==(const FaceMaterials& a, const FaceMaterials& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t f = 0; f < a.size(); ++f)
    if (a[f] != b[f]) return false;
  return true;
}

bool is_3ds(const std::filesystem::path& file) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext == ".3ds";
}

std::vector<TdsObject> read_tds_objects(const std::filesystem::path& file) {
  return TdsReader(read_tds_bytes(file)).objects();
}

std::vector<TdsObject> read_tds_objects(std::vector<unsigned char> bytes) { return TdsReader(std::move(bytes)).objects(); }

void check_3ds_tracks(const std::filesystem::path& file) {
  if (!is_3ds(file)) return;
  const std::vector<unsigned char> b = read_tds_bytes(file);
  check_tracks(b, 0, b.size(), file);
}

}  // namespace plancheck
