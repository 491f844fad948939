// SPDX-License-Identifier: MIT
// One self-contained HTML page: the page's data (JSON) and the viewer's
// JavaScript bundle (src/viewer, built by esbuild and embedded into the
// binary) inline, so the file opens from disk with no server and no network.
#pragma once

#include "src/base/files.h"

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace plancheck {

// The embedded viewer bundle (a placeholder script when the build has none:
// PLANCHECK_VIEWER=OFF without PLANCHECK_VIEWER_BUNDLE).
std::string_view viewer_bundle();
// Whether viewer_bundle() is the real viewer.
bool viewer_bundle_is_real();

// Base64 (RFC 4648, with padding) of raw bytes: how geometry and per-state
// arrays travel inside the page's JSON (little-endian float32 / uint32).
std::string base64(const void* data, std::size_t bytes);

// A page written piece by piece, so that no page needs its whole data in
// memory: the head, then the page data (JSON text, streamed in by data()),
// then the viewer, into a fresh temporary (files.h) that finish() renames
// into place (a page never finished leaves no file). The data is read by the viewer from
// <script type="application/json" id="plancheck-data">.
class HtmlPageWriter {
 public:
  HtmlPageWriter(const std::filesystem::path& file, std::string_view title);
  HtmlPageWriter(const HtmlPageWriter&) = delete;
  HtmlPageWriter& operator=(const HtmlPageWriter&) = delete;

  // More of the data's JSON text, made inert inside the page whatever its
  // strings hold: every '<' is written as \u003c (so no "</script" and no
  // "<!--" can end or re-open the element), U+2028/U+2029 as \u2028/\u2029.
  // JSON has '<' only inside strings, where these escapes mean the same.
  void data(std::string_view json);
  void finish();

 private:
  void write(std::string_view bytes);
  void flush();
  TempFile file_;
  std::string buffer_;
};

// The same in one call: `json` is the whole page data.
void write_html_page(const std::filesystem::path& file, std::string_view title, std::string_view json);

// The JSON text held by a page write_html_page wrote (tests read it back).
std::string html_page_data(std::string_view page);

}  // namespace plancheck
