// SPDX-License-Identifier: GPL-2.0-or-later
// The `latex NAME "..."` statement: which texts are safe in a formula, how the parser
// reads the statement and reports an unsafe text.
#include <catch2/catch.hpp>

#include <string>
#include <vector>

#include "mbsc/parse/latex_text.hpp"
#include "mbsc/parse/parse.hpp"

using mbsc::parse::latex_text_problem;

TEST_CASE("latex text: symbols a formula takes are safe", "[latex][parse]") {
  for (const char* ok : {"\\theta", "\\varphi_{\\mathrm{crank}}", "m_{1}", "x^{*}", "\\dot{x}", "\\{a\\}", "a\\,b",
                         "\\left(a\\right)", "q'", "\\bar{F}", "x_ 1", "\\mathbf{r}_{G}", "\\text{load}",
                         "\\varGamma", "\\hat\\theta", "\\left\\langle x\\right\\rangle", "{\\left(a\\right)}_{2}",
                         "\\left.x\\right|", "\\left\\{a\\right\\}", "\\operatorname{tr}", "\\text{load 1, max.}",
                         "\\boldsymbol{\\omega}^{\\prime}", "\\hbar\\,\\ell\\quad\\partial\\nabla\\infty", "a\\cdot b\\times c"}) {
    INFO(ok);
    CHECK(latex_text_problem(ok).empty());
  }
}

TEST_CASE("latex text: what would break the formula or the document is refused", "[latex][parse]") {
  struct Case {
    std::string text, why;
  };
  const std::vector<Case> cases = {
      {"", "empty"},
      {"\\theta_{1", "'{' that is not closed"},
      {"a}", "'}' without its '{'"},
      {"}{", "'}' without its '{'"},
      {"$x$", "'$'"},
      {"x % y", "'%'"},
      {"a & b", "'&'"},
      {"#1", "'#'"},
      {"a\\\\b", "line break"},
      {"x\\", "lone '\\'"},
      {"x^", "'^' with nothing after it"},
      {"x_{a_}", "'_' with nothing after it"},
      {"\\end{equation*}", "'\\end', which is not a command for symbols"},
      {"\\begin{x}", "'\\begin', which is not a command for symbols"},
      {"\\def\\x{1}", "'\\def', which is not a command for symbols"},
      {"\\input{f}", "'\\input', which is not a command for symbols"},
      {"\\par", "'\\par', which is not a command for symbols"},
      // Commands a deny-list missed: code run by lualatex, the end of the file, a macro.
      {"\\directlua{os.remove('victim.txt')}m", "'\\directlua', which is not a command for symbols"},
      {"\\endinput g", "'\\endinput', which is not"},
      {"\\expandafter x", "'\\expandafter', which is not"},
      {"\\mathfrak{g}", "'\\mathfrak', which is not"},  // needs a package --standalone does not load
      {"\\thetax", "'\\thetax', which is not"},
      // \left ... \right: a pair per brace group, a delimiter after each.
      {"{\\left(}\\right)", "'\\left' whose '\\right' is not in the same brace group"},
      {"\\left({\\right)}", "'\\right' without its '\\left' in the same brace group"},
      {"\\left x\\right)", "'\\left' without a delimiter"},
      {"\\left(x\\right\\alpha", "'\\right' without a delimiter"},
      {"\\left(x\\right", "'\\right' without a delimiter"},
      // Accents and fonts need something to apply to; \text takes words only.
      {"x\\hat", "'\\hat' with nothing after it"},
      {"\\mathrm}", "'\\mathrm' with nothing after it"},
      {"\\text{\\alpha}", "'\\' in '\\text{...}'"},
      {"\\text{a_b}", "'_' in '\\text{...}'"},
      {"\\text{a{b}}", "'{' in '\\text{...}'"},
      {"\\text x", "'\\text' without '{words}'"},
      {"\\text{ab", "'{' that is not closed"},
      {"\\[x\\]", "'\\['"},
      {"\\left(x", "'\\left' without its '\\right'"},
      {"x\\right)", "'\\right' without its '\\left'"},
      {"\xce\xb8", "outside ASCII"},
      {"a\tb", "control character"},
      {std::string(201, 'x'), "longer than 200"},
  };
  for (const auto& c : cases) {
    INFO(c.text);
    const std::string why = latex_text_problem(c.text);
    CHECK(why.find(c.why) != std::string::npos);
  }
}

TEST_CASE("latex statement: parsed into the tree with the name's path and the text", "[latex][parse]") {
  mbsc::Diagnostics diags;
  const auto file =
      mbsc::parse::parse_text("model m\nlatex crank.theta \"\\varphi\"; latex th1 \"\\vartheta_{1}\"\n", "t.mbs", diags);
  REQUIRE(file);
  REQUIRE(file->statements.size() == 3);
  const auto& s = *file->statements[1];
  CHECK(s.kind == mbsc::ast::Statement::Kind::Latex);
  CHECK(s.path.text == "crank.theta");
  CHECK(s.path.pos.line == 2);
  CHECK(s.path.pos.col == 7);
  CHECK(s.name == "\\varphi");
  CHECK(s.name_pos.col == 19);
  CHECK(file->statements[2]->name == "\\vartheta_{1}");
}

TEST_CASE("latex statement: errors name the symbol and point at the text", "[latex][parse]") {
  struct Case {
    const char* text;
    const char* where;
    const char* message;
  };
  const std::vector<Case> cases = {
      {"latex th1 \"\\theta_{1\"\n", "1:11", "latex symbol of 'th1' is not safe LaTeX: it has a '{' that is not closed"},
      {"latex a.b \"x}\"\n", "1:11", "latex symbol of 'a.b' is not safe LaTeX: it has a '}' without its '{'"},
      {"latex th1 \"\x01\"\n", "1:11", "latex symbol of 'th1': control character"},
      {"latex th1 \\theta\n", "1:11", "expected LaTeX text in double quotes after 'latex th1'"},
      {"latex \"x\"\n", "1:7", "expected name after 'latex'"},
      {"latex th1 \"x\" \"y\"\n", "1:15", "end of statement after latex symbol of 'th1'"},
      {"latex mass \"m\"\n", "1:7", "'mass' is a keyword"},
  };
  for (const auto& c : cases) {
    INFO(c.text);
    mbsc::Diagnostics diags;
    CHECK(!mbsc::parse::parse_text(c.text, "t.mbs", diags));
    REQUIRE(!diags.all().empty());
    const auto& d = diags.all().front();
    CHECK(std::to_string(d.pos.line) + ":" + std::to_string(d.pos.col) == c.where);
    CHECK(d.message.find(c.message) != std::string::npos);
  }
}
