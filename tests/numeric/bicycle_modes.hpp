// SPDX-License-Identifier: GPL-2.0-or-later
// The weave and capsize eigenvalues of a bicycle from its lean angle, sampled along a
// nonlinear run with a small perturbation (the Whipple bicycle tests, both models).
// After the castor mode (-12.7 to -16/s between 4 and 6 m/s) has died out, the lean
// angle is a sum of three exponentials: the weave pair and the capsize mode (the forward
// speed changes only at second order in the perturbation). Prony's method: a least-
// squares linear prediction s[k+3] = a0 s[k+2] + a1 s[k+1] + a2 s[k] over the samples;
// the roots z of z^3 - a0 z^2 - a1 z - a2 are exp(lambda dt).
#pragma once
#include <array>
#include <cmath>
#include <complex>
#include <vector>

namespace mbsc_test {

struct Modes {
  std::complex<double> weave;  // the one in the upper half plane
  double capsize = 0.0;
  int oscillating = 0;  // roots with |imaginary part| > 1/s: 2 when the fit found the weave pair
};

/// `s`: lean samples dt apart, from after the castor mode's decay. Samples 0.1 s apart
/// suit it: closer ones make the prediction's columns nearly parallel and the fit
/// sensitive to the integration error.
inline Modes modes_from_lean(const std::vector<double>& s, double dt) {
  // Normal equations of the 3-parameter fit (well conditioned enough at this size).
  double A[3][3] = {}, r[3] = {};
  for (std::size_t k = 0; k + 3 < s.size(); ++k) {
    const double row[3] = {s[k + 2], s[k + 1], s[k]};
    for (int i = 0; i < 3; ++i) {
      r[i] += row[i] * s[k + 3];
      for (int j = 0; j < 3; ++j) A[i][j] += row[i] * row[j];
    }
  }
  auto det3 = [](double M[3][3]) {
    return M[0][0] * (M[1][1] * M[2][2] - M[1][2] * M[2][1]) - M[0][1] * (M[1][0] * M[2][2] - M[1][2] * M[2][0]) +
           M[0][2] * (M[1][0] * M[2][1] - M[1][1] * M[2][0]);
  };
  const double D = det3(A);
  double a[3];
  for (int c = 0; c < 3; ++c) {  // Cramer
    double Mc[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) Mc[i][j] = j == c ? r[i] : A[i][j];
    a[c] = det3(Mc) / D;
  }
  // The cubic's roots by Durand-Kerner iteration.
  using C = std::complex<double>;
  std::array<C, 3> z{C(0.4, 0.9), C(0.9, 0.1), C(-0.5, -0.6)};
  auto p = [&](C x) { return x * x * x - a[0] * x * x - a[1] * x - a[2]; };
  for (int it = 0; it < 500; ++it)
    for (std::size_t i = 0; i < 3; ++i) {
      C den = 1.0;
      for (std::size_t j = 0; j < 3; ++j)
        if (j != i) den *= z[i] - z[j];
      z[i] -= p(z[i]) / den;
    }
  Modes m;
  for (const C& zi : z) {
    const C lambda = std::log(zi) / dt;
    if (std::fabs(lambda.imag()) > 1.0) {
      ++m.oscillating;
      if (lambda.imag() > 0) m.weave = lambda;
    } else {
      m.capsize = lambda.real();
    }
  }
  return m;
}

}  // namespace mbsc_test
