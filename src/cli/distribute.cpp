// SPDX-License-Identifier: MIT
#include "src/cli/distribute.h"

#include "src/base/error.h"
#include "src/base/files.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <ostream>
#include <stdexcept>
#include <utility>

#include <fcntl.h>
#include <unistd.h>

#if PLANCHECK_MPI
#include <mpi.h>

#include <condition_variable>
#include <deque>
#include <exception>
#include <iostream>
#include <mutex>
#include <thread>
#endif

namespace plancheck {

static_assert(std::endian::native == std::endian::little, "partial files are written little-endian, as the host");

namespace {

using Json = nlohmann::ordered_json;
constexpr std::string_view kFormat = "plancheck-partial/1";
constexpr std::uint64_t kFnvPrime = 0x100000001b3ull;

std::uint64_t fnv(std::uint64_t h, const void* data, std::size_t n) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < n; ++i) h = (h ^ p[i]) * kFnvPrime;
  return h;
}

std::uint64_t record_checksum(std::uint64_t item, std::string_view blob) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  const std::uint64_t len = blob.size();
  h = fnv(h, &item, 8);
  h = fnv(h, &len, 8);
  return fnv(h, blob.data(), blob.size());
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Test hook (tests/distribute): PLANCHECK_TEST_STOP_AFTER=K ends the process
// (status 75, no clean-up: as if killed) once K items were computed and
// journaled by this process.
std::size_t stop_after() {
  const char* v = std::getenv("PLANCHECK_TEST_STOP_AFTER");
  return v && *v ? static_cast<std::size_t>(std::strtoull(v, nullptr, 10)) : 0;
}

Json header_json(const DistOptions& o, std::size_t items, std::size_t begin, std::size_t end) {
  Json h = {{"command", o.command}, {"fingerprint", o.fingerprint}, {"setup", o.setup}};
  h["shard"] = o.shard ? Json::array({o.shard->index, o.shard->count}) : Json(nullptr);
  h["items"] = items;
  h["range"] = Json::array({begin, end});
  return h;
}

// What a reader found in a partial file or journal.
struct Scan {
  bool exists = false;
  bool header_ok = false;   // the format line and a JSON header were read
  PartialHeader header;
  bool has_shard = false;
  std::uint64_t valid_bytes = 0;   // up to the end of the last valid record (or the header)
  struct Entry {
    std::uint64_t offset = 0, length = 0;  // the blob's place in the file
  };
  std::map<std::size_t, Entry> records;    // item -> blob
  std::uint64_t checksum_chain = 0xcbf29ce484222325ull;  // over the record checksums, file order
  bool complete = false;                   // a valid end record follows the records
  std::string problem;                     // why reading stopped early (empty: clean end of file)
};

template <typename T>
bool read_raw(std::istream& in, T& v) {
  return static_cast<bool>(in.read(reinterpret_cast<char*>(&v), sizeof(T)));
}

// A line of at most max_bytes (the '\n' dropped); false when none ends in time.
bool read_line(std::istream& in, std::string& line, std::size_t max_bytes) {
  line.clear();
  for (int c; (c = in.get()) != std::char_traits<char>::eof();) {
    if (c == '\n') return true;
    if (line.size() >= max_bytes) return false;
    line.push_back(static_cast<char>(c));
  }
  return false;
}

// A header is the run's setup (its paths and options): far below this.
constexpr std::size_t kMaxHeaderBytes = std::size_t{16} << 20;

