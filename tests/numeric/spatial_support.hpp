// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// Helpers of the spatial joint tests: rotations about coordinate axes and their products,
// the quaternion of a rotation and the rotation of a quaternion, and a generated model's
// total energy.
#include <catch2/catch.hpp>
#include <array>
#include <cmath>
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

/// Rotation by angle q about coordinate axis i (0 = x, 1 = y, 2 = z).
inline Mat3 turn(int i, double q) {
  const double c = std::cos(q), s = std::sin(q);
  Mat3 R{};
  const int j = (i + 1) % 3, k = (i + 2) % 3;
  R[i][i] = 1;
  R[j][j] = c;
  R[k][k] = c;
  R[k][j] = s;
  R[j][k] = -s;
  return R;
}

/// The unit quaternion (scalar first) of a rotation matrix (the largest pivot first).
inline std::array<double, 4> quaternion(const Mat3& R) {
  const double tr = R[0][0] + R[1][1] + R[2][2];
  std::array<double, 4> e{};
  if (tr > 0) {
    const double s = 2 * std::sqrt(1 + tr);
    e = {s / 4, (R[2][1] - R[1][2]) / s, (R[0][2] - R[2][0]) / s, (R[1][0] - R[0][1]) / s};
  } else if (R[0][0] > R[1][1] && R[0][0] > R[2][2]) {
    const double s = 2 * std::sqrt(1 + R[0][0] - R[1][1] - R[2][2]);
    e = {(R[2][1] - R[1][2]) / s, s / 4, (R[0][1] + R[1][0]) / s, (R[0][2] + R[2][0]) / s};
  } else if (R[1][1] > R[2][2]) {
    const double s = 2 * std::sqrt(1 + R[1][1] - R[0][0] - R[2][2]);
    e = {(R[0][2] - R[2][0]) / s, (R[0][1] + R[1][0]) / s, s / 4, (R[1][2] + R[2][1]) / s};
  } else {
    const double s = 2 * std::sqrt(1 + R[2][2] - R[0][0] - R[1][1]);
    e = {(R[1][0] - R[0][1]) / s, (R[0][2] + R[2][0]) / s, (R[1][2] + R[2][1]) / s, s / 4};
  }
  return e;
}

/// The rotation of a unit quaternion e (scalar first), written out from the half-angle
/// form cos(a/2), sin(a/2) n: R = (e0^2 - |ev|^2) I + 2 ev evᵀ + 2 e0 [ev]x.
inline Mat3 rotation_of(const std::array<double, 4>& e) {
  const double ev[3] = {e[1], e[2], e[3]};
  const double d = e[0] * e[0] - (ev[0] * ev[0] + ev[1] * ev[1] + ev[2] * ev[2]);
  Mat3 R{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) R[i][j] = (i == j ? d : 0.0) + 2 * ev[i] * ev[j];
  R[0][1] -= 2 * e[0] * ev[2];
  R[1][0] += 2 * e[0] * ev[2];
  R[0][2] += 2 * e[0] * ev[1];
  R[2][0] -= 2 * e[0] * ev[1];
  R[1][2] -= 2 * e[0] * ev[0];
  R[2][1] += 2 * e[0] * ev[0];
  return R;
}

/// The generated energy function's total (kinetic + potential) at state x, no inputs.
using EnergyFunction = int (*)(double, const double*, const double*, const double*, double*);
inline double total_energy(EnergyFunction energy, const std::vector<double>& x, const double* p) {
  std::array<double, 3> e{};
  REQUIRE(energy(0.0, x.data(), nullptr, p, e.data()) == 0);
  return e[2];
}

}  // namespace mbsc_test
