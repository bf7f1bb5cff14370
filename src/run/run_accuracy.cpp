// SPDX-License-Identifier: GPL-2.0-or-later
// Accuracy warnings of a finished run (include/mbsc/run/run_accuracy.hpp).
#include "mbsc/run/run_accuracy.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>

namespace mbsc::run {

void NonFiniteColumns::row(double t, const std::vector<double>& values) {
  for (std::size_t i = 0; i < values.size() && i < names_.size(); ++i)
    if (!std::isfinite(values[i])) {
      if (std::isnan(first_[i])) first_[i] = t;
      ++count_[i];
    }
}

std::vector<std::string> NonFiniteColumns::report() const {
  std::vector<std::string> out;
  for (std::size_t i = 0; i < names_.size(); ++i)
    if (count_[i] > 0)
      out.push_back(fmt::format("column '{}' is not finite from t = {:g} ({} row{})", names_[i], first_[i], count_[i],
                                count_[i] == 1 ? "" : "s"));
  return out;
}

bool energy_is_conserved(const model::Model& m) {
  if (!m.inputs.empty() || !m.frictions.empty()) return false;
  GiNaC::exmap no_accelerations;
  for (const auto& a : m.speed_dots) no_accelerations[a] = 0;
  auto reads_motion = [&](const GiNaC::ex& e) {
    if (e.has(m.time)) return true;
    for (const auto& v : m.speeds)
      if (e.has(v.sym)) return true;
    return false;
  };
  for (const auto& f : m.forces)
    if (reads_motion(f.value.subs(no_accelerations))) return false;
  for (const auto& c : m.constraints)
    if (c.residual.has(m.time)) return false;
  for (const auto& g : m.gravity)
    if (g.has(m.time)) return false;
  for (const auto& n : m.nodes)
    if (n.potential.has(m.time)) return false;
  return true;
}

// The rows of a run are dense output between steps whose local errors the tolerances
// bound; residuals 10^4 times past atol + rtol (and past 1e-6) are no rounding matter.
double residual_limit(double rtol, double atol) { return std::max(1e-6, 1e4 * (atol + rtol)); }

// Relative to the energy's scale at the start: drift that far past the tolerance is an
// integration that lost the motion (a fixed step far too large, a start far off).
double energy_limit(double rtol) { return std::max(1e-6, 1e5 * rtol); }

std::vector<std::string> accuracy_warnings(const RunAccuracy& a) {
  std::vector<std::string> out;
  const double limit = residual_limit(a.rtol, a.atol);
  if (a.constrained && (a.position_residual > limit || a.velocity_residual > limit || std::isnan(a.position_residual) ||
                        std::isnan(a.velocity_residual)))
    out.push_back(fmt::format("the constraint residuals (position {:.3g}, velocity {:.3g}) are far above what "
                              "--rtol {:g} and --atol {:g} allow ({:.3g}): the motion did not stay on the mechanism (a "
                              "start far from it, a step far too large, or a singular configuration); tighten the "
                              "tolerances, use --projection on, or check the initial state",
                              a.position_residual, a.velocity_residual, a.rtol, a.atol, limit));
  if (!a.energy_defined) return out;
  const double relative = a.energy_change / a.energy_scale;
  if (a.energy_conserved && (relative > energy_limit(a.rtol) || std::isnan(relative)))
    out.push_back(fmt::format("the energy changed by {:.3g} ({:.3g} of its scale {:.3g}) in a model that conserves it, "
                              "far more than --rtol {:g} allows: the integration is not accurate (a step far too "
                              "large, or tolerances too loose)",
                              a.energy_change, relative, a.energy_scale, a.rtol));
  else if (!a.energy_conserved && relative > 1e6)
    out.push_back(fmt::format("the energy changed by {:.3g}, a million times its scale at the start ({:.3g}): the run "
                              "has most likely blown up",
                              a.energy_change, a.energy_scale));
  return out;
}

}  // namespace mbsc::run
