// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// Fixed C++ code pasted into generated sources (private to src/emit).
#include <string>

namespace mbsc::emit {

/// The anonymous-namespace `int lu_solve(int n, int k, double* A, double* B)`, emitted
/// only into sources that solve a linear system.
const std::string& lu_solve_code();

/// The anonymous-namespace `int chol_solve(int n, int k, double* A, double* B)` for
/// symmetric positive definite systems (reduced mass matrices).
const std::string& chol_solve_code();
/// psd_factor, psd_min_norm_solve, psd_rcond: a semidefinite matrix of known rank.
const std::string& psd_solve_code();

/// The anonymous-namespace `bool all_finite(const double* v, int n)` every function's
/// status check uses (one branch for the whole output, not one per entry).
const std::string& all_finite_code();

/// solve_1x1, chol_1x1, lu_solve_2x2: the smallest solves without loops over n.
const std::string& solve_1x1_code();
const std::string& chol_1x1_code();
const std::string& lu_solve_2x2_code();

/// rcond_1norm<n, g, spd>(A, G, W): reciprocal 1-norm condition number of one solve, with the
/// gain columns G of a dependent block and the Cholesky test of a mass matrix (needs lu_solve).
const std::string& rcond_code();

/// The licence exception of generated files, as lines without comment markers.
const std::string& generated_licence_text();

}  // namespace mbsc::emit
