// SPDX-License-Identifier: MIT
// Scene JSON (plancheck-scene/1) -> Scene: strict reading (unknown keys and
// wrong types are errors naming the key path), geometry converted to SI
// (driving parameters and limits stay in plan units, as written), actions
// resolved against the model's node tree, chains and checked pairs derived.
#include "src/scene/scene_loader.h"

#include "src/base/error.h"
#include "src/base/files.h"
#include "src/base/text.h"
#include "src/scene/model_loader.h"
#include "src/scene/objects.h"
#include "src/scene/robot_loader.h"
#include "src/scene/terrain.h"
#include "src/scene/terrain_window.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace plancheck {
namespace {

using Json = nlohmann::json;

constexpr double kPi = 3.14159265358979323846;

// Reads one scene file's JSON with the file name and a key path at hand for
// every message, e.g. "scene.json: actions[2].pivot: expected 3 numbers".
class Reader {
 public:
  explicit Reader(std::filesystem::path file) : file_(std::move(file)) {}

  [[noreturn]] void error(const std::string& where, const std::string& what) const {
    fail(file_, where.empty() ? what : where + ": " + what);
  }

  void check_object(const Json& j, const std::string& where) const {
    if (!j.is_object()) error(where.empty() ? "top level" : where, "expected an object");
  }

  // Every key of j must be in `allowed`: a typo must not silently disable a check.
  void check_keys(const Json& j, const std::string& where, std::initializer_list<const char*> allowed) const {
    check_object(j, where);
    for (auto it = j.begin(); it != j.end(); ++it) {
      bool known = std::any_of(allowed.begin(), allowed.end(), [&](const char* k) { return it.key() == k; });
      if (!known) error(join(where, it.key()), "unknown key");
    }
  }

  static std::string join(const std::string& where, const std::string& key) {
    return where.empty() ? key : where + "." + key;
  }

  double number(const Json& j, const std::string& where) const {
    if (!j.is_number()) error(where, "expected a number");
    double v = j.get<double>();
    if (!std::isfinite(v)) error(where, "not a finite number");
    return v;
  }

  std::string string(const Json& j, const std::string& where) const {
    if (!j.is_string()) error(where, "expected a string");
    return j.get<std::string>();
  }

  bool boolean(const Json& j, const std::string& where) const {
    if (!j.is_boolean()) error(where, "expected true or false");
    return j.get<bool>();
  }

  Vec3 vec3(const Json& j, const std::string& where) const {
    if (!j.is_array() || j.size() != 3) error(where, "expected an array of 3 numbers");
    return Vec3(number(j[0], where + "[0]"), number(j[1], where + "[1]"), number(j[2], where + "[2]"));
  }

  const std::filesystem::path& file() const { return file_; }

