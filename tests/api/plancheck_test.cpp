// SPDX-License-Identifier: MIT
// The public API (<plancheck/plancheck.h>) gives `plancheck verify`'s
// per-state answers: every state of the default plans and of a stiff bar
// scene is checked through the API and compared with the CSV row and the
// report.json verdicts verify writes for it. This suite sees only the
// public header, as a consumer does.
#include <plancheck/plancheck.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <functional>
#include <set>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iterator>
#include <random>
#include <sstream>
#include <thread>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

const fs::path kBinary = PLANCHECK_BINARY_DIR;

struct TempDir {
  fs::path path;
  TempDir() {
    std::string tmpl = (fs::temp_directory_path() / "plancheck-api-XXXXXX").string();
    if (!mkdtemp(tmpl.data())) throw std::runtime_error("mkdtemp failed");
    path = tmpl;
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

void write_text(const fs::path& p, const std::string& text) {
  std::ofstream f(p, std::ios::binary);
  f << text;
}

std::string read_text(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
}

// An axis-aligned box as one OBJ object (12 triangles, outward faces).
std::string obj_box(const std::string& name, std::array<double, 3> lo, std::array<double, 3> hi, int& base) {
  std::ostringstream o;
  o.precision(17);
  o << "o " << name << "\n";
  for (int i = 0; i < 8; ++i)
    o << "v " << (i & 1 ? hi : lo)[0] << " " << (i & 2 ? hi : lo)[1] << " " << (i & 4 ? hi : lo)[2] << "\n";
  static const int faces[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                                   {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  for (const auto& f : faces) o << "f " << base + f[0] + 1 << " " << base + f[1] + 1 << " " << base + f[2] + 1 << "\n";
  base += 8;
  return o.str();
}

// The stiff case: a 2-unit bar pitching about a horizontal axis 1 unit above
// a slab (distance 1 - 2 sin a - h cos a, h = 1 - float(0.9): margin at
// a = 25.458364447446368 deg, contact at 27.096330350410646 deg), in metres
// or millimetres (scale 1000, length_unit mm).
void write_bar_scene(const fs::path& dir, double scale, const std::string& unit) {
  int base = 0;
  auto s = [&](double v) { return v * scale; };
  std::string obj = obj_box("Slab", {s(-3), s(-1), s(-1)}, {s(3), s(1), 0}, base);
  obj += obj_box("Bar", {0, s(-0.1), s(0.9)}, {s(2), s(0.1), s(1.1)}, base);  // after Slab: base moved on
  write_text(dir / "model.obj", obj);
  std::ostringstream j;
  j.precision(17);
  j << R"({"format": "plancheck-scene/1", "model": "model.obj", "length_unit": ")" << unit
    << R"(", "angle_unit": "deg", "actions": [{"name": "J1", "node": "Bar", "type": "rotate", "pivot": [0, 0, )"
    << s(1) << R"(], "axis": [0, 1, 0], "limits": [-90, 30]}], "safety_margin": )" << s(0.05) << "}";
  write_text(dir / "scene.json", j.str());
}

// States of the stiff case, degrees as written: far, near the margin (both
// sides and on it), near contact, in contact, beyond the limits (390 poses as
// 30, -330 too, but both are outside [-90, 30] as written).
const std::vector<double> kBarAngles = {-90.0, -45.0, 0.0, 10.0, 25.45836444744637 - 1e-6, 25.458364447446368,
                                        25.45836444744637 + 1e-6, 27.096330350410646 - 1e-7,
                                        27.096330350410646, 27.1, 29.99, 30.000001, 390.0, -330.0, 720.0};

// `plancheck verify` with --quiet: its exit status and stderr.
int run_verify(const std::string& args, std::string* err_text = nullptr) {
  TempDir t;
  const std::string cmd = "\"" + (kBinary / "plancheck").string() + "\" verify " + args + " --quiet > /dev/null 2> \"" +
                          (t.path / "err").string() + "\"";
  const int status = std::system(cmd.c_str());
  if (err_text) *err_text = read_text(t.path / "err");
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::vector<std::vector<std::string>> read_csv(const fs::path& p) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(read_text(p));
  std::string line;
  while (std::getline(in, line)) {
    std::vector<std::string> fields;
    std::size_t start = 0;
    for (;;) {
      const std::size_t at = line.find(',', start);
      fields.push_back(line.substr(start, at == std::string::npos ? std::string::npos : at - start));
      if (at == std::string::npos) break;
      start = at + 1;
    }
    rows.push_back(std::move(fields));
  }
  return rows;
}

std::size_t tied_states = 0;  // states whose closest points differ from verify's at an equal distance

// verify's number format in the per-plan CSV (src/report.cpp).
std::string num(double v) {
  if (!std::isfinite(v)) return "";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.12g", v);
  return buf;
}

// One API answer against verify's CSV row (state,collision,min_distance,
// part_a,part_b,ax,ay,az,bx,by,bz,limits,...). Closest points are not
// unique where faces are parallel at the minimum, and verify seeds each
// state's search with the previous state's closest pair: with tie_points,
// points that differ from verify's must still be at min_distance from each
// other, as verify's are (to their 12 printed digits).
void expect_row(const plancheck::StateResult& r, const std::vector<std::string>& row, const std::string& where,
                bool tie_points = false) {
  ASSERT_GE(row.size(), 12u) << where;
  EXPECT_EQ(r.collision ? "1" : "0", row[1]) << where;
  EXPECT_EQ(num(r.min_distance), row[2]) << where;
  EXPECT_EQ(r.part_a, row[3]) << where;
  EXPECT_EQ(r.part_b, row[4]) << where;
  EXPECT_EQ(r.limits, row[11]) << where;
  bool same = true;
  for (std::size_t i = 0; i < 3; ++i)
    same = same && (r.part_a.empty() ? "" : num(r.point_a[i])) == row[5 + i] &&
           (r.part_a.empty() ? "" : num(r.point_b[i])) == row[8 + i];
  if (same) return;
  if (!tie_points || r.part_a.empty()) {
    ADD_FAILURE() << where << ": closest points differ from verify's: " << num(r.point_a[0]) << " " << num(r.point_a[1])
                  << " " << num(r.point_a[2]) << " / " << num(r.point_b[0]) << " " << num(r.point_b[1]) << " "
                  << num(r.point_b[2]);
    return;
  }
  auto gap = [](const std::array<double, 3>& a, const std::array<double, 3>& b) {
    return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
  };
  std::array<double, 3> va{}, vb{};
  for (std::size_t i = 0; i < 3; ++i) {
    va[i] = std::stod(row[5 + i]);
    vb[i] = std::stod(row[8 + i]);
  }
  const double tol = 1e-9 * std::max(1.0, r.min_distance);
  EXPECT_NEAR(gap(r.point_a, r.point_b), r.min_distance, tol) << where;
  EXPECT_NEAR(gap(va, vb), r.min_distance, tol) << where << " (verify's points)";
  ++tied_states;
}

// The first non-safe state and its kind must be verify's first_violation
// (a target violation comes only after every state is safe).
void expect_first_violation(const std::vector<plancheck::StateResult>& rs, const nlohmann::json& plan) {
  const std::string name = plan["name"];
  std::size_t first = rs.size();
  for (std::size_t s = 0; s < rs.size(); ++s)
    if (rs[s].verdict != plancheck::Verdict::kSafe) {
      first = s;
      break;
    }
  if (first == rs.size()) {
    EXPECT_TRUE(plan["first_violation"].is_null() || plan["first_violation"]["kind"] == "target") << name;
  } else {
    ASSERT_FALSE(plan["first_violation"].is_null()) << name;
    EXPECT_EQ(plan["first_violation"]["state"].get<std::size_t>(), first) << name;
    EXPECT_EQ(plan["first_violation"]["kind"].get<std::string>(), plancheck::verdict_name(rs[first].verdict)) << name;
  }
}

TEST(Api, VersionIsTheProjects) {
  EXPECT_STREQ(plancheck::version(), PLANCHECK_VERSION);
  TempDir t;
  const std::string cmd = "\"" + (kBinary / "plancheck").string() + "\" --version > \"" + (t.path / "v").string() + "\"";
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  EXPECT_EQ(read_text(t.path / "v"), std::string("plancheck ") + PLANCHECK_VERSION + "\n");
}

// Each bar state as a plan of its own, so report.json's verdict is that
// state's verdict exactly (no band around the margin to allow for).
void check_bar_case(double scale, const std::string& unit) {
  TempDir t;
  write_bar_scene(t.path, scale, unit);
  std::string plans;
  for (std::size_t i = 0; i < kBarAngles.size(); ++i) {
    char text[64];
    std::snprintf(text, sizeof text, "J1\n%.17g\n", kBarAngles[i]);
    const fs::path p = t.path / ("s" + std::to_string(100 + i) + ".csv");
    write_text(p, text);
    plans += " \"" + p.string() + "\"";
  }
  ASSERT_EQ(run_verify("\"" + (t.path / "scene.json").string() + "\"" + plans + " --out \"" + (t.path / "out").string() + "\""), 1);
  const nlohmann::json report = nlohmann::json::parse(read_text(t.path / "out" / "report.json"));

  const plancheck::Scene scene = plancheck::Scene::load((t.path / "scene.json").string());
  EXPECT_EQ(scene.parameter_names(), std::vector<std::string>{"J1"});
  EXPECT_EQ(scene.length_unit(), unit);
  EXPECT_DOUBLE_EQ(scene.safety_margin(), 0.05 * scale);
  const plancheck::Checker checker(scene, 2);
  std::vector<std::vector<double>> states;
  for (double a : kBarAngles) states.push_back({a});
  const std::vector<plancheck::StateResult> batch = checker.check_batch(states);
  std::size_t kinds[4] = {}, bounds = 0;
  for (std::size_t i = 0; i < kBarAngles.size(); ++i) {
    const std::string where = unit + " state " + std::to_string(kBarAngles[i]);
    const plancheck::StateResult one = checker.check(states[i]);
    const auto rows = read_csv(t.path / "out" / ("s" + std::to_string(100 + i) + ".csv"));
    ASSERT_EQ(rows.size(), 2u) << where;
    expect_row(one, rows[1], where);
    expect_row(batch[i], rows[1], where + " (batch)");
    const nlohmann::json& plan = report["plans"][i];
    const std::string verdict = plan["verdict"];
    EXPECT_EQ(plancheck::verdict_name(one.verdict), verdict) << where;
    EXPECT_EQ(batch[i].verdict, one.verdict) << where;
    ++kinds[static_cast<int>(one.verdict)];
    // Verdict-only: the same verdict; the exact distance below the margin,
    // a certified lower bound (no parts) where it proves the margin clear.
    const plancheck::StateResult vo = checker.check(states[i], plancheck::CheckOptions{true});
    EXPECT_EQ(vo.verdict, one.verdict) << where;
    EXPECT_EQ(vo.collision, one.collision) << where;
    EXPECT_FALSE(one.min_distance_is_bound) << where;
    if (one.min_distance < scene.safety_margin()) {
      EXPECT_FALSE(vo.min_distance_is_bound) << where;
      EXPECT_NEAR(vo.min_distance, one.min_distance, 1e-12 * scale) << where;
    }
    if (vo.min_distance_is_bound) {
      ++bounds;
      EXPECT_LE(vo.min_distance, one.min_distance + 1e-12 * scale) << where;
      EXPECT_GE(vo.min_distance, scene.safety_margin()) << where;
      EXPECT_TRUE(vo.part_a.empty()) << where;
    }
  }
  EXPECT_GT(bounds, 0u) << unit;
  const auto vo_batch = checker.check_batch(states, plancheck::CheckOptions{true});
  for (std::size_t i = 0; i < states.size(); ++i) EXPECT_EQ(vo_batch[i].verdict, batch[i].verdict) << unit << " " << i;
  // The stiff states cover every verdict.
  for (int k = 0; k < 4; ++k) EXPECT_GT(kinds[k], 0u) << unit << " verdict " << k;
}

TEST(Api, StiffBarEqualsVerify) { check_bar_case(1.0, "m"); }
TEST(Api, StiffBarInMillimetresEqualsVerify) { check_bar_case(1000.0, "mm"); }

// Scene::load throws verify's message (stderr's "plancheck: " line) for the same input.
TEST(Api, BadSceneThrowsVerifysMessage) {
  TempDir t;
  write_bar_scene(t.path, 1.0, "m");
  write_text(t.path / "plan.csv", "J1\n0\n");
  const std::string good = read_text(t.path / "scene.json");
  std::vector<std::pair<std::string, std::string>> cases = {
      {"missing.json", ""},
      {"bad-json.json", "{\"format\": "},
      {"bad-margin.json", good.substr(0, good.find("\"safety_margin\"")) + "\"safety_margin\": -1}"},
      {"bad-node.json", std::string(good).replace(good.find("\"node\": \"Bar\""), 13, "\"node\": \"Nope\"")},
      {"bad-model.json", std::string(good).replace(good.find("model.obj"), 9, "nothing.obj")},
  };
  for (const auto& [file, text] : cases) {
    const fs::path scene = t.path / file;
    if (!text.empty()) write_text(scene, text);
    std::string err;
    std::ostringstream args;  // (a stream, not "..." + string: GCC 12's -Wrestrict false positive, bug 105651)
    args << std::quoted(scene.string()) << ' ' << std::quoted((t.path / "plan.csv").string()) << " --out "
         << std::quoted((t.path / "out").string());
    ASSERT_EQ(run_verify(args.str(), &err), 2) << file;
    std::string message;
    try {
      const plancheck::Scene s = plancheck::Scene::load(scene.string());
      const plancheck::Checker c(s, 1);
      ADD_FAILURE() << file << ": no error";
    } catch (const plancheck::Error& e) {
      message = e.what();
    }
    EXPECT_EQ("plancheck: " + message + "\n", err) << file;
  }
}

TEST(Api, BadStatesThrow) {
  TempDir t;
  write_bar_scene(t.path, 1.0, "m");
  const plancheck::Checker checker(plancheck::Scene::load((t.path / "scene.json").string()), 1);
  auto message = [&](auto&& f) {
    try {
      f();
    } catch (const plancheck::Error& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  EXPECT_EQ(message([&] { checker.check({}); }), "state: expected 1 values (J1), got 0");
  EXPECT_EQ(message([&] { checker.check({1.0, 2.0}); }), "state: expected 1 values (J1), got 2");
  EXPECT_EQ(message([&] { checker.check({std::nan("")}); }), "state: parameter 'J1' is not a finite number");
  EXPECT_EQ(message([&] { checker.check_batch({{1.0}, {2.0}, {INFINITY}}); }),
            "state 2: parameter 'J1' is not a finite number");
  EXPECT_EQ(checker.check_batch({}).size(), 0u);
}

// Scene::read_plan reads a plan as verify does (comments, quoted names, a
// time column, values as written) and fails with verify's message.
TEST(Api, ReadPlanReadsAsVerifyReads) {
  TempDir t;
  write_bar_scene(t.path, 1.0, "m");
  const plancheck::Scene scene = plancheck::Scene::load((t.path / "scene.json").string());
  write_text(t.path / "p.csv", "# name: x\ntime,\"J1\"\n0,10\n1.5,-20.5\n2,1e300\n");
  EXPECT_EQ(scene.read_plan((t.path / "p.csv").string()),
            (std::vector<std::vector<double>>{{10.0}, {-20.5}, {1e300}}));
  write_text(t.path / "bad.csv", "J1\n0\nfive\n");
  std::string err;
  ASSERT_EQ(run_verify(std::string("\"") + (t.path / "scene.json").string() + "\" \"" + (t.path / "bad.csv").string() +
                           "\" --out \"" + (t.path / "out").string() + "\"",
                       &err),
            2);
  try {
    (void)scene.read_plan((t.path / "bad.csv").string());
    ADD_FAILURE() << "no error";
  } catch (const plancheck::Error& e) {
    EXPECT_EQ("plancheck: " + std::string(e.what()) + "\n", err);
    EXPECT_NE(std::string(e.what()).find("bad.csv:3:1"), std::string::npos) << e.what();
  }
}

// check_batch on 1 and 2 threads and check() from several threads at once
// give the same answers bit for bit (states are independent).
TEST(Api, ThreadsAgree) {
  TempDir t;
  write_bar_scene(t.path, 1.0, "m");
  const plancheck::Scene scene = plancheck::Scene::load((t.path / "scene.json").string());
  const plancheck::Checker one(scene, 1), two(scene, 2);
  std::vector<std::vector<double>> states;
  for (int i = 0; i < 200; ++i) states.push_back({-90.0 + 0.6 * i});
  const auto a = one.check_batch(states);
  const auto b = two.check_batch(states);
  std::vector<plancheck::StateResult> c(states.size());
  std::vector<std::thread> pool;
  for (int k = 0; k < 2; ++k)
    pool.emplace_back([&, k] {
      for (std::size_t i = static_cast<std::size_t>(k); i < states.size(); i += 2) c[i] = two.check(states[i]);
    });
  for (auto& th : pool) th.join();
  for (std::size_t i = 0; i < states.size(); ++i) {
    for (const plancheck::StateResult* r : {&b[i], static_cast<const plancheck::StateResult*>(&c[i])}) {
      EXPECT_EQ(a[i].collision, r->collision) << i;
      EXPECT_EQ(a[i].min_distance, r->min_distance) << i;
      EXPECT_EQ(a[i].part_a, r->part_a) << i;
      EXPECT_EQ(a[i].point_a, r->point_a) << i;
      EXPECT_EQ(a[i].point_b, r->point_b) << i;
      EXPECT_EQ(a[i].verdict, r->verdict) << i;
    }
  }
}

// Writes `scene` (a scene of directory `data`, its model and DEM named
// relative to it) to `to`, with those two paths made absolute, so that the
// copy reads the same files from anywhere.
fs::path nodig_copy(nlohmann::ordered_json scene, const fs::path& data, const fs::path& to) {
  scene["model"] = fs::absolute(data / scene["model"].get<std::string>()).string();
  if (scene.contains("terrain") && scene["terrain"].contains("dem"))
    scene["terrain"]["dem"] = fs::absolute(data / scene["terrain"]["dem"].get<std::string>()).string();
  write_text(to, scene.dump(2));
  return to;
}

// The default plans (DatasetFixture's change5): every state through the
// API equals verify's CSV row. verify digs along a plan and checks the
// terrain where it was dug; the API checks on the initial terrain, so verify
// runs here on the same scene without its scoop block (nothing dug).
TEST(ApiDataset, DefaultPlansEqualVerify) {
  const fs::path data = kBinary / "test-dataset";
  ASSERT_TRUE(fs::exists(data / "scene.json")) << "run DatasetFixture.Generate";
  nlohmann::ordered_json scene_json = nlohmann::ordered_json::parse(read_text(data / "scene.json"));
  ASSERT_TRUE(scene_json.contains("scoop"));
  scene_json.erase("scoop");
  TempDir t;
  // In the test's own directory, the model and the DEM named by absolute
  // paths: nothing is written beside the dataset.
  const fs::path nodig = nodig_copy(scene_json, data, t.path / "scene-nodig.json");
  std::vector<fs::path> plans;
  for (const auto& e : fs::directory_iterator(data / "plans")) plans.push_back(e.path());
  std::sort(plans.begin(), plans.end());
#ifdef PLANCHECK_SANITIZED
  // The same comparison at sanitizer speed: the collision and the clearance plan.
  std::erase_if(plans, [](const fs::path& p) { return p.stem() != "plan04" && p.stem() != "plan07"; });
  ASSERT_EQ(plans.size(), 2u);
#endif
  std::string args = "\"" + nodig.string() + "\"";
  for (const auto& p : plans) args += " \"" + p.string() + "\"";
  const int status = run_verify(args + " --out \"" + (t.path / "out").string() + "\"");
  ASSERT_LE(status, 1);
  const nlohmann::json report = nlohmann::json::parse(read_text(t.path / "out" / "report.json"));

  // The original scene (with its scoop): the API never digs.
  const plancheck::Scene scene = plancheck::Scene::load((data / "scene.json").string());
  const plancheck::Checker checker(scene);
  std::size_t states = 0, non_safe = 0;
  for (std::size_t p = 0; p < plans.size(); ++p) {
    const auto plan_states = scene.read_plan(plans[p].string());
    const auto results = checker.check_batch(plan_states);
    const nlohmann::json& plan = report["plans"][p];
    const auto rows = read_csv(t.path / "out" / (plan["name"].get<std::string>() + ".csv"));
    ASSERT_EQ(rows.size(), plan_states.size() + 1) << plans[p];
    for (std::size_t s = 0; s < plan_states.size(); ++s) {
      expect_row(results[s], rows[s + 1], plans[p].filename().string() + " state " + std::to_string(s), true);
      non_safe += results[s].verdict != plancheck::Verdict::kSafe;
    }
    expect_first_violation(results, plan);
    // Single calls agree with the batch (a few states per plan).
    for (std::size_t s = 0; s < plan_states.size(); s += 37) {
      const plancheck::StateResult r = checker.check(plan_states[s]);
      EXPECT_EQ(r.min_distance, results[s].min_distance);
      EXPECT_EQ(r.verdict, results[s].verdict);
    }
    states += plan_states.size();
  }
  EXPECT_GT(states, 0u);
  EXPECT_GT(non_safe, 0u);  // the default plans hold designed violations
  std::printf("%zu of %zu states: closest points differ from verify's seeded search at an equal distance\n",
              tied_states, states);

  // Exactly, points included: verify on one-state plans (its search is then
  // unseeded, as every API call is), every 7th state of the default plans.
  std::vector<std::vector<double>> picked;
  std::string one_state_plans;
  std::string header;
  for (const std::string& name : scene.parameter_names()) {
    if (!header.empty()) header += ',';
    header += name;
  }
  const fs::path single = t.path / "single";
  fs::create_directories(single);
  std::size_t k = 0;
  for (const fs::path& p : plans)
    for (const auto& state : scene.read_plan(p.string()))
      if (k++ % 7 == 0) {
        std::string text = header + "\n";
        char value[32];
        for (std::size_t j = 0; j < state.size(); ++j) {
          std::snprintf(value, sizeof value, "%.17g", state[j]);
          if (j) text += ',';
          text += value;
        }
        const fs::path plan = single / ("s" + std::to_string(10000 + picked.size()) + ".csv");
        write_text(plan, text + "\n");
        one_state_plans += " \"" + plan.string() + "\"";
        picked.push_back(state);
      }
  const int single_status = run_verify("\"" + nodig.string() + "\"" + one_state_plans + " --out \"" + (t.path / "out1").string() + "\"");
  ASSERT_LE(single_status, 1);
  const auto picked_results = checker.check_batch(picked);
  for (std::size_t i = 0; i < picked.size(); ++i) {
    const auto rows = read_csv(t.path / "out1" / ("s" + std::to_string(10000 + i) + ".csv"));
    ASSERT_EQ(rows.size(), 2u);
    expect_row(picked_results[i], rows[1], "one-state plan " + std::to_string(i));
  }
}

}  // namespace

// ---- Motions: Checker::check_motion against verify --continuous ----------

namespace {

using Motion = std::pair<std::vector<double>, std::vector<double>>;

// verify --continuous on one two-state plan per motion (values as written,
// %.17g): each plan's report.json entry, its CSV header and state 0's row
// (which holds the segment's columns).
struct VerifiedMotions {
  nlohmann::json plans;
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
};

VerifiedMotions verify_motions(const fs::path& scene, const std::vector<std::string>& names,
                               const std::vector<Motion>& motions, const fs::path& dir,
                               const std::string& extra = "") {
  std::string header;
  for (const std::string& n : names) header += (header.empty() ? "" : ",") + n;
  auto row = [](const std::vector<double>& s) {
    std::string text;
    char value[32];
    for (std::size_t j = 0; j < s.size(); ++j) {
      std::snprintf(value, sizeof value, "%.17g", s[j]);
      text += (j ? "," : "") + std::string(value);
    }
    return text + "\n";
  };
  fs::create_directories(dir / "plans");
  std::string args = "\"" + scene.string() + "\"";
  for (std::size_t i = 0; i < motions.size(); ++i) {
    const fs::path p = dir / "plans" / ("m" + std::to_string(100000 + i) + ".csv");
    write_text(p, header + "\n" + row(motions[i].first) + row(motions[i].second));
    args += " \"" + p.string() + "\"";
  }
  VerifiedMotions out;
  const int status = run_verify(args + " --continuous --out \"" + (dir / "out").string() + "\"" + extra);
  EXPECT_LE(status, 1);
  if (status > 1) return out;
  out.plans = nlohmann::json::parse(read_text(dir / "out" / "report.json"))["plans"];
  for (std::size_t i = 0; i < motions.size(); ++i) {
    const auto rows = read_csv(dir / "out" / ("m" + std::to_string(100000 + i) + ".csv"));
    EXPECT_EQ(rows.size(), 3u);
    if (rows.size() != 3) return out;
    out.header = rows[0];
    out.rows.push_back(rows[1]);
  }
  return out;
}

// One check_motion answer against verify --continuous's for the same
// two-state plan: the plan's verdict and first violation, the segment's
// collision, witness and certified bound (verdict_only: a bound at most
// verify's).
void expect_motion(const plancheck::MotionResult& m, const VerifiedMotions& v, std::size_t i, const std::string& where,
                   bool verdict_only) {
  ASSERT_LT(i, v.rows.size()) << where;
  const nlohmann::json& plan = v.plans[i];
  auto col = [&](const std::string& name) {
    const auto at = std::find(v.header.begin(), v.header.end(), name);
    EXPECT_NE(at, v.header.end()) << name;
    return at == v.header.end() ? std::string() : v.rows[i][static_cast<std::size_t>(at - v.header.begin())];
  };
  EXPECT_EQ(plancheck::verdict_name(m.verdict), plan["verdict"].get<std::string>()) << where;
  EXPECT_EQ(m.collision, col("segment_collision") == "1") << where;
  const nlohmann::json& first = plan["first_violation"];
  if (first.is_null()) {
    EXPECT_TRUE(std::isnan(m.t)) << where;
    EXPECT_TRUE(m.part_a.empty()) << where;
  } else {
    if (first.value("between", false)) {
      EXPECT_EQ(m.certified, !first.value("uncertified", false)) << where;
      if (m.certified) {
        EXPECT_EQ(num(m.t), col("segment_t")) << where;
      } else {
        EXPECT_TRUE(std::isnan(m.t)) << where;
      }
    } else {
      EXPECT_EQ(m.t, first["state"].get<int>() == 0 ? 0.0 : 1.0) << where;
    }
    if (first.contains("parts")) {
      EXPECT_EQ(m.part_a, first["parts"][0].get<std::string>()) << where;
      EXPECT_EQ(m.part_b, first["parts"][1].get<std::string>()) << where;
    } else {
      EXPECT_TRUE(m.part_a.empty()) << where;
    }
  }
  const std::string lower = col("segment_min_distance");
  if (!verdict_only) {
    EXPECT_EQ(num(m.min_distance), lower) << where;
  } else {
    const double full = lower.empty() ? INFINITY : std::stod(lower);
    EXPECT_GE(m.min_distance, 0.0) << where;
    EXPECT_LE(m.min_distance, full * (1 + 1e-11)) << where;
    if (full == 0.0) {
      EXPECT_EQ(m.min_distance, 0.0) << where;
    }
  }
}

// check_motion, both modes, one by one and batched, against verify
// --continuous on the same motions; counts of verdicts seen.
std::array<std::size_t, 4> expect_motions_equal_verify(const fs::path& scene_path, const std::vector<Motion>& motions,
                                                        const fs::path& dir, const std::string& verify_args = "",
                                                        const plancheck::LoadOptions& load = {}) {
  const plancheck::Scene scene = plancheck::Scene::load(scene_path.string(), load);
  const plancheck::Checker checker(scene);
  const VerifiedMotions v = verify_motions(scene_path, scene.parameter_names(), motions, dir, verify_args);
  std::array<std::size_t, 4> kinds{};
  if (v.rows.size() != motions.size()) {
    ADD_FAILURE() << "verify failed on " << scene_path;
    return kinds;
  }
  std::vector<std::vector<double>> from, to;
  for (const auto& [a, b] : motions) {
    from.push_back(a);
    to.push_back(b);
  }
  std::vector<plancheck::MotionResult> quick;
  for (const bool verdict_only : {false, true}) {
    const auto batch = checker.check_motion_batch(from, to, plancheck::MotionOptions{verdict_only});
    if (verdict_only) quick = batch;
    if (batch.size() != motions.size()) {
      ADD_FAILURE() << "batch size " << batch.size();
      return kinds;
    }
    for (std::size_t i = 0; i < motions.size(); ++i) {
      const std::string where = scene_path.filename().string() + " motion " + std::to_string(i) +
                                (verdict_only ? " (verdict only)" : "");
      expect_motion(batch[i], v, i, where, verdict_only);
      if (!verdict_only) ++kinds[static_cast<std::size_t>(batch[i].verdict)];
      if (i % 17 == 0) {  // single calls agree with the batch
        const plancheck::MotionResult one = checker.check_motion(from[i], to[i], plancheck::MotionOptions{verdict_only});
        EXPECT_EQ(one.verdict, batch[i].verdict) << where;
        EXPECT_EQ(one.min_distance, batch[i].min_distance) << where;
        EXPECT_EQ(one.steps, batch[i].steps) << where;
      }
    }
  }
  // first_violation: safe exactly where verify says so, certified as far;
  // safe motions and an end's own violation as verdict-only; a motion found
  // below the margin is that witness's clearance, with no bound.
  const auto first = checker.check_motion_batch(from, to, plancheck::MotionOptions{true, true});
  for (std::size_t i = 0; i < motions.size() && first.size() == motions.size() && quick.size() == motions.size(); ++i) {
    const std::string where = scene_path.filename().string() + " motion " + std::to_string(i) + " (first violation)";
    const plancheck::MotionResult& f = first[i];
    const plancheck::MotionResult& q = quick[i];
    EXPECT_EQ(f.verdict == plancheck::Verdict::kSafe, v.plans[i]["verdict"].get<std::string>() == "safe") << where;
    EXPECT_EQ(f.safe_until, q.safe_until) << where;
    EXPECT_LE(f.steps, q.steps) << where;
    const plancheck::StateResult s0 = checker.check(from[i]), s1 = checker.check(to[i]);
    if (q.verdict == plancheck::Verdict::kSafe || q.verdict == plancheck::Verdict::kLimits ||
        s0.verdict != plancheck::Verdict::kSafe || !q.certified || scene.safety_margin() == 0.0) {
      EXPECT_EQ(f.verdict, q.verdict) << where;
      if (q.verdict == plancheck::Verdict::kSafe || scene.safety_margin() == 0.0) {
        EXPECT_EQ(f.collision, q.collision) << where;
      } else {
        EXPECT_EQ(f.collision, s0.collision || s1.collision) << where;  // the contact pass was not run
      }
      EXPECT_EQ(num(f.t), num(q.t)) << where;
      EXPECT_EQ(f.part_a, q.part_a) << where;
      EXPECT_EQ(f.part_b, q.part_b) << where;
      if (q.verdict == plancheck::Verdict::kSafe || !q.certified) {
        EXPECT_EQ(f.certified, q.certified) << where;
        EXPECT_EQ(f.min_distance, q.min_distance) << where;
        EXPECT_EQ(f.steps, q.steps) << where;
      }
    } else {
      // The margin pass's witness: state 1 touching, else a clearance.
      EXPECT_GE(f.t, 0.0) << where;
      EXPECT_LE(f.t, 1.0) << where;
      EXPECT_EQ(f.verdict, f.t == 1.0 && s1.collision ? plancheck::Verdict::kCollision : plancheck::Verdict::kClearance)
          << where;
      EXPECT_EQ(f.collision, s1.collision) << where;  // (s0 is safe)
      if (s1.collision) {
        EXPECT_EQ(f.min_distance, 0.0) << where;
      } else {
        EXPECT_TRUE(std::isnan(f.min_distance)) << where;
      }
      if (q.verdict == plancheck::Verdict::kClearance) {
        EXPECT_EQ(f.t, q.t) << where;
        EXPECT_EQ(f.part_a, q.part_a) << where;
        EXPECT_EQ(f.part_b, q.part_b) << where;
      }
    }
  }
  return kinds;
}

}  // namespace

// The stiff bar: every motion between two of its states (near misses 1e-7
// and 1e-9 rad from the margin and from contact, whole turns written as 390,
// -330 and 720 degrees, the long way round) in both directions.
TEST(Api, StiffBarMotionsEqualVerifyContinuous) {
  TempDir t;
  write_bar_scene(t.path, 1.0, "m");
  std::vector<Motion> motions;
  std::vector<double> angles = kBarAngles;
  angles.push_back(25.45836444744637 + 1e-9);
  angles.push_back(27.096330350410646 + 1e-9);
  for (double a : angles)
    for (double b : angles) motions.push_back({{a}, {b}});
  const auto kinds = expect_motions_equal_verify(t.path / "scene.json", motions, t.path);
  for (std::size_t k = 0; k < 4; ++k) EXPECT_GT(kinds[k], 0u) << "verdict " << k;
}

// A motion that never comes near anything but needs more exact checks than
// the budget (thousands of turns of a 2 m bar 0.4 m from a post): a
// violation that names no pair and is not certified, never safe and never
// a contact, as verify --continuous reports it.
TEST(Api, MotionBeyondTheStepBudgetIsAnUncertifiedViolation) {
  TempDir t;
  int base = 0;
  write_text(t.path / "model.obj", obj_box("Bar", {0.2, -0.05, 0.95}, {2, 0.05, 1.05}, base) +
                                       obj_box("Post", {-0.1, -0.1, 1.2}, {0.1, 0.1, 3}, base));
  write_text(t.path / "scene.json", R"({"format": "plancheck-scene/1", "model": "model.obj", "length_unit": "m",
  "angle_unit": "deg", "actions": [{"name": "Slew", "node": "Bar", "type": "rotate", "pivot": [0, 0, 0],
  "axis": [0, 0, 1]}], "safety_margin": 0.05})");
  // The far motion second: the helper's single-call spot checks take the first.
  const std::vector<Motion> motions{{{0.0}, {720.0}}, {{0.0}, {2e7}}};
  const auto kinds = expect_motions_equal_verify(t.path / "scene.json", motions, t.path);
  EXPECT_EQ(kinds[0], 1u);  // two turns: certified safe
  EXPECT_EQ(kinds[1], 1u);  // 55,556 turns: not certified, a clearance violation naming no pair
}

namespace {

// Random motions within the limits (finite ones; +-180 where none): half
// between two random states (long, across the workspace), half short steps
// (up to 5% of each range) from a random state.
std::vector<Motion> random_motions(const plancheck::Scene& scene, std::size_t count, unsigned seed) {
  std::mt19937_64 rng(seed);
  const auto lo = scene.lower_limits(), hi = scene.upper_limits();
  std::vector<Motion> out;
  auto random_state = [&] {
    std::vector<double> s(lo.size());
    for (std::size_t j = 0; j < s.size(); ++j) {
      const double a = std::isfinite(lo[j]) ? lo[j] : -180.0, b = std::isfinite(hi[j]) ? hi[j] : 180.0;
      s[j] = std::uniform_real_distribution<double>(a, b)(rng);
    }
    return s;
  };
  for (std::size_t i = 0; i < count; ++i) {
    std::vector<double> a = random_state(), b = random_state();
    if (i % 2)
      for (std::size_t j = 0; j < a.size(); ++j) {
        const double lim_a = std::isfinite(lo[j]) ? lo[j] : -180.0, lim_b = std::isfinite(hi[j]) ? hi[j] : 180.0;
        b[j] = std::clamp(a[j] + 0.05 * (b[j] - a[j]), lim_a, lim_b);
      }
    out.emplace_back(a, b);
  }
  return out;
}

}  // namespace

// The default plans segment by segment (each as a two-state plan), random
// motions of the default arm and of the URDF example's arm on the same
// lander: check_motion, full and verdict-only, equals verify --continuous.
// verify digs along plans with a scoop; the API never digs, so verify runs
// on the scene without its scoop block.
TEST(ApiDataset, MotionsEqualVerifyContinuous) {
  const fs::path data = kBinary / "test-dataset";
  ASSERT_TRUE(fs::exists(data / "scene.json")) << "run DatasetFixture.Generate";
  nlohmann::ordered_json scene_json = nlohmann::ordered_json::parse(read_text(data / "scene.json"));
  scene_json.erase("scoop");
  TempDir t;
  const fs::path nodig = nodig_copy(scene_json, data, t.path / "scene-nodig.json");
  const plancheck::Scene scene = plancheck::Scene::load(nodig.string());

  std::vector<Motion> motions;
  std::vector<fs::path> plans;
  for (const auto& e : fs::directory_iterator(data / "plans")) plans.push_back(e.path());
  std::sort(plans.begin(), plans.end());
  // Every 3rd segment of each plan (every 15th under the sanitizers):
  // designed collision and clearance violations included.
#ifdef PLANCHECK_SANITIZED
  const std::size_t every = 15;
#else
  const std::size_t every = 3;
#endif
  for (const fs::path& p : plans) {
    const auto states = scene.read_plan(p.string());
    for (std::size_t s = 0; s + 1 < states.size(); s += every) motions.emplace_back(states[s], states[s + 1]);
  }
  const std::size_t from_plans = motions.size();
  for (auto& m : random_motions(scene, 60, 11)) motions.push_back(std::move(m));
  const auto kinds = expect_motions_equal_verify(nodig, motions, t.path / "default");
  std::printf("default arm: %zu motions (%zu from the plans): %zu safe, %zu clearance, %zu collision, %zu limits\n",
              motions.size(), from_plans, kinds[0], kinds[1], kinds[2], kinds[3]);
  EXPECT_GT(kinds[0], 0u);
  EXPECT_GT(kinds[1] + kinds[2], 0u);

  // The URDF example's survey arm on the same lander.
  const fs::path example = fs::path(PLANCHECK_SOURCE_DIR) / "datasets" / "urdf-example";
  nlohmann::json urdf = nlohmann::json::parse(read_text(example / "scene.json"));
  urdf["model"] = (data / scene_json["model"].get<std::string>()).string();
  urdf["robot"]["urdf"] = (example / urdf["robot"]["urdf"].get<std::string>()).string();
  urdf["robot"]["srdf"] = (example / urdf["robot"]["srdf"].get<std::string>()).string();
  fs::create_directories(t.path / "urdf");
  write_text(t.path / "urdf" / "scene.json", urdf.dump(2));
  const plancheck::Scene arm = plancheck::Scene::load((t.path / "urdf" / "scene.json").string());
  const auto urdf_kinds = expect_motions_equal_verify(t.path / "urdf" / "scene.json", random_motions(arm, 80, 12),
                                                      t.path / "urdf");
  std::printf("URDF arm: %zu safe, %zu clearance, %zu collision, %zu limits\n", urdf_kinds[0], urdf_kinds[1],
              urdf_kinds[2], urdf_kinds[3]);
  EXPECT_GT(urdf_kinds[0], 0u);
  EXPECT_GT(urdf_kinds[1] + urdf_kinds[2], 0u);
}

// ---- World objects (scene-format.md "World objects", Embedding) ----

namespace {

// The bar scene with `objects` (a JSON array's text) and allowed_collisions.
void write_bar_scene_with(const fs::path& dir, const std::string& objects, const std::string& allowed = "") {
  write_bar_scene(dir, 1.0, "m");
  std::string j = read_text(dir / "scene.json");
  j.pop_back();  // the closing brace
  if (!objects.empty()) j += R"(, "objects": )" + objects;
  if (!allowed.empty()) j += R"(, "allowed_collisions": )" + allowed;
  write_text(dir / "scene.json", j + "}");
}

plancheck::Object box_object(const std::string& name, std::array<double, 3> size, std::array<double, 3> xyz,
                             std::array<double, 3> rpy = {}, const std::string& parent = "") {
  plancheck::Object o;
  o.name = name;
  o.shape = plancheck::Object::Shape::kBox;
  o.box = size;
  o.pose = {xyz, rpy};
  o.parent = parent;
  return o;
}

plancheck::Object sphere_object(const std::string& name, double radius, std::array<double, 3> xyz) {
  plancheck::Object o;
  o.name = name;
  o.shape = plancheck::Object::Shape::kSphere;
  o.radius = radius;
  o.pose.xyz = xyz;
  return o;
}

void expect_same(const plancheck::StateResult& a, const plancheck::StateResult& b, const std::string& what) {
  EXPECT_EQ(a.collision, b.collision) << what;
  EXPECT_EQ(a.min_distance, b.min_distance) << what;
  EXPECT_EQ(a.part_a, b.part_a) << what;
  EXPECT_EQ(a.part_b, b.part_b) << what;
  EXPECT_EQ(a.verdict, b.verdict) << what;
}

// Distance between two axis-aligned boxes (lo, hi): the slow obvious reference.
double box_distance(std::array<double, 3> alo, std::array<double, 3> ahi, std::array<double, 3> blo,
                    std::array<double, 3> bhi) {
  double s = 0;
  for (int k = 0; k < 3; ++k) {
    const double gap = std::max({0.0, blo[k] - ahi[k], alo[k] - bhi[k]});
    s += gap * gap;
  }
  return std::sqrt(s);
}

const std::string kBarObjects = R"([
  {"name": "Rock", "box": [0.2, 0.3, 0.4], "pose": {"xyz": [1, 0.5, 1.6], "rpy": [10, 20, 30]}},
  {"name": "Pole", "cylinder": {"radius": 0.05, "length": 1.2}, "pose": {"xyz": [-1, 0.4, 0.6], "rpy": [0, 90, 0]}},
  {"name": "Ball", "sphere": 0.1, "pose": {"xyz": [1.5, 0, 0.5]}},
  {"name": "Crate", "mesh": "crate.obj", "scale": [2, 1, 0.5], "pose": {"xyz": [2.5, 0, 0.3]}},
  {"name": "Tag", "box": [0.1, 0.1, 0.1], "parent": "Bar", "pose": {"xyz": [1, 0, 0.5]}}])";

void add_bar_objects(plancheck::Checker& c, const fs::path& dir) {
  c.add_object(box_object("Rock", {0.2, 0.3, 0.4}, {1, 0.5, 1.6}, {10, 20, 30}));
  plancheck::Object pole;
  pole.name = "Pole";
  pole.shape = plancheck::Object::Shape::kCylinder;
  pole.radius = 0.05;
  pole.length = 1.2;
  pole.pose = {{-1, 0.4, 0.6}, {0, 90, 0}};
  c.add_object(pole);
  c.add_object(sphere_object("Ball", 0.1, {1.5, 0, 0.5}));
  plancheck::Object crate;
  crate.name = "Crate";
  crate.shape = plancheck::Object::Shape::kMesh;
  crate.mesh = (dir / "crate.obj").string();
  crate.scale = {2, 1, 0.5};
  crate.pose.xyz = {2.5, 0, 0.3};
  c.add_object(crate);
  c.add_object(box_object("Tag", {0.1, 0.1, 0.1}, {1, 0, 0.5}, {}, "Bar"));
}

void write_crate(const fs::path& dir) {
  int base = 0;
  write_text(dir / "crate.obj", obj_box("Crate", {-0.1, -0.1, -0.1}, {0.1, 0.1, 0.1}, base));
}

}  // namespace

// The scene file's objects and the same objects added at run time are the
// same parts: state by state the same answers (exactly), and the same motions.
TEST(Api, ObjectsInJsonEqualObjectsAddedAtRunTime) {
  TempDir a, b;
  write_crate(a.path);
  write_bar_scene_with(a.path, kBarObjects);
  write_bar_scene(b.path, 1.0, "m");
  const plancheck::Checker json(plancheck::Scene::load((a.path / "scene.json").string()), 2);
  plancheck::Checker run(plancheck::Scene::load((b.path / "scene.json").string()), 2);
  add_bar_objects(run, a.path);
  const std::vector<std::string> objects = {"Rock", "Pole", "Ball", "Crate", "Tag"};
  EXPECT_EQ(json.object_names(), objects);
  EXPECT_EQ(run.object_names(), objects);
  EXPECT_EQ(json.part_names(), run.part_names());
  std::vector<std::vector<double>> states;
  for (int i = 0; i <= 240; ++i) states.push_back({-90.0 + 0.5 * i});
  const auto ra = json.check_batch(states), rb = run.check_batch(states);
  std::set<std::string> named;
  for (std::size_t i = 0; i < states.size(); ++i) {
    expect_same(ra[i], rb[i], "state " + std::to_string(i));
    named.insert(ra[i].part_b);
  }
  // The objects decide answers here (not only the slab).
  EXPECT_TRUE(named.count("Ball") && named.count("Rock")) << named.size();
  for (std::size_t i = 0; i + 10 < states.size(); i += 10) {
    const auto ma = json.check_motion(states[i], states[i + 10]), mb = run.check_motion(states[i], states[i + 10]);
    EXPECT_EQ(ma.verdict, mb.verdict) << i;
    EXPECT_EQ(ma.min_distance, mb.min_distance) << i;
    EXPECT_EQ(ma.part_b, mb.part_b) << i;
  }
}

// The default dataset with objects in its scene file equals the same objects
// added at run time, on random states.
TEST(ApiDataset, ObjectsInJsonEqualObjectsAddedAtRunTime) {
  const fs::path data = kBinary / "test-dataset";
  TempDir t;
  nlohmann::json j = nlohmann::json::parse(read_text(data / "scene.json"));
  j.erase("scoop");
  j.erase("probes");
  j["model"] = (data / j["model"].get<std::string>()).string();
  if (j.contains("terrain")) j["terrain"]["dem"] = (data / j["terrain"]["dem"].get<std::string>()).string();
  write_text(t.path / "plain.json", j.dump());
  j["objects"] = nlohmann::json::parse(R"([
    {"name": "Rock1", "box": [0.3, 0.2, 0.15], "pose": {"xyz": [2.9, 0.1, 0.07], "rpy": [0, 0, 30]}},
    {"name": "Ball", "sphere": 0.25, "pose": {"xyz": [2.0, 0.5, 1.6]}},
    {"name": "Bag", "box": [0.05, 0.05, 0.08], "parent": "Scoop", "pose": {"xyz": [0, 0, 0.06]}}])");
  write_text(t.path / "objects.json", j.dump());
  const plancheck::Checker json(plancheck::Scene::load((t.path / "objects.json").string()), 2);
  plancheck::Checker run(plancheck::Scene::load((t.path / "plain.json").string()), 2);
  run.add_object(box_object("Rock1", {0.3, 0.2, 0.15}, {2.9, 0.1, 0.07}, {0, 0, 30}));
  run.add_object(sphere_object("Ball", 0.25, {2.0, 0.5, 1.6}));
  run.add_object(box_object("Bag", {0.05, 0.05, 0.08}, {0, 0, 0.06}, {}, "Scoop"));
  EXPECT_EQ(json.part_names(), run.part_names());
  std::vector<std::vector<double>> states;
  for (const auto& [from, to] : random_motions(json.scene(), 100, 32)) {
    states.push_back(from);
    states.push_back(to);
  }
  const auto ra = json.check_batch(states), rb = run.check_batch(states);
  std::size_t object_pairs = 0;
  for (std::size_t i = 0; i < states.size(); ++i) {
    expect_same(ra[i], rb[i], "state " + std::to_string(i));
    for (const char* n : {"Rock1", "Ball", "Bag"}) object_pairs += ra[i].part_a == n || ra[i].part_b == n;
  }
  EXPECT_GT(object_pairs, 0u);  // some state's closest pair is an object's
}

// A moved object is seen at its new pose only, against the analytic distance
// of two axis-aligned boxes (the bar at 0 degrees and the object).
TEST(Api, MovedObjectIsSeenAtItsNewPoseOnly) {
  TempDir t;
  write_bar_scene(t.path, 1.0, "m");
  plancheck::Checker c(plancheck::Scene::load((t.path / "scene.json").string()), 1);
  // The OBJ's coordinates are read as floats.
  const double f01 = static_cast<float>(0.1), f09 = static_cast<float>(0.9), f11 = static_cast<float>(1.1);
  const std::array<double, 3> bar_lo{0, -f01, f09}, bar_hi{2, f01, f11};
  const std::vector<double> level = {0.0};
  const double slab = f09;  // the bar's bottom above the slab's top
  EXPECT_EQ(c.check(level).part_b, "Slab");
  const std::array<std::array<double, 3>, 4> centres = {{{1, 0, 1.5}, {2.3, 0.4, 1.0}, {1, 0, 1.25}, {0.5, 0, 1.0}}};
  const std::array<double, 3> size{0.2, 0.4, 0.2};
  c.add_object(box_object("Cube", size, centres[0], {0, 0, 180}));
  for (std::size_t k = 0; k < centres.size(); ++k) {
    if (k > 0) c.move_object("Cube", {centres[k], {0, 0, 180}});
    std::array<double, 3> lo, hi;
    for (int i = 0; i < 3; ++i) {
      lo[static_cast<std::size_t>(i)] = centres[k][static_cast<std::size_t>(i)] - size[static_cast<std::size_t>(i)] / 2;
      hi[static_cast<std::size_t>(i)] = centres[k][static_cast<std::size_t>(i)] + size[static_cast<std::size_t>(i)] / 2;
    }
    const double d = box_distance(bar_lo, bar_hi, lo, hi);
    const plancheck::StateResult r = c.check(level);
    EXPECT_EQ(r.collision, d == 0.0) << k;
    EXPECT_NEAR(r.min_distance, std::min(d, slab), 1e-12) << k;
    EXPECT_EQ(r.part_b, d < slab ? "Cube" : "Slab") << k;
    EXPECT_EQ(c.object_names(), std::vector<std::string>{"Cube"});
  }
  // A later change that builds (an added object) keeps the moved one where it was moved to.
  const plancheck::StateResult moved = c.check(level);
  c.add_object(box_object("Far", {0.1, 0.1, 0.1}, {-2.5, 0, 3}));
  expect_same(moved, c.check(level), "after an added object");
  c.remove_object("Far");
  c.remove_object("Cube");
  EXPECT_TRUE(c.object_names().empty());
  EXPECT_EQ(c.check(level).part_b, "Slab");
  EXPECT_NEAR(c.check(level).min_distance, slab, 1e-12);
}

// check_motion keeps the end states its thread checked last for the next
// motion sharing an end; a world change makes a new world, whose motions
// never take a state checked in the old one. State {10} is clear before
// the cube moves onto the bar there and in contact after: the motion from
// it must say so at t = 0, as the same motion checked cold on a new thread.
TEST(Api, MotionAfterAnObjectMovedSeesTheMoveAtItsSharedEnd) {
  TempDir t;
  write_bar_scene(t.path, 1.0, "m");
  plancheck::Checker c(plancheck::Scene::load((t.path / "scene.json").string()), 1);
  c.add_object(box_object("Cube", {0.3, 0.3, 0.3}, {1, 0, 3}));
  const std::vector<double> a{0.0}, b{10.0}, d{20.0};
  for (bool verdict_only : {true, false}) {
    SCOPED_TRACE(verdict_only ? "verdict-only" : "full");
    c.move_object("Cube", {{1, 0, 3}, {}});
    ASSERT_FALSE(c.check(b).collision);
    c.check_motion(a, b, plancheck::MotionOptions{verdict_only});  // keeps a and b as the old world showed them
    c.move_object("Cube", {{1, 0, 1}, {}});
    ASSERT_TRUE(c.check(b).collision);
    const plancheck::MotionResult warm = c.check_motion(b, d, plancheck::MotionOptions{verdict_only});
    plancheck::MotionResult cold;
    std::thread([&] { cold = c.check_motion(b, d, plancheck::MotionOptions{verdict_only}); }).join();
    EXPECT_EQ(warm.verdict, plancheck::Verdict::kCollision);
    EXPECT_EQ(warm.t, 0.0);
    EXPECT_EQ(warm.safe_until, 0.0);
    EXPECT_EQ(warm.part_a, cold.part_a);
    EXPECT_EQ(warm.part_b, cold.part_b);
    EXPECT_EQ(warm.verdict, cold.verdict);
    EXPECT_EQ(warm.min_distance, cold.min_distance);
    EXPECT_EQ(warm.steps, cold.steps);
  }
}

// check_motion keeps the answers its thread gave last: the same motion
// asked again (same states, same options, same world) is the same answer,
// bit for bit, as one checked cold on a new thread, also after other
// motions and options in between and after more motions than are kept;
// the same motion after the world changed is checked in the new world.
TEST(Api, MotionAskedAgainIsTheSameAnswerAndSeesWorldChanges) {
  TempDir t;
  write_bar_scene(t.path, 1.0, "m");
  plancheck::Checker c(plancheck::Scene::load((t.path / "scene.json").string()), 1);
  c.add_object(box_object("Cube", {0.3, 0.3, 0.3}, {1, 0, 3.5}));
  auto bits = [](double v) {
    std::uint64_t u;
    std::memcpy(&u, &v, sizeof u);
    return u;
  };
  auto expect_same = [&](const plancheck::MotionResult& x, const plancheck::MotionResult& y, const std::string& where) {
    EXPECT_EQ(x.verdict, y.verdict) << where;
    EXPECT_EQ(x.collision, y.collision) << where;
    EXPECT_EQ(bits(x.min_distance), bits(y.min_distance)) << where;
    EXPECT_EQ(bits(x.t), bits(y.t)) << where;
    EXPECT_EQ(x.part_a, y.part_a) << where;
    EXPECT_EQ(x.part_b, y.part_b) << where;
    EXPECT_EQ(x.certified, y.certified) << where;
    EXPECT_EQ(x.steps, y.steps) << where;
    EXPECT_EQ(x.safe_until, y.safe_until) << where;
  };
  auto cold = [&](const std::vector<double>& a, const std::vector<double>& b, const plancheck::MotionOptions& o) {
    plancheck::MotionResult r;
    std::thread([&] { r = c.check_motion(a, b, o); }).join();
    return r;
  };
  const std::vector<double> a{-80.0}, b{20.0};
  for (const plancheck::MotionOptions o : {plancheck::MotionOptions{false}, plancheck::MotionOptions{true},
                                           plancheck::MotionOptions{true, true}}) {
    const std::string where = std::string(o.verdict_only ? "verdict-only" : "full") + (o.first_violation ? ", first" : "");
    c.move_object("Cube", {{1, 0, 3.5}, {}});
    const plancheck::MotionResult clear = c.check_motion(a, b, o);
    EXPECT_EQ(clear.verdict, plancheck::Verdict::kSafe) << where;
    expect_same(c.check_motion(a, b, o), clear, where + ": again");
    expect_same(c.check_motion(a, b, o), cold(a, b, o), where + ": again against cold");
    c.check_motion(a, b, plancheck::MotionOptions{!o.verdict_only});  // other options between
    for (int i = 0; i < 300; ++i) c.check_motion({-50.0 + 0.25 * i}, {-49.0 + 0.25 * i}, o);  // more than are kept (128)
    expect_same(c.check_motion(a, b, o), clear, where + ": after many");
    c.move_object("Cube", {{1, 0, 1}, {}});  // onto the bar's way: the motion meets it
    const plancheck::MotionResult hit = c.check_motion(a, b, o);
    EXPECT_NE(hit.verdict, plancheck::Verdict::kSafe) << where;
    expect_same(hit, cold(a, b, o), where + ": moved");
    for (const plancheck::MotionOptions other : {plancheck::MotionOptions{false}, plancheck::MotionOptions{true},
                                                 plancheck::MotionOptions{true, true}})
      expect_same(c.check_motion(a, b, other), cold(a, b, other), where + ": moved, the other options");
  }
}

// An object on the bar's node moves with it: its lowest corner above the
// slab, rotated about the pivot (0, 0, 1) by the right-hand rotation about
// +y, is the analytic distance (the bar's own is the other candidate).
TEST(Api, AttachedObjectsMoveWithTheirNode) {
  TempDir t;
  write_bar_scene_with(t.path, R"([{"name": "Tag", "box": [0.1, 0.1, 0.1], "parent": "Bar", "pose": {"xyz": [1, 0, 0.5]}}])");
  const plancheck::Checker c(plancheck::Scene::load((t.path / "scene.json").string()), 1);
  const double pi = 3.14159265358979323846;
  auto lowest = [&](double deg, std::array<double, 3> lo, std::array<double, 3> hi) {
    const double a = deg * pi / 180, s = std::sin(a), co = std::cos(a);
    double z = INFINITY;
    for (int i = 0; i < 8; ++i) {
      const double x = i & 1 ? hi[0] : lo[0], zr = (i & 4 ? hi[2] : lo[2]) - 1.0;
      z = std::min(z, -s * x + co * zr + 1.0);
    }
    return z;
  };
  for (double deg : {-40.0, -10.0, 0.0, 15.0, 20.0, 24.0}) {
    const double tag = lowest(deg, {0.95, -0.05, 0.45}, {1.05, 0.05, 0.55});
    const double bar = lowest(deg, {0, -0.1, static_cast<float>(0.9)}, {2, 0.1, static_cast<float>(1.1)});  // OBJ floats
    const plancheck::StateResult r = c.check({deg});
    EXPECT_NEAR(r.min_distance, std::max(0.0, std::min(tag, bar)), 1e-12) << deg;
    EXPECT_EQ(r.part_a, tag < bar ? "Tag" : "Bar") << deg;
    EXPECT_EQ(r.part_b, "Slab") << deg;
  }
  // Moved at run time on its node, it equals the scene file holding it there.
  TempDir u;
  write_bar_scene_with(u.path, R"([{"name": "Tag", "box": [0.1, 0.1, 0.1], "parent": "Bar", "pose": {"xyz": [1.5, 0, 0.7], "rpy": [0, 0, 45]}}])");
  const plancheck::Checker there(plancheck::Scene::load((u.path / "scene.json").string()), 1);
  plancheck::Checker moved(plancheck::Scene::load((t.path / "scene.json").string()), 1);
  moved.move_object("Tag", {{1.5, 0, 0.7}, {0, 0, 45}});
  for (double deg : {-40.0, 0.0, 20.0, 26.0}) expect_same(there.check({deg}), moved.check({deg}), std::to_string(deg));
}

// allowed_collisions naming an object drops its pairs; the bar's subtree
// holds the attached object.
TEST(Api, AllowedCollisionsNameObjects) {
  TempDir t, u;
  const std::string objects = R"([{"name": "Block", "box": [0.5, 0.5, 0.5], "pose": {"xyz": [1, 0, 1]}},
    {"name": "Tag", "box": [0.1, 0.1, 0.1], "parent": "Bar", "pose": {"xyz": [1, 0, 0.5]}}])";
  write_bar_scene_with(t.path, objects);
  write_bar_scene_with(u.path, objects, R"([["Block", "Bar"], ["Slab", "Bar"]])");
  const plancheck::Checker all(plancheck::Scene::load((t.path / "scene.json").string()), 1);
  const plancheck::Checker allowed(plancheck::Scene::load((u.path / "scene.json").string()), 1);
  const plancheck::StateResult r = all.check({0.0}), s = allowed.check({0.0});
  EXPECT_TRUE(r.collision);
  EXPECT_EQ(r.part_b, "Block");
  // [Block, Bar] allows Block against Bar and Tag; [Slab, Bar] Slab against both: no pair is left.
  EXPECT_FALSE(s.collision);
  EXPECT_TRUE(std::isinf(s.min_distance));
}

