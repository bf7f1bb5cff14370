// SPDX-License-Identifier: GPL-2.0-or-later
// --formulation multipliers against the modular (complement) formulation of the same
// models: equal accelerations at assembled consistent states, equal trajectories, and
// reactions that obey Newton's law for the whole mechanism.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "four_bar/four_bar.hpp"
#include "four_bar_mult/four_bar_mult.hpp"
#include "mbsc/runtime/assemble.hpp"
#include "mbsc/runtime/rk4.hpp"
#include "pendulum_mult/pendulum_mult.hpp"
#include "ring_disc/ring_disc.hpp"
#include "ring_disc_mult/ring_disc_mult.hpp"
#include "slider_crank/slider_crank.hpp"
#include "slider_crank_mult/slider_crank_mult.hpp"
#include "test_support.hpp"

using mbsc::runtime::AssemblyModel;
using mbsc_test::index_of;

namespace {

using Fn = int (*)(double, const double*, const double*, const double*, double*);

/// Parameters of the multipliers build: the model's, then alpha and beta.
template <int NP>
std::vector<double> with_gains(const double (&p)[NP], int np_model) {
  std::vector<double> v(p, p + NP);
  REQUIRE(static_cast<int>(v.size()) == np_model + 2);
  return v;
}

double largest_abs(const std::vector<double>& v) {
  double w = 1.0;
  for (double e : v) w = std::max(w, std::abs(e));
  return w;
}

/// Both rhs at x (same layout: both are full-state builds of one model).
void same_rhs(Fn complement, Fn multipliers, const std::vector<double>& x, const double* u, const double* p_c,
              const double* p_m, int nx) {
  std::vector<double> a(static_cast<std::size_t>(nx)), b(static_cast<std::size_t>(nx));
  REQUIRE(complement(0.0, x.data(), u, p_c, a.data()) == 0);
  REQUIRE(multipliers(0.0, x.data(), u, p_m, b.data()) == 0);
  const double scale = largest_abs(a);
  for (int i = 0; i < nx; ++i) CHECK(std::abs(a[static_cast<std::size_t>(i)] - b[static_cast<std::size_t>(i)]) < 1e-9 * scale);
}

}  // namespace

TEST_CASE("multipliers: four-bar equals the complement form, states and trajectories", "[numeric][multipliers]") {
  namespace C = mbsc_gen::four_bar;
  namespace M = mbsc_gen::four_bar_mult;
  REQUIRE(M::kNx == C::kNx);
  const auto pm = with_gains(M::kParamDefaults, C::kNp);
  const auto model = MBSC_TEST_ASSEMBLY_MODEL(C);
  auto ix = [](const char* n) { return static_cast<std::size_t>(index_of(C::kStateNames, C::kNx, n)); };
  std::vector<double> x0;
  for (double crank : {0.4, 1.5, 3.0, 4.4}) {
    std::vector<double> x(C::kNx, 0.0);
    x[ix("crank.theta")] = crank;
    x[ix("coupler.theta")] = 0.4;
    x[ix("rocker.theta")] = 1.9;
    x[ix("crank.w")] = 3.0;
    std::vector<bool> gq(C::kNq, false), gu(C::kNu, false);
    gq[ix("crank.theta")] = true;
    gu[ix("crank.w") - C::kNq] = true;
    REQUIRE(mbsc::runtime::assemble(model, 0.0, x, gq, gu, nullptr, C::kParamDefaults).ok());
    same_rhs(C::rhs, M::rhs, x, nullptr, C::kParamDefaults, pm.data(), C::kNx);
    if (x0.empty()) x0 = x;
  }
  // One second of RK4 in each formulation from the same consistent state.
  std::vector<double> xc = x0, xm = x0;
  auto fc = [](double t, const double* xs, double* xd) { return C::rhs(t, xs, nullptr, C::kParamDefaults, xd); };
  auto fm = [&pm](double t, const double* xs, double* xd) { return M::rhs(t, xs, nullptr, pm.data(), xd); };
  auto ignore = [](double, const std::vector<double>&) {};
  REQUIRE(mbsc::runtime::rk4_integrate(fc, 0.0, 1.0, 4000, xc, ignore) == 0);
  REQUIRE(mbsc::runtime::rk4_integrate(fm, 0.0, 1.0, 4000, xm, ignore) == 0);
  for (int i = 0; i < C::kNx; ++i) CHECK(std::abs(xc[static_cast<std::size_t>(i)] - xm[static_cast<std::size_t>(i)]) < 1e-7);

  // Baumgarte: from a state that violates the loop closure, f'' + 2 alpha f' + beta^2 f = 0
  // (alpha = beta = 10) pulls the residual down by about (1 + 10 t) exp(-10 t).
  std::vector<double> xb = x0, g(C::kNposc);
  xb[ix("rocker.theta")] += 1e-3;
  REQUIRE(C::position_constraints(0.0, xb.data(), nullptr, C::kParamDefaults, g.data()) == 0);
  double before = 0.0;
  for (double e : g) before = std::max(before, std::abs(e));
  REQUIRE(mbsc::runtime::rk4_integrate(fm, 0.0, 1.0, 4000, xb, ignore) == 0);
  REQUIRE(C::position_constraints(0.0, xb.data(), nullptr, C::kParamDefaults, g.data()) == 0);
  double after = 0.0;
  for (double e : g) after = std::max(after, std::abs(e));
  CHECK(before > 1e-4);
  CHECK(after < 1e-3 * before);
}

