// SPDX-License-Identifier: GPL-2.0-or-later
// Eigenvalue sweeps with mode tracking and stability crossings (include/mbsc/run/eigen_sweep.hpp).
#include "mbsc/run/eigen_sweep.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <limits>
#include <numeric>
#include <stdexcept>

namespace mbsc::run {

namespace {

using Complex = std::complex<double>;

/// The eigenvalues (and, when asked, unit eigenvectors) at one parameter value, in the
/// eigensolver's order.
struct Spectrum {
  std::vector<Complex> values;
  std::vector<Eigen::VectorXcd> vectors;
  Eigen::MatrixXcd columns;  // the same vectors as columns
};

/// A(p) formed and checked: square, not empty, of `size` rows when size >= 0, finite.
bool matrix_at(const MatrixAt& A, double p, Eigen::Index size, Eigen::MatrixXd& M, std::string& error,
               const std::string& name) {
  std::string why;
  M.resize(0, 0);
  if (!A(p, M, why)) {
    error = fmt::format("cannot form the state matrix at {} = {}: {}", name, p,
                        why.empty() ? std::string("no reason given") : why);
    return false;
  }
  if (M.rows() == 0 || M.rows() != M.cols()) {
    error = fmt::format("the state matrix at {} = {} is {}x{}, not a non-empty square matrix", name, p, M.rows(),
                        M.cols());
    return false;
  }
  if (size >= 0 && M.rows() != size) {
    error = fmt::format("the state matrix at {} = {} is {}x{}, but {}x{} at the sweep's first point", name, p,
                        M.rows(), M.cols(), size, size);
    return false;
  }
  for (Eigen::Index j = 0; j < M.cols(); ++j)
    for (Eigen::Index i = 0; i < M.rows(); ++i)
      if (!std::isfinite(M(i, j))) {
        error = fmt::format("the state matrix at {} = {} has a non-finite entry {} at row {}, column {}", name, p,
                            M(i, j), i + 1, j + 1);
        return false;
      }
  return true;
}

bool spectrum_of(const Eigen::MatrixXd& M, bool with_vectors, double p, Spectrum& s, std::string& error,
                 const std::string& name) {
  Eigen::EigenSolver<Eigen::MatrixXd> solver(M, with_vectors);
  if (solver.info() != Eigen::Success) {
    error = fmt::format("the eigenvalues of the state matrix at {} = {} did not converge", name, p);
    return false;
  }
  const Eigen::Index n = M.rows();
  s.values.resize(static_cast<std::size_t>(n));
  s.vectors.clear();
  for (Eigen::Index j = 0; j < n; ++j) s.values[static_cast<std::size_t>(j)] = solver.eigenvalues()(j);
  if (with_vectors) {
    s.columns = solver.eigenvectors();
    for (Eigen::Index j = 0; j < n; ++j) {
      const double norm = s.columns.col(j).norm();
      if (norm > 0) s.columns.col(j) /= norm;
      s.vectors.push_back(s.columns.col(j));
    }
  }
  return true;
}

/// The largest component (the first of equal ones) made real and positive. Conjugate
/// vectors stay conjugate: their components have the same magnitudes.
void phase_by_largest(Eigen::VectorXcd& v) {
  Eigen::Index best = 0;
  for (Eigen::Index i = 1; i < v.size(); ++i)
    if (std::abs(v(i)) > std::abs(v(best))) best = i;
  const double m = std::abs(v(best));
  if (m > 0) v *= std::conj(v(best)) / m;
}

/// The phase turned so that previous^H v is real and positive; where the two are nearly
/// orthogonal (a repeated eigenvalue's arbitrary basis) the largest component decides.
void phase_along(Eigen::VectorXcd& v, const Eigen::VectorXcd& previous) {
  const Complex c = previous.dot(v);  // previous^H v
  if (std::abs(c) > 1e-6)
    v *= std::conj(c) / std::abs(c);
  else
    phase_by_largest(v);
}

/// Phases along the sweep: a real mode's (real) vector keeps its sign, the upper member of
/// a conjugate pair its phase, and the lower member is the upper one's conjugate.
void set_phases(const std::vector<Complex>& values, std::vector<Eigen::VectorXcd>& vectors,
                const std::vector<Eigen::VectorXcd>& previous) {
  const std::size_t n = values.size();
  for (std::size_t i = 0; i < n; ++i) {
    if (values[i].imag() == 0) {
      if (previous[i].dot(vectors[i]).real() < 0) vectors[i] = -vectors[i];
    } else if (values[i].imag() > 0) {
      phase_along(vectors[i], previous[i]);
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (values[i].imag() >= 0) continue;
    bool paired = false;
    for (std::size_t j = 0; j < n && !paired; ++j)
      if (values[j] == std::conj(values[i])) {
        vectors[i] = vectors[j].conjugate();
        paired = true;
      }
    if (!paired) phase_along(vectors[i], previous[i]);
  }
}

/// The minimum-cost assignment of rows to columns of a square cost matrix (the Hungarian
/// method with potentials, O(n^3)): result[row] = column.
std::vector<int> assign(const std::vector<std::vector<double>>& cost) {
  const int n = static_cast<int>(cost.size());
  // Usually every row's cheapest column is a different one: then that is optimal.
  {
    std::vector<int> cheapest(static_cast<std::size_t>(n));
    std::vector<char> taken(static_cast<std::size_t>(n), 0);
    bool distinct = true;
    for (std::size_t i = 0; i < cost.size() && distinct; ++i) {
      const auto& row = cost[i];
      const auto j = static_cast<std::size_t>(std::min_element(row.begin(), row.end()) - row.begin());
      cheapest[i] = static_cast<int>(j);
      distinct = !taken[j];
      taken[j] = 1;
    }
    if (distinct) return cheapest;
  }
  const double inf = std::numeric_limits<double>::infinity();
  // 1-based: column 0 is a virtual column that starts each augmenting search.
  std::vector<double> u(n + 1, 0.0), w(n + 1, 0.0);
  std::vector<int> row_of(n + 1, 0), way(n + 1, 0);
  for (int i = 1; i <= n; ++i) {
    row_of[0] = i;
    int j0 = 0;
    std::vector<double> minv(n + 1, inf);
    std::vector<char> used(n + 1, 0);
    do {
      used[j0] = 1;
      const int i0 = row_of[j0];
      double delta = inf;
      int j1 = 0;
      for (int j = 1; j <= n; ++j) {
        if (used[j]) continue;
        const double reduced = cost[i0 - 1][j - 1] - u[i0] - w[j];
        if (reduced < minv[j]) {
          minv[j] = reduced;
          way[j] = j0;
        }
        if (minv[j] < delta) {
          delta = minv[j];
          j1 = j;
        }
      }
      for (int j = 0; j <= n; ++j) {
        if (used[j]) {
          u[row_of[j]] += delta;
          w[j] -= delta;
        } else {
          minv[j] -= delta;
        }
      }
      j0 = j1;
    } while (row_of[j0] != 0);
    do {
      const int j1 = way[j0];
      row_of[j0] = row_of[j1];
      j0 = j1;
    } while (j0 != 0);
  }
  std::vector<int> column_of(n, 0);
  for (int j = 1; j <= n; ++j) column_of[row_of[j] - 1] = j - 1;
  return column_of;
}

/// Where two modes meet and turn from a real pair into a conjugate pair (or back), either
/// member is an equally continuous continuation. Fix the choice the way the principal square
/// root of the discriminant would: the larger real one takes Im > 0, and the Im > 0 one
/// becomes the larger real one.
void order_coalescences(const std::vector<Complex>& before, std::vector<Complex>& now,
                        std::vector<Eigen::VectorXcd>& vectors) {
  const std::size_t n = now.size();
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j) {
      bool swap = false;
      if (before[i].imag() == 0 && before[j].imag() == 0 && now[i].imag() != 0 && now[j] == std::conj(now[i])) {
        // two reals became a pair: the one that was larger (the later one on a tie) takes Im > 0
        const bool i_up = before[i].real() > before[j].real();
        swap = i_up != (now[i].imag() > 0);
      } else if (before[i].imag() != 0 && before[j] == std::conj(before[i]) && now[i].imag() == 0 &&
                 now[j].imag() == 0 && now[i].real() != now[j].real()) {
        // a pair became two reals: the one that had Im > 0 takes the larger
        swap = (before[i].imag() > 0) != (now[i].real() > now[j].real());
      }
      if (swap) {
        std::swap(now[i], now[j]);
        std::swap(vectors[i], vectors[j]);
      }
    }
}

}  // namespace

bool sweep_eigenvalues(const MatrixAt& A, const std::vector<double>& grid, TrackedSweep& out, std::string& error,
                       const std::string& param_name) {
  out = TrackedSweep{};
  if (grid.empty()) {
    error = "the sweep's grid is empty";
    return false;
  }
  for (std::size_t k = 0; k < grid.size(); ++k)
    if (!std::isfinite(grid[k])) {
      error = fmt::format("the sweep's grid has a non-finite value {} (point {})", grid[k], k + 1);
      return false;
    }
  if (grid.size() > 1) {
    const bool up = grid[1] > grid[0];
    for (std::size_t k = 1; k < grid.size(); ++k)
      if (up ? !(grid[k] > grid[k - 1]) : !(grid[k] < grid[k - 1])) {
        error = fmt::format("the sweep's grid is not strictly monotonic: {} = {} (point {}) follows {} (point {})",
                            param_name, grid[k], k + 1, grid[k - 1], k);
        return false;
      }
  }

  Eigen::MatrixXd M;
  Eigen::MatrixXcd previous;  // the last point's tracked vectors as columns
  Eigen::Index size = -1;
  for (std::size_t k = 0; k < grid.size(); ++k) {
    const double p = grid[k];
    Spectrum s;
    if (!matrix_at(A, p, size, M, error, param_name) || !spectrum_of(M, true, p, s, error, param_name)) {
      out = TrackedSweep{};
      return false;
    }
    size = M.rows();
    const std::size_t n = s.values.size();
    std::vector<Complex> values(n);
    std::vector<Eigen::VectorXcd> vectors(n);

    if (k == 0) {
      // The modes' numbers: ascending real part, then imaginary part.
      std::vector<std::size_t> order(n);
      std::iota(order.begin(), order.end(), std::size_t{0});
      std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        const Complex x = s.values[a], y = s.values[b];
        return x.real() != y.real() ? x.real() < y.real() : x.imag() < y.imag();
      });
      for (std::size_t i = 0; i < n; ++i) {
        values[i] = s.values[order[i]];
        vectors[i] = s.vectors[order[i]];
        phase_by_largest(vectors[i]);
      }
    } else {
      // Where each mode should be: on the line through its two previous values (the
      // previous value alone at the second point).
      const std::vector<Complex>& last = out.values[k - 1];
      std::vector<Complex> predicted = last;
      if (k >= 2) {
        const double step = (grid[k] - grid[k - 1]) / (grid[k - 1] - grid[k - 2]);
        for (std::size_t i = 0; i < n; ++i) predicted[i] += (last[i] - out.values[k - 2][i]) * step;
      }
      // Cost: the distance to the prediction, plus a tiny multiple of the eigenvectors'
      // misalignment that only decides between (nearly) equal distances.
      double scale = 0.0;
      for (std::size_t i = 0; i < n; ++i) scale = std::max({scale, std::abs(predicted[i]), std::abs(s.values[i])});
      const double tie = 1e-8 * scale;
      const Eigen::MatrixXd overlaps = (previous.adjoint() * s.columns).cwiseAbs();
      std::vector<std::vector<double>> cost(n, std::vector<double>(n));
      for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j) {
          const double overlap =
              std::min(1.0, overlaps(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)));
          cost[i][j] = std::abs(predicted[i] - s.values[j]) + tie * (1.0 - overlap);
        }
      const std::vector<int> column = assign(cost);
      for (std::size_t i = 0; i < n; ++i) {
        values[i] = s.values[static_cast<std::size_t>(column[i])];
        vectors[i] = s.vectors[static_cast<std::size_t>(column[i])];
      }
      order_coalescences(last, values, vectors);
      set_phases(values, vectors, out.vectors[k - 1]);
    }
    previous.resize(size, size);
    for (std::size_t i = 0; i < n; ++i) previous.col(static_cast<Eigen::Index>(i)) = vectors[i];
    out.param.push_back(p);
    out.values.push_back(std::move(values));
    out.vectors.push_back(std::move(vectors));
  }
  return true;
}

