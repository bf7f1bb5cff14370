// SPDX-License-Identifier: GPL-2.0-or-later WITH mbsc-runtime-exception
// (see LICENSE: this file may be copied into applications under any terms)
#pragma once
// The ensemble both versions of the app integrate (main.cpp on CPU threads, main.cu on a
// GPU): N double pendulums (models/double_pendulum.mbs, generated with --state minimal,
// x = th1, th2, w1, w2) released from rest, trajectory i with its own first angle and
// second mass, in struct-of-arrays layout (value k of pendulum i at [k * N + i]).
#include <cmath>
#include <cstdio>
#include <vector>

#include "dp/dp.hpp"

namespace ensemble {

namespace dp = mbsc_gen::dp;

constexpr double kTEnd = 2.0;  // s

struct Ensemble {
  int n = 0;
  std::vector<double> x, p;  // kNx x n and kNp x n
};

inline Ensemble make(int n) {
  Ensemble e;
  e.n = n;
  e.x.assign(static_cast<std::size_t>(dp::kNx) * n, 0.0);
  e.p.assign(static_cast<std::size_t>(dp::kNp) * n, 0.0);
  for (int i = 0; i < n; ++i) {
    const double s = n > 1 ? static_cast<double>(i) / (n - 1) : 0.0;
    for (int k = 0; k < dp::kNp; ++k) e.p[static_cast<std::size_t>(k) * n + i] = dp::kParamDefaults[k];
    e.p[static_cast<std::size_t>(1) * n + i] = 0.4 + 0.2 * s;  // m2
    e.x[static_cast<std::size_t>(0) * n + i] = 1.0 + 1.0 * s;  // th1
    e.x[static_cast<std::size_t>(1) * n + i] = 2.5;            // th2
  }
  return e;
}

/// Column i of an SoA array.
inline std::vector<double> column(const std::vector<double>& a, int rows, int n, int i) {
  std::vector<double> v(static_cast<std::size_t>(rows));
  for (int k = 0; k < rows; ++k) v[static_cast<std::size_t>(k)] = a[static_cast<std::size_t>(k) * n + i];
  return v;
}

/// The total energy of each pendulum.
inline std::vector<double> energies(const Ensemble& e) {
  std::vector<double> out(static_cast<std::size_t>(e.n));
  for (int i = 0; i < e.n; ++i) {
    const std::vector<double> x = column(e.x, dp::kNx, e.n, i), p = column(e.p, dp::kNp, e.n, i);
    double E[3];
    dp::energy(0.0, x.data(), nullptr, p.data(), E);
    out[static_cast<std::size_t>(i)] = E[2];
  }
  return out;
}

/// The largest relative change of the total energy over the ensemble, from e0 (n values).
inline double energy_drift(const Ensemble& e, const std::vector<double>& e0) {
  const std::vector<double> now = energies(e);
  double worst = 0.0;
  for (std::size_t i = 0; i < now.size(); ++i)
    worst = std::fmax(worst, std::fabs(now[i] - e0[i]) / std::fmax(1.0, std::fabs(e0[i])));
  return worst;
}

}  // namespace ensemble
