// SPDX-License-Identifier: GPL-2.0-or-later
#include "renderer.hpp"

#include <cctype>
#include <set>
#include <stdexcept>
#include <vector>

namespace mbsc::emit {

namespace {

std::vector<std::string> split_lines(const std::string& text) {
  std::vector<std::string> lines;
  std::size_t b = 0;
  while (true) {
    const std::size_t e = text.find('\n', b);
    if (e == std::string::npos) {
      lines.push_back(text.substr(b));
      return lines;
    }
    lines.push_back(text.substr(b, e - b));
    b = e + 1;
  }
}

// Lines of a fragment; a final newline ends the last line instead of starting an empty one.
std::vector<std::string> fragment_lines(const std::string& frag) {
  if (frag.empty()) return {};
  std::vector<std::string> lines = split_lines(frag);
  if (lines.size() > 1 && lines.back().empty()) lines.pop_back();
  return lines;
}

bool is_blank(const std::string& s) { return s.find_first_not_of(" \t") == std::string::npos; }

std::string trim(const std::string& s) {
  const std::size_t b = s.find_first_not_of(" \t");
  if (b == std::string::npos) return "";
  const std::size_t e = s.find_last_not_of(" \t");
  return s.substr(b, e - b + 1);
}

bool is_key(const std::string& k) {
  if (k.empty() || !(std::isalpha(static_cast<unsigned char>(k[0])) || k[0] == '_')) return false;
  for (char c : k)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return false;
  return true;
}

struct Piece {
  bool placeholder;
  std::string text;  // literal text, or the key
};

}  // namespace

// Line by line: split each template line into literal text and placeholders, then either
// expand a whole-line placeholder (indented like the line) or substitute inline.
std::string render(const std::string& template_name, const std::string& text, const Fragments& fragments) {
  std::set<std::string> used;
  std::vector<std::string> out;
  const std::vector<std::string> lines = split_lines(text);
  for (std::size_t ln = 0; ln < lines.size(); ++ln) {
    const std::string& line = lines[ln];
    const std::string where = template_name + ":" + std::to_string(ln + 1) + ": ";
    // Tokenise the line.
    std::vector<Piece> pieces;
    bool had_comment = false;
    for (std::size_t pos = 0; pos < line.size();) {
      const std::size_t open = line.find("{{", pos);
      if (open == std::string::npos) {
        pieces.push_back({false, line.substr(pos)});
        break;
      }
      const std::size_t close = line.find("}}", open + 2);
      if (close == std::string::npos) throw std::runtime_error(where + "unterminated '{{'");
      if (open > pos) pieces.push_back({false, line.substr(pos, open - pos)});
      const std::string key = trim(line.substr(open + 2, close - open - 2));
      if (!key.empty() && key[0] == '!') {
        had_comment = true;
      } else {
        if (!is_key(key)) throw std::runtime_error(where + "malformed placeholder '{{" + key + "}}'");
        if (!fragments.count(key)) throw std::runtime_error(where + "unknown key '" + key + "'");
        used.insert(key);
        pieces.push_back({true, key});
      }
      pos = close + 2;
    }
    if (line.find("}}") != std::string::npos && line.find("{{") == std::string::npos)
      throw std::runtime_error(where + "stray '}}'");

    // A line that held only comments disappears.
    std::vector<Piece> kept;
    for (const Piece& p : pieces)
      if (p.placeholder || !p.text.empty()) kept.push_back(p);
    bool all_blank = true;
    for (const Piece& p : kept)
      if (p.placeholder || !is_blank(p.text)) all_blank = false;
    if (had_comment && all_blank) continue;

    // Whole-line placeholder: every fragment line gets the line's indentation.
    const bool leading_ws = kept.size() == 2 && !kept[0].placeholder && is_blank(kept[0].text) && kept[1].placeholder;
    const bool alone = kept.size() == 1 && kept[0].placeholder;
    if (leading_ws || alone) {
      const std::string indent = leading_ws ? kept[0].text : "";
      for (const std::string& fl : fragment_lines(fragments.at(kept.back().text)))
        out.push_back(fl.empty() ? fl : indent + fl);
      continue;
    }
    // Inline placeholders: later fragment lines are indented to the placeholder's column.
    std::string cur;
    for (const Piece& p : kept) {
      if (!p.placeholder) {
        cur += p.text;
        continue;
      }
      const std::vector<std::string> fl = fragment_lines(fragments.at(p.text));
      const std::string indent(cur.size(), ' ');
      for (std::size_t i = 0; i < fl.size(); ++i) {
        if (i == 0) {
          cur += fl[i];
        } else {
          out.push_back(cur);
          cur = fl[i].empty() ? fl[i] : indent + fl[i];
        }
      }
    }
    out.push_back(cur);
  }
  for (const auto& kv : fragments)
    if (!used.count(kv.first)) throw std::runtime_error(template_name + ": unused fragment '" + kv.first + "'");
  std::string result;
  for (std::size_t i = 0; i < out.size(); ++i) {
    if (i) result += '\n';
    result += out[i];
  }
  return result;
}

}  // namespace mbsc::emit
