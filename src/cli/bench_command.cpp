// SPDX-License-Identifier: MIT
#include "src/cli/bench_command.h"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <ostream>

namespace plancheck {

int run_bench(const std::vector<std::string>& args, std::ostream& err) {
  namespace fs = std::filesystem;
  std::error_code ec;
  // /proc/self/exe, not argv[0]: the bench sits beside the real binary even
  // when plancheck was started through PATH or a symlink.
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  const fs::path bench = (ec ? fs::path(".") : self.parent_path()) / "plancheck_bench";
  if (!fs::exists(bench)) {
    err << "plancheck: bench: " << bench.string()
        << " not found; build it (cmake -DPLANCHECK_BUILD_BENCH=ON, needs FCL and Google Benchmark) and run\n"
           "  plancheck_bench table3 SCENE.json [PLAN.csv... | --random N [--seed S]] [--json FILE] [--fcl]\n"
           "  plancheck_bench two_mesh [--poses N] [--seed S] [--json FILE]\n";
    return 2;
  }
  // --two-mesh picks the two-mesh random-pose case; everything else is table3's.
  std::vector<std::string> rest = args;
  const auto two_mesh = std::find(rest.begin(), rest.end(), "--two-mesh");
  const bool is_two_mesh = two_mesh != rest.end();
  if (is_two_mesh) rest.erase(two_mesh);
  std::vector<std::string> words{bench.string(), is_two_mesh ? "two_mesh" : "table3"};
  words.insert(words.end(), rest.begin(), rest.end());
  std::vector<char*> argv;
  for (std::string& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  err.flush();
  ::execv(bench.c_str(), argv.data());
  err << "plancheck: bench: cannot run " << bench.string() << ": " << std::strerror(errno) << "\n";
  return 2;
}

}  // namespace plancheck
