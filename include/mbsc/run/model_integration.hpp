// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// One integration of a compiled model, as `mbsc run` and every run of `mbsc bench`
/// make it: the inputs at t, the active independent set's rhs (re-selected between
/// steps when the model declares alternatives), the named integrator, the runtime's
/// simulation loop; timed in CPU seconds.
#include <functional>
#include <string>
#include <vector>

#include "mbsc/run/compiled_model.hpp"
#include "mbsc/runtime/simulate.hpp"
#include "mbsc/runtime/stepper.hpp"

namespace mbsc::run {

struct Integration {
  runtime::SimulationResult result;
  runtime::StepperStats stats;
  std::string method;  // the stepper's name
  double cpu_seconds = 0.0;
};

using Observer = std::function<void(double t, const std::vector<double>& x)>;

/// Where bdf's and ark-dirk's Newton matrices take dxdot/dx from (`mbsc run --newton-jacobian`).
enum class NewtonJacobian {
  Generated,    // the generated rhs_jacobian, when the model was compiled with it (else as Sundials)
  Differences,  // forward differences of the rhs, one column per state (runtime/rhs_jacobian.hpp)
  Sundials,     // SUNDIALS' own difference quotients
};

/// The inputs at t (status as the generated `inputs`).
using InputFunction = std::function<int(double t, double* u)>;

/// `integrator` must be one of available_integrators(); `continuation` evaluates the rhs
/// through the runtime's BranchContinuation (through rank loss of the constraints).
/// `inputs`: the inputs the rhs reads (default: the compiled model's `inputs`).
Integration integrate(const CompiledModel& model, const std::vector<double>& p, const std::vector<double>& x0,
                      const std::string& integrator, const runtime::StepperOptions& options,
                      runtime::SimulationOptions sim, const Observer& observe, bool continuation = false,
                      NewtonJacobian newton = NewtonJacobian::Generated, const InputFunction& inputs = {});

}  // namespace mbsc::run