 private:
  std::filesystem::path file_;
};

// nlohmann reports a byte offset; people want line and column.
void line_column(const std::string& text, std::size_t byte, long& line, long& column) {
  line = true;
  column = true;
  std::size_t end = std::min(byte > 0 ? byte - 1 : 0, text.size());
  for (std::size_t i = 0; i < end; ++i) {
    if (text[i] == '\n') {
      ++line;
      column = true;
    } else {
      ++column;
    }
  }
}

Json parse_json(const std::string& text, const std::filesystem::path& file) {
  // Duplicate keys: nlohmann keeps the last one silently; a repeated key is as
  // likely a mistake as an unknown one.
  std::vector<std::set<std::string>> open_objects;
  std::string duplicate;
  auto callback = [&](int, Json::parse_event_t event, Json& parsed) {
    if (event == Json::parse_event_t::object_start) {
      open_objects.emplace_back();
    } else if (event == Json::parse_event_t::object_end) {
      if (!open_objects.empty()) open_objects.pop_back();
    } else if (event == Json::parse_event_t::key && !open_objects.empty()) {
      if (!open_objects.back().insert(parsed.get<std::string>()).second && duplicate.empty())
        duplicate = parsed.get<std::string>();
    }
    return true;
  };
  Json j;
  try {
    j = Json::parse(text, callback);
  } catch (const Json::parse_error& e) {
    long line = 0, column = 0;
    line_column(text, e.byte, line, column);
    std::string reason = e.what();
    // Keep nlohmann's reason, drop its own "[json.exception...] parse error at line L, column C: " prefix.
    std::size_t colon = reason.find(": ");
    if (colon != std::string::npos) reason = reason.substr(colon + 2);
    // nor the text it last read: the file may hold what must not reach a log.
    const std::size_t echo = reason.find("; last read:");
    if (echo != std::string::npos) reason.erase(echo);
    fail(file, "invalid JSON: " + reason, line, column);
  } catch (const Json::out_of_range& e) {
    // A number beyond double range ("1e999") stops the parser without a
    // position; its text, quoted in the message, is found in the file instead.
    const std::string what = e.what();
    const std::size_t open = what.find('\''), close = what.rfind('\'');
    long line = 0, column = 0;
    if (open != std::string::npos && close > open) {
      const std::size_t at = text.find(what.substr(open + 1, close - open - 1));
      if (at != std::string::npos) line_column(text, at + 1, line, column);
    }
    fail(file, "number out of range: " + (open == std::string::npos ? what : what.substr(open)) +
                   " is not a finite number", line, column);
  }
  if (!duplicate.empty()) fail(file, duplicate + ": key given twice");
  return j;
}

double length_scale_of(const Reader& r, const std::string& unit) {
  if (unit == "m") return 1.0;
  if (unit == "cm") return 0.01;
  if (unit == "mm") return 0.001;
  r.error("length_unit", "unknown unit '" + unit + "' (expected m, cm or mm)");
}

double angle_scale_of(const Reader& r, const std::string& unit) {
  if (unit == "deg") return kPi / 180.0;
  if (unit == "rad") return 1.0;
  r.error("angle_unit", "unknown unit '" + unit + "' (expected deg or rad)");
}

// The node named `name`: exactly one node may carry it.
int find_node(const Reader& r, const Scene& scene, const std::string& name, const std::string& where) {
  int found = -1;
  for (std::size_t i = 0; i < scene.nodes.size(); ++i) {
    if (scene.nodes[i].name != name) continue;
    if (found >= 0)
      r.error(where, "node name '" + name + "' is not unique: " + scene.nodes[found].path + " and " +
                         scene.nodes[i].path);
    found = static_cast<int>(i);
  }
  if (found < 0) r.error(where, "node '" + name + "' not found in " + scene.model_file.filename().string());
  return found;
}

// The unit vector along a finite direction given at any scale. Dividing by
// the largest |component| first keeps the norm free of underflow (axes like
// [0, 0, 1e-300], whose squared norm is 0, or 1e-160, whose squared norm is
// subnormal and inexact) and of overflow ([0, 0, 1e300], whose norm is inf
// and would normalise to the zero vector). Only an all-zero vector is refused.
Vec3 unit_direction(const Reader& r, const Vec3& v, const std::string& field, const char* message) {
  const double largest = v.cwiseAbs().maxCoeff();
  if (!(largest > 0.0)) r.error(field, message);
  return (v / largest).normalized();
}

int kind_of(ActionType t) {  // translate with and without axis are one kind
  return t == ActionType::kRotate ? 0 : t == ActionType::kScale ? 2 : 1;
}

void read_actions(const Reader& r, const Json& list, Scene& scene) {
  if (!list.is_array()) r.error("actions", "expected an array");
  std::set<std::string> names;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string where = "actions[" + std::to_string(i) + "]";
    const Json& j = list[i];
    r.check_keys(j, where, {"name", "node", "type", "pivot", "axis", "fixed_point", "limits"});
    for (const char* key : {"name", "node", "type"})
      if (!j.contains(key)) r.error(where + "." + key, "missing");
    Action a;
    a.name = r.string(j["name"], where + ".name");
    if (a.name.empty()) r.error(where + ".name", "empty name");
    if (a.name == "time") r.error(where + ".name", "'time' is reserved for the plan's time column");
    if (!names.insert(a.name).second) r.error(where + ".name", "two actions named '" + a.name + "'");
    a.node_name = r.string(j["node"], where + ".node");
    a.node = find_node(r, scene, a.node_name, where + ".node");
    const std::string type = r.string(j["type"], where + ".type");
    auto require = [&](const char* key) {
      if (!j.contains(key)) r.error(where + "." + key, "missing (needed by a " + type + " action)");
    };
    auto forbid = [&](const char* key) {
      if (j.contains(key)) r.error(where + "." + key, "not allowed on a " + type + " action");
    };
    auto unit_axis = [&]() {
      return unit_direction(r, r.vec3(j["axis"], where + ".axis"), where + ".axis", "zero-length axis");
    };
    if (type == "rotate") {
      require("pivot");
      require("axis");
      forbid("fixed_point");
      a.type = ActionType::kRotate;
      a.pivot = r.vec3(j["pivot"], where + ".pivot") * scene.length_scale;
      a.axis = unit_axis();
      a.unit_to_si = scene.angle_scale;
      a.whole_turn = scene.angle_unit == "deg" ? 360.0 : 0.0;
    } else if (type == "translate") {
      forbid("pivot");
      forbid("fixed_point");
      if (j.contains("axis")) {
        a.type = ActionType::kTranslateAxis;
        a.axis = unit_axis();
      } else {
        a.type = ActionType::kTranslateFree;
        a.parameter_count = 3;
      }
      a.unit_to_si = scene.length_scale;
    } else if (type == "scale") {
      require("fixed_point");
      forbid("pivot");
      forbid("axis");
      a.type = ActionType::kScale;
      a.fixed_point = r.vec3(j["fixed_point"], where + ".fixed_point") * scene.length_scale;
      a.parameter_count = 3;  // scale factors have no unit: unit_to_si stays 1
    } else {
      r.error(where + ".type", "unknown action type '" + type + "' (expected rotate, translate or scale)");
    }
    if (j.contains("limits")) {
      const Json& l = j["limits"];
      if (!l.is_array() || l.size() != 2) r.error(where + ".limits", "expected [lower, upper]");
      double lower = r.number(l[0], where + ".limits[0]");
      double upper = r.number(l[1], where + ".limits[1]");
      if (lower > upper) r.error(where + ".limits", "lower limit is above the upper limit");
      if (a.type == ActionType::kScale && lower <= 0.0)
        r.error(where + ".limits", "scale factors must be positive");
      a.has_limits = true;
      a.lower = lower;  // as written: limits compare with the written values
      a.upper = upper;
    }
    Node& node = scene.nodes[a.node];
    for (int other : node.actions) {
      if (kind_of(scene.actions[other].type) == kind_of(a.type))
        r.error(where + ".node", "node '" + a.node_name + "' already carries a " + type + " action ('" +
                                     scene.actions[other].name + "')");
    }
    a.first_parameter = static_cast<int>(scene.parameter_names.size());
    if (a.parameter_count == 1) {
      scene.parameter_names.push_back(a.name);
      scene.reference_parameters.push_back(0.0);
    } else {
      const double reference = a.type == ActionType::kScale ? 1.0 : 0.0;
      for (const char* axis : {".x", ".y", ".z"}) {
        scene.parameter_names.push_back(a.name + axis);
        scene.reference_parameters.push_back(reference);
      }
    }
    node.actions.push_back(static_cast<int>(scene.actions.size()));
    scene.actions.push_back(std::move(a));
  }
  // "A.x" of a free translation must not also be the name of another action.
  std::set<std::string> columns;
  for (const std::string& name : scene.parameter_names)
    if (!columns.insert(name).second) r.error("actions", "two driving parameters named '" + name + "'");
}

