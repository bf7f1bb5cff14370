// SPDX-License-Identifier: GPL-2.0-or-later
// The messages docs/language.md quotes are the ones mbsc prints: each is produced by a
// real run (a model of tests/data/bad or a shipped one with a flag) and found in the
// document, its line breaks read as spaces.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "run_command.hpp"

using namespace mbsc_test;

namespace {

/// The document with every run of whitespace (line breaks, indentation) one space.
std::string flowing_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return std::regex_replace(ss.str(), std::regex("\\s+"), " ");
}

}  // namespace

TEST_CASE("docs/language.md quotes the messages mbsc prints", "[cli][docs]") {
  const std::string root = MBSC_SOURCE_DIR, bad = root + "/tests/data/bad/", dp = root + "/models/double_pendulum.mbs";
  const std::string doc = flowing_text(root + "/docs/language.md");
  struct Quote {
    std::string arguments, message;
  };
  const Quote quotes[] = {
      {"check " + bad + "spatial_friction_negative.mbs", "the friction coefficient must not be negative (it is -0.3)"},
      {"check " + bad + "planar_friction.mbs", "unknown option 'friction'"},
      {"check " + bad + "spatial_friction_on_revolute.mbs", "'friction' is available on spatial prismatic and cylindrical joints only"},
      {"check " + quote(dp) + " --freeze m1=-1", "mass of body 'b1' is negative (-1), with --freeze m1=-1"},
      {"check " + quote(dp) + " --freeze m1=1e-320", "number '1e-320' is too small for a double"},
      {"check " + bad + "value_mass_too_large.mbs", "the mass of body 'b': 2e+307 is larger in magnitude than 1e+30"},
      {"check " + quote(dp) + " --freeze gg=1",
       "error: --freeze: model 'double_pendulum' has no parameter 'gg' (did you mean 'g'?)"},
      {"print " + quote(dp) + " --what inavriants",
       "mbsc: error: --what: unknown item 'inavriants' (did you mean 'invariants'?) (known: eom M h invariants rates A B C "
       "S f fbar)"},
      {"check " + bad + "mass_reads_coordinate_through_let.mbs",
       "mass of body 'b' must be constant: it reads coordinate 'q' ("},
      {"check " + bad + "latex_on_let.mbs",
       "latex: 's' is a let (a named expression substituted where it is used); it has no symbol of its own to name in "
       "LaTeX"},
      {"check " + bad + "let_in_gravity.mbs",
       "let 'G' cannot be used in gravity: lets are read after the parameters, gravity and the ground (write its "
       "expression here instead)"},
      {"check " + bad + "parameter_declared_later.mbs",
       "parameter 'k' is declared after the default of parameter 'm' (at 3:11); declare it first"},
      {"check " + bad + "parameter_named_pi.mbs", "parameter 'pi' clashes with the constant pi "},
      {"check " + bad + "unknown_point_suggestion.mbs",
       "unknown point 'ground.orgin' (did you mean 'ground.origin'?) (a point of a rigid2d body or the ground, or a "
       "particle2d body)"},
      {"check " + bad + "joint_kind_typo.mbs",
       "unknown joint kind 'revolut' (did you mean 'revolute'?) (known: revolute, prismatic, pin_in_slot, weld, gear, "
       "rolling, rolling_inside, knife_edge, spherical, universal, cylindrical, point_on_line, point_on_plane, rolling_sphere)"},
      {"check " + bad + "coordinate_clashes_parameter.mbs", "coordinate 'th' is already declared as a parameter at 2:11"},
      {"check " + bad + "duplicate_subsystem.mbs", "body 'b' is already declared as a body at 2:6"},
      {"check " + bad + "coordinate_clashes_builtin.mbs",
       "coordinate 'b.x' is already declared as a coordinate of the particle2d body at 3:6"},
      {"check " + bad + "point_declared_twice.mbs", "axis 'b.A' is declared twice (as a point at 5:9)"},
      {"check " + bad + "duplicate_output.mbs", "output 'o' is already declared at 3:8"},
      {"check " + bad + "joint_coordinate_placed_twice.mbs",
       "joint 'again': body 'b' is already placed by joint 'elbow' (at 5:1); a body is the second end of at most one "
       "joint with a coordinate (close a loop with a joint without one)"},
      {"check " + bad + "spatial_spring_particle3d.mbs",
       "spring 's': 'ball' is a particle3d body, not a point; a spatial spring connects points (BODY.NAME) of rigid3d "
       "bodies and the ground"},
      {"check " + bad + "spatial_spring_planar_body.mbs",
       "spring 's': 'plate.P' is on rigid2d body 'plate'; a spatial spring connects rigid3d bodies and the ground"},
      {"check " + bad + "spatial_rotational_spring_without_joint.mbs",
       "spring 's': a rotational spring in space needs a revolute or cylindrical joint between its axes 'a.h' and 'b.h' "
       "(none joins them), which keeps them parallel"},
  };
  for (const auto& q : quotes) {
    INFO("mbsc " << q.arguments);
    const auto r = run(std::string(MBSC_BINARY) + " " + q.arguments);
    INFO(r.output);
    CHECK(r.exit_code == 1);
    CHECK(r.output.find(q.message) != std::string::npos);
    CHECK(doc.find(q.message) != std::string::npos);
  }
  // A warning (exit 0): the shipped gantry crane with a massless cart.
  const auto r = run(std::string(MBSC_BINARY) + " check " + quote(root + "/models/gantry_crane.mbs") + " --freeze M=0");
  INFO(r.output);
  CHECK(r.exit_code == 0);
  const std::string warning =
      "models/gantry_crane.mbs:14:28: warning: the reduced mass matrix is positive definite at a generic configuration "
      "but singular at the reference configuration";
  const std::string culprits = "there the motion along v, w moves only bodies without inertia, 'cart' (mass 0, with "
                               "--freeze M=0: cart.u) and 'load' (inertia 0: load.w)";
  CHECK(r.output.find(culprits) != std::string::npos);
  CHECK(r.output.find(warning.substr(warning.find(":14:28:"))) != std::string::npos);
  CHECK(doc.find(warning) != std::string::npos);
  CHECK(doc.find(culprits) != std::string::npos);
}
