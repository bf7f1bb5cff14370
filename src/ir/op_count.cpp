// SPDX-License-Identifier: GPL-2.0-or-later
#include "op_count.hpp"

#include <cmath>

namespace mbsc::ir {

// Factorisation ~n^3/3 multiply-adds, forward and back substitution n^2 per right-hand side.
long lu_solve_flops(int n, int k) {
  const double nn = static_cast<double>(n);
  return std::lround(nn * nn * nn / 3.0 + nn * nn * static_cast<double>(k));
}

// Cholesky: ~n^3/6 multiply-adds, then n^2 per right-hand side (forward and back).
long chol_solve_flops(int n, int k) {
  const double nn = static_cast<double>(n);
  return std::lround(nn * nn * nn / 6.0 + nn * nn * static_cast<double>(k));
}

OpCount& operator+=(OpCount& a, const OpCount& b) {
  a.adds += b.adds;
  a.muls += b.muls;
  a.divs += b.divs;
  a.calls += b.calls;
  a.solve_flops += b.solve_flops;
  return a;
}

}  // namespace mbsc::ir
