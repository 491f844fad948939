// SPDX-License-Identifier: MIT
// Model files through assimp and our own 3ds chunk reader and OFF guard. The
// first byte picks the format (the file name's extension, which is what
// assimp and our readers go by); the rest is the file. assimp runs in its
// child process (src/scene/isolate.h), so its own crashes and hangs end as
// InputErrors; what is fuzzed here is that containment, our guards ahead of
// assimp and our checks of what the child hands back. The child's time limit
// stays under libFuzzer's -timeout (10 s in `make fuzz`).
#include "src/base/error.h"
#include "src/scene/model_loader.h"
#include "tests/fuzz/support.h"

#include <iterator>
#include <string_view>

using namespace plancheck;

namespace {
const char* const kExtensions[] = {"3ds", "obj", "stl", "ply", "off", "gltf", "dae", "glb"};
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const char* ext = kExtensions[data[0] % std::size(kExtensions)];
  const auto file = fuzz::scratch() / (std::string("model.") + ext);
  fuzz::write_file(file, std::string_view(reinterpret_cast<const char*>(data + 1), size - 1));
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