// Chains: the actions of a part's node and its ancestors, root first. Within
// one node carrying several actions (of different kinds) they keep the order
// of the scene file, so the first listed is applied last (outermost).
void resolve_chains(Scene& scene) {
  scene.chains.clear();
  for (std::size_t p = 0; p < scene.parts.size(); ++p) {
    Part& part = scene.parts[p];
    std::vector<int> path;
    for (int n = part.node; n >= 0; n = scene.nodes[n].parent) path.push_back(n);
    part.chain.clear();
    for (auto it = path.rbegin(); it != path.rend(); ++it)
      for (int a : scene.nodes[*it].actions) part.chain.push_back(a);
    auto found = std::find(scene.chains.begin(), scene.chains.end(), part.chain);
    if (found == scene.chains.end()) {
      part.chain_id = static_cast<int>(scene.chains.size());
      scene.chains.push_back(part.chain);
    } else {
      part.chain_id = static_cast<int>(found - scene.chains.begin());
    }
  }
}

std::vector<int> subtree_parts(const Scene& scene, int node) {
  std::vector<int> out;
  std::vector<int> todo{node};
  while (!todo.empty()) {
    int n = todo.back();
    todo.pop_back();
    if (scene.nodes[n].part >= 0) out.push_back(scene.nodes[n].part);
    for (int c : scene.nodes[n].children) todo.push_back(c);
  }
  return out;
}

