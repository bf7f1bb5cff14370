// SPDX-License-Identifier: GPL-2.0-or-later
// Time derivatives along the model's kinematics: d/dt e(t, q0, q1) =
//   de/dt + sum_i de/dq0_i * rate_i(t, q0, q1) + sum_j de/dq1_j * q1dot_j.
#include "mbsc/sym/eom.hpp"
#include "mbsc/sym/symbol_set.hpp"

namespace mbsc::sym {

GiNaC::ex time_derivative(const model::Model& model, const GiNaC::ex& e) {
  const SymbolSet in_e(e);  // one traversal instead of one has() per variable
  GiNaC::ex result = in_e.diff(e, model.time);
  for (size_t i = 0; i < model.coords.size(); ++i)
    if (in_e.contains(model.coords[i].sym)) result += e.diff(model.coords[i].sym) * model.coord_rates[i];
  for (size_t j = 0; j < model.speeds.size(); ++j)
    if (in_e.contains(model.speeds[j].sym)) result += e.diff(model.speeds[j].sym) * model.speed_dots[j];
  // Kinematic names (issue 25): d/dt R = R [w]x, never through the ancestors' angles.
  for (const auto& k : model.kinematic_names)
    if (in_e.contains(k.sym)) result += e.diff(k.sym) * k.rate;
  return result;
}

std::vector<GiNaC::ex> velocity_residuals(const model::Model& model) {
  std::vector<GiNaC::ex> out;
  out.reserve(model.constraints.size());
  for (const auto& c : model.constraints)
    out.push_back(c.level == model::Constraint::Level::Position ? time_derivative(model, c.residual) : c.residual);
  return out;
}

}  // namespace mbsc::sym
