// SPDX-License-Identifier: GPL-2.0-or-later WITH mbsc-runtime-exception
// (see LICENSE: this header may be included in applications under any terms)
#pragma once
/// The Hermite polynomial of a vector function through k nodes where its values and
/// rates are known (degree 2k - 1), in Newton's form over the doubled nodes
/// t0, t0, t1, t1, ...: the divided difference over a doubled node is the rate there.
/// singular_crossing.hpp evaluates it past its last node (an extrapolation) to carry a
/// run across an instant where the rhs cannot be evaluated accurately.
///
///   HermitePolynomial h({t0, t1, t2}, {x0, x1, x2}, {f0, f1, f2});
///   h.evaluate(t, out);   // out = p(t), p(ti) = xi, p'(ti) = fi
#include <cstddef>
#include <vector>

namespace mbsc::runtime {

class HermitePolynomial {
 public:
  HermitePolynomial() = default;  // no nodes: evaluates to an empty vector
  /// t: distinct node times; x, f: the values and rates there (one vector of n entries per node).
  HermitePolynomial(const std::vector<double>& t, const std::vector<std::vector<double>>& x,
                    const std::vector<std::vector<double>>& f) {
    const std::size_t k = t.size(), m = 2 * k;
    if (k == 0) return;
    n_ = x[0].size();
    z_.resize(m);
    for (std::size_t i = 0; i < m; ++i) z_[i] = t[i / 2];
    // Column j of the divided-difference table, kept in place: after pass j, d[i] holds
    // f[z_{i-j}, ..., z_i] for i >= j; d[j] is then the j-th Newton coefficient.
    coef_.assign(m, std::vector<double>(n_));
    std::vector<std::vector<double>> d(m, std::vector<double>(n_));
    for (std::size_t i = 0; i < m; ++i) d[i] = x[i / 2];
    coef_[0] = d[0];
    for (std::size_t j = 1; j < m; ++j) {
      for (std::size_t i = m - 1; i >= j; --i) {
        const double dz = z_[i] - z_[i - j];
        for (std::size_t c = 0; c < n_; ++c)
          d[i][c] = dz == 0.0 ? f[i / 2][c] : (d[i][c] - d[i - 1][c]) / dz;  // dz = 0 only for j = 1
      }
      coef_[j] = d[j];
    }
  }

  /// out = p(tau): Horner's scheme on the Newton form.
  void evaluate(double tau, std::vector<double>& out) const {
    const std::size_t m = z_.size();
    out.assign(n_, 0.0);
    if (m == 0) return;
    out = coef_[m - 1];
    for (std::size_t j = m - 1; j-- > 0;)
      for (std::size_t c = 0; c < n_; ++c) out[c] = out[c] * (tau - z_[j]) + coef_[j][c];
  }

 private:
  std::size_t n_ = 0;
  std::vector<double> z_;                  // the doubled nodes
  std::vector<std::vector<double>> coef_;  // Newton coefficients, one vector each
};

}  // namespace mbsc::runtime
