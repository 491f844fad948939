// SPDX-License-Identifier: MIT
// Planning with OMPL on plancheck (<plancheck/ompl.h>), as a planning user
// does it: RRTConnect with plancheck's state validity checker and certified
// motion validator, on the default arm and on the URDF example's arm on the
// same lander with a world object (a box) beside it, for start/goal pairs
// whose straight motion is not safe (the lander, or the box, is in the
// way); each path is simplified, written as a plan CSV and
// checked by `plancheck verify --continuous`, which must find every path
// safe. Exit 0 when all is well, 1 with a message otherwise.
//
//   plancheck_ompl_example DATASET URDF_EXAMPLE PLANCHECK OUT
//
// DATASET: generate_change5's output; URDF_EXAMPLE: datasets/urdf-example;
// PLANCHECK: the command line; OUT: a scratch folder (recreated).
#include <plancheck/ompl.h>
#include <plancheck/plancheck.h>

#include <nlohmann/json.hpp>
#include <ompl/base/ScopedState.h>
#include <ompl/geometric/SimpleSetup.h>
#include <ompl/geometric/planners/rrt/RRTConnect.h>
#include <ompl/util/Console.h>
#include <ompl/util/RandomNumbers.h>

#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

namespace fs = std::filesystem;
namespace ob = ompl::base;
namespace og = ompl::geometric;

