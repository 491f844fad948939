// SPDX-License-Identifier: MIT
// plancheck_bench: `plancheck_bench table3 SCENE [PLAN...] [--json FILE] [--fcl]`
// reproduces the paper's Table 3 (or, with --random N, random cold states);
// `plancheck_bench two_mesh [--poses N]` times one small mesh at random
// poses over another beside FCL; anything else runs the Google Benchmark
// micro benchmarks (BM_<Component>_<Operation>, each checking its answer first).
#include "bench/table3.h"
#include "bench/two_mesh.h"

#include <benchmark/benchmark.h>

#include <cstring>

int main(int argc, char** argv) {
  if (argc >= 2 && std::strcmp(argv[1], "table3") == 0) return plancheck::bench::run_table3(argc - 1, argv + 1);
  if (argc >= 2 && std::strcmp(argv[1], "two_mesh") == 0) return plancheck::bench::run_two_mesh(argc - 1, argv + 1);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 2;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
