// SPDX-License-Identifier: GPL-2.0-or-later
// The SUNDIALS steppers (src/run/sundials_stepper.cpp) on problems with closed forms:
//  - a damped oscillator x'' + 2 zeta w x' + w^2 x = 0: every method ends within a small
//    multiple of its tolerance, lands exactly on t_stop, and its dense output inside each
//    step matches the closed form;
//  - restarting (reset) keeps the statistics counting and continues the same solution;
//  - the three Jacobian sources (CVODE's differences, rhs_jacobian_x, an analytic one) give
//    the same answer, and the user Jacobian's evaluations are counted;
//  - failures are Status values with a message that names the method, t and the cause:
//    a failing rhs, a non-finite rhs, a spent step budget; an unknown name gives null.
#include <catch2/catch.hpp>
#include <cmath>
#include <string>
#include <vector>

#include "run/sundials_stepper.hpp"

using mbsc::run::JacobianSource;
using mbsc::run::make_sundials_stepper;
using mbsc::run::SundialsOptions;
using mbsc::runtime::Rhs;
using mbsc::runtime::Stepper;
using mbsc::runtime::StepperOptions;

namespace {

constexpr double kW = 3.0, kZeta = 0.1;

Rhs oscillator() {
  return [](double, const double* x, double* xd) {
    xd[0] = x[1];
    xd[1] = -2.0 * kZeta * kW * x[1] - kW * kW * x[0];
    return 0;
  };
}

/// The closed form from x(0) = 1, x'(0) = 0.
std::vector<double> exact(double t) {
  const double wd = kW * std::sqrt(1.0 - kZeta * kZeta), s = kZeta * kW;
  const double e = std::exp(-s * t), c = std::cos(wd * t), n = std::sin(wd * t);
  return {e * (c + s / wd * n), e * (-(s * s / wd + wd) * n)};
}

double error_at(double t, const std::vector<double>& x) {
  const auto r = exact(t);
  return std::max(std::abs(x[0] - r[0]), std::abs(x[1] - r[1]));
}

}  // namespace

TEST_CASE("sundials steppers: names, unknown names, sizes", "[numeric][sundials]") {
  const auto& names = mbsc::run::sundials_stepper_names();
  REQUIRE(names == std::vector<std::string>{"bdf", "adams", "ark-dirk", "ark-erk"});
  CHECK(mbsc::run::sundials_version().rfind("6.", 0) == 0);
  CHECK(make_sundials_stepper("dopri5", oscillator(), 2, {}) == nullptr);
  CHECK(make_sundials_stepper("bdf", oscillator(), 0, {}) == nullptr);
  SundialsOptions no_fn;
  no_fn.jacobian_source = JacobianSource::User;
  CHECK(make_sundials_stepper("bdf", oscillator(), 2, {}, no_fn) == nullptr);
  for (const auto& name : names) REQUIRE(make_sundials_stepper(name, oscillator(), 2, {})->name() == name);
}

TEST_CASE("sundials steppers follow a damped oscillator to their tolerance, with dense output", "[numeric][sundials]") {
  for (const std::string name : {"bdf", "adams", "ark-dirk", "ark-erk"}) {
    INFO(name);
    StepperOptions opt;
    opt.rtol = 1e-9;
    opt.atol = 1e-11;
    auto s = make_sundials_stepper(name, oscillator(), 2, opt);
    REQUIRE(s->reset(0.0, {1.0, 0.0}) == Stepper::Status::Ok);
    const double t_end = 5.0;
    double worst = 0.0, worst_dense = 0.0;
    std::vector<double> mid;
    int steps = 0;
    while (s->t() < t_end) {
      REQUIRE(s->step(t_end) == Stepper::Status::Ok);
      ++steps;
      REQUIRE(s->t() > s->t_begin());
      worst = std::max(worst, error_at(s->t(), s->x()));
      const double tm = 0.5 * (s->t_begin() + s->t());
      s->interpolate(tm, mid);
      worst_dense = std::max(worst_dense, error_at(tm, mid));
    }
    CHECK(s->t() == t_end);  // exactly at the stop time
    CHECK(worst < 2e-7);
    CHECK(worst_dense < 2e-6);  // dense output is a lower-order interpolant
    const auto& st = s->stats();
    CHECK(st.accepted == steps);
    CHECK(st.steps == st.accepted + st.rejected);
    CHECK(st.rhs_evals >= st.accepted);
    std::printf("%-9s steps %5ld rejected %3ld rhs %6ld jac %3ld newton %5ld  error %.1e dense %.1e\n", name.c_str(),
                st.accepted, st.rejected, st.rhs_evals, st.jacobian_evals, st.newton_iterations, worst, worst_dense);
  }
}

