// SPDX-License-Identifier: MIT
// Certified motion checks inside OMPL (issue 32), answers checked before
// anything is timed:
//  1. Per segment: plancheck's MotionValidator (its screen of OMPL's
//     discrete states, then check_motion) and Checker::check_motion
//     (verdict-only, first violation) alone, against OMPL's
//     DiscreteMotionValidator at its default resolution over plancheck's
//     verdict-only point checks, on >= N segments of planned paths per arm,
//     by segment length.
//  2. Per query: RRTConnect + simplification with the certified validator
//     against the same planner with the discrete one (median wall time over
//     the seeds), and how many of each one's paths `plancheck verify
//     --continuous` rejects.
//
//   plancheck_ompl_bench DATASET URDF_EXAMPLE PLANCHECK OUT [--seeds 20] [--segments 1000]
//
// OUT gets each arm's scene (scene-nodig.json, urdf-scene.json) and its
// planned edges (default-edges.csv, urdf-edges.csv) for
// plancheck_motion_replay.
#include <plancheck/ompl.h>
#include <plancheck/plancheck.h>

#include <nlohmann/json.hpp>
#include <ompl/base/DiscreteMotionValidator.h>
#include <ompl/base/ScopedState.h>
#include <ompl/geometric/SimpleSetup.h>
#include <ompl/geometric/planners/rrt/RRTConnect.h>
#include <ompl/util/Console.h>
#include <ompl/util/RandomNumbers.h>

#include <sys/wait.h>

#include <algorithm>
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
#include <tuple>
#include <vector>

namespace fs = std::filesystem;
namespace ob = ompl::base;
namespace og = ompl::geometric;

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

