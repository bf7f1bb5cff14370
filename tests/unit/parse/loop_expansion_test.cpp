// SPDX-License-Identifier: GPL-2.0-or-later
// Unit tests of `for` loops and `name[index]` (src/parse/loop_expansion.cpp), through
// parse_text: the statements they expand to, the structural parameters they report,
// and their mistakes.
#include <catch2/catch.hpp>

#include <string>
#include <vector>

#include "mbsc/parse/parse.hpp"

using mbsc::Diagnostics;
using Kind = mbsc::ast::Statement::Kind;

namespace {

/// "kind name" of every statement, flattening subsystem bodies one level.
std::vector<std::string> names(const std::string& text, const std::map<std::string, double>& overrides = {},
                               std::map<std::string, double>* structural = nullptr) {
  Diagnostics diags;
  auto file = mbsc::parse::parse_text(text, "t.mbs", diags, overrides);
  INFO(diags.format());
  REQUIRE(file.has_value());
  if (structural) *structural = file->structural;
  std::vector<std::string> out;
  for (const auto& s : file->statements) {
    if (s->kind == Kind::Parameter) continue;
    std::string line = s->name;
    for (const auto& p : s->paths) line += " " + p.text;
    out.push_back(line);
    for (const auto& b : s->body)
      if (!b->name.empty()) out.push_back("  " + b->name);
  }
  return out;
}

std::string error_of(const std::string& text) {
  Diagnostics diags;
  auto file = mbsc::parse::parse_text(text, "t.mbs", diags);
  CHECK_FALSE(file.has_value());
  return diags.format();
}

}  // namespace

TEST_CASE("for loops repeat their statements with the loop variable's value", "[parse][loop]") {
  const auto got = names("parameter N = 3\n"
                         "for i = 1 to N {\n"
                         "  body b[i] : particle2d { mass i }\n"
                         "  joint j[i] : revolute b[i] b[i+1]\n"
                         "}\n");
  CHECK(got == std::vector<std::string>{"b_1", "j_1 b_1 b_2", "b_2", "j_2 b_2 b_3", "b_3", "j_3 b_3 b_4"});
}

TEST_CASE("nested loops, arithmetic in indices, empty ranges", "[parse][loop]") {
  const auto got = names("for i = 0 to 1 {\n"
                         "  for k = i to 1 {\n"
                         "    body c[2*i + k] : particle2d { mass 1 }\n"
                         "  }\n"
                         "}\n"
                         "for i = 3 to 2 { body never : particle2d { mass 1 } }\n");
  CHECK(got == std::vector<std::string>{"c_0", "c_1", "c_3"});
}

TEST_CASE("the loop variable in expressions becomes its number, negative ones bracketed", "[parse][loop]") {
  Diagnostics diags;
  auto file = mbsc::parse::parse_text("for i = -1 to -1 {\n  output y[i+2] = 2*i\n}\n", "t.mbs", diags);
  REQUIRE(file.has_value());
  REQUIRE(file->statements.size() == 1);
  const auto& s = *file->statements[0];
  CHECK(s.name == "y_1");
  REQUIRE(s.value);
  // 2 * (-1): a product whose right factor is a negation, not a parse of "2*-1".
  REQUIRE(s.value->kind == mbsc::ast::Expr::Kind::Product);
  CHECK(s.value->args.at(1)->kind == mbsc::ast::Expr::Kind::Unary);
}

TEST_CASE("bounds read parameter defaults, overridden by --freeze values, reported as structural", "[parse][loop]") {
  const std::string text = "parameter N = 2, L = 0.5\nfor i = 1 to N { body b[i] : particle2d { mass L } }\n";
  std::map<std::string, double> structural;
  CHECK(names(text, {}, &structural).size() == 2);
  CHECK(structural == std::map<std::string, double>{{"N", 2.0}});
  CHECK(names(text, {{"N", 5.0}}, &structural).size() == 5);
  CHECK(structural == std::map<std::string, double>{{"N", 5.0}});
}

