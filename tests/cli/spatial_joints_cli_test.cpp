// SPDX-License-Identifier: GPL-2.0-or-later
// Spatial joints through the command line: `mbsc check` counts the degrees of freedom a
// joint leaves (6 per free body minus the joint's independent rows: the numeric rank the
// check computes must equal the count of the vector forms' rows), and `print --what
// invariants` shows the joint's rows under their names.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "run_command.hpp"

using namespace mbsc_test;

namespace {
std::string path(const std::string& rel) { return quote(std::string(MBSC_SOURCE_DIR) + "/" + rel); }
const std::string kMbsc = MBSC_BINARY;
}  // namespace

TEST_CASE("spatial joints: check counts the freedom each joint leaves", "[cli][spatial_joints]") {
  // Body a hangs from the ground by a spherical joint (3 dof); body b (6) is joined to
  // it by the joint under test, which removes: spherical 3, revolute 5, universal 4,
  // cylindrical 4, prismatic 5, weld 6, point_on_line 2, point_on_plane 1.
  struct Case {
    const char* kind;
    int rows, dof;
  };
  for (const Case& c : {Case{"spherical", 3, 6}, Case{"revolute", 5, 4}, Case{"universal", 4, 5},
                        Case{"cylindrical", 4, 5}, Case{"prismatic", 5, 4}, Case{"weld", 6, 3},
                        Case{"point_on_line", 2, 7}, Case{"point_on_plane", 1, 8}}) {
    INFO(c.kind);
    const auto r = run(kMbsc + " check " + path(std::string("tests/data/spatial_joints/chain_") + c.kind + ".mbs"));
    INFO(r.output);
    CHECK(r.exit_code == 0);
    CHECK(r.output.find(std::string("model chain_") + c.kind + ": " + std::to_string(c.dof) + " degree(s) of freedom") !=
          std::string::npos);
    const std::string rank = std::to_string(3 + c.rows);
    CHECK(r.output.find(std::to_string(3 + c.rows) + " constraint(s), rank " + rank + ", " + std::to_string(c.dof) + " dof") !=
          std::string::npos);
  }
  // The heavy top: a body held at one point turns freely about it.
  const auto r = run(kMbsc + " check " + path("models/heavy_top.mbs"));
  CHECK(r.exit_code == 0);
  CHECK(r.output.find("model heavy_top: 3 degree(s) of freedom") != std::string::npos);
}

TEST_CASE("spatial joints: print shows the rows a joint expands into", "[cli][spatial_joints]") {
  // A door on a revolute joint about the raised ground axis (0, 0, 1) + s (0, 1, 0), its
  // edge at (-w/2, 0, 0) in the body: the rows are the vector form written out (the
  // ground axis's normals are n1 = y x x = (0, 0, -1), n2 = y x n1 = (-1, 0, 0)).
  auto r = run(kMbsc + " print " + path("tests/data/spatial_joints/door.mbs") + " --what invariants");
  INFO(r.output);
  CHECK(r.exit_code == 0);
  for (const char* row : {"hinge.x (position): 1/2*(door.e0^2 + door.e1^2 - door.e2^2 - door.e3^2)*w - door.x = 0",
                          "hinge.y (position): door.e0*door.e3*w + door.e1*door.e2*w - door.y = 0",
                          "hinge.z (position): 1 - door.e0*door.e2*w + door.e1*door.e3*w - door.z = 0",
                          "hinge.align1 (position): -2*door.e0*door.e1 - 2*door.e2*door.e3 = 0",
                          "hinge.align2 (position): 2*door.e0*door.e3 - 2*door.e1*door.e2 = 0"})
    CHECK(r.output.find(row) != std::string::npos);
  r = run(kMbsc + " check " + path("tests/data/spatial_joints/door.mbs"));
  CHECK(r.output.find("model door: 1 degree(s) of freedom") != std::string::npos);
}

