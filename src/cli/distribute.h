// SPDX-License-Identifier: MIT
// Work beyond one process: the engine behind `verify` (and `sweep`) for a
// single run, `--shard I/N`, `--resume`, `plancheck merge` and mpirun
// (contract: shared/spec/plan-and-report-format.md, "Beyond one machine").
//
// A command describes its work as items 0..W-1, each with a weight (its
// expected cost), and gives two callbacks:
//   compute(begin, end) -> one opaque byte string (blob) per item of the
//       contiguous range [begin, end); a blob must not depend on which
//       other items were computed with it, nor on threads, shards or ranks;
//   consume(item, blob) -> called once per item, in item order, on the one
//       process that writes the outputs (a single run, or MPI rank 0).
// run_items then runs the items one of three ways:
//   * single run: in chunks, each chunk's blobs appended to a journal
//     (DIR/.plancheck-journal) and fsync'ed, then consumed. With --resume,
//     the journal's valid records are reused and only the missing items are
//     computed. The caller writes its outputs and calls finish_items(),
//     which removes the journal: DIR holds no file more than the outputs.
//   * shard run (--shard I/N): items [b, e) of a balanced split by weight
//     (split_by_weight), appended in chunks to DIR/part-I-of-N.plancheck
//     (the partial file; it is its own journal: --resume continues it); an
//     end record marks it complete. Nothing is consumed; `plancheck merge`
//     reads the partial files of all N shards (open_partials, read_partials)
//     and consumes every item in order, as a single run would.
//   * MPI (launched by mpirun: OMPI_COMM_WORLD_SIZE or PMIX_RANK set, and
//     built with PLANCHECK_MPI): every rank sets the run up; rank 0 hands
//     out chunks (dynamic scheduling: a rank gets the next chunk when it
//     returns one) and computes chunks itself on a second thread, journals
//     and consumes what comes back, in item order. The other ranks compute
//     only (role kWorker) and write nothing. Blobs stream to rank 0 one
//     chunk per message (at most 2 GiB a chunk); rank 0 keeps a returned
//     chunk in memory only until the items before it have come back (so
//     worst case, with a slow first chunk, all of them). Outside mpirun no
//     MPI call is made (no MPI_Init).
//
// Partial file and journal layout (plancheck-partial/1), little-endian:
//   "plancheck-partial/1\n", one line of JSON header + "\n": command,
//   fingerprint, setup, shard [I, N] (null for a journal), items W, range
//   [begin, end); then records 'R' u64 item, u64 length, u64 checksum
//   (64-bit FNV-1a over item, length and blob), blob; a complete partial
//   ends with 'E' u64 record count, u64 checksum over the record checksums.
//   A record cut short or with a bad checksum ends what a reader trusts.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <iosfwd>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace plancheck {

// --shard I/N: the I-th (0-based) of N parts.
struct Shard {
  std::size_t index = 0;
  std::size_t count = 1;
};

// Parses "I/N" (0 <= I < N, N >= 1, decimal). Throws InputError naming
// --shard and the value.
Shard parse_shard(std::string_view text);

// Part boundaries of items 0..W-1 split into `parts` contiguous ranges of
// about equal weight: part k is [b[k], b[k+1]), b[0] = 0, b[parts] = W.
// Deterministic (integer arithmetic). Items of weight 0 count as 1.
std::vector<std::size_t> split_by_weight(std::span<const std::uint64_t> weights, std::size_t parts);

// 128-bit digest (two 64-bit FNV-1a lanes, hex) of what makes a run's
// results: command, scene and plan bytes, options. Not cryptographic: it
// tells runs apart, it does not resist forgery.
class Fingerprint {
 public:
  void add(std::string_view bytes);      // length-prefixed, so ("ab","c") != ("a","bc")
  void add_file(const std::filesystem::path& file);  // its bytes; throws InputError when unreadable
  std::string hex() const;

 private:
  std::uint64_t a_ = 0xcbf29ce484222325ull, b_ = 0x84222325cbf29ce4ull;
};

