// SPDX-License-Identifier: GPL-2.0-or-later
#include <catch2/catch.hpp>

#include <stdexcept>
#include <string>

#include "../../../src/emit/renderer.hpp"

using mbsc::emit::Fragments;
using mbsc::emit::render;

TEST_CASE("render: inline and whole-line placeholders", "[emit]") {
  const std::string tpl = "namespace {{name}} {\n  {{body}}\n}  // {{name}}\n";
  const std::string out = render("t", tpl, Fragments{{"name", "m"}, {"body", "int a;\nint b;\n\nint c;"}});
  CHECK(out == "namespace m {\n  int a;\n  int b;\n\n  int c;\n}  // m\n");
}

TEST_CASE("render: inline multi-line fragment is indented to its column", "[emit]") {
  const std::string out = render("t", "x = {{v}};\n", Fragments{{"v", "f(1,\n  2)"}});
  CHECK(out == "x = f(1,\n      2);\n");
}

TEST_CASE("render: empty whole-line fragment removes the line; comments vanish", "[emit]") {
  const std::string tpl = "{{! SPDX-License-Identifier: GPL-2.0-or-later }}\na\n{{opt}}\nb\n";
  CHECK(render("t", tpl, Fragments{{"opt", ""}}) == "a\nb\n");
  CHECK(render("t", tpl, Fragments{{"opt", "c\n"}}) == "a\nc\nb\n");
  CHECK(render("t", "a {{! note }}b\n", Fragments{}) == "a b\n");
}

TEST_CASE("render: errors name the template and the key", "[emit]") {
  try {
    render("model.hpp.in", "a\n{{nope}}\n", Fragments{});
    FAIL("no exception");
  } catch (const std::runtime_error& e) {
    CHECK(std::string(e.what()).find("model.hpp.in:2") != std::string::npos);
    CHECK(std::string(e.what()).find("nope") != std::string::npos);
  }
  CHECK_THROWS_WITH(render("t", "a\n", Fragments{{"extra", "x"}}), Catch::Contains("unused fragment 'extra'"));
  CHECK_THROWS_WITH(render("t", "a {{b\n", Fragments{{"b", ""}}), Catch::Contains("unterminated"));
  CHECK_THROWS_WITH(render("t", "{{a b}}\n", Fragments{}), Catch::Contains("malformed"));
  CHECK_THROWS_WITH(render("t", "a }}\n", Fragments{}), Catch::Contains("stray"));
}
