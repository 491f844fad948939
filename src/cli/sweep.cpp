// SPDX-License-Identifier: MIT
#include "src/output/sweep_html.h"
#include "src/base/progress.h"
#include "src/cli/sweep.h"

#include "src/base/error.h"
#include "src/base/parallel.h"
#include "src/scene/plan.h"
#include "src/checks/verify.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <ostream>

#include "src/scene/scene_loader.h"

namespace plancheck {

namespace {

using Json = nlohmann::ordered_json;

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

std::string num(double v) {
  if (!std::isfinite(v)) return "";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.12g", v);
  return buf;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// One configuration's outcome, as much of the state check as the CSV keeps.
struct Row {
  Verdict verdict = Verdict::kSafe;
  bool collision = false;
  int part_a = -1, part_b = -1;  // the closest pair, or the first colliding one
  double min_distance = 0.0;     // m
  Vec3 target = Vec3::Zero();    // m
};

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
    if (item.empty()) {
      if (comma == grid.size() && !axes.empty()) break;
      throw InputError("--grid: empty item in '" + grid + "' (expected NAME=FROM:TO:STEP,...)");
    }
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
    if (!(n < static_cast<double>(kMaxSweepConfigurations)))
      grid_error(item, "more than " + std::to_string(kMaxSweepConfigurations) + " values");
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

int run_sweep(const SweepArgs& args, std::ostream& out, std::ostream& err) {
  const auto t_load = std::chrono::steady_clock::now();
  err << "plancheck: loading " << args.scene.string() << "\n";
  const Scene scene = load_scene(args.scene, args.scene_options);
  std::vector<SweepAxis> axes;
  if (args.grid && args.steps) throw InputError("--grid and --steps cannot be used together");
  if (args.grid)
    axes = sweep_axes_from_grid(scene, *args.grid);
  else
    axes = sweep_axes_from_steps(scene, args.steps.value_or(9));
  std::size_t total = 1;
  for (const SweepAxis& a : axes) {
    if (a.values.empty() || total > kMaxSweepConfigurations / a.values.size())
      throw InputError("sweep of more than " + std::to_string(kMaxSweepConfigurations) +
                       " configurations; use fewer steps or a coarser --grid");
    total *= a.values.size();
  }
  const double load_seconds = seconds_since(t_load);

  const int threads = args.threads > 0 ? args.threads : hardware_threads();
  const auto t_build = std::chrono::steady_clock::now();
  err << "plancheck: building collision structures\n";
  const Checker checker(scene, threads);
  const double build_seconds = seconds_since(t_build);

  std::error_code ec;
  std::filesystem::remove(args.out / "sweep.json", ec);
  std::filesystem::create_directories(args.out, ec);
  if (ec) throw InputError(args.out.string() + ": cannot create the folder (" + ec.message() + ")");
  const std::filesystem::path csv_path = args.out / "sweep.csv";
  const std::filesystem::path csv_tmp = csv_path.string() + ".tmp";
  std::ofstream csv(csv_tmp, std::ios::binary | std::ios::trunc);
  if (!csv) throw InputError(csv_tmp.string() + ": cannot write");
  for (const SweepAxis& a : axes) csv << scene.parameter_names[static_cast<std::size_t>(a.parameter)] << ",";
  csv << "verdict,collision,min_distance,part_a,part_b,target_x,target_y,target_z\n";

  err << "plancheck: checking " << total << " configurations on " << threads << " threads\n";
  const double unit = scene.length_scale;
  const double margin = scene.safety_margin;
  std::map<Verdict, std::size_t> counts;
  std::map<std::pair<int, int>, std::size_t> colliding_pairs;
  // Per axis and value: how many configurations with that value are safe.
  std::vector<std::vector<std::size_t>> safe_by_value(axes.size());
  for (std::size_t k = 0; k < axes.size(); ++k) safe_by_value[k].assign(axes[k].values.size(), 0);
  Row closest;
  closest.min_distance = std::numeric_limits<double>::infinity();
  std::size_t closest_index = 0;
  Vec3 reach_lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 reach_hi = -reach_lo;

  // Odometer order, the last axis fastest: neighbours in the order are
  // neighbours on the grid, so each check seeds the next (coherence).
  auto decode = [&](std::size_t index, std::vector<double>& params, std::vector<std::size_t>* digits) {
    params = scene.reference_parameters;
    for (std::size_t k = axes.size(); k-- > 0;) {
      const std::size_t n = axes[k].values.size();
      const std::size_t d = index % n;
      index /= n;
      params[static_cast<std::size_t>(axes[k].parameter)] = axes[k].values[d];
      if (digits) (*digits)[k] = d;
    }
  };

  // The CSV names one colliding pair per configuration and no triangles.
  CheckRequest request;
  request.max_triangle_pairs = 0;
  request.all_contacts = false;
  const auto t_check = std::chrono::steady_clock::now();
  Progress progress("sweep", total, "configurations", ProgressOptions{.quiet = args.quiet}, &err);
  constexpr std::size_t kBlock = std::size_t{1} << 16;  // rows held before writing
  constexpr std::size_t kRun = 32;                      // states seeded in order
  std::vector<Row> rows;
  std::vector<std::uint8_t> page_verdicts;  // --html: every configuration's verdict, the safe ones' targets
  std::vector<Vec3> page_targets;
  std::vector<double> params;
  std::vector<std::size_t> digits(axes.size());
  for (std::size_t block = 0; block < total; block += kBlock) {
    const std::size_t n = std::min(kBlock, total - block);
    rows.assign(n, Row{});
    parallel_for((n + kRun - 1) / kRun, threads, 1, [&](std::size_t rb, std::size_t re, int) {
      std::vector<double> p;
      StateResult st;
      for (std::size_t r = rb; r < re; ++r) {
        StateSeed seed;
        for (std::size_t i = r * kRun; i < std::min(n, (r + 1) * kRun); ++i) {
          decode(block + i, p, nullptr);
          checker.check_state(p, st, request, &seed);
          Row& row = rows[i];
          row.verdict = state_verdict(st, margin);
          row.collision = st.collision;
          row.min_distance = st.min_distance;
          if (st.collision) {
            row.part_a = st.contacts[0].part_a;
            row.part_b = st.contacts[0].part_b;
          } else {
            row.part_a = st.part_a;
            row.part_b = st.part_b;
          }
          row.target = checker.target_point(p);
        }
        progress.add(std::min(n, (r + 1) * kRun) - r * kRun);
      }
    });
    for (std::size_t i = 0; i < n; ++i) {
      const Row& row = rows[i];
      decode(block + i, params, &digits);
      ++counts[row.verdict];
      if (row.collision) {
        // Every colliding pair of the state would need the contacts kept;
        // the first is what the row names.
        ++colliding_pairs[{row.part_a, row.part_b}];
      } else if (row.part_a >= 0 && row.min_distance < closest.min_distance) {
        closest = row;
        closest_index = block + i;
      }
      if (args.html) page_verdicts.push_back(sweep_verdict_code(row.verdict));
      if (row.verdict == Verdict::kSafe) {
        if (args.html) page_targets.push_back(row.target);
        for (std::size_t k = 0; k < axes.size(); ++k) ++safe_by_value[k][digits[k]];
        reach_lo = reach_lo.cwiseMin(row.target);
        reach_hi = reach_hi.cwiseMax(row.target);
      }
      for (std::size_t k = 0; k < axes.size(); ++k)
        csv << num(params[static_cast<std::size_t>(axes[k].parameter)]) << ",";
      csv << verdict_name(row.verdict) << "," << (row.collision ? 1 : 0) << ","
          << num(row.collision ? 0.0 : row.min_distance / unit) << ","
          << (row.part_a >= 0 ? checker.part_name(row.part_a) : "") << ","
          << (row.part_b >= 0 ? checker.part_name(row.part_b) : "") << "," << num(row.target.x() / unit) << ","
          << num(row.target.y() / unit) << "," << num(row.target.z() / unit) << "\n";
    }
  }
  progress.finish();
  const double check_seconds = seconds_since(t_check);
  if (!csv.flush()) throw InputError(csv_tmp.string() + ": write failed");
  csv.close();
  std::filesystem::rename(csv_tmp, csv_path);

  // Summary: report.json's conventions (lengths in length_unit, null for none).
  const std::size_t safe = counts[Verdict::kSafe];
  Json j;
  j["format"] = "plancheck-sweep/1";
  j["scene"] = args.scene.string();
  j["safety_margin"] = margin / unit;
  j["threads"] = threads;
  j["left_out"] = {{"static_triangles", checker.left_out_static_triangles()},
                   {"reason", "beyond reach of the moving parts"}};
  Json jaxes = Json::array();
  for (std::size_t k = 0; k < axes.size(); ++k) {
    const SweepAxis& a = axes[k];
    Json values = Json::array(), safe_counts = Json::array();
    for (std::size_t v = 0; v < a.values.size(); ++v) {
      values.push_back(a.values[v]);
      safe_counts.push_back(safe_by_value[k][v]);
    }
    jaxes.push_back({{"name", scene.parameter_names[static_cast<std::size_t>(a.parameter)]},
                     {"spec", a.spec},
                     {"values", values},
                     {"safe_configurations", safe_counts}});
  }
  j["axes"] = jaxes;
  j["configurations"] = total;
  j["counts"] = {{"safe", safe},
                 {"collision", counts[Verdict::kCollision]},
                 {"clearance", counts[Verdict::kClearance]},
                 {"limits", counts[Verdict::kLimits]}};
  Json jpairs = Json::array();
  std::vector<std::pair<std::size_t, std::pair<int, int>>> by_count;
  for (const auto& [pair, c] : colliding_pairs) by_count.push_back({c, pair});
  std::stable_sort(by_count.begin(), by_count.end(), [](const auto& x, const auto& y) { return x.first > y.first; });
  for (const auto& [c, pair] : by_count)
    jpairs.push_back({{"parts", {checker.part_name(pair.first), checker.part_name(pair.second)}},
                      {"configurations", c}});
  j["colliding_pairs"] = jpairs;
  if (std::isfinite(closest.min_distance)) {
    decode(closest_index, params, nullptr);
    Json at = Json::object();
    for (const SweepAxis& a : axes)
      at[scene.parameter_names[static_cast<std::size_t>(a.parameter)]] =
          params[static_cast<std::size_t>(a.parameter)];
    j["min_distance"] = {{"distance", closest.min_distance / unit},
                         {"parts", {checker.part_name(closest.part_a), checker.part_name(closest.part_b)}},
                         {"at", at}};
  } else {
    j["min_distance"] = nullptr;
  }
  if (safe > 0)
    j["safe_target_box"] = {{"min", {reach_lo.x() / unit, reach_lo.y() / unit, reach_lo.z() / unit}},
                            {"max", {reach_hi.x() / unit, reach_hi.y() / unit, reach_hi.z() / unit}}};
  else
    j["safe_target_box"] = nullptr;
  j["seconds"] = {{"load", load_seconds}, {"build", build_seconds}, {"check", check_seconds}};
  {
    const std::filesystem::path tmp = (args.out / "sweep.json").string() + ".tmp";
    std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
    f << j.dump(2) << "\n";
    if (!f.flush()) throw InputError(tmp.string() + ": write failed");
    f.close();
    std::filesystem::rename(tmp, args.out / "sweep.json");
  }

  std::filesystem::remove(args.out / "sweep.html", ec);
  if (args.html) write_sweep_html(checker, scene, axes, page_verdicts, page_targets, args.out);

  // stdout: the summary in a few lines.
  auto pct = [&](std::size_t c) { return num(std::round(1000.0 * static_cast<double>(c) / static_cast<double>(total)) / 10.0); };
  out << "sweep: " << total << " configurations over";
  for (const SweepAxis& a : axes)
    out << " " << scene.parameter_names[static_cast<std::size_t>(a.parameter)] << "(" << a.values.size() << ")";
  out << "\n";
  out << "  safe " << safe << " (" << pct(safe) << "%), collision " << counts[Verdict::kCollision] << ", clearance "
      << counts[Verdict::kClearance] << ", limits " << counts[Verdict::kLimits] << "\n";
  for (std::size_t i = 0; i < std::min<std::size_t>(5, by_count.size()); ++i)
    out << "  collides: " << checker.part_name(by_count[i].second.first) << " / "
        << checker.part_name(by_count[i].second.second) << " in " << by_count[i].first << " configurations\n";
  if (std::isfinite(closest.min_distance))
    out << "  closest without contact: " << num(closest.min_distance / unit) << " " << scene.length_unit << " ("
        << checker.part_name(closest.part_a) << " / " << checker.part_name(closest.part_b) << ")\n";
  if (safe > 0)
    out << "  safe target reach (" << scene.length_unit << "): x " << num(reach_lo.x() / unit) << " .. "
        << num(reach_hi.x() / unit) << ", y " << num(reach_lo.y() / unit) << " .. " << num(reach_hi.y() / unit)
        << ", z " << num(reach_lo.z() / unit) << " .. " << num(reach_hi.z() / unit) << "\n";
  char line[160];
  std::snprintf(line, sizeof line, "%zu configurations, %.3f s (load %.3f, build %.3f, check %.3f), %d threads\n",
                total, load_seconds + build_seconds + check_seconds, load_seconds, build_seconds, check_seconds,
                threads);
  out << line;
  return 0;
}

}  // namespace plancheck
