// SPDX-License-Identifier: MIT
// URDF (urdfdom) and SRDF (tinyxml2) -> nodes, parts and actions.
//
// The reference pose is the URDF's zero pose (every joint at 0). A link's
// node sits at its frame there; a movable joint becomes an action on its
// child link's node with the joint's axis and origin as they are at that
// pose, so the scene's composition rule A1(A2(...Ak(x))) is the URDF's own
// forward kinematics. A fixed joint adds no action: its child moves with its
// parent. Meshes go through the project's model loader (assimp in a child
// process, src/scene/isolate.h); box, cylinder and sphere are tessellated so that
// the triangles contain the true shape. MoveIt's link padding and scale are
// applied as geometric_shapes' scaleAndPadd does.
//
// Read and ignored: inertial, visual materials and colours, transmissions,
// gazebo and other extension elements, joint dynamics, safety controllers,
// calibration, the limits of mimic joints (MoveIt checks only active
// joints); SRDF groups, group states, end effectors, virtual and passive
// joints, disable_default_collisions and enable_collisions (ignoring these
// can only leave more pairs checked).
#include "src/scene/robot_loader.h"

#include "src/base/error.h"
#include "src/base/files.h"
#include "src/scene/model_loader.h"

#include <console_bridge/console.h>
#include <tinyxml2.h>
#include <urdf_parser/urdf_parser.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>
#include <mutex>
#include <set>
#include <sstream>

namespace plancheck {
namespace {

constexpr double kPi = 3.14159265358979323846;
// Rounding in the vertices of a tessellation (a few ulps of the radius) must
// not bring a face inside the true surface: the faces are pushed out by this
// relative margin as well.
constexpr double kRoundingMargin = 1e-12;

std::string read_file(const std::filesystem::path& file, const char* what) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) fail(file, std::string("cannot open ") + what + " (missing or not a file)");
  return read_regular_file(file, kMaxSceneFileBytes, what);
}

// An XML file through tinyxml2: a syntax error names its line.
void parse_xml(tinyxml2::XMLDocument& doc, const std::string& text, const std::filesystem::path& file) {
  if (doc.Parse(text.data(), text.size()) != tinyxml2::XML_SUCCESS) {
    std::string why = doc.ErrorStr() != nullptr ? doc.ErrorStr() : "malformed";
    fail(file, "XML does not parse: " + why, doc.ErrorLineNum());
  }
}

// urdfdom reports through console_bridge; its last error is the reason.
class Capture : public console_bridge::OutputHandler {
 public:
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_ERROR) errors.push_back(text);
  }
  std::vector<std::string> errors;
};

std::mutex urdfdom_mutex;  // console_bridge's handler is process-wide

urdf::ModelInterfaceSharedPtr parse_urdf(const std::string& text, const std::filesystem::path& file) {
  std::lock_guard lock(urdfdom_mutex);
  Capture capture;
  console_bridge::useOutputHandler(&capture);
  urdf::ModelInterfaceSharedPtr model;
  std::string thrown;
  try {
    model = urdf::parseURDF(text);
  } catch (const std::exception& e) {
    thrown = e.what();
  }
  console_bridge::restorePreviousOutputHandler();
  if (!model) {
    std::string why = !thrown.empty() ? thrown : capture.errors.empty() ? "not a valid URDF" : capture.errors.back();
    fail(file, "not a valid URDF: " + why);
  }
  return model;
}

Affine to_affine(const urdf::Pose& p) {
  Affine t = Affine::Identity();
  t.translate(Vec3(p.position.x, p.position.y, p.position.z));
  t.rotate(Eigen::Quaterniond(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z).normalized());
  return t;
}

