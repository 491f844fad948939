// SPDX-License-Identifier: MIT
// plancheck as a library: load a scene, then check robot states against it
// with the same per-state answers as `plancheck verify` (contract:
// shared/spec/plan-and-report-format.md, "Embedding").
//
//   plancheck::Scene scene = plancheck::Scene::load("scene.json");  // throws plancheck::Error
//   plancheck::Checker checker(scene);                               // thread-safe
//   std::vector<double> state(scene.parameter_names().size(), 0.0);  // plan units, as written
//   plancheck::StateResult r = checker.check(state);
//   if (r.verdict != plancheck::Verdict::kSafe) ...
//   plancheck::MotionResult m = checker.check_motion(state, other);  // the motion between, certified
//
// Units are the scene's: states in plan units as a plan CSV writes them
// (degrees stay degrees, 720 is two turns), lengths in the scene's
// length_unit. Every state is checked on its own on the scene's initial
// terrain: nothing is dug (digging happens only along a plan in `verify`).
//
// This header is the whole public interface: it needs only the standard
// library, and the library exports nothing else.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

// The library is built with hidden visibility: only what carries this is exported.
#define PLANCHECK_API __attribute__((visibility("default")))

namespace plancheck {
// The public types sit in an inline namespace: callers write plancheck::Scene,
// while the library's own internal types of the same short names (the
// loader's plancheck::Scene, the core's plancheck::Checker) never share a
// mangled name with them. A TU must not include both.
inline namespace v0 {

namespace detail {
struct SceneData;
struct CheckerData;
}  // namespace detail

// The library's version (semantic versioning), as `plancheck --version` prints it.
PLANCHECK_API const char* version() noexcept;

// Bad input: a scene, model, DEM or state that cannot be used. what() is the
// message `plancheck verify` prints for the same input, after its
// "plancheck: " prefix.
class PLANCHECK_API Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message);
  ~Error() override;
};

// A state's verdict, ranked as `verify` ranks it; the values are the codes of
// `sweep`'s verdict.npy.
enum class Verdict : std::uint8_t {
  kSafe = 0,       // no checked pair closer than the safety margin, all parameters within limits
  kClearance = 1,  // a checked pair below the margin (or too close to it to settle in double)
  kCollision = 2,  // two checked parts intersect or touch
  kLimits = 3,     // a driving parameter outside its limits (no collision, no clearance violation)
};
PLANCHECK_API const char* verdict_name(Verdict v) noexcept;  // "safe", "clearance", "collision", "limits"

// What one state shows: one row of verify's per-plan CSV, and its verdict.
struct StateResult {
  bool collision = false;  // some checked pair intersects or touches
  // Minimum distance over the checked pairs (length_unit; 0 when colliding;
  // infinity when the scene checks no pair).
  double min_distance = std::numeric_limits<double>::infinity();
  // The pair at min_distance (the first colliding pair when colliding),
  // moving part first; "" and -1 when no pair is checked. Indices are into
  // Checker::part_names().
  std::string part_a, part_b;
  int part_a_index = -1, part_b_index = -1;
  // Closest points on part_a and part_b (length_unit, scene reference frame).
  std::array<double, 3> point_a{}, point_b{};
  // The first driving parameter's action outside its limits ("" none), as
  // verify's CSV `limits` column names it.
  std::string limits;
  Verdict verdict = Verdict::kSafe;
  // A verdict-only check (CheckOptions::verdict_only) that proved every pair
  // beyond the margin without an exact distance: min_distance is then a
  // certified lower bound, and part_a/part_b and the points are empty.
  bool min_distance_is_bound = false;
};

// What a check computes. The verdict is the same either way.
struct CheckOptions {
  // false (default): verify's full answer, as its CSV row has it (the first
  // colliding pair, the exact minimum distance and its points). true: verify
  // --verdict-only's: exact distances only below the safety margin
  // (min_distance_is_bound otherwise). Faster, most on safe states.
  bool verdict_only = false;
};

// What a motion check computes. The verdict is the same either way.
struct MotionOptions {
  // false (default): the segment's lower bound as verify --continuous
  // computes it. true: exact distances only where they decide the verdict
  // (what a planner's motion validator needs): min_distance is then a
  // looser certified bound on safe segments. Same verdict, t and pair.
  bool verdict_only = false;
  // true (with verdict_only): only whether the motion is safe, what a
  // planner's motion validator needs. The check stops at the first witness
  // below the margin and does not look on for a contact. verdict is kSafe
  // exactly when it would be without this, and safe_until is the same. An
  // unsafe motion is described by that witness: its t and pair, verdict
  // kClearance even where the motion goes on into a contact (kCollision
  // where state 0 or the witness, state 1, touches), collision true only
  // where an end touches, min_distance NaN (no bound over the whole motion
  // was made; 0 where an end touches). Without a margin there is one pass:
  // the same answer as without it. Safe motions: the same answer too.
  bool first_violation = false;
};

