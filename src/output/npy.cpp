// SPDX-License-Identifier: MIT
#include "src/output/npy.h"

#include "src/base/files.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <system_error>
#include <utility>

namespace plancheck {

namespace {

[[noreturn]] void fail(const std::filesystem::path& file, const std::string& what, int err) {
  throw std::runtime_error("cannot write " + file.string() + ": " + what + " (" + std::strerror(err) + ")");
}

std::size_t element_size(NpyType type) { return type == NpyType::kUint8 ? 1 : 4; }

// Writes all of [data, data + size) at `offset`.
void write_at(int fd, const std::filesystem::path& file, const char* data, std::uint64_t size, std::uint64_t offset) {
  while (size > 0) {
    const std::size_t chunk = static_cast<std::size_t>(std::min<std::uint64_t>(size, std::uint64_t{1} << 30));
    const ssize_t n = ::pwrite(fd, data, chunk, static_cast<off_t>(offset));
    if (n < 0) {
      if (errno == EINTR) continue;
      fail(file, "write", errno);
    }
    if (n == 0) fail(file, "write", EIO);
    data += n;
    size -= static_cast<std::uint64_t>(n);
    offset += static_cast<std::uint64_t>(n);
  }
}

}  // namespace

std::string npy_header(NpyType type, const std::vector<std::uint64_t>& shape) {
  std::string dict = "{'descr': '";
  dict += type == NpyType::kUint8 ? "|u1" : "<f4";
  dict += "', 'fortran_order': False, 'shape': (";
  for (std::size_t i = 0; i < shape.size(); ++i) {
    dict += std::to_string(shape[i]);
    if (shape.size() == 1 || i + 1 < shape.size()) dict += ",";
    if (i + 1 < shape.size()) dict += " ";
  }
  dict += "), }";
  // Magic (6) + version (2) + length (2) + dict + padding + '\n', a multiple of 64.
  const std::size_t unpadded = 10 + dict.size() + 1;
  dict.append((64 - unpadded % 64) % 64, ' ');
  dict += '\n';
  const std::size_t len = dict.size();
  std::string out = "\x93NUMPY";
  out += static_cast<char>(1);
  out += static_cast<char>(0);
  out += static_cast<char>(len & 0xff);
  out += static_cast<char>((len >> 8) & 0xff);
  return out + dict;
}

NpyWriter::NpyWriter(std::filesystem::path path, NpyType type, std::vector<std::uint64_t> shape)
    : path_(std::move(path)), element_size_(element_size(type)) {
  for (std::uint64_t d : shape) {
    if (d != 0 && elements_ > std::numeric_limits<std::uint64_t>::max() / 8 / d)
      throw std::runtime_error("cannot write " + path_.string() + ": the array is too large");
    elements_ *= d;
  }
  const std::string header = npy_header(type, shape);
  data_offset_ = header.size();
  file_ = std::make_unique<TempFile>(path_);
  fd_ = file_->fd();
  write_at(fd_, file_->path(), header.data(), header.size(), 0);
  if (::ftruncate(fd_, static_cast<off_t>(data_offset_ + elements_ * element_size_)) != 0)
    fail(file_->path(), "size", errno);  // file_ removes the temporary
}

NpyWriter::~NpyWriter() = default;  // file_ removes an unfinished temporary

void NpyWriter::write(std::uint64_t first, const void* data, std::uint64_t count) {
  if (!file_) throw std::logic_error("NpyWriter::write after finish");
  if (first > elements_ || count > elements_ - first)
    throw std::out_of_range("NpyWriter::write beyond the array of " + path_.string());
  write_at(fd_, file_->path(), static_cast<const char*>(data), count * element_size_, data_offset_ + first * element_size_);
}

void NpyWriter::finish() {
  if (!file_) return;
  file_->commit();
  file_.reset();
  fd_ = -1;
}

}  // namespace plancheck
