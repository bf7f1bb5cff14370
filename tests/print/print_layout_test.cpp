// SPDX-License-Identifier: GPL-2.0-or-later
// The layout of `mbsc print` as a user runs it: what users look for first (M, h,
// M z' = h, the constraints), the method's letters after; matrices as aligned grids;
// --expand; the note of a numeric complement.
#include <catch2/catch.hpp>

#include <string>

#include "cli/run_command.hpp"

namespace {

std::string print(const std::string& model, const std::string& flags, int expect_exit = 0) {
  const auto r =
      mbsc_test::run(std::string(MBSC_BINARY) + " print -q " + std::string(MBSC_SOURCE_DIR) + "/models/" + model + " " + flags);
  CHECK(r.exit_code == expect_exit);
  return r.output;
}

std::size_t at(const std::string& text, const std::string& what) {
  const auto p = text.find(what);
  INFO("looking for: " << what);
  CHECK(p != std::string::npos);
  return p;
}

}  // namespace

TEST_CASE("print leads with M, h, M z' = h and the constraints, then B, C, fbar", "[print][layout]") {
  const std::string out = print("double_pendulum.mbs", "");
  const auto M = at(out, "M (2 x 2)"), h = at(out, "h (2 x 1)"), eq = at(out, "equations of motion M z' = h, z = (w1, w2)"),
             cons = at(out, "constraints of double_pendulum (residual = 0)"), B = at(out, "B (4 x 6)"),
             C = at(out, "C (6 x 2)"), fbar = at(out, "fbar (2 x 1)");
  CHECK((M < h && h < eq && eq < cons && cons < B && B < C && C < fbar));
  // The equations row by row, with the rates named.
  at(out, "  w1:  (m1 + m2)*l1^2*w1' + l1*l2*m2*cos(th1 - th2)*w2' = ");
  // A grid: a header of column labels, then one labelled row per line, aligned.
  at(out, "       w1'                      w2'\n  w1'  (m1 + m2)*l1^2           l1*l2*m2*cos(th1 - th2)\n");
  at(out, "       w1'           w2'           b1.u'  b1.v'  b2.u'  b2.v'\n  b1x  -l1*cos(th1)  0             1      0      0      0\n");
  // The constraints as equations.
  at(out, "  b2y (position): -b1.y + b2.y + l2*cos(th2) = 0\n");
}

TEST_CASE("print: long entries fall back to a list and say so", "[print][layout]") {
  const std::string out = print("three_r_arm.mbs", "--what M");
  at(out, "(entries too long for a grid: the nonzero ones, one per line)\n");
  at(out, "  [link1.w', link1.w'] = (1/3*m1 + m2 + m3)*l1^2\n");
  // Short entries, but nine columns: too wide.
  at(print("four_bar.mbs", "--what B"), "(too wide for a grid: the nonzero entries, one per line)\n");
}

TEST_CASE("print --expand: h in closed form instead of through e_ and r_", "[print][layout]") {
  // The three-link arm keeps its recurrences (the double pendulum's are inlined when
  // derived: docs/formulation.md, step 6, small nodes).
  const std::string named = print("three_r_arm.mbs", "--what h");
  at(named, "  where (evaluated in this order; --expand writes the closed form instead)\n");
  at(named, "  r_link1_u = ");
  const std::string closed = print("three_r_arm.mbs", "--what h --expand");
  CHECK(closed.find("where") == std::string::npos);
  CHECK(closed.find("r_link1_u") == std::string::npos);
  at(print("double_pendulum.mbs", "--what h --expand"), "[w2', value] = -(g*sin(th2) - l1*w1^2*sin(th1 - th2))*l2*m2\n");
}

TEST_CASE("print of a numeric complement says so and offers the closed form", "[print][layout]") {
  const std::string out = print("slider_crank.mbs", "--what M");
  at(out, "note: the complement here is numeric (LU in the generated code)");
  at(out, "  X_top_0_0 = r*cos(crank.theta)/(l*cos(rod.theta))   (numeric solve in the generated code; closed form)\n");
  const std::string closed = print("slider_crank.mbs", "--what M --expand");
  CHECK(closed.find("X_top") == std::string::npos);
  // Every matrix: the five-bar's B, C and S read the linkage's solve, listed under them
  // (closed forms) or substituted with --expand.
  const std::string letters = print("five_bar.mbs", "--what B,C,S");
  at(letters, "  X_linkage_0_0 = aUL*sin(linkage.left.theta - linkage.right.phi)/(aBL*sin(linkage.left.phi - linkage.right.phi))");
  CHECK(print("five_bar.mbs", "--what B,C,S --expand").find("X_") == std::string::npos);
  // A block too large for a closed form is named as such.
  const std::string chain = print("parallelogram_chain.mbs", "--what M --expand");
  at(chain, "too large for a closed form here)");
}

TEST_CASE("print --what: an unknown item lists the known ones", "[print][layout]") {
  const std::string out = print("double_pendulum.mbs", "--what Q", 1);
  at(out, "--what: unknown item 'Q' (known: eom M h invariants rates A B C S f fbar)");
}
