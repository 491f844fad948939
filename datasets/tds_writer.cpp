// SPDX-License-Identifier: MIT
#include "datasets/tds_writer.h"

#include <cmath>
#include <cstring>
#include <fstream>
#include <set>
#include <stdexcept>
#include <unordered_map>

namespace plancheck {
namespace {

// Chunk ids used (3ds file format, as documented by the 3ds community specs).
constexpr std::uint16_t kMain = 0x4D4D;
constexpr std::uint16_t kVersion = 0x0002;
constexpr std::uint16_t kEditor = 0x3D3D;
constexpr std::uint16_t kMeshVersion = 0x3D3E;
constexpr std::uint16_t kMasterScale = 0x0100;
constexpr std::uint16_t kObject = 0x4000;
constexpr std::uint16_t kTriMesh = 0x4100;
constexpr std::uint16_t kVertices = 0x4110;
constexpr std::uint16_t kFaces = 0x4120;
constexpr std::uint16_t kLocalAxes = 0x4160;
constexpr std::uint16_t kKeyframer = 0xB000;
constexpr std::uint16_t kObjectNode = 0xB002;
constexpr std::uint16_t kKfSegment = 0xB008;
constexpr std::uint16_t kKfCurrentTime = 0xB009;
constexpr std::uint16_t kKfHeader = 0xB00A;
constexpr std::uint16_t kNodeHeader = 0xB010;
constexpr std::uint16_t kInstanceName = 0xB011;
constexpr std::uint16_t kPivot = 0xB013;
constexpr std::uint16_t kPositionTrack = 0xB020;
constexpr std::uint16_t kRotationTrack = 0xB021;
constexpr std::uint16_t kScaleTrack = 0xB022;
constexpr std::uint16_t kNodeId = 0xB030;
constexpr std::uint16_t kNoParent = 0xFFFF;

// Little-endian byte sink with nested chunks: open() leaves room for the
// 6-byte header, close() patches the length once the body is known.
class Writer {
 public:
  std::vector<std::uint8_t> bytes;

