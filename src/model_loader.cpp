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
// - Other importers that hang an object's meshes on generated leaf children
//   ("Object" -> "Object_3", or an unnamed child): a leaf child without
//   children whose name is empty or "<parent>_<digits>" is folded into its
//   parent (its meshes join the parent's part, its own transform still applied),
//   unless the parent is the root (STL and PLY put the only mesh there).
// - obj: root named after the file, one child per object/group; dae: the
//   visual scene tree; gltf/glb: the node tree ("nodes[1]" when unnamed);
//   stl/ply: a root (or one child) with an empty name. A part whose node has
//   no name is named after the model file's stem ("Wuson" for Wuson.ply), with
//   "_2", "_3", ... when several are unnamed.
// Coordinates: the reference frame is the file's own. assimp turns 3ds files
// from z up to y up with an extra root rotation, which is taken off again, and
// is told to leave Collada's up_axis alone. A 3ds node's transform is its
// keyframer pose at frame 0 (assimp moves the mesh back into the node's local
// frame with the inverse object matrix and the pivot).
// Non-triangle meshes (points, lines) are split off by aiProcess_SortByPType
// and skipped with a warning. aiProcess_ValidateDataStructure turns broken
// files (indices out of range, meshes without faces) into load errors instead
// of undefined reads.
#include "src/model_loader.h"

#include "src/error.h"

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
#include <map>
#include <set>
#include <string>
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

