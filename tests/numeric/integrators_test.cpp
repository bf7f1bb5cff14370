// SPDX-License-Identifier: GPL-2.0-or-later
// The runtime's explicit integrators (include/mbsc/runtime/make_stepper.hpp) on a smooth
// nonlinear, non-autonomous ODE whose solution is known in closed form:
//   y1' = 1 + y1^2        y1 = tan t
//   y2' = y2 (1 - y2)     y2 = 1 / (1 + 3 e^-t)        (logistic, y2(0) = 1/4)
//   y3' = y3 cos t        y3 = exp(sin t)
// Checked: the classical order of each method (the error at a fixed end time falls by
// 2^p when the step is halved), the order of the dense output inside a step, the
// adaptive methods' error following rtol, and the failure messages.
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "mbsc/runtime/make_stepper.hpp"

using mbsc::runtime::make_stepper;
using mbsc::runtime::Stepper;
using mbsc::runtime::StepperOptions;

namespace {

int smooth_rhs(double t, const double* y, double* yd) {
  yd[0] = 1.0 + y[0] * y[0];
  yd[1] = y[1] * (1.0 - y[1]);
  yd[2] = y[2] * std::cos(t);
  return 0;
}

std::vector<double> exact(double t) { return {std::tan(t), 1.0 / (1.0 + 3.0 * std::exp(-t)), std::exp(std::sin(t))}; }

double max_diff(const std::vector<double>& a, const std::vector<double>& b) {
  double m = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) m = std::max(m, std::abs(a[i] - b[i]));
  return m;
}

/// Runs `name` with a constant step h (adaptive methods: error control switched off by
/// a huge tolerance and h_max = h) to t_end; the error there.
double fixed_step_error(const std::string& name, double h, double t_end) {
  StepperOptions o;
  o.h = h;
  o.h_max = h;
  o.rtol = o.atol = 1e6;
  auto s = make_stepper(name, smooth_rhs, 3, o);
  REQUIRE(s);
  REQUIRE(s->reset(0.0, exact(0.0)) == Stepper::Status::Ok);
  while (s->t() < t_end) REQUIRE(s->step(t_end) == Stepper::Status::Ok);
  return max_diff(s->x(), exact(t_end));
}

}  // namespace

TEST_CASE("integrators: classical order on a smooth nonlinear ODE", "[numeric][integrators]") {
  struct Case {
    const char* name;
    int order;
    double h;
  };
  for (const Case c : {Case{"rk4", 4, 0.05}, Case{"dopri5", 5, 0.1}, Case{"dop853", 8, 0.1}}) {
    const double e1 = fixed_step_error(c.name, c.h, 1.2), e2 = fixed_step_error(c.name, c.h / 2, 1.2);
    const double observed = std::log2(e1 / e2);
    INFO(c.name << ": error " << e1 << " with h = " << c.h << ", " << e2 << " with h/2: order " << observed);
    CHECK(observed > c.order - 0.4);
    CHECK(observed < c.order + 1.0);
  }
}

TEST_CASE("integrators: dense output has its order inside a step", "[numeric][integrators]") {
  // One step from the exact start; the interpolant at theta = 0.3, 0.5, 0.8 against the
  // solution. Local error of an order-p interpolant: O(h^(p+1)).
  struct Case {
    const char* name;
    int order;
    double h;
  };
  for (const Case c : {Case{"rk4", 3, 0.1}, Case{"dopri5", 4, 0.2}, Case{"dop853", 7, 0.4}}) {
    double err[2] = {0, 0};
    for (int k = 0; k < 2; ++k) {
      const double h = c.h / (k + 1);
      StepperOptions o;
      o.h = h;
      o.h_max = h;
      o.rtol = o.atol = 1e6;
      auto s = make_stepper(c.name, smooth_rhs, 3, o);
      REQUIRE(s->reset(0.1, exact(0.1)) == Stepper::Status::Ok);
      REQUIRE(s->step(10.0) == Stepper::Status::Ok);
      REQUIRE(s->t_begin() == 0.1);
      REQUIRE(s->t() == Approx(0.1 + h));
      std::vector<double> y;
      for (double th : {0.3, 0.5, 0.8}) {
        s->interpolate(0.1 + th * h, y);
        err[k] = std::max(err[k], max_diff(y, exact(0.1 + th * h)));
      }
      // The ends of the interpolant are the step's ends.
      s->interpolate(0.1 + h, y);
      CHECK(max_diff(y, s->x()) < 1e-14);
      s->interpolate(0.1, y);
      CHECK(max_diff(y, exact(0.1)) < 1e-14);
    }
    const double observed = std::log2(err[0] / err[1]);
    INFO(c.name << ": dense error " << err[0] << " then " << err[1] << ": local order " << observed);
    CHECK(observed > c.order + 1 - 0.5);
  }
}

