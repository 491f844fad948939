// SPDX-License-Identifier: MIT
#include "src/output/result_blob.h"

#include <bit>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <type_traits>

namespace plancheck {

static_assert(std::endian::native == std::endian::little, "result blobs are written little-endian, as the host");

// A tripwire: when one of these structs grows a field, these sizes change
// (on the x86-64 Debian 12 build CI runs); add the field to the writer and
// the reader below, then the new size here.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
static_assert(sizeof(StateResult) == 120, "StateResult changed: update src/output/result_blob.cpp");
static_assert(sizeof(SegmentResult) == 56, "SegmentResult changed: update src/output/result_blob.cpp");
static_assert(sizeof(PlanResult) == 400, "PlanResult changed: update src/output/result_blob.cpp");
static_assert(sizeof(DigSummary) == 120, "DigSummary changed: update src/output/result_blob.cpp");
static_assert(sizeof(Violation) == 32, "Violation changed: update src/output/result_blob.cpp");
#endif

namespace {

constexpr std::uint32_t kMagic = 0x31525050;  // "PPR1": plancheck plan results, layout 1

class Writer {
 public:
  explicit Writer(std::string& out) : out_(out) {}
  template <typename T>
  void raw(T v) {
    static_assert(std::is_trivially_copyable_v<T>);
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    out_.append(b, sizeof(T));
  }
  void u64(std::uint64_t v) { raw(v); }
  void i32(int v) { raw(static_cast<std::int32_t>(v)); }
  void f64(double v) { raw(v); }
  void flag(bool v) { raw(static_cast<std::uint8_t>(v ? 1 : 0)); }
  void vec(const Vec3& v) {
    for (int i = 0; i < 3; ++i) f64(v[i]);
  }
  void str(const std::string& s) {
    u64(s.size());
    out_ += s;
  }