  void u8(std::uint8_t v) { bytes.push_back(v); }
  void u16(std::uint16_t v) {
    u8(static_cast<std::uint8_t>(v & 0xFF));
    u8(static_cast<std::uint8_t>(v >> 8));
  }
  void u32(std::uint32_t v) {
    for (int i = 0; i < 4; ++i) u8(static_cast<std::uint8_t>((v >> (8 * i)) & 0xFF));
  }
  void f32(float v) {
    std::uint32_t u;
    std::memcpy(&u, &v, 4);
    u32(u);
  }
  void cstr(const std::string& s) {
    for (char c : s) u8(static_cast<std::uint8_t>(c));
    u8(0);
  }
  std::size_t open(std::uint16_t id) {
    std::size_t at = bytes.size();
    u16(id);
    u32(0);
    return at;
  }
  void close(std::size_t at) {
    std::uint32_t len = static_cast<std::uint32_t>(bytes.size() - at);
    for (int i = 0; i < 4; ++i) bytes[at + 2 + i] = static_cast<std::uint8_t>((len >> (8 * i)) & 0xFF);
  }
};

struct Piece {
  std::string name;
  TdsMesh mesh;  // under both 16-bit limits
};

// Greedy split in face order: a piece closes when the next face would push its
// vertex or face count over the 16-bit limit. Deterministic, keeps file order.
std::vector<TdsMesh> split_mesh(const TdsMesh& mesh) {
  std::vector<TdsMesh> out;
  if (mesh.vertices.size() <= kTdsMaxObjectElements && mesh.faces.size() <= kTdsMaxObjectElements) {
    out.push_back(mesh);
    return out;
  }
  std::unordered_map<std::uint32_t, std::uint32_t> remap;
  TdsMesh cur;
  for (const auto& f : mesh.faces) {
    std::size_t fresh = 0;
    for (int k = 0; k < 3; ++k)
      if (!remap.count(f[k])) ++fresh;
    if (cur.faces.size() + 1 > kTdsMaxObjectElements || cur.vertices.size() + fresh > kTdsMaxObjectElements) {
      out.push_back(std::move(cur));
      cur = TdsMesh{};
      remap.clear();
    }
    std::array<std::uint32_t, 3> g{};
    for (int k = 0; k < 3; ++k) {
      auto it = remap.find(f[k]);
      if (it == remap.end()) {
        std::uint32_t idx = static_cast<std::uint32_t>(cur.vertices.size());
        cur.vertices.push_back(mesh.vertices[f[k]]);
        it = remap.emplace(f[k], idx).first;
      }
      g[k] = it->second;
    }
    cur.faces.push_back(g);
  }
  if (!cur.faces.empty()) out.push_back(std::move(cur));
  return out;
}

void write_object(Writer& w, const std::string& name, const TdsMesh& mesh) {
  std::size_t obj = w.open(kObject);
  w.cstr(name);
  std::size_t tri = w.open(kTriMesh);
  std::size_t v = w.open(kVertices);
  w.u16(static_cast<std::uint16_t>(mesh.vertices.size()));
  for (const auto& p : mesh.vertices)
    for (float c : p) w.f32(c);
  w.close(v);
  // Identity local axes: the vertices are already where the object sits, so
  // an importer that undoes this matrix leaves them untouched.
  std::size_t axes = w.open(kLocalAxes);
  const float identity[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};
  for (float c : identity) w.f32(c);
  w.close(axes);
  std::size_t f = w.open(kFaces);
  w.u16(static_cast<std::uint16_t>(mesh.faces.size()));
  for (const auto& t : mesh.faces) {
    w.u16(static_cast<std::uint16_t>(t[0]));
    w.u16(static_cast<std::uint16_t>(t[1]));
    w.u16(static_cast<std::uint16_t>(t[2]));
    w.u16(0x0007);  // all three edges visible
  }
  w.close(f);
  w.close(tri);
  w.close(obj);
}

// One keyframe at frame 0 with no spline data (flags 0).
void track_header(Writer& w) {
  w.u16(0);  // track flags
  w.u32(0);  // unused
  w.u32(0);  // unused
  w.u32(1);  // key count
  w.u32(0);  // frame
  w.u16(0);  // key flags: no tension/continuity/bias/ease data follows
}

void write_node(Writer& w, std::uint16_t id, std::uint16_t parent, const std::string& name, bool dummy) {
  std::size_t node = w.open(kObjectNode);
  std::size_t nid = w.open(kNodeId);
  w.u16(id);
  w.close(nid);
  std::size_t hdr = w.open(kNodeHeader);
  w.cstr(dummy ? "$$$DUMMY" : name);
  w.u16(0);  // flags 1
  w.u16(0);  // flags 2
  w.u16(parent);
  w.close(hdr);
  if (dummy) {
    std::size_t inst = w.open(kInstanceName);
    w.cstr(name);
    w.close(inst);
  }
  std::size_t piv = w.open(kPivot);
  w.f32(0);
  w.f32(0);
  w.f32(0);
  w.close(piv);
  std::size_t pos = w.open(kPositionTrack);
  track_header(w);
  w.f32(0);
  w.f32(0);
  w.f32(0);
  w.close(pos);
  std::size_t rot = w.open(kRotationTrack);
  track_header(w);
  w.f32(0);  // angle
  w.f32(0);  // axis
  w.f32(0);
  w.f32(1);
  w.close(rot);
  std::size_t scl = w.open(kScaleTrack);
  track_header(w);
  w.f32(1);
  w.f32(1);
  w.f32(1);
  w.close(scl);
  w.close(node);
}

void validate(const std::vector<TdsNode>& nodes) {
  std::set<std::string> names;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const TdsNode& n = nodes[i];
    if (n.name.empty()) throw std::invalid_argument("3ds writer: node " + std::to_string(i) + " has no name");
    if (n.name == "$$$DUMMY") throw std::invalid_argument("3ds writer: reserved node name $$$DUMMY");
    if (!names.insert(n.name).second) throw std::invalid_argument("3ds writer: duplicate node name " + n.name);
    if (n.parent < -1 || n.parent >= static_cast<int>(i))
      throw std::invalid_argument("3ds writer: node " + n.name + " must come after its parent");
    for (const auto& p : n.mesh.vertices)
      for (float c : p)
        if (!std::isfinite(c)) throw std::invalid_argument("3ds writer: non-finite vertex in " + n.name);
    for (const auto& f : n.mesh.faces)
      for (auto k : f)
        if (k >= n.mesh.vertices.size())
          throw std::invalid_argument("3ds writer: face index out of range in " + n.name);
  }
}

}  // namespace

