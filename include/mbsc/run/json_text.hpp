// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// JSON text for the commands that write it (`mbsc linearize --format json`).
#include <string>

namespace mbsc::run {

/// `s` as a JSON string literal: quotes and backslashes escaped, control characters as \uXXXX.
std::string json_string(const std::string& s);

}  // namespace mbsc::run
