// SPDX-License-Identifier: GPL-2.0-or-later
// One timed integration of a compiled model (include/mbsc/run/model_integration.hpp).
#include "mbsc/run/model_integration.hpp"

#include <algorithm>

#include "mbsc/run/integrators.hpp"
#include "mbsc/runtime/projection.hpp"
#include "sundials_stepper.hpp"

namespace mbsc::run {

Integration integrate(const CompiledModel& model, const std::vector<double>& p, const std::vector<double>& x0,
                      const std::string& integrator, const runtime::StepperOptions& options,
                      runtime::SimulationOptions sim, const Observer& observe, bool continuation,
                      NewtonJacobian newton, const InputFunction& inputs) {
  // The loop owns what the rhs goes through: the inputs at t and the independent set.
  runtime::ModelDynamics dynamics(model.table(), p, [&model, &p, &inputs](double t, double* u) {
    return inputs ? inputs(t, u) : model.inputs(t, p.data(), u);
  });
  if (continuation) dynamics.continue_through_rank_loss();
  sim.crossing.rtol = options.rtol;  // the extrapolation across a pose of rank loss meets the run's tolerances
  sim.crossing.atol = options.atol;
  const runtime::ModelTable& table = model.table();
  const bool constrained = table.full_state_layout() && (table.nposc > 0 || table.nc > 0);
  // BDF keeps a constrained model on its manifold by CVODE's own projection, inside the
  // method: projecting between steps restarts a multistep method at order 1 (projecting
  // every step made BDF take 100 times more steps on the four-bar), and not projecting
  // left the stiff flyball 1e-4 m off an explicit reference at rtol 1e-8.
  const bool cvode_projection =
      integrator == "bdf" && constrained && sim.projection == runtime::SimulationOptions::Projection::Auto;
  SundialsOptions extra;
  if (newton == NewtonJacobian::Differences) extra.jacobian_source = JacobianSource::Differences;
  std::vector<double> jacobian_rows;
  // The generated Jacobian is that of the declared partition's rhs without continuation:
  // the function integrated only where no other partition or branch can take over.
  if (newton == NewtonJacobian::Generated && table.rhs_jacobian && table.npartitions <= 1 && !continuation) {
    // The generated J_x (row-major, the first nx*nx values) into SUNDIALS' column-major matrix.
    extra.jacobian_source = JacobianSource::User;
    extra.jacobian = [&dynamics, &table, &jacobian_rows](double t, const double* x, const double*, double* J) {
      if (dynamics.inputs_at(t) != 0) return 1;
      const int n = table.nx;
      jacobian_rows.resize(static_cast<std::size_t>(n) * static_cast<std::size_t>(n + table.nin));
      if (const int s = table.rhs_jacobian(t, x, dynamics.inputs(), dynamics.params(), jacobian_rows.data()); s != 0) return s;
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
          J[static_cast<std::size_t>(i) + static_cast<std::size_t>(j) * static_cast<std::size_t>(n)] =
              jacobian_rows[static_cast<std::size_t>(i) * static_cast<std::size_t>(n) + static_cast<std::size_t>(j)];
      return 0;
    };
  }
  if (cvode_projection) {
    // Newton to a tenth of the absolute tolerance (or rounding, where it stalls): a
    // projection that leaves more than the error test allows makes every step fail it.
    runtime::ProjectionOptions po;
    po.position_tolerance = std::min(po.position_tolerance, 0.1 * options.atol);
    extra.projection = [&dynamics, &table, po](double t, const double* x, double* correction) {
      if (dynamics.inputs_at(t) != 0) return 1;
      std::vector<double> y(x, x + table.nx);
      // Newton stopped short of 1e-13 (rounding at a tight tolerance) still moved the state
      // onto the manifold as far as it goes: only an evaluation failure fails the step.
      const runtime::ProjectionReport r = runtime::project(table, t, y, dynamics.inputs(), dynamics.params(), po);
      if (r.status == runtime::ProjectionReport::Status::EvaluationFailed) return 1;
      for (int i = 0; i < table.nx; ++i) correction[i] = y[static_cast<std::size_t>(i)] - x[i];
      return 0;
    };
    sim.projection = runtime::SimulationOptions::Projection::Off;  // done inside the method
  }
  // A SUNDIALS method with its Newton Jacobian and projection, else the runtime's.
  std::unique_ptr<runtime::Stepper> stepper = make_sundials_stepper(integrator, dynamics.rhs(), table.nx, options, extra);
  if (!stepper) stepper = make_integrator(integrator, dynamics.rhs(), table.nx, options);
  // Project only once the constraints drift past what the tolerances allow anyway: each
  // projection restarts the stepper. The other SUNDIALS methods have no projection of
  // their own: theirs is the loop's, like the runtime's integrators'.
  sim.projection_threshold = std::max(1e-13, options.atol + options.rtol);
  Integration out;
  out.result = runtime::simulate(dynamics, *stepper, sim, x0, observe);
  out.cpu_seconds = out.result.cpu_seconds;
  out.stats = stepper->stats();
  out.method = stepper->name();
  return out;
}

}  // namespace mbsc::run
