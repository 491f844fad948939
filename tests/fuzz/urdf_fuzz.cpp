// SPDX-License-Identifier: MIT
// URDF and SRDF: the input is the URDF's text, and after its first NUL byte
// (if any) the SRDF's. Beside them in scratch(): a package "pkg" (with its
// package.xml) holding an OBJ box, so package://pkg/box.obj, meshes/box.obj
// and file:// paths resolve to a real mesh (loaded through the isolated
// importer, src/scene/isolate.h). What is fuzzed: urdfdom and tinyxml2 behind our
// own checks (tree, joints, mimic, SRDF pairs), mesh lookup, primitives.
#include "src/base/error.h"
#include "src/scene/kinematics.h"
#include "src/scene/scene_loader.h"
#include "tests/fuzz/support.h"

#include <set>
#include <string>
#include <string_view>

using namespace plancheck;

namespace {

const std::filesystem::path& package() {
  static const std::filesystem::path dir = [] {
    const auto d = fuzz::scratch() / "pkg";
    std::filesystem::create_directories(d / "meshes");
    fuzz::write_file(d / "package.xml", "<package><name>pkg</name></package>\n");
    const std::string box =
        "o box\nv 0 0 0\nv 0.1 0 0\nv 0 0.1 0\nv 0.1 0.1 0\nv 0 0 0.1\nv 0.1 0 0.1\nv 0 0.1 0.1\nv 0.1 0.1 0.1\n"
        "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
    fuzz::write_file(d / "box.obj", box);
    fuzz::write_file(d / "meshes/box.obj", box);
    return d;
  }();
  return dir;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  const std::size_t nul = input.find('\0');
  const auto urdf = package() / "robot.urdf";
  fuzz::write_file(urdf, input.substr(0, nul));
  SceneOptions options;
  if (nul != std::string_view::npos) {
    options.srdf = package() / "robot.srdf";
    fuzz::write_file(options.srdf, input.substr(nul + 1));
  }
  try {
    const Scene scene = load_scene(urdf, options);
    fuzz::require(!scene.parts.empty(), "a loaded robot has parts");
    fuzz::require(scene.parameter_names.size() == scene.reference_parameters.size(), "one reference per parameter");
    fuzz::require(std::set<std::string>(scene.parameter_names.begin(), scene.parameter_names.end()).size() ==
                      scene.parameter_names.size(), "parameter names unique");
    for (const Part& part : scene.parts) {
      fuzz::require(!part.mesh.triangles.empty(), "a part has triangles");
      for (const auto& t : part.mesh.triangles)
        for (auto i : t) fuzz::require(i < part.mesh.vertices.size(), "triangle index in range");
      for (const Vec3& v : part.mesh.vertices) fuzz::require(v.allFinite(), "finite vertex");
    }
    for (const Action& a : scene.actions) {
      fuzz::require(a.node >= 0 && a.node < static_cast<int>(scene.nodes.size()), "action node in range");
      fuzz::require(a.first_parameter + a.parameter_count <= static_cast<int>(scene.parameter_names.size()),
                    "action parameters in range");
      fuzz::require(a.mimic < static_cast<int>(scene.actions.size()), "mimic master in range");
      fuzz::require(a.mimic < 0 || scene.actions[a.mimic].parameter_count == 1, "a mimic's master has a parameter");
      fuzz::require(!a.has_limits || a.lower <= a.upper, "limits ordered");
      fuzz::require(a.axis.allFinite() && std::abs(a.axis.norm() - 1) < 1e-12, "unit axis");
    }
    for (const auto& [a, b] : scene.checked_pairs)
      fuzz::require(a >= 0 && a < b && b < static_cast<int>(scene.parts.size()), "checked pair in range");
    std::vector<Affine> transforms;
    chain_transforms(scene, scene.reference_parameters, transforms);
    for (const Affine& t : transforms) fuzz::require(is_rigid(t), "a robot's chain is rigid");
  } catch (const InputError&) {
  }
  return 0;
}
