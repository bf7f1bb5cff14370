// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// Test helper: evaluates every step before the mass-matrix solve (numeric block solves
// with Eigen, independently of the generated code, and the e_ variables) at a probe
// point and binds their results to the probe.
#include <Eigen/Dense>

#include "mbsc/driver/pipeline.hpp"
#include "mbsc/sym/probe.hpp"

namespace mbsc_test {

inline void bind_solves(mbsc::sym::Probe& p, const mbsc::model::Model& m, const mbsc::sym::Eom& eom) {
  for (const auto& step : eom.pre_steps) {
    if (const auto* d = std::get_if<mbsc::ir::Define>(&step)) {
      p.bind(d->sym, p.eval(mbsc::driver::finalize(m, eom, d->value)));
      continue;
    }
    const auto& s = std::get<mbsc::ir::Solve>(step);
    Eigen::MatrixXd A(s.n, s.n), B(s.n, s.k);
    for (int i = 0; i < s.n; ++i) {
      for (int j = 0; j < s.n; ++j) A(i, j) = p.eval(mbsc::driver::finalize(m, eom, s.A[i * s.n + j]));
      for (int j = 0; j < s.k; ++j) B(i, j) = p.eval(mbsc::driver::finalize(m, eom, s.B[i * s.k + j]));
    }
    Eigen::MatrixXd X = A.fullPivLu().solve(B);
    for (int i = 0; i < s.n; ++i)
      for (int j = 0; j < s.k; ++j) p.bind(s.X[i * s.k + j], X(i, j));
  }
}

}  // namespace mbsc_test
