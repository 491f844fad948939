// SPDX-License-Identifier: MIT
// Names from other people's files, checked where they are read and escaped
// where they are shown: a name is valid UTF-8 (checked by the loaders, so
// every writer can trust it), and on a terminal no name can move the cursor,
// clear the screen or start a new line (printable()).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace plancheck {

// The byte offset of the first byte that is not part of well-formed UTF-8
// (no overlong forms, no surrogates, nothing above U+10FFFF), or npos.
inline std::size_t invalid_utf8_at(std::string_view s) {
  const auto* p = reinterpret_cast<const unsigned char*>(s.data());
  const std::size_t n = s.size();
  std::size_t i = 0;
  while (i < n) {
    const unsigned c = p[i];
    if (c < 0x80) {
      ++i;
      continue;
    }
    std::size_t len = 0;
    unsigned lo = 0x80, hi = 0xBF;  // the allowed range of the second byte
    if (c >= 0xC2 && c <= 0xDF) {
      len = 2;
    } else if (c >= 0xE0 && c <= 0xEF) {
      len = 3;
      if (c == 0xE0) lo = 0xA0;
      if (c == 0xED) hi = 0x9F;
    } else if (c >= 0xF0 && c <= 0xF4) {
      len = 4;
      if (c == 0xF0) lo = 0x90;
      if (c == 0xF4) hi = 0x8F;
    } else {
      return i;
    }
    if (i + len > n || p[i + 1] < lo || p[i + 1] > hi) return i;
    for (std::size_t k = 2; k < len; ++k)
      if (p[i + k] < 0x80 || p[i + k] > 0xBF) return i;
    i += len;
  }
  return std::string_view::npos;
}

inline bool valid_utf8(std::string_view s) { return invalid_utf8_at(s) == std::string_view::npos; }

// `s` fit for a terminal or a one-line message: control characters (C0,
// DEL, C1: U+0080-U+009F) and bytes that are not UTF-8 as \n, \t, \xNN or
// \u{NN}; all other text (any script, backslashes too) as it is.
inline std::string printable(std::string_view s) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string out;
  out.reserve(s.size());
  std::size_t i = 0;
  while (i < s.size()) {
    const std::size_t bad = invalid_utf8_at(s.substr(i));
    const std::size_t good_end = bad == std::string_view::npos ? s.size() : i + bad;
    for (; i < good_end; ++i) {
      const auto c = static_cast<unsigned char>(s[i]);
      if (c == 0xC2 && i + 1 < good_end && static_cast<unsigned char>(s[i + 1]) < 0xA0) {  // C1 control
        const auto c1 = static_cast<unsigned char>(s[i + 1]);
        out += "\\u{";
        out += kHex[c1 >> 4];
        out += kHex[c1 & 15];
        out += '}';
        ++i;
      } else if (c == '\n') {
        out += "\\n";
      } else if (c == '\t') {
        out += "\\t";
      } else if (c == '\r') {
        out += "\\r";
      } else if (c < 0x20 || c == 0x7F) {
        out += "\\x";
        out += kHex[c >> 4];
        out += kHex[c & 15];
      } else {
        out += static_cast<char>(c);
      }
    }
    if (i < s.size()) {  // one byte that is not UTF-8
      const auto c = static_cast<unsigned char>(s[i]);
      out += "\\x";
      out += kHex[c >> 4];
      out += kHex[c & 15];
      ++i;
    }
  }
  return out;
}

}  // namespace plancheck
