// SPDX-License-Identifier: MIT
// Shared by the fuzz targets: a scratch folder per process, a small scene
// written into it, and an independent count of a plan's data rows.
#pragma once

#include "src/scene/scene.h"

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace plancheck::fuzz {

// A folder of this process's own (/tmp/plancheck-fuzz-<pid>), made on first
// use and removed at exit, so parallel fuzz jobs never share files.
const std::filesystem::path& scratch();

void write_file(const std::filesystem::path& file, std::string_view bytes);

// A small scene in scratch(): model.obj (a static slab and four moving boxes)
// and dem.asc, and scene.json driving the boxes with every action kind
// (rotate, translate along an axis, free translate, scale; all with limits).
// Returns the path of scene.json.
std::filesystem::path write_scene();

// The data rows of a plan CSV counted by the contract (docs/formats.md "Plan file")
// without the loader: after an optional UTF-8 byte order mark, lines before
// the header that are blank or start with '#' are skipped, the first other
// line is the header, and every later line that is not blank is a row.
// Spaces and tabs are trimmed at both ends of a line, '\r' at its end.
std::size_t plan_rows(std::string_view text);

// The loaders report bad input by throwing InputError; the fuzz targets let
// only that through. Anything else (another exception, a crash, a sanitizer
// report, a hang) is a finding. Aborts with a message when `ok` is false.
void require(bool ok, const char* what);

}  // namespace plancheck::fuzz
