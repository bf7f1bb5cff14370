// SPDX-License-Identifier: GPL-2.0-or-later
/// The environments and line breaking of `mbsc print --latex` (latex_layout.hpp).
#include "mbsc/driver/latex_layout.hpp"

#include <fmt/format.h>

#include <cctype>

#include "mbsc/driver/latex_names.hpp"

namespace mbsc::driver {

namespace latex_layout_detail {
namespace {

bool is_letter(char c) { return std::isalpha(static_cast<unsigned char>(c)) != 0; }

/// The command word that starts at text[i] == '\\' ("" for a control symbol such as \,).
std::string command_at(const std::string& text, std::size_t i) {
  std::size_t j = i + 1;
  while (j < text.size() && is_letter(text[j])) ++j;
  return text.substr(i + 1, j - i - 1);
}

}  // namespace

int latex_width(const std::string& latex) {
  int w = 0;
  for (std::size_t i = 0; i < latex.size(); ++i) {
    const char c = latex[i];
    if (c == '\\') {
      const std::string word = command_at(latex, i);
      if (word.empty()) {  // \, \{ ...
        w += latex.compare(i, 2, "\\,") == 0 ? 0 : 1;
        ++i;
        continue;
      }
      i += word.size();
      static const char* const silent[] = {"left", "right", "frac", "mathrm", "dot", "ddot", "dddot", "bar",
                                           "operatorname", "text", "sqrt"};
      static const char* const spelled[] = {"sin", "cos", "tan", "ln", "log", "exp", "sinh", "cosh", "tanh",
                                            "arcsin", "arccos", "arctan"};
      bool done = false;
      for (const char* s : silent) done = done || word == s;
      for (const char* s : spelled)
        if (!done && word == s) {
          w += static_cast<int>(word.size());
          done = true;
        }
      if (word == "quad") w += 2;
      else if (!done) w += 1;
      continue;
    }
    if (c == '{' || c == '}' || c == '^' || c == '_' || c == ' ') continue;
    ++w;
  }
  return w;
}

std::vector<std::string> break_terms(const std::string& rhs, int width) {
  std::vector<std::string> lines;
  std::vector<char> open;  // 'b' a brace group, 'l' a \left ... \right pair
  std::string prefix;      // \left. openers that start the current line
  std::size_t start = 0;
  for (std::size_t i = 0; i < rhs.size(); ++i) {
    const char c = rhs[i];
    if (c == '\\') {
      const std::string word = command_at(rhs, i);
      if (word.empty()) {
        ++i;  // an escaped character: \{ counts for no group
        continue;
      }
      if (word == "left") open.push_back('l');
      if (word == "right" && !open.empty()) open.pop_back();
      i += word.size();
      continue;
    }
    if (c == '{') open.push_back('b');
    if (c == '}' && !open.empty()) open.pop_back();
    const bool term = rhs.compare(i, 3, " + ") == 0 || rhs.compare(i, 3, " - ") == 0;
    if (!term) continue;
    bool in_braces = false;
    for (char o : open) in_braces = in_braces || o == 'b';
    if (in_braces) continue;
    const std::string piece = prefix + rhs.substr(start, i - start);
    if (latex_width(piece) < width) continue;
    std::string closers, openers;
    for (std::size_t k = 0; k < open.size(); ++k) {
      closers += " \\right.";
      openers += "\\left. ";
    }
    lines.push_back(piece + closers);
    prefix = openers;
    start = i + 1;  // the next line starts with the sign
  }
  lines.push_back(prefix + rhs.substr(start));
  return lines;
}

std::string wrap_source(const std::string& text, std::size_t columns) {
  const std::string indent = "    ";
  std::string out;
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    const bool newline = end != std::string::npos;
    if (!newline) end = text.size();
    const std::string line = text.substr(pos, end - pos);
    pos = newline ? end + 1 : end;
    const std::size_t first = line.find_first_not_of(' ');
    const bool comment = first != std::string::npos && line[first] == '%';
    // Pieces of the line, by index (a formula may be one line of megabytes): each cut is
    // the last space within the columns (else the first after them) that is neither an
    // escaped space "\ " nor the indentation.
    std::size_t begin = 0;
    bool continued = false;
    while (!comment && first != std::string::npos && line.size() - begin + (continued ? indent.size() : 0) > columns) {
      const std::size_t floor = continued ? begin : first;
      auto breakable = [&](std::size_t k) { return line[k] == ' ' && k > floor && line[k - 1] != '\\'; };
      const std::size_t limit = begin + columns - (continued ? indent.size() : 0);
      std::size_t cut = std::string::npos;
      for (std::size_t k = limit; k > floor && cut == std::string::npos; --k)
        if (breakable(k)) cut = k;
      for (std::size_t k = limit + 1; k < line.size() && cut == std::string::npos; ++k)
        if (breakable(k)) cut = k;
      if (cut == std::string::npos || line.find_first_not_of(' ', cut + 1) == std::string::npos) break;
      out += (continued ? indent : "") + line.substr(begin, cut - begin) + "\n";
      begin = cut + 1;
      continued = true;
    }
    out += (continued ? indent : "") + line.substr(begin);
    if (newline) out += "\n";
  }
  return out;
}

}  // namespace latex_layout_detail

