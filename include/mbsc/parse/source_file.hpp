// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// Reading model files: regular files only, at most limits::kMaxFileBytes, and a read
/// error is an error (never an empty file). A device, a pipe or a folder is refused
/// before anything is read from it, so `include "/dev/zero"` neither hangs nor fills
/// the memory.
#include <cstddef>
#include <string>

namespace mbsc::parse {

/// Reads the whole file at `path` into `text`. On failure returns false and sets `why`
/// to a short reason ("no such file", "is a folder", "is larger than 16 MiB", ...).
bool read_source_file(const std::string& path, std::string& text, std::string& why,
                      std::size_t max_bytes);

}  // namespace mbsc::parse
