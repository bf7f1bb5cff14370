// SPDX-License-Identifier: GPL-2.0-or-later
// Unit tests of the parser: syntax errors, their positions and messages, and recovery.
#include <catch2/catch.hpp>

#include <random>
#include <string>
#include <vector>

#include "mbsc/parse/parse.hpp"

using mbsc::Diagnostics;

namespace {

/// Every error of parsing `text` as "line:col: message". Also checks that parse_text
/// returns a tree exactly when no error was reported.
std::vector<std::string> errors_of(const std::string& text) {
  Diagnostics diags;
  const auto file = mbsc::parse::parse_text(text, "t.mbs", diags);
  CHECK(file.has_value() == !diags.has_errors());
  std::vector<std::string> out;
  for (const auto& d : diags.all()) {
    CHECK(d.pos.file == "t.mbs");
    out.push_back(std::to_string(d.pos.line) + ":" + std::to_string(d.pos.col) + ": " + d.message);
  }
  return out;
}

struct ErrorCase {
  const char* text;
  const char* where;    // "line:col" of the (first) error
  const char* message;  // a substring of its message
};

}  // namespace

TEST_CASE("parser errors: position and message of the first error", "[parse][errors]") {
  const std::vector<ErrorCase> cases = {
      {"model m\nmass m @ 2\n", "2:8", "unexpected character '@'"},
      {"output y = 1 + $\n", "1:16", "unexpected character '$'"},
      {"include \"abc\n", "1:9", "unterminated string"},
      {"model m\nbodyy crank : rigid2d\n", "2:1", "unknown statement 'bodyy'"},
      {"output y = sin(x\nmass m\n", "1:17", "expected ')' after arguments of 'sin', found newline"},
      {"output y = sin(x y)\n", "1:18", "expected ')' after arguments of 'sin', found 'y'"},
      {"constraint velocity {\n  R.u + R.w\n}\n", "2:3", "constraint row is not an equation (expected '=')"},
      {"constraint velocity {\n  c1: R.u; R.v = 0\n}\n", "2:3", "constraint row is not an equation (expected '=')"},
      {"constraint velocity { a + b c }\n", "1:29", "expected '=' in constraint row, found 'c'"},
      {"constraint velocity {\n a = b = c\n}\n", "2:8", "expected end of constraint row, found '='"},
      {"constraint {\n a = b\n}\n", "1:12", "expected 'position' or 'velocity' after 'constraint', found '{'"},
      {"constraint position linear { a = b }\n", "1:21", "expected '{' to begin the position constraint block, found 'linear'"},
      {"subsystem left (a, b)\n", "1:16", "subsystem 'left' has arguments but no kind"},
      {"subsystem a : rigid2d junk\n", "1:23", "expected end of statement after subsystem 'a', found 'junk'"},
      {"subsystem a : \n", "1:15", "expected kind or component name after ':' in subsystem 'a', found newline"},
      {"parameter mass = 1\n", "1:11", "'mass' is a keyword and cannot be used as a name"},
      {"output y = mass\n", "1:12", "'mass' is a keyword and cannot be used in an expression"},
      {"constraint velocity { mass = 1 }\n", "1:23", "'mass' is a keyword and cannot be used in an expression"},
      {"parameter velocity\n", "1:11", "'velocity' is a keyword and cannot be used as a name"},
      {"subsystem s {\n  include \"x.mbs\"\n}\n", "2:3", "include is only allowed at the top level of a file"},
      {"include \"\"\n", "1:9", "empty file name in include"},
      {"include arm.mbs\n", "1:9", "expected file name in double quotes after 'include', found 'arm'"},
      {"output y = sin(x)'\n", "1:18", "a prime (time derivative) can only follow a name"},
      {"output y = 2'\n", "1:13", "a prime (time derivative) can only follow a name"},
      {"mass 2x\n", "1:6", "malformed number '2x'"},
      {"gravity (g)\n", "1:11", "gravity has 2 or 3 components"},
      {"gravity (a, b, c, d)\n", "1:19", "gravity has 2 or 3 components"},
      {"gravity 0, -g\n", "1:9", "expected '(' after 'gravity', found number '0'"},
      {"model m\n}\n", "2:1", "unmatched '}'"},
      {"parameter a = 1 b = 2\n", "1:17", "expected ',' or end of statement after parameter 'a', found 'b'"},
      {"parameter a, \n", "1:14", "expected parameter name after ',', found newline"},
      {"output y x\n", "1:10", "expected '=' after output name 'y', found 'x'"},
      {"force w k*i\n", "1:9", "expected ':' after force target 'w', found 'k'"},
      {"output y = a.b(x)\n", "1:12", "'a.b' is not a function name"},
      {"output y = (a + b\noutput z = 1\n", "1:18", "expected ')' to close '(' opened at 1:12, found newline"},
      {"mass m +\ninertia J\n", "1:9", "expected expression after '+', found newline"},
      {"mass\n", "1:5", "expected expression after 'mass', found newline"},
      {"mass m *", "1:9", "expected expression after '*', found end of file"},
      {"mass m *\n", "1:9", "expected expression after '*', found newline"},
      {"mass (a + b))\n", "1:13", "expected end of statement after mass expression, found ')'"},
      {"3 + x\n", "1:1", "expected a statement, found number '3'"},
      {"energy\n", "1:1", "expected a statement, found keyword 'energy'"},
      {"model\n", "1:6", "expected model name after 'model', found newline"},
      {"component A {\n}\n", "1:13", "expected '(' after component name 'A', found '{'"},
      {"component A()\nmass m\n", "1:14", "expected '{' to begin the body of component 'A', found newline"},
      {"component A(a, 1) {}\n", "1:16", "expected parameter name in component 'A', found number '1'"},
      {"independent a.\n", "1:15", "expected name after '.' in 'a.', found newline"},
      {"output\n", "1:7", "expected output name or 'energy' after 'output', found newline"},
      {"speed v = \n", "1:11", "expected expression after '=', found newline"},
      {"input tau u\n", "1:11", "expected ',' or end of statement after input 'tau', found 'u'"},
      {"subsystem a { mass m } x\n", "1:24", "expected end of statement after the body of subsystem 'a', found 'x'"},
  };
  for (const auto& c : cases) {
    INFO("input: " << c.text);
    const auto errs = errors_of(c.text);
    REQUIRE_FALSE(errs.empty());
    CHECK(errs.size() == 1);
    const std::string first = errs.front();
    INFO("error: " << first);
    CHECK(first.rfind(std::string(c.where) + ": ", 0) == 0);
    CHECK(first.find(c.message) != std::string::npos);
  }
}