namespace {

using latex_layout_detail::break_terms;
using latex_layout_detail::latex_width;

constexpr int kLineWidth = 56;    // glyphs on one line of a displayed formula
constexpr int kCellWidth = 22;    // the widest entry a pmatrix takes
constexpr std::size_t kMaxColumns = 10;  // amsmath's pmatrix limit (MaxMatrixCols)

/// The letter of a matrix title: M, h, ...; fbar is \bar{f}; a phrase is upright text.
std::string title_symbol(const std::string& title) {
  if (title == "fbar") return "\\bar{f}";
  for (char c : title)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return "\\text{" + latex_escape_text(title) + "}";
  return latex_symbol(title);
}

}  // namespace

std::string latex_escape_text(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '\\': out += "\\textbackslash{}"; break;
      case '~': out += "\\textasciitilde{}"; break;
      case '^': out += "\\textasciicircum{}"; break;
      case '{':
      case '}':
      case '_':
      case '%':
      case '$':
      case '#':
      case '&':
        out += '\\';
        out += c;
        break;
      default:
        if (static_cast<unsigned char>(c) >= 0x20 && c != 0x7F) out += c;
    }
  }
  return out;
}

std::string latex_equations(const std::string& comment, const std::vector<LatexEquation>& equations) {
  if (equations.empty()) return "";
  std::string out = "% " + comment + "\n\\begin{align*}\n";
  for (std::size_t k = 0; k < equations.size(); ++k) {
    const auto& eq = equations[k];
    const auto lines = break_terms(eq.rhs, kLineWidth);
    out += "  " + eq.lhs + " &= " + lines[0];
    if (!eq.note.empty()) out += " && \\text{" + latex_escape_text(eq.note) + "}";
    for (std::size_t j = 1; j < lines.size(); ++j) out += " \\\\\n  &\\quad " + lines[j];
    out += k + 1 < equations.size() ? " \\\\\n" : "\n";
  }
  out += "\\end{align*}\n\n";
  return latex_layout_detail::wrap_source(out, 100);
}

std::string latex_matrix(const std::string& title, const std::vector<std::string>& rows,
                         const std::vector<std::string>& cols, const std::vector<std::vector<std::string>>& cells,
                         const std::map<std::string, std::string>& symbols) {
  const std::string comment =
      fmt::format("{}: rows ({}), columns ({})", title, fmt::join(rows, ", "), fmt::join(cols, ", "));
  // The rates: one equation per coordinate, \dot{q} = its rate.
  if (title.rfind("kinematic transformations", 0) == 0 && cols.size() == 1) {
    std::vector<LatexEquation> eqs;
    for (std::size_t i = 0; i < rows.size(); ++i) eqs.push_back({latex_symbol(rows[i], symbols), cells[i][0], ""});
    return latex_equations(comment, eqs);
  }
  const std::string letter = title_symbol(title);
  if (rows.empty() || cols.empty()) return "% " + comment + ": empty\n\n";
  bool small = cols.size() <= kMaxColumns;
  for (const auto& row : cells) {
    int width = 0;
    for (const auto& cell : row) {
      small = small && latex_width(cell) <= kCellWidth;
      width += latex_width(cell) + 2;
    }
    small = small && width <= kLineWidth;
  }
  if (small) {
    std::string out = "% " + comment + "\n\\begin{equation*}\n  " + letter + " = \\begin{pmatrix}\n";
    for (std::size_t i = 0; i < cells.size(); ++i)
      out += fmt::format("    {}{}\n", fmt::join(cells[i], " & "), i + 1 < cells.size() ? " \\\\" : "");
    out += "  \\end{pmatrix}\n\\end{equation*}\n\n";
    return latex_layout_detail::wrap_source(out, 100);
  }
  // Too wide for a matrix: the nonzero entries, one per line.
  const bool column = cols.size() == 1;
  std::vector<LatexEquation> eqs;
  for (std::size_t i = 0; i < cells.size(); ++i)
    for (std::size_t j = 0; j < cells[i].size(); ++j) {
      if (cells[i][j] == "0") continue;
      const std::string index = column ? std::to_string(i + 1) : fmt::format("{},{}", i + 1, j + 1);
      eqs.push_back({letter + "_{" + index + "}", cells[i][j], ""});
    }
  if (eqs.empty()) eqs.push_back({letter, "0", ""});
  return latex_equations(comment, eqs);
}

std::string latex_document(const std::string& model, const std::string& subsystem, const std::string& body) {
  std::string heading = "Model \\texttt{" + latex_escape_text(model) + "}";
  if (!subsystem.empty()) heading = "Subsystem \\texttt{" + latex_escape_text(subsystem) + "} of the m" + heading.substr(1);
  return "% Written by mbsc print --standalone: compile with pdflatex or lualatex.\n"
         "\\documentclass{article}\n"
         "\\usepackage{amsmath}\n"
         "% Wider lines than the article default, and equations that may break across pages.\n"
         "\\addtolength{\\textwidth}{4cm}\n"
         "\\addtolength{\\oddsidemargin}{-2cm}\n"
         "\\addtolength{\\evensidemargin}{-2cm}\n"
         "\\allowdisplaybreaks\n"
         "\\begin{document}\n"
         "\\section*{" +
         heading + "}\n\n" + body + "\\end{document}\n";
}

}  // namespace mbsc::driver
