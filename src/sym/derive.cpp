// SPDX-License-Identifier: GPL-2.0-or-later
// The recursive modular algorithm (thesis Table 4.1), leaves to root, at order 2.
#include <fmt/format.h>

#include "mbsc/model/expr_convert.hpp"

#include <Eigen/Dense>
#include <set>

#include "mbsc/sym/complement.hpp"
#include "mbsc/sym/eom.hpp"
#include "mbsc/sym/probe.hpp"

namespace mbsc::sym {
namespace {

using model::LeafKind;

class Deriver {
 public:
  Deriver(const model::Model& m, const Options& o, Diagnostics& d)
      : m_(m), diags_(d), probe_(m, param_values(m, o)) {
    eom_.model = &m;
    eom_.options = o;
    eom_.param_values = param_values(m, o);
    for (size_t i = 0; i < m.params.size(); ++i) {
      auto it = o.frozen.find(m.params[i].name);
      if (it != o.frozen.end()) frozen_[m.params[i].sym] = model::exact_decimal(it->second) ;
      else eom_.free_params.push_back(static_cast<int>(i));
    }
    eliminated_at_.assign(m.speeds.size(), -1);
  }

  static std::map<std::string, double> param_values(const model::Model& m, const Options& o) {
    std::map<std::string, double> v;
    for (size_t i = 0; i < m.params.size(); ++i) v[m.params[i].name] = m.param_defaults[i];
    for (const auto& [k, val] : o.frozen) v[k] = val;
    return v;
  }

  std::optional<Eom> run() {
    eom_.nodes.resize(m_.nodes.size());
    for (size_t n = 0; n < m_.nodes.size(); ++n) {
      if (!process(static_cast<int>(n))) return std::nullopt;
    }
    if (!assemble_root()) return std::nullopt;
    energy();
    return std::move(eom_);
  }

 private:
  GiNaC::ex fz(const GiNaC::ex& e) const { return frozen_.empty() ? e : e.subs(frozen_); }

  // ---- leaf generalized forces f (thesis (4.7)): inertia, gravity, applied forces ----
  GiNaC::ex own_force(const model::Node& node, int s, int k) {
    GiNaC::ex f = 0;
    const bool body = node.kind == LeafKind::Particle2d || node.kind == LeafKind::Particle3d || node.kind == LeafKind::Rigid2d;
    if (body) {
      // Body speeds are (u, v[, w]) = rates of (x, y[, z | theta]).
      const bool is_rotation = node.kind == LeafKind::Rigid2d && k == 2;
      if (is_rotation) {
        f += -fz(node.inertia) * m_.speed_dots[s];
      } else {
        f += -fz(node.mass) * m_.speed_dots[s];
        if (k < static_cast<int>(m_.gravity.size())) f += fz(node.mass) * fz(m_.gravity[k]);
      }
    }
    for (const auto& force : m_.forces)
      if (force.speed == s) f += fz(force.value);
    return f;
  }

  /// q1dot of speed s in terms of the variables `avail` (this node's y), composing the
  /// dependent-rate layers of the descendants where s was eliminated.
  GiNaC::ex express(int s, const std::set<int>& avail, std::map<int, GiNaC::ex>& memo) {
    if (avail.count(s)) return m_.speed_dots[s];
    auto it = memo.find(s);
    if (it != memo.end()) return it->second;
    int d = eliminated_at_[s];
    const NodeResult& r = eom_.nodes[d];
    GiNaC::ex e = r.dependent_rates.at(s);
    GiNaC::exmap sub;
    for (int t : r.y)
      if (!avail.count(t) && e.has(m_.speed_dots[t])) sub[m_.speed_dots[t]] = express(t, avail, memo);
    if (!sub.empty()) e = e.subs(sub);
    memo[s] = e;
    return e;
  }

