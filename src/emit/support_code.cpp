// SPDX-License-Identifier: GPL-2.0-or-later
#include "support_code.hpp"

namespace mbsc::emit {

// Finiteness of a whole output at once: a double is inf or NaN exactly when its 11
// exponent bits are all ones. Testing the bits of every entry and branching once is
// cheaper than std::isfinite with a branch per entry (about 4 ns of a 130 ns rhs of the
// 4-link chain, bench/run_chain.sh).
const std::string& all_finite_code() {
  static const std::string code = R"cpp(namespace {

// True when no entry of v[0..n) is infinite or NaN.
MBSC_HOST_DEVICE bool all_finite(const double* v, int n) {
  bool special = false;
  for (int i = 0; i < n; ++i) {
    std::uint64_t bits;
    std::memcpy(&bits, v + i, sizeof bits);
    special |= (~bits & 0x7ff0000000000000u) == 0;
  }
  return !special;
}

}  // namespace
)cpp";
  return code;
}

// In-place Cholesky factorisation A = L L^T (lower triangle), then forward and back
// substitution on B. Only the lower triangle of A is read.
const std::string& chol_solve_code() {
  static const std::string code = R"cpp(namespace {

// Solves A X = B in place for symmetric positive definite A. A: n x n, row-major, its
// lower triangle replaced by L with A = L L^T. B: n x k, row-major, replaced by X.
// n and k are template arguments, so every call site gets loops of known length.
// Returns 1 when a pivot is not positive or below 1e-13 times the largest diagonal entry
// (A not positive definite to working precision); else 0.
template <int n, int k>
MBSC_HOST_DEVICE int chol_solve(double* A, double* B) {
  // The largest |diagonal entry|, NaN entries skipped (as std::fmax does, but a compare
  // the compiler keeps inline instead of a call into libm per entry).
  double dmax = 0.0;
  for (int i = 0; i < n; ++i) {
    const double v = std::fabs(A[i * n + i]);
    if (v > dmax) dmax = v;
  }
  const double tiny = 1e-13 * dmax;
  for (int j = 0; j < n; ++j) {
    double d = A[j * n + j];
    for (int m = 0; m < j; ++m) d -= A[j * n + m] * A[j * n + m];
    if (!(d > tiny)) return 1;
    const double ljj = std::sqrt(d);
    A[j * n + j] = ljj;
    for (int i = j + 1; i < n; ++i) {
      double s = A[i * n + j];
      for (int m = 0; m < j; ++m) s -= A[i * n + m] * A[j * n + m];
      A[i * n + j] = s / ljj;
    }
  }
  for (int c = 0; c < k; ++c) {
    // L y = b, then L^T x = y.
    for (int i = 0; i < n; ++i) {
      double s = B[i * k + c];
      for (int m = 0; m < i; ++m) s -= A[i * n + m] * B[m * k + c];
      B[i * k + c] = s / A[i * n + i];
    }
    for (int i = n - 1; i >= 0; --i) {
      double s = B[i * k + c];
      for (int m = i + 1; m < n; ++m) s -= A[m * n + i] * B[m * k + c];
      B[i * k + c] = s / A[i * n + i];
    }
  }
  return 0;
}

}  // namespace
)cpp";
  return code;
}

