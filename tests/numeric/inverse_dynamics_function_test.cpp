// SPDX-License-Identifier: GPL-2.0-or-later
// The generated inverse_dynamics against closed forms on three one-line models: a
// state-dependent input gain (u = 2 z' / cos q, singular where cos q = 0), more inputs
// than degrees of freedom (the smallest inputs), and a forcing not affine in its input
// (status 4, NaN). The shipped models are covered by generic_abi_test and inverse_dynamics_test.
#include <catch2/catch.hpp>
#include <cmath>

#include "input_squared/input_squared.hpp"
#include "lever_input/lever_input.hpp"
#include "two_inputs/two_inputs.hpp"

TEST_CASE("inverse_dynamics: a state-dependent gain is solved, singular where it vanishes", "[numeric][inverse]") {
  namespace L = mbsc_gen::lever_input;
  REQUIRE(L::kNdof == 1);
  REQUIRE(L::kNin == 1);
  for (double q : {0.0, 0.4, -1.2, 2.9}) {
    const double x[2] = {q, 0.7}, zdot[1] = {1.5};
    double u[1] = {0.0};
    REQUIRE(L::inverse_dynamics(0.0, x, zdot, nullptr, u) == 0);
    CHECK(u[0] == Approx(2 * 1.5 / std::cos(q)).epsilon(1e-12));
    // And rhs at that input gives the acceleration back.
    double xdot[2];
    REQUIRE(L::rhs(0.0, x, u, nullptr, xdot) == 0);
    CHECK(xdot[1] == Approx(1.5).epsilon(1e-12));
  }
  const double x[2] = {std::acos(0.0), 0.0}, zdot[1] = {1.0};
  double u[1];
  // cos(pi/2) is 6e-17 in floating point, not 0: a huge input, or status 1 at exactly 0.
  const int status = L::inverse_dynamics(0.0, x, zdot, nullptr, u);
  CHECK((status == 1 || std::fabs(u[0]) > 1e15));
}

TEST_CASE("inverse_dynamics: more inputs than degrees of freedom gives the smallest inputs", "[numeric][inverse]") {
  namespace T = mbsc_gen::two_inputs;
  REQUIRE(T::kNin == 2);
  REQUIRE(T::kNdof == 1);
  // u1 + 2 u2 = 3 z': the smallest (u1, u2) is (1, 2) * 3 z' / 5.
  const double x[1] = {0.3}, zdot[1] = {1.0};
  double u[2];
  REQUIRE(T::inverse_dynamics(0.0, x, zdot, nullptr, u) == 0);
  CHECK(u[0] == Approx(0.6).epsilon(1e-14));
  CHECK(u[1] == Approx(1.2).epsilon(1e-14));
}

TEST_CASE("inverse_dynamics: a forcing not affine in the inputs is not defined", "[numeric][inverse]") {
  namespace S = mbsc_gen::input_squared;
  const double x[1] = {0.3}, zdot[1] = {1.0};
  double u[1] = {0.0};
  CHECK(S::inverse_dynamics(0.0, x, zdot, nullptr, u) == 4);
  CHECK(std::isnan(u[0]));
}
