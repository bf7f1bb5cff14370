// SPDX-License-Identifier: GPL-2.0-or-later
// Ground reactions at rest under gravity (multipliers formulation): the four-bar of
// tests/data/planar/four_bar_joints.mbs (library revolute joints, a motor torque tau at
// the crank's ground pivot) at a static equilibrium. The equilibrium is found with the
// complement form (the crank's acceleration at zero speeds is driven to zero along the
// assembled 1-DOF configuration) and confirmed by the potential energy (dV/dtheta_crank =
// tau). There, with the multipliers form:
//  - every acceleration vanishes;
//  - the two ground pins carry the total weight and nothing horizontally;
//  - the moments about either ground pivot balance (pin force, weights, tau);
//  - the ground pins' multipliers are the external part of reaction_forces (the internal
//    pins cancel in the sum over the bodies).
// The hanging pendulum's pin is in multipliers_test.cpp.
#include <catch2/catch.hpp>
#include <cmath>

#include "four_bar_joints/four_bar_joints.hpp"
#include "four_bar_joints_mult/four_bar_joints_mult.hpp"
#include "mbsc/runtime/assemble.hpp"
#include "test_support.hpp"

using mbsc_test::index_of;

namespace {

namespace C = mbsc_gen::four_bar_joints;
namespace M = mbsc_gen::four_bar_joints_mult;

std::size_t ix(const char* n) { return static_cast<std::size_t>(index_of(C::kStateNames, C::kNx, n)); }
double par(const char* n) { return C::kParamDefaults[index_of(C::kParamNames, C::kNp, n)]; }

/// The consistent state at rest with the crank at `crank`, starting from `guess`.
std::vector<double> at_rest(double crank, const std::vector<double>& guess) {
  const auto model = MBSC_TEST_ASSEMBLY_MODEL(C);
  std::vector<double> x = guess;
  for (int j = 0; j < C::kNu; ++j) x[static_cast<std::size_t>(C::kNq + j)] = 0.0;
  x[ix("crank.theta")] = crank;
  std::vector<bool> gq(C::kNq, false), gu(C::kNu, true);
  gq[ix("crank.theta")] = true;
  // Tighter than the default 1e-12: a residual g enters the multipliers form's
  // accelerations as beta^2 g (Baumgarte, beta = 10).
  mbsc::runtime::AssemblyOptions opt;
  opt.tolerance = 1e-14;
  const auto r = mbsc::runtime::assemble(model, 0.0, x, gq, gu, nullptr, C::kParamDefaults, opt);
  INFO(r.message);
  REQUIRE(r.ok());
  return x;
}

/// The crank's angular acceleration at rest (complement form).
double crank_acceleration(const std::vector<double>& x) {
  std::vector<double> xd(C::kNx);
  REQUIRE(C::rhs(0.0, x.data(), nullptr, C::kParamDefaults, xd.data()) == 0);
  return xd[ix("crank.w")];
}

double potential(const std::vector<double>& x) {
  double E[3];
  REQUIRE(C::energy(0.0, x.data(), nullptr, C::kParamDefaults, E) == 0);
  return E[1];
}

}  // namespace

