// SPDX-License-Identifier: MIT
// plancheck._plancheck, the compiled part of the Python package `plancheck`
// (src/python/plancheck): a thin layer over the public C++ API
// (plancheck/plancheck.h), contract in shared/spec/plan-and-report-format.md
// ("Embedding"); its types are in plancheck/_plancheck.pyi. A batch is
// checked on all the scene's threads with the GIL released; bad input raises
// plancheck.Error (a ValueError) with the message `plancheck verify` prints
// for the same input.
#include <algorithm>
#include <plancheck/plancheck.h>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <filesystem>
#include <map>
#include <optional>
#include <memory>
#include <string>
#include <vector>

namespace py = pybind11;

namespace {

// Per-state answers as NumPy arrays (one entry per row of the states).
struct PyResult {
  py::array_t<bool> collision;
  py::array_t<double> min_distance;    // length_unit; 0 in contact; inf: no checked pair
  py::array_t<std::uint8_t> verdict;   // 0 safe, 1 clearance, 2 collision, 3 limits (verdict.npy codes)
  py::array_t<std::int32_t> part_a;    // index into part_names; -1: none
  py::array_t<std::int32_t> part_b;
  py::array_t<double> point_a;         // (n, 3), length_unit, reference frame
  py::array_t<double> point_b;
  py::array_t<bool> min_distance_is_bound;  // verdict_only: min_distance is a certified lower bound there
  py::list part_names;
};

// Per-motion answers of Scene.check_motion (one entry per row of starts/ends).
struct PyMotionResult {
  py::array_t<std::uint8_t> verdict;   // verdict.npy codes, as verify --continuous's two-state plan
  py::array_t<bool> collision;
  py::array_t<double> min_distance;    // certified lower bound along the motion, ends included; 0 in contact
  py::array_t<double> t;               // fraction of the motion at the first violation's witness; NaN: none
  py::array_t<std::int32_t> part_a;    // the witness's pair, index into part_names; -1: none
  py::array_t<std::int32_t> part_b;
  py::array_t<bool> certified;         // False: the step budget ran out (a clearance violation, no witness)
  py::array_t<std::int64_t> steps;     // pair checks between the ends
  py::list part_names;
};

using States = py::array_t<double, py::array::c_style | py::array::forcecast>;

class PyScene {
 public:
  PyScene(const std::filesystem::path& path, int threads, const std::optional<std::filesystem::path>& srdf,
          const std::map<std::string, std::filesystem::path>& packages) {
    plancheck::LoadOptions options;
    if (srdf) options.srdf = srdf->string();
    for (const auto& [name, dir] : packages) options.packages[name] = dir.string();
    // Loading and building take a while (BVHs over the model): without the GIL.
    py::gil_scoped_release release;
    scene_ = std::make_unique<plancheck::Scene>(plancheck::Scene::load(path.string(), options));
    checker_ = std::make_unique<plancheck::Checker>(*scene_, threads);
  }

  const plancheck::Scene& scene() const { return *scene_; }
  const plancheck::Checker& checker() const { return *checker_; }

  // Any array-like of real numbers; rows are states, columns
  // parameter_names; a 1-D array of parameter_names' length is one state.
  // Complex values are refused (a cast would drop their imaginary part).
  States as_states(const py::handle& in, const std::string& what) const {
    const py::array any = py::array::ensure(in);
    if (any && any.dtype().kind() == 'c')
      throw plancheck::Error(what + ": expected real numbers, got complex values (dtype " +
                             std::string(py::str(any.dtype())) + ")");
    auto states = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(in);
    if (!states) throw plancheck::Error(what + ": expected a 2-D array of numbers (rows: states, columns: parameter_names)");
    const std::size_t n = checker_->parameter_count();
    if (states.ndim() == 1 && static_cast<std::size_t>(states.shape(0)) == n)
      states = States::ensure(states.reshape({py::ssize_t{1}, static_cast<py::ssize_t>(n)}));
    if (states.ndim() != 2 || static_cast<std::size_t>(states.shape(1)) != n)
      throw plancheck::Error(what + ": expected a 2-D array of shape (states, " + std::to_string(n) +
                             ") (columns: parameter_names) or one state of " + std::to_string(n) +
                             " values, got shape " + shape_text(states));
    return states;
  }