TEST_CASE("parser errors: a block left open is reported at the end of the file", "[parse][errors]") {
  const auto errs = errors_of(
      "model m\n"
      "\n"
      "component A() {\n"
      "    subsystem arm {\n"
      "      mass m\n");
  REQUIRE(errs.size() == 2);
  CHECK(errs[0] == "6:1: missing '}' to close subsystem 'arm' opened at 4:19");
  CHECK(errs[1] == "6:1: missing '}' to close component 'A' opened at 3:15");

  const auto body = errors_of("body crank : rigid2d {\n  mass m1");
  REQUIRE(body.size() == 1);
  CHECK(body[0] == "2:10: missing '}' to close body 'crank' opened at 1:22");
}

TEST_CASE("parser errors: a constraint block left open ends at the next statement", "[parse][errors]") {
  const auto errs = errors_of(
      "constraint velocity {\n"
      "  a = b\n"
      "independent x\n"
      "mass )\n");
  REQUIRE(errs.size() == 2);
  CHECK(errs[0] == "3:1: missing '}' to close velocity constraint block opened at 1:21");
  CHECK(errs[1] == "4:6: expected expression after 'mass', found ')'");
}

TEST_CASE("parser errors: recovery reports every independent mistake once", "[parse][errors]") {
  const auto errs = errors_of(
      "model m\n"
      "parameter 1a = 2\n"
      "mass m @\n"
      "parameter ok = 3\n"
      "output y = (a +\n"
      "            b\n"
      "subsystem s : k {\n"
      "  mass )\n"
      "  inertia J\n"
      "  subsystem t : k(1, 2 { mass m }\n"
      "  kinetic 1/2*m*v^2\n"
      "}\n"
      "constraint velocity {\n"
      "  a + b\n"
      "  c = d\n"
      "  e = f(\n"
      "}\n"
      "bodyy x\n"
      "output z = 1\n");
  const std::vector<std::string> expected = {
      "2:11: malformed number '1a'",
      "3:8: unexpected character '@'",
      "6:14: expected ')' to close '(' opened at 5:12, found newline",
      "8:8: expected expression after 'mass', found ')'",
      "10:24: expected ')' after the arguments of subsystem 't', found '{'",
      "14:3: constraint row is not an equation (expected '=')",
      "16:9: expected expression after '(', found newline",
      "18:1: unknown statement 'bodyy' (did you mean 'body'?)",
  };
  CHECK(errs == expected);
}

TEST_CASE("parser errors: diagnostics are formatted with the file name", "[parse][errors]") {
  Diagnostics diags;
  CHECK_FALSE(mbsc::parse::parse_text("model m\nmass m @\n", "models/x.mbs", diags).has_value());
  CHECK(diags.format() == "models/x.mbs:2:8: error: unexpected character '@'\n");
}

