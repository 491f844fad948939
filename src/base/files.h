// SPDX-License-Identifier: MIT
// Files from other people, and files written beside theirs.
//
// Reading: a path named by a user (scene, plan, URDF, partial result) must be
// a regular file: a device, FIFO, socket or folder is refused at once (the
// open does not block on a FIFO), and nothing is read past a size no real
// file of that kind reaches, so a lying or endless file costs no memory.
//
// Writing: every file plancheck writes goes first to a fresh temporary beside
// it, created with O_CREAT | O_EXCL | O_NOFOLLOW under an unpredictable name
// (nothing there is opened, let alone followed, and a name taken is never
// reused), then renamed over the final name: rename() replaces a link or a
// file standing there and never writes through it. A run that fails leaves
// the temporary removed and the old file as it was.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace plancheck {

// Sizes no real input reaches (docs/trust-boundaries.md): past them a file is
// refused with a message naming it (and the line).
inline constexpr std::uint64_t kMaxSceneFileBytes = std::uint64_t{64} << 20;  // scene JSON, URDF, SRDF, package.xml
inline constexpr std::size_t kMaxLineBytes = std::size_t{1} << 20;             // one line of a plan

// The bytes of `file`, a regular file of at most max_bytes; `what` names the
// kind of file in messages ("scene file", "plan file"). Throws InputError.
std::string read_regular_file(const std::filesystem::path& file, std::uint64_t max_bytes, const std::string& what);

// Opens `file` for reading as read_regular_file does and hands out its lines
// one at a time (without the '\n'), each at most kMaxLineBytes: memory is one
// line, whatever the file's size. Throws InputError naming the file and line.
class LineReader {
 public:
  LineReader(const std::filesystem::path& file, const std::string& what);
  ~LineReader();
  LineReader(const LineReader&) = delete;
  LineReader& operator=(const LineReader&) = delete;

  // The next line into `line`; false at the end of the file.
  bool next(std::string& line);
  long line_number() const { return line_no_; }
  const std::filesystem::path& file() const { return file_; }

 private:
  bool fill();
  std::filesystem::path file_;
  int fd_ = -1;
  std::string buffer_;
  std::size_t at_ = 0;
  bool eof_ = false;
  long line_no_ = 0;
};

// A fresh temporary beside `final_path` (see the top of this file), renamed
// over it by commit(); removed by the destructor when not committed.
class TempFile {
 public:
  explicit TempFile(std::filesystem::path final_path);
  ~TempFile();
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;

  int fd() const { return fd_; }
  const std::filesystem::path& path() const { return temp_; }
  const std::filesystem::path& final_path() const { return final_; }
  void write(std::string_view bytes);  // appends all of it or throws
  void commit();                       // close, then rename over the final name

 private:
  std::filesystem::path final_, temp_;
  int fd_ = -1;
};

// The whole of `bytes` as `file`, through a TempFile.
void write_file_atomically(const std::filesystem::path& file, std::string_view bytes);

// A file to be continued in place (a journal, a partial result): opened for
// writing without following a link, and only when it is a regular file.
// keep_bytes == 0: whatever stands at the name (a link included: the link is
// removed, never followed) is replaced by a new empty file. Returns the fd.
int open_for_append(const std::filesystem::path& file, std::uint64_t keep_bytes);

// Whether `file` is a symbolic link (not followed).
bool is_link(const std::filesystem::path& file);

}  // namespace plancheck
