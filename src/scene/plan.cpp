// SPDX-License-Identifier: MIT
// Plan CSV -> states. Reading rules beyond the contract, decided here:
// - CRLF and LF line endings both work; a UTF-8 byte order mark is skipped;
//   spaces and tabs around fields are ignored.
// - Before the header, blank lines and '#' lines are skipped; "# key: value"
//   lines with keys name, target, tolerance are read (others are comments).
// - After the header, blank (whitespace-only) lines are skipped, so a
//   trailing newline or an empty last line is harmless; any other line is a
//   state and must parse.
// - A target without a "# tolerance:" gets kDefaultTargetTolerance (plan.h).
// - Scale factors must be positive (the scene contract makes factor <= 0 an error).
// - Driving values are kept as written (plan units, never reduced): they drive
//   the motion between states and meet the limits; kinematics converts them
//   only to pose (action_transform). Target and tolerance are lengths: metres.
#include "src/scene/plan.h"

#include "src/base/error.h"

#include <charconv>
#include <cmath>
#include <fstream>
#include <iterator>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

namespace plancheck {
namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

std::vector<std::string_view> split(std::string_view line, char sep) {
  std::vector<std::string_view> out;
  std::size_t start = 0;
  for (;;) {
    std::size_t at = line.find(sep, start);
    out.push_back(trim(line.substr(start, at == std::string_view::npos ? std::string_view::npos : at - start)));
    if (at == std::string_view::npos) break;
    start = at + 1;
  }
  return out;
}

// Whole-field parse: from_chars must consume everything; no inf, no nan.
bool parse_finite(std::string_view s, double& value) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  if (s.empty()) return false;
  auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
  return ec == std::errc() && ptr == s.data() + s.size() && std::isfinite(value);
}

}  // namespace

void state_between(const std::vector<double>& qa, const std::vector<double>& qb, double t, std::vector<double>& out) {
  if (t == 0.0) {
    out = qa;
  } else if (t == 1.0) {
    out = qb;
  } else {
    out.resize(qa.size());
    for (std::size_t j = 0; j < qa.size(); ++j) out[j] = qa[j] + t * (qb[j] - qa[j]);
  }
}

Plan load_plan(const Scene& scene, const std::filesystem::path& csv) {
  std::ifstream in(csv, std::ios::binary);
  if (!in) fail(csv, "cannot open plan file");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return parse_plan(scene, text, csv);
}

Plan parse_plan(const Scene& scene, std::string_view text, const std::filesystem::path& csv) {
  if (text.size() >= 3 && text.compare(0, 3, "\xEF\xBB\xBF") == 0) text.remove_prefix(3);

  Plan plan;
  plan.file = csv;
  // The contract's default name: the file name without ".csv" (only that suffix).
  plan.name = csv.extension() == ".csv" ? csv.stem().string() : csv.filename().string();
  bool tolerance_given = false;

  // Per column: index into the state vector, or -1 for the time column.
  std::vector<int> column_parameter;
  std::vector<std::string> column_name;
  std::vector<bool> column_is_factor;     // scale factors must be positive
  long header_line = 0;

  std::string_view rest = text;
  long line_no = 0;
  while (!rest.empty()) {
    std::size_t nl = rest.find('\n');
    std::string_view raw = rest.substr(0, nl);
    rest.remove_prefix(nl == std::string_view::npos ? rest.size() : nl + 1);
    ++line_no;
    std::string_view line = trim(raw);

    if (header_line == 0) {
      if (line.empty()) continue;
      if (line.front() == '#') {
        std::string_view body = trim(line.substr(1));
        std::size_t colon = body.find(':');
        if (colon == std::string_view::npos) continue;
        std::string key(trim(body.substr(0, colon)));
        std::string_view value = trim(body.substr(colon + 1));
        if (key == "name") {
          if (!value.empty()) plan.name = std::string(value);
        } else if (key == "target") {
          std::vector<std::string_view> xyz = split(value, ',');
          Vec3 t;
          if (xyz.size() != 3 || !parse_finite(xyz[0], t.x()) || !parse_finite(xyz[1], t.y()) ||
              !parse_finite(xyz[2], t.z()))
            fail(csv, "target: expected three finite numbers x, y, z", line_no);
          plan.target = t * scene.length_scale;
        } else if (key == "tolerance") {
          double v = 0;
          if (!parse_finite(value, v) || v < 0)
            fail(csv, "tolerance: expected a finite number >= 0", line_no);
          plan.tolerance = v * scene.length_scale;
          tolerance_given = true;
        }
        continue;
      }
      header_line = line_no;
      std::vector<std::string_view> names = split(line, ',');
      std::vector<bool> used(scene.parameter_names.size(), false);
      for (std::size_t c = 0; c < names.size(); ++c) {
        const std::string name(names[c]);
        const long column = static_cast<long>(c) + 1;
        if (name == "time") {
          if (c != 0) fail(csv, "column 'time' must be the first column", line_no, column);
          column_parameter.push_back(-1);
          column_name.push_back(name);
          column_is_factor.push_back(false);
          continue;
        }
        int index = -1;
        for (std::size_t p = 0; p < scene.parameter_names.size(); ++p)
          if (scene.parameter_names[p] == name) index = static_cast<int>(p);
        if (index < 0) {
          fail(csv, name.empty() ? "empty column name" : "unknown column '" + name + "' (not a driving parameter of the scene)",
               line_no, column);
        }
        if (used[index]) fail(csv, "column '" + name + "' given twice", line_no, column);
        used[index] = true;
        column_parameter.push_back(index);
        column_name.push_back(name);
        bool factor = false;
        for (const Action& a : scene.actions)
          if (index >= a.first_parameter && index < a.first_parameter + a.parameter_count)
            factor = a.type == ActionType::kScale;
        column_is_factor.push_back(factor);
      }
      continue;
    }

    if (line.empty()) continue;
    std::vector<std::string_view> fields = split(line, ',');
    if (fields.size() != column_parameter.size())
      fail(csv, "expected " + std::to_string(column_parameter.size()) + " fields, found " +
                    std::to_string(fields.size()), line_no);
    std::vector<double> state = scene.reference_parameters;
    for (std::size_t c = 0; c < fields.size(); ++c) {
      const long column = static_cast<long>(c) + 1;
      double v = 0;
      if (!parse_finite(fields[c], v))
        fail(csv, "column '" + column_name[c] + "': '" + std::string(fields[c]) + "' is not a finite number",
             line_no, column);
      const int p = column_parameter[c];
      if (p < 0) {
        plan.times.push_back(v);
        continue;
      }
      if (column_is_factor[c] && !(v > 0))
        fail(csv, "column '" + column_name[c] + "': scale factor must be positive", line_no, column);
      state[static_cast<std::size_t>(p)] = v;  // as written: only the pose converts it
    }
    plan.states.push_back(std::move(state));
    plan.lines.push_back(line_no);
  }

  if (header_line == 0) fail(csv, "no header line", line_no > 0 ? line_no : 1);
  if (plan.states.empty()) fail(csv, "the plan has no states", header_line);
  if (plan.target && !tolerance_given) plan.tolerance = kDefaultTargetTolerance * scene.length_scale;
  return plan;
}

}  // namespace plancheck
