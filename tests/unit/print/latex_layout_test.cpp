// SPDX-License-Identifier: GPL-2.0-or-later
// The layout of mbsc print --latex: the estimated widths of formulas, long formulas
// broken at their terms (or factors) within a width with their \left ... \right pairs
// kept balanced on every line, wide fractions made breakable, long source lines split at spaces
// only, and the choice between a pmatrix and one entry per line.
#include <catch2/catch.hpp>

#include <string>
#include <vector>

#include "mbsc/print/latex_layout.hpp"

using namespace mbsc::print;
using namespace mbsc::print::latex_layout_detail;

namespace {

/// Occurrences of `what` in `text`.
int count(const std::string& text, const std::string& what) {
  int n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

/// The braces of `text` (escaped ones aside) close in order and all close.
bool braces_balanced(const std::string& text) {
  int depth = 0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '\\') {
      ++i;
      continue;
    }
    depth += text[i] == '{' ? 1 : text[i] == '}' ? -1 : 0;
    if (depth < 0) return false;
  }
  return depth == 0;
}

/// a_{1} + a_{2} + ... + a_{n}
std::string long_sum(int n) {
  std::string s;
  for (int i = 1; i <= n; ++i) s += (i > 1 ? " + " : "") + std::string("a_{") + std::to_string(i) + "}";
  return s;
}

}  // namespace

TEST_CASE("latex_points: the width of the glyphs, not of the markup", "[latex]") {
  const double x = latex_points("x");
  CHECK(x > 4.0);
  CHECK(x < 7.0);
  // Scripts are smaller, and a subscript and a superscript stack.
  CHECK(latex_points("x_{1}") < x + 5.0);
  CHECK(latex_points("x_{1}^{2}") == Approx(latex_points("x_{1}")));
  // A fraction is as wide as its wider part, an accent adds nothing.
  CHECK(latex_points("\\frac{a + b}{c}") < latex_points("a + b") + 3.0);
  CHECK(latex_points("\\dot{w}") == Approx(latex_points("w")));
  // Upright words are narrower than italic ones; the markup counts for nothing.
  CHECK(latex_points("\\mathrm{crank}") < latex_points("crank"));
  CHECK(latex_points("\\sin\\left(x\\right)") > latex_points("x") + 15.0);
  CHECK(latex_points("m_{\\mathrm{crank}}") < 30.0);
}

TEST_CASE("break_terms: lines within the width, nothing lost, groups balanced", "[latex]") {
  const std::string sum = long_sum(40);
  const auto lines = break_terms(sum, 150, 140);
  REQUIRE(lines.size() > 2);
  std::string joined;
  for (std::size_t k = 0; k < lines.size(); ++k) {
    CHECK(latex_points(lines[k]) <= (k == 0 ? 150 : 140));
    if (k + 1 < lines.size()) CHECK(latex_points(lines[k]) > 100);  // filled
    CHECK(braces_balanced(lines[k]));
    joined += (joined.empty() ? "" : " ") + lines[k];
  }
  CHECK(joined == sum);
  // A short formula stays on one line.
  CHECK(break_terms("a + b", 150, 150) == std::vector<std::string>{"a + b"});
}

TEST_CASE("break_terms: a short last term is not left alone on a line", "[latex]") {
  // Two long terms and a short one: the greedy cut would leave "- \tau_{3}" alone.
  const std::string big = "\\left(" + long_sum(6) + "\\right) l_{1}";
  const std::string f = big + " + " + big + " - \\tau_{3}";
  const double width = latex_points(big + " + " + big) + 2.0;
  const auto lines = break_terms(f, width, width);
  for (const auto& l : lines) CHECK(l != "- \\tau_{3}");
  CHECK(latex_points(lines.back()) > 0.25 * width);
}

TEST_CASE("break_terms: inside \\left( ... \\right) a break closes with \\right. and reopens with \\left.", "[latex]") {
  const std::string f = "m_{1} \\left(" + long_sum(40) + "\\right) - c";
  const auto lines = break_terms(f, 150, 150);
  REQUIRE(lines.size() > 2);
  for (const auto& l : lines) {
    INFO(l);
    CHECK(count(l, "\\left") == count(l, "\\right"));
    CHECK(braces_balanced(l));
    CHECK(latex_points(l) <= 150);
  }
  CHECK(lines.front().find("\\right.") != std::string::npos);
  CHECK(lines.back().find("\\left. ") != std::string::npos);
}

TEST_CASE("break_terms: a product wider than a line breaks between its factors", "[latex]") {
  std::string f;
  for (int i = 1; i <= 40; ++i) f += (i > 1 ? " " : "") + std::string("m_{") + std::to_string(i) + "}";
  const auto lines = break_terms(f, 120, 120);
  REQUIRE(lines.size() > 2);
  for (std::size_t k = 0; k < lines.size(); ++k) {
    CHECK(latex_points(lines[k]) <= 120);
    if (k > 0) CHECK(lines[k].rfind("\\cdot ", 0) == 0);  // the product goes on
  }
}

