// SPDX-License-Identifier: MIT
// The strict 3ds reader (src/scene/tds_native.h).
//
// The subset read, and what assimp 5.2 does with it (its 3DSLoader.cpp and
// 3DSConverter.cpp): one 0x4D4D chunk spanning the whole file, every chunk
// inside it tiling its parent exactly (no chunk shorter than its header or
// longer than what is left of its parent). Chunks assimp skips are skipped;
// among those it reads, declined are:
// - materials (0xAFFF) and face material lists (0x4130): assimp's default
//   material and its split by material are then the only case (one mesh per
//   object, all its faces in file order, material "%%%DEFAULT");
// - texture coordinates (0x4140): assimp clamps face indices against them;
// - lights and cameras (0x4600, 0x4700; keyframer 0xB001, 0xB003..0xB007);
// - keyframer tracks with more than one key (an animation: assimp sorts
//   and merges keys), or key flags (spline data);
// - an object with no points or no faces, a face naming a point the object
//   lacks, a second trimesh in an object or a second point, face or axes
//   list in a trimesh, smoothing groups for more faces than there are,
//   non-finite numbers;
// - names that are empty, longer than 1000 bytes, repeated (objects among
//   objects, keyframer nodes among nodes: assimp makes instances "_inst_2"
//   of those), "UNNAMED" or "$$$DUMMY" left unrenamed; a keyframer node
//   chunk without its 0xB010 header first; with a keyframer, an object that
//   no node of its name carries; a tree deeper than 256;
// - chunks our own lenient walk (read_tds_objects, which the loader matches
//   assimp's meshes to) would read where assimp does not (objects or point
//   lists nested in odd places), and keyframer chunks the track guard
//   (check_3ds_tracks) would read where assimp does not.
// Taken as they are: the master scale, an object's local axes, a node's
// pivot and its first position, rotation and scale keys. model_loader.cpp
// applies them as assimp does, in its order, with its float types and its
// inline math (assimp's headers), so vertices and transforms are its bits.
#include "src/scene/tds_native.h"

#include <cmath>
#include <cstring>
#include <fstream>
#include <unordered_set>
#include <utility>

namespace plancheck {
namespace {

constexpr std::size_t kMaxName = 1000;
constexpr int kMaxDepth = 256;

struct Declined {};  // thrown inside the reader only, caught at its top

class StrictReader {
 public:
  explicit StrictReader(const std::vector<unsigned char>& b) : b_(b) {}

  TdsFile read() {
    if (b_.size() < 16) decline();
    const Chunk main = chunk(0, b_.size());
    if (main.id != 0x4D4D || main.end != b_.size()) decline();
    out_.nodes.emplace_back();
    out_.nodes[0].name = "UNNAMED";
    names_.insert("UNNAMED");
    for_each(main, [&](const Chunk& c) {
      switch (c.id) {
        case 0x3D3D: editor(c); break;
        case 0xB000: keyframer(c); break;
        case 0x0002: need(c, 2); break;
        case 0x4D4D: case 0x4000: decline();  // read_tds_objects would read these
        default:
          if (guarded(c.id)) decline();
          break;
      }
    });
    finish();
    return std::move(out_);
  }

 private:
  struct Chunk {
    unsigned id;
    std::size_t body, end;
  };

  [[noreturn]] static void decline() { throw Declined{}; }
  // Chunks check_3ds_tracks (tds_reader.h) walks into or checks wherever it
  // meets them under 0x4D4D and the keyframer chunks, where assimp skips them.
  static bool guarded(unsigned id) { return (id >= 0xB000 && id <= 0xB007) || (id >= 0xB020 && id <= 0xB029); }
  unsigned u16(std::size_t at) const { return static_cast<unsigned>(b_[at] | (b_[at + 1] << 8)); }
  std::uint32_t u32(std::size_t at) const { return u16(at) | (static_cast<std::uint32_t>(u16(at + 2)) << 16); }
  float f32(std::size_t at) const {
    const std::uint32_t bits = u32(at);
    float f;
    std::memcpy(&f, &bits, 4);
    if (!std::isfinite(f)) decline();
    return f;
  }
  static void need(const Chunk& c, std::size_t n) {
    if (c.end - c.body < n) decline();
  }
  // The chunk at `at` inside a parent ending at `end`.
  Chunk chunk(std::size_t at, std::size_t end) const {
    if (end - at < 6) decline();
    const std::size_t len = u32(at + 2);
    if (len < 6 || len > end - at) decline();
    return {u16(at), at + 6, at + len};
  }
  template <class F>
  void for_each(const Chunk& parent, F&& f, std::size_t from = 0) {
    for (std::size_t at = from ? from : parent.body; at < parent.end;) {
      const Chunk c = chunk(at, parent.end);
      f(c);
      at = c.end;
    }
  }
  // A zero-terminated name starting at `at`, ending before `end`.
  std::string name(std::size_t at, std::size_t end, std::size_t& after) const {
    std::size_t stop = at;
    while (stop < end && b_[stop] != 0) ++stop;
    if (stop == end || stop == at || stop - at > kMaxName) decline();
    after = stop + 1;
    return std::string(reinterpret_cast<const char*>(b_.data() + at), stop - at);
  }

