// SPDX-License-Identifier: GPL-2.0-or-later
// The subcommands as a user meets them: --help, check, print.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "run_command.hpp"

using namespace mbsc_test;

namespace {
std::string model(const char* name) { return quote(std::string(MBSC_SOURCE_DIR) + "/models/" + name); }
const std::string kMbsc = MBSC_BINARY;
}  // namespace

TEST_CASE("--help on each subcommand", "[cli]") {
  for (const char* sub : {"", " check", " print", " generate"}) {
    auto r = run(kMbsc + sub + " --help");
    INFO(sub);
    CHECK(r.exit_code == 0);
    CHECK(r.output.find("Usage") != std::string::npos);
  }
  CHECK(run(kMbsc).exit_code == 1);
}

TEST_CASE("check reports the degrees of freedom and the partition", "[cli]") {
  auto r = run(kMbsc + " check " + model("double_pendulum.mbs"));
  CHECK(r.exit_code == 0);
  CHECK(r.output.find("model double_pendulum: 2 degree(s) of freedom") != std::string::npos);
  CHECK(r.output.find("independent speeds: w1, w2") != std::string::npos);
  r = run(kMbsc + " check " + model("five_bar.mbs"));
  CHECK(r.exit_code == 0);
  CHECK(r.output.find("4 degree(s) of freedom") != std::string::npos);
  CHECK(r.output.find("by LU in generated code") != std::string::npos);
  r = run(kMbsc + " check " + model("four_bar_toggle.mbs"));
  CHECK(r.exit_code == 0);
  CHECK(r.output.find("partitions for run-time re-selection (rhs_partition): crank.w | rocker.w | coupler.w") !=
        std::string::npos);
}

TEST_CASE("print shows the matrices of a subsystem, in text and LaTeX", "[cli]") {
  auto r = run(kMbsc + " print " + model("five_bar.mbs") + " --node linkage.left --what B,C,fbar");
  CHECK(r.exit_code == 0);
  CHECK(r.output.find("subsystem linkage.left") != std::string::npos);
  CHECK(r.output.find("C (8 x 2)") != std::string::npos);
  r = run(kMbsc + " print " + model("double_pendulum.mbs") + " --what M --latex");
  CHECK(r.exit_code == 0);
  // A matrix when its entries are short, else one entry per line (tests/cli/latex_test.cpp).
  CHECK((r.output.find("\\mathbf{M} = \\begin{pmatrix}") != std::string::npos ||
         r.output.find("\\mathbf{M}_{1,1} &= ") != std::string::npos));
  r = run(kMbsc + " print " + model("double_pendulum.mbs") + " --stats");
  CHECK(r.exit_code == 0);
  CHECK(r.output.find("rhs") != std::string::npos);
  // h reads named variables (e_ rates, r_ suffix sums): they are listed under it, each
  // after the ones it reads. (The three-link arm: the double pendulum's recurrences are
  // inlined, a node that small, docs/formulation.md step 6.)
  r = run(kMbsc + " print " + model("three_r_arm.mbs") + " --what h");
  CHECK(r.exit_code == 0);
  const auto where = r.output.find("where (evaluated in this order; --expand writes the closed form instead)");
  const auto e1 = r.output.find("  e_link1_u = "), e2 = r.output.find("  e_link2_u = "), r1 = r.output.find("  r_link1_u = ");
  CHECK(where != std::string::npos);
  CHECK((where < e1 && e1 < e2 && e2 < r1 && r1 != std::string::npos));
  // With --state minimal the state is smaller, so rhs counts fewer operations.
  auto ops_of_rhs = [](const std::string& stats) {
    const auto at = stats.find("\nrhs ");
    const auto end = stats.find('\n', at + 1);
    const std::string line = stats.substr(at + 1, end - at - 1);
    return std::stol(line.substr(line.find_last_of(' ') + 1));
  };
  const long full = ops_of_rhs(run(kMbsc + " print " + model("double_pendulum.mbs") + " --stats").output);
  const long minimal = ops_of_rhs(run(kMbsc + " print " + model("double_pendulum.mbs") + " --stats --state minimal").output);
  CHECK(minimal < full);
  r = run(kMbsc + " print " + model("double_pendulum.mbs") + " --node nosuch");
  CHECK(r.exit_code == 1);
}

