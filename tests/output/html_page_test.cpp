// SPDX-License-Identifier: MIT
// The page writer (src/output/html_page.h, report_html.h): base64, the data
// kept intact inside <script>, and report.html's data against the results
// it was written from (report.json, the transforms, distances, contacts).
#include "src/output/html_page.h"
#include "src/output/report_html.h"

#include "src/scene/kinematics.h"
#include "src/scene/plan.h"
#include "src/output/report.h"
#include "src/base/error.h"
#include "src/scene/scene_loader.h"
#include "src/checks/verify.h"
#include "support/bar_scene.h"
#include "support/fixtures.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <cstring>
#include <string>
#include <vector>

namespace plancheck {
namespace {

// RFC 4648 section 10 test vectors, and a slow bit-by-bit decoder as the reference.
TEST(Base64, MatchesTheRfcVectors) {
  const std::pair<std::string, std::string> cases[] = {{"", ""},         {"f", "Zg=="},         {"fo", "Zm8="},
                                                       {"foo", "Zm9v"},  {"foob", "Zm9vYg=="}, {"fooba", "Zm9vYmE="},
                                                       {"foobar", "Zm9vYmFy"}};
  for (const auto& [in, out] : cases) EXPECT_EQ(base64(in.data(), in.size()), out) << in;
}

std::vector<unsigned char> decode_base64(const std::string& s) {
  const std::string digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::vector<int> bits;
  for (char c : s) {
    if (c == '=') break;
    const auto v = digits.find(c);
    EXPECT_NE(v, std::string::npos);
    for (int b = 5; b >= 0; --b) bits.push_back((static_cast<int>(v) >> b) & 1);
  }
  std::vector<unsigned char> out;
  for (std::size_t i = 0; i + 8 <= bits.size(); i += 8) {
    int byte = 0;
    for (int b = 0; b < 8; ++b) byte = byte * 2 + bits[i + b];
    out.push_back(static_cast<unsigned char>(byte));
  }
  return out;
}

TEST(Base64, RoundTripsEveryByteValueAndLength) {
  std::vector<unsigned char> data(259);
  for (std::size_t i = 0; i < data.size(); ++i) data[i] = static_cast<unsigned char>(i * 7 + 3);
  for (std::size_t n = 0; n <= data.size(); n += 1)
    ASSERT_EQ(decode_base64(base64(data.data(), n)), std::vector<unsigned char>(data.begin(), data.begin() + n)) << n;
}

template <class T>
std::vector<T> decode_array(const std::string& b64) {
  const auto bytes = decode_base64(b64);
  std::vector<T> out(bytes.size() / sizeof(T));
  std::memcpy(out.data(), bytes.data(), out.size() * sizeof(T));
  return out;
}

// quantized_json and ints_json (src/output/scene_page.h), decoded.
std::vector<double> dequantize(const nlohmann::json& j) {
  const auto q = decode_array<std::uint16_t>(j["q"]);
  const auto lo = j["lo"].get<std::vector<double>>(), step = j["step"].get<std::vector<double>>();
  std::vector<double> out;
  for (std::size_t i = 0; i < q.size(); ++i)
    out.push_back(q[i] == 65535 ? std::nan("") : lo[i % lo.size()] + q[i] * step[i % lo.size()]);
  return out;
}

std::vector<std::int32_t> decode_ints(const nlohmann::json& j) {
  if (j.contains("i16")) {
    const auto v = decode_array<std::int16_t>(j["i16"]);
    return {v.begin(), v.end()};
  }
  return decode_array<std::int32_t>(j["i32"]);
}

TEST(HtmlPage, KeepsDataThatLooksLikeTheEndOfTheScript) {
  testing::TempDir dir("html_page");
  const std::string json = R"({"name": "</script><script>alert(1)</script>", "x": "a</b"})";
  write_html_page(dir / "p.html", "t <&>", json);
  const std::string page = testing::read_text(dir / "p.html");
  // The data cannot close its element: the only "</script" are the page's own two.
  std::size_t closes = 0;
  for (auto at = page.find("</script"); at != std::string::npos; at = page.find("</script", at + 1)) ++closes;
  EXPECT_EQ(closes, 2u);
  EXPECT_EQ(nlohmann::json::parse(html_page_data(page)), nlohmann::json::parse(json));
  EXPECT_NE(page.find("<title>t &lt;&amp;&gt;</title>"), std::string::npos);
  // Nothing loaded from elsewhere (the browser tests also refuse any request).
  EXPECT_EQ(page.find("<script src"), std::string::npos);
  EXPECT_EQ(page.find("<link"), std::string::npos);
  // No file left half written.
  EXPECT_FALSE(std::filesystem::exists(dir / "p.html.tmp"));
}

// Issue 31: a name holding "<!--<script>" kept the HTML parser from ever
// closing the data element (the viewer never ran). Whatever the strings
// hold, the data between its tags has no '<' at all (so no "</script", no
// "<!--"), no raw U+2028/U+2029, and parses back to the same values.
TEST(HtmlPage, DataIsInertWhateverTheNamesHold) {
  testing::TempDir dir("html_page_inert");
  const nlohmann::json data = {
      {"plans", {{{"name", "<!--<script>"}}, {{"name", "x</script><img src=x onerror=alert(1)>"}},
                 {{"name", "<!-- </SCRIPT --> <script>"}}, {{"name", "line\u2028sep\u2029para \"q\" \\ <b>"}}}}};
  // Streamed in pieces too: the escaping does not depend on where a piece ends.
  {
    HtmlPageWriter page(dir / "p.html", "<!--<script>");
    const std::string text = data.dump();
    const std::size_t cut = text.find("<!--") + 2;
    page.data(text.substr(0, cut));
    page.data(text.substr(cut));
    page.finish();
  }
  const std::string page = testing::read_text(dir / "p.html");
  const std::string open = "<script type=\"application/json\" id=\"plancheck-data\">";
  const std::size_t from = page.find(open) + open.size();
  const std::size_t to = page.find("</script>", from);
  ASSERT_NE(to, std::string::npos);
  const std::string inside = page.substr(from, to - from);
  EXPECT_EQ(inside.find('<'), std::string::npos) << inside;
  EXPECT_EQ(inside.find("\xE2\x80\xA8"), std::string::npos);
  EXPECT_EQ(inside.find("\xE2\x80\xA9"), std::string::npos);
  EXPECT_EQ(nlohmann::json::parse(inside), data);
  EXPECT_EQ(nlohmann::json::parse(html_page_data(page)), data);
  // The viewer follows the data, and the title holds the name as text.
  EXPECT_NE(page.find("<script>", to), std::string::npos);
  EXPECT_NE(page.find("<title>&lt;!--&lt;script&gt;</title>"), std::string::npos);
}

// --html-plans: a count or names; the violating plans always carry detail.
TEST(ReportPage, ParsesHtmlPlans) {
  EXPECT_EQ(parse_html_plans("0").closest, 0u);
  EXPECT_EQ(parse_html_plans("250").closest, 250u);
  EXPECT_TRUE(parse_html_plans("250").names.empty());
  const HtmlPlanChoice named = parse_html_plans("plan07,plan 2");
  EXPECT_EQ(named.names, (std::vector<std::string>{"plan07", "plan 2"}));
  EXPECT_EQ(named.closest, 0u);
  EXPECT_THROW(parse_html_plans(""), InputError);
  EXPECT_THROW(parse_html_plans("a,,b"), InputError);
  EXPECT_THROW(parse_html_plans("a,"), InputError);
  EXPECT_THROW(parse_html_plans("99999999999999999999"), InputError);
  std::vector<Plan> plans(2);
  plans[0].name = "a";
  plans[1].name = "b";
  EXPECT_NO_THROW(check_html_plans(parse_html_plans("b"), plans));
  EXPECT_THROW(check_html_plans(parse_html_plans("a,c"), plans), InputError);
}

TEST(ReportPage, DetailGoesToViolatingClosestAndNamedPlans) {
  const double inf = std::numeric_limits<double>::infinity();
  const std::vector<std::pair<Verdict, double>> cases = {
      {Verdict::kSafe, 0.5}, {Verdict::kCollision, 0.0}, {Verdict::kSafe, 0.2}, {Verdict::kSafe, inf},
      {Verdict::kClearance, 0.01}, {Verdict::kSafe, 0.2}, {Verdict::kLimits, 1.0}, {Verdict::kSafe, 0.3}};
  std::vector<Plan> plans(cases.size());
  std::vector<PlanResult> results(cases.size());
  for (std::size_t k = 0; k < cases.size(); ++k) {
    plans[k].name = "p" + std::to_string(k);
    results[k].plan = &plans[k];
    results[k].verdict = cases[k].first;
    results[k].min_distance = cases[k].second;
  }
  const auto chosen = [&](const HtmlPlanChoice& c) {
    std::vector<int> out;
    const std::vector<bool> d = html_detail_plans(results, c);
    for (std::size_t k = 0; k < d.size(); ++k)
      if (d[k]) out.push_back(static_cast<int>(k));
    return out;
  };
  EXPECT_EQ(chosen(parse_html_plans("0")), (std::vector<int>{1, 4, 6}));
  // The two closest safe plans: 0.2 twice (plan order on ties).
  EXPECT_EQ(chosen(parse_html_plans("2")), (std::vector<int>{1, 2, 4, 5, 6}));
  EXPECT_EQ(chosen(parse_html_plans("3")), (std::vector<int>{1, 2, 4, 5, 6, 7}));
  EXPECT_EQ(chosen(parse_html_plans("100")), (std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7}));
  EXPECT_EQ(chosen(parse_html_plans("p3,p0")), (std::vector<int>{0, 1, 3, 4, 6}));
}

TEST(HtmlPage, EmbedsTheViewerBundle) {
  const std::string_view bundle = viewer_bundle();
  EXPECT_GT(bundle.size(), 50u);
  if (viewer_bundle_is_real()) {
    EXPECT_GT(bundle.size(), 100'000u);  // three.js and uPlot are inside
    EXPECT_NE(bundle.find("plancheck-data"), std::string_view::npos);
  }
}

// report.html of the bar scene: a plan that ends in contact (detail) and a
// safe one (no detail with --html-plans 0).
TEST(ReportPage, DataMatchesTheResultsItWasWrittenFrom) {
  testing::TempDir dir("report_page");
  testing::write_bar_scene(dir);
  std::string tilt = "# name: tilt\nJ1\n", calm = "# name: calm\nJ1\n";
  for (int a = 0; a <= 30; a += 3) tilt += std::to_string(a) + "\n";
  for (int a = -30; a <= 0; a += 5) calm += std::to_string(a) + ".25\n";
  testing::write_text(dir / "tilt.csv", tilt);
  testing::write_text(dir / "calm.csv", calm);
  const Scene scene = load_scene(dir / "scene.json");
  const std::vector<Plan> plans = {load_plan(scene, dir / "tilt.csv"), load_plan(scene, dir / "calm.csv")};
  const Checker checker(scene, 1);
  const auto results = verify_plans(checker, scene, plans, VerifyOptions{1});
  ASSERT_NE(results[0].verdict, Verdict::kSafe);
  ASSERT_EQ(results[1].verdict, Verdict::kSafe);
  RunInfo info;
  info.scene_arg = dir / "scene.json";
  write_reports(checker, scene, results, info, dir / "out");
  ReportPageOptions options;
  options.plans = parse_html_plans("0");
  write_report_html(checker, scene, results, dir / "out", options);
  for (const auto& e : std::filesystem::directory_iterator(dir / "out"))
    EXPECT_NE(e.path().extension(), ".tmp") << e.path();  // the streamed page's temporary is gone

  const auto page = nlohmann::json::parse(html_page_data(testing::read_text(dir / "out/report.html")));
  const auto report = nlohmann::json::parse(testing::read_text(dir / "out/report.json"));
  EXPECT_EQ(page["report"], report);  // the plan list, verdicts and distances are report.json's
  EXPECT_EQ(page["kind"], "report");
  ASSERT_EQ(page["parts"].size(), scene.parts.size());
  ASSERT_EQ(page["plans"].size(), 2u);
  const Vec3 centre(page["centre"][0].get<double>(), page["centre"][1].get<double>(), page["centre"][2].get<double>());
  ASSERT_EQ(page["actions"].size(), scene.actions.size());
  EXPECT_EQ(page["actions"][0]["type"], "rotate");
  EXPECT_EQ(page["actions"][0]["whole_turn"].get<double>(), scene.actions[0].whole_turn);

  // Geometry: each part's vertices and triangles, in page coordinates.
  for (std::size_t k = 0; k < scene.parts.size(); ++k) {
    const auto positions = decode_array<float>(page["parts"][k]["positions"]);
    // Few vertices: indices as uint16.
    const auto small = decode_array<std::uint16_t>(page["parts"][k]["indices16"]);
    const std::vector<std::uint32_t> indices(small.begin(), small.end());
    const Mesh& mesh = scene.parts[k].mesh;
    ASSERT_EQ(positions.size(), mesh.vertices.size() * 3);
    ASSERT_EQ(indices.size(), mesh.triangles.size() * 3);
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
      for (int i = 0; i < 3; ++i) EXPECT_NEAR(positions[v * 3 + i], mesh.vertices[v][i] - centre[i], 1e-6);
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
      for (int i = 0; i < 3; ++i) EXPECT_EQ(indices[t * 3 + i], mesh.triangles[t][i]);
  }

  for (std::size_t k = 0; k < plans.size(); ++k) {
    const auto& p = page["plans"][k];
    const std::size_t n = plans[k].states.size();
    EXPECT_EQ(p["name"], plans[k].name);
    EXPECT_EQ(p["detail"].get<bool>(), k == 0);  // the violating plan only
    // The parameters as the plan holds them (float32: small values).
    ASSERT_EQ(p["params_type"], "f32");
    const auto params = decode_array<float>(p["params"]);
    ASSERT_EQ(params.size(), n);
    for (std::size_t s = 0; s < n; ++s) EXPECT_EQ(params[s], static_cast<float>(plans[k].states[s][0]));
    // The checker's transforms where the page checks its own poses: a
    // part's vertex lands where part_transform puts it.
    const auto& cp = p["checker_poses"];
    const auto states = cp["states"].get<std::vector<std::size_t>>();
    ASSERT_FALSE(states.empty());
    EXPECT_NE(std::find(states.begin(), states.end(), results[k].min_distance_state), states.end());
    if (results[k].first_violation) {
      EXPECT_NE(std::find(states.begin(), states.end(), results[k].first_violation->state), states.end());
    }
    const auto chains = decode_array<float>(cp["transforms"]);
    ASSERT_EQ(chains.size(), states.size() * scene.chains.size() * 12);
    for (std::size_t j = 0; j < states.size(); ++j)
      for (std::size_t q = 0; q < scene.parts.size(); ++q) {
        const Part& part = scene.parts[q];
        if (part.chain_id < 0) continue;
        const float* m = &chains[(j * scene.chains.size() + static_cast<std::size_t>(part.chain_id)) * 12];
        const Affine t = part_transform(scene, static_cast<int>(q), plans[k].states[states[j]]);
        for (const Vec3& v : part.mesh.vertices) {
          const Vec3 y = v - centre;
          for (int i = 0; i < 3; ++i)
            ASSERT_NEAR(m[i * 4] * y[0] + m[i * 4 + 1] * y[1] + m[i * 4 + 2] * y[2] + m[i * 4 + 3], (t * v)[i] - centre[i], 1e-5);
        }
      }
    // Per state: distance and verdict, for every plan.
    const auto distance = decode_array<float>(p["distance"]);
    const auto verdict = decode_array<std::uint8_t>(p["verdict"]);
    ASSERT_EQ(distance.size(), n);
    ASSERT_EQ(verdict.size(), n);
    for (std::size_t s = 0; s < n; ++s) {
      const StateResult& st = results[k].states[s];
      EXPECT_EQ(verdict[s], static_cast<int>(state_verdict(st, scene.safety_margin)));
      if (st.part_a >= 0) EXPECT_EQ(distance[s], static_cast<float>(st.min_distance));
      else EXPECT_TRUE(std::isnan(distance[s]));
    }
    if (k == 1) {
      // No detail: no closest points, pairs or contacts carried.
      EXPECT_FALSE(p.contains("points"));
      EXPECT_FALSE(p.contains("pair"));
      EXPECT_FALSE(p.contains("contacts"));
      continue;
    }
    // Closest points to within half a quantization step (drawn, not judged).
    const auto points = dequantize(p["points"]);
    const auto pair = decode_ints(p["pair"]);
    const auto step = p["points"]["step"].get<std::vector<double>>();
    ASSERT_EQ(points.size(), n * 6);
    ASSERT_EQ(pair.size(), n * 2);
    for (std::size_t s = 0; s < n; ++s) {
      const StateResult& st = results[k].states[s];
      EXPECT_EQ(pair[s * 2], st.part_a);
      EXPECT_EQ(pair[s * 2 + 1], st.part_b);
      EXPECT_EQ(p["contacts"].contains(std::to_string(s)), st.collision);
      if (st.part_a >= 0)
        for (int i = 0; i < 3; ++i) {
          EXPECT_NEAR(points[s * 6 + i], st.point_a[i] - centre[i], step[i] * 0.51 + 1e-6);
          EXPECT_NEAR(points[s * 6 + 3 + i], st.point_b[i] - centre[i], step[i] * 0.51 + 1e-6);
        }
      else
        EXPECT_TRUE(std::isnan(points[s * 6]));
    }
    // The bar ends in the slab (after passing below the margin): a colliding
    // state lists its triangle pairs, as report.json does.
    ASSERT_TRUE(results[k].states.back().collision);
    ASSERT_FALSE(report["plans"][k]["collisions"].empty());
    const std::size_t first = report["plans"][k]["collisions"][0]["state"];
    const auto& contact = p["contacts"][std::to_string(first)];
    ASSERT_FALSE(contact.empty());
    EXPECT_EQ(contact[0]["triangles"], report["plans"][k]["collisions"][0]["pairs"][0]["triangles"]);
  }
}

// Parameters beyond float32's exact pose range travel as float64, bit for bit.
TEST(ReportPage, LargeParametersTravelAsFloat64) {
  testing::TempDir dir("report_page_f64");
  testing::write_bar_scene(dir);
  testing::write_text(dir / "turns.csv", "# name: turns\nJ1\n3600.123456789\n-7200.5\n");
  const Scene scene = load_scene(dir / "scene.json");
  const std::vector<Plan> plans = {load_plan(scene, dir / "turns.csv")};
  const Checker checker(scene, 1);
  const auto results = verify_plans(checker, scene, plans, VerifyOptions{1});
  RunInfo info;
  info.scene_arg = dir / "scene.json";
  write_reports(checker, scene, results, info, dir / "out");
  write_report_html(checker, scene, results, dir / "out");
  const auto page = nlohmann::json::parse(html_page_data(testing::read_text(dir / "out/report.html")));
  ASSERT_EQ(page["plans"][0]["params_type"], "f64");
  EXPECT_EQ(decode_array<double>(page["plans"][0]["params"]), (std::vector<double>{3600.123456789, -7200.5}));
}

}  // namespace
}  // namespace plancheck