  PyMotionResult check_motion(const py::handle& starts_in, const py::handle& ends_in, bool verdict_only,
                              bool first_violation) const {
    const States starts = as_states(starts_in, "starts");
    const States ends = as_states(ends_in, "ends");
    if (starts.shape(0) != ends.shape(0))
      throw plancheck::Error("starts and ends: expected the same number of states, got " +
                             std::to_string(starts.shape(0)) + " and " + std::to_string(ends.shape(0)));
    const std::size_t count = static_cast<std::size_t>(starts.shape(0));
    std::vector<plancheck::MotionResult> results(count);
    {
      py::gil_scoped_release release;  // both arrays are held by this frame
      checker_->check_motion_batch(starts.data(), ends.data(), count, results.data(),
                                   plancheck::MotionOptions{verdict_only, first_violation});
    }
    PyMotionResult r;
    const auto c = static_cast<py::ssize_t>(count);
    r.verdict = py::array_t<std::uint8_t>(c);
    r.collision = py::array_t<bool>(c);
    r.min_distance = py::array_t<double>(c);
    r.t = py::array_t<double>(c);
    r.part_a = py::array_t<std::int32_t>(c);
    r.part_b = py::array_t<std::int32_t>(c);
    r.certified = py::array_t<bool>(c);
    r.steps = py::array_t<std::int64_t>(c);
    auto verdict = r.verdict.mutable_unchecked<1>();
    auto collision = r.collision.mutable_unchecked<1>();
    auto distance = r.min_distance.mutable_unchecked<1>();
    auto t = r.t.mutable_unchecked<1>();
    auto pa = r.part_a.mutable_unchecked<1>();
    auto pb = r.part_b.mutable_unchecked<1>();
    auto certified = r.certified.mutable_unchecked<1>();
    auto steps = r.steps.mutable_unchecked<1>();
    for (py::ssize_t i = 0; i < c; ++i) {
      const plancheck::MotionResult& m = results[static_cast<std::size_t>(i)];
      verdict(i) = static_cast<std::uint8_t>(m.verdict);
      collision(i) = m.collision;
      distance(i) = m.min_distance;
      t(i) = m.t;
      pa(i) = m.part_a_index;
      pb(i) = m.part_b_index;
      certified(i) = m.certified;
      steps(i) = static_cast<std::int64_t>(m.steps);
    }
    r.part_names = names_for(results, r.part_a, r.part_b);
    return r;
  }

  // World objects (plancheck.h, Checker::add_object): exactly one shape.
  using Pose = std::array<std::array<double, 3>, 2>;
  void add_object(const std::string& name, const std::optional<std::array<double, 3>>& box,
                  const std::optional<std::array<double, 2>>& cylinder, const std::optional<double>& sphere,
                  const std::optional<std::filesystem::path>& mesh, const Pose& pose,
                  const std::optional<std::string>& parent, const std::array<double, 3>& scale) {
    plancheck::Object o;
    o.name = name;
    const int shapes = int(box.has_value()) + int(cylinder.has_value()) + int(sphere.has_value()) + int(mesh.has_value());
    if (shapes != 1)
      throw plancheck::Error("objects['" + name + "']: give exactly one of box, cylinder, sphere, mesh (got " +
                             std::to_string(shapes) + ")");
    if (box) {
      o.shape = plancheck::Object::Shape::kBox;
      o.box = *box;
    } else if (cylinder) {
      o.shape = plancheck::Object::Shape::kCylinder;
      o.radius = (*cylinder)[0];
      o.length = (*cylinder)[1];
    } else if (sphere) {
      o.shape = plancheck::Object::Shape::kSphere;
      o.radius = *sphere;
    } else {
      o.shape = plancheck::Object::Shape::kMesh;
      o.mesh = mesh->string();
    }
    o.scale = scale;
    o.pose = {pose[0], pose[1]};
    o.parent = parent.value_or("");
    py::gil_scoped_release release;  // builds the object's structure
    checker_->add_object(o);
  }
  void move_object(const std::string& name, const Pose& pose) {
    py::gil_scoped_release release;
    checker_->move_object(name, {pose[0], pose[1]});
  }
  void remove_object(const std::string& name) {
    py::gil_scoped_release release;
    checker_->remove_object(name);
  }

