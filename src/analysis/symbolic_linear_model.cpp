// SPDX-License-Identifier: GPL-2.0-or-later
// The linear model by exact elimination over the Taylor coefficients, some parameters left
// as symbols (include/mbsc/analysis/symbolic_linear_model.hpp). The story follows
// runtime/linear_model.hpp: reference rates and multipliers, then the increments; where
// the runtime uses an orthonormal null space and minimum-norm solves, this uses the
// equivalent bordered (KKT) systems on the independent constraint rows, which give the
// same rates and increments (the projected equations N^T (...) = 0 hold exactly when the
// residual lies in the range of A_c^T), and the minimum-norm multipliers in the range of A_c.
#include "mbsc/analysis/symbolic_linear_model.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

#include "mbsc/diag/activity.hpp"

namespace mbsc::analysis {

namespace {

using GiNaC::ex;
using GiNaC::matrix;

bool has_symbol(const ex& e) {
  if (GiNaC::is_a<GiNaC::symbol>(e)) return true;
  for (std::size_t i = 0; i < e.nops(); ++i)
    if (has_symbol(e.op(i))) return true;
  return false;
}

// Values of a block of expressions at the nominal point.
Eigen::MatrixXd values(const matrix& M, const GiNaC::exmap& nominal) {
  Eigen::MatrixXd V(M.rows(), M.cols());
  for (unsigned i = 0; i < M.rows(); ++i)
    for (unsigned j = 0; j < M.cols(); ++j) V(i, j) = nominal_value(M(i, j), nominal);
  return V;
}

// The rows of M (r x c) a column-pivoted QR of M^T at the nominal point takes as
// independent, in their order in M.
std::vector<unsigned> independent_rows(const matrix& M, const GiNaC::exmap& nominal) {
  if (M.rows() == 0 || M.cols() == 0) return {};
  const Eigen::MatrixXd V = values(M, nominal);
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(V.transpose());
  qr.setThreshold(1e-10);
  std::vector<unsigned> rows;
  for (Eigen::Index k = 0; k < qr.rank(); ++k) rows.push_back(static_cast<unsigned>(qr.colsPermutation().indices()(k)));
  std::sort(rows.begin(), rows.end());
  return rows;
}

// X with K X = R for square K, by Gauss-Jordan elimination: in each column the pivot is
// the row whose entry is largest at the nominal point; entries stay normalized fractions.
bool solve_square(matrix K, matrix R, const GiNaC::exmap& nominal, matrix& X, double& smallest, std::string& error) {
  const unsigned n = K.rows(), c = R.cols();
  double scale = 0.0;
  for (unsigned i = 0; i < n; ++i)
    for (unsigned j = 0; j < n; ++j) scale = std::max(scale, std::fabs(nominal_value(K(i, j), nominal)));
  for (unsigned j = 0; j < n; ++j) {
    checkpoint("linearizing", "the symbolic elimination", SourcePos{}, j, n);
    unsigned p = j;
    double best = -1.0;
    for (unsigned i = j; i < n; ++i) {
      if (K(i, j).is_zero()) continue;
      const double v = std::fabs(nominal_value(K(i, j), nominal));
      if (v > best) best = v, p = i;
    }
    if (!(best > 1e-12 * scale)) {
      error = "the linearized equations are singular at the nominal values of the symbols";
      return false;
    }
    smallest = std::min(smallest, best / scale);
    if (p != j) {
      for (unsigned k = 0; k < n; ++k) std::swap(K(p, k), K(j, k));
      for (unsigned k = 0; k < c; ++k) std::swap(R(p, k), R(j, k));
    }
    const ex pivot = K(j, j);
    for (unsigned i = 0; i < n; ++i) {
      if (i == j || K(i, j).is_zero()) continue;
      const ex f = GiNaC::normal(K(i, j) / pivot);
      for (unsigned k = j; k < n; ++k)
        if (!K(j, k).is_zero()) K(i, k) = GiNaC::normal(K(i, k) - f * K(j, k));
      for (unsigned k = 0; k < c; ++k)
        if (!R(j, k).is_zero()) R(i, k) = GiNaC::normal(R(i, k) - f * R(j, k));
    }
  }
  X = matrix(n, c);
  for (unsigned i = 0; i < n; ++i)
    for (unsigned k = 0; k < c; ++k) X(i, k) = R(i, k).is_zero() ? ex(0) : GiNaC::normal(R(i, k) / K(i, i));
  return true;
}

// The rows `rows` of M.
matrix rows_of(const matrix& M, const std::vector<unsigned>& rows) {
  matrix out(static_cast<unsigned>(rows.size()), M.cols());
  for (unsigned i = 0; i < rows.size(); ++i)
    for (unsigned j = 0; j < M.cols(); ++j) out(i, j) = M(rows[i], j);
  return out;
}

matrix times(const matrix& X, const matrix& Y) {
  matrix Z(X.rows(), Y.cols());
  for (unsigned i = 0; i < X.rows(); ++i)
    for (unsigned j = 0; j < Y.cols(); ++j) {
      ex s = 0;
      for (unsigned k = 0; k < X.cols(); ++k)
        if (!X(i, k).is_zero() && !Y(k, j).is_zero()) s += X(i, k) * Y(k, j);
      Z(i, j) = GiNaC::normal(s);
    }
  return Z;
}

// Entries below 1e-12 of the largest in their row and in their column at the nominal
// values are the remains of a reference known to rounding (a generic angle's sine): zero.
void drop_rounding(matrix& M, const std::vector<GiNaC::exmap>& points) {
  if (M.rows() == 0 || M.cols() == 0) return;
  std::vector<Eigen::MatrixXd> V;
  for (const auto& at : points) V.push_back(values(M, at).cwiseAbs());
  for (unsigned i = 0; i < M.rows(); ++i)
    for (unsigned j = 0; j < M.cols(); ++j) {
      bool negligible = true;
      for (const auto& v : V) negligible = negligible && v(i, j) < 1e-12 * std::max(v.row(i).maxCoeff(), v.col(j).maxCoeff());
      if (negligible) M(i, j) = 0;
    }
}

// M q'' + C q' + K q = T in the coordinates in.coords: the state changed to
// xi = (q, q', completing components) = L z, z the written state (x = T z), so that
// xi' = L A L^-1 xi; its q' rows give -M^-1 K and -M^-1 C, and L Bq's give M^-1.
bool second_order(const SymbolicLinearInput& in, const std::vector<GiNaC::exmap>& points, const matrix& T, const matrix& qT,
                  SymbolicLinearModel& out, std::string& error) {
  const unsigned ns = static_cast<unsigned>(in.sel.size()), k = static_cast<unsigned>(in.coords.size());
  std::vector<std::vector<ex>> rows;
  for (int c : in.coords) {
    rows.emplace_back();
    for (unsigned j = 0; j < ns; ++j) rows.back().push_back(T(static_cast<unsigned>(c), j));
  }
  for (int c : in.coords) {
    rows.emplace_back();
    for (unsigned j = 0; j < ns; ++j) rows.back().push_back(qT(static_cast<unsigned>(c), j));
  }
  auto rank_of = [&]() {
    Eigen::MatrixXd V(static_cast<Eigen::Index>(rows.size()), ns);
    for (std::size_t i = 0; i < rows.size(); ++i)
      for (unsigned j = 0; j < ns; ++j) V(static_cast<Eigen::Index>(i), j) = nominal_value(rows[i][j], in.nominal);
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(V);
    qr.setThreshold(1e-9);
    return static_cast<std::size_t>(qr.rank());
  };
  if (rank_of() < 2 * k) {
    error = "--second-order: the coordinates and their rates are not independent on the motions the linearized constraints "
            "allow";
    return false;
  }
  // Completed by the full layout's components in layout order (x_i = T(i, :) z), as
  // run/second_order_form.cpp does: the same "rest" held fixed, the same M, C, K.
  for (unsigned i = 0; i < T.rows() && rows.size() < ns; ++i) {
    rows.emplace_back();
    for (unsigned j = 0; j < ns; ++j) rows.back().push_back(T(i, j));
    if (rank_of() < rows.size()) rows.pop_back();
  }
  if (rows.size() != ns) {
    error = "--second-order: cannot complete the coordinates to a state of the linear model";
    return false;
  }
  matrix L(ns, ns), I(ns, ns);
  for (unsigned i = 0; i < ns; ++i) {
    I(i, i) = 1;
    for (unsigned j = 0; j < ns; ++j) L(i, j) = rows[i][j];
  }
  matrix Linv;
  if (!solve_square(L, I, in.nominal, Linv, out.smallest_pivot, error)) return false;
  matrix Lrates(k, ns), Bc(ns, k);
  for (unsigned i = 0; i < k; ++i)
    for (unsigned j = 0; j < ns; ++j) Lrates(i, j) = L(k + i, j);
  for (unsigned i = 0; i < ns; ++i)
    for (unsigned j = 0; j < k; ++j) Bc(i, j) = out.Bq(i, static_cast<unsigned>(in.coords[j]));
  const matrix Axi = times(times(Lrates, out.A), Linv);  // the q'' rows of L A L^-1
  const matrix Minv = times(Lrates, Bc);
  matrix eye(k, k);
  for (unsigned i = 0; i < k; ++i) eye(i, i) = 1;
  matrix M;
  if (!solve_square(Minv, eye, in.nominal, M, out.smallest_pivot, error)) {
    error = "--second-order: generalized forces on these coordinates do not determine their accelerations (M is singular)";
    return false;
  }
  matrix Aq(k, k), Av(k, k), Ar(k, ns - 2 * k);
  for (unsigned i = 0; i < k; ++i) {
    for (unsigned j = 0; j < k; ++j) Aq(i, j) = Axi(i, j), Av(i, j) = Axi(i, k + j);
    for (unsigned j = 2 * k; j < ns; ++j) Ar(i, j - 2 * k) = Axi(i, j);
  }
  const matrix K = times(M, Aq), C = times(M, Av), rest = times(M, Ar);
  out.M = matrix(k, k), out.C = matrix(k, k), out.K = matrix(k, k);
  double size = 1e-300, coupled = 0.0;
  for (unsigned i = 0; i < k; ++i) {
    for (unsigned j = 0; j < k; ++j) {
      out.M(i, j) = tidy_entry(M(i, j), points);
      out.K(i, j) = tidy_entry(-K(i, j), points);
      out.C(i, j) = tidy_entry(-C(i, j), points);
      size = std::max({size, std::fabs(nominal_value(out.K(i, j), in.nominal)), std::fabs(nominal_value(out.C(i, j), in.nominal))});
    }
    for (unsigned j = 0; j < rest.cols(); ++j) coupled = std::max(coupled, std::fabs(nominal_value(rest(i, j), in.nominal)));
  }
  out.coupling = coupled / size;
  return true;
}

}  // namespace

bool solve_overdetermined(const matrix& J, const matrix& R, const GiNaC::exmap& nominal, matrix& X, std::string& error) {
  const std::vector<unsigned> rows = independent_rows(J, nominal);
  if (rows.size() != J.cols()) {
    error = fmt::format("{} unknowns but {} independent equations", J.cols(), rows.size());
    return false;
  }
  double smallest = 1.0;
  return solve_square(rows_of(J, rows), rows_of(R, rows), nominal, X, smallest, error);
}

ex exact_number(double v) {
  if (v == 0.0) return 0;
  // The shortest decimal that reads back as v, as digits and a power of ten.
  if (!std::isfinite(v)) return GiNaC::numeric(v);
  // The shortest decimal within four units of the last place: 0.49999999999999994
  // (sin(pi/6) in doubles) is 1/2, as an assembled 0.5000000000000001 is.
  std::string text = fmt::format("{}", v);
  for (int digits = 1; digits < 16; ++digits) {
    const std::string t = fmt::format("{:.{}g}", v, digits);
    if (std::fabs(std::stod(t) - v) <= 4 * std::numeric_limits<double>::epsilon() * std::fabs(v)) {
      text = t;
      break;
    }
  }
  std::string mantissa = text, exponent = "0";
  if (const auto e = text.find_first_of("eE"); e != std::string::npos) mantissa = text.substr(0, e), exponent = text.substr(e + 1);
  bool negative = false;
  if (!mantissa.empty() && mantissa[0] == '-') negative = true, mantissa = mantissa.substr(1);
  long shift = std::stol(exponent);
  std::string digits;
  for (std::size_t i = 0; i < mantissa.size(); ++i) {
    if (mantissa[i] == '.') shift -= static_cast<long>(mantissa.size() - i - 1);
    else digits += mantissa[i];
  }
  GiNaC::numeric n(digits.c_str());
  n = n * GiNaC::pow(GiNaC::numeric(10), GiNaC::numeric(shift));
  return negative ? -n : n;
}

ex fold_constants(const ex& e) {
  if (GiNaC::is_a<GiNaC::numeric>(e)) {
    const auto& n = GiNaC::ex_to<GiNaC::numeric>(e);
    return n.is_rational() ? e : exact_number(n.to_double());
  }
  if (GiNaC::is_a<GiNaC::symbol>(e)) return e;
  if (!has_symbol(e)) {
    // Inner functions first (3/10*cos(-pi/2 in doubles) is 0, not 2e-17).
    const ex v = (GiNaC::is_a<GiNaC::function>(e) ? e : e.map([](const ex& x) { return fold_constants(x); })).evalf();
    if (!GiNaC::is_a<GiNaC::numeric>(v) || !GiNaC::ex_to<GiNaC::numeric>(v).is_real()) return e;
    // cos(-pi/2) of a reference angle in doubles is 6e-17: a zero.
    const double x = GiNaC::ex_to<GiNaC::numeric>(v).to_double();
    return exact_number(GiNaC::is_a<GiNaC::function>(e) && std::fabs(x) < 1e-14 ? 0.0 : x);
  }
  return e.map([](const ex& x) { return fold_constants(x); });
}

double nominal_value(const ex& e, const GiNaC::exmap& nominal) {
  if (GiNaC::is_a<GiNaC::numeric>(e)) return GiNaC::ex_to<GiNaC::numeric>(e).to_double();
  const ex v = e.subs(nominal).evalf();
  if (!GiNaC::is_a<GiNaC::numeric>(v) || !GiNaC::ex_to<GiNaC::numeric>(v).is_real()) return std::nan("");
  return GiNaC::ex_to<GiNaC::numeric>(v).to_double();
}

ex tidy_entry(const ex& e, const std::vector<GiNaC::exmap>& points) {
  const ex f = GiNaC::normal(e);
  if (GiNaC::is_a<GiNaC::numeric>(f)) return f;
  auto chop = [&](const ex& poly) {
    const ex x = poly.expand();
    if (!GiNaC::is_a<GiNaC::add>(x)) return x;
    std::vector<bool> negligible(x.nops(), true);
    for (const auto& at : points) {
      std::vector<double> size(x.nops());
      double largest = 0.0;
      for (std::size_t i = 0; i < x.nops(); ++i) largest = std::max(largest, size[i] = std::fabs(nominal_value(x.op(i), at)));
      for (std::size_t i = 0; i < x.nops(); ++i) negligible[i] = negligible[i] && size[i] < 1e-12 * largest;
    }
    ex kept = 0;
    for (std::size_t i = 0; i < x.nops(); ++i)
      if (!negligible[i]) kept += x.op(i);
    return kept;
  };
  const ex nd = f.numer_denom();
  const ex num = chop(nd.op(0)), den = chop(nd.op(1));
  if (num.is_zero()) return 0;
  return GiNaC::normal(num / den);
}

bool symbolic_linear_model(const SymbolicLinearInput& in, SymbolicLinearModel& out, std::string& error) {
  const unsigned nq = static_cast<unsigned>(in.nq), nu = static_cast<unsigned>(in.nu), nc = static_cast<unsigned>(in.nc),
                 np = static_cast<unsigned>(in.np), nin = static_cast<unsigned>(in.nin), n = nq + nu;
  std::vector<GiNaC::exmap> points{in.nominal};
  points.insert(points.end(), in.elsewhere.begin(), in.elsewhere.end());
  // ---- the blocks at the reference, w still symbolic ----
  std::size_t at = 0;
  auto take = [&](unsigned rows, unsigned cols) {
    matrix M(rows, cols);
    for (unsigned i = 0; i < rows; ++i)
      for (unsigned j = 0; j < cols; ++j) M(i, j) = fold_constants(in.parts[at++].subs(in.at));
    return M;
  };
  const matrix Kq = take(nq, nq), Kv = take(nq, nu), Ac = take(nc, nu), Wq = take(nc, nq), P = take(np, nq);
  matrix Gq = take(nc, nq), Gv = take(nc, nu);
  const matrix My = take(nu, nu);
  matrix Fq = take(nu, nq), Fv = take(nu, nu), Fu = take(nu, nin), r = take(nu, 1), c = take(nc, 1);
  if (at != in.parts.size()) {
    error = fmt::format("internal: linear_parts has {} outputs, the layout {}", in.parts.size(), at);
    return false;
  }
  out.smallest_pivot = 1.0;

  // ---- reference rates and multipliers: My q1' - A_R^T lambda_R = hy, A_R q1' = -b_R ----
  GiNaC::exmap no_rates;
  for (unsigned j = 0; j < nu; ++j) no_rates[in.w[nin + j]] = 0;
  const std::vector<unsigned> R = independent_rows(Ac, in.nominal);
  const unsigned rho = static_cast<unsigned>(R.size());
  auto bordered = [&]() {  // [My, -A_R^T; A_R, 0]
    matrix K(nu + rho, nu + rho);
    for (unsigned i = 0; i < nu; ++i)
      for (unsigned j = 0; j < nu; ++j) K(i, j) = My(i, j);
    for (unsigned a = 0; a < rho; ++a)
      for (unsigned j = 0; j < nu; ++j) K(nu + a, j) = Ac(R[a], j), K(j, nu + a) = -Ac(R[a], j);
    return K;
  };
  const matrix K = bordered();
  matrix rhs(nu + rho, 1), sol;
  for (unsigned i = 0; i < nu; ++i) rhs(i, 0) = r(i, 0).subs(no_rates);
  for (unsigned a = 0; a < rho; ++a) rhs(nu + a, 0) = -c(R[a], 0).subs(no_rates);
  if (!solve_square(K, rhs, in.nominal, sol, out.smallest_pivot, error)) {
    error = "the reference rates: " + error;
    return false;
  }
  std::vector<ex> rates(nu), lambda(nc, ex(0));
  for (unsigned i = 0; i < nu; ++i) rates[i] = sol(i, 0);
  for (unsigned a = 0; a < rho; ++a) lambda[R[a]] = sol(nu + a, 0);
  if (rho < nc) {
    // The minimum-norm multipliers (as the runtime's): lambda = A_c(:, D) y in the range of
    // A_c, D independent columns, with A_c(:, D)^T A_c(:, D) y = (A_c^T lambda_R)(D).
    const matrix AcT = Ac.transpose();
    const std::vector<unsigned> D = independent_rows(AcT, in.nominal);
    matrix G(nc, static_cast<unsigned>(D.size()));
    for (unsigned i = 0; i < nc; ++i)
      for (unsigned k = 0; k < D.size(); ++k) G(i, k) = Ac(i, D[k]);
    matrix g(static_cast<unsigned>(D.size()), 1);
    for (unsigned k = 0; k < D.size(); ++k) {
      ex s = 0;
      for (unsigned a = 0; a < rho; ++a) s += Ac(R[a], D[k]) * lambda[R[a]];
      g(k, 0) = GiNaC::normal(s);
    }
    matrix y;
    if (!solve_square(times(G.transpose(), G), g, in.nominal, y, out.smallest_pivot, error)) {
      error = "the multipliers: " + error;
      return false;
    }
    const matrix l = times(G, y);
    for (unsigned i = 0; i < nc; ++i) lambda[i] = l(i, 0);
  }
  GiNaC::exmap w_ref;
  for (unsigned j = 0; j < nu; ++j) w_ref[in.w[nin + j]] = rates[j];
  for (unsigned i = 0; i < nc; ++i) w_ref[in.w[nin + nu + i]] = lambda[i];
  for (auto* M : {&Gq, &Gv, &Fq, &Fv, &Fu, &c})
    for (unsigned i = 0; i < M->rows(); ++i)
      for (unsigned j = 0; j < M->cols(); ++j) (*M)(i, j) = GiNaC::normal((*M)(i, j).subs(w_ref));

  // ---- the tangent space: dx = T dx_sel from P dq0 = 0, Wq dq0 + A_c dq1 = 0 ----
  const unsigned ns = static_cast<unsigned>(in.sel.size());
  std::vector<bool> chosen(n, false);
  for (int s : in.sel) chosen[static_cast<unsigned>(s)] = true;
  std::vector<unsigned> others;
  for (unsigned i = 0; i < n; ++i)
    if (!chosen[i]) others.push_back(i);
  matrix L(np + nc, n);
  for (unsigned i = 0; i < np; ++i)
    for (unsigned j = 0; j < nq; ++j) L(i, j) = P(i, j);
  for (unsigned i = 0; i < nc; ++i) {
    for (unsigned j = 0; j < nq; ++j) L(np + i, j) = Wq(i, j);
    for (unsigned j = 0; j < nu; ++j) L(np + i, nq + j) = Ac(i, j);
  }
  matrix LO(np + nc, static_cast<unsigned>(others.size())), LS(np + nc, ns);
  for (unsigned i = 0; i < np + nc; ++i) {
    for (unsigned k = 0; k < others.size(); ++k) LO(i, k) = L(i, others[k]);
    for (unsigned k = 0; k < ns; ++k) LS(i, k) = -L(i, static_cast<unsigned>(in.sel[k]));
  }
  const std::vector<unsigned> LR = independent_rows(LO, in.nominal);
  if (LR.size() != others.size()) {
    error = "the chosen components do not parametrize the linearized constraints";
    return false;
  }
  matrix XO;
  if (!others.empty() && !solve_square(rows_of(LO, LR), rows_of(LS, LR), in.nominal, XO, out.smallest_pivot, error)) {
    error = "the tangent space: " + error;
    return false;
  }
  matrix T(n, ns);
  for (unsigned k = 0; k < ns; ++k) T(static_cast<unsigned>(in.sel[k]), k) = 1;
  for (unsigned a = 0; a < others.size(); ++a)
    for (unsigned k = 0; k < ns; ++k) T(others[a], k) = XO(a, k);

  // ---- increments: My dq1' - A_R^T dlambda = F dx + Fu du + Kv^T T_q, A_R dq1' = -G_R dx ----
  matrix KqKv(nq, n), F(nu, n), G(rho, n);
  for (unsigned i = 0; i < nq; ++i) {
    for (unsigned j = 0; j < nq; ++j) KqKv(i, j) = Kq(i, j);
    for (unsigned j = 0; j < nu; ++j) KqKv(i, nq + j) = Kv(i, j);
  }
  for (unsigned i = 0; i < nu; ++i) {
    for (unsigned j = 0; j < nq; ++j) F(i, j) = Fq(i, j);
    for (unsigned j = 0; j < nu; ++j) F(i, nq + j) = Fv(i, j);
  }
  for (unsigned a = 0; a < rho; ++a) {
    for (unsigned j = 0; j < nq; ++j) G(a, j) = Gq(R[a], j);
    for (unsigned j = 0; j < nu; ++j) G(a, nq + j) = Gv(R[a], j);
  }
  const matrix FT = times(F, T), GT = times(G, T);
  const unsigned cols = ns + nin + nq;
  matrix inc(nu + rho, cols);
  for (unsigned i = 0; i < nu; ++i) {
    for (unsigned k = 0; k < ns; ++k) inc(i, k) = FT(i, k);
    for (unsigned k = 0; k < nin; ++k) inc(i, ns + k) = Fu(i, k);
    // A force T on coordinate k does the power T q_k' = T (Kq_k dq0 + Kv_k q1).
    for (unsigned k = 0; k < nq; ++k) inc(i, ns + nin + k) = Kv(k, i);
  }
  for (unsigned a = 0; a < rho; ++a)
    for (unsigned k = 0; k < ns; ++k) inc(nu + a, k) = -GT(a, k);
  matrix d;
  if (!solve_square(K, inc, in.nominal, d, out.smallest_pivot, error)) {
    error = "the increments: " + error;
    return false;
  }
  const matrix qT = times(KqKv, T);
  out.A = matrix(ns, ns), out.B = matrix(ns, nin), out.Bq = matrix(ns, nq);
  for (unsigned a = 0; a < ns; ++a) {
    const unsigned row = static_cast<unsigned>(in.sel[a]);
    for (unsigned k = 0; k < ns; ++k) out.A(a, k) = tidy_entry(row < nq ? qT(row, k) : d(row - nq, k), points);
    if (row < nq) continue;
    for (unsigned k = 0; k < nin; ++k) out.B(a, k) = tidy_entry(d(row - nq, ns + k), points);
    for (unsigned k = 0; k < nq; ++k) out.Bq(a, k) = tidy_entry(d(row - nq, ns + nin + k), points);
  }
  drop_rounding(out.A, points);
  drop_rounding(out.B, points);
  return in.coords.empty() || second_order(in, points, T, qT, out, error);
}

}  // namespace mbsc::analysis
