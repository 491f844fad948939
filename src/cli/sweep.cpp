// SPDX-License-Identifier: MIT
// plancheck sweep (src/cli/sweep.h): load, parse the grid, build the
// checker, check every configuration into verdict.npy, distance.npy (and
// sweep.csv with --csv), then sweep.json, sweep.html and the stdout summary.
// The checking runs as the engine's items (src/cli/distribute.h): certified
// blocks, or with --csv/--exact-distance chunks of 2^16 rows; each item's
// blob holds its verdict codes, float distances and tally part (or its
// rows), consumed in item order by the one process that writes, so a
// single run, shards + merge, --resume and mpirun write the same files.
#include "src/cli/sweep.h"
#include "src/cli/run_setup.h"

#include "src/base/error.h"
#include "src/base/files.h"
#include "src/base/text.h"
#include "src/cli/distribute.h"
#include "src/cli/sweep_stage.h"
#include "src/base/parallel.h"
#include "src/base/progress.h"
#include "src/checks/sweep_certify.h"
#include "src/checks/sweep_grid.h"
#include "src/checks/verify.h"
#include "src/output/npy.h"
#include "src/output/report.h"
#include "src/output/sweep_html.h"
#include "src/scene/plan.h"
#include "src/scene/scene_loader.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <ostream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

