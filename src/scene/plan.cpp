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
// - Fields are RFC 4180: a field in double quotes may hold commas, quotes
//   (doubled) and line breaks, so a joint whose name holds a comma can be
//   named in the header, as the reports write it.
// - The file is read a line at a time (files.h): at most kMaxLineBytes a
//   line, and it must be a regular file. A plan name is valid UTF-8 of at
//   most kMaxPlanNameBytes bytes, checked here, before any checking starts.
// - A number below double's range (1e-400) is its nearest double (0), as in
//   the scene file; one above it (1e400) is an error.
// - Driving values are kept as written (plan units, never reduced): they drive
//   the motion between states and meet the limits; kinematics converts them
//   only to pose (action_transform). Target and tolerance are lengths: metres.
#include "src/scene/plan.h"

#include "src/base/error.h"
#include "src/base/files.h"
#include "src/base/text.h"
#include "src/scene/kinematics.h"

#include <charconv>
#include <cmath>
#include <cstdlib>
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

// Whether `record` ends inside a quoted field (RFC 4180: the record goes on
// on the next line).
bool open_quote(std::string_view record) {
  bool in = false;
  for (char c : record)
    if (c == '"') in = !in;  // a doubled quote toggles twice
  return in;
}

// One RFC 4180 record into fields: a field that starts (after blanks) with a
// quote runs to the closing quote, "" inside it being one quote; blanks
// around fields are dropped. Returns false (and the field's 1-based column
// in `bad`) on text after a closing quote.
bool split_record(std::string_view record, std::vector<std::string>& fields, long& bad) {
  fields.clear();
  std::size_t i = 0;
  for (;;) {
    while (i < record.size() && (record[i] == ' ' || record[i] == '\t')) ++i;
    std::string field;
    if (i < record.size() && record[i] == '"') {
      ++i;
      for (;;) {
        if (i >= record.size()) break;  // unclosed: taken to the end (the reader joined what it could)
        if (record[i] == '"') {
          if (i + 1 < record.size() && record[i + 1] == '"') {
            field += '"';
            i += 2;
            continue;
          }
          ++i;
          break;
        }
        field += record[i++];
      }
      while (i < record.size() && (record[i] == ' ' || record[i] == '\t' || record[i] == '\r')) ++i;
      if (i < record.size() && record[i] != ',') {
        bad = static_cast<long>(fields.size()) + 1;
        return false;
      }
    } else {
      const std::size_t at = record.find(',', i);
      field = std::string(trim(record.substr(i, at == std::string_view::npos ? std::string_view::npos : at - i)));
      i = at == std::string_view::npos ? record.size() : at;
    }
    fields.push_back(std::move(field));
    if (i >= record.size()) return true;
    ++i;  // the comma
  }
}

// Whole-field parse: from_chars must consume everything; no inf, no nan. A
// value below the range of double rounds to its nearest double (as strtod
// and the scene's JSON reader do); one above it is refused.
bool parse_finite(std::string_view s, double& value) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  if (s.empty()) return false;
  auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
  if (ec == std::errc::result_out_of_range && ptr == s.data() + s.size()) {
    const std::string text(s);
    value = std::strtod(text.c_str(), nullptr);  // underflow: 0 or a subnormal; overflow: inf
  } else if (ec != std::errc() || ptr != s.data() + s.size()) {
    return false;
  }
  return std::isfinite(value);
}

std::string number_problem(std::string_view s) {
  double v = 0;
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec == std::errc::result_out_of_range && ptr == s.data() + s.size())
    return "is not a finite number (beyond the range of a double)";
  return "is not a finite number";
}

// Reads a plan one physical line at a time (feed), then finish().
class PlanParser {
 public:
  PlanParser(const Scene& scene, const std::filesystem::path& csv) : scene_(scene), csv_(csv) {
    plan_.file = csv;
    // The contract's default name: the file name without ".csv" (only that suffix).
    plan_.name = csv.extension() == ".csv" ? csv.stem().string() : csv.filename().string();
  }