constexpr const char* kTerrainName = "terrain";

// The parts an allowed_collisions name stands for: a node's subtree, or
// exactly one link when it names a robot link (as an SRDF does).
std::vector<int> named_parts(const Scene& scene, int node) {
  if (scene.nodes[node].robot_link)
    return scene.nodes[node].part >= 0 ? std::vector<int>{scene.nodes[node].part} : std::vector<int>{};
  return subtree_parts(scene, node);
}

// allowed_collisions (and the SRDF's part pairs) -> scene.allowed, then the
// checked pairs derived from it (derive_pairs).
void read_allowed(const Reader& r, const Json* allowed_json, Scene& scene,
                  const std::vector<std::pair<int, int>>& robot_allowed = {}) {
  scene.allowed.parts = robot_allowed;
  scene.allowed.nodes.clear();
  if (allowed_json != nullptr) {
    if (!allowed_json->is_array()) r.error("allowed_collisions", "expected an array of [node, node] pairs");
    for (std::size_t i = 0; i < allowed_json->size(); ++i) {
      const std::string where = "allowed_collisions[" + std::to_string(i) + "]";
      const Json& pair = (*allowed_json)[i];
      if (!pair.is_array() || pair.size() != 2) r.error(where, "expected a pair [node, node]");
      std::string names[2] = {r.string(pair[0], where + "[0]"), r.string(pair[1], where + "[1]")};
      int nodes[2];
      for (int k = 0; k < 2; ++k) {
        const bool is_terrain = scene.terrain.has_value() && names[k] == kTerrainName;
        nodes[k] = is_terrain ? -1 : find_node(r, scene, names[k], where + "[" + std::to_string(k) + "]");
      }
      if (nodes[0] < 0 && nodes[1] < 0) r.error(where, "the terrain cannot be paired with itself");
      scene.allowed.nodes.emplace_back(nodes[0], nodes[1]);
    }
  }
  derive_pairs(scene);
}

}  // namespace

void derive_pairs(Scene& scene) {
  resolve_chains(scene);
  const std::size_t n = scene.parts.size();
  std::vector<bool> allowed(n * n, false);  // symmetric, one bit per part pair
  auto allow = [&](int a, int b) {
    allowed[static_cast<std::size_t>(a) * n + static_cast<std::size_t>(b)] = true;
    allowed[static_cast<std::size_t>(b) * n + static_cast<std::size_t>(a)] = true;
  };
  for (const auto& [a, b] : scene.allowed.parts) allow(a, b);
  std::set<int> terrain_allowed;
  for (const auto& [na, nb] : scene.allowed.nodes) {
    if (na < 0 || nb < 0) {
      for (int p : named_parts(scene, na < 0 ? nb : na)) terrain_allowed.insert(p);
      continue;
    }
    const std::vector<int> sa = named_parts(scene, na), sb = named_parts(scene, nb);
    for (int a : sa)
      for (int b : sb) allow(a, b);
  }
  scene.terrain_allowed_parts.assign(terrain_allowed.begin(), terrain_allowed.end());
  scene.checked_pairs.clear();
  for (std::size_t a = 0; a < n; ++a) {
    for (std::size_t b = a + 1; b < n; ++b) {
      const Part& pa = scene.parts[a];
      const Part& pb = scene.parts[b];
      if (!pa.moving() && !pb.moving()) continue;
      if (pa.chain_id == pb.chain_id) continue;  // same chain: never move relative to each other
      if (allowed[a * n + b]) continue;
      scene.checked_pairs.push_back({static_cast<int>(a), static_cast<int>(b)});
    }
  }
}

