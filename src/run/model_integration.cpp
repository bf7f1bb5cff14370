// SPDX-License-Identifier: GPL-2.0-or-later
// One timed integration of a compiled model (include/mbsc/run/model_integration.hpp).
#include "mbsc/run/model_integration.hpp"

#include <algorithm>
#include <ctime>

#include "mbsc/run/integrators.hpp"
#include "mbsc/runtime/partition_selector.hpp"

namespace mbsc::run {

Integration integrate(const CompiledModel& model, const std::vector<double>& p, const std::vector<double>& x0,
                      const std::string& integrator, const runtime::StepperOptions& options,
                      runtime::SimulationOptions sim, const Observer& observe) {
  const runtime::ModelTable& T = model.table();
  runtime::PartitionSelector selector({T.npartitions, T.rhs_partition, T.conditioning_partition});
  std::vector<double> u(static_cast<std::size_t>(std::max(1, T.nin)), 0.0);
  runtime::Rhs rhs = [&](double t, const double* x, double* xdot) {
    if (model.inputs(t, p.data(), u.data()) != 0) return 5;
    return T.npartitions > 1 ? selector.rhs(t, x, u.data(), p.data(), xdot) : T.rhs(t, x, u.data(), p.data(), xdot);
  };
  if (T.npartitions > 1) sim.selector = &selector;
  auto inputs = [&](double t, double* uu) { return model.inputs(t, p.data(), uu); };
  Integration out;
  const std::clock_t c0 = std::clock();
  auto stepper = make_integrator(integrator, rhs, T.nx, options);
  out.result = runtime::simulate(T, *stepper, sim, x0, inputs, p.data(), observe);
  out.cpu_seconds = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
  out.stats = stepper->stats();
  out.method = stepper->name();
  return out;
}

}  // namespace mbsc::run