Scan scan_file(const std::filesystem::path& file) {
  Scan s;
  std::error_code ec;
  const auto status = std::filesystem::symlink_status(file, ec);
  if (ec || !std::filesystem::exists(status)) return s;
  s.exists = true;
  s.header.file = file;
  // Only a regular file is a partial result or journal (a link is never
  // followed: what it points to is not this run's to read or to continue).
  if (!std::filesystem::is_regular_file(status)) {
    s.problem = "not a regular file";
    return s;
  }
  std::ifstream in(file, std::ios::binary);
  if (!in) {
    s.problem = "cannot be read";
    return s;
  }
  const std::uint64_t file_size = std::filesystem::file_size(file, ec);
  if (ec) {
    s.problem = "cannot be read";
    return s;
  }
  std::string line;
  if (!read_line(in, line, kFormat.size()) || line != kFormat) {
    s.problem = "not a plancheck partial result (no " + std::string(kFormat) + " line)";
    return s;
  }
  if (!read_line(in, line, kMaxHeaderBytes)) {
    s.problem = "cut short in its header";
    return s;
  }
  try {
    const Json h = Json::parse(line);
    // A count as the writer writes it: a non-negative integer. nlohmann's
    // get<std::size_t> casts 1e39 or -1 (undefined behaviour, or a wrap).
    auto count = [](const Json& v) {
      if (!v.is_number_unsigned()) throw std::invalid_argument("not a count");
      return v.get<std::size_t>();
    };
    s.header.command = h.at("command").get<std::string>();
    s.header.fingerprint = h.at("fingerprint").get<std::string>();
    s.header.setup = h.at("setup").get<std::string>();
    if (!h.at("shard").is_null()) {
      s.has_shard = true;
      s.header.shard = Shard{count(h.at("shard").at(0)), count(h.at("shard").at(1))};
    }
    s.header.items = count(h.at("items"));
    s.header.begin = count(h.at("range").at(0));
    s.header.end = count(h.at("range").at(1));
  } catch (const std::exception&) {
    s.problem = "its header is not a plancheck partial header";
    return s;
  }
  if (s.header.begin > s.header.end || s.header.end > s.header.items) {
    s.problem = "its header's item range is not within the items";
    return s;
  }
  s.header_ok = true;
  s.valid_bytes = static_cast<std::uint64_t>(in.tellg());
  std::string blob;
  for (;;) {
    char tag = 0;
    if (!in.get(tag)) return s;  // clean end of file: no end record
    if (tag == 'E') {
      std::uint64_t count = 0, chain = 0;
      if (!read_raw(in, count) || !read_raw(in, chain)) {
        s.problem = "cut short in its end record";
        return s;
      }
      if (count != s.records.size() || chain != s.checksum_chain) {
        s.problem = "its end record does not match its records";
        return s;
      }
      if (in.peek() != std::char_traits<char>::eof()) {
        s.problem = "bytes after its end record";
        return s;
      }
      s.complete = true;
      s.valid_bytes = static_cast<std::uint64_t>(in.tellg() < 0 ? 0 : static_cast<std::uint64_t>(in.tellg()));
      return s;
    }
    std::uint64_t item = 0, length = 0, sum = 0;
    if (tag != 'R' || !read_raw(in, item) || !read_raw(in, length) || !read_raw(in, sum)) {
      s.problem = tag != 'R' ? "a record that is not one (corrupt)" : "cut short in a record";
      return s;
    }
    if (item < s.header.begin || item >= s.header.end || s.records.count(item)) {
      s.problem = "a record of an item out of its range or repeated (corrupt)";
      return s;
    }
    const std::uint64_t offset = static_cast<std::uint64_t>(in.tellg());
    // Nothing is allocated for more than the file holds: a length beyond
    // its end is a record cut short (or a lie), never a buffer.
    if (length > file_size - std::min(offset, file_size)) {
      s.problem = "cut short in a record";
      return s;
    }
    blob.resize(static_cast<std::size_t>(length));
    if (!in.read(blob.data(), static_cast<std::streamsize>(length))) {
      s.problem = "cut short in a record";
      return s;
    }
    if (record_checksum(item, blob) != sum) {
      s.problem = "a record with a bad checksum (corrupt)";
      return s;
    }
    s.records[item] = Scan::Entry{offset, length};
    s.checksum_chain = fnv(s.checksum_chain, &sum, 8);
    s.valid_bytes = static_cast<std::uint64_t>(in.tellg());
  }
}

std::string read_blob(std::ifstream& in, const std::filesystem::path& file, const Scan::Entry& e) {
  std::string blob(static_cast<std::size_t>(e.length), '\0');
  in.clear();
  in.seekg(static_cast<std::streamoff>(e.offset));
  if (!in.read(blob.data(), static_cast<std::streamsize>(e.length))) fail(file, "cannot read a record back");
  return blob;
}

// Appends records to a partial file or journal, fdatasync'ed per chunk.
class RecordWriter {
 public:
  // keep_bytes > 0: continue the file after its first keep_bytes (its valid
  // records); else write it anew with `header`.
  RecordWriter(const std::filesystem::path& file, const std::string& header, std::uint64_t keep_bytes,
               std::uint64_t chain, std::size_t records)
      : file_(file), chain_(chain), records_(records) {
    std::filesystem::create_directories(file.parent_path().empty() ? "." : file.parent_path());
    fd_ = open_for_append(file, keep_bytes);  // files.h: never through a link
    if (keep_bytes == 0) put(std::string(kFormat) + "\n" + header + "\n");
  }
  ~RecordWriter() {
    if (fd_ >= 0) ::close(fd_);
  }
  RecordWriter(const RecordWriter&) = delete;
  RecordWriter& operator=(const RecordWriter&) = delete;

