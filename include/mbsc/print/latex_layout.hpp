// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// The environments of `mbsc print --latex`: what it writes pastes into a document that
/// loads amsmath, and with --standalone is such a document. Entries are LaTeX already
/// (canonical_text); here they are set in equation* / align* environments, long ones
/// broken at their terms so that no line runs past the margin, and every source
/// line kept short (TeX reads a file line by line).
#include <map>
#include <string>
#include <vector>

namespace mbsc::print {

/// A labelled matrix: a comment naming its rows and columns (model names), then a pmatrix
/// in an equation* when its columns fit on a line, else its nonzero entries one per line
/// in an align* (\mathbf{M}_{i,j} = ..., or \mathbf{h}_{i} for a column): the method's
/// letters are bold, apart from any symbol of the model. The kinematic
/// transformations print as one equation per coordinate rate (\dot{q} = ...).
/// `symbols`: the model's `latex` statements, for the row symbols of the rates.
std::string latex_matrix(const std::string& title, const std::vector<std::string>& rows,
                         const std::vector<std::string>& cols, const std::vector<std::vector<std::string>>& cells,
                         const std::map<std::string, std::string>& symbols);

/// One aligned equation: lhs = rhs, with an optional note set as a tag at its right.
struct LatexEquation {
  std::string lhs, rhs, note;
};

/// Equations in an align* under a comment line; "" when there are none. Every line fits
/// the standalone document's text width: the right-hand sides broken (break_terms), a
/// long left-hand side on lines of its own with "= ..." after them, a long list in
/// several align* (TeX holds one alignment in memory at a time).
std::string latex_equations(const std::string& comment, const std::vector<LatexEquation>& equations);

/// `text` set in upright text mode: the characters LaTeX reserves are escaped.
std::string latex_escape_text(const std::string& text);

/// A complete document around `body` (the output of print --latex): article class,
/// amsmath, a heading naming the model (and the subsystem, when not the whole model).
std::string latex_document(const std::string& model, const std::string& subsystem, const std::string& body);

/// The pieces of the layout, exposed for their tests.
namespace latex_layout_detail {
/// About how wide `latex` sets in a display at 10pt, in points (Computer Modern's glyph
/// widths; scripts smaller, a fraction as wide as its wider part, a subscript and a
/// superscript stacked).
double latex_points(const std::string& latex);
/// `latex` with every \frac and \sqrt wider than `points` written so that it can break:
/// (num) / (den) and (x)^{1/2}, each part in \left( ... \right) unless a single atom.
std::string unfold_wide(const std::string& latex, double points);
/// `formula` broken into lines, the first at most `first` points wide, the others `rest`:
/// before a term's sign (" + ", " - ") outside braces, preferring those outside a
/// function's argument; between factors ("\cdot" starts the next line) where a term is
/// wider than a line. A break inside \left( ... \right) closes it with \right. and reopens
/// it with \left. on the next line. A short last line is balanced with the one before
/// or joined to it (no lone "- \tau_{3}").
std::vector<std::string> break_terms(const std::string& formula, double first, double rest);
/// Each line of `text` longer than `columns` characters (but comment lines) split at
/// spaces: TeX reads a newline in a formula as a space.
std::string wrap_source(const std::string& text, std::size_t columns);
}  // namespace latex_layout_detail

}  // namespace mbsc::print
