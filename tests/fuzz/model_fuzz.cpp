// SPDX-License-Identifier: MIT
// Model files through assimp and our own 3ds chunk reader and OFF guard. The
// first byte picks the format (the file name's extension, which is what
// assimp and our readers go by); the rest is the file. assimp runs in its
// child process (src/scene/isolate.h), so its own crashes and hangs end as
// InputErrors; what is fuzzed here is that containment, our guards ahead of
// assimp and our checks of what the child hands back. The child's time limit
// stays under libFuzzer's -timeout (10 s in `make fuzz`).
// A 3ds file the strict native reader takes (src/scene/tds_native.h) is
// loaded without assimp; for those the target also loads it through assimp
// and requires the same answer (outcome, nodes, parts, bits, warnings).
#include "src/base/error.h"
#include "src/scene/model_loader.h"
#include "src/scene/tds_native.h"
#include "tests/fuzz/support.h"

#include <cstring>
#include <iterator>
#include <string_view>
#include <vector>

using namespace plancheck;

namespace {
const char* const kExtensions[] = {"3ds", "obj", "stl", "ply", "off", "gltf", "dae", "glb"};

// load_model's outcome: "" and the scene, or the error message.
std::string load(const std::filesystem::path& file, bool native, Scene& scene) {
  IsolationLimits limits;
  limits.seconds = 5;
  limits.native_3ds = native;
  try {
    load_model(file, 1.0, scene, limits);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

bool same_bits(const Vec3& a, const Vec3& b) { return std::memcmp(a.data(), b.data(), 3 * sizeof(double)) == 0; }

void require_native_is_assimp(const std::filesystem::path& file) {
  Scene a, n;
  fuzz::require(load(file, false, a) == load(file, true, n), "native 3ds: same outcome as assimp");
  fuzz::require(a.nodes.size() == n.nodes.size() && a.parts.size() == n.parts.size() && a.warnings == n.warnings,
                "native 3ds: same nodes, parts, warnings as assimp");
  for (std::size_t i = 0; i < a.nodes.size(); ++i) {
    const Node &x = a.nodes[i], &y = n.nodes[i];
    fuzz::require(x.name == y.name && x.path == y.path && x.parent == y.parent && x.part == y.part &&
                      x.children == y.children && same_bits(x.origin, y.origin),
                  "native 3ds: same node as assimp");
  }
  for (std::size_t i = 0; i < a.parts.size(); ++i) {
    const Part &x = a.parts[i], &y = n.parts[i];
    bool same = x.name == y.name && x.node == y.node && x.mesh.triangles == y.mesh.triangles &&
                x.mesh.vertices.size() == y.mesh.vertices.size();
    for (std::size_t v = 0; same && v < x.mesh.vertices.size(); ++v)
      same = same_bits(x.mesh.vertices[v], y.mesh.vertices[v]);
    fuzz::require(same, "native 3ds: same part as assimp");
  }
}
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const char* ext = kExtensions[data[0] % std::size(kExtensions)];
  const auto file = fuzz::scratch() / (std::string("model.") + ext);
  fuzz::write_file(file, std::string_view(reinterpret_cast<const char*>(data + 1), size - 1));
  if (data[0] % std::size(kExtensions) == 0 && read_3ds_strict(std::vector<unsigned char>(data + 1, data + size)))
    require_native_is_assimp(file);
  try {
    Scene scene;
    IsolationLimits limits;
    limits.seconds = 5;
    load_model(file, 1.0, scene, limits);
    fuzz::require(!scene.parts.empty(), "a loaded model has parts");
    for (const Part& part : scene.parts) {
      fuzz::require(part.node >= 0 && part.node < static_cast<int>(scene.nodes.size()), "part node in range");
      fuzz::require(!part.mesh.triangles.empty(), "a part has triangles");
      for (const auto& t : part.mesh.triangles)
        for (auto i : t) fuzz::require(i < part.mesh.vertices.size(), "triangle index in range");
      for (const Vec3& v : part.mesh.vertices) fuzz::require(v.allFinite(), "finite vertex");
    }
  } catch (const InputError&) {
  }
  return 0;
}