  void record(std::uint64_t item, std::string_view blob) {
    const std::uint64_t length = blob.size();
    const std::uint64_t sum = record_checksum(item, blob);
    std::string head(25, '\0');
    head[0] = 'R';
    std::memcpy(head.data() + 1, &item, 8);
    std::memcpy(head.data() + 9, &length, 8);
    std::memcpy(head.data() + 17, &sum, 8);
    put(head);
    put(blob);
    chain_ = fnv(chain_, &sum, 8);
    ++records_;
  }
  void end() {
    std::string tail(17, '\0');
    tail[0] = 'E';
    const std::uint64_t count = records_;
    std::memcpy(tail.data() + 1, &count, 8);
    std::memcpy(tail.data() + 9, &chain_, 8);
    put(tail);
    sync(true);
  }
  // After a chunk: to the disk, at most once a second (a sync costs tens of
  // milliseconds on some disks, and a verify chunk may take less). A killed
  // process loses no written record either way (the kernel holds them); a
  // machine that goes down loses at most the last second's chunks.
  void sync(bool now = false) {
    const auto t = std::chrono::steady_clock::now();
    if (!now && t - last_sync_ < std::chrono::seconds(1)) return;
    if (::fdatasync(fd_) != 0) fail(file_, std::string("cannot sync: ") + std::strerror(errno));
    last_sync_ = t;
  }

 private:
  void put(std::string_view bytes) {
    while (!bytes.empty()) {
      const ssize_t n = ::write(fd_, bytes.data(), bytes.size());
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) fail(file_, std::string("write failed: ") + std::strerror(errno));
      bytes.remove_prefix(static_cast<std::size_t>(n));
    }
  }
  std::filesystem::path file_;
  int fd_ = -1;
  std::uint64_t chain_;
  std::size_t records_;
  std::chrono::steady_clock::time_point last_sync_ = std::chrono::steady_clock::now();
};

// Contiguous runs of the items not yet done, cut at about `target` weight.
std::vector<std::pair<std::size_t, std::size_t>> make_chunks(std::span<const std::uint64_t> weights, std::size_t begin,
                                                             std::size_t end, const std::map<std::size_t, Scan::Entry>& done,
                                                             std::uint64_t target) {
  std::vector<std::pair<std::size_t, std::size_t>> chunks;
  std::size_t i = begin;
  while (i < end) {
    if (done.count(i)) {
      ++i;
      continue;
    }
    const std::size_t b = i;
    std::uint64_t w = 0;
    while (i < end && !done.count(i) && (i == b || w + std::max<std::uint64_t>(weights[i], 1) <= target)) {
      w += std::max<std::uint64_t>(weights[i], 1);
      ++i;
    }
    chunks.emplace_back(b, i);
  }
  return chunks;
}

// A chunk's target weight under the command's cap (DistOptions::max_chunk_weight).
std::uint64_t capped(const DistOptions& o, std::uint64_t target) {
  return o.max_chunk_weight > 0 ? std::min(target, o.max_chunk_weight) : target;
}

std::uint64_t range_weight(std::span<const std::uint64_t> weights, std::size_t begin, std::size_t end) {
  std::uint64_t w = 0;
  for (std::size_t i = begin; i < end; ++i) w += std::max<std::uint64_t>(weights[i], 1);
  return w;
}

// What --resume finds in `file` for this run: its valid records, or nothing
// (a fresh start). Throws when the file is another run's.
Scan resume_scan(const DistOptions& o, const std::filesystem::path& file, std::size_t items, std::size_t begin,
                 std::size_t end) {
  if (!o.resume) return Scan{};
  Scan s = scan_file(file);
  if (!s.exists) {
    if (o.log) *o.log << "plancheck: --resume: no " << file.string() << ", starting from the first item\n";
    return Scan{};
  }
  if (!s.header_ok) {
    if (o.log) *o.log << "plancheck: --resume: " << file.string() << ": " << s.problem << "; starting anew\n";
    return Scan{};
  }
  const PartialHeader& h = s.header;
  const bool same_shard = o.shard ? s.has_shard && h.shard.index == o.shard->index && h.shard.count == o.shard->count
                                  : !s.has_shard;
  if (h.command != o.command || h.fingerprint != o.fingerprint || h.setup != o.setup || !same_shard ||
      h.items != items || h.begin != begin || h.end != end)
    fail(file, "--resume: this is the journal of another run (scene, plans, options or shard differ); "
               "run without --resume to start anew");
  if (o.log)
    *o.log << "plancheck: --resume: " << s.records.size() << " of " << (end - begin) << " items done in "
           << file.string() << (s.problem.empty() ? "" : " (then " + s.problem + ": redone)") << "\n";
  return s;
}

