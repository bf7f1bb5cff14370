// SPDX-License-Identifier: GPL-2.0-or-later
// The assembled initial state and two points near it, at generation time (see the header).
#include "mbsc/sym/manifold_points.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <random>
#include <limits>
#include <utility>

#include "mbsc/model/rigid3d.hpp"
#include "mbsc/sym/symbol_set.hpp"

namespace mbsc::sym {
namespace {

/// The position residuals g(q) and their nonzero partial derivatives, kinematic names
/// written out (a derivative must see through them, as the generated position_jacobian does).
struct PositionRows {
  bool differences = false;  // the Jacobian by central differences (dg holds only the extra rows')
  std::vector<GiNaC::ex> g;
  std::vector<std::vector<std::pair<int, GiNaC::ex>>> dg;  // per row: (coordinate, dg/dq)
};

PositionRows position_rows(const model::Model& m) {
  PositionRows out;
  // With kinematic names (named body rotations) the rows stay as written and the
  // Jacobian is taken by differences (`differences`): written out, a chain of 16
  // quaternion joints multiplies 16 rotations into every row, which takes minutes.
  out.differences = !m.kinematic_names.empty();
  for (const auto& c : m.constraints) {
    if (c.level != model::Constraint::Level::Position) continue;
    std::vector<std::pair<int, GiNaC::ex>> row;
    if (!out.differences) {
      const SymbolSet in_g(c.residual);
      for (std::size_t i = 0; i < m.coords.size(); ++i) {
        const GiNaC::ex d = in_g.diff(c.residual, m.coords[i].sym);
        if (!d.is_zero()) row.emplace_back(static_cast<int>(i), d);
      }
    }
    out.g.push_back(c.residual);
    out.dg.push_back(std::move(row));
  }
  return out;
}

class Assembler {
 public:
  Assembler(const model::Model& m, const std::map<std::string, double>& params, std::vector<double> u)
      : m_(m), params_(params), u_(std::move(u)), rows_(position_rows(m)) {
    for (const auto& names : model::rigid3d::unit_quaternion_names(m)) {
      std::vector<int> group;
      for (const auto& n : names)
        for (std::size_t i = 0; i < m.coords.size(); ++i)
          if (m.coords[i].name == n) group.push_back(static_cast<int>(i));
      if (group.size() == 4) quaternions_.push_back(group);
    }
    // Each quaternion on |e| = 1: a rotation reads e unnormalized, so a step along e
    // would scale the body instead of turning it.
    for (const auto& group : quaternions_) {
      GiNaC::ex norm = -1;
      std::vector<std::pair<int, GiNaC::ex>> row;
      for (int c : group) {
        const GiNaC::symbol& e = m.coords[static_cast<std::size_t>(c)].sym;
        norm += e * e;
        row.emplace_back(c, 2 * e);
      }
      rows_.g.push_back(norm);
      rows_.dg.push_back(std::move(row));
    }
  }

  const std::vector<std::vector<int>>& quaternions() const { return quaternions_; }

  Probe at(const std::vector<double>& q) const { return Probe::configuration(m_, params_, q, u_); }

  /// The residuals at q; false when one does not evaluate.
  bool residuals(const std::vector<double>& q, Eigen::VectorXd& g) const {
    const Probe p = at(q);
    g.resize(static_cast<Eigen::Index>(rows_.g.size()));
    for (Eigen::Index i = 0; i < g.size(); ++i) {
      g(i) = p.eval_double(rows_.g[static_cast<std::size_t>(i)]);
      if (!std::isfinite(g(i))) return false;
    }
    return true;
  }