TEST_CASE("parser errors: deep nesting is rejected without exhausting the stack", "[parse][errors]") {
  const std::string deep_parens = "mass " + std::string(100000, '(') + "x" + std::string(100000, ')') + "\n";
  auto errs = errors_of(deep_parens);
  REQUIRE(errs.size() == 1);
  CHECK(errs[0].find("nesting too deep") != std::string::npos);

  std::string deep_unary = "mass ";
  for (int i = 0; i < 100000; ++i) deep_unary += "-";
  errs = errors_of(deep_unary + "x\nmass y\n");
  REQUIRE(errs.size() == 1);
  CHECK(errs[0].find("nesting too deep") != std::string::npos);

  std::string deep_power = "mass x";
  for (int i = 0; i < 100000; ++i) deep_power += "^x";
  errs = errors_of(deep_power);
  REQUIRE(errs.size() == 1);

  std::string deep_blocks;
  for (int i = 0; i < 5000; ++i) deep_blocks += "subsystem s {\n";
  for (int i = 0; i < 5000; ++i) deep_blocks += "}\n";
  errs = errors_of(deep_blocks);
  REQUIRE(errs.size() == 1);
  CHECK(errs[0].find("nesting too deep") != std::string::npos);

  // Moderate nesting is fine.
  const std::string fine = "mass " + std::string(50, '(') + "x" + std::string(50, ')') + "\n";
  CHECK(errors_of(fine).empty());
}

TEST_CASE("parser errors: every prefix and many mutations of a model parse without crash or hang",
          "[parse][errors]") {
  const std::string model = R"(model ring_disc   # comment
parameter m1 = 1, m2, r1 = 0.5e-1, g = 9.81
input tau; include "lib.mbs"
gravity (g*sin(xi),
         -g*cos(xi))
component Arm(a, b) {
  body upper : rigid2d { mass a  inertia a*b^2 }
}
subsystem left : Arm(1, 2)
subsystem D : custom {
  speed w = x'' - 2
  force w : -k*w'^2
}
coordinate theta
constraint position nonlinear {
  c1: R.u + R.w*r1 = 0; R.v = -(a - b)/c
}
independent dtheta, D.w
output e = left.upper.x ; output energy
)";
  REQUIRE(errors_of(model).empty());
  for (std::size_t n = 0; n <= model.size(); ++n) {
    Diagnostics diags;
    const auto file = mbsc::parse::parse_text(model.substr(0, n), "t.mbs", diags);
    CHECK(file.has_value() == !diags.has_errors());
  }
  const std::string alphabet = "(){};:,.=+-*/^'\"#@\n x1e";
  std::mt19937 rng(12345);
  for (int round = 0; round < 3000; ++round) {
    std::string text = model;
    const int edits = 1 + static_cast<int>(rng() % 4);
    for (int k = 0; k < edits; ++k) {
      const std::size_t at = rng() % text.size();
      switch (rng() % 3) {
        case 0: text.erase(at, 1); break;
        case 1: text.insert(at, 1, alphabet[rng() % alphabet.size()]); break;
        default: text[at] = alphabet[rng() % alphabet.size()]; break;
      }
    }
    Diagnostics diags;
    const auto file = mbsc::parse::parse_text(text, "t.mbs", diags);
    CHECK(file.has_value() == !diags.has_errors());
  }
}

TEST_CASE("parser: long sums are flat; deep nesting and huge operand counts are errors", "[parse][errors]") {
  std::string sum = "output y = 1";
  for (int i = 0; i < 20000; ++i) sum += i % 2 ? " + a" : " - b";
  mbsc::Diagnostics diags;
  auto file = mbsc::parse::parse_text(sum + "\n", "t.mbs", diags);
  REQUIRE(file.has_value());
  const auto& e = file->statements.at(0)->value;
  CHECK(e->kind == mbsc::ast::Expr::Kind::Sum);
  CHECK(e->args.size() == 20001);
  CHECK(e->text.size() == 20000);
  CHECK(e->text.substr(0, 4) == "-+-+");

  mbsc::Diagnostics deep;
  CHECK_FALSE(mbsc::parse::parse_text("output y = " + std::string(300, '(') + "1" + std::string(300, ')') + "\n", "t.mbs",
                                      deep)
                  .has_value());
  CHECK(deep.format().find("nesting too deep (more than 200 levels)") != std::string::npos);
}

TEST_CASE("parser: a chain of primes is bounded like any nesting", "[parse][errors]") {
  mbsc::Diagnostics diags;
  CHECK_FALSE(mbsc::parse::parse_text("output o = t" + std::string(100000, '\'') + "\n", "t.mbs", diags).has_value());
  CHECK(diags.format().find("nesting too deep") != std::string::npos);
}