namespace {

int find_part_or_fail(const Reader& r, const Scene& scene, const std::string& name, const std::string& where) {
  int p = scene.find_part(name);
  if (p < 0) r.error(where, "part '" + name + "' not found in " + scene.model_file.filename().string());
  return p;
}

void read_terrain(const Reader& r, const Json& j, Scene& scene) {
  r.check_keys(j, "terrain", {"dem", "origin", "map_origin", "band", "collide"});
  if (!j.contains("dem")) r.error("terrain.dem", "missing");
  TerrainConfig t;
  t.dem = r.file().parent_path() / r.string(j["dem"], "terrain.dem");
  if (j.contains("origin") && j.contains("map_origin"))
    r.error("terrain.map_origin", "give origin or map_origin, not both");
  if (j.contains("origin")) t.origin = r.vec3(j["origin"], "terrain.origin") * scene.length_scale;
  if (j.contains("map_origin")) t.map_origin = r.vec3(j["map_origin"], "terrain.map_origin");
  if (j.contains("band")) {
    const double b = r.number(j["band"], "terrain.band");
    if (!(b >= 1 && b <= 1e6 && b == std::floor(b))) r.error("terrain.band", "must be a whole number from 1");
    t.band = static_cast<int>(b);
  }
  if (j.contains("collide")) t.collide = r.boolean(j["collide"], "terrain.collide");
  std::error_code ec;
  if (!std::filesystem::exists(t.dem, ec)) r.error("terrain.dem", "cannot open " + t.dem.string());
  if (!std::filesystem::is_regular_file(t.dem, ec))
    r.error("terrain.dem", t.dem.string() + " is not a regular file (a directory, device or FIFO cannot be a DEM)");
  scene.terrain = t;  // the grid itself is read once the scene file is checked (load_scene)
}

double positive(const Reader& r, const Json& j, const std::string& where) {
  double v = r.number(j, where);
  if (!(v > 0.0)) r.error(where, "must be positive");
  return v;
}

void read_scoop(const Reader& r, const Json& j, Scene& scene) {
  r.check_keys(j, "scoop",
               {"part", "bottom_point", "width", "template", "model", "capacity", "bulk_density", "repose_angle"});
  if (!scene.terrain) r.error("scoop", "a scoop needs a terrain block");
  for (const char* key : {"part", "bottom_point", "width"})
    if (!j.contains(key)) r.error(std::string("scoop.") + key, "missing");
  const double s = scene.length_scale;
  ScoopConfig c;
  c.part = r.string(j["part"], "scoop.part");
  c.part_index = find_part_or_fail(r, scene, c.part, "scoop.part");
  c.bottom_point = r.vec3(j["bottom_point"], "scoop.bottom_point") * s;
  c.width = positive(r, j["width"], "scoop.width") * s;
  if (j.contains("template")) {
    const Json& t = j["template"];
    r.check_keys(t, "scoop.template", {"pit", "rim", "rim_start"});
    if (t.contains("pit")) c.templ.pit = r.number(t["pit"], "scoop.template.pit");
    if (t.contains("rim")) c.templ.rim = r.number(t["rim"], "scoop.template.rim");
    if (t.contains("rim_start")) c.templ.rim_start = r.number(t["rim_start"], "scoop.template.rim_start");
  }
  if (j.contains("model")) {
    c.model = r.string(j["model"], "scoop.model");
    if (c.model != "template" && c.model != "swept")
      r.error("scoop.model", "unknown model '" + c.model + "' (expected template or swept)");
  }
  if (j.contains("capacity")) {
    double v = r.number(j["capacity"], "scoop.capacity");
    if (v < 0.0) r.error("scoop.capacity", "must not be negative");
    c.capacity = v * s * s * s;
  }
  if (j.contains("bulk_density")) c.bulk_density = positive(r, j["bulk_density"], "scoop.bulk_density");
  if (j.contains("repose_angle")) {
    double v = r.number(j["repose_angle"], "scoop.repose_angle") * scene.angle_scale;
    if (!(v > 0.0 && v < kPi / 2)) r.error("scoop.repose_angle", "must lie strictly between 0 and 90 degrees");
    c.repose_angle = v;
  }
  scene.scoop = c;
}

void read_probes(const Reader& r, const Json& list, Scene& scene) {
  if (!list.is_array()) r.error("probes", "expected an array");
  std::set<std::string> names;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string where = "probes[" + std::to_string(i) + "]";
    const Json& j = list[i];
    r.check_keys(j, where, {"name", "part", "origin", "direction", "fan", "max_range"});
    for (const char* key : {"name", "part", "origin", "direction", "max_range"})
      if (!j.contains(key)) r.error(where + "." + key, "missing");
    ProbeConfig p;
    p.name = r.string(j["name"], where + ".name");
    if (!names.insert(p.name).second) r.error(where + ".name", "two probes named '" + p.name + "'");
    p.part = r.string(j["part"], where + ".part");
    p.part_index = find_part_or_fail(r, scene, p.part, where + ".part");
    p.origin = r.vec3(j["origin"], where + ".origin") * scene.length_scale;
    p.direction = unit_direction(r, r.vec3(j["direction"], where + ".direction"), where + ".direction",
                                 "zero-length direction");
    p.max_range = positive(r, j["max_range"], where + ".max_range") * scene.length_scale;
    if (j.contains("fan")) {
      const Json& f = j["fan"];
      r.check_keys(f, where + ".fan", {"count", "half_angle"});
      if (!f.contains("count")) r.error(where + ".fan.count", "missing");
      if (!f.contains("half_angle")) r.error(where + ".fan.half_angle", "missing");
      if (!f["count"].is_number_integer() || f["count"].get<long long>() < 1 ||
          f["count"].get<long long>() > 1000000)
        r.error(where + ".fan.count", "expected a whole number from 1 to 1000000");
      p.fan_count = static_cast<int>(f["count"].get<long long>());
      double half = r.number(f["half_angle"], where + ".fan.half_angle") * scene.angle_scale;
      if (half < 0.0 || half > kPi) r.error(where + ".fan.half_angle", "must lie between 0 and 180 degrees");
      p.fan_half_angle = half;
    }
    scene.probes.push_back(std::move(p));
  }
}

