// SPDX-License-Identifier: MIT
#include "src/base/files.h"

#include "src/base/error.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <random>
#include <system_error>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace plancheck {
namespace {

std::string errno_text(int err) { return std::strerror(err); }

// O_NONBLOCK: opening a FIFO with no writer would otherwise wait for one.
// The flag is cleared once the file is known to be regular (where it means
// nothing anyway).
int open_regular(const std::filesystem::path& file, const std::string& what, struct stat& st) {
  int fd = -1;
  do {
    fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK | O_NOCTTY);
  } while (fd < 0 && errno == EINTR);
  if (fd < 0) fail(file, "cannot open " + what + ": " + errno_text(errno));
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    const bool dir = S_ISDIR(st.st_mode);
    ::close(fd);
    fail(file, "cannot read " + what + ": " +
                   (dir ? std::string("it is a folder") : std::string("not a regular file (a device, FIFO or socket)")));
  }
  const int flags = ::fcntl(fd, F_GETFL);
  if (flags >= 0) ::fcntl(fd, F_SETFL, flags & ~O_NONBLOCK);
  return fd;
}

ssize_t read_some(int fd, char* data, std::size_t n) {
  ssize_t got;
  do {
    got = ::read(fd, data, n);
  } while (got < 0 && errno == EINTR);
  return got;
}

std::string random_suffix() {
  thread_local std::mt19937_64 rng{(static_cast<std::uint64_t>(std::random_device{}()) << 32) ^
                                   static_cast<std::uint64_t>(::getpid())};
  char buf[24];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(rng()));
  return buf;
}

}  // namespace

std::string read_regular_file(const std::filesystem::path& file, std::uint64_t max_bytes, const std::string& what) {
  struct stat st{};
  const int fd = open_regular(file, what, st);
  if (static_cast<std::uint64_t>(st.st_size) > max_bytes) {
    ::close(fd);
    fail(file, what + " of " + std::to_string(st.st_size) + " bytes, more than the " + std::to_string(max_bytes) +
                   " bytes a real one has");
  }
  std::string bytes(static_cast<std::size_t>(st.st_size), '\0');
  std::size_t have = 0;
  for (;;) {
    if (have == bytes.size()) {
      // The file may have grown since fstat: read on, still within the limit.
      if (bytes.size() >= max_bytes) {
        char probe;
        const ssize_t more = read_some(fd, &probe, 1);
        ::close(fd);
        if (more > 0) fail(file, what + " larger than the " + std::to_string(max_bytes) + " bytes a real one has");
        if (more < 0) fail(file, "cannot read " + what + ": " + errno_text(errno));
        return bytes;
      }
      bytes.resize(std::min<std::uint64_t>(max_bytes, std::max<std::uint64_t>(bytes.size() * 2, 4096)));
    }
    const ssize_t got = read_some(fd, bytes.data() + have, bytes.size() - have);
    if (got < 0) {
      const int err = errno;
      ::close(fd);
      fail(file, "cannot read " + what + ": " + errno_text(err));
    }
    if (got == 0) break;
    have += static_cast<std::size_t>(got);
  }
  ::close(fd);
  bytes.resize(have);
  return bytes;
}

LineReader::LineReader(const std::filesystem::path& file, const std::string& what) : file_(file) {
  struct stat st{};
  fd_ = open_regular(file, what, st);
}

LineReader::~LineReader() {
  if (fd_ >= 0) ::close(fd_);
}

bool LineReader::fill() {
  if (eof_) return false;
  if (at_ > 0) {
    buffer_.erase(0, at_);
    at_ = 0;
  }
  const std::size_t have = buffer_.size();
  buffer_.resize(have + (std::size_t{1} << 16));
  const ssize_t got = read_some(fd_, buffer_.data() + have, buffer_.size() - have);
  if (got < 0) fail(file_, std::string("cannot read: ") + errno_text(errno));
  buffer_.resize(have + static_cast<std::size_t>(got));
  if (got == 0) eof_ = true;
  return got > 0;
}