// Pivoted Cholesky of a positive semidefinite matrix of known rank, and the minimum-norm
// solve built on it (the multipliers of constraints redundant on the mechanism).
const std::string& psd_solve_code() {
  static const std::string code = R"cpp(namespace {

// Pivoted Cholesky of a symmetric positive semidefinite A (n x n, row-major, both
// triangles) of rank r < n: r pivots, the largest remaining diagonal entry first, rows
// and columns swapped as they are taken (perm[i]: the original index of pivot i). A's
// lower triangle then holds L (n x r) with P^T A P = L L^T. Returns the r-th pivot over
// the first: 0 when a pivot is not positive (the rank fell below r).
template <int n, int r>
MBSC_HOST_DEVICE double psd_factor(double* A, int* perm) {
  for (int i = 0; i < n; ++i) perm[i] = i;
  double first = 0.0;
  for (int j = 0; j < r; ++j) {
    int best = j;
    for (int i = j + 1; i < n; ++i)
      if (A[i * n + i] > A[best * n + best]) best = i;
    const double d = A[best * n + best];
    if (!(d > 0.0)) return 0.0;
    if (best != j) {
      for (int c = 0; c < n; ++c) {
        const double v = A[j * n + c];
        A[j * n + c] = A[best * n + c];
        A[best * n + c] = v;
      }
      for (int c = 0; c < n; ++c) {
        const double v = A[c * n + j];
        A[c * n + j] = A[c * n + best];
        A[c * n + best] = v;
      }
      const int pj = perm[j];
      perm[j] = perm[best];
      perm[best] = pj;
    }
    if (j == 0) first = d;
    const double ljj = std::sqrt(d);
    A[j * n + j] = ljj;
    for (int i = j + 1; i < n; ++i) A[i * n + j] /= ljj;
    for (int i = j + 1; i < n; ++i)
      for (int l = j + 1; l <= i; ++l) {
        A[i * n + l] -= A[i * n + j] * A[l * n + j];
        A[l * n + i] = A[i * n + l];
      }
  }
  const double last = A[(r - 1) * n + (r - 1)];
  return first > 0.0 ? last * last / first : 0.0;
}

// The minimum-norm solution of A X = B for A as psd_factor takes it (consistent B: on
// the mechanism). The basic solution (zero on the n - r pivots not taken) minus its part
// in the null space Z = P [-L1^-T L2^T; I] of A. B: n x k, replaced by X. Returns 1 when
// the rank fell below r (the r-th pivot below 1e-13 times the first), else 0.
template <int n, int k, int r>
MBSC_HOST_DEVICE int psd_min_norm_solve(double* A, double* B) {
  constexpr int d = n - r;
  int perm[n];
  if (!(psd_factor<n, r>(A, perm) > 1e-13)) return 1;
  // W = L1^-T L2^T (r x d): column c from L1^T w = (row r + c of L)^T.
  double W[r * d];
  for (int c = 0; c < d; ++c)
    for (int i = r - 1; i >= 0; --i) {
      double s = A[(r + c) * n + i];
      for (int m = i + 1; m < r; ++m) s -= A[m * n + i] * W[m * d + c];
      W[i * d + c] = s / A[i * n + i];
    }
  // G = Z^T Z = I + W^T W (d x d), factored by Cholesky in place.
  double G[d * d];
  for (int a = 0; a < d; ++a)
    for (int b = 0; b < d; ++b) {
      double s = a == b ? 1.0 : 0.0;
      for (int i = 0; i < r; ++i) s += W[i * d + a] * W[i * d + b];
      G[a * d + b] = s;
    }
  for (int j = 0; j < d; ++j) {
    double s = G[j * d + j];
    for (int m = 0; m < j; ++m) s -= G[j * d + m] * G[j * d + m];
    G[j * d + j] = std::sqrt(s);
    for (int i = j + 1; i < d; ++i) {
      double t = G[i * d + j];
      for (int m = 0; m < j; ++m) t -= G[i * d + m] * G[j * d + m];
      G[i * d + j] = t / G[j * d + j];
    }
  }
  for (int c = 0; c < k; ++c) {
    double y[n];
    for (int i = 0; i < r; ++i) {  // L1 L1^T y1 = (P^T B)_1, y2 = 0
      double s = B[perm[i] * k + c];
      for (int m = 0; m < i; ++m) s -= A[i * n + m] * y[m];
      y[i] = s / A[i * n + i];
    }
    for (int i = r - 1; i >= 0; --i) {
      double s = y[i];
      for (int m = i + 1; m < r; ++m) s -= A[m * n + i] * y[m];
      y[i] = s / A[i * n + i];
    }
    // s = G^-1 Z^T y with Z^T y = -W^T y1; then y -= Z s: y1 += W s, y2 = -s.
    double t[d];
    for (int a = 0; a < d; ++a) {
      double v = 0.0;
      for (int i = 0; i < r; ++i) v -= W[i * d + a] * y[i];
      t[a] = v;
    }
    for (int a = 0; a < d; ++a) {
      for (int m = 0; m < a; ++m) t[a] -= G[a * d + m] * t[m];
      t[a] /= G[a * d + a];
    }
    for (int a = d - 1; a >= 0; --a) {
      for (int m = a + 1; m < d; ++m) t[a] -= G[m * d + a] * t[m];
      t[a] /= G[a * d + a];
    }
    for (int i = 0; i < r; ++i)
      for (int a = 0; a < d; ++a) y[i] += W[i * d + a] * t[a];
    for (int a = 0; a < d; ++a) y[r + a] = -t[a];
    for (int i = 0; i < n; ++i) B[perm[i] * k + c] = y[i];
  }
  return 0;
}

// What `conditioning` reports for such a solve: the r-th pivot over the first (0 where
// the rank fell below r). A is destroyed.
template <int n, int r>
MBSC_HOST_DEVICE double psd_rcond(double* A) {
  int perm[n];
  return psd_factor<n, r>(A, perm);
}

}  // namespace
)cpp";
  return code;
}

