// SPDX-License-Identifier: MIT
#include "src/checks/dig.h"

#include "src/scene/kinematics.h"

#include <algorithm>
#include <cmath>
#include <optional>

namespace plancheck {

namespace {

constexpr double kPi = 3.14159265358979323846;

std::size_t at(const Dem& g, int c, int r) { return static_cast<std::size_t>(r) * g.ncols + c; }

}  // namespace

double template_f(const ScoopTemplate& t, double x) {
  if (x < 0.0 || x > 1.0) return 0.0;
  if (x < t.rim_start) return t.pit;
  if (t.rim_start >= 1.0) return 0.0;
  return t.rim * std::sin(kPi * (x - t.rim_start) / (1.0 - t.rim_start));
}

double pit_volume(const Dem& start, const Dem& now) {
  double v = 0.0;
  for (std::size_t i = 0; i < now.z.size(); ++i)
    if (now.valid[i]) v += std::max(start.z[i] - now.z[i], 0.0);
  return v * now.cellsize * now.cellsize;
}

double soil_volume(const Dem& grid) {
  double v = 0.0;
  for (std::size_t i = 0; i < grid.z.size(); ++i)
    if (grid.valid[i]) v += grid.z[i];
  return v * grid.cellsize * grid.cellsize;
}

Digger::Digger(const Scene& scene) : Digger(scene, *scene.terrain->grid) {}

Digger::Digger(const Scene& scene, Dem undisturbed) : scene_(scene), base_(std::move(undisturbed)) {
  origin_ = scene.terrain ? scene.terrain->origin : Vec3::Zero();
  if (scene.scoop && scene.scoop->model == "swept") {
    const Mesh& m = scene.parts[static_cast<std::size_t>(scene.scoop->part_index)].mesh;
    scoop_rays_ = std::make_unique<RayScene>();
    scoop_rays_->add_mesh(m);
    scoop_rays_->commit();
    scoop_lo_ = Vec3::Constant(std::numeric_limits<double>::infinity());
    scoop_hi_ = -scoop_lo_;
    for (const Vec3& v : m.vertices) {
      scoop_lo_ = scoop_lo_.cwiseMin(v);
      scoop_hi_ = scoop_hi_.cwiseMax(v);
    }
  }
}

Digger::~Digger() = default;

bool Digger::dig_template(Dem& grid, const Dem& start, const Vec3& m, SampleRect* changed) const {
  const auto surface = dem_surface(grid, origin_, m.x(), m.y());
  if (!surface || !(m.z() < *surface)) return false;
  const ScoopConfig& sc = *scene_.scoop;
  const double w = sc.width, h = grid.cellsize;
  const double zm = m.z() - origin_.z();  // M in grid heights
  // Samples within W of M: a square of columns and rows, then the circle.
  const double u = (m.x() - origin_.x() - grid.x0) / h, v = (m.y() - origin_.y() - grid.y0) / h;
  const int c0 = std::max(0, static_cast<int>(std::floor(u - w / h))), c1 = std::min(grid.ncols - 1, static_cast<int>(std::ceil(u + w / h)));
  const int r0 = std::max(0, static_cast<int>(std::floor(v - w / h))), r1 = std::min(grid.nrows - 1, static_cast<int>(std::ceil(v + w / h)));
  if (changed) *changed = {c0, r0, c1, r1};
  for (int r = r0; r <= r1; ++r)
    for (int c = c0; c <= c1; ++c) {
      const std::size_t i = at(grid, c, r);
      if (!grid.valid[i]) continue;
      const double dx = origin_.x() + grid.x0 + c * h - m.x(), dy = origin_.y() + grid.y0 + r * h - m.y();
      const double l = std::sqrt(dx * dx + dy * dy);
      if (l > w) continue;
      const double x = l / w;
      const double f = template_f(sc.templ, x);
      if (x < sc.templ.rim_start) {
        const double d = grid.z[i] - zm;
        if (d > 0.0) grid.z[i] += d * f;
      } else if (grid.z[i] >= start.z[i]) {
        grid.z[i] = std::max(grid.z[i], start.z[i] + std::max(start.z[i] - zm, 0.0) * f);
      }
    }
  return true;
}

double Digger::dig_swept(Dem& grid, const Affine& pose, double room, double& taken, double& spilled,
                         std::array<int, 4>* window, SampleRect* changed) const {
  taken = spilled = 0.0;
  const double h = grid.cellsize, area = h * h;
  // The posed scoop's box bounds its footprint and its lowest point.
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (int k = 0; k < 8; ++k) {
    const Vec3 corner((k & 1) ? scoop_hi_.x() : scoop_lo_.x(), (k & 2) ? scoop_hi_.y() : scoop_lo_.y(),
                      (k & 4) ? scoop_hi_.z() : scoop_lo_.z());
    const Vec3 p = pose * corner;
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const auto col = [&](double x) { return (x - origin_.x() - grid.x0) / h; };
  const auto row = [&](double y) { return (y - origin_.y() - grid.y0) / h; };
  const int c0 = std::max(0, static_cast<int>(std::ceil(col(lo.x())))), c1 = std::min(grid.ncols - 1, static_cast<int>(std::floor(col(hi.x()))));
  const int r0 = std::max(0, static_cast<int>(std::ceil(row(lo.y())))), r1 = std::min(grid.nrows - 1, static_cast<int>(std::floor(row(hi.y()))));
  if (c0 > c1 || r0 > r1) return 0.0;
  // Nothing to carve when the scoop's lowest point is above every sample under it.
  double top = -std::numeric_limits<double>::infinity();
  for (int r = r0; r <= r1; ++r)
    for (int c = c0; c <= c1; ++c)
      if (grid.valid[at(grid, c, r)]) top = std::max(top, grid.z[at(grid, c, r)] + origin_.z());
  if (!(lo.z() < top)) return 0.0;

  // Vertical rays up through the scoop, cast in its reference frame (the
  // pose is rigid, so distances are unchanged).
  const Affine inv = pose.inverse();
  const double z_start = lo.z() - 1e-3, range = hi.z() - lo.z() + 2e-3;
  std::vector<Ray> rays;
  std::vector<std::size_t> cells;
  for (int r = r0; r <= r1; ++r)
    for (int c = c0; c <= c1; ++c) {
      const std::size_t i = at(grid, c, r);
      if (!grid.valid[i]) continue;
      const Vec3 o(origin_.x() + grid.x0 + c * h, origin_.y() + grid.y0 + r * h, z_start);
      rays.push_back({inv * o, inv.linear() * Vec3::UnitZ(), range});
      cells.push_back(i);
    }
  std::vector<RayHit> hits;
  scoop_rays_->intersect(rays, hits);

  std::vector<unsigned char> carved_mask;
  double carved = 0.0;
  int cc0 = grid.ncols, cc1 = -1, cr0 = grid.nrows, cr1 = -1;
  for (std::size_t k = 0; k < rays.size(); ++k) {
    if (!hits[k].hit) continue;
    const std::size_t i = cells[k];
    const double s = z_start + hits[k].distance - origin_.z();
    if (grid.z[i] <= s) continue;
    carved += (grid.z[i] - s) * area;
    grid.z[i] = s;
    if (carved_mask.empty()) carved_mask.assign(grid.z.size(), 0);
    carved_mask[i] = 1;
    const int c = static_cast<int>(i % static_cast<std::size_t>(grid.ncols)), r = static_cast<int>(i / static_cast<std::size_t>(grid.ncols));
    cc0 = std::min(cc0, c), cc1 = std::max(cc1, c), cr0 = std::min(cr0, r), cr1 = std::max(cr1, r);
  }
  if (carved <= 0.0) return 0.0;

  taken = std::min(carved, std::max(room, 0.0));
  spilled = carved - taken;
  if (spilled > 0.0) {
    // The overflow goes back on the ring of cells around the carved ones.
    std::vector<std::size_t> ring;
    for (int r = std::max(0, cr0 - 1); r <= std::min(grid.nrows - 1, cr1 + 1); ++r)
      for (int c = std::max(0, cc0 - 1); c <= std::min(grid.ncols - 1, cc1 + 1); ++c) {
        const std::size_t i = at(grid, c, r);
        if (!grid.valid[i] || carved_mask[i]) continue;
        bool next_to_carved = false;
        for (int dr = -1; dr <= 1 && !next_to_carved; ++dr)
          for (int dc = -1; dc <= 1; ++dc) {
            const int nc = c + dc, nr = r + dr;
            if (nc >= 0 && nr >= 0 && nc < grid.ncols && nr < grid.nrows && carved_mask[at(grid, nc, nr)]) {
              next_to_carved = true;
              break;
            }
          }
        if (next_to_carved) ring.push_back(i);
      }
    if (ring.empty()) {
      // Nowhere to spill (a carved patch walled in by holes): the scoop keeps it.
      taken = carved;
      spilled = 0.0;
    } else {
      const double dz = spilled / (area * static_cast<double>(ring.size()));
      for (std::size_t i : ring) grid.z[i] += dz;
    }
  }
  // The relaxation window holds the carved cells and the spill ring.
  relax(grid, scene_.scoop->repose_angle, cc0 - 2, cr0 - 2, cc1 + 2, cr1 + 2, &carved_mask, changed);
  if (window) *window = {cc0 - 2, cr0 - 2, cc1 + 2, cr1 + 2};
  return carved;
}

int Digger::relax(Dem& grid, double angle, int c0, int r0, int c1, int r1, const std::vector<unsigned char>* held,
                  SampleRect* touched) {
  const double h = grid.cellsize;
  const double limit_straight = std::tan(angle) * h, limit_diagonal = limit_straight * std::sqrt(2.0);
  // Each sample against its east, north, north-east and north-west neighbours
  // covers every 8-neighbour pair once.
  static constexpr int kDc[4] = {1, 0, 1, -1};
  static constexpr int kDr[4] = {0, 1, 1, 1};
  int sweeps = 0;
  for (; sweeps < 100000; ++sweeps) {
    c0 = std::max(c0, 0), r0 = std::max(r0, 0), c1 = std::min(c1, grid.ncols - 1), r1 = std::min(r1, grid.nrows - 1);
    bool moved = false, edge = false;
    for (int r = r0; r <= r1; ++r)
      for (int c = c0; c <= c1; ++c) {
        const std::size_t i = at(grid, c, r);
        if (!grid.valid[i] || (held && (*held)[i])) continue;
        for (int k = 0; k < 4; ++k) {
          const int nc = c + kDc[k], nr = r + kDr[k];
          if (nc < c0 - 1 || nc > c1 + 1 || nr > r1 + 1 || nc < 0 || nr >= grid.nrows || nc >= grid.ncols) continue;
          const std::size_t j = at(grid, nc, nr);
          if (!grid.valid[j] || (held && (*held)[j])) continue;
          const double limit = (kDc[k] != 0 && kDr[k] != 0) ? limit_diagonal : limit_straight;
          const double diff = grid.z[i] - grid.z[j];
          const double excess = std::abs(diff) - limit;
          if (excess <= kReposeTolerance) continue;
          // Equal areas: moving t of height from the higher to the lower cell
          // conserves volume; t = excess / 2 leaves the pair exactly at the angle.
          const double t = 0.5 * excess;
          if (diff > 0) grid.z[i] -= t, grid.z[j] += t;
          else grid.z[i] += t, grid.z[j] -= t;
          moved = true;
          if (r == r0 || r == r1 || c == c0 || c == c1 || nr > r1 || nc < c0 || nc > c1) edge = true;
        }
      }
    if (!moved) break;
    // Soil moving at the window's edge may steepen slopes just outside it.
    if (edge) --c0, --r0, ++c1, ++r1;
  }
  if (touched) {
    // Pairs reach one sample beyond the window on each side (clamped by refit).
    *touched = {std::max(c0, 0) - 1, std::max(r0, 0) - 1, std::min(c1, grid.ncols - 1) + 1,
                std::min(r1, grid.nrows - 1) + 1};
  }
  return sweeps;
}

DigSummary Digger::dig_plan(const std::vector<std::vector<double>>& states, Dem& grid, std::vector<DigStep>& steps,
                            const AfterState& after_state, bool volumes) const {
  DigSummary sum;
  steps.assign(states.size(), DigStep{});
  if (!scene_.scoop) return sum;
  const ScoopConfig& sc = *scene_.scoop;
  sum.model = sc.model;
  const bool swept = sc.model == "swept";
  const Dem start = grid;
  double volume = 0.0, carved_total = 0.0;
  // Swept: the cut whose walls the scoop still holds (a flag and a window
  // rather than std::optional, which GCC 12 misreads as maybe-uninitialised).
  bool holding = false;
  std::array<int, 4> cut{};
  for (std::size_t s = 0; s < states.size(); ++s) {
    const Affine pose = part_transform(scene_, sc.part_index, states[s]);
    const Vec3 m = pose * sc.bottom_point;
    DigStep& st = steps[s];
    SampleRect changed;
    if (const auto u = dem_surface(base_, origin_, m.x(), m.y())) st.depth = std::max(*u - m.z(), 0.0);
    if (swept) {
      double taken = 0.0, spilled = 0.0;
      std::array<int, 4> window{};
      const double carved = dig_swept(grid, pose, sc.capacity - volume, taken, spilled, &window, &changed);
      if (carved > 0.0) {
        st.in_soil = true;
        volume += taken;
        carved_total += carved;
        sum.spilled_volume += spilled;
        if (holding) {
          const auto& w = cut;
          window = {std::min(w[0], window[0]), std::min(w[1], window[1]), std::max(w[2], window[2]), std::max(w[3], window[3])};
        }
        cut = window;
        holding = true;
      } else if (holding) {
        // The scoop has left the cut: its walls relax now.
        relax(grid, sc.repose_angle, cut[0], cut[1], cut[2], cut[3], nullptr, &changed);
        holding = false;
      }
    } else if (dig_template(grid, start, m, &changed)) {
      st.in_soil = true;
      if (volumes) volume = pit_volume(start, grid);
    }
    st.volume = volume;
    if (after_state) after_state(s, grid, changed);
    if (st.depth > sum.deepest) {
      sum.deepest = st.depth;
      sum.deepest_state = s;
      sum.deepest_point = m;
    }
    sum.dug = sum.dug || st.in_soil;
  }
  if (holding) relax(grid, sc.repose_angle, cut[0], cut[1], cut[2], cut[3]);
  if (swept) {
    sum.dug_volume = carved_total;
    sum.collected_volume = volume;
    sum.over_capacity = sum.spilled_volume > 0.0;
  } else {
    sum.dug_volume = volume;
    sum.collected_volume = std::min(volume, sc.capacity);
    sum.over_capacity = volume > sc.capacity;
  }
  sum.collected_mass = sum.collected_volume * sc.bulk_density;
  return sum;
}

}  // namespace plancheck