// verify on a scene with objects names the object part in its report.
TEST(Api, VerifyReportsObjectParts) {
  TempDir t;
  write_bar_scene_with(t.path, R"([{"name": "Rock", "box": [0.2, 0.2, 0.2], "pose": {"xyz": [1.5, 0, 0.5]}}])");
  write_text(t.path / "p.csv", "J1\n0\n10\n25\n");
  ASSERT_EQ(run_verify("\"" + (t.path / "scene.json").string() + "\" \"" + (t.path / "p.csv").string() +
                       "\" --continuous --out \"" + (t.path / "out").string() + "\""), 1);
  const std::string report = read_text(t.path / "out" / "report.json");
  EXPECT_NE(report.find("\"Rock\""), std::string::npos);
  const nlohmann::json j = nlohmann::json::parse(report);
  EXPECT_NE(j.dump().find("collision"), std::string::npos);
}

TEST(Api, ObjectErrorsThrowAndChangeNothing) {
  TempDir t;
  write_bar_scene_with(t.path, R"([{"name": "Rock", "box": [0.2, 0.2, 0.2], "pose": {"xyz": [1.5, 0, 0.5]}}])");
  plancheck::Checker c(plancheck::Scene::load((t.path / "scene.json").string()), 1);
  const plancheck::StateResult before = c.check({0.0});
  auto expect_error = [&](const std::function<void()>& f, const std::string& part) {
    try {
      f();
      ADD_FAILURE() << "no Error for " << part;
    } catch (const plancheck::Error& e) {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
    }
  };
  expect_error([&] { c.add_object(box_object("Rock", {1, 1, 1}, {})); }, "objects['Rock'].name: 'Rock' is already");
  expect_error([&] { c.add_object(box_object("Slab", {1, 1, 1}, {})); }, "'Slab' is already");
  expect_error([&] { c.add_object(box_object("B", {1, -1, 1}, {})); }, "objects['B'].box[1]: must be a positive");
  expect_error([&] { c.add_object(box_object("B", {1, NAN, 1}, {})); }, "box[1]: must be a positive finite");
  expect_error([&] { c.add_object(box_object("B", {1, 1, 1}, {}, {}, "Nowhere")); }, "parent: no node or link named 'Nowhere'");
  expect_error([&] { c.add_object(box_object("B", {1, 1, 1}, {}, {}, "Rock")); }, "is a world object");
  expect_error([&] { c.add_object(box_object("B", {1, 1, 1}, {INFINITY, 0, 0})); }, "pose.xyz: not a finite number");
  plancheck::Object m;
  m.name = "M";
  m.shape = plancheck::Object::Shape::kMesh;
  m.mesh = (t.path / "missing.stl").string();
  expect_error([&] { c.add_object(m); }, "objects['M'].mesh: cannot open");
  expect_error([&] { c.move_object("Nothing", {}); }, "no object named 'Nothing'");
  expect_error([&] { c.remove_object("Slab"); }, "no object named 'Slab'");
  EXPECT_EQ(c.object_names(), std::vector<std::string>{"Rock"});
  expect_same(before, c.check({0.0}), "after the errors");
  // An object of the scene file may be removed (and added again).
  c.remove_object("Rock");
  EXPECT_TRUE(c.object_names().empty());
  c.add_object(box_object("Rock", {0.2, 0.2, 0.2}, {1.5, 0, 0.5}));
  expect_same(before, c.check({0.0}), "added again");
}

