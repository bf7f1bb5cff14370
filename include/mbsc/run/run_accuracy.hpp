// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// What a finished run's summary warns about: columns that stopped being finite, and
/// constraint residuals or an energy change far beyond what the tolerances promise. A
/// run is not silently wrong: each is a warning in the summary, and with `--strict` the
/// run ends with exit code 2 (docs/running.md, "Accuracy warnings").
#include <limits>
#include <string>
#include <vector>

#include "mbsc/model/model.hpp"

namespace mbsc::run {

/// Watches the rows written: the first t at which each column is not finite.
class NonFiniteColumns {
 public:
  explicit NonFiniteColumns(std::vector<std::string> names) : names_(std::move(names)), first_(names_.size(), nan()) {}
  void row(double t, const std::vector<double>& values);
  /// One line per column that held a non-finite value ("'b.x' from t = 0.25 (12 rows)").
  std::vector<std::string> report() const;

 private:
  static double nan() { return std::numeric_limits<double>::quiet_NaN(); }
  std::vector<std::string> names_;
  std::vector<double> first_;
  std::vector<long> count_ = std::vector<long>(names_.size(), 0);
};

/// Whether the model's total energy T + V must stay constant: no inputs, no friction,
/// and no generalized force that reads a speed, an input or t (dampers, actuators, driven
/// motions); constraints that read t do work too. Inertial terms (accelerations) are no
/// such forces.
bool energy_is_conserved(const model::Model& m);

struct RunAccuracy {
  double rtol = 0, atol = 0;
  bool constrained = false;
  double position_residual = 0, velocity_residual = 0;  // the largest over the rows written
  bool energy_defined = false, energy_conserved = false;
  double energy_change = 0, energy_scale = 1;  // largest |E - E0|; the largest of |T|, |V|, |E| at t0
};

/// The largest constraint residual a run at these tolerances should leave (with a margin
/// of orders of magnitude), and the largest relative energy change.
double residual_limit(double rtol, double atol);
double energy_limit(double rtol);

/// Warnings (whole sentences) for a finished run.
std::vector<std::string> accuracy_warnings(const RunAccuracy& a);

}  // namespace mbsc::run
