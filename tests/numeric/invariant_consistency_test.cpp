// SPDX-License-Identifier: GPL-2.0-or-later
// The generated constraint functions of the library joints (slider-crank: revolute and
// prismatic) against the calculus they come from: along the motion, the velocity residuals
// are the time derivative of the position residuals, and the time derivative of the
// velocity residuals vanishes under the generated rhs (the order-2 invariants hold).
// Derivatives by central differences along x' = rhs(x).
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "mbsc/runtime/assemble.hpp"
#include "slider_crank/slider_crank.hpp"
#include "test_support.hpp"

using mbsc_test::index_of;
namespace S = mbsc_gen::slider_crank;

TEST_CASE("slider-crank joints: velocity residual = d/dt position residual, d/dt velocity residual = 0",
          "[numeric][planar]") {
  const auto model = MBSC_TEST_ASSEMBLY_MODEL(S);
  auto ix = [](const char* n) { return static_cast<std::size_t>(index_of(S::kStateNames, S::kNx, n)); };
  std::mt19937 rng(41);
  std::uniform_real_distribution<double> angle(0.0, 6.28), rate(-5.0, 5.0);
  const double u[2] = {0.4, -0.7};
  for (int k = 0; k < 10; ++k) {
    // A consistent state (assembled from the crank angle and rate).
    std::vector<double> x(S::kNx, 0.0);
    const double th = angle(rng);
    x[ix("crank.theta")] = th;
    x[ix("rod.theta")] = -0.2 * std::sin(th);
    x[ix("slider.x")] = 0.4;
    x[ix("crank.w")] = rate(rng);
    std::vector<bool> gq(S::kNq, false), gu(S::kNu, false);
    gq[ix("crank.theta")] = true;
    gu[ix("crank.w") - S::kNq] = true;
    REQUIRE(mbsc::runtime::assemble(model, 0.0, x, gq, gu, u, S::kParamDefaults).ok());
    std::vector<double> xd(S::kNx);
    REQUIRE(S::rhs(0.0, x.data(), u, S::kParamDefaults, xd.data()) == 0);
    const double h = 1e-6;
    auto along = [&](double s) {
      std::vector<double> y = x;
      for (int i = 0; i < S::kNx; ++i) y[static_cast<std::size_t>(i)] += s * xd[static_cast<std::size_t>(i)];
      return y;
    };
    std::vector<double> gp(S::kNposc), gm(S::kNposc), v(S::kNc), vp(S::kNc), vm(S::kNc);
    const auto xp = along(h), xm = along(-h);
    S::position_constraints(0.0, xp.data(), u, S::kParamDefaults, gp.data());
    S::position_constraints(0.0, xm.data(), u, S::kParamDefaults, gm.data());
    S::velocity_constraints(0.0, x.data(), u, S::kParamDefaults, v.data());
    // Position constraints come first in kConstraintNames here (all of them are position ones).
    REQUIRE(S::kNposc == S::kNc);
    for (int i = 0; i < S::kNposc; ++i)
      CHECK((gp[static_cast<std::size_t>(i)] - gm[static_cast<std::size_t>(i)]) / (2 * h) ==
            Approx(v[static_cast<std::size_t>(i)]).margin(1e-7));
    S::velocity_constraints(0.0, xp.data(), u, S::kParamDefaults, vp.data());
    S::velocity_constraints(0.0, xm.data(), u, S::kParamDefaults, vm.data());
    for (int i = 0; i < S::kNc; ++i)
      CHECK((vp[static_cast<std::size_t>(i)] - vm[static_cast<std::size_t>(i)]) / (2 * h) == Approx(0.0).margin(1e-6));
  }
}
