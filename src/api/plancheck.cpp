// SPDX-License-Identifier: MIT
// The public API (plancheck/plancheck.h) over the core: a thin layer that
// converts units, validates states and turns the core's errors into
// plancheck::Error with verify's message.
//
// The core's types (plancheck::Scene, plancheck::Checker, ...) share short
// names with the public ones (plancheck::v0::...): they are given aliases
// here before the public header is read, and only the aliases are used after.
#include "src/base/error.h"
#include "src/base/parallel.h"
#include "src/scene/objects.h"
#include "src/scene/plan.h"
#include "src/scene/scene_loader.h"
#include "src/checks/continuous.h"
#include "src/checks/verify.h"

namespace plancheck_core {
using Scene = ::plancheck::Scene;
using Checker = ::plancheck::Checker;
using StateResult = ::plancheck::StateResult;
using Verdict = ::plancheck::Verdict;
using ActionType = ::plancheck::ActionType;
using InputError = ::plancheck::InputError;
using SceneOptions = ::plancheck::SceneOptions;
using ::plancheck::hardware_threads;
using ::plancheck::load_scene;
using ::plancheck::load_plan;
using ::plancheck::derive_pairs;
using ::plancheck::ObjectPlace;
using ::plancheck::WorldObject;
using ::plancheck::ObjectShape;
using Mesh = ::plancheck::Mesh;
using Vec3 = ::plancheck::Vec3;
using ::plancheck::parallel_for;
using ::plancheck::state_verdict;
using ::plancheck::row_request;
using ::plancheck::verdict_only_request;
using CheckRequest = ::plancheck::CheckRequest;
using SegmentChecker = ::plancheck::SegmentChecker;
using SegmentResult = ::plancheck::SegmentResult;
using ContinuousOptions = ::plancheck::ContinuousOptions;
}  // namespace plancheck_core

#include "src/api/plancheck/plancheck.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <exception>
#include <map>
#include <mutex>
#include <utility>

#ifndef PLANCHECK_VERSION
#error "PLANCHECK_VERSION must be defined by the build (project(VERSION))"
#endif

