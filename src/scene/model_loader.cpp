// SPDX-License-Identifier: MIT
// Model file -> part tree: what assimp reads (src/scene/assimp_import.h, in a
// child process) and, for 3ds, the file's own drawn pose (src/scene/tds_reader.h)
// made into nodes and parts.
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
#include "src/scene/affine_fit.h"
#include "src/scene/assimp_import.h"
#include "src/scene/isolate.h"
#include "src/scene/tds_native.h"
#include "src/scene/tds_reader.h"

#include <assimp/material.h>
#include <assimp/quaternion.h>
#include <assimp/scene.h>

#include <Eigen/Core>

#include <algorithm>
#include <atomic>
#include <functional>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <map>
#include <memory>
#include <optional>
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

// The objects as drawn_object_meshes gives them (model_loader.h): points
// times `length_scale` in file order, faces in file order.
std::vector<Mesh> object_meshes(const std::vector<TdsObject>& objects, double length_scale) {
  std::vector<Mesh> meshes;
  meshes.reserve(objects.size());
  for (const TdsObject& object : objects) {
    Mesh mesh;
    mesh.vertices.reserve(object.points.size());
    for (const Vec3& point : object.points) mesh.vertices.push_back(point * length_scale);
    mesh.triangles.reserve(object.faces.size());
    for (const auto& f : object.faces) mesh.triangles.push_back({f[0], f[1], f[2]});
    meshes.push_back(std::move(mesh));
  }
  return meshes;
}

class Builder {
 public:
  Builder(const aiScene& ai, const std::filesystem::path& file, double scale, Scene& scene, bool unique_names)
      : ai_(ai), file_(file), scale_(scale), scene_(scene), unique_names_(unique_names) {}

  // The 3ds objects as already read (the native path), instead of reading
  // the file again; they must outlive this builder.
  void use_objects(const std::vector<TdsObject>& objects) { objects_ = &objects; }

  void build() {
    if (is_3ds(file_) && objects_ == nullptr) {
      own_objects_ = read_tds_objects(file_);
      objects_ = &own_objects_;
    }
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
      std::string name = object >= 0 ? (*objects_)[object].name : std::string(mesh->mName.C_Str());
      if (name.empty()) name = "unattached_mesh_" + std::to_string(m);
      auto [it, added] = by_name.try_emplace(name, 0);
      if (added) it->second = add_node(name, root_index, root_global);
      PendingMesh pm{mesh, root_global, nullptr, {}};
      if (object >= 0 && match_drawn_faces(*mesh, (*objects_)[object], pm.object_faces))
        pm.object = &(*objects_)[object];
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
      if (object >= 0 && (flat_3ds || (*objects_)[object].name == node->mName.C_Str()) &&
          match_drawn_faces(*pm.mesh, (*objects_)[object], pm.object_faces)) {
        pm.object = &(*objects_)[object];
      }
      pending_[target].meshes.push_back(std::move(pm));
    }
  }

  // assimp names each 3ds mesh with the decimal index of its object.
  int tds_object_of(const aiMesh& mesh) const {
    const char* name = mesh.mName.C_Str();
    char* end = nullptr;
    const unsigned long object = std::strtoul(name, &end, 10);
    if (*name == '\0' || *end != '\0' || objects_ == nullptr || object >= objects_->size()) return -1;
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
      // One affine map must take the drawn points to assimp's vertices
      // (least squares from 3x3 moments: an n x 4 QR here asked for some 130
      // bytes per vertex, on a big model mostly page faults).
      std::vector<Vec3> y(mesh.mNumVertices);
      Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
      for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
        y[v] = Vec3(mesh.mVertices[v].x, mesh.mVertices[v].y, mesh.mVertices[v].z);
        lo = lo.cwiseMin(y[v]);
        hi = hi.cwiseMax(y[v]);
      }
      const double size = std::max(1.0, (hi - lo).norm());
      const double residual = affine_fit_residual(drawn, y);
      ok = std::isfinite(residual) && residual <= 1e-4 * size;
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
        if (object >= 0) name = (*objects_)[object].name;
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
  std::vector<TdsObject> own_objects_;                // read here when not given
  const std::vector<TdsObject>* objects_ = nullptr;  // 3ds files only: the objects read
  std::set<unsigned> used_meshes_;
};