#if PLANCHECK_MPI
struct MpiSession {
  bool active = false;
  int rank = 0;
  int size = 1;
};

MpiSession& mpi_session() {
  static MpiSession session = [] {
    MpiSession s;
    const bool launched = std::getenv("OMPI_COMM_WORLD_SIZE") || std::getenv("PMIX_RANK");
    if (!launched) return s;
    int provided = 0;
    MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
    if (provided < MPI_THREAD_FUNNELED) throw std::runtime_error("MPI: no MPI_THREAD_FUNNELED support");
    MPI_Comm_rank(MPI_COMM_WORLD, &s.rank);
    MPI_Comm_size(MPI_COMM_WORLD, &s.size);
    s.active = true;
    std::atexit([] {
      int finalized = 0;
      MPI_Finalized(&finalized);
      if (!finalized) MPI_Finalize();
    });
    return s;
  }();
  return session;
}
#endif

}  // namespace

Shard parse_shard(std::string_view text) {
  auto bad = [&](const std::string& why) -> InputError {
    return InputError("--shard " + std::string(text) + ": " + why);
  };
  const std::size_t slash = text.find('/');
  if (slash == std::string_view::npos) throw bad("expected I/N, the I-th (from 0) of N parts, e.g. 0/4");
  auto number = [&](std::string_view s, const char* what) {
    std::size_t v = 0;
    const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (s.empty() || ec != std::errc() || p != s.data() + s.size())
      throw bad(std::string(what) + " is not a whole number (expected I/N, e.g. 0/4)");
    return v;
  };
  Shard shard;
  shard.index = number(text.substr(0, slash), "I");
  shard.count = number(text.substr(slash + 1), "N");
  if (shard.count < 1) throw bad("N must be at least 1");
  if (shard.index >= shard.count) throw bad("I must be below N (parts are numbered 0 to N-1)");
  return shard;
}

// Weight times part count may pass 2^64 on a sweep's grid.
__extension__ typedef unsigned __int128 Wide;

// Part k starts at the first item whose weight before it reaches k/parts of
// the total (part 0 at 0; past the last item: W).
std::size_t part_start(std::span<const std::uint64_t> weights, std::size_t parts, std::size_t k) {
  if (k == 0) return 0;
  if (k >= parts) return weights.size();
  const Wide total = range_weight(weights, 0, weights.size());
  Wide before = 0;
  for (std::size_t i = 0; i < weights.size(); ++i) {
    if (before * parts >= total * k) return i;
    before += std::max<std::uint64_t>(weights[i], 1);
  }
  return weights.size();
}

std::vector<std::size_t> split_by_weight(std::span<const std::uint64_t> weights, std::size_t parts) {
  std::vector<std::size_t> b(parts + 1, weights.size());
  b[0] = 0;
  const Wide total = range_weight(weights, 0, weights.size());
  Wide before = 0;
  std::size_t k = 1;
  for (std::size_t i = 0; i < weights.size() && k < parts; ++i) {
    while (k < parts && before * parts >= total * k) b[k++] = i;
    before += std::max<std::uint64_t>(weights[i], 1);
  }
  return b;
}

void Fingerprint::add(std::string_view bytes) {
  const std::uint64_t n = bytes.size();
  std::uint64_t a = fnv(a_, &n, 8), b = fnv(b_ ^ 0x5bd1e995ull, &n, 8);
  // Both chains in one pass over the bytes (the same values as two passes):
  // each step waits on its own multiply, so the two overlap. The parts'
  // meshes are megabytes, and this was on the way to the first answer.
  const auto* p = reinterpret_cast<const unsigned char*>(bytes.data());
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    a = (a ^ p[i]) * kFnvPrime;
    b = (b ^ p[i]) * kFnvPrime;
  }
  a_ = a;
  b_ = b;
}

