// SPDX-License-Identifier: MIT
#include "src/output/scene_summary.h"

#include "src/base/text.h"

#include "src/geometry/collision_model.h"
#include "src/base/parallel.h"
#include "src/scene/robot_loader.h"
#include "src/scene/terrain.h"

#include <algorithm>
#include <cstddef>
#include <cstdio>
#include <optional>
#include <set>
#include <utility>
#include <string>

namespace plancheck {
namespace {

// Every name and path below is printed through printable() (text.h): no
// name from a model or URDF can move the cursor or start a line.
std::string pr(const std::string& s) { return printable(s); }
std::string pr(const std::filesystem::path& p) { return printable(p.string()); }


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
  for (int a : chain) s += (s.empty() ? "" : " > ") + pr(scene.actions[a].name);
  return s;
}

// The robot block: what was read, the tessellation error of its primitives,
// and its links in contact at the zero pose as lines for an SRDF.
void print_robot(const Scene& scene, const std::vector<ReferenceContact>& contacts, std::ostream& out) {
  const RobotInfo& r = *scene.robot;
  out << "\nrobot: " << (r.name.empty() ? "<unnamed>" : pr(r.name)) << " from " << pr(r.urdf);
  if (!r.srdf.empty()) out << " and " << pr(r.srdf) << " (" << r.disabled.size() << " disable_collisions)";
  out << "\n  " << r.links << " links, " << r.joints << " joints; " << (r.visual ? "visual" : "collision")
      << " geometry; padding " << r.padding << " m, scale " << r.scale << "\n";
  double cylinder = 0, sphere = 0;
  cylinder_tessellation(1.0, 1.0, cylinder);
  sphere_tessellation(1.0, sphere);
  out << "  primitives: " << r.boxes << " boxes (exact), " << r.cylinders << " cylinders, " << r.spheres
      << " spheres; tessellated with " << kPrimitiveSegments
      << " segments to contain the true shape, never smaller: at most " << cylinder * 100
      << "% of a cylinder's radius and " << sphere * 100 << "% of a sphere's radius beyond it";
  if (r.cylinders + r.spheres > 0) out << " (" << r.largest_deviation << " m here)";
  out << "\n";
  std::set<std::string> links;
  for (const Node& n : scene.nodes)
    if (n.robot_link) links.insert(n.name);
  std::set<std::pair<std::string, std::string>> adjacent;
  for (const auto& [a, b] : r.adjacent) {
    adjacent.emplace(a, b);
    adjacent.emplace(b, a);
  }
  std::vector<std::string> lines;
  for (const ReferenceContact& c : contacts) {
    if (c.allowed || !links.count(c.a) || !links.count(c.b)) continue;
    lines.push_back("  <disable_collisions link1=\"" + pr(markup_escape(c.a)) + "\" link2=\"" + pr(markup_escape(c.b)) +
                    "\" reason=\"" +
                    (adjacent.count({c.a, c.b}) ? "Adjacent" : "Default") + "\"/>");
  }
  out << "links in contact at the zero pose, not yet allowed (" << lines.size() << "; for the SRDF):\n";
  for (const std::string& l : lines) out << l << "\n";
}

}  // namespace

std::vector<ReferenceContact> reference_contacts(const Scene& scene) {
  // Every pair that could ever be checked (allowed ones included: they are
  // what this list is for), posed at the reference pose, where every action
  // is the identity.
  std::vector<const Mesh*> meshes;
  std::vector<std::string> names;
  std::vector<int> chain;
  for (const Part& p : scene.parts) {
    meshes.push_back(&p.mesh);
    names.push_back(p.name);
    chain.push_back(p.chain_id);
  }
  Mesh terrain;
  if (scene.terrain && scene.terrain->collide) {
    terrain = dem_mesh(*scene.terrain->grid, scene.terrain->origin);
    meshes.push_back(&terrain);
    names.push_back("terrain");
    chain.push_back(-1);
  }
  std::vector<std::optional<CollisionModel>> models(meshes.size());
  parallel_for(meshes.size(), 0, 1, [&](std::size_t begin, std::size_t end, int) {
    for (std::size_t i = begin; i < end; ++i) models[i].emplace(*meshes[i]);
  });
  auto allowed = [&](std::size_t a, std::size_t b) {
    const bool ta = a == scene.parts.size(), tb = b == scene.parts.size();
    const auto& t = scene.terrain_allowed_parts;
    if (ta || tb) return std::find(t.begin(), t.end(), static_cast<int>(ta ? b : a)) != t.end();
    for (const CheckedPair& c : scene.checked_pairs)
      if ((c.a == static_cast<int>(a) && c.b == static_cast<int>(b)) || (c.a == static_cast<int>(b) && c.b == static_cast<int>(a)))
        return false;
    return true;
  };
  const Affine id = Affine::Identity();
  std::vector<ReferenceContact> out;
  for (std::size_t a = 0; a < meshes.size(); ++a)
    for (std::size_t b = a + 1; b < meshes.size(); ++b) {
      if (chain[a] < 0 && chain[b] < 0) continue;  // static-static: never checked
      if (chain[a] == chain[b]) continue;          // rigidly attached
      if (meshes[a]->triangles.empty() || meshes[b]->triangles.empty()) continue;
      CollideResult r;
      collide(*models[a], id, *models[b], id, CollideRequest{0}, r);
      if (r.collide) out.push_back({names[a], names[b], allowed(a, b)});
    }
  return out;
}