// assimp's scene of a 3ds file the strict reader took (tds_native.h), made
// here as assimp 5.2's 3ds importer makes it, for what Builder reads of it:
// node names, transforms, children and meshes; mesh names, material names,
// faces and vertices. The steps and their order are the importer's
// (3DSConverter.cpp: ConvertMeshes, AddNodeToGraph, GenerateNodeGraph;
// 3DSLoader.cpp: ApplyMasterScale), with assimp's own float types and
// inline math, so the numbers are its numbers. The post-processing the
// import asks for (Triangulate, SortByPType, ValidateDataStructure) leaves
// such a scene as it is: triangles only, every index in range.
class NativeScene {
 public:
  explicit NativeScene(const TdsFile& file) : scene_(std::make_unique<aiScene>()) {
    try {
      make(file);
    } catch (...) {
      release_indices();
      throw;
    }
  }

  ~NativeScene() { release_indices(); }
  NativeScene(const NativeScene&) = delete;
  NativeScene& operator=(const NativeScene&) = delete;

  const aiScene& scene() const { return *scene_; }

 private:
  void make(const TdsFile& file) {
    aiScene& s = *scene_;
    // ReplaceDefaultMaterial: no material in the file, so every face has
    // the generated default.
    s.mNumMaterials = 1;
    s.mMaterials = new aiMaterial*[1];
    s.mMaterials[0] = new aiMaterial();
    const aiString material("%%%DEFAULT");
    s.mMaterials[0]->AddProperty(&material, AI_MATKEY_NAME);
    // ConvertMeshes: one mesh per object (one material), three fresh
    // vertices per face in face order, named with the object's index.
    std::size_t corners = 0;
    for (const TdsObject& o : file.objects) corners += 3 * o.faces.size();
    indices_ = std::make_unique<unsigned[]>(corners);
    const bool keyframer = file.nodes.size() > 1;
    s.mNumMeshes = static_cast<unsigned>(file.objects.size());
    s.mMeshes = new aiMesh*[s.mNumMeshes]();
    unsigned* index = indices_.get();
    for (unsigned m = 0; m < s.mNumMeshes; ++m) {
      const TdsObject& o = file.objects[m];
      aiMesh* mesh = s.mMeshes[m] = new aiMesh();
      mesh->mName.Set(std::to_string(m));
      mesh->mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
      mesh->mMaterialIndex = 0;
      mesh->mNumFaces = static_cast<unsigned>(o.faces.size());
      mesh->mNumVertices = 3 * mesh->mNumFaces;
      mesh->mFaces = new aiFace[mesh->mNumFaces];
      mesh->mVertices = new aiVector3D[mesh->mNumVertices];
      for (unsigned f = 0, v = 0; f < mesh->mNumFaces; ++f) {
        aiFace& face = mesh->mFaces[f];
        face.mNumIndices = 3;
        face.mIndices = index;
        for (unsigned c = 0; c < 3; ++c, ++v) {
          const Vec3& p = o.points[o.faces[f][c]];
          mesh->mVertices[v] = aiVector3D(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
          *index++ = v;
        }
      }
    }
    // GenerateNodeGraph.
    if (keyframer) {
      s.mRootNode = node(file, 0, nullptr);
    } else {
      s.mRootNode = new aiNode("<3DSDummyRoot>");
      s.mRootNode->mNumChildren = s.mNumMeshes;
      s.mRootNode->mChildren = new aiNode*[s.mNumMeshes];
      for (unsigned m = 0; m < s.mNumMeshes; ++m) {
        aiNode* child = s.mRootNode->mChildren[m] = new aiNode("3DSMesh_" + std::to_string(m));
        child->mParent = s.mRootNode;
        child->mNumMeshes = 1;
        child->mMeshes = new unsigned[1]{m};
      }
    }
    s.mRootNode->mTransformation =
        aiMatrix4x4(1.f, 0.f, 0.f, 0.f, 0.f, 0.f, 1.f, 0.f, 0.f, -1.f, 0.f, 0.f, 0.f, 0.f, 0.f, 1.f) *
        s.mRootNode->mTransformation;
    if (std::strstr(s.mRootNode->mName.C_Str(), "UNNAMED") != nullptr) s.mRootNode->mName.Set("<3DSRoot>");
    // ApplyMasterScale.
    const float master = file.master_scale == 0.0f ? 1.0f : 1.0f / file.master_scale;
    s.mRootNode->mTransformation *=
        aiMatrix4x4(master, 0.f, 0.f, 0.f, 0.f, master, 0.f, 0.f, 0.f, 0.f, master, 0.f, 0.f, 0.f, 0.f, 1.f);
  }

  // The faces' indices live in one pool (indices_), not in an array per
  // face as aiFace's destructor expects: detached before the scene goes.
  void release_indices() {
    for (unsigned m = 0; scene_->mMeshes != nullptr && m < scene_->mNumMeshes; ++m) {
      aiMesh* mesh = scene_->mMeshes[m];
      for (unsigned f = 0; mesh != nullptr && mesh->mFaces != nullptr && f < mesh->mNumFaces; ++f)
        mesh->mFaces[f].mIndices = nullptr;
    }
  }

  // AddNodeToGraph: the node's meshes are those of the object of its name;
  // its transform the first rotation, scaling and position keys.
  aiNode* node(const TdsFile& file, int k, aiNode* parent) {
    const TdsKeyNode& in = file.nodes[static_cast<std::size_t>(k)];
    aiNode* out = new aiNode(in.name);
    out->mParent = parent;
    std::vector<unsigned> meshes;
    for (unsigned m = 0; m < file.objects.size(); ++m)
      if (file.objects[m].name == in.name) meshes.push_back(m);
    if (!meshes.empty()) {
      out->mNumMeshes = static_cast<unsigned>(meshes.size());
      out->mMeshes = new unsigned[meshes.size()];
      std::copy(meshes.begin(), meshes.end(), out->mMeshes);
      // The vertices of a mesh a node carries go back into the object's
      // local frame (once: the strict reader has every object carried by
      // exactly one node): the inverse of its axes matrix, x mirrored when
      // that matrix turns space inside out, the node's pivot taken off.
      const auto& a = file.axes[meshes[0]];
      aiMatrix4x4 axes;
      axes.a1 = a[0];
      axes.b1 = a[1];
      axes.c1 = a[2];
      axes.a2 = a[3];
      axes.b2 = a[4];
      axes.c2 = a[5];
      axes.a3 = a[6];
      axes.b3 = a[7];
      axes.c3 = a[8];
      axes.a4 = a[9];
      axes.b4 = a[10];
      axes.c4 = a[11];
      aiMatrix4x4 inverse = axes;
      inverse.Inverse();
      const aiVector3D pivot(in.pivot[0], in.pivot[1], in.pivot[2]);
      for (unsigned m : meshes) {
        aiMesh* mesh = scene_->mMeshes[m];
        aiVector3D* const end = mesh->mVertices + mesh->mNumVertices;
        for (aiVector3D* v = mesh->mVertices; v != end; ++v) *v = inverse * (*v);
        if (axes.Determinant() < 0.0f)
          for (aiVector3D* v = mesh->mVertices; v != end; ++v) v->x *= -1.f;
        if (pivot.x || pivot.y || pivot.z)
          for (aiVector3D* v = mesh->mVertices; v != end; ++v) *v -= pivot;
      }
    }
    if (in.has_rotation) {
      aiVector3D axis(in.axis[0], in.axis[1], in.axis[2]);
      if (!axis.x && !axis.y && !axis.z) axis.y = 1.f;
      aiQuaternion rotation(axis, in.angle);
      rotation.w *= -1.f;
      out->mTransformation = aiMatrix4x4(rotation.GetMatrix());
    }
    aiMatrix4x4& m = out->mTransformation;
    if (in.has_scale) {
      m.a1 *= in.scale[0];
      m.b1 *= in.scale[0];
      m.c1 *= in.scale[0];
      m.a2 *= in.scale[1];
      m.b2 *= in.scale[1];
      m.c2 *= in.scale[1];
      m.a3 *= in.scale[2];
      m.b3 *= in.scale[2];
      m.c3 *= in.scale[2];
    }
    if (in.has_position) {
      m.a4 += in.position[0];
      m.b4 += in.position[1];
      m.c4 += in.position[2];
    }
    out->mNumChildren = static_cast<unsigned>(in.children.size());
    out->mChildren = new aiNode*[in.children.size()];
    for (std::size_t c = 0; c < in.children.size(); ++c) out->mChildren[c] = node(file, in.children[c], out);
    return out;
  }

  std::unique_ptr<aiScene> scene_;
  std::unique_ptr<unsigned[]> indices_;
};

// The native path: a 3ds file the strict reader takes is built into its
// part tree here, in this process, from the scene assimp would have made;
// `meanwhile` runs beside it on a thread of its own, as it would beside
// assimp's child (run_isolated: stopped once the part tree is built, joined
// before this returns or throws, what it throws dropped).
bool import_native(const std::filesystem::path& model, double length_scale, Scene& scene, bool unique_names,
                   const WhileImporting& meanwhile) {
  if (!is_3ds(model)) return false;
  std::optional<TdsFile> file = read_3ds_strict(model);
  if (!file) return false;
  // The objects as read serve the part tree and `meanwhile` both (read on
  // both threads, changed on neither; `side` joins before they go).
  const std::vector<TdsObject>& objects = file->objects;
  const SideWork side(meanwhile ? [&](const std::atomic<bool>& stop) {
    meanwhile([&] { return object_meshes(objects, length_scale); }, stop);
  } : std::function<void(const std::atomic<bool>&)>());
  Scene imported;
  {
    const NativeScene ai(*file);
    Builder builder(ai.scene(), model, length_scale, imported, unique_names);
    builder.use_objects(objects);
    builder.build();
  }
  scene.nodes = std::move(imported.nodes);
  scene.parts = std::move(imported.parts);
  for (std::string& w : imported.warnings) scene.warnings.push_back(std::move(w));
  return true;
}

// load_model's and load_mesh's import: the part tree built in assimp's child
// process, checked on its way back.
void import_checked(const std::filesystem::path& model, double length_scale, Scene& scene,
                    const IsolationLimits& limits, bool unique_names, const WhileImporting& meanwhile = {}) {
  if (limits.native_3ds && import_native(model, length_scale, scene, unique_names, meanwhile)) return;
  import_isolated(
      model, limits,
      [&](const aiScene& ai, Scene& imported) { Builder(ai, model, length_scale, imported, unique_names).build(); },
      scene,
      meanwhile ? [&](const std::atomic<bool>& stop) {
        meanwhile([&] { return drawn_object_meshes(model, length_scale); }, stop);
      } : std::function<void(const std::atomic<bool>&)>());
}

}  // namespace

void load_model(const std::filesystem::path& model, double length_scale, Scene& scene,
                const IsolationLimits& limits, const WhileImporting& meanwhile) {
  import_checked(model, length_scale, scene, limits, true, meanwhile);
}

std::vector<Mesh> drawn_object_meshes(const std::filesystem::path& model, double length_scale) {
  if (!is_3ds(model)) return {};
  return object_meshes(read_tds_objects(model), length_scale);
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