bool LineReader::next(std::string& line) {
  auto too_long = [&] {
    fail(file_, "line longer than " + std::to_string(kMaxLineBytes) + " bytes (no real file has one)", line_no_ + 1);
  };
  std::size_t scan_from = at_;
  for (;;) {
    const std::size_t nl = buffer_.find('\n', scan_from);
    if (nl != std::string::npos) {
      if (nl - at_ > kMaxLineBytes) too_long();
      line.assign(buffer_, at_, nl - at_);
      at_ = nl + 1;
      ++line_no_;
      return true;
    }
    if (buffer_.size() - at_ > kMaxLineBytes) too_long();
    const std::size_t scanned = buffer_.size() - at_;  // of the line begun at at_
    if (!fill()) {
      if (at_ >= buffer_.size()) return false;
      line.assign(buffer_, at_, std::string::npos);  // a last line without '\n'
      at_ = buffer_.size();
      ++line_no_;
      return true;
    }
    scan_from = at_ + scanned;
  }
}

TempFile::TempFile(std::filesystem::path final_path) : final_(std::move(final_path)) {
  const std::filesystem::path dir = final_.has_parent_path() ? final_.parent_path() : std::filesystem::path(".");
  const std::string base = final_.filename().string();
  for (int attempt = 0; attempt < 100; ++attempt) {
    temp_ = dir / ("." + base + "." + random_suffix() + ".tmp");
    do {
      fd_ = ::open(temp_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
    } while (fd_ < 0 && errno == EINTR);
    if (fd_ >= 0) return;
    if (errno != EEXIST) fail(final_, "cannot write: " + errno_text(errno));
  }
  fail(final_, "cannot write: no fresh temporary name beside it");
}

TempFile::~TempFile() {
  if (fd_ >= 0) ::close(fd_);
  if (!temp_.empty()) ::unlink(temp_.c_str());
}

void TempFile::write(std::string_view bytes) {
  while (!bytes.empty()) {
    const ssize_t n = ::write(fd_, bytes.data(), bytes.size());
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) fail(final_, "write failed: " + errno_text(errno));
    bytes.remove_prefix(static_cast<std::size_t>(n));
  }
}

void TempFile::commit() {
  const int fd = fd_;
  fd_ = -1;
  if (::close(fd) != 0) fail(final_, "write failed: " + errno_text(errno));
  if (::rename(temp_.c_str(), final_.c_str()) != 0) fail(final_, "cannot write: " + errno_text(errno));
  temp_.clear();
}

void write_file_atomically(const std::filesystem::path& file, std::string_view bytes) {
  TempFile f(file);
  f.write(bytes);
  f.commit();
}

int open_for_append(const std::filesystem::path& file, std::uint64_t keep_bytes) {
  int fd = -1;
  if (keep_bytes == 0) {
    if (::unlink(file.c_str()) != 0 && errno != ENOENT) fail(file, "cannot replace: " + errno_text(errno));
    do {
      fd = ::open(file.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
    } while (fd < 0 && errno == EINTR);
    if (fd < 0) fail(file, "cannot write: " + errno_text(errno));
    return fd;
  }
  do {
    fd = ::open(file.c_str(), O_WRONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
  } while (fd < 0 && errno == EINTR);
  if (fd < 0) fail(file, errno == ELOOP ? "is a symbolic link: not written through" : "cannot write: " + errno_text(errno));
  struct stat st{};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    fail(file, "not a regular file: not written");
  }
  const int flags = ::fcntl(fd, F_GETFL);
  if (flags >= 0) ::fcntl(fd, F_SETFL, flags & ~O_NONBLOCK);
  if (::ftruncate(fd, static_cast<off_t>(keep_bytes)) != 0 || ::lseek(fd, 0, SEEK_END) < 0) {
    const int err = errno;
    ::close(fd);
    fail(file, "cannot write: " + errno_text(err));
  }
  return fd;
}

bool is_link(const std::filesystem::path& file) {
  struct stat st{};
  return ::lstat(file.c_str(), &st) == 0 && S_ISLNK(st.st_mode);
}

}  // namespace plancheck