namespace plancheck {
inline namespace v0 {

namespace detail {

struct SceneData {
  plancheck_core::Scene scene;
  std::vector<bool> is_factor;  // per parameter: a scale factor (must be positive)
};

// One version of the world: a scene and the structures built for it.
struct Snapshot {
  std::shared_ptr<const SceneData> scene;  // the core checker refers to it
  std::unique_ptr<const plancheck_core::Checker> checker;
  std::vector<std::string> part_names;
  // Static objects moved since `scene` was made (a placement in `checker`
  // only, nothing built): name -> pose in the parent's frame (SI).
  std::map<std::string, ::plancheck::Affine> moved;
  // verify --continuous's defaults, made by the first motion check of this version.
  const plancheck_core::SegmentChecker& segments() const {
    std::call_once(segments_made, [&] {
      segments_ = std::make_unique<const plancheck_core::SegmentChecker>(*checker, scene->scene,
                                                                          plancheck_core::ContinuousOptions{});
    });
    return *segments_;
  }

 private:
  mutable std::once_flag segments_made;
  mutable std::unique_ptr<const plancheck_core::SegmentChecker> segments_;
};

// What copies of a Checker share: the current version of the world, loaded
// once by each check, batch or motion check (current()), and swapped whole
// by a change (changes one at a time, under `change`).
struct CheckerData {
  int threads = 1;
  std::shared_ptr<const Snapshot> current() const {
    std::lock_guard<std::mutex> lock(mutex);
    return snapshot;
  }
  void publish(std::shared_ptr<const Snapshot> next) {
    std::lock_guard<std::mutex> lock(mutex);
    snapshot = std::move(next);
  }
  std::mutex change;  // serialises add/move/remove

 private:
  mutable std::mutex mutex;  // guards `snapshot` (the pointer, never what it points to)
  std::shared_ptr<const Snapshot> snapshot;
};

}  // namespace detail

namespace {

// Runs f and turns what the core throws into Error, with the text the
// command line prints after "plancheck: " (src/main.cpp).
template <class F>
auto translated(F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const Error&) {
    throw;
  } catch (const plancheck_core::InputError& e) {
    throw Error(e.what());
  } catch (const std::exception& e) {
    throw Error(std::string("error: ") + e.what());
  }
}

// Throws Error when `state` (n values) cannot be checked; `where` prefixes
// the message ("state" or "state 12").
void validate(const detail::SceneData& data, const double* state, std::size_t n, const std::string& where) {
  const std::vector<std::string>& names = data.scene.parameter_names;
  if (n != names.size()) {
    std::string list;
    for (const std::string& name : names) list += (list.empty() ? "" : ", ") + name;
    throw Error(where + ": expected " + std::to_string(names.size()) + " values (" + list + "), got " +
                std::to_string(n));
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(state[i]))
      throw Error(where + ": parameter '" + names[i] + "' is not a finite number");
    if (data.is_factor[i] && !(state[i] > 0))
      throw Error(where + ": parameter '" + names[i] + "': scale factor must be positive");
  }
}

Verdict public_verdict(plancheck_core::Verdict v) {
  switch (v) {
    case plancheck_core::Verdict::kCollision: return Verdict::kCollision;
    case plancheck_core::Verdict::kClearance: return Verdict::kClearance;
    case plancheck_core::Verdict::kLimits: return Verdict::kLimits;
    default: return Verdict::kSafe;  // kTarget is a plan's, never a state's
  }
}

// One state, as verify's CSV row reports it (src/report.cpp) and as verify
// ranks it (state_verdict).
void check_one(const detail::Snapshot& d, const std::vector<double>& params, StateResult& out,
               const CheckOptions& options) {
  plancheck_core::StateResult st;
  const plancheck_core::Scene& scene = d.scene->scene;
  // A row needs no listing of intersecting triangles (row_request).
  d.checker->check_state(params, st,
                         options.verdict_only ? plancheck_core::verdict_only_request(scene.safety_margin)
                                              : plancheck_core::row_request());
  const double unit = scene.length_scale;
  out.min_distance_is_bound = st.distance_is_bound;
  out.collision = st.collision;
  out.part_a_index = st.part_a;
  out.part_b_index = st.part_b;
  if (st.part_a >= 0) {
    out.min_distance = st.min_distance / unit;
    out.part_a = d.part_names[static_cast<std::size_t>(st.part_a)];
    out.part_b = d.part_names[static_cast<std::size_t>(st.part_b)];
    for (int i = 0; i < 3; ++i) {
      out.point_a[static_cast<std::size_t>(i)] = st.point_a[i] / unit;
      out.point_b[static_cast<std::size_t>(i)] = st.point_b[i] / unit;
    }
  } else {
    out.min_distance = st.distance_is_bound ? st.min_distance / unit : std::numeric_limits<double>::infinity();
    out.part_a.clear();
    out.part_b.clear();
    out.point_a = {};
    out.point_b = {};
  }
  out.limits = st.limit_action >= 0 ? scene.actions[static_cast<std::size_t>(st.limit_action)].name : std::string();
  out.verdict = public_verdict(plancheck_core::state_verdict(st, scene.safety_margin));
}

void motion_checked(const detail::Snapshot& d, const std::vector<double>& from, const std::vector<double>& to,
                    MotionResult& out, const MotionOptions& options, int threads);

// A planner asks for the same motion again and again (simplifying a path
// asks for motions between its few states many times over, and checks the
// whole path again at the end): the answers this thread gave last (kKept,
// the least recently used replaced; on the OMPL bench's planner runs 128
// kept catch all but 15 and 16 of the repeats 1,024 would, 32 all but 86
// and 161) are kept, keyed by the world version
// (the core checker's own number: every change makes a new one), both
// states' bits and the options, and taken instead of checking again.
// motion_checked is a function of exactly these, so a kept answer is bit
// for bit the one a check gives.
// threads: for one motion's pairs (the answer does not depend on them).
void motion_one(const detail::Snapshot& d, const std::vector<double>& from, const std::vector<double>& to,
                MotionResult& out, const MotionOptions& options, int threads = 1) {
  struct Kept {
    std::uint64_t checker = 0;  // 0: empty
    std::uint64_t used = 0;
    std::uint64_t hash = 0;
    bool verdict_only = false, first_violation = false;
    std::vector<double> from, to;
    MotionResult result;
  };
  constexpr int kKept = 128;
  thread_local std::vector<Kept> kept(kKept);
  thread_local std::uint64_t clock = 0;
  const std::uint64_t id = d.checker->instance_id();
  std::uint64_t hash = 1469598103934665603ull;  // FNV-1a over both states' bytes
  for (const std::vector<double>* v : {&from, &to}) {
    const auto* bytes = reinterpret_cast<const unsigned char*>(v->data());
    for (std::size_t i = 0; i < v->size() * sizeof(double); ++i) hash = (hash ^ bytes[i]) * 1099511628211ull;
  }
  auto same = [](const std::vector<double>& x, const std::vector<double>& y) {
    return x.size() == y.size() && (x.empty() || std::memcmp(x.data(), y.data(), x.size() * sizeof(double)) == 0);
  };
  int slot = 0;
  for (int i = 0; i < kKept; ++i) {
    Kept& k = kept[static_cast<std::size_t>(i)];
    if (k.hash == hash && k.checker == id && k.verdict_only == options.verdict_only &&
        k.first_violation == options.first_violation && same(k.from, from) && same(k.to, to)) {
      k.used = ++clock;
      out = k.result;
      return;
    }
    if (k.used < kept[static_cast<std::size_t>(slot)].used) slot = i;
  }
  motion_checked(d, from, to, out, options, threads);
  Kept& k = kept[static_cast<std::size_t>(slot)];
  k.checker = id;
  k.used = ++clock;
  k.hash = hash;
  k.verdict_only = options.verdict_only;
  k.first_violation = options.first_violation;
  k.from = from;
  k.to = to;
  k.result = out;
}

// One motion, as verify --continuous ranks a two-state plan of it
// (src/checks/plan_check.cpp, verify_segments): state 0's own violation,
// then the segment's, then state 1's.
void motion_checked(const detail::Snapshot& d, const std::vector<double>& from, const std::vector<double>& to,
                    MotionResult& out, const MotionOptions& options, int threads) {
  plancheck_core::StateResult sa, sb;
  double until = 0.0;
  const plancheck_core::SegmentResult g = d.segments().check_motion(from, to, options.verdict_only, sa, sb, &until, options.first_violation, threads);
  const plancheck_core::Scene& scene = d.scene->scene;
  const double unit = scene.length_scale;
  out = MotionResult{};
  // An end in contact is a contact of the motion (without first_violation
  // the contact pass has found it already).
  out.collision = g.collision || sa.collision || sb.collision;
  // 0 wherever a contact is known (first_violation's NaN bound included).
  out.min_distance = out.collision ? 0.0 : g.lower_bound / unit;
  out.certified = !g.unresolved;
  out.steps = g.steps;
  int a = -1, b = -1;
  const Verdict v0 = public_verdict(plancheck_core::state_verdict(sa, scene.safety_margin));
  if (v0 != Verdict::kSafe) {
    out.verdict = v0;
    out.t = 0.0;
    if (v0 == Verdict::kCollision) {
      a = sa.contacts[0].part_a;
      b = sa.contacts[0].part_b;
    } else if (v0 == Verdict::kClearance) {
      a = sa.part_a;
      b = sa.part_b;
    }
  } else if (options.first_violation && g.witness_t == 1.0 && sb.collision) {
    // The margin pass stopped at state 1, which touches: the contact pass
    // would have stopped there too (ends first).
    out.verdict = Verdict::kCollision;
    out.t = 1.0;
    a = sb.contacts[0].part_a;
    b = sb.contacts[0].part_b;
  } else if (g.collision || g.clearance) {
    out.verdict = g.collision ? Verdict::kCollision : Verdict::kClearance;
    if (g.witness_t >= 0.0) out.t = g.witness_t;
    a = g.part_a;
    b = g.part_b;
  } else {
    out.verdict = public_verdict(plancheck_core::state_verdict(sb, scene.safety_margin));
    if (out.verdict != Verdict::kSafe) out.t = 1.0;
  }
  if (out.verdict == Verdict::kSafe)
    out.safe_until = 1.0;
  else if (v0 == Verdict::kSafe && (g.collision || g.clearance))
    out.safe_until = until;  // (first_violation: the first pass's, the same)
  if (a >= 0) {
    out.part_a_index = a;
    out.part_b_index = b;
    out.part_a = d.part_names[static_cast<std::size_t>(a)];
    out.part_b = d.part_names[static_cast<std::size_t>(b)];
  }
}

}  // namespace

