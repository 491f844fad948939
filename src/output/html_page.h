// SPDX-License-Identifier: MIT
// One self-contained HTML page: the page's data (JSON) and the viewer's
// JavaScript bundle (src/viewer, built by esbuild and embedded into the
// binary) inline, so the file opens from disk with no server and no network.
#pragma once

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

// Writes `file` (through a temporary file renamed into place): `json` is
// the page data, read by the viewer from <script id="plancheck-data">.
void write_html_page(const std::filesystem::path& file, std::string_view title, std::string_view json);

// The JSON text held by a page write_html_page wrote (tests read it back).
std::string html_page_data(std::string_view page);

}  // namespace plancheck
