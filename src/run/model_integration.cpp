// SPDX-License-Identifier: GPL-2.0-or-later
// One timed integration of a compiled model (include/mbsc/run/model_integration.hpp).
#include "mbsc/run/model_integration.hpp"

#include <algorithm>

#include "mbsc/run/integrators.hpp"
#include "sundials_stepper.hpp"

namespace mbsc::run {

Integration integrate(const CompiledModel& model, const std::vector<double>& p, const std::vector<double>& x0,
                      const std::string& integrator, const runtime::StepperOptions& options,
                      runtime::SimulationOptions sim, const Observer& observe, bool continuation) {
  // The loop owns what the rhs goes through: the inputs at t and the independent set.
  runtime::ModelDynamics dynamics(model.table(), p,
                                  [&model, &p](double t, double* u) { return model.inputs(t, p.data(), u); });
  if (continuation) dynamics.continue_through_rank_loss();
  auto stepper = make_integrator(integrator, dynamics.rhs(), model.table().nx, options);
  // Project only once the constraints drift past what the tolerances allow anyway: each
  // projection restarts the stepper, which costs a multistep method (BDF) its order and
  // step size; projecting every step made BDF take 100 times more steps on the four-bar.
  sim.projection_threshold = std::max(1e-13, options.atol + options.rtol);
  // Even so, a multistep method restarted after every few steps is no multistep method:
  // SUNDIALS' methods run without the loop's projection unless it is asked for (On).
  const auto& sundials = sundials_stepper_names();
  if (sim.projection == runtime::SimulationOptions::Projection::Auto &&
      std::find(sundials.begin(), sundials.end(), integrator) != sundials.end())
    sim.projection = runtime::SimulationOptions::Projection::Off;
  Integration out;
  out.result = runtime::simulate(dynamics, *stepper, sim, x0, observe);
  out.cpu_seconds = out.result.cpu_seconds;
  out.stats = stepper->stats();
  out.method = stepper->name();
  return out;
}

}  // namespace mbsc::run
