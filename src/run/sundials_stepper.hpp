// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// The SUNDIALS integrators behind `mbsc run --integrator NAME`, as runtime::Stepper:
///
///   bdf       CVODE, variable-order BDF (1-5), Newton with a dense direct solver: stiff models
///   adams     CVODE, variable-order Adams-Moulton (1-12), fixed-point iteration: smooth, non-stiff
///   ark-dirk  ARKODE ARKStep, implicit part only (its default 4th-order SDIRK), Newton, dense solver
///   ark-erk   ARKODE ERKStep, Dormand-Prince 5(4), explicit
///
/// Each step is one internal step (one-step mode with the stop time set to t_stop);
/// interpolate() is the integrator's own dense output over the last step; reset() reinitializes
/// the integrator (a new history, order 1) with statistics that keep counting. Messages name
/// the method, t and what failed, with SUNDIALS' own text after it (nothing is printed).
///
/// Without SUNDIALS at build time (MBSC_HAVE_SUNDIALS undefined) the list of names is empty
/// and the factory returns null.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "mbsc/runtime/stepper.hpp"

namespace mbsc::run {

/// Where the Newton matrix's Jacobian dxdot/dx comes from (bdf and ark-dirk).
enum class JacobianSource {
  Sundials,     // the integrator's internal difference quotients (the default)
  Differences,  // mbsc::runtime::rhs_jacobian_x (include/mbsc/runtime/rhs_jacobian.hpp)
  User,         // SundialsOptions::jacobian, e.g. the generated rhs_jacobian (differences where it fails)
};

/// J = dxdot/dx at (t, x), column-major n x n; xdot = f(t, x) is given. Returns 0 or a status.
using JacobianFn = std::function<int(double t, const double* x, const double* xdot, double* J)>;

/// The correction that puts x on the constraint manifold (x + correction on it), at t.
/// Returns 0, or a status where it cannot.
using ProjectionFn = std::function<int(double t, const double* x, double* correction)>;

struct SundialsOptions {
  JacobianSource jacobian_source = JacobianSource::Sundials;
  JacobianFn jacobian;  // for JacobianSource::User
  /// bdf only: CVODE's own projection (CVodeSetProjFn), after every step's corrector,
  /// inside the method: the history stays, unlike a projection between steps, which
  /// restarts a multistep method at order 1.
  ProjectionFn projection;
};

/// The names make_sundials_stepper knows, in the order `--integrator` lists them (empty
/// without SUNDIALS).
const std::vector<std::string>& sundials_stepper_names();

/// The SUNDIALS version linked in ("6.4.1"), or "" without SUNDIALS.
std::string sundials_version();

/// A stepper for `name` over f on n states, or null for a name not in sundials_stepper_names().
/// Nothing is integrated until reset(t0, x0).
std::unique_ptr<runtime::Stepper> make_sundials_stepper(const std::string& name, runtime::Rhs f, int n,
                                                        const runtime::StepperOptions& options,
                                                        const SundialsOptions& extra = {});

}  // namespace mbsc::run
