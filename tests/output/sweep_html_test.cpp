// SPDX-License-Identifier: MIT
// sweep.html's grid (src/output/sweep_html.h): a grid finer than the page
// holds is pooled into blocks, each showing its most severe verdict, against
// a brute-force walk over every block.
#include "src/output/sweep_html.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

namespace plancheck {
namespace {

std::vector<SweepAxis> grid_axes(const std::vector<std::size_t>& sizes) {
  std::vector<SweepAxis> axes;
  for (std::size_t k = 0; k < sizes.size(); ++k) {
    SweepAxis a;
    a.parameter = static_cast<int>(k);
    for (std::size_t v = 0; v < sizes[k]; ++v) a.values.push_back(static_cast<double>(v));
    axes.push_back(a);
  }
  return axes;
}

TEST(SweepPage, KeepsEveryConfigurationWhenTheGridFits) {
  const auto axes = grid_axes({4, 5});
  std::vector<std::uint8_t> codes(20);
  for (std::size_t i = 0; i < codes.size(); ++i) codes[i] = static_cast<std::uint8_t>(i % 4);
  const SweepPageGrid g = pool_sweep_verdicts(axes, codes, 20);
  EXPECT_EQ(g.stride, (std::vector<std::size_t>{1, 1}));
  EXPECT_EQ(g.count, (std::vector<std::size_t>{4, 5}));
  EXPECT_EQ(g.codes, codes);
}

TEST(SweepPage, PoolsAFineGridIntoItsMostSevereVerdicts) {
  const std::vector<std::size_t> sizes = {13, 7, 10};
  const auto axes = grid_axes(sizes);
  std::mt19937 rng(7);
  std::vector<std::uint8_t> codes(13 * 7 * 10);
  // Mostly safe, with rare violations: a block with one must not show safe.
  for (auto& c : codes) c = rng() % 20 == 0 ? static_cast<std::uint8_t>(1 + rng() % 3) : 0;
  for (std::size_t max_cells : {1u, 50u, 200u, 909u}) {
    const SweepPageGrid g = pool_sweep_verdicts(axes, codes, max_cells);
    std::size_t cells = 1;
    for (std::size_t k = 0; k < 3; ++k) {
      EXPECT_EQ(g.count[k], (sizes[k] + g.stride[k] - 1) / g.stride[k]);
      cells *= g.count[k];
    }
    EXPECT_LE(cells, max_cells);
    ASSERT_EQ(g.codes.size(), cells);
    const int severity[4] = {0, 1, 3, 2};
    for (std::size_t a = 0; a < g.count[0]; ++a)
      for (std::size_t b = 0; b < g.count[1]; ++b)
        for (std::size_t c = 0; c < g.count[2]; ++c) {
          std::uint8_t worst = 0;
          for (std::size_t x = a * g.stride[0]; x < std::min(sizes[0], (a + 1) * g.stride[0]); ++x)
            for (std::size_t y = b * g.stride[1]; y < std::min(sizes[1], (b + 1) * g.stride[1]); ++y)
              for (std::size_t z = c * g.stride[2]; z < std::min(sizes[2], (c + 1) * g.stride[2]); ++z) {
                const std::uint8_t v = codes[(x * sizes[1] + y) * sizes[2] + z];
                if (severity[v] > severity[worst]) worst = v;
              }
          ASSERT_EQ(g.codes[(a * g.count[1] + b) * g.count[2] + c], worst) << max_cells;
        }
  }
}

// However many targets are pushed, at most 2 * limit are held, and they
// are exactly every stride-th one.
TEST(SweepPage, SamplesSafeTargetsWithBoundedMemory) {
  for (std::size_t pushed : {0u, 5u, 19u, 20u, 21u, 1000u, 4097u}) {
    SafeTargetSample sample(10);
    for (std::size_t i = 0; i < pushed; ++i) sample.push(Vec3(static_cast<double>(i), 0, 0));
    EXPECT_LT(sample.kept().size(), 20u);
    ASSERT_EQ(sample.kept().size(), pushed == 0 ? 0 : (pushed - 1) / sample.stride() + 1) << pushed;
    for (std::size_t k = 0; k < sample.kept().size(); ++k)
      EXPECT_EQ(sample.kept()[k].x(), static_cast<double>(k * sample.stride()));
    if (pushed >= 20) {
      EXPECT_GE(sample.kept().size(), 10u);
    }
  }
}

}  // namespace
}  // namespace plancheck
