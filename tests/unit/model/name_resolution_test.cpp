// SPDX-License-Identifier: GPL-2.0-or-later
// A body's own variables against parameters of the same name: the one allowed at the
// place wins, both allowed is an ambiguity naming both spellings, and `global.NAME`
// always names the parameter.
#include <catch2/catch.hpp>

#include "mbsc/model/build.hpp"
#include "mbsc/parse/parse.hpp"

namespace {

std::optional<mbsc::model::Model> build(const std::string& text, mbsc::Diagnostics& d) {
  auto file = mbsc::parse::parse_text(text, "t.mbs", d);
  if (!file) return std::nullopt;
  return mbsc::model::build(*file, d);
}

const mbsc::model::Variable& named(const std::vector<mbsc::model::Variable>& vars, const std::string& name) {
  for (const auto& v : vars)
    if (v.name == name) return v;
  throw std::runtime_error("no variable " + name);
}

}  // namespace

TEST_CASE("a speed does not capture a parameter where speeds are not allowed", "[model][names]") {
  mbsc::Diagnostics d;
  auto m = build(R"(model m
parameter u = 0.25
body b : rigid2d { mass 1  inertia 1  point G (0, -u) }
joint j : revolute ground.origin b.G
)", d);
  INFO(d.format());
  REQUIRE(m);
  CHECK(d.all().empty());
  const GiNaC::ex u_param = named(m->params, "u").sym, u_speed = named(m->speeds, "b.u").sym;
  REQUIRE(m->constraints.size() == 2);
  bool uses_param = false;
  for (const auto& c : m->constraints) {
    CHECK_FALSE(c.residual.has(u_speed));
    uses_param = uses_param || c.residual.has(u_param);
  }
  CHECK(uses_param);
}

TEST_CASE("where both are allowed the name is ambiguous; global.NAME and b.NAME say which", "[model][names]") {
  mbsc::Diagnostics d;
  CHECK_FALSE(build("model m\nparameter u = 1\nbody b : particle2d { mass 1\n output s = 2*u }\n", d));
  REQUIRE(d.all().size() == 1);
  CHECK(d.all()[0].message ==
        "'u' is ambiguous here: the speed 'b.u' or the parameter 'u'; write 'b.u' for the speed or 'global.u' for "
        "the parameter");
  mbsc::Diagnostics ok;
  auto m = build("model m\nparameter u = 1\nbody b : particle2d { mass 1\n output s = 2*global.u + b.u }\n", ok);
  INFO(ok.format());
  REQUIRE(m);
  REQUIRE(m->outputs.size() == 1);
  const GiNaC::ex u_param = named(m->params, "u").sym, u_speed = named(m->speeds, "b.u").sym;
  CHECK((m->outputs[0].value - (2 * u_param + u_speed)).is_zero());
  // Outside the body there is nothing to choose: `u` is the parameter, as before.
  mbsc::Diagnostics top;
  auto t = build("model m\nparameter u = 1\nbody b : particle2d { mass 1 }\noutput s = u\n", top);
  REQUIRE(t);
  CHECK(t->outputs[0].value.is_equal(named(t->params, "u").sym));
  // A node's own variable shadows an outer node's, as before (no parameter involved).
  mbsc::Diagnostics nested;
  auto n = build("model m\ncoordinate q\nspeed dq = q'\nsubsystem a {\n coordinate q\n speed dq = q'\n output s = q }\n",
                 nested);
  INFO(nested.format());
  REQUIRE(n);
  CHECK(n->outputs[0].value.is_equal(named(n->coords, "a.q").sym));
}

TEST_CASE("global.NAME names only parameters, inputs and t", "[model][names]") {
  mbsc::Diagnostics d;
  CHECK_FALSE(build("model m\nparameter l = 1\nbody b : particle2d { mass 1 }\noutput s = global.b\n", d));
  REQUIRE(d.all().size() == 1);
  CHECK(d.all()[0].message == "no parameter or input 'b' for 'global.b'");
  mbsc::Diagnostics ok;
  auto m = build("model m\ninput tau\nbody b : particle2d { mass 1\n force u : global.tau*global.t }\n", ok);
  INFO(ok.format());
  REQUIRE(m);
  REQUIRE(m->forces.size() == 1);
  CHECK((m->forces[0].value - named(m->inputs, "tau").sym * m->time).is_zero());
}
