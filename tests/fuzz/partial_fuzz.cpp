// SPDX-License-Identifier: MIT
// Partial results and journals (plancheck-partial/1, src/cli/distribute.h)
// as `plancheck merge` and `--resume` read them: the input is the file. A
// file is refused with InputError or read whole; a journal under --resume is
// reused where valid and the rest recomputed, every item consumed once, in
// order. Lengths, counts and shard numbers in the file are claims: memory
// stays bounded by the file (libFuzzer's -rss_limit_mb catches a blow-up).
#include "src/base/error.h"
#include "src/cli/distribute.h"
#include "tests/fuzz/support.h"

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

using namespace plancheck;

namespace {

// The seeds (corpus/partial/) are toy runs of 5 items: command "toy",
// fingerprint "f00d", setup "{}", item k's blob "item k".
constexpr std::size_t kItems = 5;

std::vector<std::string> compute(std::size_t b, std::size_t e) {
  std::vector<std::string> out;
  for (std::size_t k = b; k < e; ++k) out.push_back("item " + std::to_string(k));
  return out;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  const std::filesystem::path merge_dir = fuzz::scratch() / "merge", run_dir = fuzz::scratch() / "run";
  std::filesystem::remove_all(merge_dir);
  std::filesystem::remove_all(run_dir);
  std::filesystem::create_directories(merge_dir);
  std::filesystem::create_directories(run_dir);

  // merge: the file as shard 0 of 1.
  fuzz::write_file(partial_path(merge_dir, Shard{0, 1}), bytes);
  try {
    const PartialSet set = open_partials({merge_dir});
    std::size_t next = 0;
    read_partials(set, [&](std::size_t item, std::string_view) {
      fuzz::require(item == next++, "merge consumes items in order, once each");
    });
    fuzz::require(next == set.first().items, "merge consumes every item");
  } catch (const InputError&) {
  }

  // --resume: the file as the journal of a single run.
  fuzz::write_file(journal_path(run_dir), bytes);
  DistOptions o;
  o.command = "toy";
  o.fingerprint = "f00d";
  o.setup = "{}";
  o.out = run_dir;
  o.resume = true;
  o.chunk_weight = 2;
  const std::vector<std::uint64_t> weights(kItems, 1);
  try {
    std::size_t next = 0;
    run_items(o, weights, compute, [&](std::size_t item, std::string_view) {
      fuzz::require(item == next++, "resume consumes items in order, once each");
    });
    fuzz::require(next == kItems, "resume consumes every item");
  } catch (const InputError&) {
  }
  return 0;
}
