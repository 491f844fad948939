// SPDX-License-Identifier: MIT
#include "support/fixtures.h"

#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>

namespace plancheck::testing {

TempDir::TempDir(const std::string& tag) {
  std::random_device rd;
  for (int i = 0; i < 100; ++i) {
    path_ = std::filesystem::temp_directory_path() / ("plancheck-" + tag + "-" + std::to_string(rd()));
    if (std::filesystem::create_directory(path_)) return;
  }
  throw std::runtime_error("cannot create a temporary folder");
}

TempDir::~TempDir() {
  std::error_code ec;
  std::filesystem::remove_all(path_, ec);
}

std::filesystem::path TempDir::write(const std::string& name, const std::string& text) const {
  const std::filesystem::path file = path_ / name;
  write_text(file, text);
  return file;
}

void write_text(const std::filesystem::path& file, const std::string& text) {
  std::filesystem::create_directories(file.parent_path());
  std::ofstream f(file, std::ios::binary);
  f << text;
  if (!f) throw std::runtime_error("cannot write " + file.string());
}

std::string read_text(const std::filesystem::path& file) {
  std::ifstream f(file, std::ios::binary);
  if (!f) throw std::runtime_error("cannot read " + file.string());
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

Mesh box_mesh(const Vec3& lo, const Vec3& hi) {
  Mesh m;
  for (int i = 0; i < 8; ++i)
    m.vertices.emplace_back(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(), i & 4 ? hi.z() : lo.z());
  // Two triangles per face, counter-clockwise seen from outside.
  const std::uint32_t f[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : f) {
    m.triangles.push_back({q[0], q[1], q[2]});
    m.triangles.push_back({q[0], q[2], q[3]});
  }
  return m;
}

void write_obj(const std::filesystem::path& file, const std::vector<std::pair<std::string, Mesh>>& parts) {
  std::string s;
  char buf[128];
  std::size_t base = 1;
  for (const auto& [name, mesh] : parts) {
    s += "o " + name + "\n";
    for (const Vec3& v : mesh.vertices) {
      std::snprintf(buf, sizeof buf, "v %.17g %.17g %.17g\n", v.x(), v.y(), v.z());
      s += buf;
    }
    for (const Tri& t : mesh.triangles) {
      std::snprintf(buf, sizeof buf, "f %zu %zu %zu\n", t[0] + base, t[1] + base, t[2] + base);
      s += buf;
    }
    base += mesh.vertices.size();
  }
  write_text(file, s);
}

int run_command(const std::string& command) {
  const int status = std::system(command.c_str());
  if (status == -1) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

std::vector<double> random_state(const Scene& scene, std::mt19937_64& rng, double widen) {
  std::vector<double> p = scene.reference_parameters;
  for (const Action& a : scene.actions) {
    const double lo = a.has_limits ? a.lower : -180.0, hi = a.has_limits ? a.upper : 180.0;
    for (int k = 0; k < a.parameter_count; ++k) {
      const double u = static_cast<double>(rng() >> 11) * 0x1.0p-53;
      p[static_cast<std::size_t>(a.first_parameter + k)] = lo - widen * (hi - lo) + u * (1 + 2 * widen) * (hi - lo);
    }
  }
  return p;
}

}  // namespace plancheck::testing
