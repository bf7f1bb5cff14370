// SPDX-License-Identifier: GPL-2.0-or-later
/// The environments and line breaking of `mbsc print --latex` (latex_layout.hpp).
#include "mbsc/print/latex_layout.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>

#include "mbsc/print/latex_names.hpp"

namespace mbsc::print {

namespace latex_layout_detail {

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
using latex_layout_detail::latex_points;
using latex_layout_detail::unfold_wide;

/// The widest line of a displayed formula, in points: the text width of the standalone
/// document (458pt) less a margin for the estimate's error.
constexpr double kLineWidth = 400.0;
constexpr double kEquals = 13.4;  // "=" and its spaces
constexpr double kQuad = 10.0;    // the indentation of a continued line
constexpr std::size_t kMaxRows = 120;    // rows of one align*
constexpr std::size_t kMaxColumns = 10;  // amsmath's pmatrix limit (MaxMatrixCols)

/// The symbol of a matrix of the method: bold (\mathbf{M}, \bar{\mathbf{f}}), so that it
/// never reads as a model's own symbol (a parameter M); a phrase is upright text.
std::string title_symbol(const std::string& title) {
  if (title == "fbar") return "\\bar{\\mathbf{f}}";
  for (char c : title)
    if (!std::isalpha(static_cast<unsigned char>(c))) return "\\text{" + latex_escape_text(title) + "}";
  return "\\mathbf{" + title + "}";
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
  // A left-hand side longer than this gets lines of its own (M z' of an equation of
  // motion); the others share the first column, whose width every line then loses.
  const double long_lhs = 0.3 * kLineWidth;
  double column = 0;
  for (const auto& eq : equations) {
    const double w = latex_points(eq.lhs);
    if (w <= long_lhs) column = std::max(column, w);
  }
  const double room = kLineWidth - column;
  std::vector<std::string> lines;  // the rows of the align*
  for (const auto& eq : equations) {
    const std::string tag = eq.note.empty() ? "" : " \\tag*{" + latex_escape_text(eq.note) + "}";
    const auto rhs = break_terms(unfold_wide(eq.rhs, room - kQuad - 20.0), room - kEquals, room - kQuad);
    if (latex_points(eq.lhs) <= long_lhs) {
      lines.push_back("  " + eq.lhs + " &= " + rhs[0] + tag);
    } else {
      const auto lhs = break_terms(unfold_wide(eq.lhs, room - kQuad - 20.0), room, room - kQuad);
      lines.push_back("  & " + lhs[0] + tag);
      for (std::size_t j = 1; j < lhs.size(); ++j) lines.push_back("  &\\quad " + lhs[j]);
      lines.push_back("  &= " + rhs[0]);
    }
    for (std::size_t j = 1; j < rhs.size(); ++j) lines.push_back("  &\\quad " + rhs[j]);
  }
  // TeX holds a whole alignment in memory: a long one goes on in a new align*.
  std::string out = "% " + comment + "\n\\begin{align*}\n";
  for (std::size_t k = 0; k < lines.size(); ++k) {
    const bool last = k + 1 == lines.size(), cut = !last && (k + 1) % kMaxRows == 0;
    out += lines[k] + (last || cut ? "\n" : " \\\\\n");
    if (cut) out += "\\end{align*}\n\\begin{align*}\n";
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
  // A pmatrix when it fits on a line: its columns as wide as their widest entries.
  bool small = cols.size() <= kMaxColumns;
  double width = latex_points(letter) + kEquals + 12.0;
  for (std::size_t j = 0; small && j < cols.size(); ++j) {
    double widest = 0;
    for (const auto& row : cells) widest = std::max(widest, latex_points(row[j]));
    width += widest + 10.0;
  }
  small = small && width <= kLineWidth;
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

}  // namespace mbsc::print