  /// Residuals and Jacobian at q; false when something does not evaluate.
  bool evaluate(const std::vector<double>& q, Eigen::VectorXd& g, Eigen::MatrixXd& J) const {
    if (!residuals(q, g)) return false;
    const auto nr = static_cast<Eigen::Index>(rows_.g.size());
    J = Eigen::MatrixXd::Zero(nr, static_cast<Eigen::Index>(q.size()));
    if (rows_.differences) {
      // Central differences, column by column (rounding ~1e-10 relative: Newton still
      // converges to rounding, and ranks are judged on the constraint matrix B instead).
      std::vector<double> shifted = q;
      Eigen::VectorXd gp, gm;
      for (std::size_t j = 0; j < q.size(); ++j) {
        const double h = 1e-6 * std::max(1.0, std::fabs(q[j]));
        shifted[j] = q[j] + h;
        if (!residuals(shifted, gp)) return false;
        shifted[j] = q[j] - h;
        if (!residuals(shifted, gm)) return false;
        shifted[j] = q[j];
        J.col(static_cast<Eigen::Index>(j)) = (gp - gm) / (2 * h);
      }
      return true;
    }
    const Probe p = at(q);
    for (Eigen::Index i = 0; i < nr; ++i)
      for (const auto& [j, d] : rows_.dg[static_cast<std::size_t>(i)]) {
        J(i, j) = p.eval_double(d);
        if (!std::isfinite(J(i, j))) return false;
      }
    return true;
  }

  static double scale(const std::vector<double>& q) {
    double s = 1.0;
    for (double v : q) s = std::max(s, std::fabs(v));
    return s;
  }

  /// Newton with minimum-norm least-squares steps over the coordinates `free`, each step
  /// halved while it does not reduce the residual. The largest residual at the end.
  double newton(std::vector<double>& q, const std::vector<bool>& free) const {
    std::vector<int> cols;
    for (std::size_t j = 0; j < q.size(); ++j)
      if (free[j]) cols.push_back(static_cast<int>(j));
    Eigen::VectorXd g;
    Eigen::MatrixXd J;
    if (!evaluate(q, g, J)) return std::numeric_limits<double>::infinity();
    double norm = g.size() ? g.cwiseAbs().maxCoeff() : 0.0;
    for (int it = 0; it < 60 && norm > 1e-13 * scale(q) && !cols.empty(); ++it) {
      Eigen::MatrixXd Jf(J.rows(), static_cast<Eigen::Index>(cols.size()));
      for (std::size_t k = 0; k < cols.size(); ++k) Jf.col(static_cast<Eigen::Index>(k)) = J.col(cols[k]);
      Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(Jf);
      cod.setThreshold(1e-10);
      const Eigen::VectorXd dq = cod.solve(-g);
      if (!dq.allFinite()) break;
      bool better = false;
      for (double step = 1.0; step > 1e-3 && !better; step *= 0.5) {
        std::vector<double> trial = q;
        for (std::size_t k = 0; k < cols.size(); ++k) trial[static_cast<std::size_t>(cols[k])] += step * dq(static_cast<Eigen::Index>(k));
        Eigen::VectorXd gt;
        Eigen::MatrixXd Jt;
        if (!evaluate(trial, gt, Jt)) continue;
        const double nt = gt.size() ? gt.cwiseAbs().maxCoeff() : 0.0;
        if (nt < norm) {
          q = std::move(trial);
          g = std::move(gt);
          J = std::move(Jt);
          norm = nt;
          better = true;
        }
      }
      if (!better) break;
    }
    return norm;
  }

  /// Every quaternion divided by its norm (after Newton: rounding only).
  void unit_quaternions(std::vector<double>& q) const {
    for (const auto& group : quaternions_) {
      double n2 = 0.0;
      for (int c : group) n2 += q[static_cast<std::size_t>(c)] * q[static_cast<std::size_t>(c)];
      if (n2 > 0.0)
        for (int c : group) q[static_cast<std::size_t>(c)] /= std::sqrt(n2);
    }
  }

  bool has_rows() const { return rows_.g.size() > quaternions_.size(); }

