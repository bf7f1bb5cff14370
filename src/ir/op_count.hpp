// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// Operation-count helpers (private to src/ir).
#include "mbsc/ir/program.hpp"

namespace mbsc::ir {

/// Multiply-adds of one in-place LU solve with partial pivoting: n^3/3 + n^2 k, rounded.
long lu_solve_flops(int n, int k);
long chol_solve_flops(int n, int k);

/// Field-wise sum.
OpCount& operator+=(OpCount& a, const OpCount& b);

}  // namespace mbsc::ir
