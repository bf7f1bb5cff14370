// SPDX-License-Identifier: GPL-2.0-or-later
#include "mbsc/driver/depfile.hpp"

#include <fmt/format.h>

#include "mbsc/diag/diagnostics.hpp"

namespace mbsc::driver {

// Make, Ninja and CMake read a depfile alike for these: "\ " and "\<tab>" are a space and a
// tab inside a name, and 2N+1 backslashes before them are N backslashes and the escaped
// character (so backslashes right before a space or tab are doubled); "\#" is a '#', and
// any backslashes before it stay as they are; "$$" is a '$'.
std::string make_escaped(const std::string& path) {
  std::string out;
  std::size_t backslashes = 0;  // in a row, just written
  for (char c : path) {
    if (c == ' ' || c == '\t') {
      out.append(backslashes, '\\');  // so that they stay backslashes, not an escape
      out += '\\';
    } else if (c == '#') {
      out += '\\';
    } else if (c == '$') {
      out += '$';
    }
    out += c;
    backslashes = c == '\\' ? backslashes + 1 : 0;
  }
  return out;
}

namespace {

/// Why make or ninja would read `c` in a depfile as something other than part of a name
/// (nullptr when it is safe, or escaped by make_escaped).
const char* special_meaning(char c) {
  switch (c) {
    case ';': return "starts a recipe, a command make runs";
    case ':': return "ends a rule's targets";
    case '=': return "makes a target-specific variable assignment";
    case '|': return "separates order-only prerequisites";
    case '%': return "makes a pattern rule";
    case '*': case '?': case '[': case ']': return "is a wildcard make expands";
    case '(': case ')': return "names an archive member";
    case '&': return "groups targets";
    default: break;
  }
  const auto b = static_cast<unsigned char>(c);
  if (c != '\t' && (b < 0x20 || b == 0x7f)) return "is a control character (a line break ends the rule)";
  return nullptr;
}

}  // namespace

bool depfile_text(const std::vector<std::string>& targets, const std::vector<std::string>& prerequisites,
                  std::string& text, std::string& error) {
  for (const auto* list : {&targets, &prerequisites})
    for (const auto& p : *list) {
      for (char c : p)
        if (const char* why = special_meaning(c)) {
          error = fmt::format("mbsc: error: the path '{}' holds '{}', which {} in a depfile; a depfile cannot hold it "
                              "(rename the file or folder, or generate without --depfile)",
                              printable(p), printable(std::string(1, c)), why);
          return false;
        }
      if (p.find("\\#") != std::string::npos) {
        error = fmt::format("mbsc: error: the path '{}' has a '\\' before a '#', which make and ninja read differently "
                            "in a depfile (rename the file or folder, or generate without --depfile)",
                            printable(p));
        return false;
      }
    }
  text.clear();
  for (std::size_t i = 0; i < targets.size(); ++i) text += (i ? " " : "") + make_escaped(targets[i]);
  text += ":";
  for (std::size_t i = 0; i < prerequisites.size(); ++i) text += (i ? " \\\n  " : " ") + make_escaped(prerequisites[i]);
  text += "\n";
  for (std::size_t i = 1; i < prerequisites.size(); ++i) text += "\n" + make_escaped(prerequisites[i]) + ":\n";
  return true;
}

}  // namespace mbsc::driver