// What the straight-line motion between two states shows (in plan units,
// each parameter linear from its value as written to the other's: 0 -> 720
// is two turns): verify --continuous's answer for a two-state plan of it.
struct MotionResult {
  // The two-state plan's verdict: the first violation in the order state 0,
  // the motion, state 1 (as verify ranks them). A motion whose certification
  // needs more pair checks than the budget (thousands of turns) is a
  // kClearance violation with no pair, certified false.
  Verdict verdict = Verdict::kSafe;
  bool collision = false;  // parts touch somewhere on the motion, ends included
  // A certified lower bound of the minimum distance over the whole motion,
  // ends included (length_unit; 0 where a contact is found; infinity when
  // the scene checks no pair).
  double min_distance = std::numeric_limits<double>::infinity();
  // Where the first violation's witness lies, as a fraction of the motion
  // (0: state 0, 1: state 1); NaN when safe or with no witness.
  double t = std::numeric_limits<double>::quiet_NaN();
  // The witness's pair (the first colliding pair, or the pair below the
  // margin), moving part first; "" and -1 when none.
  std::string part_a, part_b;
  int part_a_index = -1, part_b_index = -1;
  bool certified = true;  // false: the step budget ran out (verdict kClearance, no witness)
  std::size_t steps = 0;  // pair checks between the ends (one pair's search at one configuration each)
  // The motion is certified safe from state 0 up to this fraction of it (1
  // when the verdict is safe; 0 when state 0 is not safe or nothing beyond
  // it was proven): what OMPL's checkMotion(s1, s2, lastValid) reports.
  double safe_until = 0.0;
};

// Where a world object stands: translation `xyz` (length_unit), then
// `rpy` (angle_unit): roll, pitch, yaw about the fixed x, y, z axes, as a
// URDF origin; in the frame of the object's parent.
struct Pose {
  std::array<double, 3> xyz{};
  std::array<double, 3> rpy{};
};

// A world object, as the scene file's `objects` describes one
// (scene-format.md "World objects"): exactly one shape.
struct Object {
  enum class Shape : std::uint8_t { kBox, kCylinder, kSphere, kMesh };
  std::string name;             // unique among parts, nodes and links
  Shape shape = Shape::kBox;
  std::array<double, 3> box{};  // kBox: full edge lengths (length_unit), centred at the pose
  double radius = 0.0;          // kCylinder (axis local z, centred) and kSphere (length_unit)
  double length = 0.0;          // kCylinder
  std::string mesh;             // kMesh: a file the model loader reads (as given: relative to the working directory)
  std::array<double, 3> scale{1.0, 1.0, 1.0};  // kMesh: per axis, on the file's coordinates (in length_unit)
  Pose pose;
  std::string parent;           // a model node or robot link it moves with; "": the world
};

// What Scene::load reads beside the scene file (the command line's --srdf
// and --package options; for a bare .urdf scene).
struct LoadOptions {
  std::string srdf;                           // SRDF whose disable_collisions pairs are allowed
  std::map<std::string, std::string> packages;  // package name -> folder, for package:// meshes
};

// A loaded scene: parts, actions, checked pairs, terrain. Immutable; copies
// share the loaded data.
class PLANCHECK_API Scene {
 public:
  // Reads a plancheck-scene/1 JSON (or a bare .urdf) and the files it names.
  // Throws Error with verify's message for the same file.
  static Scene load(const std::string& path, const LoadOptions& options = {});

  // The plan column names in order: one per rotation or axis translation,
  // NAME.x, NAME.y, NAME.z for a free translation or a scale. A state is one
  // value per name.
  const std::vector<std::string>& parameter_names() const;
  // The reference state (0 for rotations and translations, 1 for scales).
  std::vector<double> reference_state() const;
  // Limits per parameter in plan units (-inf/+inf where the action has none).
  std::vector<double> lower_limits() const;
  std::vector<double> upper_limits() const;
  double safety_margin() const;     // length_unit
  std::string length_unit() const;  // as written in the scene ("m", "mm", ...)
  std::string angle_unit() const;   // "deg" or "rad"