TEST_CASE("four-bar at rest under gravity: the ground pins balance the weight and the torque",
          "[numeric][multipliers][statics]") {
  REQUIRE(M::kNx == C::kNx);
  const double g = par("g"), d = par("d"), tau = par("tau");
  const double W = (par("m1") + par("m2") + par("m3")) * g;

  // The elbow branch of the other tests: rough angles, mass centres at 0.
  std::vector<double> guess(C::kNx, 0.0);
  guess[ix("coupler.theta")] = 0.4;
  guess[ix("rocker.theta")] = 1.9;
  // Bracket a zero of the crank's acceleration on a scan of the crank angle (each state
  // assembled from the previous one, so the branch is kept), then bisect.
  double lo = 0.0, hi = 0.0;
  std::vector<double> x_lo = at_rest(0.0, guess), x_hi;
  double a_lo = crank_acceleration(x_lo);
  bool bracketed = false;
  for (int i = 1; i <= 72 && !bracketed; ++i) {
    hi = 2 * M_PI * i / 72;
    x_hi = at_rest(hi, x_lo);
    const double a_hi = crank_acceleration(x_hi);
    if ((a_lo < 0) != (a_hi < 0)) {
      bracketed = true;
    } else {
      lo = hi, x_lo = x_hi, a_lo = a_hi;
    }
  }
  REQUIRE(bracketed);
  std::vector<double> x = x_lo;
  for (int it = 0; it < 200 && hi - lo > 1e-15; ++it) {
    const double mid = 0.5 * (lo + hi);
    x = at_rest(mid, x_lo);
    const double a = crank_acceleration(x);
    if ((a < 0) == (a_lo < 0)) {
      lo = mid, x_lo = x, a_lo = a;
    } else {
      hi = mid;
    }
  }
  const double crank = x[ix("crank.theta")];
  INFO("equilibrium crank angle " << crank);
  CHECK(std::abs(crank_acceleration(x)) < 1e-10 * g);

  // The potential energy is stationary against the motor's work: dV/dtheta = tau.
  const double h = 1e-4;
  const double dV = (potential(at_rest(crank + h, x)) - potential(at_rest(crank - h, x))) / (2 * h);
  CHECK(std::abs(dV - tau) < 1e-8 * W * d);  // central difference: O(h^2)

  // Multipliers form at the same state.
  std::vector<double> xd(M::kNx), lambda(M::kNc), R(M::kNu);
  REQUIRE(M::rhs(0.0, x.data(), nullptr, M::kParamDefaults, xd.data()) == 0);
  REQUIRE(M::multipliers(0.0, x.data(), nullptr, M::kParamDefaults, lambda.data()) == 0);
  REQUIRE(M::reaction_forces(0.0, x.data(), nullptr, M::kParamDefaults, R.data()) == 0);
  for (int j = M::kNq; j < M::kNx; ++j) {
    INFO(M::kStateNames[j]);
    CHECK(std::abs(xd[static_cast<std::size_t>(j)]) < 1e-10 * g);
  }
  // The ground pins' rows are r(body point) - r(ground point), so their multipliers are
  // the forces of the ground on the crank at O and on the rocker at Q.
  auto lam = [&](const char* n) { return lambda[static_cast<std::size_t>(index_of(M::kConstraintNames, M::kNc, n))]; };
  const double FOx = lam("pivot.x"), FOy = lam("pivot.y"), FQx = lam("bearing.x"), FQy = lam("bearing.y");
  CHECK(std::abs(FOx + FQx) < 1e-10 * W);
  CHECK(std::abs(FOy + FQy - W) < 1e-10 * W);
  CHECK(std::abs(FOx) > 1e-3 * W);  // the pins do push sideways: the check is not vacuous
  // Moments about O = (0, 0) and about Q = (d, 0): pin force, weights at the mass centres,
  // and the motor torque (+tau on the crank, its reaction on the ground).
  double mO = d * FQy + tau, mQ = -d * FOy + tau;
  for (const auto& [body, mass] : {std::pair{"crank", "m1"}, std::pair{"coupler", "m2"}, std::pair{"rocker", "m3"}}) {
    const double xg = x[ix((std::string(body) + ".x").c_str())];
    mO += xg * (-par(mass) * g);
    mQ += (xg - d) * (-par(mass) * g);
  }
  CHECK(std::abs(mO) < 1e-10 * W * d);
  CHECK(std::abs(mQ) < 1e-10 * W * d);
  // reaction_forces: summed over the bodies, the internal pins cancel.
  double Rx = 0.0, Ry = 0.0;
  for (const char* b : {"crank", "coupler", "rocker"}) {
    Rx += R[ix((std::string(b) + ".u").c_str()) - M::kNq];
    Ry += R[ix((std::string(b) + ".v").c_str()) - M::kNq];
  }
  CHECK(std::abs(Rx - (FOx + FQx)) < 1e-10 * W);
  CHECK(std::abs(Ry - W) < 1e-10 * W);
}
