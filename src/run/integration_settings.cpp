// SPDX-License-Identifier: GPL-2.0-or-later
// What a run's options decide (include/mbsc/run/integration_settings.hpp).
#include "mbsc/run/integration_settings.hpp"

#include "mbsc/run/run_setup.hpp"

namespace mbsc::run {

double output_step(const RunArgs& a) { return a.dt_out > 0 ? a.dt_out : a.t_end / 500; }

NewtonJacobian newton_jacobian(const RunArgs& a) {
  return a.newton_jacobian == "differences" ? NewtonJacobian::Differences
         : a.newton_jacobian == "sundials"  ? NewtonJacobian::Sundials
                                            : NewtonJacobian::Generated;
}

CompileRequest compile_request(const RunArgs& a, const std::map<std::string, std::string>& input_expressions) {
  CompileRequest req;
  req.model_path = a.model;
  req.multipliers = a.multipliers;
  req.input_expressions = input_expressions;
  req.cache_dir = a.cache_dir;
  req.work = a.work;
  req.minimal_state = a.minimal_state;
  req.solver = a.solver;
  const bool newton_method = a.integrator == "bdf" || a.integrator == "ark-dirk";
  req.rhs_jacobian = newton_method && newton_jacobian(a) == NewtonJacobian::Generated;
  return req;
}

runtime::StepperOptions stepper_options(const RunArgs& a) {
  runtime::StepperOptions so;
  so.rtol = a.rtol;
  so.atol = a.atol;
  so.h = a.h > 0 ? a.h : (a.integrator == "rk4" ? output_step(a) / 10 : 0.0);
  return so;
}

runtime::SimulationOptions simulation_options(const RunArgs& a, const model::Model& m, const runtime::ModelTable& t) {
  runtime::SimulationOptions sim;
  sim.t0 = 0.0;
  sim.t_end = a.t_end;
  sim.dt_out = output_step(a);
  using Projection = runtime::SimulationOptions::Projection;
  sim.projection = a.projection == "on" ? Projection::On
                   : a.projection == "off" || t.multipliers ? Projection::Off : Projection::Auto;
  if (a.projection != "off") sim.unit_quaternions = unit_quaternion_indices(m, t);
  const auto& budget = a.work.budget;
  sim.stop_requested = [&budget](double) { return budget.seconds_left() <= 0; };
  return sim;
}

}  // namespace mbsc::run