bool finite(const urdf::Vector3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
bool finite(const urdf::Pose& p) {
  return finite(p.position) && std::isfinite(p.rotation.x) && std::isfinite(p.rotation.y) &&
         std::isfinite(p.rotation.z) && std::isfinite(p.rotation.w);
}

// Line numbers of the URDF's <link name=...> and <joint name=...> elements.
struct Lines {
  std::map<std::string, long> link, joint;
};

Lines element_lines(const tinyxml2::XMLDocument& doc) {
  Lines lines;
  const tinyxml2::XMLElement* robot = doc.FirstChildElement("robot");
  if (robot == nullptr) return lines;
  for (const auto* e = robot->FirstChildElement(); e != nullptr; e = e->NextSiblingElement()) {
    const char* name = e->Attribute("name");
    if (name == nullptr) continue;
    if (std::string(e->Name()) == "link") lines.link.emplace(name, e->GetLineNum());
    if (std::string(e->Name()) == "joint") lines.joint.emplace(name, e->GetLineNum());
  }
  return lines;
}

// %XX escapes of a URI path (a file name with spaces may be written %20).
std::string percent_decode(const std::string& s) {
  std::string out;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '%' && i + 2 < s.size() && std::isxdigit(static_cast<unsigned char>(s[i + 1])) &&
        std::isxdigit(static_cast<unsigned char>(s[i + 2]))) {
      out.push_back(static_cast<char>(std::strtol(s.substr(i + 1, 2).c_str(), nullptr, 16)));
      i += 2;
    } else {
      out.push_back(s[i]);
    }
  }
  return out;
}

// The <name> of a package.xml, or "" when it has none or does not parse.
std::string package_name(const std::filesystem::path& package_xml) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(package_xml, ec)) return {};
  std::string text;
  try {
    text = read_regular_file(package_xml, kMaxSceneFileBytes, "package.xml");
  } catch (const InputError&) {
    return {};  // not one to read: as if it had no name
  }
  tinyxml2::XMLDocument doc;
  if (doc.Parse(text.data(), text.size()) != tinyxml2::XML_SUCCESS) return {};
  const auto* package = doc.FirstChildElement("package");
  const auto* name = package != nullptr ? package->FirstChildElement("name") : nullptr;
  if (name == nullptr || name->GetText() == nullptr) return {};
  std::string n = name->GetText();
  n.erase(0, n.find_first_not_of(" \t\r\n"));
  n.erase(n.find_last_not_of(" \t\r\n") + 1);
  return n;
}

class Resolver {
 public:
  explicit Resolver(const RobotSpec& spec) : spec_(spec), folder_(spec.urdf.parent_path()) {}

