// SPDX-License-Identifier: GPL-2.0-or-later
// Language pieces as a user meets them on the command line: a model written with `let`
// generates the same code as the one written without; `print --what invariants` shows a
// knife edge's row; `check` names the massless bodies.
#include <catch2/catch.hpp>
#include <fstream>
#include <sstream>

#include "run_command.hpp"

namespace fs = std::filesystem;
using namespace mbsc_test;

namespace {

const std::string kMbsc = std::string("timeout 120 ") + MBSC_BINARY;

std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Everything after the first line (the banner's line with the source hash).
std::string past_banner(const std::string& text) { return text.substr(text.find('\n')); }

// A slider driven along x with a crank-like law, a pendulum hung from it and a bar hinged
// to the bob. The first form names the driven distance, the half masses, the bob's
// squared speed, a drag force and the bar's half length (lets in constraints, a mass,
// outputs, a force and a point, at the top level and inside bodies).
const std::string kWithLet = R"(model let_demo
parameter m = 1, l = 2, r = 0.5, w = 3, g = 9.81
gravity (0, -g)
let L = sqrt(l^2 - (r*sin(w*t))^2)
body slider : particle2d { let half = m/2 ; mass half + half }
body bob : particle2d { mass m }
coordinate th
speed om = th'
let swing_x = l*sin(th)
constraint position {
  drive: slider.x = r*cos(w*t) + L
  rail: slider.y = 0
  bx: bob.x = slider.x + swing_x
  by: bob.y = -l*cos(th)
}
let v2 = bob.u^2 + bob.v^2
output bob_kinetic = m*v2/2
output gap = L
let drag = 0.1*bob.u
force bob.u : -drag
body arm : rigid2d { let half_l = l/2 ; mass m ; inertia m*l^2/12 ; point tip (half_l, 0) }
joint pin : revolute bob arm.tip
)";

const std::string kWithout = R"(model let_demo
parameter m = 1, l = 2, r = 0.5, w = 3, g = 9.81
gravity (0, -g)
body slider : particle2d { mass m }
body bob : particle2d { mass m }
coordinate th
speed om = th'
constraint position {
  drive: slider.x = r*cos(w*t) + sqrt(l^2 - (r*sin(w*t))^2)
  rail: slider.y = 0
  bx: bob.x = slider.x + l*sin(th)
  by: bob.y = -l*cos(th)
}
output bob_kinetic = m*(bob.u^2 + bob.v^2)/2
output gap = sqrt(l^2 - (r*sin(w*t))^2)
force bob.u : -0.1*bob.u
body arm : rigid2d { mass m ; inertia m*l^2/12 ; point tip (l/2, 0) }
joint pin : revolute bob arm.tip
)";

}  // namespace

TEST_CASE("let: a model written with named expressions generates the code of the one written without",
          "[cli][let]") {
  const fs::path dir = fresh_dir("let");
  fs::create_directories(dir / "a");
  fs::create_directories(dir / "b");
  write(dir / "a" / "let_demo.mbs", kWithLet);
  write(dir / "b" / "let_demo.mbs", kWithout);
  for (const char* side : {"a", "b"}) {
    auto r = run(kMbsc + " generate " + quote((dir / side / "let_demo.mbs").string()) + " -o " +
                 quote((dir / side / "out").string()));
    INFO(side << ":\n" << r.output);
    REQUIRE(r.exit_code == 0);
  }
  for (const char* file : {"let_demo.hpp", "let_demo.cpp"}) {
    INFO(file);
    const std::string a = read_text(dir / "a" / "out" / "let_demo" / file);
    const std::string b = read_text(dir / "b" / "out" / "let_demo" / file);
    REQUIRE(!a.empty());
    CHECK(past_banner(a) == past_banner(b));
  }
  fs::remove_all(dir);
}

TEST_CASE("let: a let that reads a speed is refused where speeds are not allowed, at the use", "[cli][let]") {
  const fs::path dir = fresh_dir("let_speed");
  write(dir / "m.mbs",
             "model m\nbody b : particle2d { mass 1 }\nlet s = b.u + b.x\nconstraint position {\n  b.y = s\n}\n");
  auto r = run(kMbsc + " check " + quote((dir / "m.mbs").string()));
  INFO(r.output);
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("m.mbs:5:9: error: let 's' reads the speed 'b.u', which is not allowed here") != std::string::npos);
  CHECK(r.output.find("error", r.output.find("error") + 1) == std::string::npos);  // one error, not a cascade
  fs::remove_all(dir);
}

