// SPDX-License-Identifier: MIT
// Scooping: the terrain grid changed by the scoop, state by state along a plan.
//
// Template model (the paper's Algorithm 1, the default). At each state whose
// scoop bottom point M lies below the current surface (dem_surface at M's x, y),
// every valid grid sample N with horizontal distance L = |N - M|_xy <= W
// (W = scoop.width) is changed with x = L / W and d = Z_N - Z_M:
//
//   f(x) = pit                                                for 0 <= x < s
//   f(x) = rim * sin(pi * (x - s) / (1 - s))                  for s <= x <= 1
//   (s = template.rim_start; pit, rim as in the scene, defaults -1, 0.25, 0.7)
//
//   pit zone (x < s), when d > 0:        Z_N <- Z_N + d * f(x)
//   rim zone (x >= s), when Z_N >= S_N:  Z_N <- max(Z_N, S_N + max(S_N - Z_M, 0) * f(x))
//
// where S_N is the sample's height at the start of the plan. Two guards keep
// the paper's update sane when it is applied at every state: the pit only
// lowers soil that lies above M (with pit = -1 it lowers it exactly to Z_M,
// so a scoop resting in place digs no deeper), and the rim is measured from
// the plan's starting surface and never raises a sample the pit has lowered,
// so it neither grows geometrically while the scoop rests nor refills the
// trench behind a moving scoop. The rim profile is zero at x = s and x = 1
// and peaks (rim * d) half way.
//
// Volumes: a sample stands for its cell (samples sit at cell centres), so a
// height change dz at one sample is dz * cellsize^2 of soil. For the template
// model scoop_volume = sum over samples of max(S_N - Z_N, 0) * cellsize^2 (the
// pit below the plan's starting surface; the paper estimates the sample from
// the pit the same way).
//
// Swept model ("model": "swept"). At each state the posed scoop mesh's lowest
// point above every cell centre under its footprint is found with a vertical
// Embree ray; soil above that point is carved off. The carved volume goes into
// the scoop until it holds `capacity`; the rest is spilled evenly on the
// cells next to the carved ones (8-neighbourhood, not carved this state) as a
// rim. Then slopes between neighbouring samples (8-neighbourhood, horizontal
// distance h or h*sqrt(2)) steeper than the angle of repose relax: the pair
// exchanges soil until it stands exactly at the angle, repeated until no pair
// exceeds it by more than kReposeTolerance; the carved samples, under the
// scoop, are held while it is there, and the cut relaxes fully at the first
// state that carves nothing (or at the end of the plan). Every move transfers height
// between equal-area cells, so grid soil + scoop content is conserved to
// rounding. scoop_volume is the soil in the scoop.
#pragma once

#include "src/geometry/heightfield.h"
#include "src/geometry/raycast.h"
#include "src/scene/scene.h"
#include "src/scene/terrain.h"

#include <array>
#include <functional>
#include <memory>
#include <vector>

namespace plancheck {

// A relaxed pair may stand steeper than the angle of repose by this much
// height (m): the iteration converges geometrically, not in finite steps.
inline constexpr double kReposeTolerance = 1e-10;

// f(x) of the template model above.
double template_f(const ScoopTemplate& t, double x);

// What digging shows at one state (SI).
struct DigStep {
  bool in_soil = false;  // M below the current surface (template) / scoop carved soil (swept)
  double depth = 0.0;    // how far M is below the undisturbed surface (0 above it or off the grid)
  double volume = 0.0;   // scoop_volume after this state (m^3, cumulative along the plan)
};

struct DigSummary {
  std::string model;
  bool dug = false;                // some state took soil
  double dug_volume = 0.0;         // final scoop_volume (template: pit volume; swept: carved total)
  double collected_volume = 0.0;   // what the scoop holds: min(dug, capacity) (swept: before spill, carved into it)
  double spilled_volume = 0.0;     // swept: carved beyond capacity, put back as a rim
  double collected_mass = 0.0;     // kg: collected_volume * bulk_density
  bool over_capacity = false;      // more soil was taken than the scoop holds
  double deepest = 0.0;            // largest DigStep::depth
  std::size_t deepest_state = 0;
  Vec3 deepest_point = Vec3::Zero();  // M at that state
};

class Digger {
 public:
  // Loads the DEM (the undisturbed terrain); with the swept model, builds a
  // ray scene of the scoop mesh at its reference pose.
  explicit Digger(const Scene& scene);
  Digger(const Scene& scene, Dem undisturbed);
  ~Digger();

  const Dem& undisturbed() const { return base_; }
  const Vec3& origin() const { return origin_; }

  // Called after each state's dig with the state's index, the grid as dug so
  // far and a rectangle holding every sample that state changed (empty: none).
  using AfterState = std::function<void(std::size_t, const Dem&, const SampleRect&)>;

  // Digs one plan into `grid` (the terrain before the plan: undisturbed, or
  // the previous plan's result with --dig-carry). Sequential by nature.
  // The swept model's final relaxation (after the last state) is reported to
  // no state. volumes false (a walk that wants only the terrain): the
  // template model's pit volume, a sum over the whole grid after every
  // state in soil, is not taken (its steps' and summary's volumes are then
  // 0); the grid is dug the same.
  DigSummary dig_plan(const std::vector<std::vector<double>>& states, Dem& grid, std::vector<DigStep>& steps,
                      const AfterState& after_state = {}, bool volumes = true) const;

  // One template step with the scoop bottom at m; `start` is S (the plan's
  // starting grid). Returns whether M was below the surface; `changed`
  // receives the samples it may have changed.
  bool dig_template(Dem& grid, const Dem& start, const Vec3& m, SampleRect* changed = nullptr) const;

  // One swept step with the scoop posed by `pose`; `room` is what the scoop
  // can still take (m^3). Returns the carved volume; `taken` and `spilled`
  // split it.
  // `window` receives the carved cells' bounds grown by 2 (c0, r0, c1, r1)
  // so the caller can relax the cut once the scoop has left; `changed` the
  // samples it may have changed (carve, spill and relaxation).
  double dig_swept(Dem& grid, const Affine& pose, double room, double& taken, double& spilled,
                   std::array<int, 4>* window = nullptr, SampleRect* changed = nullptr) const;

  // Relaxes every slope steeper than `angle` in the window [c0, c1] x [r0, r1]
  // (grown while soil keeps moving at its edge). Samples marked in `held`
  // (the scoop's lower surface rests on them) neither give nor take soil:
  // the scoop holds the walls of its cut until it leaves. Returns the sweeps
  // made; `touched` receives the samples it may have changed (the final,
  // grown window and the neighbours its pairs reach).
  static int relax(Dem& grid, double angle, int c0, int r0, int c1, int r1,
                   const std::vector<unsigned char>* held = nullptr, SampleRect* touched = nullptr);

 private:
  const Scene& scene_;
  Dem base_;
  Vec3 origin_ = Vec3::Zero();
  std::unique_ptr<RayScene> scoop_rays_;  // swept model only
  Vec3 scoop_lo_ = Vec3::Zero(), scoop_hi_ = Vec3::Zero();  // scoop mesh box, reference pose
};

// Template volume bookkeeping: sum of max(S - Z, 0) * cellsize^2.
double pit_volume(const Dem& start, const Dem& now);
// Sum of Z * cellsize^2 over valid samples.
double soil_volume(const Dem& grid);

}  // namespace plancheck
