// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// What a run's options (RunArgs) decide for its compile and its integration: the same
/// for `mbsc run` and for every row of `mbsc sweep`, so that a row re-run alone with
/// `mbsc run` is the same run.
#include <map>
#include <string>

#include "mbsc/model/model.hpp"
#include "mbsc/run/compiled_model.hpp"
#include "mbsc/run/model_integration.hpp"
#include "mbsc/run/run_command.hpp"
#include "mbsc/runtime/simulate.hpp"
#include "mbsc/runtime/stepper.hpp"

namespace mbsc::run {

/// The output step: --dt-out, or t_end / 500.
double output_step(const RunArgs& a);

/// Where bdf's and ark-dirk's Newton matrices take dxdot/dx from (--newton-jacobian).
NewtonJacobian newton_jacobian(const RunArgs& a);

/// The compile a run needs: its formulation, state, solver and cache; the generated rhs
/// Jacobian only for a Newton method that uses it. `input_expressions`: the --input
/// expressions compiled into the object (tables are read by the run itself).
CompileRequest compile_request(const RunArgs& a, const std::map<std::string, std::string>& input_expressions);

/// The stepper's tolerances and step (a fixed-step method's default: dt_out / 10).
runtime::StepperOptions stepper_options(const RunArgs& a);

/// From t = 0 to t_end with rows every output_step; projection on for the complement form
/// (auto) and off for the multipliers form, which has its own stabilization (Baumgarte);
/// unit quaternions of rigid3d bodies kept at |e| = 1 unless --projection off; stopped
/// when the command's time budget runs out. `a` must outlive the result (its budget).
runtime::SimulationOptions simulation_options(const RunArgs& a, const model::Model& m, const runtime::ModelTable& t);

}  // namespace mbsc::run