TEST_CASE("sundials steppers: reset restarts on the same solution and keeps counting", "[numeric][sundials]") {
  StepperOptions opt;
  opt.rtol = 1e-9;
  opt.atol = 1e-11;
  auto s = make_sundials_stepper("bdf", oscillator(), 2, opt);
  REQUIRE(s->reset(0.0, {1.0, 0.0}) == Stepper::Status::Ok);
  while (s->t() < 1.0) REQUIRE(s->step(1.0) == Stepper::Status::Ok);
  const long rhs_before = s->stats().rhs_evals, steps_before = s->stats().accepted;
  REQUIRE(steps_before > 10);
  // Restart from the state the loop holds (as after a projection); the history is new.
  const std::vector<double> x1 = s->x();
  REQUIRE(s->reset(1.0, x1) == Stepper::Status::Ok);
  while (s->t() < 2.0) REQUIRE(s->step(2.0) == Stepper::Status::Ok);
  CHECK(s->stats().rhs_evals > rhs_before);
  CHECK(s->stats().accepted > steps_before);
  CHECK(error_at(2.0, s->x()) < 2e-7);
}

TEST_CASE("sundials bdf: the three Jacobian sources agree", "[numeric][sundials][jacobian]") {
  StepperOptions opt;
  opt.rtol = 1e-8;
  opt.atol = 1e-10;
  SundialsOptions internal, differences, analytic;
  differences.jacobian_source = JacobianSource::Differences;
  analytic.jacobian_source = JacobianSource::User;
  int analytic_calls = 0;
  analytic.jacobian = [&](double, const double*, const double*, double* J) {
    ++analytic_calls;  // column-major: J[i + 2 j] = d xdot_i / d x_j
    J[0] = 0.0;
    J[1] = -kW * kW;
    J[2] = 1.0;
    J[3] = -2.0 * kZeta * kW;
    return 0;
  };
  for (const std::string name : {"bdf", "ark-dirk"}) {
    std::vector<double> ends;
    std::vector<long> jac;
    int source = 0;
    for (const SundialsOptions* extra : {&internal, &differences, &analytic}) {
      ++source;
      analytic_calls = 0;
      auto s = make_sundials_stepper(name, oscillator(), 2, opt, *extra);
      REQUIRE(s->reset(0.0, {1.0, 0.0}) == Stepper::Status::Ok);
      while (s->t() < 3.0) REQUIRE(s->step(3.0) == Stepper::Status::Ok);
      INFO(name << " source " << source);
      std::printf("%s source %d: error %.2e jac %ld newton %ld rhs %ld\n", name.c_str(), source, error_at(3.0, s->x()),
                  s->stats().jacobian_evals, s->stats().newton_iterations, s->stats().rhs_evals);
      CHECK(error_at(3.0, s->x()) < 1e-6);
      CHECK(s->stats().jacobian_evals > 0);
      CHECK(s->stats().newton_iterations > 0);
      if (extra == &analytic) CHECK(analytic_calls == s->stats().jacobian_evals);
      ends.push_back(s->x()[0]);
    }
    CHECK(ends[1] == Approx(ends[0]).margin(1e-7));
    CHECK(ends[2] == Approx(ends[0]).margin(1e-7));
  }
}

TEST_CASE("sundials steppers: failures say what, where and when", "[numeric][sundials][errors]") {
  SECTION("an rhs status") {
    Rhs failing = [](double t, const double* x, double* xd) {
      if (t > 0.25) return 1;  // as a generated rhs at a singular solve
      xd[0] = -x[0];
      return 0;
    };
    for (const std::string name : {"bdf", "adams", "ark-dirk", "ark-erk"}) {
      INFO(name);
      auto s = make_sundials_stepper(name, failing, 1, {});
      REQUIRE(s->reset(0.0, {1.0}) == Stepper::Status::Ok);
      Stepper::Status st = Stepper::Status::Ok;
      while (st == Stepper::Status::Ok && s->t() < 1.0) st = s->step(1.0);
      CHECK(st == Stepper::Status::RhsFailed);
      const std::string m = s->message();
      INFO(m);
      const std::string head = name + ": the right-hand side returned status 1 at t = ";
      REQUIRE(m.rfind(head, 0) == 0);
      CHECK(std::stod(m.substr(head.size())) >= 0.25);  // printed to 9 digits
      CHECK(s->t() <= 0.25);  // the state stays at the last good step
    }
  }
  SECTION("a non-finite rhs") {
    Rhs blowing = [](double t, const double* x, double* xd) {
      xd[0] = t > 0.5 ? std::log(-1.0) : -x[0];
      return 0;
    };
    auto s = make_sundials_stepper("bdf", blowing, 1, {});
    REQUIRE(s->reset(0.0, {1.0}) == Stepper::Status::Ok);
    Stepper::Status st = Stepper::Status::Ok;
    while (st == Stepper::Status::Ok && s->t() < 1.0) st = s->step(1.0);
    CHECK(st == Stepper::Status::RhsFailed);
    INFO(s->message());
    CHECK(s->message().find("bdf: the right-hand side gave xdot[0] = nan at t = 0.") == 0);
  }
  SECTION("a step budget") {
    StepperOptions opt;
    opt.max_steps = 20;
    auto s = make_sundials_stepper("ark-erk", oscillator(), 2, opt);
    REQUIRE(s->reset(0.0, {1.0, 0.0}) == Stepper::Status::Ok);
    Stepper::Status st = Stepper::Status::Ok;
    while (st == Stepper::Status::Ok && s->t() < 100.0) st = s->step(100.0);
    CHECK(st == Stepper::Status::TooManySteps);
    CHECK(s->stats().accepted == 20);
    INFO(s->message());
    CHECK(s->message().find("ark-erk: step budget of 20 steps spent at t = ") == 0);
  }
}
