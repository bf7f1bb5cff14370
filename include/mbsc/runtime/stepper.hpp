// SPDX-License-Identifier: GPL-2.0-or-later WITH mbsc-runtime-exception
// (see LICENSE: this header may be included in applications under any terms)
#pragma once
/// The one interface every integrator of the runtime (and `mbsc run`'s SUNDIALS ones)
/// offers to the simulation loop: take one step at a time, never past a stopping time,
/// interpolate inside the last step (dense output), and restart from a new state after
/// the loop changed it (projection onto the constraints, a switch of the independent set).
///
/// The right-hand side is `Rhs`: f(t, x, xdot) returning 0, or the generated function's
/// non-zero status (a singular solve, a non-finite value).
#include <functional>
#include <string>
#include <vector>

namespace mbsc::runtime {

using Rhs = std::function<int(double t, const double* x, double* xdot)>;

struct StepperOptions {
  double rtol = 1e-6;
  double atol = 1e-9;
  double h = 0.0;       // fixed-step methods: the step; adaptive ones: the first step (0: chosen)
  double h_min = 0.0;   // adaptive: a step below this (and below 1e-14 |t|) is a failure
  double h_max = 0.0;   // adaptive: 0 for no limit
  long max_steps = 100000000;
};

struct StepperStats {
  long steps = 0;      // attempted
  long accepted = 0;
  long rejected = 0;   // error test failures (and, for implicit methods, convergence failures)
  long rhs_evals = 0;  // calls of f, including those for Jacobians by differences
  long jacobian_evals = 0;
  long newton_iterations = 0;
  long newton_failures = 0;  // steps retried because Newton's iteration did not converge
  long jacobian_fallbacks = 0;  // Jacobians by differences where the given one failed
  long projections = 0;  // projections inside the method (CVODE's, for bdf), not the loop's
};

class Stepper {
 public:
  enum class Status { Ok, RhsFailed, StepTooSmall, TooManySteps, SolverFailed };

  virtual ~Stepper() = default;
  /// (Re)starts at (t, x): the first call, and after the loop changed the state.
  virtual Status reset(double t, const std::vector<double>& x) = 0;
  /// One accepted step, ending at or before t_stop (exactly at t_stop when it is reached).
  virtual Status step(double t_stop) = 0;
  /// The state at the end of the last accepted step.
  virtual double t() const = 0;
  virtual const std::vector<double>& x() const = 0;
  /// Where the last accepted step began; interpolate() serves [t_begin(), t()].
  virtual double t_begin() const = 0;
  virtual void interpolate(double t, std::vector<double>& out) const = 0;
  virtual const StepperStats& stats() const = 0;
  /// After a failure: what happened, with t and the quantity (e.g. "step size 3e-15 at t = 1.2").
  virtual std::string message() const = 0;
  /// The method's name as `--integrator` spells it.
  virtual std::string name() const = 0;
};

}  // namespace mbsc::runtime
