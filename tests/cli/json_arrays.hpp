// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// The numbers of a JSON array in a command's output, for the linearization tests.
#include <cstdlib>
#include <string>
#include <vector>

namespace mbsc_test {

/// The numbers of the JSON array that follows "key": in `text` (nested arrays flattened);
/// empty when the key is not there.
inline std::vector<double> json_numbers(const std::string& text, const std::string& key) {
  std::vector<double> out;
  auto at = text.find("\"" + key + "\":");
  if (at == std::string::npos) return out;
  at = text.find('[', at);
  int depth = 0;
  for (std::size_t i = at; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '[') ++depth;
    else if (c == ']' && --depth == 0) break;
    else if (c == '-' || c == '.' || (c >= '0' && c <= '9')) {
      char* end = nullptr;
      out.push_back(std::strtod(text.c_str() + i, &end));
      i = static_cast<std::size_t>(end - text.c_str()) - 1;
    }
  }
  return out;
}

}  // namespace mbsc_test
