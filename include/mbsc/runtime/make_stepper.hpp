// SPDX-License-Identifier: GPL-2.0-or-later WITH mbsc-runtime-exception
// (see LICENSE: this header may be included in applications under any terms)
#pragma once
/// The runtime's integrators by name, as `--integrator` spells them:
///   rk4     fixed step h (StepperOptions::h), 4 rhs evaluations per step
///   dopri5  Dormand-Prince 5(4), adaptive, 4th-order dense output (rtol 1e-3 .. 1e-9)
///   dop853  Dormand-Prince 8(5,3), adaptive, 7th-order dense output (rtol 1e-6 .. 1e-13)
/// make_stepper returns null for a name it does not know (`mbsc run` adds its SUNDIALS
/// methods to this list).
#include <memory>
#include <string>
#include <vector>

#include "mbsc/runtime/dop853.hpp"
#include "mbsc/runtime/dopri5.hpp"
#include "mbsc/runtime/rk4_stepper.hpp"

namespace mbsc::runtime {

inline const std::vector<std::string>& stepper_names() {
  static const std::vector<std::string> names{"rk4", "dopri5", "dop853"};
  return names;
}

inline std::unique_ptr<Stepper> make_stepper(const std::string& name, Rhs rhs, int n, const StepperOptions& options = {}) {
  if (name == "rk4") return std::make_unique<Rk4Stepper>(std::move(rhs), n, options);
  if (name == "dopri5") return std::make_unique<Dopri5>(std::move(rhs), n, options);
  if (name == "dop853") return std::make_unique<Dop853>(std::move(rhs), n, options);
  return nullptr;
}

}  // namespace mbsc::runtime