namespace plancheck {
namespace {

using Json = nlohmann::ordered_json;

std::string num(double v) { return csv_number(v); }

std::vector<double>& params_scratch() {
  static thread_local std::vector<double> p;
  return p;
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

using Grid = SweepGrid;

// --grid or --steps (9 by default) over the loaded scene, at most
// kMaxSweepConfigurations in all. Throws InputError.
Grid parse_grid(const Scene& scene, const SweepArgs& args) {
  Grid grid;
  if (args.grid && args.steps) throw InputError("--grid and --steps cannot be used together");
  if (args.grid)
    grid.axes = sweep_axes_from_grid(scene, *args.grid);
  else
    grid.axes = sweep_axes_from_steps(scene, args.steps.value_or(9));
  for (const SweepAxis& a : grid.axes) {
    if (a.values.empty() || grid.total > kMaxSweepConfigurations / a.values.size())
      throw InputError("sweep of more than " + std::to_string(kMaxSweepConfigurations) +
                       " configurations; use fewer steps or a coarser --grid");
    grid.total *= a.values.size();
  }
  grid.reference = scene.reference_parameters;
  return grid;
}

// The output folder, emptied of an earlier sweep's files, so a failed run
// leaves nothing that passes for this run's.
void prepare_out(const std::filesystem::path& out) {
  std::error_code ec;
  for (const char* name : {"sweep.json", "sweep.csv", "verdict.npy", "distance.npy", "sweep.html"})
    std::filesystem::remove(out / name, ec);
  std::filesystem::create_directories(out, ec);
  if (ec) throw InputError(out.string() + ": cannot create the folder (" + ec.message() + ")");
  remove_stale_temporaries(out);  // what a killed run left half-written
}

// distance.npy's value: a float32 lower bound of d (m) in length_unit,
// rounded toward zero (0 in contact, +inf with no checked pair).
float distance_lower_bound(double d, double unit) {
  if (!(d > 0.0)) return 0.0f;
  if (std::isinf(d)) return std::numeric_limits<float>::infinity();
  // The division rounds to nearest: step one double down when it was not
  // exact, then take the float at or below.
  double q = d / unit;
  if (unit != 1.0 && q * unit != d) q = std::nextafter(q, 0.0);
  float f = static_cast<float>(q);
  if (static_cast<double>(f) > q) f = std::nextafter(f, 0.0f);
  return f;
}

// What the summary (sweep.json, stdout, sweep.html) keeps of all the rows.
struct Tally {
  std::map<Verdict, std::size_t> counts;
  std::map<std::pair<int, int>, std::size_t> colliding_pairs;
  // Per axis and value: how many configurations with that value are safe.
  std::vector<std::vector<std::size_t>> safe_by_value;
  Row closest;                   // the closest configuration without contact
  std::size_t closest_index = 0;
  Vec3 reach_lo = Vec3::Constant(std::numeric_limits<double>::infinity());  // safe targets' box (m)
  Vec3 reach_hi = -reach_lo;
  std::vector<std::uint8_t> page_verdicts;  // --html: every configuration's verdict, the safe ones' targets
  SafeTargetSample page_targets;
  double check_seconds = 0.0;
  std::size_t checked = 0;      // configurations with an exact distance (or in contact)
  std::size_t pair_checks = 0;  // certified path: single-pair answers computed
  std::size_t blocks = 0;       // certified path: blocks of the grid
  std::size_t witnessed = 0;       // certified path: configurations in contact by a crossing witness (no test)
  std::size_t contact_boxes = 0;  // certified path: boxes certified in contact by a crossing witness
  // Certified path: the smallest lower bound of a configuration without an
  // exact distance, and where (the closest may lie there).
  double bound_min = std::numeric_limits<double>::infinity();
  std::size_t bound_index = 0;

  std::size_t count(Verdict v) const {
    const auto found = counts.find(v);
    return found == counts.end() ? 0 : found->second;
  }
  // The colliding pairs, most configurations first (ties in pair order).
  std::vector<std::pair<std::size_t, std::pair<int, int>>> pairs_by_count() const {
    std::vector<std::pair<std::size_t, std::pair<int, int>>> by_count;
    for (const auto& [pair, c] : colliding_pairs) by_count.push_back({c, pair});
    std::stable_sort(by_count.begin(), by_count.end(), [](const auto& x, const auto& y) { return x.first > y.first; });
    return by_count;
  }
};

// sweep.csv, written to a fresh temporary (files.h) renamed when complete;
// names as RFC 4180 fields (csv_field).
class CsvOut {
 public:
  // Writes the header (the folder exists: prepare_out).
  CsvOut(const Scene& scene, const std::vector<SweepAxis>& axes, const std::filesystem::path& out)
      : file_(out / "sweep.csv") {
    for (const SweepAxis& a : axes)
      buffer_.append(csv_field(scene.parameter_names[static_cast<std::size_t>(a.parameter)])).append(",");
    buffer_ += "verdict,collision,min_distance,part_a,part_b,target_x,target_y,target_z\n";
  }

  void row(const std::vector<SweepAxis>& axes, const std::vector<double>& params, const Row& row,
           const Checker& checker, double unit) {
    for (std::size_t k = 0; k < axes.size(); ++k)
      buffer_.append(num(params[static_cast<std::size_t>(axes[k].parameter)])).append(",");
    buffer_.append(verdict_name(row.verdict)).append(row.collision ? ",1," : ",0,");
    buffer_.append(num(row.collision ? 0.0 : row.min_distance / unit)).append(",");
    if (row.part_a >= 0) buffer_.append(csv_field(checker.part_name(row.part_a)));
    buffer_.append(",");
    if (row.part_b >= 0) buffer_.append(csv_field(checker.part_name(row.part_b)));
    buffer_.append(",").append(num(row.target.x() / unit)).append(",").append(num(row.target.y() / unit));
    buffer_.append(",").append(num(row.target.z() / unit)).append("\n");
    if (buffer_.size() >= kFlushBytes) flush();
  }

  void finish() {
    flush();
    file_.commit();
  }

 private:
  static constexpr std::size_t kFlushBytes = std::size_t{1} << 20;
  void flush() {
    file_.write(buffer_);
    buffer_.clear();
  }
  TempFile file_;
  std::string buffer_;
};

// The per-configuration outputs: verdict.npy and distance.npy (the grid's
// shape, written block by block) and, with --csv, sweep.csv.
struct GridOut {
  NpyWriter verdict, distance;
  std::optional<CsvOut> csv;
  GridOut(const Scene& scene, const Grid& grid, const SweepArgs& args)
      : verdict(args.out / "verdict.npy", NpyType::kUint8, shape(grid)),
        distance(args.out / "distance.npy", NpyType::kFloat32, shape(grid)) {
    if (args.csv) csv.emplace(scene, grid.axes, args.out);
  }
  static std::vector<std::uint64_t> shape(const Grid& grid) {
    std::vector<std::uint64_t> s;
    for (const SweepAxis& a : grid.axes) s.push_back(a.values.size());
    return s;
  }
  void finish() {
    verdict.finish();
    distance.finish();
    if (csv) csv->finish();
  }
};

// Item blobs (src/cli/distribute.h): little-endian fields appended in order,
// doubles bit for bit, read back with bounds checks.
class BlobOut {
 public:
  explicit BlobOut(std::string& s) : s_(s) {}
  template <class T>
  void put(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    s_.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
  void bytes(const void* data, std::size_t n) { s_.append(static_cast<const char*>(data), n); }

 private:
  std::string& s_;
};

class BlobIn {
 public:
  explicit BlobIn(std::string_view s) : s_(s) {}
  template <class T>
  T get() {
    static_assert(std::is_trivially_copyable_v<T>);
    T v;
    bytes(&v, sizeof v);
    return v;
  }
  void bytes(void* data, std::size_t n) {
    if (n > s_.size() - at_) throw std::runtime_error("record cut short");
    std::memcpy(data, s_.data() + at_, n);
    at_ += n;
  }
  void done() const {
    if (at_ != s_.size()) throw std::runtime_error("record longer than its fields");
  }

 private:
  std::string_view s_;
  std::size_t at_ = 0;
};

// A fresh tally for the grid.
Tally empty_tally(const Grid& grid) {
  Tally tally;
  tally.safe_by_value.resize(grid.axes.size());
  for (std::size_t k = 0; k < grid.axes.size(); ++k) tally.safe_by_value[k].assign(grid.axes[k].values.size(), 0);
  tally.closest.min_distance = std::numeric_limits<double>::infinity();
  return tally;
}

// Checks configurations [begin, end) of the grid on its own each
// (--exact-distance, --csv): rows checked in parallel, in runs seeded in order.
void check_rows(const Checker& checker, const Scene& scene, const Grid& grid, std::size_t begin, std::size_t end,
                int threads, Progress& progress, std::vector<Row>& rows) {
  const double margin = scene.safety_margin;
  // The CSV names one colliding pair per configuration and no triangles.
  CheckRequest request;
  request.max_triangle_pairs = 0;
  request.all_contacts = false;
  constexpr std::size_t kRun = 32;  // states seeded in order
  const std::size_t n = end - begin;
  rows.assign(n, Row{});
  parallel_for((n + kRun - 1) / kRun, threads, 1, [&](std::size_t rb, std::size_t re, int) {
    std::vector<double> p;
    StateResult st;
    for (std::size_t r = rb; r < re; ++r) {
      StateSeed seed;
      for (std::size_t i = r * kRun; i < std::min(n, (r + 1) * kRun); ++i) {
        grid.decode(begin + i, p, nullptr);
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
}

void put_row(BlobOut& o, const Row& row) {
  o.put(static_cast<std::int32_t>(row.verdict));
  o.put(static_cast<std::uint8_t>(row.collision));
  o.put(static_cast<std::int32_t>(row.part_a));
  o.put(static_cast<std::int32_t>(row.part_b));
  o.put(row.min_distance);
  for (int k = 0; k < 3; ++k) o.put(row.target[k]);
}

Row get_row(BlobIn& in) {
  Row row;
  row.verdict = static_cast<Verdict>(in.get<std::int32_t>());
  row.collision = in.get<std::uint8_t>() != 0;
  row.part_a = in.get<std::int32_t>();
  row.part_b = in.get<std::int32_t>();
  row.min_distance = in.get<double>();
  for (int k = 0; k < 3; ++k) row.target[k] = in.get<double>();
  return row;
}

// Writes rows [begin, begin + rows.size()) into the outputs and the tally,
// in grid order.
void consume_rows(const Checker& checker, const Scene& scene, const Grid& grid, const SweepArgs& args,
                  std::size_t begin, const std::vector<Row>& rows, GridOut& outputs, Tally& tally) {
  const std::vector<SweepAxis>& axes = grid.axes;
  const double unit = scene.length_scale;
  const std::size_t n = rows.size();
  std::vector<std::uint8_t> verdict_block(n);
  std::vector<float> distance_block(n);
  for (std::size_t i = 0; i < n; ++i) {
    verdict_block[i] = sweep_verdict_code(rows[i].verdict);
    distance_block[i] = distance_lower_bound(rows[i].collision ? 0.0 : rows[i].min_distance, unit);
  }
  outputs.verdict.write(begin, verdict_block.data(), n);
  outputs.distance.write(begin, distance_block.data(), n);
  std::vector<double>& params = params_scratch();
  std::vector<std::size_t> digits(axes.size());
  for (std::size_t i = 0; i < n; ++i) {
    const Row& row = rows[i];
    grid.decode(begin + i, params, &digits);
    ++tally.counts[row.verdict];
    if (row.collision) {
      // Every colliding pair of the state would need the contacts kept;
      // the first is what the row names.
      ++tally.colliding_pairs[{row.part_a, row.part_b}];
    } else if (row.part_a >= 0 && row.min_distance < tally.closest.min_distance) {
      tally.closest = row;
      tally.closest_index = begin + i;
    }
    if (args.html) tally.page_verdicts.push_back(sweep_verdict_code(row.verdict));
    if (row.verdict == Verdict::kSafe) {
      if (args.html) tally.page_targets.push(row.target);
      for (std::size_t k = 0; k < axes.size(); ++k) ++tally.safe_by_value[k][digits[k]];
      tally.reach_lo = tally.reach_lo.cwiseMin(row.target);
      tally.reach_hi = tally.reach_hi.cwiseMax(row.target);
    }
    if (outputs.csv) outputs.csv->row(axes, params, row, checker, unit);
  }
  tally.checked += n;
}

// One certified block's answer (SweepCertifier::check_block), as written
// and tallied: its configurations' verdict codes and float distances (C
// order within the block) and its part of the tally.
struct BlockPart {
  std::vector<std::uint8_t> codes;
  std::vector<float> dist;
  Tally t;
  std::size_t pair_checks = 0;
  std::size_t witnessed = 0;
  std::size_t contact_boxes = 0;
};

void check_block_part(const Checker& checker, const Scene& scene, const Grid& grid, const SweepCertifier& certifier,
                      std::size_t b, SweepBlockResult& r, BlockPart& part) {
  const std::vector<SweepAxis>& axes = grid.axes;
  const double unit = scene.length_scale;
  const auto pairs = checker.pairs();
  std::vector<std::size_t> first, size, digit;
  std::vector<double> params;
  certifier.check_block(b, r);
  certifier.blocks().block(b, first, size);
  const std::size_t d = size.size();
  const std::size_t n = r.verdict.size();
  part.codes.resize(n);
  part.dist.resize(n);
  part.pair_checks = r.pair_checks;
  part.witnessed = r.witnessed;
  part.contact_boxes = r.contact_boxes;
  Tally& t = part.t;  // this block's part
  t = Tally{};
  t.safe_by_value.resize(axes.size());
  for (std::size_t k = 0; k < axes.size(); ++k) t.safe_by_value[k].assign(size[k], 0);
  t.closest.min_distance = std::numeric_limits<double>::infinity();
  digit.assign(d, 0);
  // The block's configurations in order, last axis fastest: the target
  // points recompose only the joints that changed (ChainCache). 5-degree
  // grid, 1 thread: target_point 4.9 G of 84.0 G instructions before.
  std::optional<ChainCache> target_chain;
  for (std::size_t i = 0; i < n; ++i) {
    const Verdict v = r.verdict[i];
    part.codes[i] = sweep_verdict_code(v);
    const bool collision = v == Verdict::kCollision;
    // An exact distance may exceed verify's by the search's tie
    // tolerance (another triangle pair within it): take it off, so the
    // float stays at or below what checking the configuration alone gives.
    const double lower = collision ? 0.0 : r.exact[i] ? r.distance[i] - kDistanceTieTolerance : r.distance[i];
    part.dist[i] = distance_lower_bound(std::max(lower, 0.0), unit);
    std::size_t index = 0;
    for (std::size_t k = 0; k < d; ++k) index = index * axes[k].values.size() + first[k] + digit[k];
    ++t.counts[v];
    t.checked += r.exact[i];
    if (collision) {
      const auto& pr = pairs[static_cast<std::size_t>(r.pair[i])];
      ++t.colliding_pairs[{pr.first, pr.second}];
    } else if (r.exact[i] && r.pair[i] >= 0 &&
               (r.distance[i] < t.closest.min_distance ||
                (r.distance[i] == t.closest.min_distance && index < t.closest_index))) {
      const auto& pr = pairs[static_cast<std::size_t>(r.pair[i])];
      t.closest.verdict = v;
      t.closest.min_distance = r.distance[i];
      t.closest.part_a = pr.first;
      t.closest.part_b = pr.second;
      t.closest_index = index;
    } else if (!collision && !r.exact[i] &&
               (r.distance[i] < t.bound_min || (r.distance[i] == t.bound_min && index < t.bound_index))) {
      t.bound_min = r.distance[i];
      t.bound_index = index;
    }
    if (v == Verdict::kSafe) {
      for (std::size_t k = 0; k < d; ++k) ++t.safe_by_value[k][digit[k]];
      grid.decode(index, params, nullptr);
      const Vec3 target = checker.target_point(params, target_chain);
      t.reach_lo = t.reach_lo.cwiseMin(target);
      t.reach_hi = t.reach_hi.cwiseMax(target);
    }
    for (std::size_t k = d; k-- > 0;) {
      if (++digit[k] < size[k]) break;
      digit[k] = 0;
    }
  }
}

std::string block_blob(const BlockPart& p) {
  std::string s;
  s.reserve(64 + p.codes.size() * (1 + sizeof(float)));  // the arrays, without doubling on the way
  BlobOut o(s);
  const Tally& t = p.t;
  o.put(static_cast<std::uint64_t>(p.codes.size()));
  o.bytes(p.codes.data(), p.codes.size());
  o.bytes(p.dist.data(), p.dist.size() * sizeof(float));
  o.put(static_cast<std::uint64_t>(t.counts.size()));
  for (const auto& [v, c] : t.counts) {
    o.put(static_cast<std::int32_t>(v));
    o.put(static_cast<std::uint64_t>(c));
  }
  o.put(static_cast<std::uint64_t>(t.colliding_pairs.size()));
  for (const auto& [pr, c] : t.colliding_pairs) {
    o.put(static_cast<std::int32_t>(pr.first));
    o.put(static_cast<std::int32_t>(pr.second));
    o.put(static_cast<std::uint64_t>(c));
  }
  o.put(static_cast<std::int32_t>(t.closest.verdict));
  o.put(t.closest.min_distance);
  o.put(static_cast<std::int32_t>(t.closest.part_a));
  o.put(static_cast<std::int32_t>(t.closest.part_b));
  o.put(static_cast<std::uint64_t>(t.closest_index));
  o.put(t.bound_min);
  o.put(static_cast<std::uint64_t>(t.bound_index));
  o.put(static_cast<std::uint64_t>(t.safe_by_value.size()));
  for (const auto& axis : t.safe_by_value) {
    o.put(static_cast<std::uint64_t>(axis.size()));
    for (std::size_t c : axis) o.put(static_cast<std::uint64_t>(c));
  }
  for (int k = 0; k < 3; ++k) o.put(t.reach_lo[k]);
  for (int k = 0; k < 3; ++k) o.put(t.reach_hi[k]);
  o.put(static_cast<std::uint64_t>(t.checked));
  o.put(static_cast<std::uint64_t>(p.pair_checks));
  o.put(static_cast<std::uint64_t>(p.witnessed));
  o.put(static_cast<std::uint64_t>(p.contact_boxes));
  return s;
}

void read_block_blob(std::string_view blob, BlockPart& p) {
  BlobIn in(blob);
  Tally& t = p.t;
  t = Tally{};
  const auto n = in.get<std::uint64_t>();
  if (n > blob.size()) throw std::runtime_error("record cut short");
  p.codes.resize(n);
  p.dist.resize(n);
  in.bytes(p.codes.data(), n);
  in.bytes(p.dist.data(), n * sizeof(float));
  for (auto c = in.get<std::uint64_t>(); c > 0; --c) {
    const auto v = static_cast<Verdict>(in.get<std::int32_t>());
    t.counts[v] = in.get<std::uint64_t>();
  }
  for (auto c = in.get<std::uint64_t>(); c > 0; --c) {
    const int a = in.get<std::int32_t>();
    const int b = in.get<std::int32_t>();
    t.colliding_pairs[{a, b}] = in.get<std::uint64_t>();
  }
  t.closest.verdict = static_cast<Verdict>(in.get<std::int32_t>());
  t.closest.min_distance = in.get<double>();
  t.closest.part_a = in.get<std::int32_t>();
  t.closest.part_b = in.get<std::int32_t>();
  t.closest_index = in.get<std::uint64_t>();
  t.bound_min = in.get<double>();
  t.bound_index = in.get<std::uint64_t>();
  const auto axes = in.get<std::uint64_t>();
  if (axes > blob.size()) throw std::runtime_error("record cut short");
  t.safe_by_value.resize(axes);
  for (auto& axis : t.safe_by_value) {
    const auto m = in.get<std::uint64_t>();
    if (m > blob.size()) throw std::runtime_error("record cut short");
    axis.resize(m);
    for (auto& c : axis) c = in.get<std::uint64_t>();
  }
  for (int k = 0; k < 3; ++k) t.reach_lo[k] = in.get<double>();
  for (int k = 0; k < 3; ++k) t.reach_hi[k] = in.get<double>();
  t.checked = in.get<std::uint64_t>();
  p.pair_checks = in.get<std::uint64_t>();
  p.witnessed = in.get<std::uint64_t>();
  p.contact_boxes = in.get<std::uint64_t>();
  in.done();
}

// Writes block b at its places in the outputs (through the stage) and
// merges its tally part (sums; minima with the smallest grid index as the
// tie-break).
void consume_block(const SweepBlocks& blocks, const Grid& grid, const SweepArgs& args, std::size_t b,
                   const BlockPart& part, GridOut& outputs, BlockStage& stage, Tally& tally) {
  const std::vector<SweepAxis>& axes = grid.axes;
  std::vector<std::size_t> first, size, digit;
  blocks.block(b, first, size);
  const std::size_t d = size.size();
  std::size_t n = 1;
  for (std::size_t s : size) n *= s;
  const Tally& t = part.t;
  if (part.codes.size() != n || t.safe_by_value.size() != d)
    throw std::runtime_error("block " + std::to_string(b) + " does not fit the grid");
  for (std::size_t k = 0; k < d; ++k)
    if (t.safe_by_value[k].size() != size[k]) throw std::runtime_error("block " + std::to_string(b) + " does not fit the grid");
  stage.put(b, part.codes.data(), part.dist.data(), part.codes.size(), outputs.verdict, outputs.distance);
  if (args.html) {
    // The block's rows along the last axis are contiguous in the grid.
    const std::size_t run = d > 0 ? size[d - 1] : 1;
    digit.assign(d, 0);
    for (std::size_t i = 0; i < n; i += run) {
      std::size_t index = 0;
      for (std::size_t k = 0; k < d; ++k) index = index * axes[k].values.size() + first[k] + digit[k];
      std::copy_n(part.codes.data() + i, run, tally.page_verdicts.data() + index);
      for (std::size_t k = d - (d > 0 ? 1 : 0); k-- > 0;) {
        if (++digit[k] < size[k]) break;
        digit[k] = 0;
      }
    }
  }
  for (const auto& [v, c] : t.counts) tally.counts[v] += c;
  for (const auto& [pr, c] : t.colliding_pairs) tally.colliding_pairs[pr] += c;
  for (std::size_t k = 0; k < d; ++k)
    for (std::size_t j = 0; j < size[k]; ++j) tally.safe_by_value[k][first[k] + j] += t.safe_by_value[k][j];
  if (t.closest.part_a >= 0 &&
      (t.closest.min_distance < tally.closest.min_distance ||
       (t.closest.min_distance == tally.closest.min_distance && t.closest_index < tally.closest_index))) {
    tally.closest = t.closest;
    tally.closest_index = t.closest_index;
  }
  if (t.bound_min < tally.bound_min || (t.bound_min == tally.bound_min && t.bound_index < tally.bound_index)) {
    tally.bound_min = t.bound_min;
    tally.bound_index = t.bound_index;
  }
  tally.reach_lo = tally.reach_lo.cwiseMin(t.reach_lo);
  tally.reach_hi = tally.reach_hi.cwiseMax(t.reach_hi);
  tally.checked += t.checked;
  tally.pair_checks += part.pair_checks;
  tally.witnessed += part.witnessed;
  tally.contact_boxes += part.contact_boxes;
}

// What decides sweep's results and files, as text: a shard writes it into
// its partial result and `plancheck merge` sets the run up again from it.
// --threads, --quiet, --out, --shard and --resume are not in it.
std::string sweep_setup(const SweepArgs& a) {
  Json s = Json::object();
  put_scene_setup(s, a.scene, a.scene_options);
  s["steps"] = a.steps ? Json(*a.steps) : Json(nullptr);
  s["grid"] = a.grid ? Json(*a.grid) : Json(nullptr);
  s["csv"] = a.csv;
  s["exact_distance"] = a.exact_distance;
  s["html"] = a.html;
  return s.dump();
}

SweepArgs sweep_args_from_setup(const std::string& text, const std::filesystem::path& file) {
  SweepArgs a;
  try {
    const Json s = Json::parse(text);
    get_scene_setup(s, a.scene, a.scene_options);
    if (!s.at("steps").is_null()) {
      // An integer as written: get<long> would cast 1e39 (undefined behaviour).
      if (!s.at("steps").is_number_integer()) fail(file, "its sweep setup is not readable (corrupt)");
      a.steps = s.at("steps").get<long>();
    }
    if (!s.at("grid").is_null()) a.grid = s.at("grid").get<std::string>();
    a.csv = s.at("csv").get<bool>();
    a.exact_distance = s.at("exact_distance").get<bool>();
    a.html = s.at("html").get<bool>();
  } catch (const nlohmann::json::exception&) {
    fail(file, "its sweep setup is not readable (corrupt)");
  }
  return a;
}

// The run's fingerprint: the setup and the bytes it reads (scene file,
// terrain, the parts' meshes as loaded).
std::string sweep_fingerprint(const std::string& setup, const Scene& scene) {
  Fingerprint fp;
  fp.add("sweep");
  fp.add(setup);
  fingerprint_scene(fp, scene);
  return fp.hex();
}

// sweep.json: report.json's conventions (lengths in length_unit, null for none).
Json summary_json(const SweepArgs& args, const Scene& scene, const Checker& checker, const Grid& grid,
                  const Tally& tally, int threads, double load_seconds, double build_seconds) {
  const std::vector<SweepAxis>& axes = grid.axes;
  const double unit = scene.length_scale;
  const std::size_t safe = tally.count(Verdict::kSafe);
  Json j;
  j["format"] = "plancheck-sweep/1";
  j["scene"] = args.scene.string();
  j["safety_margin"] = scene.safety_margin / unit;
  j["threads"] = threads;
  j["left_out"] = {{"static_triangles", checker.left_out_static_triangles()},
                   {"reason", "beyond reach of the moving parts"}};
  Json jaxes = Json::array();
  for (std::size_t k = 0; k < axes.size(); ++k) {
    const SweepAxis& a = axes[k];
    Json values = Json::array(), safe_counts = Json::array();
    for (std::size_t v = 0; v < a.values.size(); ++v) {
      values.push_back(a.values[v]);
      safe_counts.push_back(tally.safe_by_value[k][v]);
    }
    jaxes.push_back({{"name", scene.parameter_names[static_cast<std::size_t>(a.parameter)]},
                     {"spec", a.spec},
                     {"values", values},
                     {"safe_configurations", safe_counts}});
  }
  j["axes"] = jaxes;
  j["configurations"] = grid.total;
  // Configurations whose distance is exact (in contact, or some pair
  // within the cutoff and not certified in clearance): distance.npy is a
  // certified lower bound elsewhere.
  j["checked"] = tally.checked;
  // witnessed: configurations in contact by a box's crossing witness, with
  // no test of their own (counted in checked: their distance, 0, is exact).
  if (tally.blocks > 0)
    j["certified"] = {{"blocks", tally.blocks},
                      {"pair_checks", tally.pair_checks},
                      {"witnessed", tally.witnessed},
                      {"contact_boxes", tally.contact_boxes}};
  j["counts"] = {{"safe", safe},
                 {"collision", tally.count(Verdict::kCollision)},
                 {"clearance", tally.count(Verdict::kClearance)},
                 {"limits", tally.count(Verdict::kLimits)}};
  Json jpairs = Json::array();
  for (const auto& [c, pair] : tally.pairs_by_count())
    jpairs.push_back({{"parts", {checker.part_name(pair.first), checker.part_name(pair.second)}},
                      {"configurations", c}});
  j["colliding_pairs"] = jpairs;
  const Row& closest = tally.closest;
  if (std::isfinite(closest.min_distance) && closest.min_distance <= tally.bound_min) {
    std::vector<double> params;
    grid.decode(tally.closest_index, params, nullptr);
    Json at = Json::object();
    for (const SweepAxis& a : axes)
      at[scene.parameter_names[static_cast<std::size_t>(a.parameter)]] =
          params[static_cast<std::size_t>(a.parameter)];
    j["min_distance"] = {{"distance", closest.min_distance / unit},
                         {"parts", {checker.part_name(closest.part_a), checker.part_name(closest.part_b)}},
                         {"at", at}};
  } else if (std::isfinite(tally.bound_min)) {
    // Some configuration without contact has only a certified bound (beyond
    // the cutoff, or certified in clearance) below every exact distance:
    // the smallest such bound, where it holds, and no pair.
    std::vector<double> params;
    grid.decode(tally.bound_index, params, nullptr);
    Json at = Json::object();
    for (const SweepAxis& a : axes)
      at[scene.parameter_names[static_cast<std::size_t>(a.parameter)]] =
          params[static_cast<std::size_t>(a.parameter)];
    j["min_distance"] = {{"distance", tally.bound_min / unit}, {"parts", nullptr}, {"at", at}, {"is_bound", true}};
  } else {
    j["min_distance"] = nullptr;
  }
  const Vec3& lo = tally.reach_lo;
  const Vec3& hi = tally.reach_hi;
  if (safe > 0)
    j["safe_target_box"] = {{"min", {lo.x() / unit, lo.y() / unit, lo.z() / unit}},
                            {"max", {hi.x() / unit, hi.y() / unit, hi.z() / unit}}};
  else
    j["safe_target_box"] = nullptr;
  j["seconds"] = {{"load", load_seconds}, {"build", build_seconds}, {"check", tally.check_seconds}};
  return j;
}

// dir/sweep.json, through a fresh temporary renamed when complete (files.h).
void write_summary_json(const Json& j, const std::filesystem::path& dir) {
  write_file_atomically(dir / "sweep.json", j.dump(2, ' ', false, Json::error_handler_t::replace) + "\n");
}

// stdout: the summary in a few lines.
void print_summary(std::ostream& out, const Scene& scene, const Checker& checker, const Grid& grid,
                   const Tally& tally, int threads, double load_seconds, double build_seconds) {
  const std::size_t total = grid.total;
  const double unit = scene.length_scale;
  const std::size_t safe = tally.count(Verdict::kSafe);
  const auto by_count = tally.pairs_by_count();
  auto pct = [&](std::size_t c) { return num(std::round(1000.0 * static_cast<double>(c) / static_cast<double>(total)) / 10.0); };
  out << "sweep: " << total << " configurations over";
  for (const SweepAxis& a : grid.axes)
    out << " " << printable(scene.parameter_names[static_cast<std::size_t>(a.parameter)]) << "(" << a.values.size() << ")";
  out << "\n";
  out << "  safe " << safe << " (" << pct(safe) << "%), collision " << tally.count(Verdict::kCollision)
      << ", clearance " << tally.count(Verdict::kClearance) << ", limits " << tally.count(Verdict::kLimits) << "\n";
  for (std::size_t i = 0; i < std::min<std::size_t>(5, by_count.size()); ++i)
    out << "  collides: " << printable(checker.part_name(by_count[i].second.first)) << " / "
        << printable(checker.part_name(by_count[i].second.second)) << " in " << by_count[i].first << " configurations\n";
  const Row& closest = tally.closest;
  if (std::isfinite(closest.min_distance) && closest.min_distance <= tally.bound_min)
    out << "  closest without contact: " << num(closest.min_distance / unit) << " " << scene.length_unit << " ("
        << printable(checker.part_name(closest.part_a)) << " / " << printable(checker.part_name(closest.part_b)) << ")\n";
  else if (std::isfinite(tally.bound_min))
    out << "  closest without contact: at least " << num(tally.bound_min / unit) << " " << scene.length_unit
        << " (certified)\n";
  const Vec3& lo = tally.reach_lo;
  const Vec3& hi = tally.reach_hi;
  if (safe > 0)
    out << "  safe target reach (" << scene.length_unit << "): x " << num(lo.x() / unit) << " .. "
        << num(hi.x() / unit) << ", y " << num(lo.y() / unit) << " .. " << num(hi.y() / unit)
        << ", z " << num(lo.z() / unit) << " .. " << num(hi.z() / unit) << "\n";
  if (tally.blocks > 0)
    out << "  exact distances at " << tally.checked << " configurations (" << pct(tally.checked)
        << "%); the rest certified (clear of the margin's cutoff, or in clearance) in " << tally.blocks
        << " blocks\n"
        << "  in contact by a crossing witness, untested: " << tally.witnessed << " configurations ("
        << pct(tally.witnessed) << "%, " << tally.contact_boxes << " boxes)\n";
  const double check_seconds = tally.check_seconds;
  char line[160];
  std::snprintf(line, sizeof line, "%zu configurations, %.3f s (load %.3f, build %.3f, check %.3f), %d threads\n",
                total, load_seconds + build_seconds + check_seconds, load_seconds, build_seconds, check_seconds,
                threads);
  out << line;
}

// sweep for a single run, a shard, an MPI rank (merge == nullptr), or
// plancheck merge (merge: the partial results to write the outputs from).
int sweep_run(const SweepArgs& args, std::ostream& out, std::ostream& err, const PartialSet* merge) {
  const bool mpi = !merge && under_mpi();
  const int rank = mpi ? mpi_rank() : 0;
  std::ostream silent(nullptr);
  std::ostream& log = rank == 0 ? err : silent;  // one rank speaks
  const bool may_write = rank == 0 && !args.shard;

  const auto t_load = std::chrono::steady_clock::now();
  log << "plancheck: loading " << args.scene.string() << "\n";
  const Scene scene = load_scene(args.scene, args.scene_options);
  const Grid grid = parse_grid(scene, args);
  const std::string setup = sweep_setup(args);
  const std::string fingerprint = sweep_fingerprint(setup, scene);
  if (merge && merge->first().fingerprint != fingerprint)
    fail(merge->first().file, "merge: the scene read now differs from the one the shards checked "
                              "(files changed since, or merge run from another folder)");
  const double load_seconds = seconds_since(t_load);

  const int threads = args.threads > 0 ? args.threads : hardware_threads();
  const auto t_build = std::chrono::steady_clock::now();
  log << "plancheck: building collision structures\n";
  const Checker checker(scene, threads);
  const double build_seconds = seconds_since(t_build);

  // sweep.csv lists each configuration's exact distance and pair: it and
  // --exact-distance check every configuration on its own, in chunks of
  // 2^16 rows; otherwise the grid is certified in fixed blocks.
  const bool each = args.exact_distance || args.csv;
  std::optional<SweepCertifier> certifier;
  if (!each) certifier.emplace(checker, scene, grid);
  constexpr std::size_t kRows = std::size_t{1} << 16;
  std::vector<std::uint64_t> weights;
  if (each) {
    for (std::size_t b = 0; b < grid.total; b += kRows) weights.push_back(std::min(kRows, grid.total - b));
  } else {
    std::vector<std::size_t> first, size;
    for (std::size_t b = 0; b < certifier->blocks().blocks; ++b) {
      certifier->blocks().block(b, first, size);
      std::uint64_t n = 1;
      for (std::size_t s : size) n *= s;
      weights.push_back(n);
    }
  }

  std::optional<GridOut> outputs;
  if (may_write || merge) {
    prepare_out(args.out);
    outputs.emplace(scene, grid, args);
  } else if (args.shard) {
    std::error_code ec;
    std::filesystem::create_directories(args.out, ec);
  }
  Tally tally = empty_tally(grid);
  if (!each) tally.blocks = certifier->blocks().blocks;
  if (args.html && !each && outputs) tally.page_verdicts.assign(grid.total, 0);

  double consume_seconds = 0.0;
  BlockPart consumed;
  std::optional<BlockStage> stage;
  if (!each) stage.emplace(certifier->blocks());
  std::vector<Row> consumed_rows;
  const ConsumeItem consume = [&](std::size_t item, std::string_view blob) {
    const auto t0 = std::chrono::steady_clock::now();
    try {
      if (each) {
        BlobIn in(blob);
        const auto n = in.get<std::uint64_t>();
        if (n != weights[item]) throw std::runtime_error("rows do not fit the grid");
        consumed_rows.resize(n);
        for (Row& row : consumed_rows) row = get_row(in);
        in.done();
        consume_rows(checker, scene, grid, args, item * kRows, consumed_rows, *outputs, tally);
      } else {
        read_block_blob(blob, consumed);
        consume_block(certifier->blocks(), grid, args, item, consumed, *outputs, *stage, tally);
      }
    } catch (const std::runtime_error& e) {
      if (dynamic_cast<const InputError*>(&e)) throw;
      throw InputError("sweep: item " + std::to_string(item) + ": " + e.what());
    }
    consume_seconds += seconds_since(t0);
  };

  const auto t_check = std::chrono::steady_clock::now();
  DistResult dist;
  if (merge) {
    log << "plancheck: merging " << merge->parts.size() << " partial results of " << grid.total
        << " configurations\n";
    read_partials(*merge, consume);
  } else {
    DistOptions dist_options;
    dist_options.command = "sweep";
    dist_options.fingerprint = fingerprint;
    dist_options.setup = setup;
    dist_options.out = args.out;
    dist_options.shard = args.shard;
    dist_options.resume = args.resume;
    dist_options.log = &log;
    // Certified blocks differ up to twenty-fold in cost, and a chunk ends
    // with its slowest block, the other core idle: on one machine, two
    // chunks (the engine's default, eight, made the 5-degree grid 13%
    // slower). --resume then redoes at most half the grid.
    if (!each && !args.shard && !mpi) dist_options.chunk_weight = (grid.total + 1) / 2;
    // A chunk's blobs wait in memory for the journal: 5 bytes a
    // configuration for certified blocks, 45 for checked rows. Capped, a
    // chunk holds at most about 85 MB, and memory no longer grows with the
    // grid (a half of the 1-degree grid held 5.0 GB in two chunks).
    // Chunks of 2^24 configurations are about 900 blocks, so the idle end
    // of each (its slowest block) costs little.
    dist_options.max_chunk_weight = each ? kRows * 32 : std::uint64_t{1} << 24;
    if (each)
      log << "plancheck: checking " << grid.total << " configurations on " << threads << " threads";
    else
      log << "plancheck: checking " << grid.total << " configurations in " << certifier->blocks().blocks
          << " certified blocks on " << threads << " threads";
    log << (mpi ? " per rank, " + std::to_string(mpi_size()) + " MPI ranks" : std::string()) << "\n";
    Progress progress("sweep", grid.total, "configurations", ProgressOptions{.quiet = args.quiet || rank != 0}, &log);
    const ComputeItems compute = [&](std::size_t begin, std::size_t end) {
      std::vector<std::string> blobs(end - begin);
      if (each) {
        std::vector<Row> rows;
        for (std::size_t item = begin; item < end; ++item) {
          const std::size_t first = item * kRows;
          check_rows(checker, scene, grid, first, first + weights[item], threads, progress, rows);
          std::string& s = blobs[item - begin];
          BlobOut o(s);
          o.put(static_cast<std::uint64_t>(rows.size()));
          for (const Row& row : rows) put_row(o, row);
        }
      } else {
        // The chunk's blocks in parallel; each block's answer depends on it alone.
        parallel_for(end - begin, threads, 1, [&](std::size_t b0, std::size_t b1, int) {
          SweepBlockResult r;
          BlockPart part;
          for (std::size_t i = b0; i < b1; ++i) {
            check_block_part(checker, scene, grid, *certifier, begin + i, r, part);
            blobs[i] = block_blob(part);
            progress.add(part.codes.size());
          }
        });
      }
      return blobs;
    };
    dist = run_items(dist_options, weights, compute, consume);
    progress.finish();
    if (dist.role == DistRole::kWorker) return 0;
    if (dist.role == DistRole::kShard) {
      log << "plancheck: wrote " << dist.partial.string() << " (shard " << args.shard->index << " of "
          << args.shard->count << "; plancheck merge joins the shards)\n";
      return 0;
    }
  }
  if (args.html && !each) {
    // The page's targets of safe configurations, in grid order.
    for (std::size_t i = 0; i < grid.total; ++i) {
      if (tally.page_verdicts[i] != sweep_verdict_code(Verdict::kSafe)) continue;
      tally.page_targets.push_with([&] {
        grid.decode(i, params_scratch(), nullptr);
        return checker.target_point(params_scratch());
      });
    }
  }
  tally.check_seconds = seconds_since(t_check);
  outputs->finish();

  Json summary = summary_json(args, scene, checker, grid, tally, threads, load_seconds, build_seconds);
  if (dist.ranks > 0) {
    summary["ranks"] = dist.ranks;
    summary["hosts"] = dist.hosts;
    Json chunks = Json::array();
    for (const ChunkTime& c : dist.chunks)
      chunks.push_back({{"rank", c.rank}, {"items", {c.begin, c.end}}, {"seconds", c.seconds}});
    summary["seconds"]["chunks"] = chunks;
    summary["seconds"]["write"] = consume_seconds;  // rank 0's consume: blobs into the files and the tally
  }
  write_summary_json(summary, args.out);
  if (args.html) write_sweep_html(checker, scene, grid.axes, tally.page_verdicts, tally.page_targets, args.out);
  if (!merge) {
    DistOptions o;
    o.out = args.out;
    finish_items(o);  // the outputs are written: the journal goes
  }
  print_summary(out, scene, checker, grid, tally, threads, load_seconds, build_seconds);
  return 0;
}

}  // namespace

int run_sweep(const SweepArgs& args, std::ostream& out, std::ostream& err) {
  return sweep_run(args, out, err, nullptr);
}

int run_sweep_merge(const PartialSet& set, const SweepArgs& options, std::ostream& out, std::ostream& err) {
  SweepArgs args = sweep_args_from_setup(set.first().setup, set.first().file);
  args.out = options.out;
  args.threads = options.threads;
  args.quiet = options.quiet;
  return sweep_run(args, out, err, &set);
}

}  // namespace plancheck
