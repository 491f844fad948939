// SPDX-License-Identifier: MIT
// Model file -> part tree through assimp.
//
// What assimp 5.2 produces, and what we make of it (explored on the
// assimp-testmodels files):
// - 3ds with a keyframer section (CameraRollAnimWithChildObject.3ds, test1.3ds):
//   root "<3DSRoot>" (or the file's root dummy), one node per keyframer node
//   named after its object, meshes hung directly on that node, cameras and
//   dummies as mesh-less nodes (Box02 sits under Camera01). A second instance
//   of an object is a distinct node "Name_inst_2": it is a distinct part at
//   another place, so it keeps that name.
// - 3ds without a keyframer (fels.3ds): root "<3DSDummyRoot>" with one child
//   "3DSMesh_<i>" per output mesh. The object names are lost there, but each
//   mesh is named with the decimal index of its object among the file's
//   trimesh objects (0x4000 chunks holding 0x4100), and an object split by
//   material yields several meshes with that same index. We read the object
//   names from the file's own chunks and fold every "3DSMesh_<i>" of one
//   object into one node named after the object.
// - Importers (and exporters) that hang an object's meshes on generated
//   children ("Object" -> "Object_3", or an unnamed child): such a child is
//   folded into its parent (its meshes become the parent's part) when it is a
//   leaf with meshes, named "" or "<parent>_<digits>", with an identity
//   transform, under a parent that is not the root and owns no mesh itself.
//   assimp 5.2's own 3ds importer never makes such children (it hangs meshes
//   on the object's node), and the conditions are strict on purpose: a user's
//   own child "Leg_1" under a "Leg" that has a mesh, or placed by its own
//   transform, stays a part of its own.
// - obj: root named after the file, one child per object/group; dae: the
//   visual scene tree; gltf/glb: the node tree ("nodes[1]" when unnamed);
//   stl/ply: a root (or one child) with an empty name. A part whose node has
//   no name is named after the model file's stem ("Wuson" for Wuson.ply), with
//   "_2", "_3", ... when several are unnamed.
// Coordinates: the reference frame is the file's own. assimp is told to leave
// Collada's up_axis alone; its extra z-up -> y-up root turn for 3ds is taken
// off again. For 3ds the drawn pose is the editor section (0x4110 points, in
// the file's frame), which is not always the keyframer's frame 0 as assimp
// composes it: an animated file (RotatingCube.3DS), a mesh under a camera
// (assimp gives a camera node only its roll), test1.3ds's rotated boxes. So a
// 3ds part's vertices and faces are the file's own (points shared as in the
// file), matched to assimp's meshes face by face (Builder::match_drawn_faces);
// the keyframer gives the hierarchy only. A second instance of an object ("Box01_inst_2") exists only in the
// keyframer and keeps assimp's keyframer pose.
// Non-triangle meshes (points, lines) are split off by aiProcess_SortByPType
// and skipped with a warning. aiProcess_ValidateDataStructure turns broken
// files (indices out of range, meshes without faces) into load errors instead
// of undefined reads.
#include "src/scene/model_loader.h"

#include "src/base/error.h"
#include "src/scene/isolate.h"

#include <assimp/Importer.hpp>
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <Eigen/Core>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <set>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