struct DistOptions {
  std::string command;          // "verify" or "sweep": in the partial header, merge dispatches on it
  std::string fingerprint;      // Fingerprint::hex() of the run: equal on every shard of one run
  std::string setup;            // the run's arguments (JSON text) from which merge sets the run up again
  std::filesystem::path out;    // DIR: the journal or the partial file goes there
  std::optional<Shard> shard;   // --shard I/N
  bool resume = false;          // --resume: reuse the journal's (partial's) valid records
  // Weight of a chunk (journal and fsync unit, and what an MPI rank is handed);
  // 0: about an eighth of the run's (part's) weight, a 16th of it per rank under MPI.
  std::uint64_t chunk_weight = 0;
  // The most a chunk may weigh, whatever chunk_weight or the default says
  // (0: no cap). A chunk's blobs are held in memory until it is journalled
  // and consumed, so a command whose blob size grows with an item's weight
  // caps its chunks here: memory then follows this cap, not the run's size.
  std::uint64_t max_chunk_weight = 0;
  std::ostream* log = nullptr;  // status lines (stderr); nullptr: none
};

enum class DistRole {
  kWriter,  // this process consumed every item: write the outputs, then finish_items()
  kShard,   // a shard: its partial file is written; nothing else to write
  kWorker,  // an MPI rank other than 0: nothing to write
};

struct ChunkTime {
  int rank = 0;            // MPI rank that computed it (0 outside MPI)
  std::size_t begin = 0;   // items [begin, end)
  std::size_t end = 0;
  double seconds = 0.0;    // compute time, wall clock on that rank
};

struct DistResult {
  DistRole role = DistRole::kWriter;
  int ranks = 0;                   // MPI ranks (0: not under MPI)
  std::vector<std::string> hosts;  // MPI: host names, each once, in rank order
  std::vector<ChunkTime> chunks;   // chunks computed by this run (writer: all ranks')
  std::size_t reused = 0;          // items taken from the journal or partial (--resume)
  std::filesystem::path partial;   // kShard: the partial file
};

using ComputeItems = std::function<std::vector<std::string>(std::size_t begin, std::size_t end)>;
using ConsumeItem = std::function<void(std::size_t item, std::string_view blob)>;

// Whether this process was started by mpirun (and MPI is built in); the
// first call under mpirun initialises MPI (finalised at exit). Throws when
// launched by mpirun with several ranks but built without MPI.
bool under_mpi();
// This process's MPI rank (0 outside MPI) and the number of ranks (1 outside).
int mpi_rank();
int mpi_size();

// Runs the items (see the top of this file). Throws InputError on a bad
// --shard/--resume combination or a journal of another run under --resume,
// and whatever compute or consume throw.
DistResult run_items(const DistOptions& options, std::span<const std::uint64_t> weights,
                     const ComputeItems& compute, const ConsumeItem& consume);

// The writer, once its outputs are written: removes DIR's journal.
void finish_items(const DistOptions& options);

// One partial file's header.
struct PartialHeader {
  std::filesystem::path file;
  std::string command, fingerprint, setup;
  Shard shard;
  std::size_t items = 0, begin = 0, end = 0;
};

// The partial files of one run, in shard order, each checked whole: one
// run (same command, fingerprint, setup, N, items), every shard 0..N-1
// once, ranges tiling 0..W, each file complete with valid checksums.
// Throws InputError (one message naming the file at fault) otherwise.
struct PartialSet {
  std::vector<PartialHeader> parts;
  const PartialHeader& first() const { return parts.front(); }
};
PartialSet open_partials(const std::vector<std::filesystem::path>& dirs);

// Consumes every item of the set in item order (blobs read file by file).
void read_partials(const PartialSet& set, const ConsumeItem& consume);

// The file names the engine writes in DIR.
std::filesystem::path journal_path(const std::filesystem::path& dir);
std::filesystem::path partial_path(const std::filesystem::path& dir, const Shard& shard);

}  // namespace plancheck
