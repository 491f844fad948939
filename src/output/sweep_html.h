// SPDX-License-Identifier: MIT
// DIR/sweep.html (sweep --html): the configuration grid's verdicts as a heat
// map over two chosen parameters, the arm at any configuration, the targets
// of the safe configurations over the terrain. Geometry once; the arm is
// posed in the page from one transform per action and swept value (each
// action depends on its own parameters only), composed along each chain.
#pragma once

#include "src/checks/sweep_grid.h"
#include "src/checks/verify.h"

#include <cstdint>
#include <filesystem>
#include <vector>

namespace plancheck {

// sweep.html's verdict codes (those of verdict.npy): 0 safe, 1 clearance, 2 collision, 3 limits.
std::uint8_t sweep_verdict_code(Verdict v);

// The verdict grid as sweep.html holds it: at most kMaxSweepPageCells
// cells. Along each axis every stride-th value begins a block of `stride`
// values; a cell holds the most severe verdict of its block (collision,
// then limits, then clearance, then safe): a cell is safe only when every
// configuration it covers is. Strides are 1 (every configuration) when
// the grid fits.
inline constexpr std::size_t kMaxSweepPageCells = 4'000'000;
struct SweepPageGrid {
  std::vector<std::size_t> stride;  // per axis: values per block
  std::vector<std::size_t> count;   // per axis: blocks (cells along it)
  std::vector<std::uint8_t> codes;  // per cell, grid order (the last axis fastest)
};
SweepPageGrid pool_sweep_verdicts(const std::vector<SweepAxis>& axes, const std::vector<std::uint8_t>& verdicts,
                                  std::size_t max_cells = kMaxSweepPageCells);

// The targets of safe configurations the page draws: every stride-th of
// those pushed (grid order), the stride doubled whenever 2 * limit are
// held, so memory stays bounded however many configurations are safe.
class SafeTargetSample {
 public:
  static constexpr std::size_t kLimit = 500'000;
  SafeTargetSample() : SafeTargetSample(kLimit) {}
  explicit SafeTargetSample(std::size_t limit) : limit_(limit) {}
  void push(const Vec3& target) {
    push_with([&] { return target; });
  }
  // The same, computing the target only when it is kept.
  template <class MakeTarget>
  void push_with(MakeTarget make) {
    if (seen_++ % stride_ != 0) return;
    kept_.push_back(make());
    if (kept_.size() >= 2 * limit_) {
      for (std::size_t i = 0; 2 * i < kept_.size(); ++i) kept_[i] = kept_[2 * i];
      kept_.resize((kept_.size() + 1) / 2);
      stride_ *= 2;
    }
  }
  const std::vector<Vec3>& kept() const { return kept_; }
  std::size_t stride() const { return stride_; }  // kept()[i] is the (i * stride())-th target pushed

 private:
  std::size_t limit_;
  std::size_t seen_ = 0;
  std::size_t stride_ = 1;
  std::vector<Vec3> kept_;
};

// Writes dir/sweep.html; dir/sweep.json must exist. verdicts: one code per
// configuration in grid order (the last axis fastest); safe_targets: the
// target points (m) of the safe configurations, sampled.
void write_sweep_html(const Checker& checker, const Scene& scene, const std::vector<SweepAxis>& axes,
                      const std::vector<std::uint8_t>& verdicts, const SafeTargetSample& safe_targets,
                      const std::filesystem::path& dir);

}  // namespace plancheck