const char* version() noexcept { return PLANCHECK_VERSION; }

Error::Error(const std::string& message) : std::runtime_error(message) {}
Error::~Error() = default;

const char* verdict_name(Verdict v) noexcept {
  switch (v) {
    case Verdict::kSafe: return "safe";
    case Verdict::kClearance: return "clearance";
    case Verdict::kCollision: return "collision";
    case Verdict::kLimits: return "limits";
  }
  return "?";
}

Scene::Scene(std::shared_ptr<const detail::SceneData> data) : data_(std::move(data)) {}

Scene Scene::load(const std::string& path, const LoadOptions& options) {
  return translated([&] {
    plancheck_core::SceneOptions o;
    o.srdf = options.srdf;
    for (const auto& [name, dir] : options.packages) o.packages[name] = dir;
    auto data = std::make_shared<detail::SceneData>(detail::SceneData{plancheck_core::load_scene(path, o), {}});
    data->is_factor.assign(data->scene.parameter_names.size(), false);
    for (const auto& a : data->scene.actions)
      if (a.type == plancheck_core::ActionType::kScale)
        for (int k = 0; k < a.parameter_count; ++k) data->is_factor[static_cast<std::size_t>(a.first_parameter + k)] = true;
    return Scene(std::move(data));
  });
}