namespace {

/// The eigenvalue of A(p) nearest `guess`.
bool nearest_eigenvalue(const MatrixAt& A, double p, Eigen::Index size, Complex guess, Complex& value,
                        std::string& error, const std::string& name) {
  Eigen::MatrixXd M;
  Spectrum s;
  if (!matrix_at(A, p, size, M, error, name) || !spectrum_of(M, false, p, s, error, name)) return false;
  value = s.values.front();
  for (const Complex& x : s.values)
    if (std::abs(x - guess) < std::abs(value - guess)) value = x;
  return true;
}

/// Re(lambda) = 0 between xa and xb, where lambda(xa) = la and lambda(xb) = lb have real
/// parts of opposite signs: Illinois' regula falsi (the end kept twice has its value
/// halved), a bisection step where three steps did not halve the bracket.
bool refine_crossing(const MatrixAt& A, Eigen::Index size, double xa, Complex la, double xb, Complex lb,
                     double width, StabilityCrossing& c, std::string& error, const std::string& name) {
  double fa = la.real(), fb = lb.real();  // the secant's values (Illinois halves them)
  int kept = 0;                           // -1: a was kept last step, +1: b was
  double reference = std::abs(xb - xa);
  for (int step = 1; step <= 200 && la.real() != 0 && lb.real() != 0 && std::abs(xb - xa) > width; ++step) {
    double x = xb - fb * (xb - xa) / (fb - fa);
    const bool stalled = step % 3 == 0 && std::abs(xb - xa) > 0.5 * reference;
    if (step % 3 == 0) reference = std::abs(xb - xa);
    if (stalled || !std::isfinite(x) || !((x - xa) * (x - xb) < 0)) x = 0.5 * (xa + xb);
    if (x == xa || x == xb) break;  // no double left between the ends
    const Complex guess = la + (lb - la) * ((x - xa) / (xb - xa));
    Complex lx;
    if (!nearest_eigenvalue(A, x, size, guess, lx, error, name)) return false;
    if ((lx.real() < 0) == (lb.real() < 0)) {
      xb = x;
      lb = lx;
      fb = lx.real();
      if (kept == -1) fa *= 0.5;
      kept = -1;
    } else {
      xa = x;
      la = lx;
      fa = lx.real();
      if (kept == +1) fb *= 0.5;
      kept = +1;
    }
  }
  const bool a_nearer = std::abs(la.real()) <= std::abs(lb.real());
  c.param = a_nearer ? xa : xb;
  c.value = a_nearer ? la : lb;
  return true;
}

/// A mode going from unstable to marginal (or back) between xa and xb: bisection on
/// "Re > margin" (the marginal side's real part is rounding, its sign meaningless), the
/// mode followed as in refine_crossing. Where an unstable real pair meets at zero and
/// becomes an imaginary pair, Re falls like the square root of the distance to that point,
/// so the predicate changes within (margin / rate)^2 of it.
bool refine_marginal(const MatrixAt& A, Eigen::Index size, double xa, Complex la, double xb, Complex lb, double width,
                     double margin, StabilityCrossing& c, std::string& error, const std::string& name) {
  const bool a_unstable = la.real() > margin;
  for (int step = 0; step < 200 && std::abs(xb - xa) > width; ++step) {
    const double x = 0.5 * (xa + xb);
    if (x == xa || x == xb) break;
    const Complex guess = la + (lb - la) * ((x - xa) / (xb - xa));
    Complex lx;
    if (!nearest_eigenvalue(A, x, size, guess, lx, error, name)) return false;
    if ((lx.real() > margin) == a_unstable) xa = x, la = lx;
    else xb = x, lb = lx;
  }
  c.param = 0.5 * (xa + xb);
  c.value = a_unstable ? lb : la;  // the marginal side's
  return true;
}

}  // namespace