std::vector<std::string> tds_object_names(const TdsNode& node) {
  std::vector<std::string> out;
  if (node.mesh.faces.empty()) return out;
  std::size_t pieces = split_mesh(node.mesh).size();
  if (pieces == 1) {
    out.push_back(node.name);
  } else {
    for (std::size_t k = 0; k < pieces; ++k) out.push_back(node.name + "." + std::to_string(k + 1));
  }
  return out;
}

std::vector<std::uint8_t> tds_serialize(const std::vector<TdsNode>& nodes) {
  validate(nodes);
  std::vector<std::vector<int>> children(nodes.size());
  std::vector<int> roots;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    if (nodes[i].parent < 0)
      roots.push_back(static_cast<int>(i));
    else
      children[static_cast<std::size_t>(nodes[i].parent)].push_back(static_cast<int>(i));
  }

  // Keyframer nodes in depth-first pre-order, ids = position in that order.
  // Readers that rebuild the tree from the parent indices alone (the paper's
  // rule, assimp's 3DS importer) need exactly this order.
  struct KfNode {
    std::string name;
    bool dummy;
    int parent_kf;  // -1 for a root
  };
  std::vector<KfNode> kf;
  std::vector<Piece> pieces;
  auto visit = [&](auto&& self, int i, int parent_kf) -> void {
    const TdsNode& n = nodes[static_cast<std::size_t>(i)];
    std::vector<TdsMesh> split = n.mesh.faces.empty() ? std::vector<TdsMesh>{} : split_mesh(n.mesh);
    int me = static_cast<int>(kf.size());
    if (split.size() == 1) {
      kf.push_back({n.name, false, parent_kf});
      pieces.push_back({n.name, std::move(split[0])});
    } else {
      kf.push_back({n.name, true, parent_kf});
      for (std::size_t k = 0; k < split.size(); ++k) {
        std::string piece_name = n.name + "." + std::to_string(k + 1);
        kf.push_back({piece_name, false, me});
        pieces.push_back({piece_name, std::move(split[k])});
      }
    }
    for (int c : children[static_cast<std::size_t>(i)]) self(self, c, me);
  };
  for (int r : roots) visit(visit, r, -1);
  if (kf.size() >= kNoParent) throw std::invalid_argument("3ds writer: too many nodes for 16-bit ids");

  Writer w;
  std::size_t main = w.open(kMain);
  std::size_t ver = w.open(kVersion);
  w.u32(3);
  w.close(ver);
  std::size_t ed = w.open(kEditor);
  std::size_t mv = w.open(kMeshVersion);
  w.u32(3);
  w.close(mv);
  std::size_t ms = w.open(kMasterScale);
  w.f32(1.0f);
  w.close(ms);
  for (const Piece& p : pieces) write_object(w, p.name, p.mesh);
  w.close(ed);

  std::size_t kfd = w.open(kKeyframer);
  std::size_t kh = w.open(kKfHeader);
  w.u16(5);  // revision
  w.cstr("plancheck");
  w.u32(0);  // animation length: one frame
  w.close(kh);
  std::size_t seg = w.open(kKfSegment);
  w.u32(0);
  w.u32(0);
  w.close(seg);
  std::size_t ct = w.open(kKfCurrentTime);
  w.u32(0);
  w.close(ct);
  for (std::size_t i = 0; i < kf.size(); ++i) {
    std::uint16_t parent = kf[i].parent_kf < 0 ? kNoParent : static_cast<std::uint16_t>(kf[i].parent_kf);
    write_node(w, static_cast<std::uint16_t>(i), parent, kf[i].name, kf[i].dummy);
  }
  w.close(kfd);
  w.close(main);
  return std::move(w.bytes);
}

void tds_write(const std::filesystem::path& file, const std::vector<TdsNode>& nodes) {
  std::vector<std::uint8_t> bytes = tds_serialize(nodes);
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  if (!out) throw std::runtime_error(file.string() + ": cannot open for writing");
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  if (!out) throw std::runtime_error(file.string() + ": write failed");
}

}  // namespace plancheck
