// SPDX-License-Identifier: GPL-2.0-or-later
// The rows of `mbsc sweep --eig` (include/mbsc/run/sweep_eigen_rows.hpp): the reference of
// `mbsc linearize` at each row's values, its linear model in a minimal state, and the
// eigenvalues of that model, as `mbsc linearize` finds them.
#include "mbsc/run/sweep_eigen_rows.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "mbsc/runtime/linear_model.hpp"

namespace mbsc::run {

namespace {
constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
}

SweepEigenRows::SweepEigenRows(const model::Model& m, const CompiledModel& compiled, EigenRowOptions options)
    : m_(m), compiled_(compiled), parts_(parts_of(compiled, m)), o_(std::move(options)) {}

bool SweepEigenRows::eigenvalues(const std::map<std::string, double>& values, std::mutex* symbolic,
                                 std::vector<std::complex<double>>& eig, std::vector<double>& found, int& cyclic,
                                 std::string& status, std::string& why) const {
  ReferenceRequest r = o_.base;
  for (const auto& [name, v] : values) r.overrides[name] = v;
  LinearReference ref;
  {
    std::unique_lock<std::mutex> lock;
    if (symbolic) lock = std::unique_lock<std::mutex>(*symbolic);
    const bool ok = o_.find.empty() ? reference_state(m_, compiled_, r, ref, why)
                                    : find_steady(m_, compiled_, r, o_.find, o_.steady, ref, why);
    if (!ok) {
      status = "start_error";
      return false;
    }
  }
  found.clear();
  for (const auto& name : o_.find) found.push_back(r.overrides.at(name));
  status = "failed";
  runtime::LinearModel lin;
  if (runtime::linear_model(parts_, r.t, ref.x.data(), ref.u.data(), ref.p.data(), lin, why) != 0)
    return false;
  std::vector<int> sel;
  if (!minimal_state(lin, compiled_.table(), o_.keep, sel, why)) return false;
  std::vector<double> A, B;
  if (!runtime::restrict_to(lin, sel, A, B)) {
    why = "the minimal state does not parametrize the linearized constraints";
    return false;
  }
  std::vector<int> cyclic_components;
  eig = eigenvalues_without_cyclic(A, static_cast<int>(sel.size()), cyclic_components);
  cyclic = static_cast<int>(cyclic_components.size());
  for (const auto& z : eig)
    if (!std::isfinite(z.real()) || !std::isfinite(z.imag())) {
      why = "the eigenvalue solver did not converge";
      return false;
    }
  status = "ok";
  return true;
}

bool SweepEigenRows::prepare(const std::map<std::string, double>& first, std::string& error) {
  std::vector<std::complex<double>> eig;
  std::vector<double> found;
  int cyclic = 0;
  std::string status;
  if (!eigenvalues(first, nullptr, eig, found, cyclic, status, error)) {
    error = "--eig: at the first row, " + error;
    return false;
  }
  n_ = static_cast<int>(eig.size());
  columns_.clear();
  for (const auto& name : o_.find) columns_.push_back("found:" + name);
  for (const char* c : {"max_real", "unstable", "cyclic"}) columns_.push_back(c);
  for (int k = 1; k <= n_; ++k) {
    columns_.push_back(fmt::format("eig{}.re", k));
    columns_.push_back(fmt::format("eig{}.im", k));
  }
  return true;
}

EigenRow SweepEigenRows::row(const std::map<std::string, double>& values, std::mutex& symbolic) const {
  EigenRow out;
  out.values.assign(columns_.size(), kNan);
  std::vector<std::complex<double>> eig;
  std::vector<double> found;
  int cyclic = 0;
  if (!eigenvalues(values, &symbolic, eig, found, cyclic, out.status, out.message)) return out;
  if (static_cast<int>(eig.size()) != n_) {
    out.status = "failed";
    out.message = fmt::format("the minimal state has {} components here and {} at the first row", eig.size(), n_);
    return out;
  }
  std::size_t c = 0;
  for (double v : found) out.values[c++] = v;
  // By real part from the largest: the cyclic zeros come first from
  // eigenvalues_without_cyclic, the rest in rising order.
  std::vector<std::complex<double>> ordered(eig.rbegin(), eig.rend() - cyclic);
  ordered.insert(ordered.end(), eig.begin(), eig.begin() + cyclic);
  double scale = 0.0;
  for (const auto& z : ordered) scale = std::max(scale, std::abs(z));
  int unstable = 0;
  for (int k = 0; k < n_ - cyclic; ++k) unstable += ordered[static_cast<std::size_t>(k)].real() > 1e-9 * scale;
  out.values[c++] = n_ > cyclic ? ordered.front().real() : kNan;
  out.values[c++] = unstable;
  out.values[c++] = cyclic;
  for (const auto& z : ordered) {
    out.values[c++] = z.real();
    out.values[c++] = z.imag();
  }
  return out;
}

}  // namespace mbsc::run
