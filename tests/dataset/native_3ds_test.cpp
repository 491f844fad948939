// SPDX-License-Identifier: MIT
// The default scene's model (the generated change5.3ds, ~422k triangles, big
// objects split in pieces under dummy nodes) is read by the strict native
// 3ds reader, and its answer is assimp's, bit for bit.
#include "src/scene/tds_native.h"

#include "tests/dataset/generated.h"
#include "tests/support/same_model.h"

#include <gtest/gtest.h>

namespace plancheck {
namespace {

TEST(DatasetNative3ds, DefaultModelIsReadNativelyAsAssimpReadsIt) {
  const auto file = testing::generated_dataset() / "change5.3ds";
  ASSERT_TRUE(std::filesystem::exists(file));
  ASSERT_TRUE(read_3ds_strict(file)) << "the dataset's model is in the native reader's subset";
  testing::expect_same_model(testing::load_model_outcome(file, false, 1.0), testing::load_model_outcome(file, true, 1.0),
                             "change5.3ds");
}

}  // namespace
}  // namespace plancheck
