// SPDX-License-Identifier: MIT
// plancheck_api_bench DATASET [STATES]: the public API's per-call cost
// (issue 14) on the default plans' first STATES states (default 1000),
// beside `plancheck verify` on the same states. Answers are checked against
// verify's CSV before anything is timed. Prints one table; wall-clock
// medians of 5 runs.
#include <plancheck/plancheck.h>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

std::string read_text(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream s(line);
  std::string f;
  while (std::getline(s, f, ',')) out.push_back(f);
  return out;
}

template <class F>
double median_seconds(F&& f, int runs = 5) {
  std::vector<double> t;
  for (int i = 0; i < runs; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    t.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.12g", v);
  return buf;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: plancheck_api_bench DATASET [STATES]\n";
    return 2;
  }
  const fs::path data = argv[1];
  const std::size_t want = argc > 2 ? std::stoul(argv[2]) : 1000;
  const fs::path self = fs::canonical("/proc/self/exe").parent_path();  // the build folder's bench dir
  fs::path plancheck_exe = self / "plancheck";
  if (!fs::exists(plancheck_exe)) plancheck_exe = self.parent_path() / "plancheck";

  // The first `want` states of the default plans, as written.
  std::vector<fs::path> plans;
  for (const auto& e : fs::directory_iterator(data / "plans")) plans.push_back(e.path());
  std::sort(plans.begin(), plans.end());
  std::vector<std::vector<double>> states;
  std::string header;
  for (const fs::path& p : plans) {
    std::istringstream in(read_text(p));
    std::string line;
    bool seen_header = false;
    while (std::getline(in, line) && states.size() < want) {
      if (line.empty() || line[0] == '#') continue;
      if (!seen_header) {
        seen_header = true;
        header = line;
        continue;
      }
      std::vector<double> s;
      for (const std::string& f : split(line)) s.push_back(std::stod(f));
      states.push_back(s);
    }
  }
  const std::size_t n = states.size();

  // verify on the same states as one plan, on the scene without digging
  // (the API checks on the initial terrain).
  const fs::path tmp = fs::temp_directory_path() / ("plancheck-api-bench-" + std::to_string(::getpid()));
  fs::create_directories(tmp);
  {
    std::ofstream plan(tmp / "states.csv");
    plan << header << "\n";
    plan.precision(17);
    for (const auto& s : states) {
      for (std::size_t j = 0; j < s.size(); ++j) plan << (j ? "," : "") << s[j];
      plan << "\n";
    }
    std::string scene = read_text(data / "scene.json");
    // Drop the top-level "scoop" block: the generator writes it between "terrain" and "probes".
    const std::size_t at = scene.find("\n  \"scoop\"");
    const std::size_t end = scene.find("\n  \"probes\"");
    if (at == std::string::npos || end == std::string::npos) {
      std::cerr << "plancheck_api_bench: no scoop block found in " << (data / "scene.json") << "\n";
      return 2;
    }
    scene.erase(at, end - at);
    std::ofstream(data / "scene-nodig-bench.json") << scene;
  }
  double verify_seconds[3] = {};
  for (int threads : {1, 2}) {
    std::vector<double> t;
    for (int r = 0; r < 5; ++r) {
      std::ostringstream command;  // (a stream, not "..." + string: GCC 12's -Wrestrict false positive, bug 105651)
      command << std::quoted(plancheck_exe.string()) << " verify " << std::quoted((data / "scene-nodig-bench.json").string())
              << ' ' << std::quoted((tmp / "states.csv").string()) << " --quiet --threads " << threads << " --out "
              << std::quoted((tmp / "out").string()) << " > /dev/null";
      const std::string cmd = command.str();
      const int status = std::system(cmd.c_str());
      if (status != 0 && WEXITSTATUS(status) != 1) {
        std::cerr << "plancheck_api_bench: verify failed: " << cmd << "\n";
        return 2;
      }
      const std::string report = read_text(tmp / "out" / "report.json");
      const std::size_t c = report.find("\"check\":");
      t.push_back(std::stod(report.substr(c + 8)));
    }
    std::sort(t.begin(), t.end());
    verify_seconds[threads] = t[t.size() / 2];
  }
  fs::remove(data / "scene-nodig-bench.json");

  const plancheck::Scene scene = plancheck::Scene::load((data / "scene.json").string());
  const plancheck::Checker one(scene, 1), two(scene, 2);

  // Answers first: every state equals verify's CSV row (distance and pair).
  std::istringstream csv(read_text(tmp / "out" / "states.csv"));
  std::string line;
  std::getline(csv, line);
  const std::vector<plancheck::StateResult> batch = two.check_batch(states);
  for (std::size_t i = 0; i < n; ++i) {
    std::getline(csv, line);
    const std::vector<std::string> row = split(line);
    if (row.size() < 5 || row[1] != (batch[i].collision ? "1" : "0") || row[2] != num(batch[i].min_distance) ||
        row[3] != batch[i].part_a || row[4] != batch[i].part_b) {
      std::cerr << "plancheck_api_bench: state " << i << " differs from verify: " << line << "\n";
      return 1;
    }
  }
  fs::remove_all(tmp);

  std::vector<plancheck::StateResult> out(n);
  const double single = median_seconds([&] {
    for (std::size_t i = 0; i < n; ++i) out[i] = one.check(states[i]);
  });
  const double batch1 = median_seconds([&] { out = one.check_batch(states); });
  const double batch2 = median_seconds([&] { out = two.check_batch(states); });
  auto us = [&](double s) { return 1e6 * s / static_cast<double>(n); };
  std::printf("%zu states of the default plans (microseconds per state, median of 5)\n", n);
  std::printf("  verify --threads 1 (check seconds, coherent plan)  %8.1f\n", us(verify_seconds[1]));
  std::printf("  verify --threads 2                                 %8.1f\n", us(verify_seconds[2]));
  std::printf("  C++ Checker::check, one state per call, 1 thread   %8.1f\n", us(single));
  std::printf("  C++ Checker::check_batch(%zu), 1 thread           %8.1f\n", n, us(batch1));
  std::printf("  C++ Checker::check_batch(%zu), 2 threads          %8.1f\n", n, us(batch2));

  // The call itself: a two-box scene whose check costs about a microsecond,
  // so what a call adds shows above the machine's noise.
  fs::create_directories(tmp);
  std::string obj;
  const char* faces = "f 1 3 2\nf 2 3 4\nf 5 6 7\nf 6 8 7\nf 1 2 5\nf 2 6 5\nf 3 7 4\nf 4 7 8\nf 1 5 3\nf 3 5 7\nf 2 4 6\nf 4 8 6\n";
  obj += "o Slab\nv -3 -1 -1\nv 3 -1 -1\nv -3 1 -1\nv 3 1 -1\nv -3 -1 0\nv 3 -1 0\nv -3 1 0\nv 3 1 0\n";
  obj += faces;
  obj += "o Bar\nv 0 -0.1 0.9\nv 2 -0.1 0.9\nv 0 0.1 0.9\nv 2 0.1 0.9\nv 0 -0.1 1.1\nv 2 -0.1 1.1\nv 0 0.1 1.1\nv 2 0.1 1.1\n";
  obj += "f 9 11 10\nf 10 11 12\nf 13 14 15\nf 14 16 15\nf 9 10 13\nf 10 14 13\nf 11 15 12\nf 12 15 16\nf 9 13 11\nf 11 13 15\nf 10 12 14\nf 12 16 14\n";
  std::ofstream(tmp / "model.obj") << obj;
  std::ofstream(tmp / "scene.json") << R"({"format": "plancheck-scene/1", "model": "model.obj", "length_unit": "m",
    "angle_unit": "deg", "actions": [{"name": "J1", "node": "Bar", "type": "rotate", "pivot": [0, 0, 1],
    "axis": [0, 1, 0]}], "safety_margin": 0.05})";
  const plancheck::Checker tiny(plancheck::Scene::load((tmp / "scene.json").string()), 1);
  fs::remove_all(tmp);
  std::vector<std::vector<double>> angles;
  for (std::size_t i = 0; i < n; ++i) angles.push_back({-90.0 + 110.0 * static_cast<double>(i) / static_cast<double>(n)});
  std::vector<plancheck::StateResult> tiny_out(n);
  const double tiny_single = median_seconds([&] {
    for (std::size_t i = 0; i < n; ++i) tiny_out[i] = tiny.check(angles[i]);
  });
  const double tiny_batch = median_seconds([&] { tiny_out = tiny.check_batch(angles); });
  std::printf("two boxes (12 triangles each), %zu states, 1 thread (microseconds per state)\n", n);
  std::printf("  C++ Checker::check, one state per call             %8.2f\n", us(tiny_single));
  std::printf("  C++ Checker::check_batch(%zu)                     %8.2f\n", n, us(tiny_batch));
  return 0;
}