TEST_CASE("multipliers: slider-crank (library joints, inputs) equals the complement form", "[numeric][multipliers]") {
  namespace C = mbsc_gen::slider_crank;
  namespace M = mbsc_gen::slider_crank_mult;
  const auto pm = with_gains(M::kParamDefaults, C::kNp);
  const auto model = MBSC_TEST_ASSEMBLY_MODEL(C);
  auto ix = [](const char* n) { return static_cast<std::size_t>(index_of(C::kStateNames, C::kNx, n)); };
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> angle(0.0, 6.28), rate(-15.0, 15.0), load(-3.0, 3.0);
  for (int k = 0; k < 10; ++k) {
    std::vector<double> x(C::kNx, 0.0);
    const double th = angle(rng);
    x[ix("crank.theta")] = th;
    x[ix("rod.theta")] = -0.2 * std::sin(th);
    x[ix("slider.x")] = 0.4;
    x[ix("crank.w")] = rate(rng);
    std::vector<bool> gq(C::kNq, false), gu(C::kNu, false);
    gq[ix("crank.theta")] = true;
    gu[ix("crank.w") - C::kNq] = true;
    const double u[2] = {load(rng), load(rng)};
    REQUIRE(mbsc::runtime::assemble(model, 0.0, x, gq, gu, u, C::kParamDefaults).ok());
    same_rhs(C::rhs, M::rhs, x, u, C::kParamDefaults, pm.data(), C::kNx);
    // Newton for the whole mechanism: the ground's reactions (the sum of the generalized
    // reactions along the bodies' u, v) = sum of m a - weight - applied load.
    std::vector<double> xd(C::kNx), R(C::kNu);
    REQUIRE(M::rhs(0.0, x.data(), u, pm.data(), xd.data()) == 0);
    REQUIRE(M::reaction_forces(0.0, x.data(), u, pm.data(), R.data()) == 0);
    auto par = [](const char* n) { return C::kParamDefaults[index_of(C::kParamNames, C::kNp, n)]; };
    const double g = par("g");
    double rx = 0, ry = 0, max_ = 0, may = 0;
    for (const char* b : {"crank", "rod", "slider"}) {
      const double mass = par(std::string(b) == "crank" ? "m1" : std::string(b) == "rod" ? "m2" : "m3");
      rx += R[ix((std::string(b) + ".u").c_str()) - C::kNq];
      ry += R[ix((std::string(b) + ".v").c_str()) - C::kNq];
      max_ += mass * xd[ix((std::string(b) + ".u").c_str())];
      may += mass * xd[ix((std::string(b) + ".v").c_str())];
    }
    const double weight = (par("m1") + par("m2") + par("m3")) * g;
    CHECK(rx == Approx(max_ - u[1]).margin(1e-9 * std::max(1.0, std::abs(max_))));
    CHECK(ry == Approx(may + weight).margin(1e-9 * std::max(1.0, std::abs(may))));
  }
}

TEST_CASE("multipliers: ring and disc (velocity constraints) equals the complement form", "[numeric][multipliers]") {
  namespace C = mbsc_gen::ring_disc;
  namespace M = mbsc_gen::ring_disc_mult;
  const auto pm = with_gains(M::kParamDefaults, C::kNp);
  const AssemblyModel model{C::kNq,  C::kNu,  0,       C::kNc, nullptr, nullptr, C::velocity_constraints, C::constraint_jacobian,
                            nullptr, C::kConstraintNames};
  std::mt19937 rng(29);
  std::uniform_real_distribution<double> val(-1.0, 1.0);
  for (int k = 0; k < 10; ++k) {
    std::vector<double> x(C::kNx);
    for (double& e : x) e = val(rng);
    // Keep every coordinate and the independent speeds; complete the others.
    std::vector<bool> gq(C::kNq, true), gu(C::kNu, false);
    for (int j = 0; j < C::kNdof; ++j) gu[index_of(C::kStateNames, C::kNx, C::kDofNames[j]) - C::kNq] = true;
    REQUIRE(mbsc::runtime::assemble(model, 0.0, x, gq, gu, nullptr, C::kParamDefaults).ok());
    same_rhs(C::rhs, M::rhs, x, nullptr, C::kParamDefaults, pm.data(), C::kNx);
  }
}

TEST_CASE("multipliers: a hanging pendulum at rest, the pin carries its weight", "[numeric][multipliers]") {
  namespace M = mbsc_gen::pendulum_mult;
  auto ix = [](const char* n) { return static_cast<std::size_t>(index_of(M::kStateNames, M::kNx, n)); };
  auto par = [](const char* n) { return M::kParamDefaults[index_of(M::kParamNames, M::kNp, n)]; };
  std::vector<double> x(M::kNx, 0.0), R(M::kNu), xd(M::kNx), lambda(M::kNc);
  const double a = par("a");
  x[ix("bar.theta")] = -M_PI / 2;  // hanging straight down, mass centre below the pin
  x[ix("bar.y")] = -a / 2;
  REQUIRE(M::rhs(0.0, x.data(), nullptr, M::kParamDefaults, xd.data()) == 0);
  REQUIRE(M::reaction_forces(0.0, x.data(), nullptr, M::kParamDefaults, R.data()) == 0);
  REQUIRE(M::multipliers(0.0, x.data(), nullptr, M::kParamDefaults, lambda.data()) == 0);
  const double weight = par("m") * par("g");
  CHECK(std::abs(xd[ix("bar.w")]) < 1e-12);  // equilibrium
  CHECK(std::abs(R[ix("bar.u") - M::kNq]) < 1e-10);
  CHECK(std::abs(R[ix("bar.v") - M::kNq] - weight) < 1e-10 * weight);
  CHECK(std::abs(R[ix("bar.w") - M::kNq]) < 1e-10);
  // The pin's rows are r_O(bar) - 0: its multipliers are the force on the bar.
  CHECK(std::abs(std::abs(lambda[1]) - weight) < 1e-10 * weight);
}
