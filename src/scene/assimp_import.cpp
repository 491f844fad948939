// SPDX-License-Identifier: MIT
// assimp's import in a child process (src/scene/assimp_import.h): the guards
// ahead of assimp, the importer's settings, and the part tree's trip back
// from the child as checked flat bytes.
#include "src/scene/assimp_import.h"

#include "src/base/error.h"
#include "src/scene/isolate.h"
#include "src/scene/tds_reader.h"

#include <assimp/Importer.hpp>
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

namespace plancheck {
namespace {

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

// The import proper: assimp and the part tree builder, in whatever process
// runs it.
void import_model(const std::filesystem::path& model, const PartTreeBuilder& build, Scene& scene) {
  auto owner = std::make_unique<Assimp::Importer>();
  Assimp::Importer& importer = *owner;
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
  build(*ai, scene);
  // The importer's child ends with _exit: freeing assimp's scene (an
  // allocation per face) would be time spent for nothing on the way to the
  // result.
  if (in_isolated_child()) (void)owner.release();
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

void import_isolated(const std::filesystem::path& model, const IsolationLimits& limits,
                     const PartTreeBuilder& build, Scene& scene,
                     const std::function<void(const std::atomic<bool>& stop)>& meanwhile) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(model, ec)) fail(model, "cannot open model file (missing or not a file)");
  {
    std::ifstream probe(model, std::ios::binary);
    if (!probe) fail(model, "cannot open model file");
    if (probe.peek() == std::ifstream::traits_type::eof()) fail(model, "cannot read model: the file is empty");
  }
  check_off_counts(model);
  check_ply_header(model);
  check_3ds_tracks(model);
  std::string packed;
  try {
    packed = run_isolated(
        [&] {
          Scene imported;
          import_model(model, build, imported);
          return pack(imported);
        },
        limits, meanwhile);
  } catch (const IsolationError& e) {
    fail(model, std::string("cannot read model: the importer ") + e.what());
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    fail(model, std::string("cannot read model: ") + e.what());
  }
  unpack(packed, model, scene);
}

}  // namespace plancheck