// Concurrency rule: a batch sees the world before a change or after it,
// never a mix. One thread moves an object back and forth while another runs
// batches; every batch equals one of the two worlds' answers entirely.
TEST(Api, ConcurrentObjectMovesNeverShowHalfAChange) {
  TempDir t;
  write_bar_scene(t.path, 1.0, "m");
  plancheck::Checker c(plancheck::Scene::load((t.path / "scene.json").string()), 2);
  const plancheck::Pose near{{1, 0, 1.3}, {}}, far{{1, 0, 3}, {}};
  c.add_object(box_object("Cube", {0.2, 0.2, 0.2}, near.xyz));
  std::vector<std::vector<double>> states;
  for (int i = 0; i < 200; ++i) states.push_back({-60.0 + 0.4 * i});
  const auto at_near = c.check_batch(states);
  c.move_object("Cube", far);
  const auto at_far = c.check_batch(states);
  auto same = [&](const std::vector<plancheck::StateResult>& a, const std::vector<plancheck::StateResult>& b) {
    for (std::size_t i = 0; i < a.size(); ++i)
      if (a[i].min_distance != b[i].min_distance || a[i].part_b != b[i].part_b || a[i].collision != b[i].collision)
        return false;
    return true;
  };
  ASSERT_FALSE(same(at_near, at_far));
  // The mover keeps moving until the batches are done, so they overlap; it
  // ends on `far`.
  std::atomic<bool> stop{false};
  std::atomic<int> moves{0};
  std::thread mover([&] {
    for (int k = 0; !stop || k % 2 == 1; ++k) {
      c.move_object("Cube", k % 2 ? far : near);
      ++moves;
    }
  });
  int mixed = 0, seen_near = 0, seen_far = 0;
  for (int b = 0; b < 100; ++b) {
    const auto r = c.check_batch(states);
    const bool n = same(r, at_near), f = same(r, at_far);
    mixed += !(n || f);
    seen_near += n;
    seen_far += f;
  }
  stop = true;
  mover.join();
  EXPECT_EQ(mixed, 0) << seen_near << " batches saw near, " << seen_far << " far, " << moves << " moves";
  EXPECT_TRUE(same(c.check_batch(states), at_far));  // the last move (k = 29) was to `far`
}
