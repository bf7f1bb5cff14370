// SPDX-License-Identifier: GPL-2.0-or-later WITH mbsc-runtime-exception
// (see LICENSE: this header may be included in applications under any terms)
#pragma once
/// Classical fixed-step Runge-Kutta (RK4) over a generated `rhs`. Header-only; used by
/// the example app and the tests. `f(t, x, xdot)` returns 0 on success, otherwise the
/// status is passed back and the state is left at the last good step.
#include <cstddef>
#include <vector>

namespace mbsc::runtime {

template <class Rhs>
int rk4_step(Rhs&& f, double t, double h, std::vector<double>& x) {
  const std::size_t n = x.size();
  std::vector<double> k1(n), k2(n), k3(n), k4(n), tmp(n);
  int s = f(t, x.data(), k1.data());
  if (s != 0) return s;
  for (std::size_t i = 0; i < n; ++i) tmp[i] = x[i] + 0.5 * h * k1[i];
  if ((s = f(t + 0.5 * h, tmp.data(), k2.data())) != 0) return s;
  for (std::size_t i = 0; i < n; ++i) tmp[i] = x[i] + 0.5 * h * k2[i];
  if ((s = f(t + 0.5 * h, tmp.data(), k3.data())) != 0) return s;
  for (std::size_t i = 0; i < n; ++i) tmp[i] = x[i] + h * k3[i];
  if ((s = f(t + h, tmp.data(), k4.data())) != 0) return s;
  for (std::size_t i = 0; i < n; ++i) x[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
  return 0;
}

/// Integrates from t0 to t1 in `steps` equal steps; calls `observe(t, x)` after each.
template <class Rhs, class Observer>
int rk4_integrate(Rhs&& f, double t0, double t1, int steps, std::vector<double>& x, Observer&& observe) {
  const double h = (t1 - t0) / steps;
  for (int k = 0; k < steps; ++k) {
    const double t = t0 + k * h;
    int s = rk4_step(f, t, h, x);
    if (s != 0) return s;
    observe(t + h, x);
  }
  return 0;
}

}  // namespace mbsc::runtime
