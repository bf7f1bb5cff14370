// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// Helpers of the spatial joint tests: 3x3 rotation products and a generated model's total
// energy.
#include <catch2/catch.hpp>
#include <array>
#include <vector>

namespace mbsc_test {

using Mat3 = std::array<std::array<double, 3>, 3>;

inline Mat3 product(const Mat3& a, const Mat3& b) {
  Mat3 r{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) r[i][j] += a[i][k] * b[k][j];
  return r;
}

/// The generated energy function's total (kinetic + potential) at state x, no inputs.
using EnergyFunction = int (*)(double, const double*, const double*, const double*, double*);
inline double total_energy(EnergyFunction energy, const std::vector<double>& x, const double* p) {
  std::array<double, 3> e{};
  REQUIRE(energy(0.0, x.data(), nullptr, p, e.data()) == 0);
  return e[2];
}

}  // namespace mbsc_test