// The scene's `robot` block -> a RobotSpec (paths relative to the scene file).
RobotSpec read_robot(const Reader& r, const Json& j, const Scene& scene, const SceneOptions& options) {
  r.check_keys(j, "robot", {"urdf", "srdf", "packages", "geometry", "parent", "origin", "padding", "scale"});
  if (!j.contains("urdf")) r.error("robot.urdf", "missing");
  const std::filesystem::path folder = r.file().parent_path();
  RobotSpec spec;
  spec.urdf = folder / r.string(j["urdf"], "robot.urdf");
  if (j.contains("srdf")) spec.srdf = folder / r.string(j["srdf"], "robot.srdf");
  if (!options.srdf.empty()) r.error("robot.srdf", "--srdf is for a bare .urdf; a scene names its SRDF here");
  if (j.contains("packages")) {
    r.check_object(j["packages"], "robot.packages");
    for (auto it = j["packages"].begin(); it != j["packages"].end(); ++it)
      spec.packages[it.key()] = folder / r.string(it.value(), "robot.packages." + it.key());
  }
  for (const auto& [name, dir] : options.packages) spec.packages[name] = dir;
  if (j.contains("geometry")) {
    const std::string g = r.string(j["geometry"], "robot.geometry");
    if (g != "collision" && g != "visual") r.error("robot.geometry", "expected \"collision\" or \"visual\"");
    spec.visual = g == "visual";
  }
  if (j.contains("parent")) spec.parent_node = find_node(r, scene, r.string(j["parent"], "robot.parent"), "robot.parent");
  if (j.contains("origin")) {
    const Json& o = j["origin"];
    r.check_keys(o, "robot.origin", {"xyz", "rpy"});
    Vec3 xyz = Vec3::Zero(), rpy = Vec3::Zero();
    if (o.contains("xyz")) xyz = r.vec3(o["xyz"], "robot.origin.xyz");
    if (o.contains("rpy")) rpy = r.vec3(o["rpy"], "robot.origin.rpy");
    spec.origin = pose_of(xyz, rpy);
  }
  if (j.contains("padding")) {
    spec.padding = r.number(j["padding"], "robot.padding");
    if (spec.padding < 0) r.error("robot.padding", "must not be negative");
  }
  if (j.contains("scale")) spec.scale = positive(r, j["scale"], "robot.scale");
  return spec;
}