bool stability_crossings(const MatrixAt& A, const TrackedSweep& sweep, std::vector<StabilityCrossing>& out,
                         std::string& error, double tol, const std::string& param_name) {
  out.clear();
  const std::size_t points = sweep.values.size();
  if (points < 2) return true;
  const std::size_t n = sweep.values.front().size();
  const double width = tol * std::abs(sweep.param.back() - sweep.param.front());
  // Zero modes over the whole sweep: each mode's largest |lambda| against the sweep's.
  double sweep_scale = 0.0;
  std::vector<double> peak(n, 0.0);
  for (const auto& point : sweep.values)
    for (std::size_t i = 0; i < n; ++i) {
      peak[i] = std::max(peak[i], std::abs(point[i]));
      sweep_scale = std::max(sweep_scale, peak[i]);
    }
  // Each point's class for each mode: unstable (+1), marginal (0: |Re| within
  // kMarginalTolerance of the point's largest |lambda|) or stable (-1).
  std::vector<double> point_scale(points, 0.0);
  for (std::size_t k = 0; k < points; ++k)
    for (const Complex& z : sweep.values[k]) point_scale[k] = std::max(point_scale[k], std::abs(z));
  auto cls = [&](std::size_t k, std::size_t i) {
    const double margin = kMarginalTolerance * point_scale[k], re = sweep.values[k][i].real();
    return re > margin ? 1 : re < -margin ? -1 : 0;
  };
  struct Run {
    int cls;
    std::size_t first, last;
  };
  for (std::size_t i = 0; i < n; ++i) {
    if (peak[i] <= kZeroModeSweepTolerance * sweep_scale) continue;  // zero along the whole sweep
    std::vector<Run> runs;
    for (std::size_t k = 0; k < points; ++k) {
      const int c = cls(k, i);
      if (runs.empty() || runs.back().cls != c) runs.push_back({c, k, k});
      else runs.back().last = k;
    }
    // One event between grid points ka < kb: a sign change refined by Illinois, or a change
    // between unstable and marginal refined by bisection.
    auto event = [&](std::size_t ka, std::size_t kb, bool marginal) {
      const Complex la = sweep.values[ka][i], lb = sweep.values[kb][i];
      const double scale = std::max(point_scale[ka], point_scale[kb]);
      const double zero = kZeroModeTolerance * scale;
      if (std::abs(la) <= zero && std::abs(lb) <= zero) return true;  // a zero mode's rounding
      if (la.imag() + lb.imag() < 0) return true;                       // the pair's lower member
      StabilityCrossing c;
      c.mode = static_cast<int>(i);
      c.becomes_stable = cls(kb, i) != 1;
      c.marginal = marginal;
      const bool ok = marginal ? refine_marginal(A, static_cast<Eigen::Index>(n), sweep.param[ka], la, sweep.param[kb], lb,
                                                 width, kMarginalTolerance * scale, c, error, param_name)
                               : refine_crossing(A, static_cast<Eigen::Index>(n), sweep.param[ka], la, sweep.param[kb], lb,
                                                 width, c, error, param_name);
      if (ok) out.push_back(c);
      return ok;
    };
    bool ok = true;
    for (std::size_t j = 0; ok && j + 1 < runs.size(); ++j) {
      const Run& r = runs[j];
      const Run& next = runs[j + 1];
      if (r.cls == 0) {
        // A sweep that starts marginal: a change to unstable is an event of its own.
        if (j == 0 && next.cls == 1) ok = event(r.last, next.first, true);
        continue;  // otherwise the run before it handled it
      }
      if (next.cls == -r.cls) {
        ok = event(r.last, next.first, false);
        continue;
      }
      // next is marginal: through it to the other sign is a crossing like any other (the
      // grid passed close to the root); otherwise only the unstable side's changes count.
      const Run* after = j + 2 < runs.size() ? &runs[j + 2] : nullptr;
      if (after && after->cls == -r.cls) {
        ok = event(r.last, after->first, false);
      } else if (r.cls == 1) {
        ok = event(r.last, next.first, true);
        if (ok && after && after->cls == 1) ok = event(next.last, after->first, true);
      }
    }
    if (!ok) {
      out.clear();
      return false;
    }
  }
  // Brackets come in grid order; a bracket's crossings by parameter, then mode.
  const bool up = sweep.param.back() > sweep.param.front();
  std::stable_sort(out.begin(), out.end(), [up](const StabilityCrossing& x, const StabilityCrossing& y) {
    if (x.param != y.param) return up ? x.param < y.param : x.param > y.param;
    return x.mode < y.mode;
  });
  return true;
}

std::complex<double> ratio(const Eigen::VectorXcd& v, int num, int den) {
  const auto inside = [&v](int i) { return i >= 0 && i < v.size(); };
  if (!inside(num) || !inside(den))
    throw std::out_of_range(fmt::format("eigenvector component ratio {}/{} of a vector of size {}", num, den, v.size()));
  return v(num) / v(den);
}

void write_sweep_csv(std::ostream& os, const TrackedSweep& sweep, const std::string& param_name) {
  std::string line = param_name;
  for (int m = 1; m <= sweep.modes(); ++m) line += fmt::format(",re_{0},im_{0}", m);
  os << line << '\n';
  for (std::size_t k = 0; k < sweep.values.size(); ++k) {
    line = fmt::format("{}", sweep.param[k]);
    for (const Complex& x : sweep.values[k]) line += fmt::format(",{},{}", x.real(), x.imag());
    os << line << '\n';
  }
}

}  // namespace mbsc::run
