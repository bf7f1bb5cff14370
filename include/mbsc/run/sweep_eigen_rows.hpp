// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// The rows of `mbsc sweep --eig` (docs/sweep.md): instead of a run, each row's
/// eigenvalues of the linear model at its reference: the row's values taken as --set and
/// --init, or the steady motion that --find/--steady solves for from there. The columns
/// after the swept names: found:NAME for each --find unknown, max_real (the largest real
/// part, cyclic components left out), unstable (how many eigenvalues have a positive real
/// part), cyclic (how many components nothing depends on: eigenvalue 0), then eigK.re and
/// eigK.im, K = 1 .. n, by real part from the largest (the cyclic zeros last).
#include <complex>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "mbsc/model/model.hpp"
#include "mbsc/run/compiled_model.hpp"
#include "mbsc/run/linear_reference.hpp"

namespace mbsc::run {

struct EigenRowOptions {
  ReferenceRequest base;  // the model, --set, --init and --input texts, the time, the cache
  std::vector<std::string> find, steady, keep;
};

struct EigenRow {
  std::vector<double> values;  // one per column; NaN where the row failed
  std::string status = "ok";   // ok, start_error (no reference), failed (no linear model or eigenvalues)
  std::string message;
};

class SweepEigenRows {
 public:
  /// `compiled`: the model compiled for linearization (compile_for_linearization).
  SweepEigenRows(const model::Model& m, const CompiledModel& compiled, EigenRowOptions options);

  /// The size of the minimal state, from the row with `first` values (the sweep's row 0),
  /// which fixes the columns. False with `error` when that row has no linear model.
  bool prepare(const std::map<std::string, double>& first, std::string& error);
  const std::vector<std::string>& columns() const { return columns_; }

  /// One row; `symbolic` is held while its reference is assembled (GiNaC).
  EigenRow row(const std::map<std::string, double>& values, std::mutex& symbolic) const;

 private:
  /// The eigenvalues of the row (the cyclic components' zeros first, as
  /// eigenvalues_without_cyclic gives them), the --find solution, and how many are cyclic.
  bool eigenvalues(const std::map<std::string, double>& values, std::mutex* symbolic, std::vector<std::complex<double>>& eig,
                   std::vector<double>& found, int& cyclic, std::string& status, std::string& why) const;

  const model::Model& m_;
  const CompiledModel& compiled_;
  runtime::LinearParts parts_;  // the compiled model's linear parts, taken once
  EigenRowOptions o_;
  int n_ = 0;
  std::vector<std::string> columns_;
};

}  // namespace mbsc::run