void print_scene_summary(const Scene& scene, std::ostream& out) {
  std::size_t triangles = 0;
  for (const Part& p : scene.parts) triangles += p.mesh.triangles.size();
  out << "scene: " << pr(scene.file) << "\n";
  out << "model: " << pr(scene.model_file) << " (" << scene.nodes.size() << " nodes, " << scene.parts.size()
      << " parts, " << triangles << " triangles)\n";
  out << "units: length " << scene.length_unit << ", angle " << scene.angle_unit << "\n";
  out << "safety margin: " << scene.safety_margin / scene.length_scale << " " << scene.length_unit << "\n";

  out << "\nparts (" << scene.parts.size() << "):\n";
  for (const Part& p : scene.parts) {
    out << "  " << pr(p.name) << "  " << p.mesh.triangles.size() << " triangles  "
        << (p.moving() ? "moving" : "static") << "  chain: " << chain_text(scene, p.chain) << "  ("
        << pr(scene.nodes[p.node].path) << ")\n";
  }

  out << "\nactions (" << scene.actions.size() << "):\n";
  for (const Action& a : scene.actions) {
    out << "  " << pr(a.name) << "  " << type_name(a) << "  node " << pr(a.node_name) << "  limits ";
    if (a.mimic >= 0) {
      out << "none; mimics " << pr(scene.actions[a.mimic].name) << " (" << a.multiplier << " x + " << a.offset
          << "), no column";
    } else if (a.has_limits) {
      const std::string unit_name = a.type == ActionType::kRotate ? scene.angle_unit
                                    : a.type == ActionType::kScale ? "" : scene.length_unit;
      out << "[" << a.lower << ", " << a.upper << "]" << (unit_name.empty() ? "" : " ") << unit_name;
    } else {
      out << "none";
    }
    out << "\n";
  }

  out << "\nchecked pairs (" << scene.checked_pairs.size() << "):\n";
  for (const CheckedPair& c : scene.checked_pairs)
    out << "  " << pr(scene.parts[c.a].name) << " - " << pr(scene.parts[c.b].name) << "\n";
  if (scene.terrain) {
    const Dem& g = *scene.terrain->grid;
    const DemSource& src = g.source;
    const auto e = window_extent(g);
    char line[320];  // numbers only: the path is printed on its own (any length)
    std::snprintf(line, sizeof line,
                  ", band %d, %d x %d pixels): read %s %d x %d pixels from column %d, row %d "
                  "(map x %.10g .. %.10g, y %.10g .. %.10g)\n",
                  src.band, src.raster_cols, src.raster_rows,
                  src.whole ? "the whole raster," : "the window within reach,", g.ncols, g.nrows, src.col_off + 1,
                  src.row_off + 1, e[0], e[2], e[1], e[3]);
    out << "terrain: " << pr(src.file) << " (" << pr(src.driver);
    out << line;
  }
  if (scene.terrain && scene.terrain->collide) {
    out << "terrain: checked against every moving part";
    if (!scene.terrain_allowed_parts.empty()) {
      out << " except";
      for (int p : scene.terrain_allowed_parts) out << " " << pr(scene.parts[p].name);
    }
    out << "\n";
  }

  const auto contacts = reference_contacts(scene);
  out << "\ncontacts at reference pose (" << contacts.size() << "):\n";
  for (const ReferenceContact& c : contacts)
    out << "  " << pr(c.a) << " - " << pr(c.b) << (c.allowed ? "  (allowed)" : "  (checked: a collision at the reference pose)")
        << "\n";

  if (scene.robot) print_robot(scene, contacts, out);
  for (const std::string& w : scene.warnings) out << "warning: " << pr(w) << "\n";
}

}  // namespace plancheck
