// SPDX-License-Identifier: GPL-2.0-or-later
// `latex NAME "..."` in the model: which names it may give a symbol to, how it is looked
// up from inside a body or a component, and its errors.
#include <catch2/catch.hpp>

#include "mbsc/model/build.hpp"
#include "mbsc/parse/parse.hpp"

namespace {

std::optional<mbsc::model::Model> build(const std::string& text, mbsc::Diagnostics& d) {
  auto file = mbsc::parse::parse_text(text, "test.mbs", d);
  if (!file) return std::nullopt;
  return mbsc::model::build(*file, d);
}

const char* const kPendulum = R"(model p
parameter m1 = 1, l = 1, g = 9.81
input tau
gravity (0, -g)
body crank : rigid2d {
  mass m1
  inertia m1*l^2/12
  point P (0, 0.5)
  latex theta "\varphi"
  latex m1 "m_{\mathrm{c}}"
}
ground { point O (0, 0) }
joint revolute ground.O crank.P
latex tau "\tau_{\mathrm{motor}}"
latex crank.w "\Omega"
latex t "\tau"
)";

}  // namespace

TEST_CASE("latex statement: parameters, inputs, coordinates, speeds and t get their symbols", "[latex][model]") {
  mbsc::Diagnostics d;
  auto m = build(kPendulum, d);
  INFO(d.format());
  REQUIRE(m);
  const std::map<std::string, std::string> expected = {{"crank.theta", "\\varphi"},
                                                       {"m1", "m_{\\mathrm{c}}"},
                                                       {"tau", "\\tau_{\\mathrm{motor}}"},
                                                       {"crank.w", "\\Omega"},
                                                       {"t", "\\tau"}};
  CHECK(m->latex_symbols == expected);
}

TEST_CASE("latex statement in a component: each instance's variables", "[latex][model]") {
  mbsc::Diagnostics d;
  auto m = build(R"(model arms
parameter g = 9.81
gravity (0, -g)
component Link(len) {
  body rod : rigid2d { mass 1  inertia len^2/12 }
  latex rod.theta "\phi"
  latex g "\mathrm{g}"
}
subsystem a : Link(1)
subsystem b : Link(2)
)",
                 d);
  INFO(d.format());
  REQUIRE(m);
  CHECK(m->latex_symbols.at("a.rod.theta") == "\\phi");
  CHECK(m->latex_symbols.at("b.rod.theta") == "\\phi");
  CHECK(m->latex_symbols.at("g") == "\\mathrm{g}");  // the same statement met twice is no duplicate
}

TEST_CASE("latex statement: unknown names, duplicates, subsystems and component parameters are errors",
          "[latex][model]") {
  struct Case {
    const char* text;
    const char* where;
    const char* message;
  };
  const std::vector<Case> cases = {
      {"model m\nparameter a = 1\nlatex b \"b\"\n", "3:7", "unknown name 'b' in latex statement"},
      {"model m\nparameter a = 1\nlatex a \"x\"\nlatex a \"y\"\n", "4:7", "latex symbol of 'a' is already given at 3:1"},
      {"model m\nbody p : particle2d { mass 1 }\nlatex p \"P\"\n", "3:7", "'p' is a subsystem"},
      {"model m\ncomponent C(k) { body p : particle2d { mass k } latex k \"K\" }\nsubsystem c : C(1)\n", "2:55",
       "'c.k' is a component parameter"},
      {"model m\nbody p : particle2d { mass 1 }\nlatex p.z \"z\"\n", "3:7", "unknown name 'p.z' in latex statement"},
  };
  for (const auto& c : cases) {
    INFO(c.text);
    mbsc::Diagnostics d;
    CHECK(!build(c.text, d));
    REQUIRE(!d.all().empty());
    const auto& e = d.all().front();
    INFO(d.format());
    CHECK(std::to_string(e.pos.line) + ":" + std::to_string(e.pos.col) == c.where);
    CHECK(e.message.find(c.message) != std::string::npos);
  }
}
