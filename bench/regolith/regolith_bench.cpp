// SPDX-License-Identifier: MIT
// Error against run time for digging and probes (issue 7), as plain tables:
//   plancheck_regolith_bench datasets/change5
// 1. An analytic dig: flat ground; the template model with M at a known
//    depth (pit volume pi r^2 d) and the swept model with a box scoop pushed
//    to that depth (footprint area x d), per grid resolution.
// 2. The default plan01 on its site resampled to each resolution: collected
//    volume, error against the finest grid, time per state, both models.
// 3. Probes: rays per second over every state of the default plans, and the
//    clearance error of a downward fan of 8/32/128 rays at the scoop bottom
//    against the exact distance from that point to the terrain mesh.
#include "src/checks/dig.h"
#include "src/scene/kinematics.h"
#include "src/scene/plan.h"
#include "src/checks/probes.h"
#include "src/geometry/raycast.h"
#include "src/scene/scene_loader.h"
#include "src/scene/terrain.h"

#include "kernels/tri_distance.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

namespace {

using namespace plancheck;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

constexpr double kPi = 3.14159265358979323846;
const double kResolutions[] = {0.08, 0.04, 0.02, 0.01, 0.005};

// A bench that prints a wrong answer measures nothing: stop with status 3.
void require(bool ok, const std::string& what) {
  if (ok) return;
  std::fprintf(stderr, "plancheck_regolith_bench: wrong answer: %s\n", what.c_str());
  std::exit(3);
}

double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

Dem flat_grid(double extent, double h, double z) {
  Dem d;
  d.ncols = d.nrows = static_cast<int>(std::lround(extent / h));
  d.cellsize = h;
  d.x0 = d.y0 = 0.5 * h;
  d.z.assign(static_cast<std::size_t>(d.ncols) * d.nrows, z);
  d.valid.assign(d.z.size(), 1);
  return d;
}

// The site resampled at cell h over the same extent (heights from the mesh surface).
Dem resample(const Dem& src, const Vec3& origin, double h) {
  const double ex = (src.ncols - 1) * src.cellsize, ey = (src.nrows - 1) * src.cellsize;
  Dem d;
  d.ncols = static_cast<int>(std::floor(ex / h)) + 1;
  d.nrows = static_cast<int>(std::floor(ey / h)) + 1;
  d.cellsize = h;
  d.x0 = src.x0;
  d.y0 = src.y0;
  d.z.assign(static_cast<std::size_t>(d.ncols) * d.nrows, 0.0);
  d.valid.assign(d.z.size(), 1);
  for (int r = 0; r < d.nrows; ++r)
    for (int c = 0; c < d.ncols; ++c) {
      const auto z = dem_surface(src, origin, origin.x() + d.x0 + c * h, origin.y() + d.y0 + r * h);
      const std::size_t i = static_cast<std::size_t>(r) * d.ncols + c;
      if (z) d.z[i] = *z - origin.z();
      else d.valid[i] = 0;
    }
  return d;
}

void analytic(const Scene& site) {
  std::printf("\n## Analytic dig: flat ground, depth 3 cm\n");
  std::printf("template: M 3 cm deep, pit radius rim_start*W = %.3f m, exact pi r^2 d\n",
              site.scoop->templ.rim_start * site.scoop->width);
  std::printf("swept: box scoop 10 x 6 cm pushed 3 cm deep, exact 0.1*0.06*d (before repose)\n");
  std::printf("| cell (cm) | template volume (cm^3) | rel. error | swept carved (cm^3) | rel. error | template ms/state | swept ms/state |\n|---|---|---|---|---|---|---|\n");
  const double d = 0.03;
  for (double h : kResolutions) {
    Scene s = site;
    s.scoop->templ.rim = 0.0;
    s.terrain->origin = Vec3::Zero();
    // Template.
    const Digger tdig(s, flat_grid(0.64, h, 0.0));
    const double r = s.scoop->templ.rim_start * s.scoop->width;
    double tv = 0.0;
    const int reps = 20;
    auto t0 = Clock::now();
    for (int k = 0; k < reps; ++k) {
      Dem g = tdig.undisturbed();
      const Dem start = g;
      tdig.dig_template(g, start, Vec3(0.3137, 0.3071, -d));  // off the lattice: no sample favoured
      tv = pit_volume(start, g);
    }
    const double tms = 1e3 * since(t0) / reps;
    const double texact = kPi * r * r * d;
    // Swept: a box scoop.
    Scene sw = s;
    sw.scoop->model = "swept";
    sw.parts[static_cast<std::size_t>(sw.scoop->part_index)].mesh = [] {
      Mesh m;
      for (int k = 0; k < 8; ++k)
        m.vertices.emplace_back((k & 1) ? 0.05 : -0.05, (k & 2) ? 0.03 : -0.03, (k & 4) ? 0.05 : 0.0);
      const Tri t[12] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                         {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
      m.triangles.assign(t, t + 12);
      return m;
    }();
    const Digger sdig(sw, flat_grid(0.64, h, 0.0));
    double sv = 0.0;
    t0 = Clock::now();
    for (int k = 0; k < reps; ++k) {
      Dem g = sdig.undisturbed();
      Affine pose = Affine::Identity();
      pose.translation() = Vec3(0.3137, 0.3071, -d);
      double taken = 0, spilled = 0;
      sv = sdig.dig_swept(g, pose, 1.0, taken, spilled);
    }
    const double sms = 1e3 * since(t0) / reps;
    const double sexact = 0.1 * 0.06 * d;
    // On cells of 2 cm and finer the box's footprint covers whole cells, so
    // the carved volume is exact (to Embree's single precision).
    require(tv > 0.0 && sv > 0.0, "nothing dug on the flat ground");
    if (h <= 0.02 + 1e-12)
      require(std::abs(sv / sexact - 1.0) < 1e-4, "box scoop carved " + std::to_string(sv) + " m^3 at cell " +
                                                      std::to_string(h) + " m, exact " + std::to_string(sexact));
    std::printf("| %.1f | %.3f | %+.4f | %.3f | %+.4f | %.3f | %.3f |\n", h * 100, tv * 1e6, tv / texact - 1,
                sv * 1e6, sv / sexact - 1, tms, sms);
  }
}

void site_plans(const Scene& site, const fs::path& dir) {
  std::printf("\n## plan01 on the site resampled per resolution (error against 0.5 cm)\n");
  std::printf("| model | cell (cm) | collected (cm^3) | error vs finest | depth (cm) | ms/state (all states) |\n|---|---|---|---|---|---|\n");
  const Plan plan = load_plan(site, dir / "plans/plan01.csv");
  const Dem& src = *site.terrain->grid;
  for (const std::string model : {"template", "swept"}) {
    Scene s = site;
    s.scoop->model = model;
    std::vector<std::pair<double, DigSummary>> rows;
    std::vector<double> ms;
    for (double h : kResolutions) {
      const Digger digger(s, resample(src, s.terrain->origin, h));
      Dem g = digger.undisturbed();
      std::vector<DigStep> steps;
      const auto t0 = Clock::now();
      rows.emplace_back(h, digger.dig_plan(plan.states, g, steps));
      ms.push_back(1e3 * since(t0) / static_cast<double>(plan.states.size()));
    }
    const double finest = rows.back().second.dug_volume;
    for (std::size_t k = 0; k < rows.size(); ++k)
      std::printf("| %s | %.1f | %.2f | %+.4f | %.2f | %.4f |\n", model.c_str(), rows[k].first * 100,
                  rows[k].second.dug_volume * 1e6, rows[k].second.dug_volume / finest - 1,
                  rows[k].second.deepest * 100, ms[k]);
  }
  std::printf("(collected = dug volume here: template pit volume, swept carved volume, before the capacity cap)\n");
}

void probes(const Scene& site, const fs::path& dir) {
  std::printf("\n## Probes\n");
  std::vector<Plan> plans;
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dir / "plans")) files.push_back(e.path());
  std::sort(files.begin(), files.end());  // plan01 first, whatever the directory order
  for (const auto& f : files) plans.push_back(load_plan(site, f));
  const ProbeCaster caster(site);
  std::size_t states = 0;
  for (const Plan& p : plans) states += p.states.size();
  for (int threads : {1, 2}) {
    std::vector<std::vector<ProbeReading>> out;
    const auto t0 = Clock::now();
    for (const Plan& p : plans) caster.cast(p.states, threads, out);
    const double s = since(t0);
    std::printf("scene probes: %zu states x %zu rays, %d thread(s): %.3f s, %.3g rays/s\n", states,
                caster.rays_per_state(), threads, s, static_cast<double>(states * caster.rays_per_state()) / s);
  }