// The scene's `objects`: each a part (src/scene/objects.h), after the
// model, the robot and the actions, before allowed_collisions (which may
// name them) and the probes (which may be fixed to them or hit them).
void read_objects(const Reader& r, const Json& list, Scene& scene) {
  if (!list.is_array()) r.error("objects", "expected an array");
  if (list.size() > kMaxObjects) r.error("objects", "more than " + std::to_string(kMaxObjects) + " objects");
  std::map<std::filesystem::path, Mesh> files;  // mesh files read so far
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string where = "objects[" + std::to_string(i) + "]";
    const ObjectPlace at{r.file(), where};
    const Json& j = list[i];
    r.check_keys(j, where, {"name", "box", "cylinder", "sphere", "mesh", "scale", "pose", "parent"});
    if (!j.contains("name")) r.error(where + ".name", "missing");
    WorldObject o;
    o.name = r.string(j["name"], where + ".name");
    int shapes = 0;
    for (const char* key : {"box", "cylinder", "sphere", "mesh"}) shapes += j.contains(key) ? 1 : 0;
    if (shapes != 1)
      r.error(where, shapes == 0 ? "no shape (give one of box, cylinder, sphere, mesh)"
                                 : "more than one shape (give one of box, cylinder, sphere, mesh)");
    if (j.contains("scale") && !j.contains("mesh")) r.error(where + ".scale", "only a mesh has a scale");
    const double s = scene.length_scale;
    Mesh local;
    if (j.contains("box")) {
      o.shape = ObjectShape::kBox;
      local = box_object(r.vec3(j["box"], where + ".box") * s, at);
    } else if (j.contains("cylinder")) {
      o.shape = ObjectShape::kCylinder;
      const Json& c = j["cylinder"];
      r.check_keys(c, where + ".cylinder", {"radius", "length"});
      for (const char* key : {"radius", "length"})
        if (!c.contains(key)) r.error(where + ".cylinder." + key, "missing");
      local = cylinder_object(r.number(c["radius"], where + ".cylinder.radius") * s,
                              r.number(c["length"], where + ".cylinder.length") * s, at);
    } else if (j.contains("sphere")) {
      o.shape = ObjectShape::kSphere;
      local = sphere_object(r.number(j["sphere"], where + ".sphere") * s, at);
    } else {
      o.shape = ObjectShape::kMesh;
      const std::string file = r.string(j["mesh"], where + ".mesh");
      if (file.empty()) r.error(where + ".mesh", "empty path");
      o.mesh_file = r.file().parent_path() / file;
      const Vec3 scale = j.contains("scale") ? r.vec3(j["scale"], where + ".scale") : Vec3(1, 1, 1);
      // The file's own coordinates in length_unit, as the model's are.
      local = mesh_object(o.mesh_file, scale * s, scene.warnings, at, &files);
    }
    o.local = std::make_shared<const Mesh>(std::move(local));
    Vec3 xyz = Vec3::Zero(), rpy = Vec3::Zero();
    if (j.contains("pose")) {
      const Json& p = j["pose"];
      r.check_keys(p, where + ".pose", {"xyz", "rpy"});
      if (p.contains("xyz")) xyz = r.vec3(p["xyz"], where + ".pose.xyz") * s;
      if (p.contains("rpy")) rpy = r.vec3(p["rpy"], where + ".pose.rpy") * scene.angle_scale;
    }
    o.pose = pose_of(xyz, rpy);
    o.parent = j.contains("parent") ? object_parent(scene, r.string(j["parent"], where + ".parent"), at) : -1;
    add_object(scene, std::move(o), at);
  }
}

bool is_urdf(const std::filesystem::path& file) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext == ".urdf";
}

}  // namespace

namespace {

// Names from model and URDF files reach every report (JSON, CSV, pages):
// they must be UTF-8 text. The scene file's own names are (JSON is).
void check_names(const Scene& scene) {
  for (const Node& node : scene.nodes)
    if (!valid_utf8(node.name))
      fail(node.robot_link && scene.robot ? scene.robot->urdf : scene.model_file,
           "node '" + printable(node.path) + "': its name is not valid UTF-8 text");
  for (const Action& a : scene.actions)
    if (!valid_utf8(a.name))
      fail(scene.robot ? scene.robot->urdf : scene.file, "joint '" + printable(a.name) + "': its name is not valid UTF-8 text");
}

Scene load_scene_unguarded(const std::filesystem::path& scene_json, const SceneOptions& options);

}  // namespace

Scene load_scene(const std::filesystem::path& scene_json, const SceneOptions& options) {
  try {
    return load_scene_unguarded(scene_json, options);
  } catch (const std::bad_alloc&) {
    fail(scene_json, "out of memory while loading the scene (or its model, robot or terrain)");
  }
}