 private:
  std::string& out_;
};

class Reader {
 public:
  explicit Reader(std::string_view in) : in_(in) {}
  template <typename T>
  T raw() {
    if (in_.size() - pos_ < sizeof(T)) throw std::runtime_error("plan results cut short");
    T v;
    std::memcpy(&v, in_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  std::uint64_t u64() { return raw<std::uint64_t>(); }
  int i32() { return raw<std::int32_t>(); }
  double f64() { return raw<double>(); }
  bool flag() {
    const auto b = raw<std::uint8_t>();
    if (b > 1) throw std::runtime_error("plan results: a flag is not 0 or 1");
    return b == 1;
  }
  Vec3 vec() {
    Vec3 v;
    for (int i = 0; i < 3; ++i) v[i] = f64();
    return v;
  }
  // A count of items each at least `min_bytes` long: never more than what is left.
  std::size_t count(std::size_t min_bytes) {
    const std::uint64_t n = u64();
    if (n > (in_.size() - pos_) / std::max<std::size_t>(min_bytes, 1))
      throw std::runtime_error("plan results: a count exceeds the bytes left");
    return static_cast<std::size_t>(n);
  }
  std::string str() {
    const std::size_t n = count(1);
    std::string s(in_.substr(pos_, n));
    pos_ += n;
    return s;
  }
  bool done() const { return pos_ == in_.size(); }

 private:
  std::string_view in_;
  std::size_t pos_ = 0;
};

void write_state(Writer& w, const StateResult& st) {
  w.flag(st.collision);
  w.u64(st.contacts.size());
  for (const PairContact& c : st.contacts) {
    w.i32(c.part_a);
    w.i32(c.part_b);
    w.u64(c.triangles.size());
    for (const auto& [a, b] : c.triangles) {
      w.raw(a);
      w.raw(b);
    }
  }
  w.f64(st.min_distance);
  w.i32(st.part_a);
  w.i32(st.part_b);
  w.vec(st.point_a);
  w.vec(st.point_b);
  w.i32(st.limit_action);
  w.f64(st.distance_tolerance);
  w.flag(st.distance_is_bound);
}

StateResult read_state(Reader& r) {
  StateResult st;
  st.collision = r.flag();
  st.contacts.resize(r.count(16));
  for (PairContact& c : st.contacts) {
    c.part_a = r.i32();
    c.part_b = r.i32();
    c.triangles.resize(r.count(8));
    for (auto& [a, b] : c.triangles) {
      a = r.raw<std::uint32_t>();
      b = r.raw<std::uint32_t>();
    }
  }
  st.min_distance = r.f64();
  st.part_a = r.i32();
  st.part_b = r.i32();
  st.point_a = r.vec();
  st.point_b = r.vec();
  st.limit_action = r.i32();
  st.distance_tolerance = r.f64();
  st.distance_is_bound = r.flag();
  return st;
}

void write_segment(Writer& w, const SegmentResult& g) {
  w.flag(g.checked);
  w.flag(g.collision);
  w.flag(g.clearance);
  w.f64(g.lower_bound);
  w.f64(g.min_sampled);
  w.i32(g.part_a);
  w.i32(g.part_b);
  w.f64(g.witness_t);
  w.u64(g.steps);
  w.flag(g.unresolved);
}

SegmentResult read_segment(Reader& r) {
  SegmentResult g;
  g.checked = r.flag();
  g.collision = r.flag();
  g.clearance = r.flag();
  g.lower_bound = r.f64();
  g.min_sampled = r.f64();
  g.part_a = r.i32();
  g.part_b = r.i32();
  g.witness_t = r.f64();
  g.steps = r.u64();
  g.unresolved = r.flag();
  return g;
}

Verdict read_verdict(Reader& r) {
  const int v = r.i32();
  if (v < static_cast<int>(Verdict::kSafe) || v > static_cast<int>(Verdict::kTarget))
    throw std::runtime_error("plan results: an unknown verdict");
  return static_cast<Verdict>(v);
}

void write_plan(Writer& w, const PlanResult& p) {
  w.u64(p.states.size());
  for (const StateResult& st : p.states) write_state(w, st);
  w.i32(static_cast<int>(p.verdict));
  w.flag(p.first_violation.has_value());
  if (p.first_violation) {
    const Violation& v = *p.first_violation;
    w.u64(v.state);
    w.i32(static_cast<int>(v.kind));
    w.i32(v.part_a);
    w.i32(v.part_b);
    w.i32(v.action);
    w.flag(v.between);
  }
  w.f64(p.min_distance);
  w.u64(p.min_distance_state);
  w.i32(p.min_part_a);
  w.i32(p.min_part_b);
  w.vec(p.min_point_a);
  w.vec(p.min_point_b);
  w.flag(p.target_error.has_value());
  if (p.target_error) w.f64(*p.target_error);
  w.f64(p.seconds);
  w.u64(p.dig_steps.size());
  for (const DigStep& d : p.dig_steps) {
    w.flag(d.in_soil);
    w.f64(d.depth);
    w.f64(d.volume);
  }
  w.flag(p.dig.has_value());
  if (p.dig) {
    const DigSummary& d = *p.dig;
    w.str(d.model);
    w.flag(d.dug);
    w.f64(d.dug_volume);
    w.f64(d.collected_volume);
    w.f64(d.spilled_volume);
    w.f64(d.collected_mass);
    w.flag(d.over_capacity);
    w.f64(d.deepest);
    w.u64(d.deepest_state);
    w.vec(d.deepest_point);
  }
  w.u64(p.probes.size());
  for (const auto& row : p.probes) {
    w.u64(row.size());
    for (const ProbeReading& pr : row) {
      w.f64(pr.distance);
      w.i32(pr.hit);
    }
  }
  w.u64(p.probe_targets.size());
  for (const std::string& t : p.probe_targets) w.str(t);
  w.u64(p.segments.size());
  for (const SegmentResult& g : p.segments) write_segment(w, g);
}

PlanResult read_plan(Reader& r) {
  PlanResult p;
  const std::size_t states = r.count(1);
  p.states.reserve(states);
  for (std::size_t s = 0; s < states; ++s) p.states.push_back(read_state(r));
  p.verdict = read_verdict(r);
  if (r.flag()) {
    Violation v;
    v.state = r.u64();
    v.kind = read_verdict(r);
    v.part_a = r.i32();
    v.part_b = r.i32();
    v.action = r.i32();
    v.between = r.flag();
    p.first_violation = v;
  }
  p.min_distance = r.f64();
  p.min_distance_state = r.u64();
  p.min_part_a = r.i32();
  p.min_part_b = r.i32();
  p.min_point_a = r.vec();
  p.min_point_b = r.vec();
  if (r.flag()) p.target_error = r.f64();
  p.seconds = r.f64();
  p.dig_steps.resize(r.count(17));
  for (DigStep& d : p.dig_steps) {
    d.in_soil = r.flag();
    d.depth = r.f64();
    d.volume = r.f64();
  }
  if (r.flag()) {
    DigSummary d;
    d.model = r.str();
    d.dug = r.flag();
    d.dug_volume = r.f64();
    d.collected_volume = r.f64();
    d.spilled_volume = r.f64();
    d.collected_mass = r.f64();
    d.over_capacity = r.flag();
    d.deepest = r.f64();
    d.deepest_state = r.u64();
    d.deepest_point = r.vec();
    p.dig = d;
  }
  p.probes.resize(r.count(8));
  for (auto& row : p.probes) {
    row.resize(r.count(12));
    for (ProbeReading& pr : row) {
      pr.distance = r.f64();
      pr.hit = r.i32();
    }
  }
  p.probe_targets.resize(r.count(8));
  for (std::string& t : p.probe_targets) t = r.str();
  p.segments.resize(r.count(44));
  for (SegmentResult& g : p.segments) g = read_segment(r);
  return p;
}

}  // namespace

void append_plan_results(const std::vector<PlanResult>& results, std::string& out) {
  Writer w(out);
  w.raw(kMagic);
  w.u64(results.size());
  for (const PlanResult& p : results) write_plan(w, p);
}

void read_plan_results(std::string_view bytes, const std::vector<Plan>& plans, std::vector<PlanResult>& out) {
  Reader r(bytes);
  if (r.raw<std::uint32_t>() != kMagic) throw std::runtime_error("plan results: not of layout 1");
  const std::size_t n = r.count(1);
  for (std::size_t k = 0; k < n; ++k) {
    if (out.size() >= plans.size()) throw std::runtime_error("plan results: more results than plans");
    PlanResult p = read_plan(r);
    p.plan = &plans[out.size()];
    if (p.states.size() != p.plan->states.size())
      throw std::runtime_error("plan results: " + p.plan->name + " has " + std::to_string(p.plan->states.size()) +
                               " states, the results " + std::to_string(p.states.size()));
    out.push_back(std::move(p));
  }
  if (!r.done()) throw std::runtime_error("plan results: bytes left over");
}

}  // namespace plancheck
