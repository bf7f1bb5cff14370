// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// The numbers or the strings of a JSON array in a command's output, for the linearization tests.
#include <cstdlib>
#include <string>
#include <vector>

namespace mbsc_test {

/// Walks the JSON array that follows "key": in `text` (nested arrays flattened), passing
/// each number to `number` and each string (without its quotes) to `string`. False when the
/// key is not there.
template <class OnNumber, class OnString>
bool walk_json_array(const std::string& text, const std::string& key, OnNumber number, OnString string) {
  auto at = text.find("\"" + key + "\":");
  if (at == std::string::npos) return false;
  at = text.find('[', at);
  int depth = 0;
  for (std::size_t i = at; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '[') ++depth;
    else if (c == ']' && --depth == 0) break;
    else if (c == '"') {
      const std::size_t end = text.find('"', i + 1);
      string(text.substr(i + 1, end - i - 1));
      i = end;
    } else if (c == '-' || c == '.' || (c >= '0' && c <= '9')) {
      char* end = nullptr;
      number(std::strtod(text.c_str() + i, &end));
      i = static_cast<std::size_t>(end - text.c_str()) - 1;
    }
  }
  return true;
}

/// The numbers of that array; empty when the key is not there.
inline std::vector<double> json_numbers(const std::string& text, const std::string& key) {
  std::vector<double> out;
  walk_json_array(text, key, [&](double v) { out.push_back(v); }, [](const std::string&) {});
  return out;
}

/// The strings of that array (an entry of `mbsc linearize --symbolic --format json` each);
/// empty when the key is not there.
inline std::vector<std::string> json_strings(const std::string& text, const std::string& key) {
  std::vector<std::string> out;
  walk_json_array(text, key, [](double) {}, [&](const std::string& s) { out.push_back(s); });
  return out;
}

}  // namespace mbsc_test