  PyResult check(const py::handle& states_in, bool verdict_only) const {
    const States states = as_states(states_in, "states");
    const std::size_t count = static_cast<std::size_t>(states.shape(0));
    std::vector<plancheck::StateResult> results(count);
    {
      py::gil_scoped_release release;  // states is held by this frame: its buffer stays valid
      checker_->check_batch(states.data(), count, results.data(), plancheck::CheckOptions{verdict_only});
    }
    PyResult r;
    const auto c = static_cast<py::ssize_t>(count);
    r.collision = py::array_t<bool>(c);
    r.min_distance = py::array_t<double>(c);
    r.verdict = py::array_t<std::uint8_t>(c);
    r.part_a = py::array_t<std::int32_t>(c);
    r.part_b = py::array_t<std::int32_t>(c);
    r.point_a = py::array_t<double>({c, py::ssize_t{3}});
    r.point_b = py::array_t<double>({c, py::ssize_t{3}});
    r.min_distance_is_bound = py::array_t<bool>(c);
    auto bound = r.min_distance_is_bound.mutable_unchecked<1>();
    auto collision = r.collision.mutable_unchecked<1>();
    auto distance = r.min_distance.mutable_unchecked<1>();
    auto verdict = r.verdict.mutable_unchecked<1>();
    auto pa = r.part_a.mutable_unchecked<1>();
    auto pb = r.part_b.mutable_unchecked<1>();
    auto qa = r.point_a.mutable_unchecked<2>();
    auto qb = r.point_b.mutable_unchecked<2>();
    for (py::ssize_t i = 0; i < c; ++i) {
      const plancheck::StateResult& s = results[static_cast<std::size_t>(i)];
      collision(i) = s.collision;
      distance(i) = s.min_distance;
      verdict(i) = static_cast<std::uint8_t>(s.verdict);
      bound(i) = s.min_distance_is_bound;
      pa(i) = s.part_a_index;
      pb(i) = s.part_b_index;
      for (py::ssize_t k = 0; k < 3; ++k) {
        qa(i, k) = s.point_a[static_cast<std::size_t>(k)];
        qb(i, k) = s.point_b[static_cast<std::size_t>(k)];
      }
    }
    r.part_names = names_for(results, r.part_a, r.part_b);
    return r;
  }

 private:
  // The names part_a/part_b index: the current world's parts, unless a
  // change (from another thread, while the batch ran without the GIL)
  // renumbered them; then the names the results carry, and their indices
  // into that list.
  template <class Result>
  py::list names_for(const std::vector<Result>& results, py::array_t<std::int32_t>& a,
                     py::array_t<std::int32_t>& b) const {
    std::vector<std::string> names = checker_->part_names();
    auto ia = a.mutable_unchecked<1>();
    auto ib = b.mutable_unchecked<1>();
    auto agrees = [&](int i, const std::string& n) {
      return i < 0 || (static_cast<std::size_t>(i) < names.size() && names[static_cast<std::size_t>(i)] == n);
    };
    bool same = true;
    for (std::size_t i = 0; i < results.size() && same; ++i)
      same = agrees(results[i].part_a_index, results[i].part_a) && agrees(results[i].part_b_index, results[i].part_b);
    if (same) return py::cast(names);
    names.clear();
    auto index = [&](int i, const std::string& n) -> std::int32_t {
      if (i < 0) return -1;
      auto it = std::find(names.begin(), names.end(), n);
      if (it == names.end()) it = names.insert(names.end(), n);
      return static_cast<std::int32_t>(it - names.begin());
    };
    for (std::size_t i = 0; i < results.size(); ++i) {
      ia(static_cast<py::ssize_t>(i)) = index(results[i].part_a_index, results[i].part_a);
      ib(static_cast<py::ssize_t>(i)) = index(results[i].part_b_index, results[i].part_b);
    }
    return py::cast(names);
  }

  static std::string shape_text(const py::array& a) {
    std::string s = "(";
    for (py::ssize_t d = 0; d < a.ndim(); ++d) s += (d ? ", " : "") + std::to_string(a.shape(d));
    return s + (a.ndim() == 1 ? ",)" : ")");
  }
  std::unique_ptr<plancheck::Scene> scene_;
  std::unique_ptr<plancheck::Checker> checker_;
};

py::array_t<double> as_array(const std::vector<double>& v) {
  return py::array_t<double>(static_cast<py::ssize_t>(v.size()), v.data());
}

// Names of the parts at part_a/part_b (None where -1), for printing.
template <class R>
py::list names_of(const R& r, const py::array_t<std::int32_t>& idx) {
  py::list out;
  auto v = idx.unchecked<1>();
  for (py::ssize_t i = 0; i < v.shape(0); ++i)
    out.append(v(i) < 0 ? py::object(py::none()) : py::object(r.part_names[static_cast<std::size_t>(v(i))]));
  return out;
}

// What both result classes (CheckResult, MotionResult) share: the parts of
// their pairs as names, and a length.
template <class R>
void add_pair_names_and_len(py::class_<R>& cls) {
  cls.def_readonly("part_names", &R::part_names, "the parts part_a and part_b index")
      .def_property_readonly("part_a_names", [](const R& r) { return names_of(r, r.part_a); },
                             "part_a as names (None where -1)")
      .def_property_readonly("part_b_names", [](const R& r) { return names_of(r, r.part_b); },
                             "part_b as names (None where -1)")
      .def("__len__", [](const R& r) { return r.verdict.shape(0); });
}

}  // namespace