  // The file a URDF mesh filename names; `where` names the element for messages.
  std::filesystem::path resolve(const std::string& uri, const std::string& where) {
    static const std::string kPackage = "package://", kFile = "file://";
    std::filesystem::path path;
    if (uri.compare(0, kPackage.size(), kPackage) == 0) {
      const std::string rest = uri.substr(kPackage.size());
      const std::size_t slash = rest.find('/');
      const std::string name = rest.substr(0, slash);
      if (name.empty() || slash == std::string::npos)
        fail(spec_.urdf, where + ": mesh '" + uri + "': expected package://NAME/path");
      // Inside the package's folder: a ".." step (written or percent-encoded)
      // would reach files the package does not hold.
      const std::filesystem::path inside = percent_decode(rest.substr(slash + 1));
      for (const auto& step : inside)
        if (step == "..")
          fail(spec_.urdf, where + ": mesh '" + uri + "': a '..' step leaves the package's folder");
      if (inside.is_absolute()) fail(spec_.urdf, where + ": mesh '" + uri + "': an absolute path after package://NAME/");
      path = package_folder(name, uri, where) / inside;
    } else if (uri.compare(0, kFile.size(), kFile) == 0) {
      path = percent_decode(uri.substr(kFile.size()));
      if (path.is_relative()) path = folder_ / path;
    } else if (uri.find("://") != std::string::npos) {
      fail(spec_.urdf, where + ": mesh '" + uri + "': only package://, file:// and plain paths are read");
    } else {
      path = uri;
      if (path.is_relative()) path = folder_ / path;
    }
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec))
      fail(spec_.urdf, where + ": mesh '" + uri + "' not found (looked for " + path.string() + ")");
    return path;
  }

 private:
  std::filesystem::path package_folder(const std::string& name, const std::string& uri, const std::string& where) {
    auto cached = found_.find(name);
    if (cached != found_.end()) return cached->second;
    std::filesystem::path folder;
    auto given = spec_.packages.find(name);
    if (given != spec_.packages.end()) {
      folder = given->second;
    } else if (const char* ros = std::getenv("ROS_PACKAGE_PATH"); ros != nullptr && *ros != '\0') {
      std::stringstream list(ros);
      std::string entry;
      while (folder.empty() && std::getline(list, entry, ':'))
        if (!entry.empty()) folder = search_tree(entry, name);
    }
    if (folder.empty()) {
      for (std::filesystem::path up = std::filesystem::absolute(folder_).lexically_normal(); !up.empty();
           up = up.parent_path()) {
        if (package_name(up / "package.xml") == name) {
          folder = up;
          break;
        }
        if (up == up.parent_path()) break;
      }
    }
    if (folder.empty())
      fail(spec_.urdf, where + ": mesh '" + uri + "': package '" + name +
                           "' not found (not in the package map, not under ROS_PACKAGE_PATH, and no package.xml "
                           "naming it in the URDF's folder or above)");
    found_.emplace(name, folder);
    return folder;
  }

  // A folder under `root` (itself included, a few levels deep, as rospack
  // crawls) whose package.xml names `name`.
  static std::filesystem::path search_tree(const std::filesystem::path& root, const std::string& name) {
    if (package_name(root / "package.xml") == name) return root;
    std::error_code ec;
    std::filesystem::recursive_directory_iterator it(
        root, std::filesystem::directory_options::skip_permission_denied, ec);
    for (; !ec && it != std::filesystem::recursive_directory_iterator(); it.increment(ec)) {
      if (it.depth() >= 4) {
        it.disable_recursion_pending();
        continue;
      }
      if (it->is_directory(ec) && package_name(it->path() / "package.xml") == name) return it->path();
    }
    return {};
  }

  const RobotSpec& spec_;
  std::filesystem::path folder_;
  std::map<std::string, std::filesystem::path> found_;
};

void append(Mesh& into, const Mesh& mesh, const Affine& t) {
  const auto base = static_cast<std::uint32_t>(into.vertices.size());
  for (const Vec3& v : mesh.vertices) into.vertices.push_back(t * v);
  for (const Tri& tri : mesh.triangles) into.triangles.push_back({base + tri[0], base + tri[1], base + tri[2]});
}

}  // namespace

Mesh box_tessellation(const Vec3& size) {
  const Vec3 h = size / 2;
  Mesh m;
  for (int i = 0; i < 8; ++i)
    m.vertices.emplace_back(i & 1 ? h.x() : -h.x(), i & 2 ? h.y() : -h.y(), i & 4 ? h.z() : -h.z());
  // Two outward triangles per face.
  m.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                 {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return m;
}

// A prism over a regular polygon of kPrimitiveSegments sides whose edges
// touch the circle of `radius` from outside (circumscribed): every point of
// the cylinder is inside, and the farthest the prism reaches beyond it is at
// the polygon's corners, radius * (1 / cos(pi / n) - 1).
Mesh cylinder_tessellation(double radius, double length, double& deviation) {
  const int n = kPrimitiveSegments;
  const double corner = radius / std::cos(kPi / n) * (1 + kRoundingMargin);
  deviation = corner - radius;
  Mesh m;
  const double z = length / 2;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * kPi * i / n;
    m.vertices.emplace_back(corner * std::cos(a), corner * std::sin(a), -z);
    m.vertices.emplace_back(corner * std::cos(a), corner * std::sin(a), z);
  }
  const auto bottom = static_cast<std::uint32_t>(m.vertices.size());
  m.vertices.emplace_back(0, 0, -z);
  m.vertices.emplace_back(0, 0, z);
  for (std::uint32_t i = 0; i < static_cast<std::uint32_t>(n); ++i) {
    const std::uint32_t j = (i + 1) % n;
    m.triangles.push_back({2 * i, 2 * j, 2 * i + 1});
    m.triangles.push_back({2 * j, 2 * j + 1, 2 * i + 1});
    m.triangles.push_back({bottom, 2 * j, 2 * i});
    m.triangles.push_back({bottom + 1, 2 * i + 1, 2 * j + 1});
  }
  return m;
}

