// SPDX-License-Identifier: GPL-2.0-or-later
/// Is the text of a `latex` statement safe in a formula? (latex_text.hpp)
///
/// Printable ASCII only (pdflatex has no Greek letters in math: \theta, not θ); no
/// character that ends the formula or the line ($ %), starts an alignment cell (&) or
/// a macro parameter (#); balanced braces and \left ... \right; a ^ or _ with
/// something to apply to; commands by name, but none that ends a line or a paragraph,
/// opens or closes an environment, or defines, reads or writes anything.
#include "mbsc/parse/latex_text.hpp"

#include <array>
#include <cctype>

namespace mbsc::parse {
namespace {

constexpr std::size_t kMaxLength = 200;

bool is_letter(char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z'); }

/// Commands that would break the document around the formula.
bool forbidden_command(const std::string& word) {
  static const std::array<const char*, 30> words = {
      "begin",   "end",        "par",          "newline",  "linebreak", "input",      "include",  "def",
      "edef",    "gdef",       "xdef",         "let",      "futurelet", "newcommand", "renewcommand",
      "providecommand", "DeclareRobustCommand", "catcode", "write", "immediate", "openout", "openin", "read",
      "csname",  "special",    "cr",           "crcr",     "noalign",   "tag",        "label"};
  for (const char* w : words)
    if (word == w) return true;
  return false;
}

/// Control symbols allowed in math: spacing (\, \; \: \! \> and \ ) and escaped
/// characters (\{ \} \| \_ \% \$ \# \&).
bool allowed_control_symbol(char c) {
  for (char ok : std::string(",;:!> {}|_%$#&"))
    if (c == ok) return true;
  return false;
}

}  // namespace

std::string latex_text_problem(const std::string& text) {
  if (text.empty()) return "it is empty";
  if (text.size() > kMaxLength) return "it is longer than " + std::to_string(kMaxLength) + " characters";
  int braces = 0, lefts = 0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    const unsigned char u = static_cast<unsigned char>(c);
    if (u < 0x20 || u == 0x7F) return "it has a control character";
    if (u >= 0x80) return "it has a character outside ASCII (write a command such as \\theta)";
    switch (c) {
      case '$': return "it has '$', which would end the formula";
      case '%': return "it has '%', which would comment out the rest of the line";
      case '&': return "it has '&', which would start a new matrix cell";
      case '#': return "it has '#'";
      case '{': ++braces; break;
      case '}':
        if (--braces < 0) return "it has a '}' without its '{'";
        break;
      case '^':
      case '_': {
        std::size_t j = i + 1;
        while (j < text.size() && text[j] == ' ') ++j;
        if (j == text.size() || text[j] == '}' || text[j] == '^' || text[j] == '_')
          return std::string("it has a '") + c + "' with nothing after it to apply to";
        break;
      }
      case '\\': {
        if (i + 1 == text.size()) return "it ends with a lone '\\'";
        const char next = text[i + 1];
        if (next == '\\') return "it has '\\\\', a line break";
        if (!is_letter(next)) {
          if (!allowed_control_symbol(next)) return std::string("it has '\\") + next + "', which is not for formulas";
          ++i;  // an escaped brace counts for nothing
          break;
        }
        std::size_t j = i + 1;
        while (j < text.size() && is_letter(text[j])) ++j;
        const std::string word = text.substr(i + 1, j - i - 1);
        if (forbidden_command(word)) return "it has '\\" + word + "', which would break the document around the formula";
        if (word == "left") ++lefts;
        if (word == "right" && --lefts < 0) return "it has a '\\right' without its '\\left'";
        i = j - 1;
        break;
      }
      default: break;
    }
  }
  if (braces > 0) return "it has a '{' that is not closed";
  if (lefts > 0) return "it has a '\\left' without its '\\right'";
  return "";
}

}  // namespace mbsc::parse