  void feed(std::string_view raw, long line_no) {
    if (!pending_.empty()) {
      // A quoted field of the record begun on line pending_line_ goes on.
      pending_.append("\n").append(raw);
      if (pending_.size() > kMaxLineBytes)
        fail(csv_, "a quoted field longer than " + std::to_string(kMaxLineBytes) + " bytes", pending_line_);
      if (open_quote(pending_)) return;
      const std::string record = std::move(pending_);
      pending_.clear();
      record_line(record, pending_line_);
      return;
    }
    if (line_no == 1 && raw.size() >= 3 && raw.compare(0, 3, "\xEF\xBB\xBF") == 0) raw.remove_prefix(3);
    const std::string_view line = trim(raw);
    if (header_line_ == 0 && (line.empty() || line.front() == '#')) {
      comment(line, line_no);
      return;
    }
    if (line.empty()) return;
    if (open_quote(line)) {
      pending_.assign(line);
      pending_line_ = line_no;
      return;
    }
    record_line(line, line_no);
  }

  Plan finish(long last_line) {
    if (!pending_.empty()) fail(csv_, "a quoted field is not closed", pending_line_);
    if (header_line_ == 0) fail(csv_, "no header line", last_line > 0 ? last_line : 1);
    if (plan_.states.empty()) fail(csv_, "the plan has no states", header_line_);
    if (plan_.target && !tolerance_given_) plan_.tolerance = kDefaultTargetTolerance * scene_.length_scale;
    check_name(name_line_);
    return std::move(plan_);
  }

 private:
  void comment(std::string_view line, long line_no) {
    if (line.empty()) return;
    std::string_view body = trim(line.substr(1));
    std::size_t colon = body.find(':');
    if (colon == std::string_view::npos) return;
    std::string key(trim(body.substr(0, colon)));
    std::string_view value = trim(body.substr(colon + 1));
    if (key == "name") {
      if (!value.empty()) {
        plan_.name = std::string(value);
        name_line_ = line_no;
        check_name(line_no);
      }
    } else if (key == "target") {
      std::vector<std::string_view> xyz = split(value, ',');
      Vec3 t;
      if (xyz.size() != 3 || !parse_finite(xyz[0], t.x()) || !parse_finite(xyz[1], t.y()) ||
          !parse_finite(xyz[2], t.z()))
        fail(csv_, "target: expected three finite numbers x, y, z", line_no);
      plan_.target = t * scene_.length_scale;
    } else if (key == "tolerance") {
      double v = 0;
      if (!parse_finite(value, v) || v < 0) fail(csv_, "tolerance: expected a finite number >= 0", line_no);
      plan_.tolerance = v * scene_.length_scale;
      tolerance_given_ = true;
    }
  }

  // The name (from "# name:" or the file name) names the plan's CSV and its
  // lines in every report: text, one line, a length a file name can carry.
  void check_name(long line_no) const {
    const std::string& n = plan_.name;
    const std::string where = line_no > 0 ? "name" : "name (the file name)";
    if (!valid_utf8(n)) fail(csv_, where + ": not valid UTF-8 text", line_no);
    if (n.size() > kMaxPlanNameBytes)
      fail(csv_, where + ": longer than " + std::to_string(kMaxPlanNameBytes) + " bytes", line_no);
    for (unsigned char c : n)
      if (c < 0x20 || c == 0x7F) fail(csv_, where + ": holds a control character", line_no);
  }

  void record_line(std::string_view line, long line_no) {
    long bad = 0;
    if (!split_record(line, fields_, bad)) fail(csv_, "text after a closing quote", line_no, bad);
    if (header_line_ == 0) {
      header(line_no);
      return;
    }
    if (fields_.size() != column_parameter_.size())
      fail(csv_, "expected " + std::to_string(column_parameter_.size()) + " fields, found " +
                     std::to_string(fields_.size()), line_no);
    std::vector<double> state = scene_.reference_parameters;
    for (std::size_t c = 0; c < fields_.size(); ++c) {
      const long column = static_cast<long>(c) + 1;
      double v = 0;
      if (!parse_finite(fields_[c], v))
        fail(csv_, "column '" + column_name_[c] + "': '" + fields_[c] + "' " + number_problem(fields_[c]), line_no,
             column);
      const int p = column_parameter_[c];
      if (p < 0) {
        plan_.times.push_back(v);
        continue;
      }
      if (column_is_factor_[c] && !(v > 0))
        fail(csv_, "column '" + column_name_[c] + "': scale factor must be positive", line_no, column);
      state[static_cast<std::size_t>(p)] = v;  // as written: only the pose converts it
    }
    // A pose past the range of doubles (1e308 m added to 1e308 m) cannot
    // be checked: say so here, where the line is known.
    chain_transforms(scene_, state, chains_);
    for (std::size_t c = 0; c < chains_.size(); ++c)
      if (!chains_[c].matrix().allFinite())
        fail(csv_, "these values pose node '" +
                       scene_.actions[static_cast<std::size_t>(scene_.chains[c].back())].node_name +
                       "' beyond the range of doubles", line_no);
    plan_.states.push_back(std::move(state));
    plan_.lines.push_back(line_no);
  }