// A latitude-longitude polyhedron (kPrimitiveSegments meridians, half as many
// bands) with every vertex on one sphere: it is convex (each band's quad is a
// planar isosceles trapezoid), so it contains the ball exactly when each face
// plane is at least `radius` from the centre. The unit polyhedron's nearest
// face plane is measured and the vertices are pushed out by radius over it.
Mesh sphere_tessellation(double radius, double& deviation) {
  const int n = kPrimitiveSegments, bands = n / 2;
  Mesh m;
  m.vertices.emplace_back(0, 0, -1);
  for (int b = 1; b < bands; ++b) {
    const double polar = kPi * b / bands;  // from the south pole
    for (int i = 0; i < n; ++i) {
      const double a = 2 * kPi * i / n;
      m.vertices.emplace_back(std::sin(polar) * std::cos(a), std::sin(polar) * std::sin(a), -std::cos(polar));
    }
  }
  m.vertices.emplace_back(0, 0, 1);
  const auto top = static_cast<std::uint32_t>(m.vertices.size() - 1);
  auto ring = [&](int b, int i) { return static_cast<std::uint32_t>(1 + (b - 1) * n + (i % n)); };
  for (int i = 0; i < n; ++i) {
    m.triangles.push_back({0, ring(1, i + 1), ring(1, i)});
    for (int b = 1; b + 1 < bands; ++b) {
      m.triangles.push_back({ring(b, i), ring(b, i + 1), ring(b + 1, i + 1)});
      m.triangles.push_back({ring(b, i), ring(b + 1, i + 1), ring(b + 1, i)});
    }
    m.triangles.push_back({ring(bands - 1, i), ring(bands - 1, i + 1), top});
  }
  double nearest = 1.0;
  for (const Tri& t : m.triangles) {
    const Vec3 normal = (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]).normalized();
    nearest = std::min(nearest, std::abs(normal.dot(m.vertices[t[0]])));
  }
  const double reach = radius / nearest * (1 + kRoundingMargin);
  for (Vec3& v : m.vertices) v *= reach;
  deviation = reach - radius;
  return m;
}

Mesh scale_and_pad(const Mesh& mesh, double scale, double padding) {
  // Identical vertices merged, as geometric_shapes' createMeshFromVertices does.
  std::map<std::array<double, 3>, std::uint32_t> index;
  Mesh out;
  std::vector<std::uint32_t> remap(mesh.vertices.size());
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    const Vec3& v = mesh.vertices[i];
    auto [it, added] = index.try_emplace({v.x(), v.y(), v.z()}, static_cast<std::uint32_t>(out.vertices.size()));
    if (added) out.vertices.push_back(v);
    remap[i] = it->second;
  }
  for (const Tri& t : mesh.triangles) out.triangles.push_back({remap[t[0]], remap[t[1]], remap[t[2]]});
  Vec3 centre = Vec3::Zero();
  for (const Vec3& v : out.vertices) centre += v;
  centre /= static_cast<double>(std::max<std::size_t>(1, out.vertices.size()));
  std::vector<Vec3> normal(out.vertices.size(), Vec3::Zero());
  for (const Tri& t : out.triangles) {
    const Vec3& a = out.vertices[t[0]];
    const Vec3& b = out.vertices[t[1]];
    const Vec3& c = out.vertices[t[2]];
    Vec3 n = (a - b).cross(b - c);
    const double len = n.norm();
    if (len > 0) n /= len;
    for (auto k : t) normal[k] += n;
  }
  for (std::size_t i = 0; i < out.vertices.size(); ++i) {
    Vec3 n = normal[i];
    const double len = n.norm();
    if (len > 0) n /= len;
    out.vertices[i] = centre + (out.vertices[i] - centre) * scale + n * padding;
  }
  return out;
}