std::string read_text(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
}
void write_text(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

[[noreturn]] void die(const std::string& what) {
  std::cerr << "plancheck_ompl_bench: " << what << "\n";
  std::exit(1);
}

std::vector<double> values(const ob::State* s, std::size_t n) {
  const double* v = s->as<ob::RealVectorStateSpace::StateType>()->values;
  return std::vector<double>(v, v + n);
}

struct Arm {
  std::string name;
  fs::path scene;
  std::shared_ptr<plancheck::Checker> checker;
  ob::SpaceInformationPtr si;  // certified validator
  ob::SpaceInformationPtr discrete_si;  // OMPL's default DiscreteMotionValidator
  std::vector<std::pair<std::vector<double>, std::vector<double>>> queries;  // obstacle in the way
};

ob::SpaceInformationPtr make_si(const std::shared_ptr<plancheck::Checker>& checker, bool certified) {
  auto si = std::make_shared<ob::SpaceInformation>(plancheck::ompl::make_space(checker));
  si->setStateValidityChecker(std::make_shared<plancheck::ompl::StateValidityChecker>(si, checker));
  if (certified) si->setMotionValidator(std::make_shared<plancheck::ompl::MotionValidator>(si, checker));
  si->setup();  // default: DiscreteMotionValidator at 1% of the space's extent
  return si;
}

Arm make_arm(const std::string& name, const fs::path& scene, int queries) {
  Arm a;
  a.name = name;
  a.scene = scene;
  a.checker = std::make_shared<plancheck::Checker>(plancheck::Scene::load(scene.string()));
  a.si = make_si(a.checker, true);
  a.discrete_si = make_si(a.checker, false);
  const std::size_t n = a.checker->parameter_count();
  const ob::StateSamplerPtr sampler = a.si->allocStateSampler();
  ob::ScopedState<> s(a.si), g(a.si);
  for (int tries = 0; static_cast<int>(a.queries.size()) < queries && tries < 1000000; ++tries) {
    sampler->sampleUniform(s.get());
    sampler->sampleUniform(g.get());
    if (a.si->isValid(s.get()) && a.si->isValid(g.get()) &&
        a.checker->check_motion(values(s.get(), n), values(g.get(), n)).verdict != plancheck::Verdict::kSafe)
      a.queries.emplace_back(values(s.get(), n), values(g.get(), n));
  }
  if (static_cast<int>(a.queries.size()) < queries) die(name + ": too few queries with an obstacle in the way");
  return a;
}

struct Solved {
  double seconds = 0.0;
  std::vector<std::vector<double>> path;
};

Solved solve(const Arm& a, const ob::SpaceInformationPtr& si, std::size_t query, bool simplify) {
  og::SimpleSetup ss(si);
  ss.setPlanner(std::make_shared<og::RRTConnect>(si));
  ob::ScopedState<> s(si), g(si);
  const std::size_t n = a.checker->parameter_count();
  for (std::size_t j = 0; j < n; ++j) {
    s[static_cast<unsigned>(j)] = a.queries[query].first[j];
    g[static_cast<unsigned>(j)] = a.queries[query].second[j];
  }
  ss.setStartAndGoalStates(s, g);
  Solved out;
  const auto t0 = Clock::now();
  if (ss.solve(10.0) != ob::PlannerStatus::EXACT_SOLUTION) die(a.name + ": query not solved");
  if (simplify) ss.simplifySolution();
  out.seconds = since(t0);
  for (const ob::State* st : ss.getSolutionPath().getStates()) out.path.push_back(values(st, n));
  return out;
}

std::string plan_csv(const Arm& a, const std::vector<std::vector<double>>& path) {
  std::string csv;
  for (const std::string& c : a.checker->scene().parameter_names()) csv += (csv.empty() ? "" : ",") + c;
  csv += "\n";
  char v[32];
  for (const auto& s : path) {
    for (std::size_t j = 0; j < s.size(); ++j) {
      std::snprintf(v, sizeof v, "%.17g", s[j]);
      csv += (j ? "," : "") + std::string(v);
    }
    csv += "\n";
  }
  return csv;
}

// How many of `paths` verify --continuous rejects (its per-plan verdicts).
int rejected(const Arm& a, const std::vector<std::vector<std::vector<double>>>& paths, const std::string& plancheck,
             const fs::path& dir) {
  fs::create_directories(dir);
  std::string args;
  for (std::size_t i = 0; i < paths.size(); ++i) {
    const fs::path p = dir / ("p" + std::to_string(100 + i) + ".csv");
    write_text(p, plan_csv(a, paths[i]));
    args += " \"" + p.string() + "\"";
  }
  const std::string cmd = "\"" + plancheck + "\" verify \"" + a.scene.string() + "\"" + args +
                          " --continuous --quiet --out \"" + (dir / "out").string() + "\" > /dev/null 2>&1";
  const int status = std::system(cmd.c_str());
  if (!WIFEXITED(status) || WEXITSTATUS(status) > 1) die("verify failed: " + cmd);
  const auto report = nlohmann::json::parse(read_text(dir / "out" / "report.json"));
  int bad = 0;
  for (const auto& p : report["plans"]) bad += p["verdict"] != "safe";
  return bad;
}

void segment_table(const Arm& a, std::size_t want, const fs::path& edges_csv) {
  // Segments of planned (unsimplified) paths: RRTConnect's own edges, from
  // the discrete validator's planner (the faster one to collect them with).
  std::vector<std::pair<std::vector<double>, std::vector<double>>> segs;
  for (std::size_t q = 0; segs.size() < want; q = (q + 1) % a.queries.size()) {
    const Solved s = solve(a, a.discrete_si, q, false);
    for (std::size_t i = 0; i + 1 < s.path.size(); ++i) segs.emplace_back(s.path[i], s.path[i + 1]);
  }
  // The planned edges, for plancheck_motion_replay (the same edges again,
  // one thread, under callgrind if asked).
  {
    std::ofstream csv(edges_csv, std::ios::binary);
    char buf[32];
    for (const auto& [from, to] : segs) {
      std::string line;
      for (const std::vector<double>* v : {&from, &to})
        for (double x : *v) {
          std::snprintf(buf, sizeof buf, "%.17g", x);
          line += (line.empty() ? "" : ",") + std::string(buf);
        }
      csv << line << "\n";
    }
  }
  // 200 more between random valid states near each other, so that both
  // validators see unsafe segments too.
  const std::size_t planned = segs.size();
  {
    const ob::StateSamplerPtr sampler = a.si->allocStateSampler();
    ob::ScopedState<> s(a.si), g(a.si);
    const std::size_t n = a.checker->parameter_count();
    while (segs.size() < planned + 200) {
      sampler->sampleUniform(s.get());
      sampler->sampleUniformNear(g.get(), s.get(), 0.25 * a.si->getMaximumExtent());
      a.si->enforceBounds(g.get());
      if (a.si->isValid(s.get()) && a.si->isValid(g.get())) segs.emplace_back(values(s.get(), n), values(g.get(), n));
    }
  }
  const std::size_t n = a.checker->parameter_count();
  auto ompl_state = [&](const std::vector<double>& v, ob::ScopedState<>& st) {
    for (std::size_t j = 0; j < n; ++j) st[static_cast<unsigned>(j)] = v[j];
  };
  ob::ScopedState<> s1(a.discrete_si), s2(a.discrete_si);
  const auto discrete = a.discrete_si->getMotionValidator();
  const auto certified = a.si->getMotionValidator();

  // Answers first: the certified verdict-only answer equals the full one;
  // certified safe implies every discrete sample safe.
  std::vector<char> cert(segs.size()), disc(segs.size());
  std::size_t missed = 0, unsafe = 0;
  for (std::size_t i = 0; i < segs.size(); ++i) {
    const auto full = a.checker->check_motion(segs[i].first, segs[i].second);
    const auto vo = a.checker->check_motion(segs[i].first, segs[i].second, plancheck::MotionOptions{true});
    if (full.verdict != vo.verdict) die(a.name + ": verdict-only motion verdict differs from the full one");
    ompl_state(segs[i].first, s1);
    ompl_state(segs[i].second, s2);
    cert[i] = certified->checkMotion(s1.get(), s2.get());
    disc[i] = discrete->checkMotion(s1.get(), s2.get());
    if (cert[i] != (full.verdict == plancheck::Verdict::kSafe)) die(a.name + ": validator differs from check_motion");
    if (cert[i] && !disc[i]) die(a.name + ": certified safe but a discrete sample is not");
    missed += disc[i] && !cert[i];
    unsafe += !cert[i];
  }
  // Timing: each validator over all segments, best of 3 runs.
  auto time_all = [&](const ob::MotionValidatorPtr& mv, std::size_t begin, std::size_t end) {
    double best = 1e300;
    for (int rep = 0; rep < 3; ++rep) {
      const auto t0 = Clock::now();
      std::size_t ok = 0;
      for (std::size_t i = begin; i < end; ++i) {
        ompl_state(segs[i].first, s1);
        ompl_state(segs[i].second, s2);
        ok += mv->checkMotion(s1.get(), s2.get());
      }
      best = std::min(best, since(t0));
      if (ok > end - begin) die("impossible");
    }
    return best;
  };
  std::printf("\n%s: %zu segments (%zu from RRTConnect paths, %zu random near pairs); %zu unsafe, %zu of them passed by "
              "the discrete validator\n",
              a.name.c_str(), segs.size(), planned, segs.size() - planned, unsafe, missed);
  // check_motion alone (verdict-only, first violation), as the validator
  // calls it after its screen of the discrete states.
  auto time_check_motion = [&](std::size_t begin, std::size_t end) {
    double best = 1e300;
    for (int rep = 0; rep < 3; ++rep) {
      const auto t0 = Clock::now();
      std::size_t ok = 0;
      for (std::size_t i = begin; i < end; ++i)
        ok += a.checker->check_motion(segs[i].first, segs[i].second, plancheck::MotionOptions{true, true}).verdict ==
              plancheck::Verdict::kSafe;
      best = std::min(best, since(t0));
      if (ok > end - begin) die("impossible");
    }
    return best;
  };
  std::printf("%-26s %8s %14s %14s %14s %8s %8s\n", "segments", "count", "validator us", "check_motion us",
              "discrete us", "ratio", "cm ratio");
  auto row = [&](const std::string& label, std::size_t b, std::size_t e) {
    if (e <= b) return;
    const double c = time_all(certified, b, e), m = time_check_motion(b, e), d = time_all(discrete, b, e);
    const double k = static_cast<double>(e - b);
    std::printf("%-26s %8zu %14.1f %14.1f %14.1f %8.2f %8.2f\n", label.c_str(), e - b, 1e6 * c / k, 1e6 * m / k,
                1e6 * d / k, c / d, m / d);
  };
  row("planned paths", 0, planned);
  std::fflush(stdout);
  {
    // The same segments timed one by one (three passes in order, as the
    // rows above run them, each segment's best): how the time spreads.
    std::vector<double> tm(planned, 1e300), td(planned, 1e300);
    for (int rep = 0; rep < 3; ++rep)
      for (std::size_t i = 0; i < planned; ++i) {
        auto t0 = Clock::now();
        const bool ok = a.checker->check_motion(segs[i].first, segs[i].second, plancheck::MotionOptions{true, true})
                            .verdict == plancheck::Verdict::kSafe;
        tm[i] = std::min(tm[i], since(t0));
        ompl_state(segs[i].first, s1);
        ompl_state(segs[i].second, s2);
        t0 = Clock::now();
        if (discrete->checkMotion(s1.get(), s2.get()) < ok) die("certified safe but a discrete sample is not");
        td[i] = std::min(td[i], since(t0));
      }
    std::vector<double> ratio(planned), dear = tm;
    for (std::size_t i = 0; i < planned; ++i) ratio[i] = tm[i] / td[i];
    std::sort(ratio.begin(), ratio.end());
    std::sort(dear.rbegin(), dear.rend());
    double all = 0.0;
    for (double x : dear) all += x;
    auto share = [&](double fraction) {
      double s = 0.0;
      for (std::size_t i = 0; i < static_cast<std::size_t>(fraction * static_cast<double>(planned) + 0.5); ++i) s += dear[i];
      return 100.0 * s / all;
    };
    auto at = [&](double q) { return ratio[static_cast<std::size_t>(q * static_cast<double>(planned - 1))]; };
    std::printf("planned paths one by one: check_motion / discrete per segment, median %.2f, 90th percentile %.2f, "
                "largest %.1f; the dearest 1%% of segments take %.0f%% of check_motion's time, the dearest 10%% %.0f%%\n",
                at(0.5), at(0.9), ratio.back(), share(0.01), share(0.1));
    std::fflush(stdout);
  }
  row("random near pairs", planned, segs.size());
  // By length (the discrete validator's sample count): sort a copy.
  std::vector<std::size_t> order(planned);
  for (std::size_t i = 0; i < planned; ++i) order[i] = i;
  std::vector<double> len(planned);
  for (std::size_t i = 0; i < planned; ++i) {
    ompl_state(segs[i].first, s1);
    ompl_state(segs[i].second, s2);
    len[i] = a.discrete_si->distance(s1.get(), s2.get()) / a.discrete_si->getMaximumExtent();
  }
  std::sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) { return len[x] < len[y]; });
  auto sorted = segs;
  for (std::size_t i = 0; i < planned; ++i) sorted[i] = segs[order[i]];
  segs.swap(sorted);
  for (int qt = 0; qt < 4; ++qt) {
    const std::size_t b = planned * static_cast<std::size_t>(qt) / 4, e = planned * static_cast<std::size_t>(qt + 1) / 4;
    char label[64];
    std::snprintf(label, sizeof label, "planned, length %.3f-%.3f", len[order[b]], len[order[e - 1]]);
    row(label, b, e);
  }
}

