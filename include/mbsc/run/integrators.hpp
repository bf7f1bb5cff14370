// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// Every integrator `mbsc run` and `mbsc bench` offer by name: the runtime's
/// (header-only: rk4, dopri5, dop853) and, when mbsc was built with SUNDIALS, its
/// methods (src/run/sundials_stepper.hpp).
#include <memory>
#include <string>
#include <vector>

#include "mbsc/runtime/stepper.hpp"

namespace mbsc::run {

std::vector<std::string> available_integrators();

/// Null for a name not in available_integrators().
std::unique_ptr<runtime::Stepper> make_integrator(const std::string& name, runtime::Rhs rhs, int n,
                                                  const runtime::StepperOptions& options);

}  // namespace mbsc::run