TEST_CASE("knife edge: print --what invariants shows the blade's velocity row", "[cli][knife_edge]") {
  const std::string model = quote(std::string(MBSC_SOURCE_DIR) + "/models/chaplygin_sleigh.mbs");
  auto r = run(kMbsc + " print " + model + " --what invariants");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK(r.output.find("runner.lateral (velocity):") != std::string::npos);
  r = run(kMbsc + " check " + model);
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK(r.output.find("2 degree(s) of freedom") != std::string::npos);
}

TEST_CASE("massless links: check names the massless bodies", "[cli][massless]") {
  auto r = run(kMbsc + " check " + quote(std::string(MBSC_SOURCE_DIR) + "/models/massless_rod_pendulum.mbs"));
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK(r.output.find("1 degree(s) of freedom") != std::string::npos);
  CHECK(r.output.find("massless bodies: rod (mass 0, inertia 0); the reduced mass matrix is positive definite at a generic "
                      "configuration and at the reference configuration") != std::string::npos);
}

TEST_CASE("massless links: one cause, one error naming every body of the motion", "[cli][massless]") {
  // The user freezes the bob's mass to 0: the rod already had no inertia. One motion
  // (the rod turning) moves nothing with inertia; the error is at what the user changed.
  const std::string model = std::string(MBSC_SOURCE_DIR) + "/models/massless_rod_pendulum.mbs";
  auto r = run(kMbsc + " check " + quote(model) + " --freeze m=0");
  INFO(r.output);
  CHECK(r.exit_code == 1);
  int errors = 0;
  for (auto at = r.output.find(": error: "); at != std::string::npos; at = r.output.find(": error: ", at + 1)) ++errors;
  CHECK(errors == 1);
  CHECK(r.output.find(model + ":14:30: error: bodies 'bob' (mass 0, with --freeze m=0) and 'rod' (inertia 0) carry no "
                              "inertia and the reduced mass matrix is singular: the motion along rod.w moves bob (bob.u, "
                              "bob.v) and turns rod (rod.w) and nothing with inertia; give 'bob' a mass or 'rod' an "
                              "inertia, or constrain that motion") != std::string::npos);
}

TEST_CASE("massless links: a chain in absolute angles (rates solved step by step) finds its massless bob",
          "[cli][massless]") {
  // The positive-definiteness check runs the chain's rate steps numerically instead of
  // forming the symbolic M; a massless last bob must still make M singular there, and
  // a massive one must not.
  std::string model = "model chain3\nparameter m = 1.0, l = 1.0, g = 9.81\ngravity (0, -g)\n"
                      "body b1 : particle2d { mass m }\nbody b2 : particle2d { mass m }\n"
                      "body b3 : particle2d { mass MASS }\n"
                      "coordinate th1, th2, th3\nspeed w1 = th1', w2 = th2', w3 = th3'\n"
                      "constraint position {\n"
                      "  b1x: b1.x = l*sin(th1)\n  b1y: b1.y = -l*cos(th1)\n"
                      "  b2x: b2.x = b1.x + l*sin(th2)\n  b2y: b2.y = b1.y - l*cos(th2)\n"
                      "  b3x: b3.x = b2.x + l*sin(th3)\n  b3y: b3.y = b2.y - l*cos(th3)\n}\n"
                      "independent w1, w2, w3\n";
  const fs::path dir = fresh_dir("massless_chain");
  for (const char* mass : {"m", "0"}) {
    std::string text = model;
    text.replace(text.find("MASS"), 4, mass);
    write(dir / "chain3.mbs", text);
    auto r = run(kMbsc + " check " + quote((dir / "chain3.mbs").string()));
    INFO(r.output);
    if (std::string(mass) == "m") {
      CHECK(r.exit_code == 0);
      CHECK(r.output.find("3 degree(s) of freedom") != std::string::npos);
    } else {
      CHECK(r.exit_code == 1);
      CHECK(r.output.find("chain3.mbs:6:29: error: body 'b3' is massless (mass 0) and the reduced mass matrix is singular: "
                          "the motion along w3 moves it") != std::string::npos);
    }
  }
}
