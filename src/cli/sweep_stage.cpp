// SPDX-License-Identifier: MIT
// Blocks gathered into ranges of the sweep's arrays (src/cli/sweep_stage.h).
#include "src/cli/sweep_stage.h"

#include "src/output/npy.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace plancheck {

BlockStage::BlockStage(const SweepBlocks& blocks, std::size_t max_elements)
    : blocks_(blocks), d_(blocks.shape.size()) {
  lead_ = d_;
  for (std::size_t l = 1; l < d_; ++l) {
    std::size_t span = 1;
    for (std::size_t k = 0; k < l; ++k) span *= blocks.edge[k];
    for (std::size_t k = l; k < d_ && span <= max_elements; ++k) span *= blocks.shape[k];
    if (span <= max_elements) {
      lead_ = l;
      break;
    }
  }
  for (std::size_t k = lead_; k < d_; ++k) group_ *= blocks.count[k];
}

void BlockStage::put(std::size_t b, const std::uint8_t* codes, const float* dist, std::size_t n, NpyWriter& verdict,
                     NpyWriter& distance) {
  if (b != next_) throw std::logic_error("BlockStage: block " + std::to_string(b) + " out of order");
  ++next_;
  blocks_.block(b, first_, size_);
  std::size_t cells = 1;
  for (std::size_t s : size_) cells *= s;
  if (n != cells) throw std::logic_error("BlockStage: block " + std::to_string(b) + " of a wrong size");
  if (b % group_ == 0) {
    // A new group: its span, local on the leading axes, the whole grid on the others.
    std::size_t span = 1;
    for (std::size_t k = 0; k < d_; ++k) span *= k < lead_ ? size_[k] : blocks_.shape[k];
    codes_.assign(span, 0);
    dist_.assign(span, 0.0f);
    group_first_ = first_;
    group_size_ = size_;
  }
  const std::size_t run = d_ > 0 ? size_[d_ - 1] : 1;
  digit_.assign(d_, 0);
  for (std::size_t i = 0; i < n; i += run) {
    std::size_t at = 0;
    for (std::size_t k = 0; k < d_; ++k)
      at = at * (k < lead_ ? size_[k] : blocks_.shape[k]) + (k < lead_ ? 0 : first_[k]) + digit_[k];
    std::copy_n(codes + i, run, codes_.data() + at);
    std::copy_n(dist + i, run, dist_.data() + at);
    for (std::size_t k = d_ - (d_ > 0 ? 1 : 0); k-- > 0;) {
      if (++digit_[k] < size_[k]) break;
      digit_[k] = 0;
    }
  }
  if (b % group_ == group_ - 1) write(verdict, distance);
}

// The group's span: one range per combination of the leading axes but the
// last of them, each size[lead - 1] times the rest of the grid.
void BlockStage::write(NpyWriter& verdict, NpyWriter& distance) {
  std::size_t range = 1;
  for (std::size_t k = lead_ > 0 ? lead_ - 1 : 0; k < d_; ++k) range *= k < lead_ ? group_size_[k] : blocks_.shape[k];
  std::vector<std::size_t> digit(lead_ > 0 ? lead_ - 1 : 0, 0);
  for (std::size_t at = 0; at < codes_.size(); at += range) {
    std::size_t index = 0;
    for (std::size_t k = 0; k < d_; ++k)
      index = index * blocks_.shape[k] + (k < lead_ ? group_first_[k] : 0) + (k + 1 < lead_ ? digit[k] : 0);
    verdict.write(index, codes_.data() + at, range);
    distance.write(index, dist_.data() + at, range);
    for (std::size_t k = digit.size(); k-- > 0;) {
      if (++digit[k] < group_size_[k]) break;
      digit[k] = 0;
    }
  }
}

}  // namespace plancheck
