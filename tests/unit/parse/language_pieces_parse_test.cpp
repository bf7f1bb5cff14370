// SPDX-License-Identifier: GPL-2.0-or-later
// The parser's side of `let` and of the knife-edge joint (docs/language_syntax.md).
#include <catch2/catch.hpp>

#include <string>

#include "mbsc/parse/parse.hpp"

using mbsc::Diagnostics;
using Kind = mbsc::ast::Statement::Kind;

namespace {

mbsc::ast::File parse_ok(const std::string& text) {
  Diagnostics diags;
  auto file = mbsc::parse::parse_text(text, "t.mbs", diags);
  INFO(diags.format());
  REQUIRE(file.has_value());
  return *file;
}

std::string first_error(const std::string& text) {
  Diagnostics diags;
  auto file = mbsc::parse::parse_text(text, "t.mbs", diags);
  CHECK_FALSE(file.has_value());
  const std::string all = diags.format();
  return all.substr(0, all.find('\n'));
}

}  // namespace

TEST_CASE("let: a named expression statement, at the top level and in a block", "[parse][let]") {
  const auto f = parse_ok("let L = sqrt(l^2 - x)\nbody b : rigid2d { let h = l/2 ; mass m }\n");
  REQUIRE(f.statements.size() == 2);
  const auto& let = *f.statements[0];
  CHECK(let.kind == Kind::Let);
  CHECK(let.name == "L");
  CHECK(let.name_pos.col == 5);
  REQUIRE(let.value);
  CHECK(let.value->kind == mbsc::ast::Expr::Kind::Call);
  REQUIRE(f.statements[1]->body.size() == 2);
  CHECK(f.statements[1]->body[0]->kind == Kind::Let);
  CHECK(f.statements[1]->body[0]->name == "h");
  CHECK(f.statements[1]->body[1]->kind == Kind::Mass);
  // 'let' is a keyword now: it cannot name anything.
  CHECK(first_error("parameter let = 1\n").find("'let' is a keyword and cannot be used as a name") != std::string::npos);
  CHECK(first_error("let L 2\n").find("t.mbs:1:7: error: expected '=' after 'let L'") != std::string::npos);
}

TEST_CASE("knife_edge: a body, then point and axis names in either order", "[parse][knife_edge]") {
  const auto f = parse_ok("joint a : knife_edge s\njoint b : knife_edge s point P\njoint c : knife_edge s axis A point P\n");
  REQUIRE(f.statements.size() == 3);
  for (const auto& s : f.statements) {
    CHECK(s->kind == Kind::Joint);
    CHECK(s->kind_name == "knife_edge");
    REQUIRE(s->paths.size() == 3);
    CHECK(s->paths[0].text == "s");
  }
  CHECK(f.statements[0]->paths[1].text.empty());
  CHECK(f.statements[0]->paths[2].text.empty());
  CHECK(f.statements[1]->paths[1].text == "P");
  CHECK(f.statements[1]->paths[2].text.empty());
  CHECK(f.statements[2]->paths[1].text == "P");
  CHECK(f.statements[2]->paths[2].text == "A");
  CHECK(f.statements[2]->paths[2].pos.col == 29);
  CHECK(first_error("joint k : knife_edge s point P point Q\n").find("t.mbs:1:32: error: joint 'k': 'point' given twice") !=
        std::string::npos);
}
