// SPDX-License-Identifier: MIT
// The sweep grid (src/checks/sweep_grid.h): axes from the limits or from --grid.
#include "src/checks/sweep_grid.h"

#include "src/base/error.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

namespace plancheck {
namespace {

const Action* parameter_action(const Scene& scene, int parameter) {
  for (const Action& a : scene.actions)
    if (parameter >= a.first_parameter && parameter < a.first_parameter + a.parameter_count) return &a;
  return nullptr;
}

[[noreturn]] void grid_error(const std::string& item, const std::string& what) {
  throw InputError("--grid: '" + item + "': " + what);
}

double parse_number(const std::string& item, const std::string& text, const char* which) {
  double v = 0.0;
  const char* b = text.data();
  const char* e = text.data() + text.size();
  while (b < e && *b == ' ') ++b;
  while (e > b && e[-1] == ' ') --e;
  if (b < e && *b == '+') ++b;
  const auto [ptr, ec] = std::from_chars(b, e, v);
  if (b == e || ec != std::errc() || ptr != e || !std::isfinite(v))
    grid_error(item, std::string(which) + " '" + text + "' is not a finite number");
  return v;
}

std::string trim(std::string s) {
  const auto b = s.find_first_not_of(' ');
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(' ') - b + 1);
}

}  // namespace

std::vector<SweepAxis> sweep_axes_from_steps(const Scene& scene, long steps) {
  if (steps < 2) throw InputError("--steps: " + std::to_string(steps) + " is below 2 (the two ends of each range)");
  std::vector<SweepAxis> axes;
  for (std::size_t p = 0; p < scene.parameter_names.size(); ++p) {
    const Action* a = parameter_action(scene, static_cast<int>(p));
    if (!a || !a->has_limits) continue;
    SweepAxis axis;
    axis.parameter = static_cast<int>(p);
    axis.spec = "limits";
    // Values straight from the limits (as written), the ends exact: a value
    // rounded past a limit would show as a limits violation that is not there.
    const double lo = a->lower, hi = a->upper;
    for (long i = 0; i < steps; ++i) {
      const double t = static_cast<double>(i) / static_cast<double>(steps - 1);
      double v = i == 0 ? lo : i == steps - 1 ? hi : lo + (hi - lo) * t;
      axis.values.push_back(std::clamp(v, lo, hi));
    }
    axes.push_back(std::move(axis));
  }
  if (axes.empty())
    throw InputError(scene.file.string() + ": no driving parameter has limits, so --steps has no ranges; use --grid");
  return axes;
}

std::vector<SweepAxis> sweep_axes_from_grid(const Scene& scene, const std::string& grid) {
  std::vector<SweepAxis> axes;
  std::size_t start = 0;
  while (start <= grid.size()) {
    const std::size_t comma = std::min(grid.find(',', start), grid.size());
    const std::string item = trim(grid.substr(start, comma - start));
    start = comma + 1;
    if (item.empty())  // a trailing comma too: a parameter may have been lost there
      throw InputError("--grid: empty item in '" + grid + "' (expected NAME=FROM:TO:STEP,...)");
    const std::size_t eq = item.find('=');
    if (eq == std::string::npos) grid_error(item, "expected NAME=FROM:TO:STEP");
    const std::string name = trim(item.substr(0, eq));
    int parameter = -1;
    for (std::size_t p = 0; p < scene.parameter_names.size(); ++p)
      if (scene.parameter_names[p] == name) parameter = static_cast<int>(p);
    if (parameter < 0) grid_error(item, "'" + name + "' is not a driving parameter of the scene");
    for (const SweepAxis& a : axes)
      if (a.parameter == parameter) grid_error(item, "'" + name + "' is given twice");
    const std::string range = item.substr(eq + 1);
    const std::size_t c1 = range.find(':');
    const std::size_t c2 = c1 == std::string::npos ? c1 : range.find(':', c1 + 1);
    if (c2 == std::string::npos || range.find(':', c2 + 1) != std::string::npos)
      grid_error(item, "expected FROM:TO:STEP after '='");
    const double from = parse_number(item, range.substr(0, c1), "FROM");
    const double to = parse_number(item, range.substr(c1 + 1, c2 - c1 - 1), "TO");
    const double step = parse_number(item, range.substr(c2 + 1), "STEP");
    if (to < from) grid_error(item, "TO is below FROM");
    if (!(step > 0.0)) grid_error(item, "STEP must be positive");
    // The last value is FROM + k STEP <= TO, with a slack of 1e-9 steps so
    // that decimal steps (0.1) reach a TO they land on.
    const double n = std::floor((to - from) / step + 1e-9);
    if (!(n < static_cast<double>(kMaxSweepAxisValues)))
      grid_error(item, "more than " + std::to_string(kMaxSweepAxisValues) + " values");
    SweepAxis axis;
    axis.parameter = parameter;
    const Action* owner = parameter_action(scene, parameter);
    const bool factor = owner && owner->type == ActionType::kScale;
    axis.spec = item;
    for (long i = 0; i <= static_cast<long>(n); ++i) {
      const double v = std::min(to, from + step * static_cast<double>(i));
      if (factor && !(v > 0.0)) grid_error(item, "scale factors must be positive");
      axis.values.push_back(v);  // as written, like a plan column
    }
    axes.push_back(std::move(axis));
  }
  return axes;
}

SweepBlocks::SweepBlocks(const std::vector<std::size_t>& grid_shape) : shape(grid_shape) {
  // About 2^16 configurations a block: 16 values an axis in 4 axes, 256 in
  // 2; at least 2 an axis, so a block always spans some motion.
  const std::size_t d = shape.size();
  std::size_t e = 2;
  if (d > 0) {
    e = static_cast<std::size_t>(std::floor(std::pow(65536.0, 1.0 / static_cast<double>(d)) + 1e-9));
    e = std::max<std::size_t>(e, 2);
  }
  for (std::size_t n : shape) {
    edge.push_back(std::min(e, std::max<std::size_t>(n, 1)));
    count.push_back((n + edge.back() - 1) / edge.back());
    blocks *= count.back();
  }
}

void SweepBlocks::block(std::size_t b, std::vector<std::size_t>& first, std::vector<std::size_t>& size) const {
  const std::size_t d = shape.size();
  first.resize(d);
  size.resize(d);
  for (std::size_t k = d; k-- > 0;) {
    const std::size_t i = b % count[k];
    b /= count[k];
    first[k] = i * edge[k];
    size[k] = std::min(edge[k], shape[k] - first[k]);
  }
}

}  // namespace plancheck