TEST_CASE("loop mistakes are reported at their token", "[parse][loop]") {
  CHECK_THAT(error_of("parameter L = 0.5\nfor i = 1 to L { }\n"),
             Catch::Contains("t.mbs:2:14: error: the last value of 'i' must be a whole number") &&
                 Catch::Contains("parameter 'L' is 0.5"));
  CHECK_THAT(error_of("for i = 1 to M { }\n"),
             Catch::Contains("t.mbs:1:14: error:") && Catch::Contains("'M' is not a loop variable or a parameter"));
  CHECK_THAT(error_of("body b[1 : particle2d { mass 1 }\n"), Catch::Contains("t.mbs:1:7: error: '[' after 'b' is not closed"));
  CHECK_THAT(error_of("for i = 1 N { }\n"), Catch::Contains("t.mbs:1:1: error: loop over 'i': expected 'for i = FIRST to LAST"));
  CHECK_THAT(error_of("for i = 1 to 2 {\n body b[i] : particle2d { mass 1 }\n"),
             Catch::Contains("t.mbs:1:16: error: loop over 'i': '{' is not closed"));
  CHECK_THAT(error_of("output y = x[1/2]\n"), Catch::Contains("1 / 2 is not a whole number"));
  CHECK_THAT(error_of("output y = ] + 1\n"), Catch::Contains("t.mbs:1:12: error: ']' belongs after a name"));
  CHECK_THAT(error_of("for i = 1 to 20000 { }\n"), Catch::Contains("runs 20000 times"));
  // Out-of-range literals are errors, not exceptions (in a bound, and in a parameter
  // default the loops may read).
  // (Literals beyond a double's range are lexical errors, reported at their token.)
  CHECK_THAT(error_of("for i = 1 to 1e999 { }\n"),
             Catch::Contains("t.mbs:1:14: error: the last value of 'i' must be a whole number") &&
                 Catch::Contains("number '1e999' is too large for a double"));
  CHECK_THAT(error_of("parameter N = 1e999\nfor i = 1 to 2 { }\n"),
             Catch::Contains("t.mbs:1:15: error: number '1e999' is too large for a double"));
  CHECK_THAT(error_of("for i = 1 to 1e300 { }\n"), Catch::Contains("1e300 is not a whole number of at most"));
  // No overflow on the way, and nested loops share one budget.
  CHECK_THAT(error_of("for i = 1 to 1000000000*1000000000*1000000000 { }\n"), Catch::Contains("out of range"));
  CHECK_THAT(error_of("for i = 1 to 9000 {\n for j = 1 to 9000 {\n }\n}\n"),
             Catch::Contains("more than 100000 repetitions in all"));
}

TEST_CASE("the work of expanding loops is bounded, whatever the loops' shape", "[parse][loop]") {
  // Loops that run no time still count toward the repetitions.
  CHECK_THAT(error_of("for a = 1 to 10000 { for b = 1 to 9 { for c = 1 to 0 { } } }\n"),
             Catch::Contains("expand to more than 100000 repetitions"));
  // A long loop head repeated by an outer loop: the scanning is counted.
  std::string head = "1";
  for (int i = 0; i < 20000; ++i) head += "+0";
  CHECK_THAT(error_of("for a = 1 to 9000 { for b = " + head + " to 1 { } }\n"),
             Catch::Contains("take more than 16777216 steps to expand"));
  // Long indices likewise.
  CHECK_THAT(error_of("for a = 1 to 9000 { output y[a] = x[" + head + "] }\n"),
             Catch::Contains("take more than 16777216 steps to expand"));
  // The output itself is bounded (4 Mi tokens).
  std::string body;
  for (int i = 0; i < 1000; ++i) body += "a ";
  CHECK_THAT(error_of("for a = 1 to 9000 { " + body + "}\n"), Catch::Contains("to more than 4194304 tokens"));
}
