// SPDX-License-Identifier: GPL-2.0-or-later
// A DOP853 run of a generated rhs sampled at a fixed step (the bicycle tests).
#pragma once
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "mbsc/runtime/dop853.hpp"

namespace mbsc_test {

/// Integrates `rhs(t, x, xdot)` from x0 at tolerance tol and calls `sample(t, x)` every dt
/// up to t_end.
template <class Rhs, class F>
void sampled_run(Rhs rhs, std::vector<double> x0, double t_end, double dt, double tol, F&& sample) {
  mbsc::runtime::StepperOptions o;
  o.rtol = o.atol = tol;
  mbsc::runtime::Dop853 stepper(rhs, static_cast<int>(x0.size()), o);
  REQUIRE(stepper.reset(0.0, x0) == mbsc::runtime::Stepper::Status::Ok);
  std::vector<double> s(x0.size());
  const int n = static_cast<int>(std::lround(t_end / dt));
  for (int k = 0; k <= n; ++k) {
    const double t = k * dt;
    while (stepper.t() < t) REQUIRE(stepper.step(t) == mbsc::runtime::Stepper::Status::Ok);
    stepper.interpolate(t, s);
    sample(t, s);
  }
}

}  // namespace mbsc_test