  void editor(const Chunk& editor) {
    for_each(editor, [&](const Chunk& c) {
      switch (c.id) {
        case 0x4000: object(c); break;
        case 0xAFFF: case 0x4D4D: case 0x3D3D: decline();
        case 0x0100:
          need(c, 4);
          out_.master_scale = f32(c.body);  // the last one counts, as in assimp
          break;
        default: break;  // ambient colour, background: materials only
      }
    });
  }

  void object(const Chunk& object) {
    std::size_t after;
    TdsObject o;
    o.name = name(object.body, object.end, after);
    std::array<float, 12> axes{1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};
    bool trimesh = false;
    for_each(
        object,
        [&](const Chunk& c) {
          switch (c.id) {
            case 0x4100:
              if (trimesh) decline();
              trimesh = true;
              mesh(c, o, axes);
              break;
            case 0x4600: case 0x4700: decline();
            case 0x4D4D: case 0x3D3D: case 0x4000: case 0x4110: case 0x4120: case 0x4130: decline();
            default: break;
          }
        },
        after);
    if (!trimesh) return;  // assimp reads no mesh from it
    if (o.points.empty() || o.faces.empty()) decline();
    for (const auto& f : o.faces)
      for (unsigned i : f)
        if (i >= o.points.size()) decline();
    if (!object_names_.insert(o.name).second) decline();
    out_.objects.push_back(std::move(o));
    out_.axes.push_back(axes);
  }

  void mesh(const Chunk& mesh, TdsObject& o, std::array<float, 12>& axes) {
    bool points = false, faces = false, matrix = false;
    for_each(mesh, [&](const Chunk& c) {
      switch (c.id) {
        case 0x4110: {
          if (points) decline();
          points = true;
          need(c, 2);
          const unsigned n = u16(c.body);
          need(c, 2 + 12 * std::size_t{n});
          o.points.reserve(n);
          for (unsigned i = 0; i < n; ++i)
            o.points.emplace_back(f32(c.body + 2 + 12 * i), f32(c.body + 6 + 12 * i), f32(c.body + 10 + 12 * i));
          break;
        }
        case 0x4160: {
          if (matrix) decline();
          matrix = true;
          need(c, 48);
          for (int k = 0; k < 12; ++k) axes[k] = f32(c.body + 4 * k);
          break;
        }
        case 0x4120: {
          if (faces) decline();
          faces = true;
          need(c, 2);
          const unsigned n = u16(c.body);
          need(c, 2 + 8 * std::size_t{n});
          o.faces.reserve(n);
          for (unsigned i = 0; i < n; ++i)
            o.faces.push_back({u16(c.body + 2 + 8 * i), u16(c.body + 4 + 8 * i), u16(c.body + 6 + 8 * i)});
          o.face_material.assign_unassigned(n);
          const std::size_t sub = c.body + 2 + 8 * std::size_t{n};
          if (sub < c.end)
            for_each(
                c,
                [&](const Chunk& s) {
                  if (s.id == 0x4130 || s.id == 0x4D4D || s.id == 0x3D3D || s.id == 0x4000 || s.id == 0x4100 ||
                      s.id == 0x4110 || s.id == 0x4120)
                    decline();
                  if (s.id == 0x4150 && (s.end - s.body) / 4 > n) decline();  // assimp throws
                },
                sub);
          break;
        }
        case 0x4140: decline();
        case 0x4D4D: case 0x3D3D: case 0x4000: case 0x4100: case 0x4130: decline();
        default: break;
      }
    });
  }

  void keyframer(const Chunk& keyframer) {
    for_each(keyframer, [&](const Chunk& c) {
      switch (c.id) {
        case 0xB002: node(c); break;
        case 0xB000: case 0xB001: case 0xB003: case 0xB004: case 0xB005: case 0xB006: case 0xB007: decline();
        default:
          if (guarded(c.id)) decline();
          break;
      }
    });
  }