// In-place LU factorisation with partial pivoting (Doolittle, row swaps applied to B too),
// then forward elimination on B during the factorisation and back substitution.
const std::string& lu_solve_code() {
  static const std::string code = R"cpp(namespace {

// Solves A X = B in place. A: n x n, row-major, destroyed. B: n x k, row-major, replaced by
// X (n and k are template arguments: loops of known length at every call site).
// Gaussian elimination with partial pivoting. Returns 1, leaving A and B unspecified,
// when a pivot's magnitude is below 1e-13 times the largest magnitude in A (or is not a
// number); else 0.
template <int n, int k>
MBSC_HOST_DEVICE int lu_solve(double* A, double* B) {
  // The largest |entry|, NaN entries skipped (as std::fmax does, inline).
  double amax = 0.0;
  for (int i = 0; i < n * n; ++i) {
    const double v = std::fabs(A[i]);
    if (v > amax) amax = v;
  }
  const double tiny = 1e-13 * amax;
  for (int c = 0; c < n; ++c) {
    // Pivot: the largest magnitude in column c on or below the diagonal.
    int piv = c;
    for (int r = c + 1; r < n; ++r) {
      if (std::fabs(A[r * n + c]) > std::fabs(A[piv * n + c])) piv = r;
    }
    const double pmag = std::fabs(A[piv * n + c]);
    if (!(pmag > 0.0) || pmag < tiny) return 1;
    if (piv != c) {
      for (int j = 0; j < n; ++j) {
        const double a = A[c * n + j];
        A[c * n + j] = A[piv * n + j];
        A[piv * n + j] = a;
      }
      for (int j = 0; j < k; ++j) {
        const double b = B[c * k + j];
        B[c * k + j] = B[piv * k + j];
        B[piv * k + j] = b;
      }
    }
    // Eliminate column c below the pivot, in A and in B.
    for (int r = c + 1; r < n; ++r) {
      const double f = A[r * n + c] / A[c * n + c];
      for (int j = c + 1; j < n; ++j) A[r * n + j] -= f * A[c * n + j];
      for (int j = 0; j < k; ++j) B[r * k + j] -= f * B[c * k + j];
    }
  }
  // Back substitution, one column of B at a time.
  for (int c = n - 1; c >= 0; --c) {
    for (int j = 0; j < k; ++j) {
      double s = B[c * k + j];
      for (int m = c + 1; m < n; ++m) s -= A[c * n + m] * B[m * k + j];
      B[c * k + j] = s / A[c * n + c];
    }
  }
  return 0;
}

}  // namespace
)cpp";
  return code;
}

// The 1x1 and 2x2 solves, written out: the same arithmetic and the same singularity
// test as lu_solve / chol_solve, without their loops over n (the loop-closure cores of
// planar linkages and one-DOF mass matrices are this small). One per function, so a
// file holds only those it calls.
const std::string& solve_1x1_code() {
  static const std::string code = R"cpp(namespace {

// A x = B for 1x1 A, k right-hand sides; 1 when A is zero or not a number.
MBSC_HOST_DEVICE int solve_1x1(int k, const double* A, double* B) {
  if (!(std::fabs(A[0]) > 0.0)) return 1;
  for (int j = 0; j < k; ++j) B[j] /= A[0];
  return 0;
}

}  // namespace
)cpp";
  return code;
}

const std::string& chol_1x1_code() {
  static const std::string code = R"cpp(namespace {

// A x = B for a 1x1 A that must be positive (a one-DOF mass matrix); 1 unless A > 0.
MBSC_HOST_DEVICE int chol_1x1(int k, const double* A, double* B) {
  if (!(A[0] > 0.0)) return 1;
  for (int j = 0; j < k; ++j) B[j] /= A[0];
  return 0;
}

}  // namespace
)cpp";
  return code;
}

const std::string& lu_solve_2x2_code() {
  static const std::string code = R"cpp(namespace {

// A X = B for 2x2 A (row-major), B 2 x k: Gaussian elimination with partial pivoting,
// as lu_solve does it. 1 when a pivot is below 1e-13 times the largest |A| entry. k is a
// template argument, so the loop over B's columns unrolls at every call site.
template <int k>
MBSC_HOST_DEVICE int lu_solve_2x2(const double* A, double* B) {
  double amax = 0.0;  // NaN entries skipped, as std::fmax would, without a call into libm
  for (int i = 0; i < 4; ++i) {
    const double v = std::fabs(A[i]);
    if (v > amax) amax = v;
  }
  const double tiny = 1e-13 * amax;
  const bool swap = std::fabs(A[2]) > std::fabs(A[0]);
  const double a = swap ? A[2] : A[0], b = swap ? A[3] : A[1];
  const double c = swap ? A[0] : A[2], d = swap ? A[1] : A[3];
  if (!(std::fabs(a) > 0.0) || std::fabs(a) < tiny) return 1;
  const double f = c / a;
  const double e = d - f * b;
  if (!(std::fabs(e) > 0.0) || std::fabs(e) < tiny) return 1;
  for (int j = 0; j < k; ++j) {
    const double r0 = swap ? B[k + j] : B[j], r1 = swap ? B[j] : B[k + j];
    const double x1 = (r1 - f * r0) / e;
    B[j] = (r0 - b * x1) / a;
    B[k + j] = x1;
  }
  return 0;
}

}  // namespace
)cpp";
  return code;
}