void Fingerprint::add_file(const std::filesystem::path& file) {
  // As add(the file's bytes), a block at a time: a plan of any size costs
  // one block of memory here.
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) fail(file, "cannot read: not a regular file");
  const std::uint64_t n = std::filesystem::file_size(file, ec);
  if (ec) fail(file, "cannot read");
  std::uint64_t a = fnv(a_, &n, 8), b = fnv(b_ ^ 0x5bd1e995ull, &n, 8);
  std::ifstream in(file, std::ios::binary);
  if (!in) fail(file, "cannot read");
  std::string block(std::size_t{1} << 20, '\0');
  std::uint64_t seen = 0;
  while (in) {
    in.read(block.data(), static_cast<std::streamsize>(block.size()));
    const auto got = static_cast<std::size_t>(in.gcount());
    const auto* p = reinterpret_cast<const unsigned char*>(block.data());
    for (std::size_t i = 0; i < got; ++i) {
      a = (a ^ p[i]) * kFnvPrime;
      b = (b ^ p[i]) * kFnvPrime;
    }
    seen += got;
  }
  if (seen != n) fail(file, "changed while being read");
  a_ = a;
  b_ = b;
}

std::string Fingerprint::hex() const {
  char buf[33];
  std::snprintf(buf, sizeof buf, "%016llx%016llx", static_cast<unsigned long long>(a_),
                static_cast<unsigned long long>(b_));
  return buf;
}

std::filesystem::path journal_path(const std::filesystem::path& dir) { return dir / ".plancheck-journal"; }

std::filesystem::path partial_path(const std::filesystem::path& dir, const Shard& shard) {
  return dir / ("part-" + std::to_string(shard.index) + "-of-" + std::to_string(shard.count) + ".plancheck");
}

bool under_mpi() {
#if PLANCHECK_MPI
  return mpi_session().active;
#else
  const char* size = std::getenv("OMPI_COMM_WORLD_SIZE");
  if (size && std::atoi(size) > 1)
    throw InputError("started by mpirun with " + std::string(size) +
                     " ranks, but this plancheck was built without MPI (cmake -DPLANCHECK_MPI=ON, libopenmpi-dev)");
  return false;
#endif
}

int mpi_rank() {
#if PLANCHECK_MPI
  return under_mpi() ? mpi_session().rank : 0;
#else
  return 0;
#endif
}

int mpi_size() {
#if PLANCHECK_MPI
  return under_mpi() ? mpi_session().size : 1;
#else
  return 1;
#endif
}