  // One keyframer object node: placed in the tree as assimp's
  // ParseHierarchyChunk places it (the file's parent index is only a hint
  // to that algorithm; it is followed here step by step).
  void node(const Chunk& node) {
    int me = -1;
    int positions = 0, rotations = 0, scales = 0;
    for_each(node, [&](const Chunk& c) {
      if (c.id == 0xB030) return;
      // Tracks read by check_3ds_tracks (tds_reader.h) only, and nested keyframer chunks.
      if ((c.id >= 0xB023 && c.id <= 0xB029) || (c.id >= 0xB000 && c.id <= 0xB007)) decline();
      if (c.id == 0xB010) {
        if (me >= 0) decline();
        std::size_t after;
        std::string n = name(c.body, c.end, after);
        if (c.end - after < 6 || names_.count(n)) decline();  // assimp: an instance
        TdsKeyNode k;
        k.name = n;
        const auto hierarchy = static_cast<std::uint16_t>(u16(after + 4) + 1);
        k.hierarchy_pos = static_cast<std::int16_t>(hierarchy);
        me = static_cast<int>(out_.nodes.size());
        out_.nodes.push_back(std::move(k));
        names_.insert(n);
        place(me, hierarchy);
        return;
      }
      if (me < 0) {
        if (c.id == 0xB011 || c.id == 0xB013 || (c.id >= 0xB020 && c.id <= 0xB022)) decline();
        return;  // assimp ignores it
      }
      TdsKeyNode& k = out_.nodes[me];
      switch (c.id) {
        case 0xB011: {
          std::size_t after;
          std::string n = name(c.body, c.end, after);
          if (k.name == "$$$DUMMY") {
            if (names_.count(n)) decline();
            names_.erase(k.name);
            k.name = n;
            names_.insert(n);
          }
          break;
        }
        case 0xB013:
          need(c, 12);
          k.pivot = {f32(c.body), f32(c.body + 4), f32(c.body + 8)};
          break;
        case 0xB020: case 0xB021: case 0xB022: {
          need(c, 14);
          // The scale track's count is 16 bits (assimp reads it so).
          const std::uint32_t keys = c.id == 0xB022 ? u16(c.body + 10) : u32(c.body + 10);
          if (c.id == 0xB022 && u16(c.body + 12) != 0) decline();  // check_3ds_tracks reads 32 bits
          if (keys == 0) break;
          if (keys > 1) decline();
          const std::size_t key = c.body + 14;
          need(c, 14 + 6 + (c.id == 0xB021 ? 16 : 12));
          if (u16(key + 4) != 0) decline();  // spline data
          const std::size_t v = key + 6;
          if (c.id == 0xB020) {
            if (++positions > 1) decline();
            k.has_position = true;
            k.position = {f32(v), f32(v + 4), f32(v + 8)};
          } else if (c.id == 0xB021) {
            if (++rotations > 1) decline();
            k.has_rotation = true;
            k.angle = f32(v);
            k.axis = {f32(v + 4), f32(v + 8), f32(v + 12)};
          } else {
            if (++scales > 1) decline();
            k.has_scale = true;
            k.scale = {f32(v), f32(v + 4), f32(v + 8)};
            for (float& s : k.scale)
              if (s == 0.0f) s = 1.0f;  // as assimp does
          }
          break;
        }
        default: break;  // node id, bounding box, morph smoothing, FOV, roll: assimp skips them here
      }
    });
    if (me < 0) decline();
  }

  void add_child(int parent, int child) {
    out_.nodes[parent].children.push_back(child);
    out_.nodes[child].parent = parent;
  }

  // assimp's placement: against the node touched last (current_) and the
  // running index last_, with assimp's types: the position in the file is
  // 16 bits unsigned, a node's position and the running index 16 bits
  // signed (so they wrap as assimp's do).
  void place(int me, std::uint16_t hierarchy) {
    const TdsKeyNode& current = out_.nodes[static_cast<std::size_t>(current_)];
    if (current.hierarchy_pos == hierarchy) {
      if (current.parent < 0) decline();  // assimp would dereference null
      add_child(current.parent, me);
      last_ = static_cast<std::int16_t>(last_ + 1);
    } else if (hierarchy >= last_) {
      add_child(current_, me);
      last_ = static_cast<std::int16_t>(hierarchy);
    } else {
      const std::int16_t pos = out_.nodes[static_cast<std::size_t>(me)].hierarchy_pos;
      int at = current_;
      while (at >= 0 && out_.nodes[static_cast<std::size_t>(at)].hierarchy_pos != pos)
        at = out_.nodes[static_cast<std::size_t>(at)].parent;
      if (at < 0)
        add_child(0, me);
      else
        add_child(out_.nodes[static_cast<std::size_t>(at)].parent >= 0 ? out_.nodes[static_cast<std::size_t>(at)].parent : at, me);
      last_ = static_cast<std::int16_t>(last_ + 1);
    }
    current_ = me;
  }

  void finish() {
    if (out_.objects.empty()) decline();
    std::unordered_set<std::string> carried;
    for (const TdsKeyNode& k : out_.nodes) {
      if (k.name == "$$$DUMMY") decline();
      if (object_names_.count(k.name)) carried.insert(k.name);
    }
    if (out_.nodes.size() > 1 && carried.size() != out_.objects.size()) decline();
    // Depth, iteratively: parents precede children in out_.nodes.
    std::vector<int> depth(out_.nodes.size(), 0);
    for (std::size_t i = 1; i < out_.nodes.size(); ++i) {
      depth[i] = depth[static_cast<std::size_t>(out_.nodes[i].parent)] + 1;
      if (depth[i] > kMaxDepth) decline();
    }
  }

  const std::vector<unsigned char>& b_;
  TdsFile out_;
  std::unordered_set<std::string> names_, object_names_;
  int current_ = 0;
  std::int16_t last_ = -1;
};

}  // namespace

std::optional<TdsFile> read_3ds_strict(const std::vector<unsigned char>& bytes) {
  try {
    return StrictReader(bytes).read();
  } catch (const Declined&) {
    return std::nullopt;
  }
}

std::optional<TdsFile> read_3ds_strict(const std::filesystem::path& file) {
  return read_3ds_strict(read_tds_bytes(file));
}

}  // namespace plancheck
