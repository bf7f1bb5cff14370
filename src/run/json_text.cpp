// SPDX-License-Identifier: GPL-2.0-or-later
#include "mbsc/run/json_text.hpp"

#include <fmt/format.h>

namespace mbsc::run {

std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    if (static_cast<unsigned char>(c) < 0x20) {
      out += fmt::format("\\u{:04x}", static_cast<int>(c));
      continue;
    }
    out += c;
  }
  return out + "\"";
}

}  // namespace mbsc::run
