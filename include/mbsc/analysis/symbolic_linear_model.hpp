// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// The linear model with some parameters left as symbols (`mbsc linearize --symbolic`;
/// docs/linearization.md, "Symbolic linear models"). The equations are those the runtime
/// solves in floating point (include/mbsc/runtime/linear_model.hpp): the reference rates
/// and multipliers from the dynamic equations and the acceleration-level invariants, then
/// the increments from their linearization, here solved by exact elimination in GiNaC
/// over the Taylor coefficients of driver::linear_parts_spec, every number an exact rational.
///
/// The choices a factorization makes (which constraint rows are independent, which
/// pivots) are taken from the values of the expressions at the nominal values of the
/// symbols, so the result holds where those pivots stay nonzero: around the nominal
/// values, as the floating-point model does at each point.
#include <ginac/ginac.h>

#include <string>
#include <vector>

namespace mbsc::analysis {

struct SymbolicLinearInput {
  /// linear_parts' outputs (driver::linear_parts_spec, its block order) and the symbols
  /// of its third argument w = (u, q1', lambda), in w's order.
  std::vector<GiNaC::ex> parts;
  std::vector<GiNaC::symbol> w;
  int nq = 0, nu = 0, nc = 0, np = 0, nin = 0;  // np: P's rows (position rows, then quaternion norms)
  /// The reference: every coordinate, speed, input, the time and every parameter not
  /// kept symbolic -> its value (exact rationals, or expressions of the kept symbols).
  GiNaC::exmap at;
  /// The kept symbols -> their nominal values (pivot choices and the closing check).
  GiNaC::exmap nominal;
  /// Other values of the symbols (each moved in turn): a term or an entry is dropped as
  /// rounding only where it is negligible at these too (a symbol whose nominal value is
  /// 0 makes its terms vanish there, not everywhere).
  std::vector<GiNaC::exmap> elsewhere;
  /// The components of the state written (indices into the full layout q0, q1); the
  /// others follow from the linearized invariants.
  std::vector<int> sel;
  /// Coordinates (indices < nq) of the second-order form M q'' + C q' + K q = T, or none.
  std::vector<int> coords;
};

struct SymbolicLinearModel {
  GiNaC::matrix A, B;  // sel x sel, sel x nin: d/dt dx_sel = A dx_sel + B du
  /// sel x nq: the response to a generalized force on each coordinate (the second-order
  /// form's M is read from it, as runtime::LinearModel::Bq).
  GiNaC::matrix Bq;
  /// Products of the factorization's pivots at the nominal values, smallest first
  /// relative: how far the nominal point is from where the symbolic result stops holding.
  double smallest_pivot = 0.0;
  /// With `coords`: the second-order form in those coordinates, read off as
  /// run/second_order_form.hpp does (state (q, q', the rest), M from the response to
  /// generalized forces), and how strongly the rest of the state enters its q'' rows
  /// (at the nominal values, relative to K and C).
  GiNaC::matrix M, C, K;
  double coupling = 0.0;
};

/// False with `error` set when an elimination meets no nonzero pivot at the nominal values
/// (the mass matrix singular on the constrained motions, or `sel` not a minimal state) or
/// when redundant rows disagree.
bool symbolic_linear_model(const SymbolicLinearInput& in, SymbolicLinearModel& out, std::string& error);

/// X with J X = R for J with at least as many rows as columns (rows that depend on the
/// others at the nominal values dropped: they must agree), by the elimination above.
bool solve_overdetermined(const GiNaC::matrix& J, const GiNaC::matrix& R, const GiNaC::exmap& nominal, GiNaC::matrix& X,
                          std::string& error);

/// The exact rational of the shortest decimal within four units in the last place of v
/// (0.0603 -> 603/10000; 0.49999999999999994 -> 1/2).
GiNaC::ex exact_number(double v);

/// Every subexpression without symbols (sin(3/10), Pi, sqrt(2)) replaced by the exact
/// rational of its double value (a function's value below 1e-14: zero, as cos(-pi/2) in doubles); numbers
/// stay rationals, so elimination is exact.
GiNaC::ex fold_constants(const GiNaC::ex& e);

/// The value of e at `nominal` (every symbol of e given there), as a double; NaN when e
/// does not evaluate to a real number.
double nominal_value(const GiNaC::ex& e, const GiNaC::exmap& nominal);

/// e brought to one fraction, each numerator and denominator term dropped whose value is
/// below 1e-12 of that polynomial's largest term at every one of `points` (the remains of
/// cancellations that were exact only in real arithmetic, such as sin^2 + cos^2 - 1).
GiNaC::ex tidy_entry(const GiNaC::ex& e, const std::vector<GiNaC::exmap>& points);

}  // namespace mbsc::analysis