PYBIND11_MODULE(_plancheck, m) {
  m.doc() = "plancheck: check robot-arm states against a scene with the answers of `plancheck verify`";
  m.attr("__version__") = plancheck::version();
  py::register_exception<plancheck::Error>(m, "Error", PyExc_ValueError);

  auto check_result = py::class_<PyResult>(m, "CheckResult",
                       "Per-state answers of Scene.check, one entry per row of the states (NumPy arrays).")
      .def_readonly("collision", &PyResult::collision, "bool: two checked parts intersect or touch")
      .def_readonly("min_distance", &PyResult::min_distance,
                    "float64: minimum distance over the checked pairs (length_unit); 0 in contact, inf with no pair")
      .def_readonly("verdict", &PyResult::verdict, "uint8: 0 safe, 1 clearance, 2 collision, 3 limits (as verdict.npy)")
      .def_readonly("part_a", &PyResult::part_a, "int32: the closest (or first colliding) pair's moving part, index into part_names; -1: none")
      .def_readonly("part_b", &PyResult::part_b, "int32: the other part of that pair")
      .def_readonly("point_a", &PyResult::point_a, "float64 (n, 3): closest point on part_a (length_unit, reference frame)")
      .def_readonly("point_b", &PyResult::point_b, "float64 (n, 3): closest point on part_b")
      .def_readonly("min_distance_is_bound", &PyResult::min_distance_is_bound,
                    "bool: min_distance is only a certified lower bound there (verdict_only, every pair proven\n"
                    "beyond the margin); always False for a full check");
  add_pair_names_and_len(check_result);

  auto motion_result = py::class_<PyMotionResult>(m, "MotionResult",
                             "Per-motion answers of Scene.check_motion, one entry per row of starts/ends (NumPy arrays).")
      .def_readonly("verdict", &PyMotionResult::verdict,
                    "uint8: verify --continuous's verdict for a two-state plan of the motion (0 safe, 1 clearance,\n"
                    "2 collision, 3 limits): state 0's own violation first, then the motion's, then state 1's")
      .def_readonly("collision", &PyMotionResult::collision, "bool: parts touch somewhere on the motion, ends included")
      .def_readonly("min_distance", &PyMotionResult::min_distance,
                    "float64: a certified lower bound of the distance along the whole motion, ends included\n"
                    "(length_unit); 0 where a contact is found")
      .def_readonly("t", &PyMotionResult::t, "float64: the first violation's witness as a fraction of the motion; NaN: none")
      .def_readonly("part_a", &PyMotionResult::part_a, "int32: the witness's pair, index into part_names; -1: none")
      .def_readonly("part_b", &PyMotionResult::part_b, "int32: the other part of that pair")
      .def_readonly("certified", &PyMotionResult::certified,
                    "bool: False where the motion needs more pair checks than the budget (then a clearance\n"
                    "violation with no witness)")
      .def_readonly("steps", &PyMotionResult::steps, "int64: pair checks between the ends (one pair's search at one configuration each)");
  add_pair_names_and_len(motion_result);

  py::class_<PyScene>(m, "Scene",
                      "A scene loaded and its collision structures built (raises plancheck.Error on bad input).")
      .def(py::init<const std::filesystem::path&, int, const std::optional<std::filesystem::path>&,
                    const std::map<std::string, std::filesystem::path>&>(),
           py::arg("path"), py::arg("threads") = 0, py::arg("srdf") = py::none(),
           py::arg("packages") = std::map<std::string, std::filesystem::path>(),
           "Loads a plancheck-scene/1 JSON (or a .urdf; srdf and packages as verify's --srdf and\n"
           "--package NAME=DIR) and builds its checker; threads=0: all cores.")
      .def_property_readonly("parameter_names", [](const PyScene& s) { return s.scene().parameter_names(); },
                             "plan column names, in order: the columns of a states array")
      .def_property_readonly("part_names", [](const PyScene& s) { return s.checker().part_names(); },
                             "checked parts (the scene's parts, then 'terrain' when it collides)")
      .def_property_readonly("lower_limits", [](const PyScene& s) { return as_array(s.scene().lower_limits()); },
                             "float64 per parameter: lower limit in plan units, -inf where none")
      .def_property_readonly("upper_limits", [](const PyScene& s) { return as_array(s.scene().upper_limits()); },
                             "float64 per parameter: upper limit in plan units, inf where none")
      .def_property_readonly("reference_state", [](const PyScene& s) { return s.scene().reference_state(); })
      .def(
          "read_plan",
          [](const PyScene& s, const std::filesystem::path& path) {
            const std::vector<std::vector<double>> rows = s.scene().read_plan(path.string());
            const std::size_t n = s.scene().parameter_names().size();
            py::array_t<double> out({static_cast<py::ssize_t>(rows.size()), static_cast<py::ssize_t>(n)});
            auto o = out.mutable_unchecked<2>();
            for (std::size_t i = 0; i < rows.size(); ++i)
              for (std::size_t j = 0; j < n; ++j) o(static_cast<py::ssize_t>(i), static_cast<py::ssize_t>(j)) = rows[i][j];
            return out;
          },
          py::arg("path"),
          "A plan CSV read as verify reads it: float64 (states, parameters), one row per state, a\n"
          "column the file leaves out at its reference value, values as written (raises\n"
          "plancheck.Error naming the file, line and column)")
      .def_property_readonly("safety_margin", [](const PyScene& s) { return s.scene().safety_margin(); },
                             "length_unit")
      .def_property_readonly("length_unit", [](const PyScene& s) { return s.scene().length_unit(); })
      .def_property_readonly("angle_unit", [](const PyScene& s) { return s.scene().angle_unit(); })
      .def_property_readonly("threads", [](const PyScene& s) { return s.checker().threads(); })
      .def_property_readonly("object_names", [](const PyScene& s) { return s.checker().object_names(); },
                             "world objects in order: the scene file's, then those added")
      .def("add_object", &PyScene::add_object, py::arg("name"), py::kw_only(), py::arg("box") = py::none(),
           py::arg("cylinder") = py::none(), py::arg("sphere") = py::none(), py::arg("mesh") = py::none(),
           py::arg("pose") = PyScene::Pose{}, py::arg("parent") = py::none(),
           py::arg("scale") = std::array<double, 3>{1.0, 1.0, 1.0},
           "Adds a world object, as the scene file's `objects` (one shape: box=(x, y, z) full edge\n"
           "lengths; cylinder=(radius, length) along local z; sphere=radius; mesh=path with scale),\n"
           "pose=((x, y, z), (roll, pitch, yaw)) in length_unit and angle_unit (fixed axes, as URDF) in\n"
           "the frame of parent (a node or robot link it moves with; None: the world). Builds that\n"
           "object's structure only. Checks started after it see it; none sees half of it.")
      .def("move_object", &PyScene::move_object, py::arg("name"), py::arg("pose"),
           "Moves a world object to pose ((x, y, z), (roll, pitch, yaw)) in its parent's frame\n"
           "(nothing is rebuilt for an object on a static node).")
      .def("remove_object", &PyScene::remove_object, py::arg("name"),
           "Removes a world object (the scene file's too).")
      .def("check", &PyScene::check, py::arg("states"), py::arg("verdict_only") = false,
           "Checks each row of `states` (2-D, columns parameter_names, plan units as written) as an\n"
           "independent state on the scene's initial terrain, on all threads without the GIL.\n"
           "verdict_only=True: verify --verdict-only's answer, the same verdicts faster: the first\n"
           "colliding pair only, and exact distances only below the safety margin (elsewhere\n"
           "min_distance is a certified lower bound, min_distance_is_bound True, no parts or points).\n"
           "A 1-D array of len(parameter_names) values is one state.")
      .def("check_motion", &PyScene::check_motion, py::arg("starts"), py::arg("ends"), py::arg("verdict_only") = false,
           py::arg("first_violation") = false,
           "Checks the straight-line motion (in plan units, values as written) from each row of `starts`\n"
           "to the same row of `ends` (arrays as check's), certified as verify --continuous: never safe\n"
           "where any configuration on it comes below the margin. verdict_only=True: the same verdicts\n"
           "and witnesses, exact distances only where they decide (what a planner needs); min_distance\n"
           "is then a looser certified bound. first_violation=True: only whether each motion is safe\n"
           "(a motion validator's question): stops at the first witness below the margin without\n"
           "looking on for a contact; the same safe or not, but an unsafe motion's verdict, collision\n"
           "and t are that witness's (clearance) and its min_distance is NaN (0 where an end touches).");
}