// Names of the trimesh objects of a 3ds file in file order: assimp's mesh
// names in a keyframer-less file are indices into this list.
std::vector<std::string> read_3ds_object_names(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::vector<unsigned char> b((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::vector<std::string> names;
  auto u16 = [&](std::size_t at) { return static_cast<unsigned>(b[at] | (b[at + 1] << 8)); };
  auto u32 = [&](std::size_t at) {
    return static_cast<std::size_t>(b[at]) | (static_cast<std::size_t>(b[at + 1]) << 8) |
           (static_cast<std::size_t>(b[at + 2]) << 16) | (static_cast<std::size_t>(b[at + 3]) << 24);
  };
  // Iterative walk of the chunks that can contain objects: main 0x4D4D,
  // editor 0x3D3D, object 0x4000 (name first, then sub-chunks).
  struct Range { std::size_t begin, end; };
  std::vector<Range> todo{{0, b.size()}};
  while (!todo.empty()) {
    Range r = todo.back();
    todo.pop_back();
    std::vector<Range> inner;
    for (std::size_t at = r.begin; at + 6 <= r.end;) {
      unsigned id = u16(at);
      std::size_t len = u32(at + 2);
      if (len < 6 || len > r.end - at) break;  // damaged: assimp has already judged the file
      if (id == 0x4D4D || id == 0x3D3D) {
        inner.push_back({at + 6, at + len});
      } else if (id == 0x4000) {
        std::size_t name_end = at + 6;
        while (name_end < at + len && b[name_end] != 0) ++name_end;
        std::string name(b.begin() + static_cast<long>(at + 6), b.begin() + static_cast<long>(name_end));
        bool trimesh = false;
        for (std::size_t sub = name_end + 1; sub + 6 <= at + len;) {
          std::size_t sub_len = u32(sub + 2);
          if (u16(sub) == 0x4100) trimesh = true;
          if (sub_len < 6) break;
          sub += sub_len;
        }
        if (trimesh) names.push_back(name);
      }
      at += len;
    }
    // Keep file order: process the inner ranges front to back.
    for (auto it = inner.rbegin(); it != inner.rend(); ++it) todo.push_back(*it);
  }
  return names;
}

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

bool is_generated_child_name(const std::string& child, const std::string& parent) {
  if (child.empty()) return true;
  if (parent.empty() || child.size() <= parent.size() + 1) return false;
  if (child.compare(0, parent.size(), parent) != 0 || child[parent.size()] != '_') return false;
  return std::all_of(child.begin() + static_cast<long>(parent.size()) + 1, child.end(),
                     [](unsigned char c) { return std::isdigit(c); });
}

// One output node while the tree is built: meshes with the global transform
// of the assimp node that carried them.
struct Pending {
  std::vector<std::pair<const aiMesh*, Mat4>> meshes;
};

class Builder {
 public:
  Builder(const aiScene& ai, const std::filesystem::path& file, double scale, Scene& scene)
      : ai_(ai), file_(file), scale_(scale), scene_(scene) {}

  void build() {
    const aiNode* root = ai_.mRootNode;
    int root_index = add_node(root->mName.C_Str(), -1);
    Mat4 root_global = to_eigen(root->mTransformation);
    if (is_3ds(file_)) {
      // assimp's 3ds importer prepends a z-up -> y-up turn (x, y, z) -> (x, z, -y)
      // to the root; the reference frame is the file's own (z up, as the
      // terrain and every pivot in the scene are), so take it off again.
      Mat4 y_up_to_z_up = Mat4::Identity();
      y_up_to_z_up.topLeftCorner<3, 3>() << 1, 0, 0, 0, 0, -1, 0, 1, 0;
      root_global = y_up_to_z_up * root_global;
    }
    attach_meshes(root, root_global, root_index);
    if (is_3ds(file_) && std::strcmp(root->mName.C_Str(), "<3DSDummyRoot>") == 0) {
      build_flat_3ds(root, root_global, root_index);
    } else {
      for (unsigned i = 0; i < root->mNumChildren; ++i) walk(root->mChildren[i], root_global, root_index);
    }
    make_parts();
  }

 private:
  int add_node(const std::string& name, int parent) {
    Node n;
    n.name = name;
    n.parent = parent;
    int index = static_cast<int>(scene_.nodes.size());
    if (parent >= 0) scene_.nodes[parent].children.push_back(index);
    scene_.nodes.push_back(std::move(n));
    pending_.emplace_back();
    return index;
  }

  void attach_meshes(const aiNode* node, const Mat4& global, int target) {
    for (unsigned i = 0; i < node->mNumMeshes; ++i) {
      unsigned m = node->mMeshes[i];
      used_meshes_.insert(m);
      pending_[target].meshes.emplace_back(ai_.mMeshes[m], global);
    }
  }

  void walk(const aiNode* node, const Mat4& parent_global, int parent) {
    Mat4 global = parent_global * to_eigen(node->mTransformation);
    const std::string name = node->mName.C_Str();
    if (node->mNumChildren == 0 && node->mNumMeshes > 0 && parent != 0 &&
        is_generated_child_name(name, scene_.nodes[parent].name)) {
      attach_meshes(node, global, parent);
      return;
    }
    int index = add_node(name, parent);
    attach_meshes(node, global, index);
    for (unsigned i = 0; i < node->mNumChildren; ++i) walk(node->mChildren[i], global, index);
  }

  void build_flat_3ds(const aiNode* root, const Mat4& root_global, int root_index) {
    std::vector<std::string> objects = read_3ds_object_names(file_);
    std::map<std::string, int> by_object;
    for (unsigned i = 0; i < root->mNumChildren; ++i) {
      const aiNode* child = root->mChildren[i];
      Mat4 global = root_global * to_eigen(child->mTransformation);
      std::string name = child->mName.C_Str();
      if (child->mNumMeshes > 0) {
        // The mesh name is the object's index (see the comment at the top).
        const std::string& mesh_name = ai_.mMeshes[child->mMeshes[0]]->mName.C_Str();
        char* end = nullptr;
        unsigned long object = std::strtoul(mesh_name.c_str(), &end, 10);
        if (!mesh_name.empty() && *end == '\0' && object < objects.size()) name = objects[object];
      }
      auto found = by_object.find(name);
      int index;
      if (found != by_object.end() && child->mNumMeshes > 0) {
        index = found->second;
      } else {
        index = add_node(name, root_index);
        if (child->mNumMeshes > 0) by_object[name] = index;
      }
      attach_meshes(child, global, index);
      for (unsigned c = 0; c < child->mNumChildren; ++c) walk(child->mChildren[c], global, index);
    }
  }

  void make_parts() {
    const std::string stem = file_.stem().string();
    int unnamed = 0;
    std::size_t ignored_faces = 0;
    std::size_t ignored_meshes = 0;
    for (std::size_t i = 0; i < scene_.nodes.size(); ++i) {
      Node& node = scene_.nodes[i];
      Pending& p = pending_[i];
      Mesh mesh;
      for (const auto& [m, global] : p.meshes) {
        if (!(m->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) {
          ++ignored_meshes;
          ignored_faces += m->mNumFaces;
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
      auto [it, inserted] = seen.emplace(part.name, part.node);
      if (!inserted)
        fail(file_, "duplicate part name '" + part.name + "': " + scene_.nodes[it->second].path + " and " +
                        scene_.nodes[part.node].path);
    }
    if (scene_.parts.empty()) fail(file_, "the model has no triangles");
    if (ignored_faces > 0)
      scene_.warnings.push_back(located(file_, std::to_string(ignored_faces) +
                                                   " non-triangle primitives (points, lines) ignored"));
    (void)ignored_meshes;
    std::size_t orphans = ai_.mNumMeshes - used_meshes_.size();
    if (orphans > 0)
      scene_.warnings.push_back(located(file_, std::to_string(orphans) + " meshes not attached to any node ignored"));
  }

  const aiScene& ai_;
  std::filesystem::path file_;
  double scale_;
  Scene& scene_;
  std::vector<Pending> pending_;
  std::set<unsigned> used_meshes_;
};

}  // namespace

void load_model(const std::filesystem::path& model, double length_scale, Scene& scene) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(model, ec)) fail(model, "cannot open model file (missing or not a file)");
  {
    std::ifstream probe(model, std::ios::binary);
    if (!probe) fail(model, "cannot open model file");
    if (probe.peek() == std::ifstream::traits_type::eof()) fail(model, "cannot read model: the file is empty");
  }
  check_off_counts(model);
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
  Builder(*ai, model, length_scale, scene).build();
}

}  // namespace plancheck
