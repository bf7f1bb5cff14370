// SPDX-License-Identifier: GPL-2.0-or-later
// The integrators by name (include/mbsc/run/integrators.hpp).
#include "mbsc/run/integrators.hpp"

#include "mbsc/runtime/make_stepper.hpp"
#include "sundials_stepper.hpp"

namespace mbsc::run {

std::vector<std::string> available_integrators() {
  std::vector<std::string> names = runtime::stepper_names();
  for (const auto& s : sundials_stepper_names()) names.push_back(s);
  return names;
}

std::unique_ptr<runtime::Stepper> make_integrator(const std::string& name, runtime::Rhs rhs, int n,
                                                  const runtime::StepperOptions& options) {
  if (auto s = runtime::make_stepper(name, rhs, n, options)) return s;
  return make_sundials_stepper(name, std::move(rhs), n, options);
}

}  // namespace mbsc::run