const std::vector<std::string>& Scene::parameter_names() const { return data_->scene.parameter_names; }
std::vector<double> Scene::reference_state() const { return data_->scene.reference_parameters; }

std::vector<double> Scene::lower_limits() const {
  std::vector<double> out(data_->scene.parameter_names.size(), -std::numeric_limits<double>::infinity());
  for (const auto& a : data_->scene.actions)
    if (a.has_limits)
      for (int k = 0; k < a.parameter_count; ++k) out[static_cast<std::size_t>(a.first_parameter + k)] = a.lower;
  return out;
}

std::vector<double> Scene::upper_limits() const {
  std::vector<double> out(data_->scene.parameter_names.size(), std::numeric_limits<double>::infinity());
  for (const auto& a : data_->scene.actions)
    if (a.has_limits)
      for (int k = 0; k < a.parameter_count; ++k) out[static_cast<std::size_t>(a.first_parameter + k)] = a.upper;
  return out;
}

double Scene::safety_margin() const { return data_->scene.safety_margin / data_->scene.length_scale; }
std::string Scene::length_unit() const { return data_->scene.length_unit; }
std::string Scene::angle_unit() const { return data_->scene.angle_unit; }

std::vector<std::vector<double>> Scene::read_plan(const std::string& path) const {
  return translated([&] { return plancheck_core::load_plan(data_->scene, path).states; });
}