TEST_CASE("integrators: adaptive error follows rtol, and dense output keeps it", "[numeric][integrators]") {
  for (const char* name : {"dopri5", "dop853"}) {
    double previous = 0.0;
    long previous_evals = 0;
    for (double rtol : {1e-5, 1e-7, 1e-9}) {
      StepperOptions o;
      o.rtol = rtol;
      o.atol = rtol * 1e-2;
      auto s = make_stepper(name, smooth_rhs, 3, o);
      REQUIRE(s->reset(0.0, exact(0.0)) == Stepper::Status::Ok);
      double worst = 0.0;
      std::vector<double> y;
      for (int k = 1; k <= 120; ++k) {  // samples every 0.01 up to 1.2 through dense output
        const double tk = 0.01 * k;
        while (s->t() < tk) REQUIRE(s->step(1.2) == Stepper::Status::Ok);
        s->interpolate(tk, y);
        worst = std::max(worst, max_diff(y, exact(tk)) / 2.6);  // relative to |y| <= 2.6
      }
      const long evals = s->stats().rhs_evals;
      INFO(name << " rtol " << rtol << ": worst relative error " << worst << ", " << evals << " rhs evaluations, "
                << s->stats().rejected << " rejected");
      CHECK(worst < 30 * rtol);     // global error of the order of the tolerance...
      CHECK(worst > 1e-4 * rtol);   // ...not wastefully below it
      if (previous > 0.0) {
        CHECK(worst < previous / 10);  // two decades of rtol buy at least one of error
        CHECK(evals > previous_evals);
      }
      previous = worst;
      previous_evals = evals;
    }
  }
}

TEST_CASE("integrators: failures name t and the step", "[numeric][integrators]") {
  // y' = y^2 from 1 blows up at t = 1: the adaptive step collapses there.
  auto blowup = [](double, const double* y, double* yd) {
    yd[0] = y[0] * y[0];
    return std::isfinite(yd[0]) ? 0 : 2;
  };
  for (const char* name : {"dopri5", "dop853"}) {
    auto s = make_stepper(name, blowup, 1, {});
    REQUIRE(s->reset(0.0, {1.0}) == Stepper::Status::Ok);
    Stepper::Status st = Stepper::Status::Ok;
    while (st == Stepper::Status::Ok && s->t() < 2.0) st = s->step(2.0);
    INFO(s->message());
    CHECK(st != Stepper::Status::Ok);
    CHECK(std::abs(s->t() - 1.0) < 1e-3);  // followed the solution up to its pole
    CHECK(s->message().find("step size") != std::string::npos);
    CHECK(s->message().find("at t = 1") != std::string::npos);
  }
  // A rhs that fails beyond t = 0.5 (a singular solve): the step shrinks onto it, then
  // the failure is reported with its t.
  auto wall = [](double t, const double*, double* yd) {
    yd[0] = 1.0;
    return t > 0.5 ? 1 : 0;
  };
  for (const char* name : {"rk4", "dopri5", "dop853"}) {
    StepperOptions o;
    o.h = 0.1;
    auto s = make_stepper(name, wall, 1, o);
    REQUIRE(s->reset(0.0, {0.0}) == Stepper::Status::Ok);
    Stepper::Status st = Stepper::Status::Ok;
    while (st == Stepper::Status::Ok && s->t() < 1.0) st = s->step(1.0);
    INFO(s->message());
    CHECK(st == Stepper::Status::RhsFailed);
    CHECK(s->message().find("singular") != std::string::npos);
    CHECK(s->message().find("t = 0.") != std::string::npos);
    CHECK(s->t() <= 0.5);
  }
  // A failure just before t_stop (closer than the smallest step): reported, not retried forever.
  auto late_wall = [](double t, const double*, double* yd) {
    yd[0] = 1.0;
    return t > 1.0 - 1e-15 ? 1 : 0;
  };
  for (const char* name : {"dopri5", "dop853"}) {
    auto s = make_stepper(name, late_wall, 1, {});
    REQUIRE(s->reset(0.0, {0.0}) == Stepper::Status::Ok);
    Stepper::Status st = Stepper::Status::Ok;
    while (st == Stepper::Status::Ok && s->t() < 1.0) st = s->step(1.0);
    INFO(s->message());
    CHECK(st == Stepper::Status::RhsFailed);
    CHECK(s->stats().steps < 1000);
  }
  // max_steps
  StepperOptions o;
  o.max_steps = 10;
  o.rtol = 1e-12;
  o.atol = 1e-14;
  auto s = make_stepper("dopri5", smooth_rhs, 3, o);
  REQUIRE(s->reset(0.0, exact(0.0)) == Stepper::Status::Ok);
  Stepper::Status st = Stepper::Status::Ok;
  while (st == Stepper::Status::Ok && s->t() < 1.0) st = s->step(1.0);
  CHECK(st == Stepper::Status::TooManySteps);
  CHECK(s->message().find("max_steps") != std::string::npos);
  // Unknown names.
  CHECK(make_stepper("euler", smooth_rhs, 3) == nullptr);
  CHECK(mbsc::runtime::stepper_names().size() == 3);
}