  bool process(int n) {
    const model::Node& node = m_.nodes[n];
    NodeResult& r = eom_.nodes[n];
    r.node = n;
    // y = (own speeds, children's independent speeds)
    std::vector<GiNaC::ex> f;
    for (size_t k = 0; k < node.speeds.size(); ++k) {
      r.y.push_back(node.speeds[k]);
      f.push_back(own_force(node, node.speeds[k], static_cast<int>(k)));
    }
    for (int c : node.children) {
      const NodeResult& rc = eom_.nodes[c];
      for (size_t k = 0; k < rc.independent.size(); ++k) {
        r.y.push_back(rc.independent[k]);
        f.push_back(rc.fbar[k]);
      }
    }
    const std::set<int> avail(r.y.begin(), r.y.end());
    // Accelerations in forces must be of this node's own speeds.
    for (const auto& force : m_.forces) {
      if (m_.speeds[force.speed].node != n) continue;
      for (size_t j = 0; j < m_.speeds.size(); ++j)
        if (force.value.has(m_.speed_dots[j]) && m_.speeds[j].node != n) {
          diags_.error(force.pos, fmt::format("force on '{}' uses the acceleration of '{}', which belongs to another subsystem",
                                              m_.speeds[force.speed].name, m_.speeds[j].name));
          return false;
        }
    }
    // Order-2 invariants of this node, with descendants' dependent rates composed in.
    std::vector<GiNaC::ex> rows;
    std::map<int, GiNaC::ex> memo;
    for (int ci : node.constraints) {
      const auto& c = m_.constraints[ci];
      GiNaC::ex g = fz(c.residual);
      if (c.level == model::Constraint::Level::Position) g = time_derivative(m_, g);
      g = time_derivative(m_, g);
      GiNaC::exmap sub;
      for (size_t j = 0; j < m_.speeds.size(); ++j) {
        if (!g.has(m_.speed_dots[j])) continue;
        if (!in_subtree(static_cast<int>(j), n)) {
          diags_.error(c.pos, fmt::format("constraint '{}' of subsystem '{}' involves '{}', which is outside that subsystem; "
                                          "declare it in a common parent",
                                          c.name, node.name.empty() ? "<top>" : node.name, m_.speeds[j].name));
          return false;
        }
        if (!avail.count(static_cast<int>(j))) sub[m_.speed_dots[j]] = express(static_cast<int>(j), avail, memo);
      }
      rows.push_back(sub.empty() ? g : g.subs(sub));
      r.rows.push_back(ci);
    }
    const int ny = static_cast<int>(r.y.size());
    const int nr = static_cast<int>(rows.size());
    if (nr == 0) {
      // Without constraints every y is independent; a given set must say exactly that.
      for (int s : node.independent)
        if (!avail.count(s)) {
          diags_.error(node.independent_pos, fmt::format("independent speed '{}' is not free at subsystem '{}' (it is not one of its "
                                                         "speeds or was eliminated in a child subsystem)",
                                                         m_.speeds[s].name, node.name.empty() ? "<top>" : node.name));
          return false;
        }
      if (!node.independent.empty() && node.independent.size() != r.y.size()) {
        diags_.error(node.independent_pos, fmt::format("subsystem '{}' has {} degree(s) of freedom but {} independent speed(s) are given",
                                                       node.name.empty() ? "<top>" : node.name, r.y.size(), node.independent.size()));
        return false;
      }
      r.independent = node.independent.empty() ? r.y : node.independent;
      r.rank = 0;
      r.C = GiNaC::matrix(ny, ny);
      for (int i = 0; i < ny; ++i) r.C(i, i) = 1;
      r.f = f;
      r.fbar = f;
      return true;
    }
    // B = d rows / d y, b = rows at y = 0.
    r.B = GiNaC::matrix(nr, ny);
    r.b = GiNaC::matrix(nr, 1);
    GiNaC::exmap zero;
    for (int j = 0; j < ny; ++j) zero[m_.speed_dots[r.y[j]]] = 0;
    for (int i = 0; i < nr; ++i) {
      for (int j = 0; j < ny; ++j) r.B(i, j) = rows[i].diff(m_.speed_dots[r.y[j]]);
      r.b(i, 0) = rows[i].subs(zero);
    }
    ComplementInput in{&m_, &probe_, n, r.y, r.rows, &r.B, node.independent, node.independent_pos};
    auto choice = choose_partition(in, diags_);
    if (!choice) return false;
    r.rank = nr;
    r.independent = choice->independent;
    r.dependent = choice->dependent;
    // Solve the dependent rates: symbolically when cheap, else as a numeric solve.
    std::map<int, int> col;  // speed -> column in y
    for (int j = 0; j < ny; ++j) col[r.y[j]] = j;
    std::map<int, GiNaC::ex> sol;
    if (choice->symbolic) {
      sol = solve_symbolic(r, *choice, col);
    } else {
      r.symbolic_complement = false;
      sol = solve_numeric(r, col, n);
    }
    // C = [I on #; d sol/d y# on ⋆] in y order.
    const int nd = static_cast<int>(r.independent.size());
    r.C = GiNaC::matrix(ny, nd);
    for (int j = 0; j < nd; ++j) r.C(col[r.independent[j]], j) = 1;
    for (int s : r.dependent)
      for (int j = 0; j < nd; ++j) r.C(col[s], j) = sol[s].diff(m_.speed_dots[r.independent[j]]);
    // fbar = C^T f with the dependent rates substituted (thesis (4.11)).
    GiNaC::exmap dep;
    for (int s : r.dependent) dep[m_.speed_dots[s]] = sol[s];
    r.f.resize(ny);
    for (int j = 0; j < ny; ++j) r.f[j] = f[j].subs(dep);
    r.fbar.assign(nd, 0);
    for (int j = 0; j < nd; ++j) {
      GiNaC::ex acc = r.f[col[r.independent[j]]];
      for (int s : r.dependent)
        if (!r.C(col[s], j).is_zero()) acc += r.C(col[s], j) * r.f[col[s]];
      r.fbar[j] = acc;
    }
    for (int s : r.dependent) {
      r.dependent_rates[s] = sol[s];
      eliminated_at_[s] = n;
    }
    return true;
  }

