// SPDX-License-Identifier: GPL-2.0-or-later
// The output rows of a run (include/mbsc/run/output_rows.hpp).
#include "mbsc/run/output_rows.hpp"

#include <algorithm>
#include <cmath>

namespace mbsc::run {

namespace {

const double kNan = std::numeric_limits<double>::quiet_NaN();

bool gave(int status) { return status == 0 || status == 2; }

/// worst = max(worst, |v|), NaN once either is NaN (std::max would drop it).
void largest(double& worst, double v) { worst = std::isnan(v) || std::isnan(worst) ? kNan : std::max(worst, std::fabs(v)); }

}  // namespace

OutputRows::OutputRows(const runtime::ModelTable& model, bool has_energy) : T_(model), has_energy_(has_energy) {
  nfull_ = T_.nq_full + T_.nu_full;
  names_.push_back("t");
  for (const auto& s : runtime::ModelTable::names_of(T_.full_state_names, nfull_)) names_.push_back(s);
  first_output_ = names_.size();
  for (const auto& s : runtime::ModelTable::names_of(T_.output_names, T_.ny)) names_.push_back(s);
  first_input_ = names_.size();
  if (T_.nin > 0)
    for (const auto& s : runtime::ModelTable::names_of(T_.input_names, T_.nin)) names_.push_back(s);
  first_energy_ = names_.size();
  if (has_energy_)
    for (const char* s : {"kinetic", "potential", "energy"}) names_.push_back(s);
  full_x_.resize(static_cast<std::size_t>(nfull_));
  y_.resize(static_cast<std::size_t>(std::max(1, T_.ny)));
  residual_.resize(static_cast<std::size_t>(std::max({1, T_.nposc, T_.nc})));
}

void OutputRows::fill(double t, const std::vector<double>& x, const double* u, const double* p, std::vector<double>& all) {
  all.assign(names_.size(), kNan);
  all[0] = t;
  if (T_.full_state_layout()) {
    for (int i = 0; i < T_.nx; ++i) all[1 + static_cast<std::size_t>(i)] = x[static_cast<std::size_t>(i)];
  } else if (gave(T_.full_state(t, x.data(), u, p, full_x_.data()))) {
    for (int i = 0; i < nfull_; ++i) all[1 + static_cast<std::size_t>(i)] = full_x_[static_cast<std::size_t>(i)];
  }
  if (T_.ny > 0 && gave(T_.outputs(t, x.data(), u, p, y_.data())))
    for (int i = 0; i < T_.ny; ++i) all[first_output_ + static_cast<std::size_t>(i)] = y_[static_cast<std::size_t>(i)];
  for (int i = 0; i < T_.nin; ++i) all[first_input_ + static_cast<std::size_t>(i)] = u[i];
  // Residuals of the rows (dense output between steps is not projected): the full layout only.
  if (T_.full_state_layout()) {
    if (T_.nposc > 0 && gave(T_.position_constraints(t, x.data(), u, p, residual_.data())))
      for (int i = 0; i < T_.nposc; ++i) largest(position_, residual_[static_cast<std::size_t>(i)]);
    if (T_.nc > 0 && gave(T_.velocity_constraints(t, x.data(), u, p, residual_.data())))
      for (int i = 0; i < T_.nc; ++i) largest(velocity_, residual_[static_cast<std::size_t>(i)]);
  }
  if (has_energy_) {
    double e[3] = {kNan, kNan, kNan};
    if (gave(T_.energy(t, x.data(), u, p, e))) {
      for (int i = 0; i < 3; ++i) all[first_energy_ + static_cast<std::size_t>(i)] = e[i];
      if (std::isnan(e0_)) e0_ = e[2];
      largest(energy_change_, e[2] - e0_);
    }
  }
}

}  // namespace mbsc::run
