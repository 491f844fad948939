// SPDX-License-Identifier: MIT
// The part tree of the synthetic lander (the paper's Figure 9):
//   probe -> {lander -> groups of lander parts, ascender -> ascender parts}
//   arm -> J1 -> {ArmJ1, J2 -> {ArmJ2, J3 -> {ArmJ3, J4 -> {ArmJ4, Scoop}}}}
// Shapes are plausible, not measured: see datasets/README.md for what is
// public fact and what is assumed.
#include "datasets/change5.h"
#include "datasets/geometry.h"

#include <cmath>
#include <stdexcept>

namespace plancheck::dataset {
namespace {

constexpr double kPi = 3.14159265358979323846;

Vec3 polar(double r, double deg, double z) {
  double a = deg * kPi / 180.0;
  return {r * std::cos(a), r * std::sin(a), z};
}

class TreeBuilder {
 public:
  Model model;
  int group(const std::string& name, int parent) {
    model.nodes.push_back({name, parent, {}});
    return static_cast<int>(model.nodes.size() - 1);
  }
  int part(const std::string& name, int parent, MeshBuilder&& mb) {
    model.nodes.push_back({name, parent, std::move(mb.mesh)});
    return static_cast<int>(model.nodes.size() - 1);
  }
  std::size_t subtree_triangles(int root) const {
    std::size_t n = 0;
    for (std::size_t i = 0; i < model.nodes.size(); ++i)
      if (model.in_subtree(static_cast<int>(i), root)) n += model.nodes[i].mesh.triangles.size();
    return n;
  }
};

// A straight strut between two points: a cylinder with end collars.
void strut(MeshBuilder& mb, const Vec3& a, const Vec3& b, double r, int seg, int rings) {
  mb.cylinder(a, b, r, seg, rings);
}

// ---------------------------------------------------------------- lander ----
void build_lander(TreeBuilder& t, int lander) {
  // Body: an octagonal box (flat faces towards +-x, +-y) and the top deck.
  int body_group = t.group("LanderBodyGroup", lander);
  {
    MeshBuilder mb;
    mb.prism({0, 0, 0.60}, {0, 0, 1.30}, 1.25, 8, 22.5);
    // Side panels with thermal blankets: finely split plates on each face.
    for (int k = 0; k < 8; ++k) {
      double deg = k * 45.0;
      Vec3 n = polar(1.0, deg, 0.0);
      Vec3 c = polar(1.155 + 0.012, deg, 0.95);
      mb.box(c, {0.01, 0.42, 0.30}, n, Vec3::UnitZ().cross(n), 18);
    }
    t.part("LanderBody", body_group, std::move(mb));
  }
  {
    MeshBuilder mb;
    mb.prism({0, 0, 1.30}, {0, 0, kDeckTop}, 1.32, 8, 22.5);
    // Deck equipment plates and a handrail of short posts around the rim.
    mb.box({-0.9, 0.55, 1.38}, {0.12, 0.12, 0.03}, Vec3::UnitX(), Vec3::UnitY(), 18);
    mb.box({-0.9, -0.35, 1.38}, {0.12, 0.18, 0.03}, Vec3::UnitX(), Vec3::UnitY(), 18);
    t.part("TopDeck", body_group, std::move(mb));
  }
  {
    // Shoulder base of the arm: the static mount J1 turns on.
    MeshBuilder mb;
    mb.cylinder({0.90, 0, kDeckTop}, {0.90, 0, 1.46}, 0.12, 96, 6);
    mb.torus({0.90, 0, 1.37}, Vec3::UnitZ(), 0.13, 0.02, 96, 16);
    for (int k = 0; k < 12; ++k) {
      Vec3 p = Vec3(0.90, 0, 0) + polar(0.145, k * 30.0, 0.0);
      mb.cylinder({p.x(), p.y(), kDeckTop}, {p.x(), p.y(), 1.375}, 0.008, 12);
    }
    t.part("ArmMount", body_group, std::move(mb));
  }

  // Four landing legs on the diagonals: main strut, two secondary struts, footpad.
  int legs = t.group("Legs", lander);
  const char* leg_names[4] = {"LegA", "LegB", "LegC", "LegD"};
  for (int k = 0; k < 4; ++k) {
    double deg = 45.0 + 90.0 * k;
    MeshBuilder mb;
    Vec3 top = polar(1.05, deg, 1.00);
    Vec3 knee = polar(1.98, deg, 0.20);
    Vec3 pad = polar(2.05, deg, 0.0);
    strut(mb, top, knee, 0.05, 48, 24);
    strut(mb, knee, pad + Vec3(0, 0, 0.08), 0.04, 48, 8);
    for (int s = -1; s <= 1; s += 2) {
      Vec3 side = polar(1.0, deg + s * 22.0, 0.62);
      strut(mb, side, knee + Vec3(0, 0, 0.03), 0.028, 32, 24);
    }
    // Footpad: a shallow dish on a disc.
    mb.frustum(pad, pad + Vec3(0, 0, 0.05), 0.22, 0.24, 96, 4);
    mb.dish(pad + Vec3(0, 0, 0.05), Vec3::UnitZ(), 0.24, 0.04, 0.01, 96, 12);
    mb.sphere(knee, 0.07, 32, 16);
    t.part(leg_names[k], legs, std::move(mb));
  }

  // Two solar wings on +-y: yoke and a panel of cells in a frame.
  int wings = t.group("SolarWings", lander);
  for (int s = 0; s < 2; ++s) {
    double sy = s == 0 ? 1.0 : -1.0;
    MeshBuilder mb;
    strut(mb, {-0.2, sy * 1.155, 1.10}, {-0.2, sy * 1.36, 1.10}, 0.03, 32, 4);
    strut(mb, {0.2, sy * 1.155, 1.10}, {0.2, sy * 1.36, 1.10}, 0.03, 32, 4);
    mb.box({0, sy * 2.25, 1.10}, {0.60, 0.90, 0.015}, Vec3::UnitX(), Vec3::UnitY(), 44);
    // Frame rails along the long edges.
    strut(mb, {0.61, sy * 1.35, 1.10}, {0.61, sy * 3.15, 1.10}, 0.018, 24, 30);
    strut(mb, {-0.61, sy * 1.35, 1.10}, {-0.61, sy * 3.15, 1.10}, 0.018, 24, 30);
    t.part(s == 0 ? "SolarWingL" : "SolarWingR", wings, std::move(mb));
  }

  // Propellant tanks inside the body and the main engine bell under it.
  int propulsion = t.group("Propulsion", lander);
  {
    MeshBuilder mb;
    for (int k = 0; k < 4; ++k) mb.sphere(polar(0.62, 45.0 + 90.0 * k, 0.95), 0.30, 96, 48);
    t.part("PropellantTanks", propulsion, std::move(mb));
  }
  {
    MeshBuilder mb;
    mb.frustum({0, 0, 0.60}, {0, 0, 0.50}, 0.15, 0.13, 96, 4);
    mb.frustum({0, 0, 0.50}, {0, 0, 0.30}, 0.13, 0.32, 128, 30);
    mb.torus({0, 0, 0.30}, Vec3::UnitZ(), 0.32, 0.01, 128, 12);
    t.part("EngineBell", propulsion, std::move(mb));
  }

  // Communications: high-gain antenna on a mast at the rear-right of the deck.
  int comms = t.group("Communications", lander);
  const Vec3 mast_base{-0.55, -0.75, kDeckTop};
  {
    MeshBuilder mb;
    strut(mb, mast_base, mast_base + Vec3(0, 0, 1.00), 0.04, 48, 40);
    mb.frustum(mast_base, mast_base + Vec3(0, 0, 0.08), 0.10, 0.05, 48, 2);
    mb.box(mast_base + Vec3(0, 0, 1.04), {0.06, 0.06, 0.05}, Vec3::UnitX(), Vec3::UnitY(), 6);
    t.part("AntennaMast", comms, std::move(mb));
  }
  {
    MeshBuilder mb;
    Vec3 axis = Vec3(-0.35, -0.35, 0.87).normalized();
    Vec3 c = mast_base + Vec3(0, 0, 1.10);
    mb.dish(c, axis, 0.30, 0.09, 0.012, 128, 56);
    mb.cylinder(c, c + axis * 0.22, 0.012, 24, 6);  // feed support
    mb.cone(c + axis * 0.22, c + axis * 0.27, 0.03, 32);
    t.part("HighGainAntenna", comms, std::move(mb));
  }

  // Cameras: a panoramic camera mast on the -y front of the deck.
  int cameras = t.group("Cameras", lander);
  {
    MeshBuilder mb;
    Vec3 b{0.75, -0.80, kDeckTop};
    strut(mb, b, b + Vec3(0, 0, 0.60), 0.03, 32, 20);
    mb.box(b + Vec3(0, 0, 0.66), {0.05, 0.09, 0.05}, Vec3::UnitX(), Vec3::UnitY(), 10);
    for (int s = -1; s <= 1; s += 2) {
      Vec3 lens = b + Vec3(0.05, s * 0.05, 0.66);
      mb.cylinder(lens, lens + Vec3(0.04, 0, 0), 0.02, 48, 2);
    }
    t.part("PanoramicCamera", cameras, std::move(mb));
  }
  {
    MeshBuilder mb;  // landing camera under the body, looking down
    Vec3 c{0.8, 0.3, 0.55};
    mb.box(c, {0.05, 0.05, 0.05}, Vec3::UnitX(), Vec3::UnitY(), 8);
    mb.cylinder(c - Vec3(0, 0, 0.05), c - Vec3(0, 0, 0.09), 0.025, 48, 2);
    t.part("LandingCamera", cameras, std::move(mb));
  }

  // Drill: a square truss tower on the -x side with the drill rod.
  int drill = t.group("Drill", lander);
  {
    MeshBuilder mb;
    const double x0 = -1.55, x1 = -1.30, y0 = 0.25, y1 = 0.50, z0 = 0.35, z1 = 2.05;
    const Vec3 corners[4] = {{x0, y0, 0}, {x1, y0, 0}, {x1, y1, 0}, {x0, y1, 0}};
    const int bays = 10;
    for (const Vec3& c : corners) strut(mb, c + Vec3(0, 0, z0), c + Vec3(0, 0, z1), 0.015, 24, 20);
    for (int k = 0; k <= bays; ++k) {
      double z = z0 + (z1 - z0) * k / bays;
      for (int i = 0; i < 4; ++i) {
        Vec3 a = corners[i] + Vec3(0, 0, z), b = corners[(i + 1) % 4] + Vec3(0, 0, z);
        strut(mb, a, b, 0.01, 16, 2);
        if (k < bays) strut(mb, a, corners[(i + 1) % 4] + Vec3(0, 0, z + (z1 - z0) / bays), 0.008, 12, 4);
      }
    }
    strut(mb, {-1.425, 0.375, 0.05}, {-1.425, 0.375, 2.00}, 0.02, 32, 30);
    t.part("DrillTower", drill, std::move(mb));
  }

  // Sample handling: the storage can on the deck and its handle.
  int sampling = t.group("SampleHandling", lander);
  {
    MeshBuilder mb;
    mb.tube(kCanCentre, kCanCentre + Vec3(0, 0, kCanHeight), kCanRadius, 0.006, 96);
    mb.torus(kCanCentre + Vec3(0, 0, kCanHeight), Vec3::UnitZ(), kCanRadius, 0.006, 96, 8);
    t.part("SampleCan", sampling, std::move(mb));
  }
  {
    // A bail over the opening, across the arm's approach direction, so the
    // scoop's hook can take it from above (plan10).
    MeshBuilder mb;
    Vec3 top = kCanCentre + Vec3(0, 0, kCanHeight);
    Vec3 radial = Vec3(kCanCentre.x() - kShoulderPivot.x(), kCanCentre.y() - kShoulderPivot.y(), 0).normalized();
    Vec3 across = Vec3::UnitZ().cross(radial);
    for (int s = -1; s <= 1; s += 2)
      mb.cylinder(top + s * kHandleSpan * across, top + s * kHandleSpan * across + Vec3(0, 0, kHandleLift), 0.006, 24, 8);
    mb.torus(top + Vec3(0, 0, kHandleLift), radial, kHandleSpan, 0.006, 64, 12, 0.0, 180.0, across);
    t.part("CanHandle", sampling, std::move(mb));
  }

  // Whatever Table 2 still asks for goes into a cable harness under the body,
  // out of the arm's reach.
  std::size_t have = t.subtree_triangles(lander);
  if (have > kLanderTriangles) throw std::logic_error("lander has " + std::to_string(have) + " triangles before filling");
  auto& body_mesh = t.model.nodes[static_cast<std::size_t>(t.model.find("LanderBody"))].mesh;
  MeshBuilder fill;
  fill.mesh = std::move(body_mesh);
  if (!fill.fill_to(fill.triangle_count() + (kLanderTriangles - have), {-0.8, -0.9, 0.55}, {0.8, -0.9, 0.55}, 0.02))
    throw std::logic_error("lander has more triangles than Table 2");
  body_mesh = std::move(fill.mesh);
  if (kLanderTriangles < have) throw std::logic_error("lander over budget");
}

// -------------------------------------------------------------- ascender ----
void build_ascender(TreeBuilder& t, int ascender) {
  const Vec3 c{-0.25, 0.0, kDeckTop};
  {
    MeshBuilder mb;
    mb.prism(c, c + Vec3(0, 0, 0.80), 0.62, 12, 15.0);
    for (int k = 0; k < 12; ++k) {
      double deg = 15.0 + 30.0 * k + 15.0;
      Vec3 n = polar(1.0, deg, 0.0);
      Vec3 p = c + polar(0.62 * std::cos(kPi / 12) + 0.008, deg, 0.40);
      mb.box(p, {0.006, 0.12, 0.30}, n, Vec3::UnitZ().cross(n), 14);
    }
    t.part("AscenderBody", ascender, std::move(mb));
  }
  {
    MeshBuilder mb;  // the ascent engine sits in the lander's central well
    mb.frustum(c + Vec3(0, 0, 0.05), c + Vec3(0, 0, -0.35), 0.10, 0.22, 96, 24);
    t.part("AscentEngine", ascender, std::move(mb));
  }
  for (int s = 0; s < 2; ++s) {
    double sy = s == 0 ? 1.0 : -1.0;
    MeshBuilder mb;
    strut(mb, c + Vec3(-0.2, sy * 0.55, 0.55), c + Vec3(-0.2, sy * 0.68, 0.55), 0.02, 24, 4);
    mb.box(c + Vec3(-0.2, sy * 0.98, 0.55), {0.0125, 0.30, 0.25}, Vec3::UnitX(), Vec3::UnitY(), 30);
    t.part(s == 0 ? "AscenderWingL" : "AscenderWingR", ascender, std::move(mb));
  }
  {
    MeshBuilder mb;
    for (int k = 0; k < 4; ++k) {
      Vec3 p = c + polar(0.75, 45.0 + 90.0 * k, 0.22);
      mb.sphere(p, 0.12, 64, 32);
      strut(mb, p - polar(0.12, 45.0 + 90.0 * k, 0.0), p - polar(0.16, 45.0 + 90.0 * k, 0.0), 0.02, 16, 2);
    }
    t.part("GasBottles", ascender, std::move(mb));
  }
  {
    MeshBuilder mb;  // docking frame: a ring on six struts above the top
    Vec3 top = c + Vec3(0, 0, 0.80);
    mb.torus(top + Vec3(0, 0, 0.15), Vec3::UnitZ(), 0.45, 0.03, 192, 24);
    for (int k = 0; k < 6; ++k) {
      double deg = 30.0 + 60.0 * k;
      strut(mb, top + polar(0.50, deg, 0.0), top + polar(0.45, deg, 0.15), 0.015, 24, 8);
      Vec3 latch = top + polar(0.45, deg + 30.0, 0.15);
      mb.box(latch + Vec3(0, 0, 0.05), {0.03, 0.03, 0.04}, polar(1.0, deg + 30.0, 0.0), Vec3::UnitZ().cross(polar(1.0, deg + 30.0, 0.0)), 6);
    }
    t.part("DockingFrame", ascender, std::move(mb));
  }
  {
    MeshBuilder mb;  // star sensor and rendezvous sensor on the rear of the top
    Vec3 top = c + Vec3(0, 0, 0.80);
    mb.box(top + Vec3(-0.35, 0.20, 0.05), {0.05, 0.05, 0.05}, Vec3::UnitX(), Vec3::UnitY(), 8);
    mb.frustum(top + Vec3(-0.35, 0.20, 0.10), top + Vec3(-0.35, 0.20, 0.18), 0.03, 0.05, 48, 4);
    mb.box(top + Vec3(-0.35, -0.20, 0.04), {0.06, 0.04, 0.04}, Vec3::UnitX(), Vec3::UnitY(), 8);
    mb.cylinder(top + Vec3(-0.29, -0.20, 0.04), top + Vec3(-0.25, -0.20, 0.04), 0.025, 48, 2);
    t.part("Sensors", ascender, std::move(mb));
  }
  {
    MeshBuilder mb;  // the container receptacle on the top: a tube with a funnel
    const Vec3& b = kReceptacleCentre;
    mb.tube(b, b + Vec3(0, 0, 0.20), 0.13, 0.008, 128);
    mb.frustum(b + Vec3(0, 0, 0.20), b + Vec3(0, 0, kReceptacleHeight), 0.135, 0.18, 128, 6);
    t.part("Receptacle", ascender, std::move(mb));
  }
  std::size_t have = t.subtree_triangles(ascender);
  if (have > kAscenderTriangles) throw std::logic_error("ascender has " + std::to_string(have) + " triangles before filling");
  auto& body = t.model.nodes[static_cast<std::size_t>(t.model.find("AscenderBody"))].mesh;
  MeshBuilder fill;
  fill.mesh = std::move(body);
  if (have > kAscenderTriangles ||
      !fill.fill_to(fill.triangle_count() + (kAscenderTriangles - have), c + Vec3(-0.5, -0.3, 0.85), c + Vec3(-0.5, 0.3, 0.85), 0.015))
    throw std::logic_error("ascender over budget");
  body = std::move(fill.mesh);
}

// ------------------------------------------------------------------- arm ----
// Each link is one part under its joint node; hubs of neighbouring links meet
// on the joint axis (declared in allowed_collisions).
void finish(MeshBuilder& mb, std::size_t target, const Vec3& a, const Vec3& b, double r, const char* what) {
  if (!mb.fill_to(target, a, b, r))
    throw std::logic_error(std::string(what) + " has " + std::to_string(mb.triangle_count()) + " triangles before filling");
}

void build_arm(TreeBuilder& t, int arm) {
  const Vec3& p2 = kShoulderPivot;
  const Vec3& p3 = kElbowPivot;
  const Vec3& p4 = kWristPivot;
  const Vec3 y = Vec3::UnitY();

  int j1 = t.group("J1", arm);
  {
    MeshBuilder mb;  // turret on the mount and a clevis holding the J2 axle
    mb.cylinder({0.90, 0, 1.46}, {0.90, 0, 1.59}, 0.10, 96, 10);
    for (int s = -1; s <= 1; s += 2) {
      mb.box({0.90, s * 0.085, p2.z() - 0.02}, {0.075, 0.012, 0.075}, Vec3::UnitX(), y, 8);
      mb.cylinder(p2 + Vec3(0, s * 0.073, 0), p2 + Vec3(0, s * 0.105, 0), 0.06, 64, 4);
    }
    mb.cylinder({0.78, -0.05, 1.53}, {0.78, 0.05, 1.53}, 0.025, 32, 2);  // J1 motor
    finish(mb, kJointTriangles[0], {0.95, -0.10, 1.53}, {0.95, 0.10, 1.53}, 0.008, "ArmJ1");
    t.part("ArmJ1", j1, std::move(mb));
  }
  int j2 = t.group("J2", j1);
  {
    MeshBuilder mb;  // upper arm: hub, carbon tube, elbow clevis
    mb.cylinder(p2 - Vec3(0, 0.073, 0), p2 + Vec3(0, 0.073, 0), 0.07, 96, 4);
    mb.cylinder(p2 + Vec3(0.07, 0, 0), p3 - Vec3(0.10, 0, 0), 0.05, 64, 30);
    for (int s = -1; s <= 1; s += 2) {
      mb.box(p3 + Vec3(-0.06, s * 0.085, 0), {0.08, 0.012, 0.06}, Vec3::UnitX(), y, 8);
      mb.cylinder(p3 + Vec3(0, s * 0.073, 0), p3 + Vec3(0, s * 0.097, 0), 0.06, 64, 2);
    }
    mb.frustum(p3 - Vec3(0.10, 0, 0), p3 - Vec3(0.06, 0, 0), 0.05, 0.04, 64, 2);
    finish(mb, kJointTriangles[1], p2 + Vec3(0.20, 0, 0.062), p3 - Vec3(0.25, 0, -0.062), 0.010, "ArmJ2");
    t.part("ArmJ2", j2, std::move(mb));
  }
  int j3 = t.group("J3", j2);
  {
    MeshBuilder mb;  // forearm
    mb.cylinder(p3 - Vec3(0, 0.073, 0), p3 + Vec3(0, 0.073, 0), 0.055, 96, 4);
    mb.cylinder(p3 + Vec3(0.055, 0, 0), p4 - Vec3(0.10, 0, 0), 0.045, 64, 30);
    for (int s = -1; s <= 1; s += 2) {
      mb.box(p4 + Vec3(-0.05, s * 0.075, 0), {0.07, 0.010, 0.05}, Vec3::UnitX(), y, 8);
      mb.cylinder(p4 + Vec3(0, s * 0.065, 0), p4 + Vec3(0, s * 0.085, 0), 0.05, 64, 2);
    }
    mb.frustum(p4 - Vec3(0.10, 0, 0), p4 - Vec3(0.06, 0, 0), 0.045, 0.035, 64, 2);
    finish(mb, kJointTriangles[2], p3 + Vec3(0.20, 0, 0.057), p4 - Vec3(0.25, 0, -0.057), 0.009, "ArmJ3");
    t.part("ArmJ3", j3, std::move(mb));
  }
  int j4 = t.group("J4", j3);
  {
    MeshBuilder mb;  // wrist: hub on the J4 axle and a bracket down to the scoop
    mb.cylinder(p4 - Vec3(0, 0.065, 0), p4 + Vec3(0, 0.065, 0), 0.045, 96, 20);
    mb.box(p4 + Vec3(0.025, 0, -0.08), {0.025, 0.03, 0.06}, Vec3::UnitX(), y, 10);
    mb.cylinder(p4 + Vec3(0.025, 0, -0.14), p4 + Vec3(0.025, 0, -0.15), 0.03, 64, 2);
    finish(mb, kJointTriangles[3], p4 + Vec3(0.055, -0.02, -0.03), p4 + Vec3(0.055, 0.02, -0.12), 0.006, "ArmJ4");
    t.part("ArmJ4", j4, std::move(mb));
  }
  {
    MeshBuilder mb;  // hooked scoop: shank, bend, bucket of 10 cm inner width
    const Vec3& m = kScoopBottom;
    Vec3 shank_top = p4 + Vec3(0.025, 0, -0.15);
    Vec3 bend_centre{shank_top.x() + 0.06, 0, m.z() + 0.095};
    mb.cylinder(shank_top, {shank_top.x(), 0, bend_centre.z()}, 0.012, 24, 4);
    mb.torus(bend_centre, y, 0.06, 0.012, 16, 12, 90.0, 90.0, Vec3::UnitX());
    mb.cylinder({bend_centre.x(), 0, bend_centre.z() - 0.06}, {m.x() - 0.074, 0, bend_centre.z() - 0.06}, 0.012, 24, 2);
    mb.box({m.x(), 0, m.z() + 0.003}, {0.08, 0.056, 0.003}, Vec3::UnitX(), y, 4);              // floor
    for (int s = -1; s <= 1; s += 2)
      mb.box({m.x(), s * 0.053, m.z() + 0.04}, {0.08, 0.003, 0.034}, Vec3::UnitX(), y, 4);      // sides
    mb.box({m.x() - 0.077, 0, m.z() + 0.04}, {0.003, 0.05, 0.034}, Vec3::UnitX(), y, 4);        // back
    // The hook behind the bucket that lifts the can by its handle.
    mb.torus({m.x() - 0.10, 0, m.z() + 0.10}, y, 0.025, 0.005, 12, 8, 90.0, 180.0, Vec3::UnitX());
    finish(mb, kScoopTriangles, {m.x() - 0.06, -0.02, m.z() + 0.075}, {m.x() - 0.06, 0.02, m.z() + 0.075}, 0.004, "Scoop");
    t.part("Scoop", j4, std::move(mb));
  }
}

}  // namespace

Model build_model() {
  TreeBuilder t;
  int probe = t.group("probe", -1);
  build_lander(t, t.group("lander", probe));
  build_ascender(t, t.group("ascender", probe));
  build_arm(t, t.group("arm", -1));
  return std::move(t.model);
}

}  // namespace plancheck::dataset
