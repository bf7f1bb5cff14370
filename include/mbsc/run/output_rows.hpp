// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// The output rows of a run: the columns of `mbsc run`'s CSV (t, every coordinate and
/// speed in the full layout, the outputs, the inputs, kinetic, potential and energy) and
/// how one row fills them from the state, with the largest constraint residuals and the
/// largest |E - E0| over the rows so far. `mbsc run` writes these rows; `mbsc sweep`
/// summarises them.
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

#include "mbsc/runtime/model_table.hpp"

namespace mbsc::run {

class OutputRows {
 public:
  /// `has_energy`: the energy columns are there (a model whose energy is defined).
  OutputRows(const runtime::ModelTable& model, bool has_energy);

  const std::vector<std::string>& names() const { return names_; }
  std::size_t first_output() const { return first_output_; }
  std::size_t first_input() const { return first_input_; }
  std::size_t first_energy() const { return first_energy_; }
  bool has_energy() const { return has_energy_; }

  /// Row (t, x) with inputs u and parameters p into `all` (names().size() values). A value
  /// a function could not give (a singular solve) is NaN; status 2 (not finite) still
  /// fills its values, as they are. Updates the residual and energy maxima. E0 is the
  /// energy of the first row unless set_initial_energy gave it.
  void fill(double t, const std::vector<double>& x, const double* u, const double* p, std::vector<double>& all);
  void set_initial_energy(double e0) { e0_ = e0; }
  double initial_energy() const { return e0_; }

  /// The largest |residual| over the rows filled (NaN once one was not finite); only for
  /// a model integrated in the full layout, else 0.
  double position_residual() const { return position_; }
  double velocity_residual() const { return velocity_; }
  /// The largest |E - E0| over the rows whose energy was given (NaN once one was not finite).
  double energy_change() const { return energy_change_; }

 private:
  const runtime::ModelTable& T_;
  bool has_energy_;
  std::vector<std::string> names_;
  std::size_t first_output_ = 0, first_input_ = 0, first_energy_ = 0;
  int nfull_ = 0;
  std::vector<double> full_x_, y_, residual_;
  double e0_ = std::numeric_limits<double>::quiet_NaN();
  double position_ = 0.0, velocity_ = 0.0, energy_change_ = 0.0;
};

}  // namespace mbsc::run
