// SPDX-License-Identifier: MIT
// The work engine of src/cli/distribute.h on toy items (blobs that name
// their item), and the plan-result bytes of src/output/result_blob.h.
#include "src/cli/distribute.h"
#include "src/base/error.h"
#include "src/output/result_blob.h"

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <iterator>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include <unistd.h>

namespace plancheck {
namespace {

std::filesystem::path scratch(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("plancheck-distribute-" + name + "-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  return dir;
}

TEST(Distribute, ShardParsingNamesTheFlag) {
  EXPECT_EQ(parse_shard("2/5").index, 2u);
  EXPECT_EQ(parse_shard("2/5").count, 5u);
  for (const char* bad : {"5/5", "0/0", "x/2", "1", "-1/2", "1/", "/3", "1/3 "}) {
    try {
      parse_shard(bad);
      ADD_FAILURE() << bad << " was accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("--shard"), std::string::npos) << e.what();
    }
  }
}

TEST(Distribute, SplitIsContiguousAndBalanced) {
  std::vector<std::uint64_t> w;
  for (int i = 0; i < 1000; ++i) w.push_back(1 + static_cast<std::uint64_t>(i % 7) * 3);
  std::uint64_t total = 0;
  for (auto x : w) total += x;
  for (std::size_t parts : {1u, 2u, 3u, 7u, 64u}) {
    const auto b = split_by_weight(w, parts);
    ASSERT_EQ(b.size(), parts + 1);
    EXPECT_EQ(b.front(), 0u);
    EXPECT_EQ(b.back(), w.size());
    for (std::size_t k = 0; k < parts; ++k) {
      ASSERT_LE(b[k], b[k + 1]);
      std::uint64_t part = 0;
      for (std::size_t i = b[k]; i < b[k + 1]; ++i) part += w[i];
      // Within one item's weight (at most 19) of an even share.
      EXPECT_NEAR(static_cast<double>(part), static_cast<double>(total) / parts, 20.0) << parts << " parts, part " << k;
    }
  }
  EXPECT_EQ(split_by_weight(std::vector<std::uint64_t>{5}, 3), (std::vector<std::size_t>{0, 1, 1, 1}));
}

// Toy work: item i's blob is "item i" repeated i % 5 + 1 times (some empty-ish sizes).
std::string blob_of(std::size_t i) {
  std::string s;
  for (std::size_t k = 0; k <= i % 5; ++k) s += "item " + std::to_string(i) + ";";
  return s;
}

DistOptions toy_options(const std::filesystem::path& out) {
  DistOptions o;
  o.command = "toy";
  o.fingerprint = "f00d";
  o.setup = "{}";
  o.out = out;
  o.chunk_weight = 3;
  return o;
}

TEST(Distribute, ShardsMergeToTheItemsInOrder) {
  const auto dir = scratch("shards");
  const std::vector<std::uint64_t> w(23, 1);
  std::vector<std::filesystem::path> dirs;
  for (std::size_t i = 0; i < 4; ++i) {
    DistOptions o = toy_options(dir / std::to_string(i));
    o.shard = Shard{i, 4};
    const DistResult r = run_items(
        o, w,
        [](std::size_t b, std::size_t e) {
          std::vector<std::string> out;
          for (std::size_t k = b; k < e; ++k) out.push_back(blob_of(k));
          return out;
        },
        [](std::size_t, std::string_view) { ADD_FAILURE() << "a shard consumed"; });
    EXPECT_EQ(r.role, DistRole::kShard);
    EXPECT_TRUE(std::filesystem::exists(partial_path(o.out, *o.shard)));
    dirs.push_back(o.out);
  }
  const PartialSet set = open_partials({dirs[3], dirs[1], dirs[0], dirs[2]});
  EXPECT_EQ(set.first().command, "toy");
  std::size_t next = 0;
  read_partials(set, [&](std::size_t item, std::string_view blob) {
    EXPECT_EQ(item, next++);
    EXPECT_EQ(blob, blob_of(item));
  });
  EXPECT_EQ(next, w.size());
  EXPECT_THROW(open_partials({dirs[0], dirs[1], dirs[3]}), InputError);             // shard 2 missing
  EXPECT_THROW(open_partials({dirs[0], dirs[1], dirs[2], dirs[3], dirs[1]}), InputError);  // repeated
  std::filesystem::remove_all(dir);
}

// max_chunk_weight caps every chunk, whether the weight asked for is the
// command's (chunk_weight) or the default share of the run, single or
// sharded: the largest range handed to compute weighs at most the cap
// (or is one item), and every item is still consumed once, in order.
TEST(Distribute, ChunksStayUnderTheCapWhateverTheyAskFor) {
  const auto dir = scratch("cap");
  std::vector<std::uint64_t> w;
  for (std::size_t i = 0; i < 200; ++i) w.push_back(i % 7 == 0 ? 9 : 1 + i % 3);  // some items above the cap
  for (const std::uint64_t asked : {std::uint64_t{0}, std::uint64_t{1000}}) {
    for (const bool sharded : {false, true}) {
      DistOptions o = toy_options(dir / (std::to_string(asked) + (sharded ? "s" : "")));
      o.chunk_weight = asked;
      o.max_chunk_weight = 8;
      if (sharded) o.shard = Shard{1, 2};
      std::uint64_t heaviest = 0;
      std::size_t calls = 0, next = 0;
      run_items(
          o, w,
          [&](std::size_t b, std::size_t e) {
            std::uint64_t weight = 0;
            for (std::size_t k = b; k < e; ++k) weight += w[k];
            if (e - b > 1) heaviest = std::max(heaviest, weight);
            ++calls;
            std::vector<std::string> out;
            for (std::size_t k = b; k < e; ++k) out.push_back(blob_of(k));
            return out;
          },
          [&](std::size_t item, std::string_view blob) {
            EXPECT_EQ(item, next++);
            EXPECT_EQ(blob, blob_of(item));
          });
      EXPECT_LE(heaviest, 8u) << "asked " << asked << (sharded ? ", sharded" : "");
      EXPECT_GT(heaviest, 4u);  // the cap, not something smaller, set the chunks
      EXPECT_GT(calls, 20u);
      EXPECT_EQ(next, sharded ? 0u : w.size());
    }
  }
  std::filesystem::remove_all(dir);
}

TEST(Distribute, ResumeRecomputesOnlyTheMissingItems) {
  const auto dir = scratch("resume");
  const std::vector<std::uint64_t> w(10, 1);
  DistOptions o = toy_options(dir);
  // A journal holding items 0..5 and then a record cut short, as a killed run leaves it.
  {
    std::size_t calls = 0;
    run_items(o, w, [&](std::size_t b, std::size_t e) {
      std::vector<std::string> out;
      for (std::size_t k = b; k < e; ++k) out.push_back(blob_of(k));
      ++calls;
      return out;
    }, [](std::size_t, std::string_view) {});
    EXPECT_EQ(calls, 4u);  // chunks of weight 3
  }
  // The run finished: its journal stays until finish_items; cut it after 2 chunks and a bit.
  const auto journal = journal_path(dir);
  ASSERT_TRUE(std::filesystem::exists(journal));
  std::string bytes;
  {
    std::ifstream f(journal, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(f), {});
  }
  const std::size_t record7 = bytes.find("item 6;");  // inside item 6's record
  ASSERT_NE(record7, std::string::npos);
  std::filesystem::resize_file(journal, record7 + 3);

  o.resume = true;
  std::vector<std::size_t> computed;
  std::vector<std::string> consumed;
  const DistResult r = run_items(o, w, [&](std::size_t b, std::size_t e) {
    std::vector<std::string> out;
    for (std::size_t k = b; k < e; ++k) {
      computed.push_back(k);
      out.push_back(blob_of(k));
    }
    return out;
  }, [&](std::size_t item, std::string_view blob) {
    EXPECT_EQ(item, consumed.size());
    consumed.emplace_back(blob);
  });
  EXPECT_EQ(r.reused, 6u);
  EXPECT_EQ(computed, (std::vector<std::size_t>{6, 7, 8, 9}));
  ASSERT_EQ(consumed.size(), w.size());
  for (std::size_t i = 0; i < w.size(); ++i) EXPECT_EQ(consumed[i], blob_of(i));
  finish_items(o);
  EXPECT_TRUE(std::filesystem::is_empty(dir));

  // A journal of another run is refused under --resume.
  o.resume = false;
  run_items(o, w, [&](std::size_t b, std::size_t e) { return std::vector<std::string>(e - b, "x"); },
            [](std::size_t, std::string_view) {});
  o.resume = true;
  o.fingerprint = "beef";
  EXPECT_THROW(run_items(o, w, [&](std::size_t b, std::size_t e) { return std::vector<std::string>(e - b, "x"); },
                         [](std::size_t, std::string_view) {}),
               InputError);
  std::filesystem::remove_all(dir);
}

TEST(ResultBlob, PlanResultsComeBackBitForBit) {
  Plan plan;
  plan.name = "p";
  plan.states.assign(3, std::vector<double>{0.0});
  std::vector<Plan> plans{plan};
  PlanResult r;
  r.states.resize(3);
  r.states[1].collision = true;
  r.states[1].contacts.push_back(PairContact{2, 5, {{7, 9}, {1, 4000000000u}}});
  r.states[2].min_distance = -0.0;
  r.states[2].point_a = Vec3(std::nextafter(1.0, 2.0), -1e-300, 3.0);
  r.states[0].min_distance = std::numeric_limits<double>::quiet_NaN();
  r.states[0].distance_is_bound = true;
  r.verdict = Verdict::kCollision;
  r.first_violation = Violation{1, Verdict::kCollision, 2, 5, -1, true};
  r.target_error = 0.1;
  r.dig_steps = {DigStep{true, 0.25, 1e-9}, {}, {}};
  DigSummary d;
  d.model = "swept";
  d.deepest_point = Vec3(1, 2, 3);
  r.dig = d;
  r.probes = {{ProbeReading{1.5, 0}}, {ProbeReading{2.5, -1}}, {ProbeReading{3.5, 0}}};
  r.probe_targets = {"Lander"};
  r.segments.resize(3);
  r.segments[0].checked = true;
  r.segments[0].witness_t = 0.125;
  r.segments[0].steps = 77;
  std::string bytes;
  append_plan_results({r}, bytes);
  std::vector<PlanResult> back;
  read_plan_results(bytes, plans, back);
  ASSERT_EQ(back.size(), 1u);
  std::string again;
  append_plan_results(back, again);
  EXPECT_EQ(again, bytes);  // every field written comes back to the same bits
  EXPECT_EQ(back[0].plan, &plans[0]);
  EXPECT_EQ(std::bit_cast<std::uint64_t>(back[0].states[2].min_distance), std::bit_cast<std::uint64_t>(-0.0));
  EXPECT_TRUE(std::isnan(back[0].states[0].min_distance));
  EXPECT_EQ(back[0].states[1].contacts[0].triangles[1].second, 4000000000u);
  EXPECT_EQ(back[0].dig->model, "swept");
  // Cut short anywhere: refused, never read as something else.
  for (std::size_t n = 0; n < bytes.size(); n += 7) {
    std::vector<PlanResult> cut;
    EXPECT_THROW(read_plan_results(std::string_view(bytes).substr(0, n), plans, cut), std::runtime_error) << n;
  }
}


// A run's fingerprint is kept in partial results and journals, so its value
// must not change with how it is computed: against FNV-1a written out here,
// two 64-bit chains (the second seeded differently, its state xored with
// 0x5bd1e995 before each item), each item prefixed by its length.
TEST(Fingerprint, ValuesAreTwoLengthPrefixedFnvChains) {
  auto fnv = [](std::uint64_t h, const unsigned char* p, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 0x100000001b3ull;
    return h;
  };
  std::uint64_t a = 0xcbf29ce484222325ull, b = 0x84222325cbf29ce4ull;
  Fingerprint fp;
  std::string big(100003, '\0');
  for (std::size_t i = 0; i < big.size(); ++i) big[i] = static_cast<char>((i * 2654435761u) >> 13);
  for (const std::string& item : {std::string(), std::string("verify"), big, std::string("\xff\x00z", 3)}) {
    fp.add(item);
    const std::uint64_t n = item.size();
    const auto* p = reinterpret_cast<const unsigned char*>(item.data());
    a = fnv(fnv(a, reinterpret_cast<const unsigned char*>(&n), 8), p, item.size());
    b = fnv(fnv(b ^ 0x5bd1e995ull, reinterpret_cast<const unsigned char*>(&n), 8), p, item.size());
  }
  char expected[33];
  std::snprintf(expected, sizeof expected, "%016llx%016llx", static_cast<unsigned long long>(a),
                static_cast<unsigned long long>(b));
  EXPECT_EQ(fp.hex(), expected);
}

// Records and headers that lie about sizes (issue "Hostile files"): memory
// follows the file, never what it claims.

std::vector<std::string> toy_blobs(std::size_t b, std::size_t e) {
  std::vector<std::string> out;
  for (std::size_t k = b; k < e; ++k) out.push_back(blob_of(k));
  return out;
}

TEST(Distribute, AJournalRecordClaimingTerabytesIsRedoneNotAllocated) {
  const auto dir = scratch("lying-record");
  const std::vector<std::uint64_t> w(6, 1);
  DistOptions o = toy_options(dir);
  o.shard = Shard{0, 1};
  run_items(o, w, toy_blobs, [](std::size_t, std::string_view) {});
  const std::filesystem::path file = partial_path(dir, *o.shard);
  std::ifstream in(file, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  in.close();
  // The first record's length field: after the two header lines and the tag and item.
  const std::size_t first_record = bytes.find('\n', bytes.find('\n') + 1) + 1;
  ASSERT_EQ(bytes[first_record], 'R');
  const std::uint64_t lie = (std::uint64_t{1} << 40) - 1;
  std::memcpy(bytes.data() + first_record + 9, &lie, 8);
  std::ofstream(file, std::ios::binary | std::ios::trunc) << bytes;
  // Not a complete partial any more: merge refuses it with a message, no allocation.
  EXPECT_THROW(open_partials({dir}), InputError);
  // --resume redoes every item from the lying record on.
  o.resume = true;
  std::size_t computed = 0;
  run_items(o, w, [&](std::size_t b, std::size_t e) { computed += e - b; return toy_blobs(b, e); },
            [](std::size_t, std::string_view) {});
  EXPECT_EQ(computed, w.size());
  std::size_t next = 0;
  read_partials(open_partials({dir}), [&](std::size_t item, std::string_view blob) {
    EXPECT_EQ(item, next++);
    EXPECT_EQ(blob, blob_of(item));
  });
  EXPECT_EQ(next, w.size());
  std::filesystem::remove_all(dir);
}

TEST(Distribute, AHeaderClaimingABillionShardsCostsAShortMessage) {
  const auto dir = scratch("billion");
  const std::vector<std::uint64_t> w(4, 1);
  DistOptions o = toy_options(dir);
  o.shard = Shard{0, 1'000'000'000};
  run_items(o, w, toy_blobs, [](std::size_t, std::string_view) {});  // shard 0 of a billion: no N-sized table
  try {
    open_partials({dir});
    ADD_FAILURE() << "999,999,999 shards missing and accepted";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_LT(what.size(), 600u) << what.substr(0, 600);
    EXPECT_NE(what.find("1, 2, 3"), std::string::npos) << what;
    EXPECT_NE(what.find("more"), std::string::npos) << what;
  }
  std::filesystem::remove_all(dir);
}


// A header's counts as the writer writes them: non-negative integers. A
// count of 1e39, -1, 2.5 or "3" is refused with the header's message (it
// was once cast to size_t: undefined behaviour), the item range too.
TEST(Distribute, AHeaderCountThatIsNoCountIsRefusedByName) {
  const auto dir = scratch("counts");
  const std::vector<std::uint64_t> w(4, 1);
  DistOptions o = toy_options(dir);
  o.shard = Shard{0, 1};
  run_items(o, w, toy_blobs, [](std::size_t, std::string_view) {});
  const std::filesystem::path file = partial_path(dir, *o.shard);
  std::ifstream in(file, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  in.close();
  ASSERT_NO_THROW(open_partials({dir}));
  const std::size_t h0 = bytes.find('\n') + 1, h1 = bytes.find('\n', h0);
  const std::string header = bytes.substr(h0, h1 - h0);
  for (const std::string field : {"\"items\":4", "\"range\":[0,4]", "\"shard\":[0,1]"}) {
    ASSERT_NE(header.find(field), std::string::npos) << header;
    for (const std::string bad : {"1e39", "-1", "2.5", "\"3\"", "null"}) {
      std::string lie = field;
      // The field's first number replaced by the bad value.
      const std::size_t at = field.find_first_of("0123456789");
      const std::size_t len = field.find_first_not_of("0123456789", at) == std::string::npos
                                  ? field.size() - at
                                  : field.find_first_not_of("0123456789", at) - at;
      lie.replace(at, len, bad);
      std::string changed = header;
      changed.replace(changed.find(field), field.size(), lie);
      std::ofstream(file, std::ios::binary | std::ios::trunc)
          << bytes.substr(0, h0) << changed << bytes.substr(h1);
      try {
        open_partials({dir});
        ADD_FAILURE() << lie << " was accepted";
      } catch (const InputError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("not a plancheck partial header"), std::string::npos) << lie << ": " << what;
        EXPECT_NE(what.find(file.filename().string()), std::string::npos) << what;
      }
    }
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace plancheck