  void header(long line_no) {
    header_line_ = line_no;
    std::vector<bool> used(scene_.parameter_names.size(), false);
    for (std::size_t c = 0; c < fields_.size(); ++c) {
      const std::string& name = fields_[c];
      const long column = static_cast<long>(c) + 1;
      if (name == "time") {
        if (c != 0) fail(csv_, "column 'time' must be the first column", line_no, column);
        column_parameter_.push_back(-1);
        column_name_.push_back(name);
        column_is_factor_.push_back(false);
        continue;
      }
      int index = -1;
      for (std::size_t p = 0; p < scene_.parameter_names.size(); ++p)
        if (scene_.parameter_names[p] == name) index = static_cast<int>(p);
      if (index < 0) fail(csv_, unknown_column(name), line_no, column);
      if (used[index]) fail(csv_, "column '" + name + "' given twice", line_no, column);
      used[index] = true;
      column_parameter_.push_back(index);
      column_name_.push_back(name);
      bool factor = false;
      for (const Action& a : scene_.actions)
        if (index >= a.first_parameter && index < a.first_parameter + a.parameter_count)
          factor = a.type == ActionType::kScale;
      column_is_factor_.push_back(factor);
    }
  }

  std::string unknown_column(const std::string& name) const {
    if (name.empty()) return "empty column name";
    for (const Action& a : scene_.actions)
      if (a.name == name && a.mimic >= 0)
        return "column '" + name + "' names a mimic joint: it follows joint '" +
               scene_.actions[static_cast<std::size_t>(a.mimic)].name + "' and has no column of its own";
    return "unknown column '" + name + "' (not a driving parameter of the scene)";
  }

  const Scene& scene_;
  const std::filesystem::path& csv_;
  Plan plan_;
  bool tolerance_given_ = false;
  long name_line_ = 0;
  long header_line_ = 0;
  std::string pending_;  // a record whose quoted field spans lines
  long pending_line_ = 0;
  std::vector<std::string> fields_;
  std::vector<Affine> chains_;  // a row's poses (scratch)
  // Per column: index into the state vector, or -1 for the time column.
  std::vector<int> column_parameter_;
  std::vector<std::string> column_name_;
  std::vector<bool> column_is_factor_;  // scale factors must be positive
};

}  // namespace

void state_between(const std::vector<double>& qa, const std::vector<double>& qb, double t, std::vector<double>& out) {
  if (t == 0.0) {
    out = qa;
  } else if (t == 1.0) {
    out = qb;
  } else {
    out.resize(qa.size());
    for (std::size_t j = 0; j < qa.size(); ++j) {
      const double d = qb[j] - qa[j];
      // Values far apart (1e308 to -1e308) overflow the difference: the
      // same line, weighted, stays finite (NaN would make the checker's
      // searches visit every triangle pair).
      out[j] = std::isfinite(d) ? qa[j] + t * d : (1 - t) * qa[j] + t * qb[j];
    }
  }
}

Plan load_plan(const Scene& scene, const std::filesystem::path& csv) {
  LineReader in(csv, "plan file");
  PlanParser parser(scene, csv);
  std::string line;
  while (in.next(line)) parser.feed(line, in.line_number());
  return parser.finish(in.line_number());
}

Plan parse_plan(const Scene& scene, std::string_view text, const std::filesystem::path& csv) {
  PlanParser parser(scene, csv);
  long line_no = 0;
  while (!text.empty()) {
    const std::size_t nl = text.find('\n');
    const std::string_view raw = text.substr(0, nl);
    text.remove_prefix(nl == std::string_view::npos ? text.size() : nl + 1);
    if (raw.size() > kMaxLineBytes)
      fail(csv, "line longer than " + std::to_string(kMaxLineBytes) + " bytes (no real file has one)", line_no + 1);
    parser.feed(raw, ++line_no);
  }
  return parser.finish(line_no);
}

}  // namespace plancheck
