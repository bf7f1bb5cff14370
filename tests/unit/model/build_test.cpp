// SPDX-License-Identifier: GPL-2.0-or-later
// Model building: scopes, components, leaf kinds, and the kinematic transformations
// solved from quasi-velocity definitions.
#include <catch2/catch.hpp>

#include "mbsc/model/build.hpp"
#include "mbsc/parse/parse.hpp"

namespace {

std::optional<mbsc::model::Model> build(const std::string& text, mbsc::Diagnostics& d) {
  auto file = mbsc::parse::parse_text(text, "test.mbs", d);
  if (!file) return std::nullopt;
  return mbsc::model::build(*file, d);
}

int coord(const mbsc::model::Model& m, const std::string& n) {
  for (size_t i = 0; i < m.coords.size(); ++i)
    if (m.coords[i].name == n) return static_cast<int>(i);
  return -1;
}
int speed(const mbsc::model::Model& m, const std::string& n) {
  for (size_t i = 0; i < m.speeds.size(); ++i)
    if (m.speeds[i].name == n) return static_cast<int>(i);
  return -1;
}

}  // namespace

TEST_CASE("body-frame speeds: coordinate rates are solved from the definitions", "[model]") {
  mbsc::Diagnostics d;
  auto m = build(R"(model car
coordinate x, y, th
speed v = x'*cos(th) + y'*sin(th)
speed s = -x'*sin(th) + y'*cos(th)
speed w = th'
)", d);
  INFO(d.format());
  REQUIRE(m);
  const auto th = m->coords[coord(*m, "th")].sym;
  const GiNaC::ex v = m->speeds[speed(*m, "v")].sym, s = m->speeds[speed(*m, "s")].sym;
  // The solve gives x' = v cos - s sin, y' = v sin + s cos (up to trigonometric identities):
  // check by substituting back into the definitions.
  GiNaC::ex xd = m->coord_rates[coord(*m, "x")], yd = m->coord_rates[coord(*m, "y")];
  GiNaC::ex back_v = xd * cos(th) + yd * sin(th), back_s = -xd * sin(th) + yd * cos(th);
  GiNaC::exmap trig{{pow(sin(th), 2), 1 - pow(cos(th), 2)}};
  CHECK((back_v - v).expand().subs(trig).expand().normal().is_zero());
  CHECK((back_s - s).expand().subs(trig).expand().normal().is_zero());
  CHECK(m->coord_rates[coord(*m, "th")].is_equal(m->speeds[speed(*m, "w")].sym));
}

TEST_CASE("names resolve from the innermost subsystem outwards", "[model]") {
  mbsc::Diagnostics d;
  auto m = build(R"(model scopes
parameter l = 2
subsystem arm {
  body b : particle2d { mass 1 }
  coordinate th
  speed w = th'
  constraint position {
    tip: b.x = l*cos(th)
  }
}
constraint position {
  top: arm.b.y = 0
}
)", d);
  INFO(d.format());
  REQUIRE(m);
  REQUIRE(m->constraints.size() == 2);
  CHECK(m->constraints[0].name == "arm.tip");
  CHECK(m->constraints[1].name == "top");
  CHECK(m->constraints[0].residual.has(m->coords[coord(*m, "arm.b.x")].sym));
  CHECK(m->constraints[1].residual.has(m->coords[coord(*m, "arm.b.y")].sym));
  // Post-order storage: leaves first, the root last.
  CHECK(m->nodes.back().name.empty());
  CHECK(m->nodes[m->nodes[0].parent].name == "arm");
}

TEST_CASE("component instances get their own variables and bound formals", "[model]") {
  mbsc::Diagnostics d;
  auto m = build(R"(model comps
parameter m0 = 3
component Bob(mm) {
  body b : particle2d { mass mm }
}
subsystem one : Bob(m0)
subsystem two : Bob(2*m0)
)", d);
  INFO(d.format());
  REQUIRE(m);
  CHECK(coord(*m, "one.b.x") >= 0);
  CHECK(coord(*m, "two.b.y") >= 0);
  REQUIRE(m->formals.count("two.mm"));
  CHECK(m->formals.at("two.mm").value.is_equal(2 * m->params[0].sym));
  int one = -1, two = -1;
  for (size_t n = 0; n < m->nodes.size(); ++n) {
    if (m->nodes[n].name == "one") one = static_cast<int>(n);
    if (m->nodes[n].name == "two") two = static_cast<int>(n);
  }
  CHECK(m->nodes[two].instance_of == one);
  CHECK(m->nodes[one].instance_of == -1);
}

TEST_CASE("decimal literals are exact rationals", "[model]") {
  mbsc::Diagnostics d;
  auto m = build("model n\nparameter a = 0.15, b = 1e-3, c = 2.5E+2\n", d);
  REQUIRE(m);
  CHECK(m->param_defaults[0] == 0.15);
  CHECK(m->param_defaults[1] == 1e-3);
  CHECK(m->param_defaults[2] == 250.0);
}
