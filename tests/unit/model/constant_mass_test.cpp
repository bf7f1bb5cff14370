// SPDX-License-Identifier: GPL-2.0-or-later
// Masses and inertias are constants (a body's inertia forces m v', J w' lack the dm/dt
// terms), while a custom leaf's kinetic energy may read its coordinates.
#include <catch2/catch.hpp>

#include "mbsc/model/build.hpp"
#include "mbsc/parse/parse.hpp"

namespace {

std::optional<mbsc::model::Model> build(const std::string& text, mbsc::Diagnostics& d,
                                        const std::map<std::string, double>& frozen = {}) {
  auto file = mbsc::parse::parse_text(text, "test.mbs", d);
  if (!file) return std::nullopt;
  return mbsc::model::build(*file, d, frozen);
}

const mbsc::model::Node& node(const mbsc::model::Model& m, const std::string& name) {
  for (const auto& n : m.nodes)
    if (n.name == name) return n;
  throw std::runtime_error("no node " + name);
}

}  // namespace

TEST_CASE("a mass of parameters, lets of parameters and component arguments is accepted", "[model][mass]") {
  const std::string text = R"(model ok
parameter m = 1, J = 0.5, k = 2
let twice = 2*m
component Ball(mm) {
  body b : particle2d { mass mm }
}
body r : rigid2d { mass twice*k  inertia J + m/12 }
subsystem s : Ball(3*m)
)";
  mbsc::Diagnostics d;
  auto m = build(text, d);
  INFO(d.format());
  REQUIRE(m);
  const GiNaC::ex mp = m->params[0].sym, jp = m->params[1].sym, kp = m->params[2].sym;
  CHECK((node(*m, "r").mass - 2 * mp * kp).is_zero());
  CHECK((node(*m, "r").inertia - (jp + mp / 12)).is_zero());
  // Frozen parameters are constants too.
  mbsc::Diagnostics frozen;
  CHECK(build(text, frozen, {{"m", 4}, {"J", 0}}));
  CHECK(!frozen.has_errors());
}

TEST_CASE("a mass or inertia that varies with the motion is refused, naming body and variable", "[model][mass]") {
  struct Case {
    const char* body;
    const char* reads;
  };
  const std::pair<std::string, Case> cases[] = {
      {"body b : particle2d { mass m*(1 + b.y^2) }", {"mass of body 'b'", "coordinate 'b.y'"}},
      {"body b : particle2d { mass m*exp(-t) }", {"mass of body 'b'", "the time t"}},
      {"body b : particle2d { mass m*(1 + b.v^2) }", {"mass of body 'b'", "speed 'b.v'"}},
      {"let r = 1 + b.x^2\nbody b : particle2d { mass m*r }", {"mass of body 'b'", "coordinate 'b.x'"}},
      {"input F\nbody b : particle2d { mass m + F }", {"mass of body 'b'", "input 'F'"}},
      {"body b : rigid2d { mass m  inertia m*(2 + sin(theta)) }", {"inertia of body 'b'", "coordinate 'b.theta'"}},
  };
  for (const auto& [body, expected] : cases) {
    INFO(body);
    mbsc::Diagnostics d;
    CHECK(!build("model bad\nparameter m = 1\n" + body + "\n", d));
    const std::string message = std::string(expected.body) + " must be constant: it reads " + expected.reads;
    INFO(d.format());
    CHECK(d.format().find(message) != std::string::npos);
    CHECK(d.error_count() == 1);
  }
}

TEST_CASE("a custom leaf's kinetic energy may read its coordinates", "[model][mass]") {
  // A bead whose effective mass m (1 + q^2) depends on where it is: written as a custom
  // leaf with its own forces, which hold the d/dt terms, and its kinetic energy.
  mbsc::Diagnostics d;
  auto m = build(R"(model bead
parameter m = 1, k = 2
subsystem c : custom {
  coordinate q
  speed w = q'
  force w : -m*(1 + q^2)*w' - m*q*w^2 - k*q
  kinetic m*(1 + q^2)*w^2/2
}
)", d);
  INFO(d.format());
  REQUIRE(m);
  const auto& c = node(*m, "c");
  REQUIRE(c.has_kinetic);
  CHECK(c.kinetic.has(m->coords[0].sym));
  CHECK(c.kinetic.has(m->speeds[0].sym));
}