namespace {

std::shared_ptr<const detail::Snapshot> build_snapshot(std::shared_ptr<const detail::SceneData> scene, int threads,
                                                       const detail::Snapshot* earlier) {
  auto d = std::make_shared<detail::Snapshot>();
  d->scene = std::move(scene);
  d->checker = std::make_unique<const plancheck_core::Checker>(d->scene->scene, threads, nullptr,
                                                               earlier != nullptr ? earlier->checker.get() : nullptr);
  for (std::size_t i = 0; i < d->checker->part_count(); ++i) d->part_names.push_back(d->checker->part_name(static_cast<int>(i)));
  return d;
}

plancheck_core::ObjectPlace place_of(const std::string& name) { return {{}, "objects['" + name + "']"}; }

// A world change: `edit` changes a copy of the current scene; the new
// version shares every unchanged part's structure with the current one.
template <class Edit>
void change_world(detail::CheckerData& data, Edit&& edit) {
  std::lock_guard<std::mutex> lock(data.change);
  const std::shared_ptr<const detail::Snapshot> now = data.current();
  auto scene = std::make_shared<detail::SceneData>(*now->scene);
  translated([&] {
    for (const auto& [name, pose] : now->moved) ::plancheck::move_object(scene->scene, name, pose, place_of(name));
    // The API neither digs nor casts probes: a changed world builds neither.
    scene->scene.probes.clear();
    scene->scene.scoop.reset();
    edit(scene->scene);
    data.publish(build_snapshot(std::move(scene), data.threads, now.get()));
  });
}

plancheck_core::WorldObject core_object(const plancheck_core::Scene& scene, const Object& o,
                                        const plancheck_core::ObjectPlace& at) {
  plancheck_core::WorldObject w;
  w.name = o.name;
  const double s = scene.length_scale;
  plancheck_core::Mesh local;
  switch (o.shape) {
    case Object::Shape::kBox:
      w.shape = plancheck_core::ObjectShape::kBox;
      local = ::plancheck::box_object(plancheck_core::Vec3(o.box[0], o.box[1], o.box[2]) * s, at);
      break;
    case Object::Shape::kCylinder:
      w.shape = plancheck_core::ObjectShape::kCylinder;
      local = ::plancheck::cylinder_object(o.radius * s, o.length * s, at);
      break;
    case Object::Shape::kSphere:
      w.shape = plancheck_core::ObjectShape::kSphere;
      local = ::plancheck::sphere_object(o.radius * s, at);
      break;
    case Object::Shape::kMesh: {
      w.shape = plancheck_core::ObjectShape::kMesh;
      if (o.mesh.empty()) at.error("mesh", "empty path");
      w.mesh_file = o.mesh;
      std::vector<std::string> warnings;
      local = ::plancheck::mesh_object(w.mesh_file, plancheck_core::Vec3(o.scale[0], o.scale[1], o.scale[2]) * s,
                                       warnings, at);
      break;
    }
    default:
      at.error("shape", "unknown shape");
  }
  w.local = std::make_shared<const plancheck_core::Mesh>(std::move(local));
  w.parent = ::plancheck::object_parent(scene, o.parent, at);
  return w;
}

::plancheck::Affine core_pose(const plancheck_core::Scene& scene, const Pose& p, const plancheck_core::ObjectPlace& at) {
  for (double v : p.xyz)
    if (!std::isfinite(v)) at.error("pose.xyz", "not a finite number");
  for (double v : p.rpy)
    if (!std::isfinite(v)) at.error("pose.rpy", "not a finite number");
  return ::plancheck::pose_of(plancheck_core::Vec3(p.xyz[0], p.xyz[1], p.xyz[2]) * scene.length_scale,
                              plancheck_core::Vec3(p.rpy[0], p.rpy[1], p.rpy[2]) * scene.angle_scale);
}

}  // namespace

Checker::Checker(const Scene& scene, int threads) {
  data_ = translated([&] {
    auto d = std::make_shared<detail::CheckerData>();
    d->threads = threads > 0 ? threads : plancheck_core::hardware_threads();
    d->publish(build_snapshot(scene.data_, d->threads, nullptr));
    return d;
  });
}

