// SPDX-License-Identifier: MIT
#include "src/scene_summary.h"

#include <cstddef>
#include <string>

namespace plancheck {
namespace {

const char* type_name(const Action& a) {
  switch (a.type) {
    case ActionType::kRotate: return "rotate";
    case ActionType::kTranslateAxis: return "translate (axis)";
    case ActionType::kTranslateFree: return "translate (x, y, z)";
    case ActionType::kScale: return "scale";
  }
  return "?";
}

std::string chain_text(const Scene& scene, const std::vector<int>& chain) {
  if (chain.empty()) return "-";
  std::string s;
  for (int a : chain) s += (s.empty() ? "" : " > ") + scene.actions[a].name;
  return s;
}

}  // namespace

void print_scene_summary(const Scene& scene, std::ostream& out) {
  std::size_t triangles = 0;
  for (const Part& p : scene.parts) triangles += p.mesh.triangles.size();
  out << "scene: " << scene.file.string() << "\n";
  out << "model: " << scene.model_file.string() << " (" << scene.nodes.size() << " nodes, " << scene.parts.size()
      << " parts, " << triangles << " triangles)\n";
  out << "units: length " << scene.length_unit << ", angle " << scene.angle_unit << "\n";
  out << "safety margin: " << scene.safety_margin / scene.length_scale << " " << scene.length_unit << "\n";

  out << "\nparts (" << scene.parts.size() << "):\n";
  for (const Part& p : scene.parts) {
    out << "  " << p.name << "  " << p.mesh.triangles.size() << " triangles  "
        << (p.moving() ? "moving" : "static") << "  chain: " << chain_text(scene, p.chain) << "  ("
        << scene.nodes[p.node].path << ")\n";
  }

  out << "\nactions (" << scene.actions.size() << "):\n";
  for (const Action& a : scene.actions) {
    out << "  " << a.name << "  " << type_name(a) << "  node " << a.node_name << "  limits ";
    if (a.has_limits) {
      const double unit = a.type == ActionType::kRotate ? scene.angle_scale
                          : a.type == ActionType::kScale ? 1.0 : scene.length_scale;
      const std::string unit_name = a.type == ActionType::kRotate ? scene.angle_unit
                                    : a.type == ActionType::kScale ? "" : scene.length_unit;
      out << "[" << a.lower / unit << ", " << a.upper / unit << "]" << (unit_name.empty() ? "" : " ") << unit_name;
    } else {
      out << "none";
    }
    out << "\n";
  }

  out << "\nchecked pairs (" << scene.checked_pairs.size() << "):\n";
  for (const CheckedPair& c : scene.checked_pairs)
    out << "  " << scene.parts[c.a].name << " - " << scene.parts[c.b].name << "\n";
  if (scene.terrain && scene.terrain->collide) {
    out << "terrain: checked against every moving part";
    if (!scene.terrain_allowed_parts.empty()) {
      out << " except";
      for (int p : scene.terrain_allowed_parts) out << " " << scene.parts[p].name;
    }
    out << "\n";
  }

  // HOOK: contacts at the reference pose need the collision models
  // (src/collision_model.h, another area); the integrator replaces this line
  // with a collide() over all part pairs at scene.reference_parameters.
  out << "\ncontacts at reference pose: (not yet computed)\n";

  for (const std::string& w : scene.warnings) out << "warning: " << w << "\n";
}

}  // namespace plancheck
