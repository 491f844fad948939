// SPDX-License-Identifier: MIT
// What report.html and sweep.html share: page coordinates, the scene's
// geometry sent once (positions float32, indices uint32, base64), the part
// tree, probes and the terrain's DEM.
#pragma once

#include "src/output/html_page.h"
#include "src/scene/terrain.h"
#include "src/geometry/heightfield.h"
#include "src/checks/verify.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdint>
#include <vector>

namespace plancheck {

using PageJson = nlohmann::ordered_json;

// Page coordinates: the scene's length_unit, shifted by `centre` (metres) so
// float32 keeps its precision in scenes placed far from their origin.
struct PageFrame {
  Vec3 centre = Vec3::Zero();
  double unit = 1.0;  // metres per length_unit
  Vec3 point(const Vec3& p) const { return (p - centre) / unit; }
  // The same motion in page coordinates, y -> R y + (R c + t - c) / unit,
  // appended as 12 floats, row-major 3 x 4.
  void affine(const Affine& t, std::vector<float>& out) const;
};

// The centre of the parts' reference boxes, in the scene's length unit.
PageFrame page_frame(const Scene& scene);

template <class T>
std::string base64_array(const std::vector<T>& v) {
  return base64(v.data(), v.size() * sizeof(T));
}

// Values (NaN: none) in `stride` components, each quantized to 16 bits over
// its own range: {"lo": [...], "step": [...], "q": base64 uint16}, value =
// lo + q * step, q = 65535 for NaN. The error is at most step / 2: for what
// is drawn (points, heights, ray lengths), never for what is judged.
PageJson quantized_json(const std::vector<float>& values, int stride);

// Small integers (part indices, probe hits) as int16 when they all fit,
// else int32: {"i16": base64} or {"i32": base64}.
PageJson ints_json(const std::vector<std::int32_t>& values);

inline PageJson number_or_null(double v) { return std::isfinite(v) ? PageJson(v) : PageJson(nullptr); }
inline PageJson point_json(const Vec3& p) { return PageJson::array({p.x(), p.y(), p.z()}); }

// Heights of the samples in `rect` in page coordinates (NaN: no data), base64 float32.
PageJson dem_rect_json(const Dem& dem, const Vec3& origin, const PageFrame& frame, const SampleRect& rect);

// The scene part of a page: units, names, part tree, geometry, probes, the
// terrain as its DEM gives it (no terrain: null).
PageJson scene_page_json(const Checker& checker, const Scene& scene, const PageFrame& frame);

}  // namespace plancheck