void Checker::add_object(const Object& object) {
  change_world(*data_, [&](plancheck_core::Scene& scene) {
    const plancheck_core::ObjectPlace at = place_of(object.name);
    plancheck_core::WorldObject w = core_object(scene, object, at);
    w.pose = core_pose(scene, object.pose, at);
    ::plancheck::add_object(scene, std::move(w), at);
    plancheck_core::derive_pairs(scene);
  });
}

void Checker::move_object(const std::string& name, const Pose& pose) {
  detail::CheckerData& data = *data_;
  {
    // A static object: a new placement in a copy of the current checker,
    // whose every structure it shares (nothing is built).
    std::lock_guard<std::mutex> lock(data.change);
    const std::shared_ptr<const detail::Snapshot> now = data.current();
    const plancheck_core::Scene& scene = now->scene->scene;
    const plancheck_core::ObjectPlace at = place_of(name);
    const bool moved = translated([&] {
      const int i = ::plancheck::find_object(scene, name);
      if (i < 0) at.error("", "no object named '" + name + "'");
      const int part = scene.find_part(name);
      if (scene.parts[static_cast<std::size_t>(part)].moving()) return false;
      plancheck_core::WorldObject there = scene.objects[static_cast<std::size_t>(i)];
      there.pose = core_pose(scene, pose, at);
      const ::plancheck::Affine placement =
          ::plancheck::object_frame(scene, there) *
          ::plancheck::object_frame(scene, scene.objects[static_cast<std::size_t>(i)]).inverse(Eigen::Isometry);
      if (!placement.matrix().allFinite()) at.error("pose", "not finite");
      auto next = std::make_shared<detail::Snapshot>();
      next->scene = now->scene;
      next->checker = now->checker->with_placement(part, placement);
      next->part_names = now->part_names;
      next->moved = now->moved;
      next->moved[name] = there.pose;
      data.publish(std::move(next));
      return true;
    });
    if (moved) return;
  }
  // An object on a moving node: its part is posed again and built.
  change_world(data, [&](plancheck_core::Scene& scene) {
    const plancheck_core::ObjectPlace at = place_of(name);
    ::plancheck::move_object(scene, name, core_pose(scene, pose, at), at);
  });
}

void Checker::remove_object(const std::string& name) {
  change_world(*data_, [&](plancheck_core::Scene& scene) {
    ::plancheck::remove_object(scene, name, place_of(name));
    plancheck_core::derive_pairs(scene);
  });
}

std::vector<std::string> Checker::object_names() const {
  std::vector<std::string> out;
  for (const auto& o : data_->current()->scene->scene.objects) out.push_back(o.name);
  return out;
}

StateResult Checker::check(const std::vector<double>& state) const { return check(state, CheckOptions{}); }

StateResult Checker::check(const std::vector<double>& state, const CheckOptions& options) const {
  const auto now = data_->current();
  validate(*now->scene, state.data(), state.size(), "state");
  StateResult out;
  translated([&] { check_one(*now, state, out, options); });
  return out;
}

std::vector<StateResult> Checker::check_batch(const std::vector<std::vector<double>>& states) const {
  return check_batch(states, CheckOptions{});
}

std::vector<StateResult> Checker::check_batch(const std::vector<std::vector<double>>& states,
                                              const CheckOptions& options) const {
  const std::size_t n = parameter_count();
  const auto now = data_->current();
  for (std::size_t i = 0; i < states.size(); ++i)
    validate(*now->scene, states[i].data(), states[i].size(), "state " + std::to_string(i));
  std::vector<double> rows;
  rows.reserve(states.size() * n);
  for (const auto& s : states) rows.insert(rows.end(), s.begin(), s.end());
  std::vector<StateResult> out(states.size());
  check_batch(rows.data(), states.size(), out.data(), options);
  return out;
}

void Checker::check_batch(const double* states, std::size_t count, StateResult* out) const {
  check_batch(states, count, out, CheckOptions{});
}

