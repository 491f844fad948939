// SPDX-License-Identifier: MIT
// The dataset suite reads one dataset generated per build by the CTest
// fixture `DatasetFixture.Generate` (tests/CMakeLists.txt), instead of each
// test process running the generator again: ctest starts one process per
// test, and under the sanitizers a generation takes a minute or more.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <string>

namespace plancheck::testing {

// Where the fixture wrote this build's dataset.
inline std::filesystem::path generated_dataset() {
  return std::filesystem::path(PLANCHECK_BINARY_DIR) / "test-dataset";
}

// Runs this build's generator into `out`; its exit status.
inline int run_generator(const std::filesystem::path& out) {
  const std::string cmd = std::string("\"") + PLANCHECK_BINARY_DIR + "/generate_change5\" \"" + out.string() + "\"";
  return std::system(cmd.c_str());
}

}  // namespace plancheck::testing