  bool in_subtree(int speed, int n) const {
    for (int k = m_.speeds[speed].node; k >= 0; k = m_.nodes[k].parent)
      if (k == n) return true;
    return false;
  }

  /// Dependent rates by forward substitution (triangular order) or a small exact solve.
  std::map<int, GiNaC::ex> solve_symbolic(const NodeResult& r, const Partition& p, const std::map<int, int>& col) {
    std::map<int, GiNaC::ex> sol;
    if (!p.triangular_order.empty()) {
      // Row i solves for speed s_i: B(i,s_i) y_s + sum_others B(i,j) y_j + b_i = 0.
      for (auto [row, s] : p.triangular_order) {
        GiNaC::ex rest = r.b(row, 0);
        for (size_t j = 0; j < r.y.size(); ++j) {
          if (r.y[j] == s || r.B(row, j).is_zero()) continue;
          auto it = sol.find(r.y[j]);
          rest += r.B(row, j) * (it != sol.end() ? it->second : GiNaC::ex(m_.speed_dots[r.y[j]]));
        }
        sol[s] = -rest / r.B(row, col.at(s));
      }
      return sol;
    }
    // Small block with a state-free determinant: exact solve.
    const int nd = static_cast<int>(p.dependent.size());
    GiNaC::matrix Bs(nd, nd), rhs(nd, 1);
    for (int i = 0; i < nd; ++i) {
      GiNaC::ex rest = r.b(i, 0);
      for (size_t j = 0; j < r.y.size(); ++j)
        if (std::find(p.dependent.begin(), p.dependent.end(), r.y[j]) == p.dependent.end())
          rest += r.B(i, j) * m_.speed_dots[r.y[j]];
      rhs(i, 0) = -rest;
      for (int k = 0; k < nd; ++k) Bs(i, k) = r.B(i, col.at(p.dependent[k]));
    }
    GiNaC::matrix inv = Bs.inverse();
    for (int k = 0; k < nd; ++k) {
      GiNaC::ex acc = 0;
      for (int i = 0; i < nd; ++i) acc += inv(k, i).normal() * rhs(i, 0);
      sol[p.dependent[k]] = acc;
    }
    return sol;
  }

  /// X = B*^-1 [B# | b] solved in the generated code; y* = -X [y#; 1].
  std::map<int, GiNaC::ex> solve_numeric(NodeResult& r, const std::map<int, int>& col, int n) {
    const int nd = static_cast<int>(r.dependent.size());
    const int ni = static_cast<int>(r.independent.size());
    ir::Solve solve;
    solve.label = fmt::format("subsystem '{}': dependent block B*", m_.nodes[n].name.empty() ? "<top>" : m_.nodes[n].name);
    solve.n = nd;
    solve.k = ni + 1;
    const std::string tag = sanitize(m_.nodes[n].name.empty() ? "top" : m_.nodes[n].name);
    Eigen::MatrixXd An(nd, nd), Bn(nd, ni + 1);
    for (int i = 0; i < nd; ++i) {
      for (int k = 0; k < nd; ++k) {
        solve.A.push_back(r.B(i, col.at(r.dependent[k])));
        An(i, k) = probe_.eval(solve.A.back());
      }
      for (int j = 0; j < ni; ++j) {
        solve.B.push_back(r.B(i, col.at(r.independent[j])));
        Bn(i, j) = probe_.eval(solve.B.back());
      }
      solve.B.push_back(r.b(i, 0));
      Bn(i, ni) = probe_.eval(solve.B.back());
    }
    Eigen::MatrixXd Xn = An.partialPivLu().solve(Bn);
    std::map<int, GiNaC::ex> sol;
    for (int i = 0; i < nd; ++i) {
      GiNaC::ex acc = 0;
      for (int j = 0; j <= ni; ++j) {
        GiNaC::symbol x(fmt::format("X_{}_{}_{}", tag, i, j));
        solve.X.push_back(x);
        probe_.bind(x, Xn(i, j));
        acc -= x * (j < ni ? GiNaC::ex(m_.speed_dots[r.independent[j]]) : GiNaC::ex(1));
      }
      sol[r.dependent[i]] = acc;
    }
    r.solves.push_back(solve);
    eom_.solves.push_back(solve);
    return sol;
  }

