// SPDX-License-Identifier: MIT
// The sweep's certified blocks on their way into verdict.npy and
// distance.npy (src/output/npy.h). A block's rows along the last axis are
// runs of 16 elements in the files, and one positioned write a run cost
// about 1.7 us in the one thread that writes, the other cores idle: 12 s
// of the 2.5-degree grid of the default arm. Consecutive blocks (C order,
// src/checks/sweep_grid.h) that share their block indices on the leading
// axes cover whole ranges of the files, so they are gathered here and
// written a range at a time: the fewest leading axes whose group of
// blocks spans at most `max_elements` (a single block at worst, written
// run by run as before), so memory stays bounded whatever the grid.
#pragma once

#include "src/checks/sweep_grid.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace plancheck {

class NpyWriter;

class BlockStage {
 public:
  static constexpr std::size_t kMaxElements = std::size_t{1} << 22;  // 20 MB for both arrays

  explicit BlockStage(const SweepBlocks& blocks, std::size_t max_elements = kMaxElements);

  // Block b's n codes and distances (C order within the block). Blocks
  // come in item order (0, 1, 2, ...; std::logic_error otherwise); a
  // group is written once its last block is in.
  void put(std::size_t b, const std::uint8_t* codes, const float* dist, std::size_t n, NpyWriter& verdict,
           NpyWriter& distance);

  // How many leading axes a group shares (the grid's dimension: one block a group).
  std::size_t leading_axes() const { return lead_; }

 private:
  void write(NpyWriter& verdict, NpyWriter& distance);

  const SweepBlocks& blocks_;
  std::size_t d_, lead_ = 0, group_ = 1, next_ = 0;
  std::vector<std::size_t> first_, size_, digit_, group_first_, group_size_;
  std::vector<std::uint8_t> codes_;
  std::vector<float> dist_;
};

}  // namespace plancheck
