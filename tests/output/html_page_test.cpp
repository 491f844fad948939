// SPDX-License-Identifier: MIT
// The page writer (src/output/html_page.h, report_html.h): base64, the data
// kept intact inside <script>, and report.html's data against the results
// it was written from (report.json, the transforms, distances, contacts).
#include "src/output/html_page.h"
#include "src/output/report_html.h"

#include "src/scene/kinematics.h"
#include "src/scene/plan.h"
#include "src/output/report.h"
#include "src/scene/scene_loader.h"
#include "src/checks/verify.h"
#include "support/bar_scene.h"
#include "support/fixtures.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
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

TEST(HtmlPage, EmbedsTheViewerBundle) {
  const std::string_view bundle = viewer_bundle();
  EXPECT_GT(bundle.size(), 50u);
  if (viewer_bundle_is_real()) {
    EXPECT_GT(bundle.size(), 100'000u);  // three.js and uPlot are inside
    EXPECT_NE(bundle.find("plancheck-data"), std::string_view::npos);
  }
}

// report.html of the bar scene: a plan that ends in contact.
TEST(ReportPage, DataMatchesTheResultsItWasWrittenFrom) {
  testing::TempDir dir("report_page");
  testing::write_bar_scene(dir);
  std::string plan = "# name: tilt\nJ1\n";
  for (int a = 0; a <= 30; a += 3) plan += std::to_string(a) + "\n";
  testing::write_text(dir / "tilt.csv", plan);
  const Scene scene = load_scene(dir / "scene.json");
  const std::vector<Plan> plans = {load_plan(scene, dir / "tilt.csv")};
  const Checker checker(scene, 1);
  const auto results = verify_plans(checker, scene, plans, VerifyOptions{1});
  RunInfo info;
  info.scene_arg = dir / "scene.json";
  write_reports(checker, scene, results, info, dir / "out");
  write_report_html(checker, scene, results, dir / "out");

  const auto page = nlohmann::json::parse(html_page_data(testing::read_text(dir / "out/report.html")));
  const auto report = nlohmann::json::parse(testing::read_text(dir / "out/report.json"));
  EXPECT_EQ(page["report"], report);  // the plan list, verdicts and distances are report.json's
  EXPECT_EQ(page["kind"], "report");
  ASSERT_EQ(page["parts"].size(), scene.parts.size());
  ASSERT_EQ(page["plans"].size(), 1u);
  const auto& p = page["plans"][0];
  const std::size_t n = plans[0].states.size();
  const Vec3 centre(page["centre"][0].get<double>(), page["centre"][1].get<double>(), page["centre"][2].get<double>());

  // Geometry: each part's vertices and triangles, in page coordinates.
  for (std::size_t k = 0; k < scene.parts.size(); ++k) {
    const auto positions = decode_array<float>(page["parts"][k]["positions"]);
    const auto indices = decode_array<std::uint32_t>(page["parts"][k]["indices"]);
    const Mesh& mesh = scene.parts[k].mesh;
    ASSERT_EQ(positions.size(), mesh.vertices.size() * 3);
    ASSERT_EQ(indices.size(), mesh.triangles.size() * 3);
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
      for (int i = 0; i < 3; ++i) EXPECT_NEAR(positions[v * 3 + i], mesh.vertices[v][i] - centre[i], 1e-6);
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
      for (int i = 0; i < 3; ++i) EXPECT_EQ(indices[t * 3 + i], mesh.triangles[t][i]);
  }

  // Per state: the chain transform poses a part's vertex where part_transform does.
  const auto chains = decode_array<float>(p["chains"]);
  ASSERT_EQ(chains.size(), n * scene.chains.size() * 12);
  const auto points = decode_array<float>(p["points"]);
  ASSERT_EQ(points.size(), n * 6);
  bool moved = false;
  for (std::size_t s = 0; s < n; ++s) {
    for (std::size_t k = 0; k < scene.parts.size(); ++k) {
      const Part& part = scene.parts[k];
      ASSERT_EQ(page["parts"][k]["chain"].get<int>(), part.chain_id);
      if (part.chain_id < 0) continue;
      const float* m = &chains[(s * scene.chains.size() + static_cast<std::size_t>(part.chain_id)) * 12];
      const Affine t = part_transform(scene, static_cast<int>(k), plans[0].states[s]);
      for (const Vec3& v : part.mesh.vertices) {
        const Vec3 y = v - centre;
        for (int i = 0; i < 3; ++i) {
          const double page_value = m[i * 4] * y[0] + m[i * 4 + 1] * y[1] + m[i * 4 + 2] * y[2] + m[i * 4 + 3];
          ASSERT_NEAR(page_value, (t * v)[i] - centre[i], 1e-5) << "state " << s;
        }
      }
      if (s > 0 && std::memcmp(m, &chains[static_cast<std::size_t>(part.chain_id) * 12], 12 * sizeof(float)) != 0)
        moved = true;
    }
    const StateResult& st = results[0].states[s];
    EXPECT_EQ(p["pair"][s][0].get<int>(), st.part_a);
    EXPECT_EQ(p["verdict"][s].get<int>(), static_cast<int>(state_verdict(st, scene.safety_margin)));
    EXPECT_EQ(p["contacts"].contains(std::to_string(s)), st.collision);
    if (st.part_a >= 0) {
      EXPECT_DOUBLE_EQ(p["distance"][s].get<double>(), st.min_distance);
      for (int i = 0; i < 3; ++i) {
        EXPECT_NEAR(points[s * 6 + i], st.point_a[i] - centre[i], 1e-6);
        EXPECT_NEAR(points[s * 6 + 3 + i], st.point_b[i] - centre[i], 1e-6);
      }
    }
    // The parameters as the plan holds them.
    EXPECT_EQ(p["params"][s].get<std::vector<double>>(), plans[0].states[s]);
  }
  EXPECT_TRUE(moved);
  // The bar ends in the slab (after passing below the margin): a colliding
  // state lists its triangle pairs, as report.json does.
  ASSERT_TRUE(results[0].states.back().collision);
  ASSERT_FALSE(report["plans"][0]["collisions"].empty());
  const std::size_t first = report["plans"][0]["collisions"][0]["state"];
  const auto& contact = p["contacts"][std::to_string(first)];
  ASSERT_FALSE(contact.empty());
  EXPECT_EQ(contact[0]["triangles"], report["plans"][0]["collisions"][0]["pairs"][0]["triangles"]);
}

}  // namespace
}  // namespace plancheck