namespace {

int failures = 0;

// The sanitizer builds (about 10x the time per check) compare a third of
// the release run's random motions with the validator (the queries stay:
// fewer leave no motion certified partly from its start). Every path of
// the example is still walked (tests/support/sanitized.h says why).
#ifdef PLANCHECK_SANITIZED
constexpr int kShare = 3;
#else
constexpr int kShare = 1;
#endif

void fail(const std::string& what) {
  std::cerr << "FAIL: " << what << "\n";
  ++failures;
}

std::string read_text(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
}

void write_text(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

std::vector<double> values(const ob::State* s, std::size_t n) {
  const double* v = s->as<ob::RealVectorStateSpace::StateType>()->values;
  return std::vector<double>(v, v + n);
}

// Plans `queries` start/goal pairs on `scene` into OUT/<name>/qK.csv, then
// verifies them all with verify --continuous.
// `obstacle` (a part name, "" for any): the straight motion of every query
// meets that part first.
void plan_and_verify(const std::string& name, const fs::path& scene_path, const std::string& plancheck,
                     const fs::path& out, int queries, const std::string& obstacle = "") {
  const auto t0 = std::chrono::steady_clock::now();
  // The ten lines a planning user needs.
  auto checker = std::make_shared<plancheck::Checker>(plancheck::Scene::load(scene_path.string()));
  og::SimpleSetup ss(plancheck::ompl::make_space(checker));
  const ob::SpaceInformationPtr si = ss.getSpaceInformation();
  ss.setStateValidityChecker(std::make_shared<plancheck::ompl::StateValidityChecker>(si, checker));
  si->setMotionValidator(std::make_shared<plancheck::ompl::MotionValidator>(si, checker));
  ss.setPlanner(std::make_shared<og::RRTConnect>(si));
  ss.setup();
  const double load_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  const std::size_t n = checker->parameter_count();
  const std::vector<std::string>& names = checker->scene().parameter_names();
  std::string header;
  for (const std::string& c : names) header += (header.empty() ? "" : ",") + c;
  const fs::path dir = out / name;
  fs::create_directories(dir);
  const ob::StateSamplerPtr sampler = si->allocStateSampler();
  ob::ScopedState<> start(si), goal(si);
  std::string plans;
  double plan_seconds = 0.0;
  std::size_t states = 0;
  int partly_valid = 0;  // unsafe straight motions whose lastValid lies beyond the start
  for (int q = 0; q < queries; ++q) {
    // Two safe states whose straight motion is not: something in the way.
    bool found = false;
    for (int tries = 0; tries < 100000 && !found; ++tries) {
      sampler->sampleUniform(start.get());
      sampler->sampleUniform(goal.get());
      if (!si->isValid(start.get()) || !si->isValid(goal.get())) continue;
      const plancheck::MotionResult m = checker->check_motion(values(start.get(), n), values(goal.get(), n));
      found = m.verdict != plancheck::Verdict::kSafe && (obstacle.empty() || m.part_a == obstacle || m.part_b == obstacle);
    }
    if (!found) return fail(name + ": no start/goal pair with an obstacle in the way");
    {
      // The validator's lastValid: the certified-safe stretch from the
      // start, which check_motion then finds safe (with its own certificate).
      std::pair<ob::State*, double> last(si->allocState(), -1.0);
      if (si->getMotionValidator()->checkMotion(start.get(), goal.get(), last))
        fail(name + ": an unsafe motion passed the validator");
      if (!(last.second >= 0.0 && last.second < 1.0)) fail(name + ": lastValid fraction out of [0, 1)");
      if (last.second > 0.0) {
        ++partly_valid;
        // Safe, or flagged only within the tolerance above the margin
        // (where the certificate stopped: its witness is no closer).
        const auto m = checker->check_motion(values(start.get(), n), values(last.first, n));
        bool bad = m.verdict == plancheck::Verdict::kCollision || m.verdict == plancheck::Verdict::kLimits;
        if (m.verdict == plancheck::Verdict::kClearance) {
          ob::ScopedState<> w(si);
          si->getStateSpace()->interpolate(start.get(), last.first, std::isnan(m.t) ? 1.0 : m.t, w.get());
          bad = checker->check(values(w.get(), n)).min_distance < checker->scene().safety_margin();
        }
        if (bad) fail(name + ": the motion up to lastValid is not safe");
      }
      si->freeState(last.first);
    }
    ss.clear();
    ss.setStartAndGoalStates(start, goal);
    const auto p0 = std::chrono::steady_clock::now();
    const ob::PlannerStatus status = ss.solve(10.0);
    if (status != ob::PlannerStatus::EXACT_SOLUTION) return fail(name + " query " + std::to_string(q) + ": not solved");
    ss.simplifySolution();
    plan_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - p0).count();
    og::PathGeometric& path = ss.getSolutionPath();
    std::string csv = header + "\n";
    char value[32];
    for (const ob::State* s : path.getStates()) {
      const std::vector<double> v = values(s, n);
      for (std::size_t j = 0; j < n; ++j) {
        std::snprintf(value, sizeof value, "%.17g", v[j]);
        csv += (j ? "," : "") + std::string(value);
      }
      csv += "\n";
    }
    states += path.getStateCount();
    const fs::path file = dir / ("q" + std::to_string(q) + ".csv");
    write_text(file, csv);
    plans += " \"" + file.string() + "\"";
  }
  {
    // The validator's bool answer is check_motion's, whether its screen
    // (states at a quarter of OMPL's resolution) rejects the motion first
    // or the certificate decides: random safe states and others near them (a quarter of the
    // space's extent), and each unsafe one shortened from its end in steps
    // of 10% until it is safe, so that some violations fall between the
    // discrete states (the certificate's) as others fall on one (the
    // screen's).
    ob::ScopedState<> a(si), b(si), c(si), mid(si);
    int screened = 0, certificate = 0, motions = 0;
    auto compare = [&](const ob::State* x, const ob::State* y) {
      ++motions;
      const bool safe = checker->check_motion(values(x, n), values(y, n)).verdict == plancheck::Verdict::kSafe;
      if (si->getMotionValidator()->checkMotion(x, y) != safe) {
        fail(name + ": the motion validator's answer is not check_motion's");
        return true;
      }
      if (safe) return true;
      // Would the screen alone reject it (one of its states not safe)?
      const unsigned int segs = (si->getStateSpace()->validSegmentCount(x, y) + 3) / 4;
      bool hit = false;
      for (unsigned int k = 1; k < segs && !hit; ++k) {
        si->getStateSpace()->interpolate(x, y, static_cast<double>(k) / segs, mid.get());
        hit = !si->isValid(mid.get());
      }
      (hit ? screened : certificate)++;
      return false;
    };
    for (int i = 0; i < 300 / kShare; ++i) {
      do sampler->sampleUniform(a.get());
      while (!si->isValid(a.get()));
      do {
        sampler->sampleUniformNear(b.get(), a.get(), 0.25 * si->getMaximumExtent());
        si->enforceBounds(b.get());
      } while (!si->isValid(b.get()));
      double s = 1.0;
      for (int k = 0; k < 40 && !compare(a.get(), k == 0 ? b.get() : c.get()); ++k) {
        s *= 0.9;
        si->getStateSpace()->interpolate(a.get(), b.get(), s, c.get());
      }
    }
    std::printf("%s: %d motions; unsafe: %d with a screened state not safe, %d without\n", name.c_str(), motions,
                screened, certificate);
    if (screened == 0 || certificate == 0) fail(name + ": the motions did not exercise both the screen and the certificate");
  }
  // Every path, every motion between its states: certified safe.
  const std::string cmd = "\"" + plancheck + "\" verify \"" + scene_path.string() + "\"" + plans +
                          " --continuous --quiet --out \"" + (dir / "verify").string() + "\" > \"" +
                          (dir / "verify.txt").string() + "\" 2>&1";
  const int status = std::system(cmd.c_str());
  const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::printf("%s: %d queries, %zu path states, load+build %.2f s, plan+simplify %.3f s, verify --continuous exit %d\n",
              name.c_str(), queries, states, load_seconds, plan_seconds, code);
  if (code != 0) fail(name + ": verify --continuous exit " + std::to_string(code) + ":\n" + read_text(dir / "verify.txt"));
  if (partly_valid == 0) fail(name + ": no unsafe motion was certified any way from its start (lastValid)");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 5) {
    std::cerr << "usage: plancheck_ompl_example DATASET URDF_EXAMPLE PLANCHECK OUT\n";
    return 2;
  }
  const fs::path data = fs::absolute(argv[1]), example = fs::absolute(argv[2]), out = fs::absolute(argv[4]);
  const std::string plancheck = argv[3];
  ompl::RNG::setSeed(20261127);  // the same queries every run
  ompl::msg::setLogLevel(ompl::msg::LOG_WARN);
  fs::remove_all(out);
  fs::create_directories(out);
  try {
    // The default arm. verify digs along a plan with the scoop; planning
    // states never dig, so both see the scene without its scoop block.
    nlohmann::ordered_json scene = nlohmann::ordered_json::parse(read_text(data / "scene.json"));
    scene.erase("scoop");
    const fs::path nodig = data / ("scene-nodig-ompl-" + std::to_string(::getpid()) + ".json");
    write_text(nodig, scene.dump(2));
    plan_and_verify("default-arm", nodig, plancheck, out, 2);
    fs::remove(nodig);

    // The URDF example's survey arm on the same lander, with a world object
    // (a 0.12 x 0.12 x 0.6 m box, the scene file's `objects`) in its way:
    // every query's straight motion meets the box.
    nlohmann::json urdf = nlohmann::json::parse(read_text(example / "scene.json"));
    urdf["objects"] = nlohmann::json::parse(
        R"([{"name": "Post", "box": [0.12, 0.12, 0.6], "pose": {"xyz": [0.95, -0.45, 1.75], "rpy": [0, 0, 0.3]}}])");
    urdf["model"] = (data / scene["model"].get<std::string>()).string();
    urdf["robot"]["urdf"] = (example / urdf["robot"]["urdf"].get<std::string>()).string();
    urdf["robot"]["srdf"] = (example / urdf["robot"]["srdf"].get<std::string>()).string();
    write_text(out / "urdf-scene.json", urdf.dump(2));
    plan_and_verify("urdf-arm", out / "urdf-scene.json", plancheck, out, 4, "Post");
  } catch (const std::exception& e) {
    fail(std::string("error: ") + e.what());
  }
  if (failures) return 1;
  std::printf("all paths certified safe by verify --continuous\n");
  return 0;
}