namespace plancheck {
namespace {

using Mat4 = Eigen::Matrix4d;

Mat4 to_eigen(const aiMatrix4x4& m) {
  Mat4 r;
  r << m.a1, m.a2, m.a3, m.a4,
       m.b1, m.b2, m.b3, m.b4,
       m.c1, m.c2, m.c3, m.c4,
       m.d1, m.d2, m.d3, m.d4;
  return r;
}

bool is_3ds(const std::filesystem::path& file) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext == ".3ds";
}

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
// to assimp's own pose (see Builder::editor_vertices).
class TdsReader {
 public:
  explicit TdsReader(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    b_.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }

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
          if (object && has(body, 2, stop) && has(body + 2, 12 * std::size_t{u16(body)}, stop))
            for (unsigned i = 0, n = u16(body); i < n; ++i)
              object->points.emplace_back(f32(body + 2 + 12 * i), f32(body + 6 + 12 * i), f32(body + 10 + 12 * i));
          break;
        case 0x4120:
          if (object && has(body, 2, stop) && has(body + 2, 8 * std::size_t{u16(body)}, stop)) {
            const unsigned n = u16(body);
            for (unsigned i = 0; i < n; ++i)
              object->faces.push_back({u16(body + 2 + 8 * i), u16(body + 4 + 8 * i), u16(body + 6 + 8 * i)});
            object->face_material.assign(n, std::string());
            walk(body + 2 + 8 * std::size_t{n}, stop, object);  // material groups follow the face list
          }
          break;
        case 0x4130:
          if (object) {
            std::size_t after;
            const std::string material = cstring(body, stop, after);
            if (has(after, 2, stop) && has(after + 2, 2 * std::size_t{u16(after)}, stop))
              for (unsigned i = 0, n = u16(after); i < n; ++i) {
                const unsigned face = u16(after + 2 + 2 * i);
                if (face < object->face_material.size()) object->face_material[face] = material;
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

// assimp's OFF reader believes the header's counts and spends a minute and
// gigabytes on a header like "353535235358 6 0" (assimp-testmodels
// invalid/OutOfMemory.off). A count the file cannot hold is refused up front:
// a vertex line takes at least 6 bytes ("0 0 0\n"), a face line at least 8.
void check_off_counts(const std::filesystem::path& file) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext != ".off") return;
  std::error_code ec;
  const auto size = std::filesystem::file_size(file, ec);
  if (ec) return;
  std::ifstream in(file);
  std::string word;
  std::vector<std::string> words;
  while (words.size() < 3 && in >> word) {
    if (word[0] == '#') {
      std::getline(in, word);
      continue;
    }
    if (words.empty() && word.size() >= 3 && word.compare(word.size() - 3, 3, "OFF") == 0) continue;
    words.push_back(word);
  }
  if (words.size() < 2) return;  // let assimp say what is wrong
  char* end = nullptr;
  const unsigned long long vertices = std::strtoull(words[0].c_str(), &end, 10);
  const unsigned long long faces = std::strtoull(words[1].c_str(), &end, 10);
  if (vertices > size / 6 + 1 || faces > size / 8 + 1)
    fail(file, "cannot read model: the OFF header claims " + words[0] + " vertices and " + words[1] +
                   " faces, more than the file can hold");
}

// assimp 5.2's PLY reader never returns on a header that ends before its
// "end_header" line (found by fuzz_model: a 121-byte truncated header hung
// `plancheck scene` forever). The header is text ahead of any binary body,
// so that line is looked for first. Whatever the extension: assimp hands a
// file whose own importer refuses it to any importer that recognises its
// content, and the PLY reader takes any file that starts with "ply" (found
// by fuzz_model: PLY text named model.glb hung the same way).
void check_ply_header(const std::filesystem::path& file) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  std::ifstream in(file, std::ios::binary);
  char magic[3] = {0, 0, 0};
  in.read(magic, 3);
  const bool ply_content = in.gcount() == 3 && std::tolower(static_cast<unsigned char>(magic[0])) == 'p' &&
                           std::tolower(static_cast<unsigned char>(magic[1])) == 'l' &&
                           std::tolower(static_cast<unsigned char>(magic[2])) == 'y';
  if (ext != ".ply" && !ply_content) return;
  in.clear();
  in.seekg(0);
  std::string line;
  while (std::getline(in, line)) {
    const std::size_t first = line.find_first_not_of(" \t\r");
    const std::size_t last = line.find_last_not_of(" \t\r");
    if (first != std::string::npos && line.compare(first, last + 1 - first, "end_header") == 0) return;
  }
  fail(file, "cannot read model: the PLY header has no end_header line");
}

// assimp 5.2's 3ds reader reserves a keyframer track's keys from the count
// in the file before reading them (found by fuzz_model: one 38-byte position
// track claiming 1644167169 keys made it ask for 39 GB). A key takes at least
// 6 bytes (frame number and flags), so a count its chunk cannot hold is
// refused up front. Tracks are chunks 0xB020..0xB029 in the keyframer's
// node chunks 0xB001..0xB007 under 0xB000.
void check_3ds_tracks(const std::vector<unsigned char>& b, std::size_t at, std::size_t end,
                      const std::filesystem::path& file, int depth = 0) {
  auto u16 = [&](std::size_t i) { return static_cast<unsigned>(b[i] | (b[i + 1] << 8)); };
  auto u32 = [&](std::size_t i) { return u16(i) | (static_cast<std::size_t>(u16(i + 2)) << 16); };
  while (at + 6 <= end && depth < 8) {
    const unsigned id = u16(at);
    const std::size_t len = u32(at + 2);
    if (len < 6 || len > end - at) return;  // damage: assimp judges it
    if (id == 0x4D4D || id == 0xB000 || (id >= 0xB001 && id <= 0xB007)) {
      check_3ds_tracks(b, at + 6, at + len, file, depth + 1);
    } else if (id >= 0xB020 && id <= 0xB029 && len >= 20) {
      const std::size_t keys = u32(at + 16);
      if (keys > (len - 20) / 6)
        fail(file, "cannot read model: a 3ds keyframer track at byte " + std::to_string(at) + " claims " +
                       std::to_string(keys) + " keys in " + std::to_string(len) + " bytes");
    }
    at += len;
  }
}

void check_3ds(const std::filesystem::path& file) {
  if (!is_3ds(file)) return;
  std::ifstream in(file, std::ios::binary);
  const std::vector<unsigned char> b((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  check_3ds_tracks(b, 0, b.size(), file);
}

bool is_generated_child_name(const std::string& child, const std::string& parent) {
  if (child.empty()) return true;
  if (parent.empty() || child.size() <= parent.size() + 1) return false;
  if (child.compare(0, parent.size(), parent) != 0 || child[parent.size()] != '_') return false;
  return std::all_of(child.begin() + static_cast<long>(parent.size()) + 1, child.end(),
                     [](unsigned char c) { return std::isdigit(c); });
}

// One output node while the tree is built: meshes with the global transform
// of the assimp node that carried them.
struct PendingMesh {
  const aiMesh* mesh;
  Mat4 global;             // node transforms from the root down
  // 3ds drawn pose: the object whose points to use and, per mesh face, the
  // object's face it came from. Null: the mesh's vertices through `global`.
  const TdsObject* object = nullptr;
  std::vector<unsigned> object_faces;
};

struct Pending {
  std::vector<PendingMesh> meshes;
};

class Builder {
 public:
  Builder(const aiScene& ai, const std::filesystem::path& file, double scale, Scene& scene, bool unique_names)
      : ai_(ai), file_(file), scale_(scale), scene_(scene), unique_names_(unique_names) {}

  void build() {
    if (is_3ds(file_)) tds_objects_ = TdsReader(file_).objects();
    const aiNode* root = ai_.mRootNode;
    Mat4 root_global = to_eigen(root->mTransformation);
    if (is_3ds(file_)) {
      // assimp's 3ds importer prepends a z-up -> y-up turn (x, y, z) -> (x, z, -y)
      // to the root; the reference frame is the file's own (z up, as the
      // terrain and every pivot in the scene are), so take it off again.
      Mat4 y_up_to_z_up = Mat4::Identity();
      y_up_to_z_up.topLeftCorner<3, 3>() << 1, 0, 0, 0, 0, -1, 0, 1, 0;
      root_global = y_up_to_z_up * root_global;
    }
    const int root_index = add_node(root->mName.C_Str(), -1, root_global);
    attach_meshes(root, root_global, root_index);
    if (is_3ds(file_) && std::strcmp(root->mName.C_Str(), "<3DSDummyRoot>") == 0) {
      build_flat_3ds(root, root_global, root_index);
    } else {
      for (unsigned i = 0; i < root->mNumChildren; ++i) walk(root->mChildren[i], root_global, root_index);
    }
    keep_unattached(root_global, root_index);
    make_parts();
  }

  // A mesh no node carries (a 3ds object the keyframer leaves out, which
  // assimp then hangs nowhere) is still geometry: dropping it could let a plan
  // pass as safe. Each becomes a static part under the root, named after its
  // 3ds object when there is one, with a warning.
  void keep_unattached(const Mat4& root_global, int root_index) {
    std::size_t kept = 0;
    std::map<std::string, int> by_name;
    for (unsigned m = 0; m < ai_.mNumMeshes; ++m) {
      if (used_meshes_.count(m)) continue;
      const aiMesh* mesh = ai_.mMeshes[m];
      const int object = tds_object_of(*mesh);
      std::string name = object >= 0 ? tds_objects_[object].name : std::string(mesh->mName.C_Str());
      if (name.empty()) name = "unattached_mesh_" + std::to_string(m);
      auto [it, added] = by_name.try_emplace(name, 0);
      if (added) it->second = add_node(name, root_index, root_global);
      PendingMesh pm{mesh, root_global, nullptr, {}};
      if (object >= 0 && match_drawn_faces(*mesh, tds_objects_[object], pm.object_faces))
        pm.object = &tds_objects_[object];
      pending_[it->second].meshes.push_back(std::move(pm));
      used_meshes_.insert(m);
      ++kept;
    }
    if (kept > 0)
      scene_.warnings.push_back(located(file_, std::to_string(kept) +
                                                   " meshes attached to no node kept as static parts under the root"));
  }

 private:
  int add_node(const std::string& name, int parent, const Mat4& global) {
    Node n;
    n.name = name;
    n.parent = parent;
    n.origin = global.topRightCorner<3, 1>() * scale_;
    int index = static_cast<int>(scene_.nodes.size());
    if (parent >= 0) scene_.nodes[parent].children.push_back(index);
    scene_.nodes.push_back(std::move(n));
    pending_.emplace_back();
    return index;
  }

  void attach_meshes(const aiNode* node, const Mat4& global, int target, bool flat_3ds = false) {
    for (unsigned i = 0; i < node->mNumMeshes; ++i) {
      unsigned m = node->mMeshes[i];
      used_meshes_.insert(m);
      PendingMesh pm{ai_.mMeshes[m], global, nullptr, {}};
      // A 3ds object is taken as drawn (see the top of the file); a second
      // instance ("Name_inst_2") exists only in the keyframer, so it keeps
      // assimp's keyframer pose.
      const int object = tds_object_of(*pm.mesh);
      if (object >= 0 && (flat_3ds || tds_objects_[object].name == node->mName.C_Str()) &&
          match_drawn_faces(*pm.mesh, tds_objects_[object], pm.object_faces)) {
        pm.object = &tds_objects_[object];
      }
      pending_[target].meshes.push_back(std::move(pm));
    }
  }

  // assimp names each 3ds mesh with the decimal index of its object.
  int tds_object_of(const aiMesh& mesh) const {
    const char* name = mesh.mName.C_Str();
    char* end = nullptr;
    const unsigned long object = std::strtoul(name, &end, 10);
    if (*name == '\0' || *end != '\0' || object >= tds_objects_.size()) return -1;
    return static_cast<int>(object);
  }

  // assimp splits a 3ds object by material (faces of one material in file
  // order, three fresh vertices per face) and moves it into its node's frame.
  // Matching the faces back gives the file's own faces and points. The match
  // is accepted only when one affine map takes the file's points to assimp's
  // vertices (which is what assimp did); otherwise the keyframer pose is used,
  // with a warning.
  bool match_drawn_faces(const aiMesh& mesh, const TdsObject& object, std::vector<unsigned>& faces) {
    aiString material_name;
    if (mesh.mMaterialIndex < ai_.mNumMaterials)
      ai_.mMaterials[mesh.mMaterialIndex]->Get(AI_MATKEY_NAME, material_name);
    const std::string material = material_name.C_Str();
    std::vector<unsigned> with_unassigned;
    faces.clear();
    for (unsigned f = 0; f < object.faces.size(); ++f) {
      if (object.face_material[f] == material) faces.push_back(f);
      if (object.face_material[f] == material || object.face_material[f].empty()) with_unassigned.push_back(f);
    }
    if (faces.size() != mesh.mNumFaces) faces = with_unassigned;  // assimp's default material
    bool ok = faces.size() == mesh.mNumFaces && mesh.mNumVertices > 0;
    std::vector<Vec3> drawn(mesh.mNumVertices, Vec3::Constant(std::numeric_limits<double>::quiet_NaN()));
    for (unsigned q = 0; ok && q < mesh.mNumFaces; ++q) {
      const aiFace& face = mesh.mFaces[q];
      ok = face.mNumIndices == 3;
      for (unsigned a = 0; ok && a < 3; ++a) {
        const unsigned point = object.faces[faces[q]][a];
        ok = face.mIndices[a] < mesh.mNumVertices && point < object.points.size();
        if (ok) drawn[face.mIndices[a]] = object.points[point];
      }
    }
    if (ok) {
      // Least squares: assimp_vertex = A * [drawn; 1].
      Eigen::MatrixXd x(mesh.mNumVertices, 4), y(mesh.mNumVertices, 3);
      for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
        ok = ok && drawn[v].allFinite();
        x.row(v) << drawn[v].transpose(), 1.0;
        y.row(v) << mesh.mVertices[v].x, mesh.mVertices[v].y, mesh.mVertices[v].z;
      }
      if (ok) {
        const Eigen::MatrixXd a = x.colPivHouseholderQr().solve(y);
        const double size = std::max(1.0, (y.colwise().maxCoeff() - y.colwise().minCoeff()).norm());
        ok = a.allFinite() && ((x * a - y).rowwise().norm().maxCoeff() <= 1e-4 * size);
      }
    }
    if (!ok)
      scene_.warnings.push_back(located(file_, "3ds object '" + object.name +
                                                   "': faces not matched to assimp's mesh; keyframer pose used"));
    return ok;
  }

  void walk(const aiNode* node, const Mat4& parent_global, int parent) {
    Mat4 global = parent_global * to_eigen(node->mTransformation);
    const std::string name = node->mName.C_Str();
    if (node->mNumChildren == 0 && node->mNumMeshes > 0 && parent != 0 && node->mParent != nullptr &&
        node->mParent->mNumMeshes == 0 && node->mTransformation.IsIdentity() &&
        is_generated_child_name(name, scene_.nodes[parent].name)) {
      attach_meshes(node, global, parent);
      return;
    }
    int index = add_node(name, parent, global);
    attach_meshes(node, global, index);
    for (unsigned i = 0; i < node->mNumChildren; ++i) walk(node->mChildren[i], global, index);
  }

  void build_flat_3ds(const aiNode* root, const Mat4& root_global, int root_index) {
    std::map<std::string, int> by_object;
    for (unsigned i = 0; i < root->mNumChildren; ++i) {
      const aiNode* child = root->mChildren[i];
      Mat4 global = root_global * to_eigen(child->mTransformation);
      std::string name = child->mName.C_Str();
      if (child->mNumMeshes > 0) {
        const int object = tds_object_of(*ai_.mMeshes[child->mMeshes[0]]);
        if (object >= 0) name = tds_objects_[object].name;
      }
      auto found = by_object.find(name);
      int index;
      if (found != by_object.end() && child->mNumMeshes > 0) {
        index = found->second;
      } else {
        index = add_node(name, root_index, global);
        if (child->mNumMeshes > 0) by_object[name] = index;
      }
      attach_meshes(child, global, index, true);
      for (unsigned c = 0; c < child->mNumChildren; ++c) walk(child->mChildren[c], global, index);
    }
  }

  void make_parts() {
    const std::string stem = file_.stem().string();
    int unnamed = 0;
    std::size_t ignored_faces = 0;
    for (std::size_t i = 0; i < scene_.nodes.size(); ++i) {
      Node& node = scene_.nodes[i];
      Pending& p = pending_[i];
      Mesh mesh;
      // A 3ds object's points enter a part once, shared by its meshes' faces.
      std::map<const TdsObject*, std::uint32_t> object_base;
      for (const auto& [m, global, object, object_faces] : p.meshes) {
        if (!(m->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) {
          ignored_faces += m->mNumFaces;
          continue;
        }
        if (object != nullptr) {
          auto [at, inserted] = object_base.emplace(object, static_cast<std::uint32_t>(mesh.vertices.size()));
          if (inserted)
            for (const Vec3& point : object->points) mesh.vertices.push_back(point * scale_);
          for (unsigned f : object_faces) {
            const auto& t = object->faces[f];
            mesh.triangles.push_back({at->second + t[0], at->second + t[1], at->second + t[2]});
          }
          continue;
        }
        const auto base = static_cast<std::uint32_t>(mesh.vertices.size());
        const Mat3 linear = global.topLeftCorner<3, 3>();
        const Vec3 offset = global.topRightCorner<3, 1>();
        for (unsigned v = 0; v < m->mNumVertices; ++v) {
          const aiVector3D& a = m->mVertices[v];
          mesh.vertices.push_back((linear * Vec3(a.x, a.y, a.z) + offset) * scale_);
        }
        for (unsigned f = 0; f < m->mNumFaces; ++f) {
          const aiFace& face = m->mFaces[f];
          if (face.mNumIndices != 3) {
            ++ignored_faces;
            continue;
          }
          mesh.triangles.push_back({base + face.mIndices[0], base + face.mIndices[1], base + face.mIndices[2]});
        }
      }
      if (mesh.triangles.empty()) continue;
      if (node.name.empty()) node.name = unnamed++ == 0 ? stem : stem + "_" + std::to_string(unnamed);
      Part part;
      part.name = node.name;
      part.node = static_cast<int>(i);
      part.mesh = std::move(mesh);
      node.part = static_cast<int>(scene_.parts.size());
      scene_.parts.push_back(std::move(part));
    }
    // Paths after naming, parents before children by construction.
    for (Node& node : scene_.nodes) {
      const std::string shown = node.name.empty() ? "<unnamed>" : node.name;
      node.path = (node.parent < 0 ? std::string() : scene_.nodes[node.parent].path) + "/" + shown;
    }
    for (const Part& part : scene_.parts) {
      for (const Vec3& v : part.mesh.vertices) {
        if (!v.allFinite())
          fail(file_, "part '" + part.name + "' (" + scene_.nodes[part.node].path + "): non-finite vertex");
      }
    }
    std::map<std::string, int> seen;
    for (const Part& part : scene_.parts) {
      if (!unique_names_) break;
      auto [it, inserted] = seen.emplace(part.name, part.node);
      if (!inserted)
        fail(file_, "duplicate part name '" + part.name + "': " + scene_.nodes[it->second].path + " and " +
                        scene_.nodes[part.node].path);
    }
    if (scene_.parts.empty()) fail(file_, "the model has no triangles");
    if (ignored_faces > 0)
      scene_.warnings.push_back(located(file_, std::to_string(ignored_faces) +
                                                   " non-triangle primitives (points, lines) ignored"));
  }

  const aiScene& ai_;
  std::filesystem::path file_;
  double scale_;
  Scene& scene_;
  bool unique_names_;
  std::vector<Pending> pending_;
  std::vector<TdsObject> tds_objects_;  // 3ds files only
  std::set<unsigned> used_meshes_;
};

// The import proper: assimp and the Builder, in whatever process runs it.
void import_model(const std::filesystem::path& model, double length_scale, Scene& scene, bool unique_names) {
  Assimp::Importer importer;
  // The reference frame is the file's own coordinates: no up-axis conversion.
  importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, true);
  // FBX pivots would otherwise appear as extra "$AssimpFbx$" nodes in the part tree.
  importer.SetPropertyBool(AI_CONFIG_IMPORT_FBX_PRESERVE_PIVOTS, false);
  const aiScene* ai = nullptr;
  try {
    ai = importer.ReadFile(model.string(),
                           aiProcess_Triangulate | aiProcess_SortByPType | aiProcess_ValidateDataStructure);
  } catch (const std::exception& e) {
    fail(model, std::string("cannot read model: ") + e.what());
  }
  if (ai == nullptr) fail(model, std::string("cannot read model: ") + importer.GetErrorString());
  if (ai->mRootNode == nullptr || (ai->mFlags & AI_SCENE_FLAGS_INCOMPLETE) || ai->mNumMeshes == 0)
    fail(model, "cannot read model: the file holds no meshes");
  scene.nodes.clear();
  scene.parts.clear();
  Builder(*ai, model, length_scale, scene, unique_names).build();
}

// What the import hands back from its child process: the part tree, the
// meshes and the warnings, as flat bytes (same machine, same build).
static_assert(sizeof(Vec3) == 3 * sizeof(double), "points travel as packed doubles");

class Packer {
 public:
  template <class T>
  void put(const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    bytes_.append(reinterpret_cast<const char*>(&value), sizeof value);
  }
  template <class T>
  void put_array(const T* data, std::size_t count) {
    put<std::uint64_t>(count);
    if (count > 0) bytes_.append(reinterpret_cast<const char*>(data), count * sizeof(T));
  }
  void put_string(const std::string& s) { put_array(s.data(), s.size()); }
  void put_point(const Vec3& v) {
    for (int k = 0; k < 3; ++k) put<double>(v[k]);
  }
  void put_points(const std::vector<Vec3>& points) {  // Vec3: three packed doubles
    put_array(points.empty() ? nullptr : points.data()->data(), 3 * points.size());
  }
  std::string take() { return std::move(bytes_); }

 private:
  std::string bytes_;
};

class Unpacker {
 public:
  Unpacker(std::string_view bytes, const std::filesystem::path& file) : bytes_(bytes), file_(file) {}
  template <class T>
  T get() {
    static_assert(std::is_trivially_copyable_v<T>);
    T value;
    need(sizeof value);
    std::memcpy(&value, bytes_.data() + at_, sizeof value);
    at_ += sizeof value;
    return value;
  }
  Vec3 get_point() {
    Vec3 v;
    for (int k = 0; k < 3; ++k) v[k] = get<double>();
    return v;
  }
  void get_points(std::vector<Vec3>& out) {
    const auto count = get<std::uint64_t>();
    if (count % 3 != 0 || count > (bytes_.size() - at_) / sizeof(double)) damaged();
    out.resize(count / 3);
    if (count > 0) std::memcpy(out.data()->data(), bytes_.data() + at_, count * sizeof(double));
    at_ += count * sizeof(double);
  }
  template <class T>
  void get_array(std::vector<T>& out) {
    static_assert(std::is_trivially_copyable_v<T>);
    const auto count = get<std::uint64_t>();
    if (count > (bytes_.size() - at_) / sizeof(T)) damaged();
    out.resize(count);
    if (count > 0) std::memcpy(out.data(), bytes_.data() + at_, count * sizeof(T));
    at_ += count * sizeof(T);
  }
  std::string get_string() {
    std::vector<char> chars;
    get_array(chars);
    return std::string(chars.begin(), chars.end());
  }
  bool done() const { return at_ == bytes_.size(); }
  [[noreturn]] void damaged() const { fail(file_, "cannot read model: the importer's result is damaged"); }

 private:
  void need(std::size_t n) const {
    if (n > bytes_.size() - at_) damaged();
  }
  std::string_view bytes_;
  std::filesystem::path file_;
  std::size_t at_ = 0;
};

std::string pack(const Scene& scene) {
  Packer p;
  p.put<std::uint64_t>(scene.nodes.size());
  for (const Node& n : scene.nodes) {
    p.put_string(n.name);
    p.put_string(n.path);
    p.put<std::int32_t>(n.parent);
    p.put<std::int32_t>(n.part);
    p.put_array(n.children.data(), n.children.size());
    p.put_point(n.origin);
  }
  p.put<std::uint64_t>(scene.parts.size());
  for (const Part& part : scene.parts) {
    p.put_string(part.name);
    p.put<std::int32_t>(part.node);
    p.put_points(part.mesh.vertices);
    p.put_array(part.mesh.triangles.data(), part.mesh.triangles.size());
  }
  p.put<std::uint64_t>(scene.warnings.size());
  for (const std::string& w : scene.warnings) p.put_string(w);
  return p.take();
}

// Unpacks into scene and checks what the rest of plancheck relies on (a
// tree with parents before children, parts and nodes pointing at each
// other, indices in range, finite vertices) rather than trusting the child.
void unpack(std::string_view bytes, const std::filesystem::path& file, Scene& scene) {
  Unpacker u(bytes, file);
  std::vector<Node> nodes(std::min<std::uint64_t>(u.get<std::uint64_t>(), bytes.size()));
  for (Node& n : nodes) {
    n.name = u.get_string();
    n.path = u.get_string();
    n.parent = u.get<std::int32_t>();
    n.part = u.get<std::int32_t>();
    u.get_array(n.children);
    n.origin = u.get_point();
  }
  std::vector<Part> parts(std::min<std::uint64_t>(u.get<std::uint64_t>(), bytes.size()));
  for (Part& part : parts) {
    part.name = u.get_string();
    part.node = u.get<std::int32_t>();
    u.get_points(part.mesh.vertices);
    u.get_array(part.mesh.triangles);
  }
  std::vector<std::string> warnings(std::min<std::uint64_t>(u.get<std::uint64_t>(), bytes.size()));
  for (std::string& w : warnings) w = u.get_string();
  if (!u.done() || nodes.empty() || parts.empty()) u.damaged();
  const auto node_count = static_cast<long>(nodes.size()), part_count = static_cast<long>(parts.size());
  for (long i = 0; i < node_count; ++i) {
    const Node& n = nodes[i];
    if ((i == 0) != (n.parent < 0) || n.parent >= i || n.part < -1 || n.part >= part_count) u.damaged();
    for (int c : n.children)
      if (c <= i || c >= node_count || nodes[c].parent != i) u.damaged();
  }
  for (long i = 0; i < part_count; ++i) {
    const Part& part = parts[i];
    if (part.node < 0 || part.node >= node_count || nodes[part.node].part != i || part.mesh.triangles.empty())
      u.damaged();
    for (const Vec3& v : part.mesh.vertices)
      if (!v.allFinite()) u.damaged();
    for (const Tri& t : part.mesh.triangles)
      for (auto index : t)
        if (index >= part.mesh.vertices.size()) u.damaged();
  }
  scene.nodes = std::move(nodes);
  scene.parts = std::move(parts);
  for (std::string& w : warnings) scene.warnings.push_back(std::move(w));
}

}  // namespace

namespace {

// load_model's body: the checks ahead of assimp, the isolated import, the
// checked unpacking.
void import_checked(const std::filesystem::path& model, double length_scale, Scene& scene,
                    const IsolationLimits& limits, bool unique_names) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(model, ec)) fail(model, "cannot open model file (missing or not a file)");
  {
    std::ifstream probe(model, std::ios::binary);
    if (!probe) fail(model, "cannot open model file");
    if (probe.peek() == std::ifstream::traits_type::eof()) fail(model, "cannot read model: the file is empty");
  }
  check_off_counts(model);
  check_ply_header(model);
  check_3ds(model);
  std::string packed;
  try {
    packed = run_isolated(
        [&] {
          Scene imported;
          import_model(model, length_scale, imported, unique_names);
          return pack(imported);
        },
        limits);
  } catch (const IsolationError& e) {
    fail(model, std::string("cannot read model: the importer ") + e.what());
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    fail(model, std::string("cannot read model: ") + e.what());
  }
  unpack(packed, model, scene);
}

}  // namespace

void load_model(const std::filesystem::path& model, double length_scale, Scene& scene,
                const IsolationLimits& limits) {
  import_checked(model, length_scale, scene, limits, true);
}

Mesh load_mesh(const std::filesystem::path& model, std::vector<std::string>& warnings,
               const IsolationLimits& limits) {
  Scene imported;
  import_checked(model, 1.0, imported, limits, false);
  Mesh mesh;
  for (const Part& part : imported.parts) {
    const auto base = static_cast<std::uint32_t>(mesh.vertices.size());
    mesh.vertices.insert(mesh.vertices.end(), part.mesh.vertices.begin(), part.mesh.vertices.end());
    for (const Tri& t : part.mesh.triangles) mesh.triangles.push_back({base + t[0], base + t[1], base + t[2]});
  }
  for (std::string& w : imported.warnings) warnings.push_back(std::move(w));
  return mesh;
}

}  // namespace plancheck