  // Fan clearance against the exact point-to-terrain distance.
  const Dem& dem = *site.terrain->grid;
  const Mesh terrain = dem_mesh(dem, site.terrain->origin);
  RayScene rs;
  rs.add_mesh(terrain);
  rs.commit();
  const Plan& plan = plans.front();
  std::printf("fan at the scoop bottom (1 mm above M), pointing down, half angle 60 deg, %s states with M above ground:\n",
              plan.name.c_str());
  std::printf("| rays | mean error (mm) | max error (mm) | rays/s |\n|---|---|---|---|\n");
  std::vector<Vec3> origins;
  std::vector<double> exact;
  for (const auto& st : plan.states) {
    const Affine t = part_transform(site, site.scoop->part_index, st);
    const Vec3 o = t * (site.scoop->bottom_point + Vec3(0, 0, 0.001));
    const auto z = dem_surface(dem, site.terrain->origin, o.x(), o.y());
    if (!z || o.z() <= *z || o.z() > *z + 1.0) continue;  // over the site, above ground, within 1 m
    double best = 1e300;
    const double p9[9] = {o.x(), o.y(), o.z(), o.x(), o.y(), o.z(), o.x(), o.y(), o.z()};
    for (const Tri& tri : terrain.triangles) {
      double q9[9];
      for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 3; ++j) q9[3 * k + j] = terrain.vertices[tri[static_cast<std::size_t>(k)]][j];
      best = std::min(best, tri_distance(p9, q9).distance);
    }
    origins.push_back(o);
    exact.push_back(best);
  }
  for (int n : {8, 32, 128}) {
    ProbeConfig p;
    p.direction = -Vec3::UnitZ();
    p.fan_count = n;
    p.fan_half_angle = 60.0 * kPi / 180.0;
    const auto dirs = ProbeCaster::fan_directions(p);
    std::vector<Ray> rays;
    for (const Vec3& o : origins)
      for (const Vec3& d : dirs) rays.push_back({o, d, 3.0});
    std::vector<RayHit> hits;
    const auto t0 = Clock::now();
    rs.intersect(rays, hits);
    const double s = since(t0);
    double sum = 0, worst = 0;
    for (std::size_t i = 0; i < origins.size(); ++i) {
      double m = 3.0;
      for (int k = 0; k < n; ++k) m = std::min(m, hits[i * n + k].distance);
      // A ray's first hit is never nearer than the nearest terrain point.
      require(m >= exact[i] - 1e-5, "fan clearance below the exact distance at state " + std::to_string(i));
      sum += m - exact[i];
      worst = std::max(worst, m - exact[i]);
    }
    std::printf("| %d | %.3f | %.3f | %.3g |\n", n, 1e3 * sum / origins.size(), 1e3 * worst,
                static_cast<double>(rays.size()) / s);
  }
  std::printf("(%zu states)\n", origins.size());
}

}  // namespace

int main(int argc, char** argv) {
  const fs::path dir = argc > 1 ? fs::path(argv[1]) : fs::path("datasets/change5");
  const Scene site = load_scene(dir / "scene.json");
  analytic(site);
  site_plans(site, dir);
  probes(site, dir);
  return 0;
}
