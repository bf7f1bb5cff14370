// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// What the symbolic core hands to the back end: for each emitted function, a list of
/// steps (symbol definitions and numeric linear solves) and the expressions of its
/// outputs. The back end lowers this to a Program (CSE, trig hoisting, dead code
/// dropped) and prints it; it never simplifies the mathematics.
#include <ginac/ginac.h>

#include <optional>
#include <string>
#include <variant>
#include <vector>

namespace mbsc::ir {

/// Where an input symbol's value comes from in the emitted C++ ("x[3]", "p[0]", "t").
struct Binding {
  GiNaC::symbol sym;
  std::string cpp;
  /// The same value in every call of a function (a parameter, p[k]): products group
  /// their invariant factors into one shared node (m*l^2 computed once).
  bool invariant = false;
};

/// sym := value. The value may use bindings and symbols defined by earlier steps.
/// By default the value is substituted into its readers (and CSE shares it); a `named`
/// Define is kept as a variable that readers refer to, so its value never merges into
/// theirs (used for recurrences, where each value reads the previous one).
struct Define {
  GiNaC::symbol sym;
  GiNaC::ex value;
  bool named = false;
};

/// X = A^-1 B, solved numerically in the generated code (LU with partial pivoting).
/// A: n x n row-major, B: n x k row-major, X: n x k row-major result symbols.
/// The emitted function returns status 1 when A is singular to working precision.
struct Solve {
  std::string label;  // what is solved, for comments ("node R: dependent block B*")
  int n = 0;
  int k = 0;
  std::vector<GiNaC::ex> A;
  std::vector<GiNaC::ex> B;
  std::vector<GiNaC::symbol> X;
  /// A is symmetric positive definite (a reduced mass matrix): the generated code uses a
  /// Cholesky factorisation (n^3/6 instead of n^3/3) and returns status 1 when A is not
  /// positive definite to working precision.
  bool spd = false;
  /// With `spd`: A is only positive semidefinite, of this rank (0: full). The generated
  /// code takes the minimum-norm solution (psd_min_norm_solve): the multipliers of
  /// constraint rows redundant on the mechanism, and returns status 1 where the rank
  /// falls below it.
  int rank = 0;
  /// Not a solve: X[0] := the reciprocal 1-norm condition number of A,
  /// 1 / (|A|_1 |A^-1|_1), divided by max(1, |A^-1 B|_1) when B is given (n x k: the
  /// coefficients of the independent rates, so that a 1x1 block that is small next to
  /// them reports it), or 0 when A is singular to working precision (with `spd`: when
  /// the Cholesky factorisation the solve uses fails). What the generated `conditioning`
  /// functions report for each solve the rhs makes.
  bool condition = false;
  /// Whether the generated `conditioning` function reports this block.
  bool reported = true;
  /// The first `gains` columns of B are the coefficients of the independent rates (a
  /// dependent block B* solved for the complement): its conditioning counts them too.
  int gains = 0;
  /// `conditioning` reports its measure to this power. A constraint pivot of a loop
  /// eliminated speeds first (a block of A My^-1 A^T) has a measure that falls like the
  /// cube of the distance to a rank loss of the constraints (rcond like the square, the
  /// gain growing like its inverse), where the dense forms it replaces fall like the
  /// distance (the complement's dependent blocks: power 1/3) or its square (the
  /// multipliers' Schur complement: power 2/3); so thresholds on the conditioning
  /// (runtime/branch_continuation.hpp) mean the same whichever solver was chosen.
  GiNaC::numeric report_power = 1;
};

using Step = std::variant<Define, Solve>;

/// A dense symmetric output formed in the generated code as M = C^T My C from the
/// nonzeros of its sparse factors (a reduced mass matrix of a long chain: N^2 entries of
/// O(N) terms each, where C and My hold O(N^2) and O(N) short entries). The function's
/// `outputs` are then the distinct values of those nonzeros (into a local array); each
/// nonzero names its value by index, and a loop over the nonzeros forms OUT.
struct CongruenceProduct {
  int ny = 0;  // rows of C (and of My)
  int nd = 0;  // columns of C: OUT is nd x nd, row-major
  std::vector<int> c_row_ptr, c_col, c_value;  // C in compressed rows; c_value indexes `outputs`
  std::vector<int> my_row, my_col, my_value;   // My's nonzeros (both triangles), my_value indexes `outputs`
};

/// One emitted function:
///   int NAME(double t, const double* x, const double* u, const double* p, double* OUT)
/// OUT[i] = outputs[i] (row-major for matrices). Returns 0, 1 (singular solve) or
/// 2 (a non-finite output).
struct FunctionSpec {
  std::string name;       // "rhs"
  std::string doc;        // one-line description for the header ("state derivative xdot = f(t, x, u, p)")
  std::string out_name;   // "xdot"
  std::string out_shape;  // "kNx" or "kNdof*kNdof" (text for the header comment)
  std::vector<Step> steps;
  std::vector<GiNaC::ex> outputs;
  /// The name of the third pointer argument: "u" (the inputs), or "zdot" for
  /// inverse_dynamics (the independent accelerations, kNdof values).
  std::string third_arg = "u";
  /// Where the third argument is neither u nor zdot (linear_parts' w): the symbols it
  /// binds, replacing the inputs' u[k] bindings.
  std::vector<Binding> third_bindings{};
  /// When set, the function cannot be computed for this model: it is emitted returning 4
  /// with NaN outputs, and this sentence in its documentation.
  std::string undefined_reason{};
  /// When set, OUT is formed from the outputs by this product (CongruenceProduct).
  std::optional<CongruenceProduct> congruence{};
};

}  // namespace mbsc::ir