TEST_CASE("spatial joints: a ground point in space", "[cli][spatial_joints]") {
  // The top's tip on a raised ground point: the same 3 dof.
  const auto dir = fresh_dir("spatial_ground");
  const auto file = dir / "raised.mbs";
  {
    std::ofstream out(file);
    out << "model raised\ngravity (0, 0, -9.81)\nground {\n  point P (0.5, 0, 1)\n}\n"
           "body top : rigid3d {\n  mass 1\n  inertia (1, 1, 2)\n  point tip (0, 0, -0.1)\n}\n"
           "joint pivot : spherical ground.P top.tip\n";
  }
  const auto r = run(kMbsc + " print " + quote(file.string()) + " --what invariants");
  INFO(r.output);
  CHECK(r.exit_code == 0);
  CHECK(r.output.find("pivot.x") != std::string::npos);
  CHECK(r.output.find("pivot.x (position): 1/2 + 1/5*top.e0*top.e2 + 1/5*top.e1*top.e3 - top.x = 0") != std::string::npos);
  std::filesystem::remove_all(dir);
}

TEST_CASE("spatial joint coordinates: every instance of a component places its own body", "[cli][spatial_joints]") {
  // Two instances of a component whose hinge has a coordinate: each places its link
  // (3 position rows and 3 angular velocity rows), 2 x (6 + 6 + 1 - 6) = 14 freedoms. A
  // joint placed only in the first instance would leave the second link free (20).
  const auto r = run(kMbsc + " check " + path("tests/data/spatial_joints/arm_component.mbs"));
  INFO(r.output);
  CHECK(r.exit_code == 0);
  CHECK(r.output.find("model arm_component: 14 degree(s) of freedom") != std::string::npos);
  CHECK(r.output.find("constraints (12)") != std::string::npos);
  CHECK(r.output.find("arm1.q arm2.base.x") != std::string::npos);  // no attitude coordinates for the links
}

TEST_CASE("spatial joint coordinates: a rebuilt joint angle is defined before the named rotations that read it",
          "[cli][spatial_joints][names]") {
  // Link 5 is five joints from the ground, so its rotation is named (docs/formulation.md,
  // "Named body rotations"); q5 is tied to q1, and --state minimal rebuilds it.
  const auto dir = fresh_dir("chain6_tied");
  const auto r = run(kMbsc + " generate " + path("tests/data/spatial_joints/chain6_tied.mbs") + " -q --state minimal -o " +
                     quote(dir.string()));
  INFO(r.output);
  CHECK(r.exit_code == 0);
  CHECK(std::filesystem::exists(dir / "chain6_tied" / "chain6_tied.cpp"));
  std::filesystem::remove_all(dir);
}

TEST_CASE("the tree recursion conserves a tumbling humanoid's energy, in both states", "[cli][spatial_joints][tree]") {
  // tests/data/spatial_joints/humanoid_tree.mbs: a free torso with four three-link limbs,
  // no dissipation; auto takes the articulated-body recursion. One second at tight
  // tolerances: the energy stays put (relative change below 1e-9).
  const auto dir = fresh_dir("humanoid_tree");
  for (const std::string state : {"full", "minimal"}) {
    const auto r = run(kMbsc + " run " + path("tests/data/spatial_joints/humanoid_tree.mbs") + " --state " + state +
                       " --t-end 1 --rtol 1e-10 -o " + quote((dir / (state + ".csv")).string()) + " --cache-dir " +
                       quote((dir / "cache").string()));
    INFO(state << ": " << r.output);
    REQUIRE(r.exit_code == 0);
    const auto at = r.output.find("energy change: largest |E - E0| = ");
    REQUIRE(at != std::string::npos);
    const double change = std::stod(r.output.substr(at + 35));
    const auto e0_at = r.output.find("(E0 = ", at);
    REQUIRE(e0_at != std::string::npos);
    const double e0 = std::stod(r.output.substr(e0_at + 6));
    CHECK(std::fabs(change) < 1e-9 * std::fabs(e0));
  }
  std::filesystem::remove_all(dir);
}
