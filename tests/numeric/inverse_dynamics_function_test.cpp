// SPDX-License-Identifier: GPL-2.0-or-later
// The generated inverse_dynamics against closed forms on three one-line models: a
// state-dependent input gain (u = 2 z' / cos q, singular where cos q = 0), more inputs
// than degrees of freedom (the smallest inputs), and a forcing not affine in its input
// (status 4, NaN), and a spatial arm's joint torques (statics by hand, and the forward rhs
// driven by them). The shipped models are covered by generic_abi_test and
// inverse_dynamics_test.
#include <catch2/catch.hpp>
#include <array>
#include <cmath>
#include <random>

#include "input_squared/input_squared.hpp"
#include "lever_input/lever_input.hpp"
#include "spatial_arm_torques/spatial_arm_torques.hpp"
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

namespace {

using V3 = std::array<double, 3>;
using M3 = std::array<V3, 3>;

M3 turn(int axis, double q) {  // rotation by q about coordinate axis 0, 1 or 2
  const double c = std::cos(q), s = std::sin(q);
  const int j = (axis + 1) % 3, k = (axis + 2) % 3;
  M3 R{};
  R[axis][axis] = 1;
  R[j][j] = R[k][k] = c;
  R[k][j] = s;
  R[j][k] = -s;
  return R;
}
M3 mul(const M3& a, const M3& b) {
  M3 r{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) r[i][j] += a[i][k] * b[k][j];
  return r;
}
V3 apply(const M3& R, const V3& v) {
  return {R[0][0] * v[0] + R[0][1] * v[1] + R[0][2] * v[2], R[1][0] * v[0] + R[1][1] * v[1] + R[1][2] * v[2],
          R[2][0] * v[0] + R[2][1] * v[1] + R[2][2] * v[2]};
}
V3 add(const V3& a, const V3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
V3 sub(const V3& a, const V3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
V3 cross(const V3& a, const V3& b) { return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}; }
double dot(const V3& a, const V3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

}  // namespace

TEST_CASE("inverse_dynamics: a spatial arm's joint torques hold it against gravity and drive its motion",
          "[numeric][inverse]") {
  namespace A = mbsc_gen::spatial_arm_torques;
  REQUIRE(A::kNdof == 3);
  REQUIRE(A::kNin == 3);
  REQUIRE(A::kNx == 6);  // q1, q2, q3 and their rates
  const double g = 9.81, mass[3] = {2.0, 1.5, 1.0};
  std::mt19937 rng(26);
  std::uniform_real_distribution<double> angle(-3.0, 3.0), rate(-2.0, 2.0);
  for (int trial = 0; trial < 10; ++trial) {
    const double q[3] = {angle(rng), angle(rng), angle(rng)};
    // At rest, held still: each joint's torque balances the weight of the links beyond
    // it about its axis (by hand, from the links' poses R1 = Rz(q1), R2 = R1 Ry(q2),
    // R3 = R2 Ry(q3)).
    const M3 R1 = turn(2, q[0]), R2 = mul(R1, turn(1, q[1])), R3 = mul(R2, turn(1, q[2]));
    const V3 p1{0, 0, 0}, p2 = apply(R1, {0, 0, 0.5}), p3 = add(p2, apply(R2, {0, 0, 0.4}));
    const V3 c[3] = {apply(R1, {0, 0, 0.25}), add(p2, apply(R2, {0.03, 0, 0.2})), add(p3, apply(R3, {0, 0.02, 0.15}))};
    const V3 pivot[3] = {p1, p2, p3}, axis[3] = {{0, 0, 1}, apply(R1, {0, 1, 0}), apply(R2, {0, 1, 0})};
    double held[3];
    for (int j = 0; j < 3; ++j) {
      V3 moment{0, 0, 0};
      for (int k = j; k < 3; ++k) moment = add(moment, cross(sub(c[k], pivot[j]), {0, 0, -mass[k] * g}));
      held[j] = -dot(axis[j], moment);
    }
    const double still[6] = {q[0], q[1], q[2], 0, 0, 0}, zero[3] = {0, 0, 0};
    double u[3];
    REQUIRE(A::inverse_dynamics(0.0, still, zero, A::kParamDefaults, u) == 0);
    for (int j = 0; j < 3; ++j) {
      INFO("trial " << trial << " joint " << j + 1);
      CHECK(u[j] == Approx(held[j]).margin(1e-12));
    }
    // Moving: the torques for random accelerations, fed to the forward rhs, give them back.
    const double x[6] = {q[0], q[1], q[2], rate(rng), rate(rng), rate(rng)};
    const double zdot[3] = {rate(rng), rate(rng), rate(rng)};
    REQUIRE(A::inverse_dynamics(0.0, x, zdot, A::kParamDefaults, u) == 0);
    double xdot[6];
    REQUIRE(A::rhs(0.0, x, u, A::kParamDefaults, xdot) == 0);
    for (int j = 0; j < 3; ++j) {
      INFO("trial " << trial << " joint " << j + 1);
      CHECK(xdot[3 + j] == Approx(zdot[j]).margin(1e-11));
    }
  }
}
