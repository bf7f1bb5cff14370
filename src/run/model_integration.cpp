// SPDX-License-Identifier: GPL-2.0-or-later
// One timed integration of a compiled model (include/mbsc/run/model_integration.hpp).
#include "mbsc/run/model_integration.hpp"

#include "mbsc/run/integrators.hpp"

namespace mbsc::run {

Integration integrate(const CompiledModel& model, const std::vector<double>& p, const std::vector<double>& x0,
                      const std::string& integrator, const runtime::StepperOptions& options,
                      runtime::SimulationOptions sim, const Observer& observe) {
  // The loop owns what the rhs goes through: the inputs at t and the independent set.
  runtime::ModelDynamics dynamics(model.table(), p,
                                  [&model, &p](double t, double* u) { return model.inputs(t, p.data(), u); });
  auto stepper = make_integrator(integrator, dynamics.rhs(), model.table().nx, options);
  Integration out;
  out.result = runtime::simulate(dynamics, *stepper, sim, x0, observe);
  out.cpu_seconds = out.result.cpu_seconds;
  out.stats = stepper->stats();
  out.method = stepper->name();
  return out;
}

}  // namespace mbsc::run