TEST_CASE("break_terms never breaks inside braces; unfold_wide makes a wide fraction breakable", "[latex]") {
  const std::string f = "\\frac{" + long_sum(40) + "}{d + e}";
  CHECK(break_terms(f, 150, 150).size() == 1);
  const std::string open = unfold_wide(f, 150);
  CHECK(open == "\\left(" + long_sum(40) + "\\right) / \\left(d + e\\right)");
  const auto lines = break_terms(open, 150, 150);
  CHECK(lines.size() > 2);
  for (const auto& l : lines) {
    CHECK(latex_points(l) <= 150);
    CHECK(count(l, "\\left") == count(l, "\\right"));
  }
  // Narrow fractions stay; a wide one's narrow parts too; a wrapped part keeps its parentheses.
  CHECK(unfold_wide("a + \\frac{1}{2} b", 150) == "a + \\frac{1}{2} b");
  CHECK(unfold_wide("-\\frac{\\frac{1}{2} " + long_sum(20) + "}{\\left(a + b\\right)}", 150) ==
        "-\\left(\\frac{1}{2} " + long_sum(20) + "\\right) / \\left(a + b\\right)");
  CHECK(unfold_wide("\\sqrt{" + long_sum(30) + "}", 150) == "\\left(" + long_sum(30) + "\\right)^{1/2}");
}

TEST_CASE("wrap_source: short lines, split at spaces, comments and escaped spaces kept", "[latex]") {
  const std::string line = "  x = " + long_sum(60) + "\\ b";
  const std::string wrapped = wrap_source(line + "\n% " + long_sum(60) + "\n", 50);
  std::size_t start = 0;
  int lines = 0;
  while (start < wrapped.size()) {
    const auto end = wrapped.find('\n', start);
    const std::string l = wrapped.substr(start, end - start);
    if (l.rfind("% ", 0) != 0) CHECK(l.size() <= 60);
    CHECK(!l.empty());
    start = end + 1;
    ++lines;
  }
  CHECK(lines > 3);
  // Undo the split: every newline (and the indentation after it) was one space.
  std::string back;
  for (std::size_t i = 0; i < wrapped.size(); ++i) {
    if (wrapped[i] == '\n' && wrapped.compare(i + 1, 4, "    ") == 0) {
      back += ' ';
      i += 4;
    } else {
      back += wrapped[i];
    }
  }
  CHECK(back == line + "\n% " + long_sum(60) + "\n");
}

TEST_CASE("latex_matrix: a pmatrix when the entries are short, else one entry per line", "[latex]") {
  const std::vector<std::vector<std::string>> small = {{"m_{1}", "0"}, {"0", "m_{2}"}};
  const std::string a = latex_matrix("M", {"w1'", "w2'"}, {"w1'", "w2'"}, small, {});
  CHECK(a.find("\\begin{equation*}") != std::string::npos);
  CHECK(a.find("\\mathbf{M} = \\begin{pmatrix}") != std::string::npos);
  CHECK(a.find("% M: rows (w1', w2'), columns (w1', w2')") == 0);
  const std::vector<std::vector<std::string>> wide = {{long_sum(30), "0"}, {"0", "b"}};
  const std::string b = latex_matrix("M", {"w1'", "w2'"}, {"w1'", "w2'"}, wide, {});
  CHECK(b.find("\\begin{align*}") != std::string::npos);
  CHECK(b.find("\\mathbf{M}_{1,1} &= ") != std::string::npos);
  CHECK(b.find("\\mathbf{M}_{2,2} &= b") != std::string::npos);
  CHECK(b.find("M_{1,2}") == std::string::npos);  // zero entries are left out
  CHECK(braces_balanced(b));
  // More columns than a pmatrix takes (amsmath's limit is 10).
  const std::vector<std::vector<std::string>> eleven = {std::vector<std::string>(11, "1")};
  CHECK(latex_matrix("S", {"a"}, std::vector<std::string>(11, "b"), eleven, {}).find("pmatrix") == std::string::npos);
  // The rates: one equation per coordinate, the dotted coordinate on the left.
  const std::string r = latex_matrix("kinematic transformations q0'", {"th1'", "crank.theta'"}, {"value"},
                                     {{"w_{1}"}, {"w_{\\mathrm{crank}}"}}, {{"crank.theta", "\\varphi"}});
  CHECK(r.find("\\dot{\\theta}_{1} &= w_{1}") != std::string::npos);
  CHECK(r.find("\\dot{\\varphi} &= w_{\\mathrm{crank}}") != std::string::npos);
  CHECK(latex_matrix("fbar", {"w1'"}, {"value"}, {{"a"}}, {}).find("\\bar{\\mathbf{f}} = ") != std::string::npos);
}

TEST_CASE("latex text and documents escape what LaTeX reserves", "[latex]") {
  CHECK(latex_escape_text("crank.position[1]") == "crank.position[1]");
  CHECK(latex_escape_text("a_b%c&d$e#f{g}") == "a\\_b\\%c\\&d\\$e\\#f\\{g\\}");
  const std::string doc = latex_document("double_pendulum", "", "BODY\n");
  CHECK(doc.find("\\documentclass") != std::string::npos);
  CHECK(doc.find("\\usepackage{amsmath}") != std::string::npos);
  CHECK(doc.find("Model \\texttt{double\\_pendulum}") != std::string::npos);
  CHECK(doc.find("BODY\n\\end{document}\n") != std::string::npos);
  CHECK(latex_document("m", "linkage.left", "").find("Subsystem \\texttt{linkage.left} of the model \\texttt{m}") !=
        std::string::npos);
}