 private:
  const model::Model& m_;
  const std::map<std::string, double>& params_;
  std::vector<double> u_;
  PositionRows rows_;
  std::vector<std::vector<int>> quaternions_;
};

}  // namespace

ManifoldPoints manifold_points(const model::Model& m, const std::map<std::string, double>& param_values) {
  ManifoldPoints out;
  const std::size_t nq = m.coords.size();
  const Probe defaults = Probe::reference(m, param_values);
  // Starting values: `initial guess` and `initial` (the latter fixed), speeds as given.
  std::vector<double> q(nq, 0.0), u(m.speeds.size(), 0.0);
  std::vector<bool> free(nq, true);
  for (const auto* list : {&m.initial_guesses, &m.initial_values})
    for (const auto& iv : *list) {
      const double v = defaults.eval(iv.value);
      if (!std::isfinite(v)) continue;
      for (std::size_t i = 0; i < nq; ++i)
        if (m.coords[i].name == iv.name) {
          q[i] = v;
          if (list == &m.initial_values) free[i] = false;
        }
      for (std::size_t i = 0; i < m.speeds.size(); ++i)
        if (m.speeds[i].name == iv.name) u[i] = v;
    }
  // Where every position row places a coordinate of its own (a tree in joint
  // coordinates: no loop), nothing is to assemble and no row can be redundant: the start
  // is left to the reference, and the rows are not evaluated (a 16-joint quaternion chain
  // spent minutes here).
  bool loop = false, any_position = false;
  for (const auto& c : m.constraints)
    if (c.level == model::Constraint::Level::Position) {
      any_position = true;
      loop = loop || c.explicit_coordinate < 0;
    }
  if (any_position && !loop) {
    out.why_not = "every position row places a coordinate of its own (no loop)";
    return out;
  }
  Assembler assembler(m, param_values, u);
  for (const auto& group : assembler.quaternions()) {
    bool given = false;
    for (int c : group) given = given || q[static_cast<std::size_t>(c)] != 0.0;
    if (!given) q[static_cast<std::size_t>(group[0])] = 1.0;  // the identity
  }
  assembler.unit_quaternions(q);
  if (!assembler.has_rows()) {
    out.start = assembler.at(q);
    return out;
  }
  const double residual = assembler.newton(q, free);
  if (!(residual <= 1e-10 * Assembler::scale(q))) {
    out.why_not = "the initial state does not assemble: largest position residual " + std::to_string(residual);
    return out;
  }
  assembler.unit_quaternions(q);
  out.start = assembler.at(q);
  // Two nearby points: a deterministic step along the null space of the position
  // Jacobian (the mechanism's motion, to first order), pulled back with every coordinate free.
  Eigen::VectorXd g;
  Eigen::MatrixXd J;
  if (!assembler.evaluate(q, g, J)) return out;
  Eigen::FullPivLU<Eigen::MatrixXd> lu(J);
  lu.setThreshold(1e-9);
  const Eigen::MatrixXd N = lu.kernel();
  if (N.cols() == 0 || N.isZero()) return out;
  std::mt19937 rng(2718);
  const std::vector<bool> all(nq, true);
  for (double size : {0.07, 0.13}) {
    Eigen::VectorXd w(N.cols());
    for (Eigen::Index k = 0; k < w.size(); ++k) w(k) = -1.0 + 2.0 * (static_cast<double>(rng()) / 4294967296.0);
    Eigen::VectorXd dq = N * w;
    const double largest = dq.cwiseAbs().maxCoeff();
    if (!(largest > 0.0)) continue;
    dq *= size / largest;
    std::vector<double> qn = q;
    for (std::size_t i = 0; i < nq; ++i) qn[i] += dq(static_cast<Eigen::Index>(i));
    const double r = assembler.newton(qn, all);
    if (!(r <= 1e-10 * Assembler::scale(qn))) continue;
    assembler.unit_quaternions(qn);
    out.nearby.push_back(assembler.at(qn));
  }
  return out;
}

}  // namespace mbsc::sym