namespace {

Scene load_scene_unguarded(const std::filesystem::path& scene_json, const SceneOptions& options) {
  if (is_urdf(scene_json)) {
    // A robot alone: the URDF's own units, no model, no other blocks.
    Scene scene;
    scene.file = scene_json;
    scene.model_file = scene_json;
    scene.length_unit = "m";
    scene.angle_unit = "rad";
    scene.length_scale = 1.0;
    scene.angle_scale = 1.0;
    RobotSpec spec;
    spec.urdf = scene_json;
    spec.srdf = options.srdf;
    spec.packages = options.packages;
    const auto allowed = add_robot(spec, scene);
    if (scene.parts.empty()) fail(scene_json, "the robot has no geometry (no link has a collision element)");
    check_names(scene);
    read_allowed(Reader(scene_json), nullptr, scene, allowed);
    return scene;
  }
  if (!options.srdf.empty()) fail(scene_json, "--srdf is for a bare .urdf; a scene file names its SRDF in robot.srdf");
  return parse_scene(read_regular_file(scene_json, kMaxSceneFileBytes, "scene file"), scene_json, options);
}

}  // namespace

Scene parse_scene(const std::string& text, const std::filesystem::path& scene_json, const SceneOptions& options) {
  Reader r(scene_json);
  const Json root = parse_json(text, scene_json);
  r.check_keys(root, "",
               {"format", "model", "length_unit", "angle_unit", "actions", "allowed_collisions", "safety_margin",
                "terrain", "scoop", "probes", "robot", "objects"});
  if (!root.contains("format")) r.error("format", "missing (expected \"plancheck-scene/1\")");
  const std::string format = r.string(root["format"], "format");
  if (format != "plancheck-scene/1") r.error("format", "unsupported format '" + format + "' (expected plancheck-scene/1)");
  const bool has_robot = root.contains("robot");
  if (!root.contains("model") && !has_robot) r.error("model", "missing (a scene needs a model, a robot or both)");

  Scene scene;
  scene.file = scene_json;
  if (root.contains("length_unit")) scene.length_unit = r.string(root["length_unit"], "length_unit");
  if (root.contains("angle_unit")) scene.angle_unit = r.string(root["angle_unit"], "angle_unit");
  scene.length_scale = length_scale_of(r, scene.length_unit);
  scene.angle_scale = angle_scale_of(r, scene.angle_unit);
  if (has_robot && scene.length_unit != "m")
    r.error("length_unit", "must be m with a robot (URDF lengths are metres), not " + scene.length_unit);
  if (has_robot && scene.angle_unit != "rad")
    r.error("angle_unit", "must be rad with a robot (URDF angles are radians), not " + scene.angle_unit +
                              (root.contains("angle_unit") ? "" : " (the default)"));
  if (root.contains("safety_margin")) {
    double margin = r.number(root["safety_margin"], "safety_margin");
    if (margin < 0.0) r.error("safety_margin", "must not be negative");
    scene.safety_margin = margin * scene.length_scale;
  }
  // Optional blocks that do not need the model are read first so their
  // mistakes are reported before a possibly slow model load.
  if (root.contains("terrain")) read_terrain(r, root["terrain"], scene);

  if (root.contains("model")) {
    const std::string model = r.string(root["model"], "model");
    if (model.empty()) r.error("model", "empty path");
    scene.model_file = scene_json.parent_path() / model;
    load_model(scene.model_file, scene.length_scale, scene, {}, options.while_importing);
  }
  std::vector<std::pair<int, int>> robot_allowed;
  if (has_robot) {
    const RobotSpec spec = read_robot(r, root["robot"], scene, options);
    if (!root.contains("model")) scene.model_file = spec.urdf;
    robot_allowed = add_robot(spec, scene);
    if (scene.parts.empty()) r.error("robot", "the robot has no geometry and the scene no model");
  }

  if (scene.terrain && scene.terrain->collide && scene.find_part(kTerrainName) >= 0)
    r.error("terrain", "the model has a part named 'terrain', which clashes with the terrain block");
  check_names(scene);
  if (root.contains("actions")) read_actions(r, root["actions"], scene);
  if (root.contains("objects")) read_objects(r, root["objects"], scene);
  read_allowed(r, root.contains("allowed_collisions") ? &root["allowed_collisions"] : nullptr, scene, robot_allowed);
  if (root.contains("scoop")) read_scoop(r, root["scoop"], scene);
  if (root.contains("probes")) read_probes(r, root["probes"], scene);
  // The DEM is read once, here, after every check of the scene file itself,
  // so a scene's own errors are reported first; everything that needs the
  // terrain (checks, digging, probes, pages) starts from this grid, the
  // window of the raster the moving parts can reach.
  if (scene.terrain) load_terrain(scene);
  return scene;
}

}  // namespace plancheck