void Checker::check_batch(const double* states, std::size_t count, StateResult* out,
                          const CheckOptions& options) const {
  const std::size_t n = parameter_count();
  const auto now = data_->current();  // the whole batch on one version of the world
  for (std::size_t i = 0; i < count; ++i) validate(*now->scene, states + i * n, n, "state " + std::to_string(i));
  // States are independent (no coherence seed between them), so out[i] is
  // check(state i) bit for bit whatever the thread count. Small chunks: a
  // state costs tens of microseconds or more.
  translated([&] {
    plancheck_core::parallel_for(count, data_->threads, 4, [&](std::size_t begin, std::size_t end, int) {
      std::vector<double> params(n);
      for (std::size_t i = begin; i < end; ++i) {
        params.assign(states + i * n, states + (i + 1) * n);
        check_one(*now, params, out[i], options);
      }
    });
  });
}

MotionResult Checker::check_motion(const std::vector<double>& from, const std::vector<double>& to,
                                   const MotionOptions& options) const {
  const auto now = data_->current();  // the whole motion on one version of the world
  validate(*now->scene, from.data(), from.size(), "from");
  validate(*now->scene, to.data(), to.size(), "to");
  MotionResult out;
  // One motion: its pairs march on the checker's threads.
  translated([&] { motion_one(*now, from, to, out, options, data_->threads); });
  return out;
}

std::vector<MotionResult> Checker::check_motion_batch(const std::vector<std::vector<double>>& from,
                                                      const std::vector<std::vector<double>>& to,
                                                      const MotionOptions& options) const {
  if (from.size() != to.size())
    throw Error("motions: " + std::to_string(from.size()) + " start states but " + std::to_string(to.size()) +
                " end states");
  const std::size_t n = parameter_count();
  std::vector<double> a, b;
  a.reserve(from.size() * n);
  b.reserve(to.size() * n);
  const auto now = data_->current();
  for (std::size_t i = 0; i < from.size(); ++i) {
    validate(*now->scene, from[i].data(), from[i].size(), "from " + std::to_string(i));
    validate(*now->scene, to[i].data(), to[i].size(), "to " + std::to_string(i));
    a.insert(a.end(), from[i].begin(), from[i].end());
    b.insert(b.end(), to[i].begin(), to[i].end());
  }
  std::vector<MotionResult> out(from.size());
  check_motion_batch(a.data(), b.data(), from.size(), out.data(), options);
  return out;
}

void Checker::check_motion_batch(const double* from, const double* to, std::size_t count, MotionResult* out,
                                 const MotionOptions& options) const {
  const std::size_t n = parameter_count();
  const auto now = data_->current();  // every motion of the batch on one version of the world
  for (std::size_t i = 0; i < count; ++i) {
    validate(*now->scene, from + i * n, n, "from " + std::to_string(i));
    validate(*now->scene, to + i * n, n, "to " + std::to_string(i));
  }
  // Motions are independent: out[i] is check_motion(i) whatever the thread
  // count. One motion per chunk: a motion costs from one to thousands of checks.
  if (count == 1) {
    // One motion (a planner's, from Python): its pairs on the threads.
    std::vector<double> a(from, from + n), b(to, to + n);
    translated([&] { motion_one(*now, a, b, out[0], options, data_->threads); });
    return;
  }
  translated([&] {
    plancheck_core::parallel_for(count, data_->threads, 1, [&](std::size_t begin, std::size_t end, int) {
      std::vector<double> a(n), b(n);
      for (std::size_t i = begin; i < end; ++i) {
        a.assign(from + i * n, from + (i + 1) * n);
        b.assign(to + i * n, to + (i + 1) * n);
        motion_one(*now, a, b, out[i], options);
      }
    });
  });
}

Scene Checker::scene() const { return Scene(data_->current()->scene); }

std::vector<std::string> Checker::part_names() const { return data_->current()->part_names; }
std::size_t Checker::parameter_count() const { return data_->current()->scene->scene.parameter_names.size(); }
int Checker::threads() const { return data_->threads; }

}  // namespace v0
}  // namespace plancheck
