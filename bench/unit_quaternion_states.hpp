// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// For the bench drivers' random states: every unit quaternion of a generated model's state
// (its kQuaternionIndices, four indices each) divided by its norm. Off |e| = 1 the k-th
// link of a chain of quaternion joints is scaled by a product of k norms, far from any
// state the model is run at.
#include <cmath>
#include <cstddef>
#include <vector>

inline void normalize_unit_quaternions(std::vector<double>& x, const int* indices, int count) {
  for (int q = 0; q < count; ++q) {
    double n2 = 0.0;
    for (int k = 0; k < 4; ++k) n2 += x[static_cast<std::size_t>(indices[4 * q + k])] * x[static_cast<std::size_t>(indices[4 * q + k])];
    for (int k = 0; k < 4; ++k) x[static_cast<std::size_t>(indices[4 * q + k])] /= std::sqrt(n2);
  }
}
