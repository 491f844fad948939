// SPDX-License-Identifier: MIT
// World objects at run time (issue 32): what moving an object and checking
// again costs over the check alone, on the default dataset (no digging, as
// the API checks). Answers first: every move's check equals the check of a
// checker built from a scene file holding the object at that pose.
//   plancheck_objects_bench DATASET [REPETITIONS]
#include <plancheck/plancheck.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

std::string read_text(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// A moved object is placed, not posed again: its distances equal the scene
// file's up to the rounding of the posing.
bool same(const plancheck::StateResult& a, const plancheck::StateResult& b) {
  return a.collision == b.collision && std::abs(a.min_distance - b.min_distance) <= 1e-12 && a.part_a == b.part_a &&
         a.part_b == b.part_b && a.verdict == b.verdict;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: plancheck_objects_bench DATASET [REPETITIONS]\n";
    return 2;
  }
  const fs::path data = argv[1];
  const int reps = argc > 2 ? std::stoi(argv[2]) : 200;
  nlohmann::json j = nlohmann::json::parse(read_text(data / "scene.json"));
  j.erase("scoop");
  j.erase("probes");
  j["model"] = fs::absolute(data / j["model"].get<std::string>()).string();
  if (j.contains("terrain")) j["terrain"]["dem"] = fs::absolute(data / j["terrain"]["dem"].get<std::string>()).string();
  const fs::path tmp = fs::temp_directory_path() / ("plancheck-objects-bench-" + std::to_string(::getpid()));
  fs::create_directories(tmp);
  j.erase("objects");
  std::ofstream(tmp / "plain.json") << j.dump();
  const plancheck::Scene scene = plancheck::Scene::load((tmp / "plain.json").string());
  plancheck::Checker c(scene, 1);
  // A state of plan01 (its middle row, as written), and two poses of a box
  // above the arm's point closest to the lander there.
  const std::vector<std::vector<double>> rows = scene.read_plan((data / "plans" / "plan01.csv").string());
  const std::vector<double> state = rows[rows.size() / 2];
  const plancheck::StateResult base = c.check(state);
  const auto& p0 = base.point_a;
  // Two poses above that point where the box is the closest part without touching.
  plancheck::Object rock;
  rock.name = "Rock";
  rock.box = {0.3, 0.2, 0.15};
  rock.pose.xyz = {p0[0], p0[1], p0[2] + 3};
  c.add_object(rock);
  std::vector<plancheck::Pose> poses;
  for (int k = 1; k <= 40 && poses.size() < 2; ++k) {
    const plancheck::Pose p{{p0[0], p0[1], p0[2] + 0.05 * k}, {0, 0, 10.0 * static_cast<double>(poses.size())}};
    c.move_object("Rock", p);
    const plancheck::StateResult r = c.check(state);
    if (!r.collision && (r.part_a == "Rock" || r.part_b == "Rock")) poses.push_back(p);
  }
  if (poses.size() < 2) {
    std::cerr << "plancheck_objects_bench: found no pose where the box is the closest part\n";
    return 1;
  }
  std::vector<plancheck::StateResult> expected;
  for (const plancheck::Pose& p : poses) {
    j["objects"] = nlohmann::json::array(
        {{{"name", "Rock"}, {"box", {0.3, 0.2, 0.15}}, {"pose", {{"xyz", p.xyz}, {"rpy", p.rpy}}}}});
    std::ofstream(tmp / "objects.json") << j.dump();
    const plancheck::Checker fresh(plancheck::Scene::load((tmp / "objects.json").string()), 1);
    expected.push_back(fresh.check(state));
    std::printf("object at pose %zu: closest pair %s / %s, %.6g %s\n", expected.size() - 1,
                expected.back().part_a.c_str(), expected.back().part_b.c_str(), expected.back().min_distance,
                fresh.scene().length_unit().c_str());
  }
  fs::remove_all(tmp);
  // Answers first.
  for (int k = 0; k < 4; ++k) {
    c.move_object("Rock", poses[k % 2]);
    if (!same(c.check(state), expected[static_cast<std::size_t>(k % 2)])) {
      std::cerr << "plancheck_objects_bench: a moved object's check differs from the scene file's\n";
      return 1;
    }
  }
  std::vector<double> check_alone, move_and_check, move_alone;
  for (int r = 0; r < reps; ++r) {
    auto t0 = std::chrono::steady_clock::now();
    const plancheck::StateResult a = c.check(state);
    check_alone.push_back(seconds_since(t0));
    t0 = std::chrono::steady_clock::now();
    c.move_object("Rock", poses[r % 2]);
    move_alone.push_back(seconds_since(t0));
    const plancheck::StateResult b = c.check(state);
    move_and_check.push_back(seconds_since(t0));
    if (!same(b, expected[static_cast<std::size_t>(r % 2)]) || a.verdict != expected[static_cast<std::size_t>((r + 1) % 2)].verdict) {
      std::cerr << "plancheck_objects_bench: wrong answer at repetition " << r << "\n";
      return 1;
    }
  }
  // Adding and removing a second box (each builds the new version of the world).
  std::vector<double> add, remove;
  for (int r = 0; r < std::max(3, reps / 20); ++r) {
    plancheck::Object other = rock;
    other.name = "Other";
    other.pose.xyz = {p0[0] + 5, p0[1], p0[2]};
    auto t0 = std::chrono::steady_clock::now();
    c.add_object(other);
    add.push_back(seconds_since(t0));
    t0 = std::chrono::steady_clock::now();
    c.remove_object("Other");
    remove.push_back(seconds_since(t0));
  }
  const double ms = 1e3;
  std::printf("default dataset (%zu parts), 1 thread, median of %d (milliseconds)\n", c.part_names().size(), reps);
  std::printf("  check alone                 %8.3f\n", median(check_alone) * ms);
  std::printf("  move_object alone           %8.3f\n", median(move_alone) * ms);
  std::printf("  move_object + check         %8.3f\n", median(move_and_check) * ms);
  std::printf("  overhead (move+check - check) %6.3f\n", (median(move_and_check) - median(check_alone)) * ms);
  std::printf("  add_object (a box)          %8.3f\n", median(add) * ms);
  std::printf("  remove_object               %8.3f\n", median(remove) * ms);
  return 0;
}