namespace {

// The single run and the shard run: chunks in order, journaled, consumed
// (single run) right after.
DistResult run_local(const DistOptions& o, std::span<const std::uint64_t> weights, const ComputeItems& compute,
                     const ConsumeItem& consume) {
  const std::size_t items = weights.size();
  std::size_t begin = 0, end = items;
  if (o.shard) {
    // Two bounds, not N + 1: memory follows the items, not what --shard claims.
    begin = part_start(weights, o.shard->count, o.shard->index);
    end = part_start(weights, o.shard->count, o.shard->index + 1);
  }
  const bool writer = !o.shard;
  const std::filesystem::path file = o.shard ? partial_path(o.out, *o.shard) : journal_path(o.out);
  DistResult result;
  result.role = writer ? DistRole::kWriter : DistRole::kShard;
  if (o.shard) result.partial = file;

  const Scan done = resume_scan(o, file, items, begin, end);
  result.reused = done.records.size();
  if (o.shard && done.complete) {
    if (o.log) *o.log << "plancheck: --resume: " << file.string() << " is complete already\n";
    return result;
  }
  const std::string header = header_json(o, items, begin, end).dump();
  RecordWriter journal(file, header, done.header_ok ? done.valid_bytes : 0, done.checksum_chain,
                       done.records.size());
  std::ifstream reread;
  if (!done.records.empty()) reread.open(file, std::ios::binary);

  std::size_t next = begin;  // next item to consume
  auto consume_done_until = [&](std::size_t until) {
    for (; next < until; ++next) consume(next, read_blob(reread, file, done.records.at(next)));
  };
  const std::uint64_t target =
      capped(o, o.chunk_weight > 0 ? o.chunk_weight : std::max<std::uint64_t>(1, range_weight(weights, begin, end) / 8));
  const std::size_t stop = stop_after();
  std::size_t computed = 0;
  for (const auto& [b, e] : make_chunks(weights, begin, end, done.records, target)) {
    const auto t0 = std::chrono::steady_clock::now();
    std::vector<std::string> blobs = compute(b, e);
    if (blobs.size() != e - b) throw std::logic_error("run_items: compute returned a wrong number of blobs");
    result.chunks.push_back(ChunkTime{0, b, e, seconds_since(t0)});
    for (std::size_t i = b; i < e; ++i) journal.record(i, blobs[i - b]);
    journal.sync();
    computed += e - b;
    if (stop > 0 && computed >= stop) std::_Exit(75);
    if (writer) {
      consume_done_until(b);
      for (std::size_t i = b; i < e; ++i) consume(i, blobs[i - b]);
      next = e;
    }
  }
  if (writer) consume_done_until(end);
  if (o.shard) journal.end();
  return result;
}

#if PLANCHECK_MPI
// Messages: a rank sends kResult (its finished chunk, or none at first) and
// gets kAssign back (a chunk, or begin == end: stop).
constexpr int kTagResult = 1;
constexpr int kTagAssign = 2;

// Waits for a message without spinning a core (Open MPI's blocking calls
// poll): probe, sleep 200 us, probe again.
MPI_Status wait_message(int source, int tag) {
  MPI_Status status;
  for (;;) {
    int flag = 0;
    MPI_Iprobe(source, tag, MPI_COMM_WORLD, &flag, &status);
    if (flag) return status;
    ::usleep(200);
  }
}

void put_u64(std::string& s, std::uint64_t v) { s.append(reinterpret_cast<const char*>(&v), 8); }
std::uint64_t get_u64(std::string_view s, std::size_t& pos) {
  if (s.size() - pos < 8) throw std::runtime_error("MPI: a message cut short");
  std::uint64_t v;
  std::memcpy(&v, s.data() + pos, 8);
  pos += 8;
  return v;
}

std::string host_name() {
  char name[MPI_MAX_PROCESSOR_NAME];
  int len = 0;
  MPI_Get_processor_name(name, &len);
  return std::string(name, static_cast<std::size_t>(len));
}

void send_bytes(const std::string& bytes, int dest, int tag) {
  if (bytes.size() > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw std::runtime_error("MPI: a chunk's results exceed 2 GiB; use a smaller chunk weight");
  MPI_Send(bytes.data(), static_cast<int>(bytes.size()), MPI_BYTE, dest, tag, MPI_COMM_WORLD);
}

std::string recv_bytes(const MPI_Status& status) {
  int count = 0;
  MPI_Get_count(&status, MPI_BYTE, &count);
  std::string bytes(static_cast<std::size_t>(count), '\0');
  MPI_Recv(bytes.data(), count, MPI_BYTE, status.MPI_SOURCE, status.MPI_TAG, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  return bytes;
}

// Result message: begin, end, seconds (as bits), host name, then per item its length and bytes.
std::string pack_result(std::size_t b, std::size_t e, double seconds, const std::string& host,
                        const std::vector<std::string>& blobs) {
  std::string m;
  put_u64(m, b);
  put_u64(m, e);
  put_u64(m, std::bit_cast<std::uint64_t>(seconds));
  put_u64(m, host.size());
  m += host;
  for (const std::string& blob : blobs) {
    put_u64(m, blob.size());
    m += blob;
  }
  return m;
}

void run_worker(const ComputeItems& compute) {
  const std::string host = host_name();
  std::string message = pack_result(0, 0, 0.0, host, {});
  for (;;) {
    send_bytes(message, 0, kTagResult);
    const std::string assign = recv_bytes(wait_message(0, kTagAssign));
    std::size_t pos = 0;
    const std::size_t b = get_u64(assign, pos), e = get_u64(assign, pos);
    if (b == e) return;
    const auto t0 = std::chrono::steady_clock::now();
    std::vector<std::string> blobs = compute(b, e);
    if (blobs.size() != e - b) throw std::logic_error("run_items: compute returned a wrong number of blobs");
    message = pack_result(b, e, seconds_since(t0), host, blobs);
  }
}

DistResult run_root(const DistOptions& o, std::span<const std::uint64_t> weights, const ComputeItems& compute,
                    const ConsumeItem& consume, int size) {
  const std::size_t items = weights.size();
  const std::filesystem::path file = journal_path(o.out);
  DistResult result;
  result.role = DistRole::kWriter;
  result.ranks = size;
  const Scan done = resume_scan(o, file, items, 0, items);
  result.reused = done.records.size();
  RecordWriter journal(file, header_json(o, items, 0, items).dump(), done.header_ok ? done.valid_bytes : 0,
                       done.checksum_chain, done.records.size());
  std::ifstream reread;
  if (!done.records.empty()) reread.open(file, std::ios::binary);

  const std::uint64_t target = capped(
      o, o.chunk_weight > 0 ? o.chunk_weight
                            : std::max<std::uint64_t>(1, range_weight(weights, 0, items) / (16 * static_cast<std::uint64_t>(size))));
  const auto chunks = make_chunks(weights, 0, items, done.records, target);
  const std::size_t stop = stop_after();

  std::mutex mutex;  // guards everything below, the journal and consume
  std::size_t next_chunk = 0;
  std::map<std::size_t, std::string> arrived;  // item -> blob, until consumed
  std::size_t next = 0;                        // next item to consume
  std::size_t computed = 0;
  std::vector<std::string> hosts(static_cast<std::size_t>(size));
  hosts[0] = host_name();
  auto take_chunk = [&]() -> std::pair<std::size_t, std::size_t> {
    std::lock_guard lock(mutex);
    if (next_chunk == chunks.size()) return {0, 0};
    return chunks[next_chunk++];
  };
  // A chunk came back: journal it, consume what is now in order.
  auto deliver = [&](int rank, std::size_t b, std::size_t e, double seconds, std::vector<std::string>& blobs) {
    std::lock_guard lock(mutex);
    result.chunks.push_back(ChunkTime{rank, b, e, seconds});
    for (std::size_t i = b; i < e; ++i) journal.record(i, blobs[i - b]);
    journal.sync();
    computed += e - b;
    if (stop > 0 && computed >= stop) std::_Exit(75);
    for (std::size_t i = b; i < e; ++i) arrived.emplace(i, std::move(blobs[i - b]));
    while (next < items) {
      if (auto it = done.records.find(next); it != done.records.end()) {
        consume(next, read_blob(reread, file, it->second));
      } else if (auto a = arrived.find(next); a != arrived.end()) {
        consume(next, a->second);
        arrived.erase(a);
      } else {
        break;
      }
      ++next;
    }
  };

  // Rank 0's own share, on a second thread (MPI calls stay on this one).
  std::exception_ptr local_error;
  std::thread local([&] {
    try {
      for (;;) {
        const auto [b, e] = take_chunk();
        if (b == e) return;
        const auto t0 = std::chrono::steady_clock::now();
        std::vector<std::string> blobs = compute(b, e);
        if (blobs.size() != e - b) throw std::logic_error("run_items: compute returned a wrong number of blobs");
        deliver(0, b, e, seconds_since(t0), blobs);
      }
    } catch (...) {
      local_error = std::current_exception();
    }
  });

  int running = size - 1;
  try {
    while (running > 0) {
      const MPI_Status status = wait_message(MPI_ANY_SOURCE, kTagResult);
      const std::string m = recv_bytes(status);
      std::size_t pos = 0;
      const std::size_t b = get_u64(m, pos), e = get_u64(m, pos);
      const double seconds = std::bit_cast<double>(get_u64(m, pos));
      const std::size_t host_len = get_u64(m, pos);
      if (m.size() - pos < host_len) throw std::runtime_error("MPI: a message cut short");
      hosts[static_cast<std::size_t>(status.MPI_SOURCE)] = m.substr(pos, host_len);
      pos += host_len;
      std::vector<std::string> blobs;
      for (std::size_t i = b; i < e; ++i) {
        const std::size_t len = get_u64(m, pos);
        if (m.size() - pos < len) throw std::runtime_error("MPI: a message cut short");
        blobs.emplace_back(m.substr(pos, len));
        pos += len;
      }
      if (e > b) deliver(status.MPI_SOURCE, b, e, seconds, blobs);
      const auto [nb, ne] = take_chunk();
      std::string assign;
      put_u64(assign, nb);
      put_u64(assign, ne);
      send_bytes(assign, status.MPI_SOURCE, kTagAssign);
      if (nb == ne) --running;
    }
  } catch (...) {
    local.join();
    throw;
  }
  local.join();
  if (local_error) std::rethrow_exception(local_error);
  if (next != items) throw std::logic_error("run_items: not every item came back");
  for (const std::string& h : hosts)
    if (std::find(result.hosts.begin(), result.hosts.end(), h) == result.hosts.end()) result.hosts.push_back(h);
  std::sort(result.chunks.begin(), result.chunks.end(),
            [](const ChunkTime& x, const ChunkTime& y) { return x.begin < y.begin; });
  return result;
}
#endif

}  // namespace

DistResult run_items(const DistOptions& o, std::span<const std::uint64_t> weights, const ComputeItems& compute,
                     const ConsumeItem& consume) {
  if (under_mpi()) {
    if (o.shard) throw InputError("--shard: not under mpirun (mpirun spreads the whole run over its ranks)");
#if PLANCHECK_MPI
    const int size = mpi_size();
    if (size > 1) {
      if (mpi_rank() != 0) {
        try {
          run_worker(compute);
        } catch (const std::exception& e) {
          std::cerr << "plancheck: rank " << mpi_rank() << ": " << e.what() << "\n";
          MPI_Abort(MPI_COMM_WORLD, 2);
        }
        DistResult r;
        r.role = DistRole::kWorker;
        r.ranks = size;
        return r;
      }
      try {
        return run_root(o, weights, compute, consume, size);
      } catch (const std::exception& e) {
        std::cerr << "plancheck: rank 0: " << e.what() << "\n";
        MPI_Abort(MPI_COMM_WORLD, 2);
      }
    }
    DistResult r = run_local(o, weights, compute, consume);
    r.ranks = 1;
    return r;
#endif
  }
  return run_local(o, weights, compute, consume);
}

void finish_items(const DistOptions& o) {
  std::error_code ec;
  std::filesystem::remove(journal_path(o.out), ec);
}

PartialSet open_partials(const std::vector<std::filesystem::path>& dirs) {
  std::vector<Scan> scans;
  for (const std::filesystem::path& dir : dirs) {
    if (!std::filesystem::is_directory(dir)) fail(dir, "not a folder of partial results");
    std::vector<std::filesystem::path> files;
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
      const std::string name = entry.path().filename().string();
      if (name.starts_with("part-") && name.ends_with(".plancheck")) files.push_back(entry.path());
    }
    if (files.empty()) fail(dir, "no partial result (part-I-of-N.plancheck) in this folder");
    std::sort(files.begin(), files.end());
    for (const auto& f : files) {
      Scan s = scan_file(f);
      if (!s.header_ok) fail(f, s.problem);
      if (!s.has_shard) fail(f, "not a shard's partial result");
      if (!s.complete)
        fail(f, "cut short or corrupt (" + (s.problem.empty() ? std::string("no end record") : s.problem) +
                    "): the shard did not finish; run it again (--resume continues it)");
      scans.push_back(std::move(s));
    }
  }
  const PartialHeader& h0 = scans.front().header;
  for (const Scan& s : scans) {
    const PartialHeader& h = s.header;
    if (h.command != h0.command || h.fingerprint != h0.fingerprint || h.setup != h0.setup ||
        h.shard.count != h0.shard.count || h.items != h0.items)
      fail(h.file, "not of the same run as " + h0.file.string() +
                       " (a different command, scene, plans or options, or another N)");
  }
  std::sort(scans.begin(), scans.end(),
            [](const Scan& a, const Scan& b) { return a.header.shard.index < b.header.shard.index; });
  for (std::size_t k = 1; k < scans.size(); ++k)
    if (scans[k].header.shard.index == scans[k - 1].header.shard.index)
      fail(scans[k].header.file, "shard " + std::to_string(scans[k].header.shard.index) + " of " +
                                     std::to_string(h0.shard.count) + " is given twice (also " +
                                     scans[k - 1].header.file.string() + ")");
  // The shards missing, the first few named: walked gap by gap over the
  // files given, so N (as a header claims it) costs nothing.
  if (scans.size() != h0.shard.count) {
    constexpr std::size_t kNamed = 10;
    std::string missing;
    std::size_t named = 0;
    std::size_t expect = 0;
    for (std::size_t k = 0; k <= scans.size() && named < kNamed; ++k) {
      const std::size_t next = k < scans.size() ? scans[k].header.shard.index : h0.shard.count;
      for (; expect < next && named < kNamed; ++expect, ++named) missing += (named ? ", " : "") + std::to_string(expect);
      expect = next + 1;
    }
    const std::size_t count = h0.shard.count - scans.size();
    if (count > named) missing += " and " + std::to_string(count - named) + " more";
    throw InputError("merge: shard" + std::string(count > 1 ? "s " : " ") + missing + " of " +
                     std::to_string(h0.shard.count) + " missing (have " + std::to_string(scans.size()) +
                     " partial results of the run of " + h0.file.string() + ")");
  }
  std::size_t at = 0;
  for (const Scan& s : scans) {
    if (s.header.begin != at || s.records.size() != s.header.end - s.header.begin)
      fail(s.header.file, "its items do not follow the previous shard's (corrupt)");
    at = s.header.end;
  }
  if (at != h0.items) fail(scans.back().header.file, "the shards do not cover every item (corrupt)");
  PartialSet set;
  for (Scan& s : scans) set.parts.push_back(std::move(s.header));
  return set;
}

void read_partials(const PartialSet& set, const ConsumeItem& consume) {
  for (const PartialHeader& h : set.parts) {
    const Scan s = scan_file(h.file);  // again: the index of its records
    if (!s.complete) fail(h.file, "changed while being merged");
    std::ifstream in(h.file, std::ios::binary);
    for (std::size_t i = h.begin; i < h.end; ++i) {
      consume(i, read_blob(in, h.file, s.records.at(i)));
    }
  }
}

}  // namespace plancheck