// Reciprocal 1-norm condition number of one solve an rhs makes, through lu_solve on the
// identity; with the gain columns of a dependent block and the Cholesky test of a mass matrix.
const std::string& rcond_code() {
  static const std::string code = R"cpp(namespace {

// How safely the rhs can make one of its solves, for `conditioning`: 1 / (|A|_1 |A^-1|_1)
// of the n x n row-major A (destroyed), divided by max(1, |A^-1 G|_1) where G (n x g,
// row-major; unused when g = 0) holds the coefficients of the independent rates that the
// solve turns into dependent rates, so a block that is small next to them (even a 1 x 1
// one) reports it. spd: A is the reduced mass matrix the rhs factors by Cholesky; 0 where
// that factorisation fails (the test of chol_solve). W: n x n workspace that receives
// A^-1. 0 when lu_solve finds A singular; 1 is perfectly conditioned; values near
// machine epsilon mean the solve is numerically singular.
template <int n, int g, bool spd>
MBSC_HOST_DEVICE double rcond_1norm(double* A, const double* G, double* W) {
  if (spd) {
    double dmax = 0.0;
    for (int i = 0; i < n; ++i) dmax = std::fmax(dmax, std::fabs(A[i * n + i]));
    for (int i = 0; i < n * n; ++i) W[i] = A[i];
    for (int j = 0; j < n; ++j) {
      double d = W[j * n + j];
      for (int m = 0; m < j; ++m) d -= W[j * n + m] * W[j * n + m];
      if (!(d > 1e-13 * dmax)) return 0.0;
      const double ljj = std::sqrt(d);
      W[j * n + j] = ljj;
      for (int i = j + 1; i < n; ++i) {
        double s = W[i * n + j];
        for (int m = 0; m < j; ++m) s -= W[i * n + m] * W[j * n + m];
        W[i * n + j] = s / ljj;
      }
    }
  }
  double norm_a = 0.0;
  for (int j = 0; j < n; ++j) {
    double col = 0.0;
    for (int i = 0; i < n; ++i) col += std::fabs(A[i * n + j]);
    norm_a = std::fmax(norm_a, col);
  }
  for (int i = 0; i < n * n; ++i) W[i] = 0.0;
  for (int i = 0; i < n; ++i) W[i * n + i] = 1.0;
  if (lu_solve<n, n>(A, W) != 0) return 0.0;
  double norm_inv = 0.0;
  for (int j = 0; j < n; ++j) {
    double col = 0.0;
    for (int i = 0; i < n; ++i) col += std::fabs(W[i * n + j]);
    norm_inv = std::fmax(norm_inv, col);
  }
  // |A^-1 G|_1: the largest column sum of the dependent rates per unit independent rate.
  double gain = 1.0;
  for (int j = 0; j < g; ++j) {
    double col = 0.0;
    for (int i = 0; i < n; ++i) {
      double s = 0.0;
      for (int m = 0; m < n; ++m) s += W[i * n + m] * G[m * g + j];
      col += std::fabs(s);
    }
    gain = std::fmax(gain, col);
  }
  const double r = 1.0 / (norm_a * norm_inv * gain);
  return r == r ? r : 0.0;
}

}  // namespace
)cpp";
  return code;
}

// In the spirit of Bison's skeleton exception: the output is free to use under any terms.
const std::string& generated_licence_text() {
  static const std::string text =
      "This file was generated by mbsc. mbsc is free software under the GNU General\n"
      "Public License, version 2 or (at your option) any later version, and this file\n"
      "is covered by that licence with the following special exception.\n"
      "\n"
      "As a special exception, you may use, modify, compile and distribute this file,\n"
      "alone or as part of any application or library, under terms of your choice,\n"
      "without the conditions of the GNU General Public License applying to it. The\n"
      "exception does not extend to a program that is itself a symbolic equation\n"
      "compiler using this file, or a modified version of it, as a pattern for the code\n"
      "it generates. If you distribute a modified version of mbsc itself, you may remove\n"
      "this exception from the files your version generates.\n";
  return text;
}

}  // namespace mbsc::emit