TEST_CASE("print is the same text in every run (GiNaC's term order is not)", "[cli]") {
  const std::string cmd = kMbsc + " print " + model("five_bar.mbs") + " --what A,B,C,S,f,fbar,M,h";
  auto a = run(cmd), b = run(cmd), c = run(cmd + " --latex"), d = run(cmd + " --latex");
  CHECK(a.exit_code == 0);
  CHECK(a.output == b.output);
  CHECK(c.output == d.output);
}

TEST_CASE("generate --state minimal: a smaller state, and clear refusals", "[cli]") {
  namespace fs = std::filesystem;
  const fs::path dir = fresh_dir("minimal_state");
  auto r = run(kMbsc + " generate " + model("double_pendulum.mbs") + " --state minimal -o " + quote(dir.string()));
  REQUIRE(r.exit_code == 0);
  std::ifstream in(dir / "double_pendulum" / "double_pendulum.hpp");
  const std::string header((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  CHECK(header.find("kNx = 4;") != std::string::npos);
  CHECK(header.find("kNxFull = 12;") != std::string::npos);
  CHECK(header.find("int full_state(") != std::string::npos);
  // The common ABI: the Jacobians stay, over the full layout (kNc x kNuFull, kNposc x kNqFull).
  CHECK(header.find("int constraint_jacobian(") != std::string::npos);
  CHECK(header.find("row-major kNc x kNuFull") != std::string::npos);
  CHECK(header.find("int position_jacobian(") != std::string::npos);
  fs::remove_all(dir);

  // A nonlinear velocity block cannot rebuild its speeds: the constraint is named.
  const fs::path bad = fresh_dir("minimal_state_bad");
  r = run(kMbsc + " generate " + model("spherical_pendulum_extra_speed.mbs") + " --state minimal -o " + quote(bad.string()));
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("spherical_pendulum_extra_speed.mbs:18:3: error:") != std::string::npos);
  CHECK(r.output.find("'speed_square'") != std::string::npos);
  CHECK(fs::is_empty(bad));
  // An unknown function in --outputs is refused, and names the known ones.
  r = run(kMbsc + " generate " + model("double_pendulum.mbs") + " --outputs rhs,full_sate -o " + quote(bad.string()));
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("unknown function 'full_sate'") != std::string::npos);
  CHECK(r.output.find("full_state") != std::string::npos);
  // Alternative independent sets re-select at run time over the full state only: with
  // the minimal state they are set aside, with a warning at the statement.
  const fs::path alt = fresh_dir("minimal_state_alternatives");
  r = run(kMbsc + " generate " + model("four_bar_toggle.mbs") + " --state minimal -o " + quote(alt.string()));
  CHECK(r.exit_code == 0);
  CHECK(r.output.find("four_bar_toggle.mbs:43:1: warning: 'alternative' independent sets are ignored with --state "
                      "minimal") != std::string::npos);
  {
    std::ifstream in(alt / "four_bar_toggle" / "four_bar_toggle.hpp");
    const std::string header((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    CHECK(header.find("kNpartitions = 1;") != std::string::npos);
  }
  fs::remove_all(alt);
  r = run(kMbsc + " generate " + model("double_pendulum.mbs") + " --state smallest -o " + quote(bad.string()));
  CHECK(r.exit_code == 1);
  CHECK(fs::is_empty(bad));
  fs::remove_all(bad);
}

TEST_CASE("generate --formulation multipliers: its functions and its refusals", "[cli]") {
  namespace fs = std::filesystem;
  const fs::path dir = fresh_dir("multipliers");
  auto r = run(kMbsc + " generate " + model("four_bar.mbs") + " --formulation multipliers -o " + quote(dir.string()));
  REQUIRE(r.exit_code == 0);
  std::ifstream in(dir / "four_bar" / "four_bar.hpp");
  const std::string header((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  CHECK(header.find("int multipliers(") != std::string::npos);
  CHECK(header.find("int reaction_forces(") != std::string::npos);
  CHECK(header.find("\"baumgarte_alpha\"") != std::string::npos);
  // The common ABI: the reduced M z' = h of the declared set, as in the complement form.
  CHECK(header.find("int mass_matrix(") != std::string::npos);
  CHECK(header.find("int forcing(") != std::string::npos);
  CHECK(header.find("int full_state(") != std::string::npos);
  fs::remove_all(dir);
  const fs::path bad = fresh_dir("multipliers_bad");
  r = run(kMbsc + " generate " + model("four_bar.mbs") + " --formulation multipliers --state minimal -o " + quote(bad.string()));
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("--state minimal") != std::string::npos);
  r = run(kMbsc + " generate " + model("four_bar.mbs") + " --outputs multipliers -o " + quote(bad.string()));
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("only --formulation multipliers has multipliers") != std::string::npos);
  CHECK(fs::is_empty(bad));
  fs::remove_all(bad);
}

TEST_CASE("generate --derivatives and --outputs: the derivatives with or without their functions", "[cli]") {
  namespace fs = std::filesystem;
  const fs::path dir = fresh_dir("derivative_outputs");
  auto header = [&](const char* options) {
    fs::remove_all(dir / "four_bar");
    const auto r = run(kMbsc + " generate " + model("four_bar.mbs") + " " + options + " -o " + quote(dir.string()));
    INFO(options << ": " << r.output);
    REQUIRE(r.exit_code == 0);
    std::ifstream in(dir / "four_bar" / "four_bar.hpp");
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  };
  // By default: neither derivative.
  std::string h = header("");
  CHECK(h.find("int rhs_jacobian(") == std::string::npos);
  CHECK(h.find("int inverse_dynamics_jacobian(") == std::string::npos);
  // --derivatives: both, with every other function.
  h = header("--derivatives");
  CHECK(h.find("int rhs_jacobian(") != std::string::npos);
  CHECK(h.find("int inverse_dynamics_jacobian(") != std::string::npos);
  CHECK(h.find("int mass_matrix(") != std::string::npos);
  // With a list that lacks the functions they differentiate: those are derived, not written.
  h = header("--outputs mass_matrix --derivatives");
  CHECK(h.find("int rhs_jacobian(") != std::string::npos);
  CHECK(h.find("int inverse_dynamics_jacobian(") != std::string::npos);
  CHECK(h.find("int rhs(") == std::string::npos);
  CHECK(h.find("int inverse_dynamics(") == std::string::npos);
  h = header("--outputs rhs_jacobian");
  CHECK(h.find("int rhs_jacobian(") != std::string::npos);
  CHECK(h.find("int inverse_dynamics_jacobian(") == std::string::npos);
  CHECK(h.find("int rhs(") == std::string::npos);
  fs::remove_all(dir);
}

TEST_CASE("generate: a tree's rhs_jacobian by the implicit form, a loop's by forward mode", "[cli]") {
  namespace fs = std::filesystem;
  const fs::path dir = fresh_dir("implicit_jacobian");
  auto doc = [&](const std::string& name, const char* options) {
    fs::remove_all(dir / name);
    const auto r = run(kMbsc + " generate " + model((name + ".mbs").c_str()) + " --outputs rhs_jacobian " + options + " -o " +
                       quote(dir.string()));
    INFO(name << " " << options << ": " << r.output);
    REQUIRE(r.exit_code == 0);
    std::ifstream in(dir / name / (name + ".hpp"));
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  };
  // The tree recursion's rhs (--solver sparse on a joint-coordinate arm): the implicit form.
  CHECK(doc("three_r_arm_joint", "--solver sparse").find("implicit form") != std::string::npos);
  // The dense rhs, and a loop's recursion: forward mode over the rhs's steps.
  CHECK(doc("three_r_arm_joint", "--solver dense").find("implicit form") == std::string::npos);
  CHECK(doc("four_bar", "--solver sparse").find("implicit form") == std::string::npos);
  fs::remove_all(dir);
}
