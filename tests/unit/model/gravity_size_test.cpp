// SPDX-License-Identifier: GPL-2.0-or-later
// The gravity vector has the bodies' dimension: two components for planar bodies, three
// when a spatial one is present (mixed models: the planar bodies feel gx and gy).
#include <catch2/catch.hpp>

#include "mbsc/model/build.hpp"
#include "mbsc/parse/parse.hpp"
#include "mbsc/sym/own_force.hpp"

namespace {

std::optional<mbsc::model::Model> build(const std::string& text, mbsc::Diagnostics& d) {
  auto file = mbsc::parse::parse_text(text, "t.mbs", d);
  if (!file) return std::nullopt;
  return mbsc::model::build(*file, d);
}

std::string first_error(const std::string& text) {
  mbsc::Diagnostics d;
  build(text, d);
  for (const auto& x : d.all())
    if (x.severity == mbsc::Severity::Error)
      return std::to_string(x.pos.line) + ":" + std::to_string(x.pos.col) + ": " + x.message;
  return "";
}

}  // namespace

TEST_CASE("gravity: two components for planar bodies, three for spatial ones", "[model][gravity]") {
  CHECK(first_error("model m\ngravity (0, -9.81)\nbody a : particle2d { mass 1 }\nbody b : rigid2d { mass 1  inertia 1 }\n") == "");
  CHECK(first_error("model m\ngravity (0, 0, -9.81)\nbody a : particle3d { mass 1 }\n") == "");
  CHECK(first_error("model m\ngravity (0, 0, -9.81)\nbody a : particle2d { mass 1 }\n") ==
        "2:1: gravity has 3 components, but the bodies are planar (particle2d 'a' moves in the x-y plane, so gz would be "
        "ignored): write gravity (gx, gy)");
  CHECK(first_error("model m\nparametrization nodal\ngravity (0, 0, -9.81)\nbody a : rigid2d { mass 1  inertia 1\n"
                    " point P (0, 0)\n point Q (1, 0) }\n") ==
        "3:1: gravity has 3 components, but the bodies are planar (rigid2d_nodal 'a' moves in the x-y plane, so gz would "
        "be ignored): write gravity (gx, gy)");
  // A model without bodies has nothing to match.
  CHECK(first_error("model m\ngravity (0, 0, -9.81)\nsubsystem s : custom { speed w\n force w : -w' }\n") == "");
}

TEST_CASE("gravity: a mixed model takes three components; its planar bodies feel gx and gy", "[model][gravity]") {
  CHECK(first_error("model m\ngravity (0, -9.81)\nbody a : particle2d { mass 1 }\nbody b : particle3d { mass 1 }\n") ==
        "2:1: gravity has 2 components, but body 'b' is particle3d (spatial): write gravity (gx, gy, gz)");
  mbsc::Diagnostics d;
  auto m = build("model m\nparameter gx = 1, gy = 2, gz = 3\ngravity (gx, gy, gz)\nbody a : particle2d { mass 5 }\n"
                 "body b : particle3d { mass 7 }\n",
                 d);
  INFO(d.format());
  REQUIRE(m);
  GiNaC::exmap at_rest;
  for (const auto& s : m->speed_dots) at_rest[s] = 0;
  std::map<std::string, GiNaC::ex> f;
  for (std::size_t i = 0; i < m->speeds.size(); ++i)
    f[m->speeds[i].name] = mbsc::sym::own_force(*m, static_cast<int>(i)).subs(at_rest);
  GiNaC::ex gx = m->params[0].sym, gy = m->params[1].sym, gz = m->params[2].sym;
  CHECK((f.at("a.u") - 5 * gx).is_zero());
  CHECK((f.at("a.v") - 5 * gy).is_zero());
  CHECK((f.at("b.u") - 7 * gx).is_zero());
  CHECK((f.at("b.v") - 7 * gy).is_zero());
  CHECK((f.at("b.w") - 7 * gz).is_zero());
}