void planner_table(const Arm& a, int seeds, const std::string& plancheck, const fs::path& out) {
  std::vector<double> tc, td;
  std::vector<std::vector<std::vector<double>>> pc, pd;
  for (int k = 0; k < seeds; ++k) {
    const std::size_t q = static_cast<std::size_t>(k) % a.queries.size();
    Solved c = solve(a, a.si, q, true);
    Solved d = solve(a, a.discrete_si, q, true);
    tc.push_back(c.seconds);
    td.push_back(d.seconds);
    pc.push_back(std::move(c.path));
    pd.push_back(std::move(d.path));
  }
  const int bad_c = rejected(a, pc, plancheck, out / (a.name + "-certified"));
  const int bad_d = rejected(a, pd, plancheck, out / (a.name + "-discrete"));
  if (bad_c != 0) die(a.name + ": a certified path fails verify --continuous");
  auto median = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
  };
  std::printf("\n%s: RRTConnect + simplifySolution, %d runs over %zu queries (obstacle in the way)\n", a.name.c_str(),
              seeds, a.queries.size());
  std::printf("%-24s %16s %30s\n", "motion validator", "median ms", "paths failing verify --continuous");
  std::printf("%-24s %16.2f %22d of %d\n", "certified (check_motion)", 1e3 * median(tc), bad_c, seeds);
  std::printf("%-24s %16.2f %22d of %d\n", "discrete (OMPL default)", 1e3 * median(td), bad_d, seeds);
  std::printf("ratio certified / discrete: %.2f\n", median(tc) / median(td));
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  int seeds = 20;
  std::size_t segments = 1000;
  std::vector<std::string> pos;
  for (std::size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "--seeds" && i + 1 < args.size()) seeds = std::stoi(args[++i]);
    else if (args[i] == "--segments" && i + 1 < args.size()) segments = std::stoul(args[++i]);
    else pos.push_back(args[i]);
  }
  if (pos.size() != 4 || seeds < 1) die("usage: plancheck_ompl_bench DATASET URDF_EXAMPLE PLANCHECK OUT [--seeds N] [--segments N]");
  const fs::path data = fs::absolute(pos[0]), example = fs::absolute(pos[1]), out = fs::absolute(pos[3]);
  ompl::RNG::setSeed(42);
  ompl::msg::setLogLevel(ompl::msg::LOG_ERROR);
  fs::remove_all(out);
  fs::create_directories(out);
  nlohmann::ordered_json scene = nlohmann::ordered_json::parse(read_text(data / "scene.json"));
  scene.erase("scoop");  // planning states never dig; verify sees the same scene
  // Written into OUT, never beside the dataset (a run stopped half way left
  // its copy there): the model and the DEM named by absolute paths, as the
  // URDF scene below names its files.
  scene["model"] = (data / scene["model"].get<std::string>()).string();
  if (scene.contains("terrain") && scene["terrain"].contains("dem"))
    scene["terrain"]["dem"] = (data / scene["terrain"]["dem"].get<std::string>()).string();
  const fs::path nodig = out / "scene-nodig.json";
  write_text(nodig, scene.dump(2));
  nlohmann::json urdf = nlohmann::json::parse(read_text(example / "scene.json"));
  urdf["model"] = (data / scene["model"].get<std::string>()).string();
  urdf["robot"]["urdf"] = (example / urdf["robot"]["urdf"].get<std::string>()).string();
  urdf["robot"]["srdf"] = (example / urdf["robot"]["srdf"].get<std::string>()).string();
  write_text(out / "urdf-scene.json", urdf.dump(2));
  for (const auto& [name, path, edges] :
       {std::tuple<std::string, fs::path, fs::path>{"default arm", nodig, out / "default-edges.csv"},
        std::tuple<std::string, fs::path, fs::path>{"URDF arm", out / "urdf-scene.json", out / "urdf-edges.csv"}}) {
    const Arm a = make_arm(name, path, 5);
    segment_table(a, segments, edges);
    planner_table(a, seeds, pos[2], out);
  }
  return 0;
}
