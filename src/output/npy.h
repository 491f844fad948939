// SPDX-License-Identifier: MIT
// NumPy .npy files (format version 1.0), written in place and in any order:
// the header and the file's full size first, then blocks of elements at
// their positions (positioned writes, so threads or ranks may write
// disjoint blocks at once), then a rename from a temporary name, so a run
// cut short leaves no file that looks complete. Memory stays bounded by the
// caller's blocks however large the array (sweep's verdict.npy and
// distance.npy, up to 2e9 elements).
//
// Layout (numpy.lib.format): "\x93NUMPY", version 1 0, a little-endian
// uint16 header length, then an ASCII dict
// {'descr': '|u1', 'fortran_order': False, 'shape': (73, 32), }
// padded with spaces and ended by '\n' so the data starts on a 64-byte
// boundary; then the elements in C order, little-endian.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace plancheck {

class TempFile;  // src/base/files.h

enum class NpyType { kUint8, kFloat32 };

// The header bytes for an array of `type` and `shape` (its length is a
// multiple of 64).
std::string npy_header(NpyType type, const std::vector<std::uint64_t>& shape);

class NpyWriter {
 public:
  // Creates `path`'s temporary sibling with the header, sized for the whole
  // array (unwritten elements read as zero). Throws std::runtime_error
  // naming the file on any I/O error.
  NpyWriter(std::filesystem::path path, NpyType type, std::vector<std::uint64_t> shape);
  ~NpyWriter();  // removes the temporary file unless finish() ran (files.h: created fresh, never through a link)
  NpyWriter(const NpyWriter&) = delete;
  NpyWriter& operator=(const NpyWriter&) = delete;

  // Writes `count` elements (of the array's type, host order: x86-64 is
  // little-endian) at element index `first` (C order). Thread-safe for
  // disjoint ranges.
  void write(std::uint64_t first, const void* data, std::uint64_t count);

  // Flushes, closes and renames the file to its name.
  void finish();

  std::uint64_t elements() const { return elements_; }

 private:
  std::filesystem::path path_;
  std::size_t element_size_;
  std::uint64_t elements_ = 1;
  std::uint64_t data_offset_ = 0;
  std::unique_ptr<TempFile> file_;  // null once finished
  int fd_ = -1;                     // file_'s, for the positioned writes
};

}  // namespace plancheck
