// SPDX-License-Identifier: MIT
// Input errors: thrown at the edges (loaders, parsers) with a message that
// names the file and the line, field or node at fault. The command line turns
// one into a single stderr line and exit status 2.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>

namespace plancheck {

class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& message) : std::runtime_error(message) {}
};

// "file: what" or "file:line: what" (line > 0) or "file:line:column: what".
inline std::string located(const std::filesystem::path& file, const std::string& what,
                           long line = 0, long column = 0) {
  std::string s = file.string();
  if (line > 0) s.append(":").append(std::to_string(line));
  if (line > 0 && column > 0) s.append(":").append(std::to_string(column));
  return s.append(": ").append(what);
}

[[noreturn]] inline void fail(const std::filesystem::path& file, const std::string& what,
                              long line = 0, long column = 0) {
  throw InputError(located(file, what, line, column));
}

}  // namespace plancheck
