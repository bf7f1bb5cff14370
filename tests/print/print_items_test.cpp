// SPDX-License-Identifier: GPL-2.0-or-later
// What `mbsc print` lists beside the matrices, through the command as a user runs it:
// the "where" list holds only what the shown entries read (an alias is shown by its
// value), --expand writes the dependent speeds through the independent ones (checked
// against the velocity constraint solved by hand), and an empty --what is an error.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <string>

#include "cli/run_command.hpp"

namespace fs = std::filesystem;

namespace {

/// A gantry crane: a cart on a rail, a load on a massless cable, the speeds of the cable
/// and the load chosen independent, so the cart's speed is dependent and its damping
/// force reads it. The derivation names e_cart_u equal to e_cable_u (an alias).
const char* kCrane = R"(model crane
parameter M = 10, m = 2, L = 1.5, g = 9.81, c = 0.5
input F
gravity (0, -g)
body cart : rigid2d { mass M ; inertia 1 ; point hook (0, 0) }
body cable : rigid2d { mass 0 ; inertia 0 ; point top (0, 0) ; point end (0, -L) }
body load : particle2d { mass m }
joint rail : prismatic ground.x_axis cart.hook
joint hoist : revolute cart.hook cable.top
joint hang : revolute cable.end load
force cart.u : F - c*cart.u
)";

/// A body hinged at an offset point: M reads nothing, h reads e_ and r_ variables.
const char* kOffset = R"(model offset
parameter d = 0.5, m = 1, J = 1, g = 9.81
gravity (0, -g)
body b : rigid2d { mass m  inertia J  point G (0, d) }
joint j : revolute ground.origin b.G
)";

fs::path write_model(const std::string& name, const std::string& text) {
  const fs::path dir = fs::temp_directory_path() / "mbsc_print_items_test";
  fs::create_directories(dir);
  const fs::path file = dir / (name + ".mbs");
  std::ofstream(file) << text;
  return file;
}

mbsc_test::CommandResult print(const fs::path& model, const std::string& flags) {
  return mbsc_test::run(std::string(MBSC_BINARY) + " print -q " + model.string() + " " + flags);
}

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace

TEST_CASE("print: the where list holds only what the shown entries read", "[print][where]") {
  const fs::path offset = write_model("offset", kOffset);
  // M alone reads no intermediate: no list (before: e_b_v, e_b_u, r_b_v, read only by h).
  for (const char* what : {"M", "invariants,M", "M,invariants"}) {
    INFO(what);
    const auto r = print(offset, std::string("--what ") + what);
    REQUIRE(r.exit_code == 0);
    CHECK(has(r.output, "J + d^2*m"));
    CHECK(!has(r.output, "where"));
    CHECK(!has(r.output, "e_b_"));
  }
  // h reads them: listed, each after what it reads. (The offset pendulum's own h is
  // closed now: a node this small has its recurrences inlined, docs/formulation.md step
  // 6; the three-link arm keeps them.)
  const fs::path arm = fs::path(MBSC_SOURCE_DIR) / "models" / "three_r_arm.mbs";
  const auto h = print(arm, "--what h");
  REQUIRE(h.exit_code == 0);
  const auto where = h.output.find("where"), ev = h.output.find("  e_link1_v = "), rv = h.output.find("  r_link1_v = ");
  CHECK((where != std::string::npos && where < ev && ev < rv && rv != std::string::npos));
  // M then h: one list after the run, with what h reads.
  const auto mh = print(arm, "--what M,h");
  CHECK(has(mh.output, "  r_link1_v = "));
}

TEST_CASE("print: a pure alias is shown by its value, not listed", "[print][where]") {
  const fs::path crane = write_model("crane", kCrane);
  const auto r = print(crane, "--what h");
  REQUIRE(r.exit_code == 0);
  CHECK(!has(r.output, "e_cart_u"));  // before: "e_cart_u = e_cable_u", read by r_cart_u
  CHECK(has(r.output, "  e_cable_u = L*cable.w^2*sin(cable.theta)\n"));
  CHECK(has(r.output, "  r_cart_u = F - M*e_cable_u - c*cart.u\n"));
}

TEST_CASE("print --expand: dependent speeds through the independent ones", "[print][expand]") {
  // z = (cable.w, load.u); the hang and hoist joints give load.u = cart.u + L cos(theta) w
  // (the load's velocity), so cart.u = load.u - L*cable.w*cos(cable.theta), and the
  // damping force F - c*cart.u reads F - c*load.u + c*L*cable.w*cos(cable.theta).
  const fs::path crane = write_model("crane", kCrane);
  const auto r = print(crane, "--what h --expand");
  REQUIRE(r.exit_code == 0);
  CHECK(!has(r.output, "cart.u"));
  CHECK(has(r.output, "[load.u', value] = F - L*M*cable.w^2*sin(cable.theta) + L*c*cable.w*cos(cable.theta) - c*load.u\n"));
  // Without --expand h reads the state as the generated code does (cart.u included).
  CHECK(has(print(crane, "--what h").output, "c*cart.u"));
}

TEST_CASE("print --expand: a dependent speed without a closed form is named in a note", "[print][expand]") {
  // The extra speed's constraint is not linear in bob.u: the rebuild cannot give it.
  const fs::path model = fs::path(MBSC_SOURCE_DIR) / "models" / "spherical_pendulum_extra_speed.mbs";
  const auto r = print(model, "--what M,h --expand");
  REQUIRE(r.exit_code == 0);
  CHECK(has(r.output, "note: h reads the dependent speed"));
  CHECK(has(r.output, "bob.u"));
  // The crane's closed form reads z only: no note.
  CHECK(!has(print(write_model("crane", kCrane), "--what M,h --expand").output, "note: h reads"));
}

TEST_CASE("print --what with no item is an error, not a silent default", "[print][cli]") {
  const fs::path offset = write_model("offset", kOffset);
  for (const char* flags : {"--what ''", "--what ,", "--what ' '"}) {
    INFO(flags);
    const auto r = print(offset, flags);
    CHECK(r.exit_code == 1);
    CHECK(has(r.output, "error: --what: no item given"));
    CHECK(has(r.output, "leave --what out for the default set"));
    CHECK(!has(r.output, "subsystem offset"));  // nothing half-printed
  }
  // Left out: the default set, M first.
  const auto r = print(offset, "");
  CHECK(r.exit_code == 0);
  CHECK(has(r.output, "M (1 x 1)"));
  CHECK(has(r.output, "fbar (1 x 1)"));
}
