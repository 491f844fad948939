// SPDX-License-Identifier: MIT
// The sweep's block stage (src/cli/sweep_stage.h): blocks gathered into
// ranges land in verdict.npy and distance.npy exactly where writing each
// block's rows on their own puts them, at every grouping depth.
#include "src/cli/sweep_stage.h"
#include "src/output/npy.h"
#include "tests/support/fixtures.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

namespace plancheck {
namespace {

// Element `index`'s code and distance: distinct enough that a misplaced run shows.
std::uint8_t code_of(std::size_t index) { return static_cast<std::uint8_t>(1 + index % 251); }
float dist_of(std::size_t index) { return static_cast<float>(index) + 0.5f; }

std::string file_bytes(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// Every block of `shape`, in item order, through a stage of `max_elements`;
// checks both files element by element. Returns the stage's leading axes.
std::size_t stage_round_trip(const std::vector<std::size_t>& shape, std::size_t max_elements) {
  testing::TempDir dir("sweep-stage");
  const SweepBlocks blocks(shape);
  const std::vector<std::uint64_t> npy_shape(shape.begin(), shape.end());
  NpyWriter verdict(dir / "verdict.npy", NpyType::kUint8, npy_shape);
  NpyWriter distance(dir / "distance.npy", NpyType::kFloat32, npy_shape);
  BlockStage stage(blocks, max_elements);
  std::vector<std::size_t> first, size, digit;
  std::vector<std::uint8_t> codes;
  std::vector<float> dist;
  for (std::size_t b = 0; b < blocks.blocks; ++b) {
    blocks.block(b, first, size);
    std::size_t n = 1;
    for (std::size_t s : size) n *= s;
    codes.clear();
    dist.clear();
    digit.assign(shape.size(), 0);
    for (std::size_t i = 0; i < n; ++i) {
      std::size_t index = 0;
      for (std::size_t k = 0; k < shape.size(); ++k) index = index * shape[k] + first[k] + digit[k];
      codes.push_back(code_of(index));
      dist.push_back(dist_of(index));
      for (std::size_t k = shape.size(); k-- > 0;) {
        if (++digit[k] < size[k]) break;
        digit[k] = 0;
      }
    }
    stage.put(b, codes.data(), dist.data(), n, verdict, distance);
  }
  verdict.finish();
  distance.finish();
  std::size_t total = 1;
  for (std::size_t s : shape) total *= s;
  const std::string v = file_bytes(dir / "verdict.npy");
  const std::string d = file_bytes(dir / "distance.npy");
  const std::size_t hv = npy_header(NpyType::kUint8, npy_shape).size();
  const std::size_t hd = npy_header(NpyType::kFloat32, npy_shape).size();
  EXPECT_EQ(v.size(), hv + total);
  EXPECT_EQ(d.size(), hd + 4 * total);
  std::size_t wrong = 0;
  for (std::size_t i = 0; i < total && v.size() == hv + total && d.size() == hd + 4 * total; ++i) {
    float f;
    std::memcpy(&f, d.data() + hd + 4 * i, 4);
    wrong += static_cast<std::uint8_t>(v[hv + i]) != code_of(i) || f != dist_of(i);
  }
  EXPECT_EQ(wrong, 0u) << "max_elements " << max_elements;
  return stage.leading_axes();
}

TEST(SweepStage, EveryGroupingWritesEveryElementInPlace) {
  // 4 axes, blocks of 16 (3 x 2 x 2 x 3 of them, the far ones short): a
  // group of one leading axis spans 16 x 20 x 18 x 33 = 190,080 elements,
  // of two 152,064, of three 135,168.
  const std::vector<std::size_t> shape{35, 20, 18, 33};
  EXPECT_EQ(stage_round_trip(shape, std::size_t{1} << 22), 1u);
  EXPECT_EQ(stage_round_trip(shape, 160000), 2u);
  EXPECT_EQ(stage_round_trip(shape, 140000), 3u);
  EXPECT_EQ(stage_round_trip(shape, 1), 4u);  // one block a group: its runs one by one
  // Two axes (blocks of 256), one axis (blocks of 65,536), and none.
  EXPECT_EQ(stage_round_trip({600, 300}, std::size_t{1} << 22), 1u);
  EXPECT_EQ(stage_round_trip({600, 300}, 1000), 2u);
  EXPECT_EQ(stage_round_trip({200000}, std::size_t{1} << 22), 1u);
  EXPECT_EQ(stage_round_trip({}, std::size_t{1} << 22), 0u);
}

TEST(SweepStage, BlocksOutOfOrderAreRefused) {
  testing::TempDir dir("sweep-stage");
  const SweepBlocks blocks({40, 40});
  NpyWriter verdict(dir / "verdict.npy", NpyType::kUint8, {40, 40});
  NpyWriter distance(dir / "distance.npy", NpyType::kFloat32, {40, 40});
  BlockStage stage(blocks);
  const std::vector<std::uint8_t> codes(1600, 1);
  const std::vector<float> dist(1600, 1.0f);
  EXPECT_THROW(stage.put(1, codes.data(), dist.data(), 1600, verdict, distance), std::logic_error);
  EXPECT_THROW(stage.put(0, codes.data(), dist.data(), 10, verdict, distance), std::logic_error);
}

}  // namespace
}  // namespace plancheck