  // A plan CSV read as verify reads it: one state per row (each a value per
  // parameter_names(); a column the file leaves out keeps its reference
  // value; a `time` column is not part of a state), values as written.
  // Throws Error with verify's message (file, line and column).
  std::vector<std::vector<double>> read_plan(const std::string& path) const;

 private:
  friend class Checker;
  explicit Scene(std::shared_ptr<const detail::SceneData> data);
  std::shared_ptr<const detail::SceneData> data_;
};

// The collision structures of a scene, built once. Every method may be
// called from any number of threads at once.
//
// World objects change at run time (add_object, move_object,
// remove_object): each change makes a new version of the world, built from
// the last (the changed object's structure only; every other part's is
// shared, not rebuilt) and swapped in whole. A check, a batch or a motion
// check takes the version current when it starts and uses it to its end: it
// sees every change completed before it started, never half a change, and
// never one made while it runs. Changes from several threads are applied one
// at a time. Copies of a Checker share one world. Part indices
// (StateResult::part_a_index, part_names()) are those of the version a
// result was checked on; a change may renumber the parts after an added or
// removed object. Objects named in the scene file may be moved and removed
// like the others.
class PLANCHECK_API Checker {
 public:
  // Builds on `threads` threads (0: all hardware threads); check_batch uses
  // as many. Throws Error (for example an unreadable DEM) with verify's message.
  explicit Checker(const Scene& scene, int threads = 0);

  // Checks one state: scene.parameter_names().size() values in plan units.
  // Throws Error if the count is wrong, a value is not finite, or a scale
  // factor is not positive.
  StateResult check(const std::vector<double>& state) const;
  StateResult check(const std::vector<double>& state, const CheckOptions& options) const;

  // Checks many independent states on all the checker's threads; result i is
  // check(states[i]). Throws Error naming the first bad state (by index)
  // before anything is checked.
  std::vector<StateResult> check_batch(const std::vector<std::vector<double>>& states) const;
  std::vector<StateResult> check_batch(const std::vector<std::vector<double>>& states, const CheckOptions& options) const;

  // The same over `count` states stored row by row (count x parameter count
  // doubles, C order) into out[0..count). For callers holding a matrix.
  void check_batch(const double* states, std::size_t count, StateResult* out) const;
  void check_batch(const double* states, std::size_t count, StateResult* out, const CheckOptions& options) const;

  // Checks the straight-line motion from `from` to `to` (states as
  // check()'s), certified: never kSafe where any configuration on it comes
  // below the margin. Throws Error as check() does for a bad state. Its
  // pairs are certified on the checker's threads; the answer is the same
  // whatever their number.
  MotionResult check_motion(const std::vector<double>& from, const std::vector<double>& to,
                            const MotionOptions& options = {}) const;
  // Many independent motions on all the checker's threads: result i is
  // check_motion(from[i], to[i]). Throws Error naming the first bad state
  // (by index) before anything is checked.
  std::vector<MotionResult> check_motion_batch(const std::vector<std::vector<double>>& from,
                                               const std::vector<std::vector<double>>& to,
                                               const MotionOptions& options = {}) const;
  // The same over `count` motions stored row by row (count x parameter count
  // doubles each, C order) into out[0..count).
  void check_motion_batch(const double* from, const double* to, std::size_t count, MotionResult* out,
                          const MotionOptions& options = {}) const;

  // World objects (see above). Units and frames as the scene file's
  // `objects`. Throws Error (nothing changed) for a bad shape or size, a
  // name already used, an unknown parent, a mesh that cannot be read, or
  // (move, remove) a name that is no object. Adding builds the new object's
  // structure only; moving rebuilds nothing but the moved object's.
  void add_object(const Object& object);
  void move_object(const std::string& name, const Pose& pose);
  void remove_object(const std::string& name);
  // The world objects in order: the scene file's, then those added.
  std::vector<std::string> object_names() const;

  // The scene of the current world (its limits, names, units). The Scene
  // returned holds its data: references into it (parameter_names()) live as
  // long as it does, not as long as the world (a change may free the old one).
  Scene scene() const;

  // Parts as StateResult indexes them: the scene's parts (world objects
  // last), then "terrain" when the terrain collides. For the current world.
  std::vector<std::string> part_names() const;
  std::size_t parameter_count() const;
  int threads() const;  // threads check_batch runs on

 private:
  std::shared_ptr<detail::CheckerData> data_;
};

}  // namespace v0
}  // namespace plancheck
