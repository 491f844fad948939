// SPDX-License-Identifier: MIT
#include "src/output/sweep_html.h"

#include "src/base/error.h"
#include "src/scene/kinematics.h"
#include "src/output/scene_page.h"

#include <algorithm>
#include <fstream>

namespace plancheck {

std::uint8_t sweep_verdict_code(Verdict v) {
  switch (v) {
    case Verdict::kSafe: return 0;
    case Verdict::kClearance: return 1;
    case Verdict::kCollision: return 2;
    default: return 3;
  }
}

namespace {

// Severity of a verdict code (sweep_verdict_code): safe < clearance < limits < collision.
constexpr int kSeverity[4] = {0, 1, 3, 2};

}  // namespace

SweepPageGrid pool_sweep_verdicts(const std::vector<SweepAxis>& axes, const std::vector<std::uint8_t>& verdicts,
                                  std::size_t max_cells) {
  SweepPageGrid g;
  const std::size_t n = axes.size();
  g.stride.assign(n, 1);
  g.count.resize(n);
  for (std::size_t k = 0; k < n; ++k) g.count[k] = axes[k].values.size();
  auto cells = [&] {
    std::size_t c = 1;
    for (std::size_t v : g.count) c *= v;
    return c;
  };
  // Halve the axis with the most cells until the grid fits.
  while (cells() > std::max<std::size_t>(max_cells, 1)) {
    const std::size_t k = static_cast<std::size_t>(std::max_element(g.count.begin(), g.count.end()) - g.count.begin());
    g.stride[k] *= 2;
    g.count[k] = (axes[k].values.size() + g.stride[k] - 1) / g.stride[k];
  }
  const std::size_t total = cells();
  g.codes.assign(total, 0);
  if (std::all_of(g.stride.begin(), g.stride.end(), [](std::size_t s) { return s == 1; })) {
    g.codes = verdicts;
    return g;
  }
  // Walk the configurations in grid order with their digits.
  std::vector<std::size_t> digit(n, 0), cell_stride(n, 1);
  for (std::size_t k = n; k-- > 1;) cell_stride[k - 1] = cell_stride[k] * g.count[k];
  for (std::size_t i = 0; i < verdicts.size(); ++i) {
    std::size_t cell = 0;
    for (std::size_t k = 0; k < n; ++k) cell += digit[k] / g.stride[k] * cell_stride[k];
    std::uint8_t& c = g.codes[cell];
    if (kSeverity[verdicts[i] & 3] > kSeverity[c & 3]) c = verdicts[i];
    for (std::size_t k = n; k-- > 0;) {
      if (++digit[k] < axes[k].values.size()) break;
      digit[k] = 0;
    }
  }
  return g;
}

void write_sweep_html(const Checker& checker, const Scene& scene, const std::vector<SweepAxis>& axes,
                      const std::vector<std::uint8_t>& verdicts, const SafeTargetSample& safe_targets,
                      const std::filesystem::path& dir) {
  PageJson sweep;
  {
    std::ifstream f(dir / "sweep.json");
    if (!f) fail(dir / "sweep.json", "cannot read");
    sweep = PageJson::parse(f);
  }
  // The page's own axes carry the values it shows (one per cell); the
  // values' lists of sweep.json (one per configuration) stay out of it.
  sweep.erase("axes");
  const PageFrame frame = page_frame(scene);
  const SweepPageGrid grid = pool_sweep_verdicts(axes, verdicts);
  PageJson page = {{"kind", "sweep"}, {"format", "plancheck-sweep-page/2"}, {"sweep", sweep}};
  page.update(scene_page_json(checker, scene, frame));

  PageJson jaxes = PageJson::array();
  for (std::size_t k = 0; k < axes.size(); ++k) {
    const SweepAxis& a = axes[k];
    std::vector<double> kept;
    for (std::size_t v = 0; v < a.values.size(); v += grid.stride[k]) kept.push_back(a.values[v]);
    jaxes.push_back({{"name", scene.parameter_names[static_cast<std::size_t>(a.parameter)]},
                     {"parameter", a.parameter},
                     {"count", grid.count[k]},
                     {"stride", grid.stride[k]},
                     {"values_total", a.values.size()},
                     {"values", kept}});
  }
  page["axes"] = jaxes;

  // Per action: its transform at the reference parameters, or one per value
  // of the one axis that drives it. An action driven by two swept
  // parameters (a free translation swept in x and y) is not posed: "arm": false.
  bool arm = true;
  PageJson actions = PageJson::array();
  for (const Action& act : scene.actions) {
    // A URDF mimic joint has no parameter of its own: its master's drives it.
    const Action& src = act.mimic >= 0 ? scene.actions[static_cast<std::size_t>(act.mimic)] : act;
    int axis = -1, driving = 0;
    for (std::size_t k = 0; k < axes.size(); ++k)
      if (axes[k].parameter >= src.first_parameter && axes[k].parameter < src.first_parameter + src.parameter_count) {
        axis = static_cast<int>(k);
        ++driving;
      }
    std::vector<double> params = scene.reference_parameters;
    std::vector<float> t;
    if (driving > 1) arm = false;
    if (axis < 0 || driving > 1) {
      PageFrame{}.affine(action_transform_at(scene, act, params), t);
      actions.push_back({{"axis", -1}, {"transforms", base64_array(t)}});
      continue;
    }
    const SweepAxis& a = axes[static_cast<std::size_t>(axis)];
    for (std::size_t v = 0; v < a.values.size(); v += grid.stride[static_cast<std::size_t>(axis)]) {
      params[static_cast<std::size_t>(a.parameter)] = a.values[v];
      PageFrame{}.affine(action_transform_at(scene, act, params), t);
    }
    actions.push_back({{"axis", axis}, {"transforms", base64_array(t)}});
  }
  // Chains compose action transforms in metres about the scene's origin;
  // the page maps the product to page coordinates (PageFrame::affine).
  page["actions"] = actions;
  page["arm"] = arm;
  page["verdicts"] = base64_array(grid.codes);
  // At most SafeTargetSample::kLimit points drawn (every stride-th safe configuration).
  const std::vector<Vec3>& kept = safe_targets.kept();
  const std::size_t stride = std::max<std::size_t>((kept.size() + SafeTargetSample::kLimit - 1) / SafeTargetSample::kLimit, 1);
  std::vector<float> targets;
  for (std::size_t i = 0; i < kept.size(); i += stride) {
    const Vec3 q = frame.point(kept[i]);
    for (int c = 0; c < 3; ++c) targets.push_back(static_cast<float>(q[c]));
  }
  page["safe_targets"] = base64_array(targets);
  page["safe_targets_stride"] = stride * safe_targets.stride();
  page["centre_m"] = point_json(frame.centre);
  page["unit_m"] = frame.unit;

  write_html_page(dir / "sweep.html", "plancheck sweep: " + sweep.value("scene", std::string()), page.dump());
}

}  // namespace plancheck