  static std::string sanitize(const std::string& s) {
    std::string out;
    for (char c : s) out += (std::isalnum(static_cast<unsigned char>(c)) ? c : '_');
    return out;
  }

  // ---- root: fbar = -M z' + h, and the top-down dependent rates ----
  bool assemble_root() {
    const NodeResult& root = eom_.nodes[m_.root()];
    eom_.independent = root.independent;
    const int nd = static_cast<int>(root.independent.size());
    eom_.M = GiNaC::matrix(nd, nd);
    eom_.h = GiNaC::matrix(nd, 1);
    GiNaC::exmap zero;
    for (int s : root.independent) zero[m_.speed_dots[s]] = 0;
    for (int i = 0; i < nd; ++i) {
      for (int j = 0; j < nd; ++j) eom_.M(i, j) = -root.fbar[i].diff(m_.speed_dots[root.independent[j]]);
      eom_.h(i, 0) = root.fbar[i].subs(zero);
    }
    // Sanity: M must be symmetric positive definite at the probe point.
    if (nd > 0) {
      Eigen::MatrixXd Mn(nd, nd);
      for (int i = 0; i < nd; ++i)
        for (int j = 0; j < nd; ++j) Mn(i, j) = probe_.eval(eom_.M(i, j));
      Eigen::LLT<Eigen::MatrixXd> llt(0.5 * (Mn + Mn.transpose()));
      if (!Mn.allFinite() || llt.info() != Eigen::Success)
        diags_.warning(m_.nodes[m_.root()].pos, "the reduced mass matrix is not positive definite at a generic configuration "
                                               "(massless directions or a singular independent set)");
    }
    // Dependent rates, root to leaves (reverse post-order).
    for (int n = m_.root(); n >= 0; --n) {
      const NodeResult& r = eom_.nodes[n];
      for (int s : r.dependent) eom_.top_down.push_back(ir::Define{m_.speed_dots[s], r.dependent_rates.at(s)});
    }
    return true;
  }

  // ---- energy: bodies' kinetic and gravitational potential, plus user terms ----
  void energy() {
    GiNaC::ex T = 0, V = 0;
    bool ok = true;
    for (const auto& node : m_.nodes) {
      const bool body = node.kind == LeafKind::Particle2d || node.kind == LeafKind::Particle3d || node.kind == LeafKind::Rigid2d;
      if (body) {
        for (size_t k = 0; k < node.speeds.size(); ++k) {
          const GiNaC::ex u = m_.speeds[node.speeds[k]].sym;
          const bool rot = node.kind == LeafKind::Rigid2d && k == 2;
          T += GiNaC::numeric(1, 2) * fz(rot ? node.inertia : node.mass) * u * u;
          if (!rot && k < m_.gravity.size()) V -= fz(node.mass) * fz(m_.gravity[k]) * m_.coords[node.coords[k]].sym;
        }
      }
      if (node.has_kinetic) T += fz(node.kinetic);
      else if (node.kind == LeafKind::Custom && !node.speeds.empty()) ok = false;
      V += fz(node.potential);
    }
    eom_.kinetic = T;
    eom_.potential = V;
    eom_.has_energy = ok;
  }

  const model::Model& m_;
  Diagnostics& diags_;
  Probe probe_;
  Eom eom_;
  GiNaC::exmap frozen_;
  std::vector<int> eliminated_at_;
};

}  // namespace

std::optional<Eom> derive(const model::Model& model, const Options& options, Diagnostics& diags) {
  for (const auto& [name, v] : options.frozen) {
    bool found = false;
    for (const auto& p : model.params) found = found || p.name == name;
    if (!found) {
      diags.error(SourcePos{}, fmt::format("--freeze: model '{}' has no parameter '{}'", model.name, name));
      return std::nullopt;
    }
  }
  try {
    Deriver d(model, options, diags);
    return d.run();
  } catch (const std::exception& e) {
    diags.error(model.nodes.empty() ? SourcePos{} : model.nodes.back().pos,
                std::string("internal error while deriving the equations: ") + e.what());
    return std::nullopt;
  }
}

}  // namespace mbsc::sym