std::vector<std::pair<int, int>> add_robot(const RobotSpec& spec, Scene& scene) {
  const std::filesystem::path& file = spec.urdf;
  const std::string text = read_file(file, "URDF file");
  tinyxml2::XMLDocument doc;
  parse_xml(doc, text, file);
  if (doc.FirstChildElement("robot") == nullptr) fail(file, "not a URDF: the root element is not <robot>");
  const Lines lines = element_lines(doc);
  // Every link some joint's child (a joint cycle with no root), or a joint
  // from a link to itself: said here, before urdfdom, which gives up on
  // either with the cycle's shared pointers still holding each other (a
  // leak inside the library; the fuzzer found the second).
  if (!lines.link.empty()) {
    std::set<std::string> children;
    for (const auto* e = doc.FirstChildElement("robot")->FirstChildElement("joint"); e != nullptr;
         e = e->NextSiblingElement("joint")) {
      const auto* c = e->FirstChildElement("child");
      const auto* p = e->FirstChildElement("parent");
      if (c == nullptr || c->Attribute("link") == nullptr) continue;
      children.insert(c->Attribute("link"));
      if (p != nullptr && p->Attribute("link") != nullptr && std::string(p->Attribute("link")) == c->Attribute("link"))
        fail(file, "joint '" + std::string(e->Attribute("name") != nullptr ? e->Attribute("name") : "") + "' (line " +
                       std::to_string(e->GetLineNum()) + ") joins link '" + c->Attribute("link") +
                       "' to itself: a joint cycle");
    }
    if (std::all_of(lines.link.begin(), lines.link.end(), [&](const auto& l) { return children.count(l.first) > 0; }))
      fail(file, "no root link (every link is some joint's child: a joint cycle)");
  }
  const urdf::ModelInterfaceSharedPtr model = parse_urdf(text, file);
  // urdfdom links hold their children by shared pointer: a model with a joint
  // cycle (refused below) would never be freed. Cut every link's ties when
  // this function is left, whichever way.
  struct CutTies {
    const urdf::ModelInterfaceSharedPtr& model;
    ~CutTies() {
      for (auto& [name, link] : model->links_) {
        link->child_links.clear();
        link->child_joints.clear();
        link->parent_joint.reset();
      }
    }
  } cut_ties{model};

  auto link_where = [&](const std::string& name) {
    auto it = lines.link.find(name);
    return "link '" + name + "'" + (it != lines.link.end() ? " (line " + std::to_string(it->second) + ")" : "");
  };
  auto joint_where = [&](const std::string& name) {
    auto it = lines.joint.find(name);
    return "joint '" + name + "'" + (it != lines.joint.end() ? " (line " + std::to_string(it->second) + ")" : "");
  };

  // A tree: one parent joint per link, every link reachable from the one root.
  std::map<std::string, std::string> parent_joint;
  for (const auto& [name, joint] : model->joints_) {
    auto [it, added] = parent_joint.emplace(joint->child_link_name, name);
    if (!added)
      fail(file, "link '" + joint->child_link_name + "' is the child of two joints, " + joint_where(it->second) +
                     " and " + joint_where(name) + ": a joint cycle or a link with two parents");
  }
  const urdf::LinkConstSharedPtr root = model->getRoot();
  if (!root) fail(file, "no root link (every link is some joint's child: a joint cycle)");
  std::vector<urdf::LinkConstSharedPtr> order;  // depth first, children by joint name
  std::set<std::string> seen;
  std::function<void(const urdf::LinkConstSharedPtr&)> visit = [&](const urdf::LinkConstSharedPtr& link) {
    if (!seen.insert(link->name).second) fail(file, link_where(link->name) + " is reached twice: a joint cycle");
    order.push_back(link);
    std::vector<urdf::JointSharedPtr> joints = link->child_joints;
    std::sort(joints.begin(), joints.end(), [](const auto& a, const auto& b) { return a->name < b->name; });
    for (const auto& j : joints) {
      urdf::LinkConstSharedPtr child = model->getLink(j->child_link_name);
      if (child) visit(child);
    }
  };
  visit(root);
  if (seen.size() != model->links_.size()) {
    std::string lost;
    for (const auto& [name, link] : model->links_)
      if (!seen.count(name)) lost += (lost.empty() ? "" : ", ") + link_where(name);
    fail(file, "joint cycle: " + lost + " not reachable from the root link '" + root->name + "'");
  }

  RobotInfo info;
  info.urdf = file;
  info.srdf = spec.srdf;
  info.name = model->getName();
  info.visual = spec.visual;
  info.padding = spec.padding;
  info.scale = spec.scale;
  info.links = static_cast<int>(model->links_.size());
  info.joints = static_cast<int>(model->joints_.size());

  // Nodes: an extra root when the robot stands alone.
  int parent_node = spec.parent_node;
  if (parent_node < 0) {
    if (!scene.nodes.empty()) {
      parent_node = 0;
    } else {
      Node world;
      world.path = "";
      scene.nodes.push_back(world);
      parent_node = 0;
    }
  }
  for (const Part& p : scene.parts) {
    if (model->links_.count(p.name))
      fail(file, link_where(p.name) + " has the name of the model's part " + scene.nodes[p.node].path);
  }

  Resolver resolver(spec);
  std::map<std::filesystem::path, Mesh> meshes;  // by resolved file
  std::map<std::string, Affine> frame;           // link frame at the zero pose, reference frame
  std::map<std::string, int> node_of;
  std::map<std::string, int> action_of;          // joint -> action
  std::vector<std::pair<int, std::string>> mimics;  // action, master joint

  for (const urdf::LinkConstSharedPtr& link : order) {
    const std::string where = link_where(link->name);
    Affine t = spec.origin;
    int parent = parent_node;
    urdf::JointConstSharedPtr joint;
    if (auto pj = parent_joint.find(link->name); pj != parent_joint.end()) {
      joint = model->getJoint(pj->second);
      if (!finite(joint->parent_to_joint_origin_transform))
        fail(file, joint_where(joint->name) + ": origin is not finite");
      t = frame.at(joint->parent_link_name) * to_affine(joint->parent_to_joint_origin_transform);
      parent = node_of.at(joint->parent_link_name);
      info.adjacent.emplace_back(joint->parent_link_name, link->name);
    }
    if (!t.matrix().allFinite()) fail(file, where + ": its frame is not finite (origins too large)");
    frame[link->name] = t;
    Node node;
    node.name = link->name;
    node.parent = parent;
    node.path = scene.nodes[parent].path + "/" + link->name;
    node.origin = t.translation();
    node.axes = t.linear();
    node.robot_link = true;
    const int index = static_cast<int>(scene.nodes.size());
    scene.nodes[parent].children.push_back(index);
    scene.nodes.push_back(node);
    node_of[link->name] = index;

    if (joint && joint->type != urdf::Joint::FIXED) {
      const std::string jw = joint_where(joint->name);
      Action a;
      a.name = joint->name;
      a.node_name = link->name;
      a.node = index;
      if (joint->type == urdf::Joint::FLOATING || joint->type == urdf::Joint::PLANAR ||
          joint->type == urdf::Joint::UNKNOWN)
        fail(file, jw + ": only revolute, continuous, prismatic and fixed joints are read");
      const Vec3 axis(joint->axis.x, joint->axis.y, joint->axis.z);
      const double largest = axis.cwiseAbs().maxCoeff();
      if (!axis.allFinite() || !(largest > 0)) fail(file, jw + ": zero-length or non-finite axis");
      a.axis = (t.linear() * (axis / largest)).normalized();
      if (joint->type == urdf::Joint::PRISMATIC) {
        a.type = ActionType::kTranslateAxis;
      } else {
        a.type = ActionType::kRotate;
        a.pivot = t.translation();
      }
      if (joint->type != urdf::Joint::CONTINUOUS && joint->limits) {
        const double lo = joint->limits->lower, hi = joint->limits->upper;
        if (!std::isfinite(lo) || !std::isfinite(hi)) fail(file, jw + ": limits are not finite");
        if (lo > hi) fail(file, jw + ": lower limit is above the upper limit");
        a.has_limits = true;
        a.lower = lo;
        a.upper = hi;
      }
      if (joint->mimic) {
        if (!std::isfinite(joint->mimic->multiplier) || !std::isfinite(joint->mimic->offset))
          fail(file, jw + ": mimic multiplier or offset is not finite");
        a.multiplier = joint->mimic->multiplier;
        a.offset = joint->mimic->offset;
        a.parameter_count = 0;
        a.has_limits = false;  // MoveIt checks the limits of active joints only
        a.first_parameter = static_cast<int>(scene.parameter_names.size());
        mimics.emplace_back(static_cast<int>(scene.actions.size()), joint->mimic->joint_name);
      } else {
        if (a.name == "time") fail(file, jw + ": 'time' is reserved for the plan's time column");
        a.first_parameter = static_cast<int>(scene.parameter_names.size());
        scene.parameter_names.push_back(a.name);
        scene.reference_parameters.push_back(0.0);
      }
      action_of[joint->name] = static_cast<int>(scene.actions.size());
      scene.nodes[index].actions.push_back(static_cast<int>(scene.actions.size()));
      scene.actions.push_back(std::move(a));
    }

    // Geometry: every collision (or visual) element of the link, in file order.
    std::vector<std::pair<urdf::Pose, urdf::GeometrySharedPtr>> shapes;
    if (spec.visual) {
      for (const auto& v : link->visual_array)
        if (v && v->geometry) shapes.emplace_back(v->origin, v->geometry);
    } else {
      for (const auto& c : link->collision_array)
        if (c && c->geometry) shapes.emplace_back(c->origin, c->geometry);
    }
    Mesh part_mesh;
    for (std::size_t s = 0; s < shapes.size(); ++s) {
      const std::string element = where + " " + (spec.visual ? "visual" : "collision") + "[" + std::to_string(s) + "]";
      const auto& [origin, geometry] = shapes[s];
      if (!finite(origin)) fail(file, element + ": origin is not finite");
      const Affine place = t * to_affine(origin);
      const double k = spec.scale, pad = spec.padding;
      Mesh local;
      switch (geometry->type) {
        case urdf::Geometry::MESH: {
          const auto& g = static_cast<const urdf::Mesh&>(*geometry);
          if (!finite(g.scale)) fail(file, element + ": mesh scale is not finite");
          const std::filesystem::path path = resolver.resolve(g.filename, element);
          auto cached = meshes.find(path);
          if (cached == meshes.end()) cached = meshes.emplace(path, load_mesh(path, scene.warnings)).first;
          local = cached->second;
          for (Vec3& v : local.vertices) v = v.cwiseProduct(Vec3(g.scale.x, g.scale.y, g.scale.z));
          if (k != 1.0 || pad != 0.0) local = scale_and_pad(local, k, pad);
          break;
        }
        case urdf::Geometry::BOX: {
          const auto& g = static_cast<const urdf::Box&>(*geometry);
          const Vec3 size = Vec3(g.dim.x, g.dim.y, g.dim.z) * k + Vec3::Constant(2 * pad);
          if (!size.allFinite() || !(size.minCoeff() > 0)) fail(file, element + ": box size must be positive");
          local = box_tessellation(size);
          ++info.boxes;
          break;
        }
        case urdf::Geometry::CYLINDER: {
          const auto& g = static_cast<const urdf::Cylinder&>(*geometry);
          const double r = g.radius * k + pad, l = g.length * k + 2 * pad;
          if (!std::isfinite(r) || !std::isfinite(l) || !(r > 0) || !(l > 0))
            fail(file, element + ": cylinder radius and length must be positive");
          double deviation = 0;
          local = cylinder_tessellation(r, l, deviation);
          info.largest_deviation = std::max(info.largest_deviation, deviation);
          ++info.cylinders;
          break;
        }
        case urdf::Geometry::SPHERE: {
          const auto& g = static_cast<const urdf::Sphere&>(*geometry);
          const double r = g.radius * k + pad;
          if (!std::isfinite(r) || !(r > 0)) fail(file, element + ": sphere radius must be positive");
          double deviation = 0;
          local = sphere_tessellation(r, deviation);
          info.largest_deviation = std::max(info.largest_deviation, deviation);
          ++info.spheres;
          break;
        }
      }
      append(part_mesh, local, place);
    }
    if (part_mesh.triangles.empty()) continue;
    for (const Vec3& v : part_mesh.vertices)
      if (!v.allFinite()) fail(file, where + ": non-finite vertex");
    Part part;
    part.name = link->name;
    part.node = index;
    part.mesh = std::move(part_mesh);
    scene.nodes[index].part = static_cast<int>(scene.parts.size());
    scene.parts.push_back(std::move(part));
  }

  for (const auto& [action, master] : mimics) {
    const std::string jw = joint_where(scene.actions[action].name);
    auto it = action_of.find(master);
    if (it == action_of.end())
      fail(file, jw + ": mimics joint '" + master + "', which " +
                     (model->joints_.count(master) ? "is fixed" : "does not exist"));
    if (scene.actions[it->second].mimic >= 0 || scene.actions[it->second].parameter_count == 0)
      fail(file, jw + ": mimics joint '" + master + "', which is itself a mimic joint");
    scene.actions[action].mimic = it->second;
  }

  // SRDF: disable_collisions pairs of links.
  std::vector<std::pair<int, int>> allowed;
  if (!spec.srdf.empty()) {
    const std::string srdf_text = read_file(spec.srdf, "SRDF file");
    tinyxml2::XMLDocument srdf;
    parse_xml(srdf, srdf_text, spec.srdf);
    const auto* robot = srdf.FirstChildElement("robot");
    if (robot == nullptr) fail(spec.srdf, "not an SRDF: the root element is not <robot>");
    for (const auto* e = robot->FirstChildElement("disable_collisions"); e != nullptr;
         e = e->NextSiblingElement("disable_collisions")) {
      const long line = e->GetLineNum();
      const char* names[2] = {e->Attribute("link1"), e->Attribute("link2")};
      int parts[2];
      for (int k = 0; k < 2; ++k) {
        if (names[k] == nullptr)
          fail(spec.srdf, std::string("disable_collisions: missing link") + (k == 0 ? "1" : "2"), line);
        auto node = node_of.find(names[k]);
        if (node == node_of.end())
          fail(spec.srdf, std::string("disable_collisions: link '") + names[k] + "' is not a link of " +
                              file.filename().string(), line);
        parts[k] = scene.nodes[node->second].part;
      }
      info.disabled.emplace_back(names[0], names[1]);
      if (parts[0] >= 0 && parts[1] >= 0) allowed.emplace_back(parts[0], parts[1]);
    }
  }
  scene.robot = std::move(info);
  return allowed;
}

}  // namespace plancheck
