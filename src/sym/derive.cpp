// SPDX-License-Identifier: GPL-2.0-or-later
// The recursive modular algorithm (thesis Table 4.1), leaves to root, at order 2.
#include <fmt/format.h>

#include "mbsc/diag/activity.hpp"
#include "mbsc/model/exact_guard.hpp"
#include "mbsc/model/expr_convert.hpp"
#include "mbsc/model/value_bound.hpp"

#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <map>
#include <algorithm>
#include <set>
#include <utility>
#include <vector>

#include "mbsc/sym/complement.hpp"
#include "mbsc/sym/pivot_elimination.hpp"
#include "mbsc/sym/eom.hpp"
#include "mbsc/sym/massless_check.hpp"
#include "mbsc/model/rigid3d.hpp"
#include "mbsc/sym/own_force.hpp"
#include "mbsc/sym/probe.hpp"
#include "mbsc/sym/linear_gradient.hpp"
#include "mbsc/sym/manifold_points.hpp"
#include "mbsc/sym/symbol_set.hpp"
#include "mbsc/sym/tidy.hpp"

namespace mbsc::sym {
namespace {

using model::LeafKind;

class Deriver {
 public:
  Deriver(const model::Model& m, const Options& o, Diagnostics& d)
      : m_(m),
        diags_(d),
        probe_(m, param_values(m, o)),
        manifold_(manifold_points(m, param_values(m, o))),
        reference_(Probe::reference(m, param_values(m, o))) {
    eom_.start_missing = manifold_.why_not;
    if (manifold_.start && initial_coordinates_given()) start_name_ = "the initial state (the model's `initial` values, assembled)";
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

  /// The independent set asked for at a node in this partition (empty: automatic).
  const std::vector<int>& requested(const model::Node& node) const {
    const int k = eom_.options.partition;
    return k > 0 && k <= static_cast<int>(node.alternatives.size()) ? node.alternatives[static_cast<std::size_t>(k - 1)]
                                                                     : node.independent;
  }
  SourcePos requested_pos(const model::Node& node) const {
    const int k = eom_.options.partition;
    return k > 0 && k <= static_cast<int>(node.alternatives.size()) ? node.alternative_pos[static_cast<std::size_t>(k - 1)]
                                                                     : node.independent_pos;
  }

  static std::map<std::string, double> param_values(const model::Model& m, const Options& o) {
    std::map<std::string, double> v;
    for (size_t i = 0; i < m.params.size(); ++i) v[m.params[i].name] = m.param_defaults[i];
    for (const auto& [k, val] : o.frozen) v[k] = val;
    return v;
  }

  /// A checkpoint of the time budget and --progress while subsystem n is derived: at its
  /// start and within its long steps (rows, entries of B, blocks), so that one large
  /// subsystem cannot run on past the budget between two subsystems.
  void still_deriving(int n) const {
    checkpoint("deriving", fmt::format("subsystem '{}'", m_.label(n)), m_.nodes[static_cast<std::size_t>(n)].pos,
               static_cast<std::size_t>(n), m_.nodes.size());
  }

  std::optional<Eom> run() {
    eom_.nodes.resize(m_.nodes.size());
    const std::vector<int> clone_from =
        eom_.options.reuse_components ? component_clones() : std::vector<int>(m_.nodes.size(), -1);
    for (size_t n = 0; n < m_.nodes.size(); ++n) {
      still_deriving(static_cast<int>(n));
      if (clone_from[n] >= 0) {
        clone(static_cast<int>(n), clone_from[n]);
      } else if (!process(static_cast<int>(n))) {
        return std::nullopt;
      }
    }
    if (!assemble_root()) return std::nullopt;
    eom_.massless = massless_bodies(m_, probe_);
    energy();
    return std::move(eom_);
  }

 private:
  GiNaC::ex fz(const GiNaC::ex& e) const { return frozen_.empty() ? e : e.subs(frozen_); }

  // ---- leaf generalized forces f (thesis (4.7)): inertia, gravity, applied forces ----
  GiNaC::ex own_force(const model::Node& /*node*/, int s, int /*k*/) { return fz(sym::own_force(m_, s)); }

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
    if (!sub.empty()) e = e.subs(sub, GiNaC::subs_options::no_pattern);
    memo[s] = e;
    return e;
  }

  bool process(int n) {
    const model::Node& node = m_.nodes[n];
    NodeResult& r = eom_.nodes[n];
    r.node = n;
    // y = (own speeds, children's independent speeds); f over y as f = -My y' + hy,
    // with My block-diagonal: own speeds' block from the leaf forces, children's M.
    std::vector<GiNaC::ex> f_own;
    for (size_t k = 0; k < node.speeds.size(); ++k) {
      r.y.push_back(node.speeds[k]);
      f_own.push_back(own_force(node, node.speeds[k], static_cast<int>(k)));
    }
    for (int c : node.children)
      for (int s : eom_.nodes[c].independent) r.y.push_back(s);
    const int ny = static_cast<int>(r.y.size());
    r.My = GiNaC::matrix(ny, ny);
    r.hy = GiNaC::matrix(ny, 1);
    {
      const int no = static_cast<int>(node.speeds.size());
      GiNaC::exmap zero_own;
      for (int s : node.speeds) zero_own[m_.speed_dots[s]] = 0;
      for (int i = 0; i < no; ++i) {
        for (int j = 0; j < no; ++j) r.My(i, j) = -f_own[i].diff(m_.speed_dots[node.speeds[j]]);
        r.hy(i, 0) = f_own[i].subs(zero_own, GiNaC::subs_options::no_pattern);
      }
      int off = no;
      for (int c : node.children) {
        const NodeResult& rc = eom_.nodes[c];
        const int nc = static_cast<int>(rc.independent.size());
        for (int i = 0; i < nc; ++i) {
          for (int j = 0; j < nc; ++j) r.My(off + i, off + j) = rc.M(i, j);
          r.hy(off + i, 0) = rc.h(i, 0);
        }
        off += nc;
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
      still_deriving(n);
      const auto& c = m_.constraints[ci];
      GiNaC::ex g = fz(c.residual);
      if (c.level == model::Constraint::Level::Position) g = time_derivative(m_, g);
      g = time_derivative(m_, g);
      GiNaC::exmap sub;
      const SymbolSet in_g(g);
      for (size_t j = 0; j < m_.speeds.size(); ++j) {
        if (!in_g.contains(m_.speed_dots[j])) continue;
        if (!in_subtree(static_cast<int>(j), n)) {
          diags_.error(c.pos, fmt::format("constraint '{}' of subsystem '{}' involves '{}', which is outside that subsystem; "
                                          "declare it in a common parent",
                                          c.name, m_.label(n), m_.speeds[j].name));
          return false;
        }
        if (!avail.count(static_cast<int>(j))) sub[m_.speed_dots[j]] = express(static_cast<int>(j), avail, memo);
      }
      rows.push_back(sub.empty() ? g : g.subs(sub, GiNaC::subs_options::no_pattern));
      r.rows.push_back(ci);
    }
    const int nr = static_cast<int>(rows.size());
    if (nr == 0) {
      // Without constraints every y is independent; a given set must say exactly that.
      for (int s : requested(node))
        if (!avail.count(s)) {
          diags_.error(requested_pos(node), fmt::format("independent speed '{}' is not free at subsystem '{}' (it is not one of its "
                                                         "speeds or was eliminated in a child subsystem)",
                                                         m_.speeds[s].name, m_.label(n)));
          return false;
        }
      if (!requested(node).empty() && requested(node).size() != r.y.size()) {
        diags_.error(requested_pos(node), fmt::format("subsystem '{}' has {} degree(s) of freedom but {} independent speed(s) are given",
                                                       m_.label(n), r.y.size(), requested(node).size()));
        return false;
      }
      r.independent = requested(node).empty() ? r.y : requested(node);
      r.rank = 0;
      // C is a permutation (the given order of the independent speeds).
      GiNaC::matrix C(ny, ny);
      for (int j = 0; j < ny; ++j)
        C(static_cast<int>(std::find(r.y.begin(), r.y.end(), r.independent[j]) - r.y.begin()), j) = 1;
      r.C = DeferredMatrix(std::move(C));
      r.e = GiNaC::matrix(ny, 1);
      reduce_forces(r, n != m_.root());
      return true;
    }
    // B = d rows / d y, b = rows at y = 0.
    r.B = GiNaC::matrix(nr, ny);
    r.b = GiNaC::matrix(nr, 1);
    GiNaC::exmap zero;
    for (int j = 0; j < ny; ++j) zero[m_.speed_dots[r.y[j]]] = 0;
    for (int i = 0; i < nr; ++i) {
      const SymbolSet in_row(rows[i]);
      for (int j = 0; j < ny; ++j) {
        still_deriving(n);
        r.B(i, j) = in_row.diff(rows[i], m_.speed_dots[r.y[j]]);
      }
      r.b(i, 0) = rows[i].subs(zero, GiNaC::subs_options::no_pattern);
    }
    ComplementInput in{&m_, &probe_, n, r.y, r.rows, &r.B, requested(node), requested_pos(node), &reference_};
    if (manifold_.start) {
      in.start = &*manifold_.start;
      in.nearby = &manifold_.nearby;
      in.start_name = start_name_;
    }
    auto choice = choose_partition(in, diags_);
    if (!choice) return false;
    r.rank = choice->rank;
    for (int i : choice->redundant_rows) r.redundant.push_back(r.rows[static_cast<std::size_t>(i)]);
    for (int c : r.redundant) eom_.redundant_on_manifold.push_back(c);
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
    std::vector<GiNaC::symbol> independent_dots;
    for (int s : r.independent) independent_dots.push_back(m_.speed_dots[s]);
    auto form_C = [ny, nd, col, sol, independent_dots, independent = r.independent, dependent = r.dependent]() {
      GiNaC::matrix C(static_cast<unsigned>(ny), static_cast<unsigned>(nd));
      for (int j = 0; j < nd; ++j) C(static_cast<unsigned>(col.at(independent[static_cast<std::size_t>(j)])), static_cast<unsigned>(j)) = 1;
      for (int s : dependent) {
        const std::vector<GiNaC::ex> row = linear_gradient(sol.at(s), independent_dots);
        for (int j = 0; j < nd; ++j) C(static_cast<unsigned>(col.at(s)), static_cast<unsigned>(j)) = row[static_cast<std::size_t>(j)];
      }
      return C;
    };
    // A triangular root needs C only where something reads it (M, the full complement):
    // h comes from the transposed rate steps, the rhs from the steps themselves.
    if (n == m_.root() && !r.rate_steps.empty()) {
      r.C = DeferredMatrix(static_cast<unsigned>(ny), static_cast<unsigned>(nd), form_C);
    } else {
      still_deriving(n);
      r.C = DeferredMatrix(form_C());
    }
    // e: the dependent rates when every independent rate is zero.
    r.e = GiNaC::matrix(ny, 1);
    GiNaC::exmap zero_indep;
    for (int s : r.independent) zero_indep[m_.speed_dots[s]] = 0;
    if (!r.rate_steps.empty()) {
      // Triangular: e is evaluated row by row in the generated code (one named variable
      // per dependent speed, each reading the ones before it), so h = C^T (hy - My e)
      // stays linear in size instead of repeating ever longer sums.
      GiNaC::exmap earlier;
      for (const auto& [s, local] : r.rate_steps) {
        const GiNaC::ex value = local.subs(zero_indep, GiNaC::subs_options::no_pattern).subs(earlier, GiNaC::subs_options::no_pattern);
        if (GiNaC::is_a<GiNaC::numeric>(value)) {  // 0 for a rate without velocity products
          earlier[m_.speed_dots[s]] = value;
          r.e(col[s], 0) = value;
          continue;
        }
        GiNaC::symbol E("e_" + sanitize(m_.speeds[s].name));
        r.named_defines.push_back(ir::Define{E, value, true});
        probe_.bind(E, probe_.eval(value));
        earlier[m_.speed_dots[s]] = E;
        r.e(col[s], 0) = E;
      }
      for (const auto& d : r.named_defines) eom_.pre_steps.push_back(d);
    } else {
      for (int s : r.dependent) r.e(col[s], 0) = sol[s].subs(zero_indep, GiNaC::subs_options::no_pattern);
    }
    reduce_forces(r, n != m_.root());
    // A subsystem's reduced M and h enter its parent as blocks: tidy them here, while
    // they are small, so sin^2 + cos^2 and common factors do not reach the root unmerged.
    if (n != m_.root()) {
      for (unsigned i = 0; i < r.M.rows(); ++i)
        for (unsigned j = 0; j < r.M.cols(); ++j) r.M(i, j) = tidy(pythagoras(r.M(i, j)));
      for (unsigned i = 0; i < r.h.rows(); ++i) r.h(i, 0) = tidy(pythagoras(r.h(i, 0)));
    }
    for (int s : r.dependent) {
      r.dependent_rates[s] = sol[s];
      eliminated_at_[s] = n;
    }
    return true;
  }

  /// fbar = C^T f with y = C z + e (thesis (4.11) and Thm 4.1):
  ///   M = C^T My C,  h = C^T (hy - My e),  fbar = -M z' + h.
  /// Only products with nonzero factors are formed; M is symmetric by construction.
  /// Triangular nodes form h by the transposed rate steps instead (see transpose_steps).
  /// The root leaves M to assemble_root, which defers it (DeferredMatrix).
  void reduce_forces(NodeResult& r, bool form_M = true) {
    const unsigned ny = r.C.rows(), nd = r.C.cols();
    if (form_M) r.M = reduced_mass(r.C.get(), r.My);
    // rest = hy - My e, over My's nonzeros.
    GiNaC::matrix rest(ny, 1);
    for (unsigned i = 0; i < ny; ++i) {
      GiNaC::ex acc_rest = r.hy(i, 0);
      for (unsigned k = 0; k < ny; ++k)
        if (!r.e(k, 0).is_zero() && !r.My(i, k).is_zero()) acc_rest -= r.My(i, k) * r.e(k, 0);
      rest(i, 0) = acc_rest;
    }
    r.h = GiNaC::matrix(nd, 1);
    if (!r.rate_steps.empty()) {
      transpose_steps(r, rest);
      return;
    }
    for (unsigned a = 0; a < nd; ++a) {
      GiNaC::ex acc = 0;
      for (unsigned i = 0; i < ny; ++i)
        if (!r.C(i, a).is_zero() && !rest(i, 0).is_zero()) acc += r.C(i, a) * rest(i, 0);
      r.h(a, 0) = acc;
    }
  }

  /// M = C^T My C over the nonzeros only: My and C are mostly zero (block diagonal, one
  /// or a few entries per row), and the dense triple loops were cubic in the number of
  /// speeds. Every entry still sums its terms in the same order as the dense product
  /// (ascending inner index), so the expressions are the same.
  static GiNaC::matrix reduced_mass(const GiNaC::matrix& C, const GiNaC::matrix& My) {
    const unsigned ny = C.rows(), nd = C.cols();
    using Sparse = std::vector<std::vector<std::pair<unsigned, GiNaC::ex>>>;
    Sparse my_rows(ny), c_rows(ny), c_cols(nd);
    for (unsigned i = 0; i < ny; ++i) {
      for (unsigned k = 0; k < ny; ++k)
        if (!My(i, k).is_zero()) my_rows[i].emplace_back(k, My(i, k));
      for (unsigned j = 0; j < nd; ++j)
        if (!C(i, j).is_zero()) {
          c_rows[i].emplace_back(j, C(i, j));
          c_cols[j].emplace_back(i, C(i, j));
        }
    }
    // Row i of My C.
    Sparse myc_rows(ny);
    std::vector<GiNaC::ex> row_acc(nd);
    std::vector<unsigned> touched;
    for (unsigned i = 0; i < ny; ++i) {
      touched.clear();
      for (const auto& [k, myik] : my_rows[i])
        for (const auto& [j, ckj] : c_rows[k]) {
          if (row_acc[j].is_zero()) touched.push_back(j);
          row_acc[j] += myik * ckj;
        }
      std::sort(touched.begin(), touched.end());
      touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
      for (unsigned j : touched) {
        if (!row_acc[j].is_zero()) myc_rows[i].emplace_back(j, row_acc[j]);
        row_acc[j] = 0;
      }
    }
    GiNaC::matrix M(nd, nd);
    std::vector<GiNaC::ex> m_acc(nd);
    for (unsigned a = 0; a < nd; ++a) {
      touched.clear();
      for (const auto& [i, cia] : c_cols[a])
        for (const auto& [b, mycib] : myc_rows[i]) {
          if (b < a) continue;
          if (m_acc[b].is_zero()) touched.push_back(b);
          m_acc[b] += cia * mycib;
        }
      std::sort(touched.begin(), touched.end());
      touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
      for (unsigned b : touched) {
        M(a, b) = m_acc[b];
        M(b, a) = m_acc[b];
        m_acc[b] = 0;
      }
    }
    return M;
  }

  /// M = C^T My C at the probe point in floating point: the positive-definiteness check
  /// without the symbolic M. Triangular nodes get C's rows by running their rate steps
  /// numerically (each dependent rate is a few earlier ones times coefficients), so a
  /// chain needs evaluations linear in its size.
  Eigen::MatrixXd numeric_reduced_mass(const NodeResult& r) {
    const int ny = static_cast<int>(r.C.rows()), nd = static_cast<int>(r.C.cols());
    std::map<int, int> col;  // speed -> row of y
    for (int j = 0; j < ny; ++j) col[r.y[static_cast<std::size_t>(j)]] = j;
    using Row = Eigen::SparseVector<double>;
    std::vector<Row> c(static_cast<std::size_t>(ny), Row(nd));
    if (!r.rate_steps.empty()) {
      for (int a = 0; a < nd; ++a) c[static_cast<std::size_t>(col[r.independent[static_cast<std::size_t>(a)]])].insert(a) = 1.0;
      for (const auto& [s, local] : r.rate_steps) {
        Row acc(nd);
        for (const auto& [j, a] : step_coefficients(r, s, local)) acc += probe_.eval(a) * c[static_cast<std::size_t>(col[j])];
        c[static_cast<std::size_t>(col[s])] = acc;
      }
    } else {
      for (int i = 0; i < ny; ++i)
        for (int j = 0; j < nd; ++j)
          if (!r.C(i, j).is_zero()) c[static_cast<std::size_t>(i)].insert(j) = probe_.eval(r.C(i, j));
    }
    Eigen::MatrixXd Mn = Eigen::MatrixXd::Zero(nd, nd);
    for (int i = 0; i < ny; ++i)
      for (int k = 0; k < ny; ++k) {
        if (r.My(i, k).is_zero()) continue;
        const double myik = probe_.eval(r.My(i, k));
        for (Row::InnerIterator a(c[static_cast<std::size_t>(i)]); a; ++a)
          for (Row::InnerIterator b(c[static_cast<std::size_t>(k)]); b; ++b) Mn(a.index(), b.index()) += a.value() * myik * b.value();
      }
    return Mn;
  }

  /// Rate step s reads y*_s = sum_j a_sj y_j + const: the nonzero a_sj, in y order (a
  /// step reads a few rates, so it is differentiated only by those it contains).
  std::vector<std::pair<int, GiNaC::ex>> step_coefficients(const NodeResult& r, int s, const GiNaC::ex& local) const {
    std::vector<std::pair<int, GiNaC::ex>> out;
    const SymbolSet in_local(local);
    for (int j : r.y) {
      if (j == s) continue;
      const GiNaC::ex a = in_local.diff(local, m_.speed_dots[j]);
      if (!a.is_zero()) out.emplace_back(j, a);
    }
    return out;
  }

  /// h = C^T v by running the rate steps backwards (the transpose of the forward
  /// substitution, as in reverse-mode differentiation). Step s reads
  /// y*_s = sum_j a_sj y_j + const, so the adjoint of every y_j it reads gains a_sj v_s,
  /// and v_s is complete once every later step has been visited. In a chain, where
  /// each dependent rate reads the one before it, v becomes a running suffix sum and
  /// h costs O(steps) instead of O(steps x dof). Each complete v_s with more than one
  /// term is a named variable r_<speed> of the generated code.
  void transpose_steps(NodeResult& r, const GiNaC::matrix& v) {
    std::map<int, GiNaC::ex> adjoint;  // speed -> accumulated v
    for (size_t i = 0; i < r.y.size(); ++i) adjoint[r.y[i]] = v(static_cast<unsigned>(i), 0);
    for (auto step = r.rate_steps.rbegin(); step != r.rate_steps.rend(); ++step) {
      const auto& [s, local] = *step;
      GiNaC::ex vs = adjoint[s];
      if (vs.is_zero()) continue;
      if (GiNaC::is_a<GiNaC::add>(vs)) {
        GiNaC::symbol R("r_" + sanitize(m_.speeds[s].name));
        r.named_defines.push_back(ir::Define{R, vs, true});
        eom_.pre_steps.push_back(r.named_defines.back());
        probe_.bind(R, probe_.eval(vs));
        vs = R;
      }
      for (const auto& [j, a] : step_coefficients(r, s, local)) adjoint[j] += a * vs;
    }
    for (size_t a = 0; a < r.independent.size(); ++a) r.h(static_cast<unsigned>(a), 0) = adjoint[r.independent[a]];
  }

  // ---- components: derived once, instantiated by substitution ----
  int subtree_size(int n) const {
    int size = 1;
    for (int c : m_.nodes[n].children) size += subtree_size(c);
    return size;
  }

  /// For every node inside a later instance of a component whose first instance has
  /// the same structure and forces, the corresponding node of the first instance.
  std::vector<int> component_clones() {
    std::vector<int> from(m_.nodes.size(), -1);
    for (size_t n = 0; n < m_.nodes.size(); ++n) {
      const int p = m_.nodes[n].instance_of;
      if (p < 0) continue;
      const int size = subtree_size(static_cast<int>(n));
      if (size != subtree_size(p)) continue;
      const int shift = static_cast<int>(n) - p;
      bool same = true;
      for (int k = static_cast<int>(n) - size + 1; k <= static_cast<int>(n) && same; ++k) {
        const auto& a = m_.nodes[k];
        const auto& b = m_.nodes[k - shift];
        same = a.kind == b.kind && a.coords.size() == b.coords.size() && a.speeds.size() == b.speeds.size() &&
               a.constraints.size() == b.constraints.size() && a.children.size() == b.children.size() &&
               a.independent.size() == b.independent.size();
      }
      // A body placed by a joint with a coordinate has a named rotation (Model::
      // kinematic_names) whose values and rates read its parent's names: the renaming
      // below does not carry them, so such an instance is derived on its own.
      for (int k = static_cast<int>(n) - size + 1; k <= static_cast<int>(n) && same; ++k)
        same = !m_.nodes[k].rigid3d.named_rotation && !m_.nodes[k - shift].rigid3d.named_rotation;
      if (!same) continue;
      GiNaC::exmap map = instance_map(static_cast<int>(n), p);
      // Forces aimed into the instance must be the prototype's, renamed.
      for (int k = static_cast<int>(n) - size + 1; k <= static_cast<int>(n) && same; ++k)
        for (size_t i = 0; i < m_.nodes[k].speeds.size() && same; ++i)
          same = forces_on(m_.nodes[k].speeds[i]).is_equal(forces_on(m_.nodes[k - shift].speeds[i]).subs(map));
      if (!same) continue;
      for (int k = static_cast<int>(n) - size + 1; k <= static_cast<int>(n); ++k) from[k] = k - shift;
    }
    return from;
  }

  GiNaC::ex forces_on(int s) const {
    GiNaC::ex f = 0;
    for (const auto& force : m_.forces)
      if (force.speed == s) f += force.value;
    return f;
  }

  /// Prototype symbols -> instance symbols (variables, their rates, formals).
  GiNaC::exmap instance_map(int n, int p) const {
    GiNaC::exmap map;
    const int size = subtree_size(n), shift = n - p;
    for (int k = n - size + 1; k <= n; ++k) {
      const auto& a = m_.nodes[k];
      const auto& b = m_.nodes[k - shift];
      for (size_t i = 0; i < a.coords.size(); ++i) map[m_.coords[b.coords[i]].sym] = m_.coords[a.coords[i]].sym;
      for (size_t i = 0; i < a.speeds.size(); ++i) {
        map[m_.speeds[b.speeds[i]].sym] = m_.speeds[a.speeds[i]].sym;
        map[m_.speed_dots[b.speeds[i]]] = m_.speed_dots[a.speeds[i]];
      }
    }
    const std::string from = m_.nodes[p].name + ".", to = m_.nodes[n].name + ".";
    for (const auto& [name, f] : m_.formals)
      if (name.rfind(from, 0) == 0) {
        auto it = m_.formals.find(to + name.substr(from.size()));
        if (it != m_.formals.end()) map[f.sym] = it->second.sym;
      }
    return map;
  }

  /// Node k's result from node q's (same place in another instance of the component).
  void clone(int k, int q) {
    int inst = k;
    while (m_.nodes[inst].instance_of < 0) inst = m_.nodes[inst].parent;
    GiNaC::exmap map = instance_map(inst, m_.nodes[inst].instance_of);
    const int shift = k - q;
    // Speeds and constraints correspond by position within corresponding nodes.
    std::map<int, int> speed_of;
    const int size = subtree_size(k);
    for (int a = k - size + 1; a <= k; ++a)
      for (size_t i = 0; i < m_.nodes[a].speeds.size(); ++i) speed_of[m_.nodes[a - shift].speeds[i]] = m_.nodes[a].speeds[i];
    auto speeds = [&](const std::vector<int>& v) {
      std::vector<int> out;
      for (int s : v) out.push_back(speed_of.at(s));
      return out;
    };
    auto mat = [&](const GiNaC::matrix& M) {
      GiNaC::matrix out(M.rows(), M.cols());
      for (unsigned i = 0; i < M.rows(); ++i)
        for (unsigned j = 0; j < M.cols(); ++j) out(i, j) = M(i, j).subs(map);
      return out;
    };
    const NodeResult& src = eom_.nodes[q];
    NodeResult r;
    r.node = k;
    r.y = speeds(src.y);
    r.rows = m_.nodes[k].constraints;
    r.independent = speeds(src.independent);
    r.dependent = speeds(src.dependent);
    r.rank = src.rank;
    // Rows redundant on the mechanism, by position among the node's constraints.
    for (int c : src.redundant) {
      const auto at = std::find(src.rows.begin(), src.rows.end(), c) - src.rows.begin();
      r.redundant.push_back(r.rows[static_cast<std::size_t>(at)]);
      eom_.redundant_on_manifold.push_back(r.redundant.back());
    }
    r.symbolic_complement = src.symbolic_complement;
    r.numeric_core = src.numeric_core;
    r.from_component_cache = true;
    // Opaque solve results get instance names, bound at the probe point like the originals.
    for (const auto& s : src.solves) {
      ir::Solve c = s;
      c.label = s.label + " (instance " + m_.nodes[k].name + ")";
      for (auto& x : c.X) {
        GiNaC::symbol renamed(x.get_name() + "_i" + std::to_string(k));
        map[x] = renamed;
        x = renamed;
      }
      for (auto& e : c.A) e = e.subs(map);
      for (auto& e : c.B) e = e.subs(map);
      bind_probe(c);
      r.solves.push_back(c);
      eom_.solves.push_back(c);
      eom_.pre_steps.push_back(c);
    }
    // Named e_ and r_ variables get instance names too.
    for (const auto& d : src.named_defines) {
      GiNaC::symbol renamed(d.sym.get_name() + "_i" + std::to_string(k));
      map[d.sym] = renamed;
      const ir::Define c{renamed, d.value.subs(map), true};
      probe_.bind(renamed, probe_.eval(c.value));
      r.named_defines.push_back(c);
      eom_.pre_steps.push_back(c);
    }
    r.B = mat(src.B);
    r.b = mat(src.b);
    r.C = DeferredMatrix(mat(src.C.get()));
    r.e = mat(src.e);
    r.My = mat(src.My);
    r.hy = mat(src.hy);
    r.M = mat(src.M);
    r.h = mat(src.h);
    for (const auto& [s, e] : src.rate_steps) r.rate_steps.push_back({speed_of.at(s), e.subs(map)});
    r.step_rows = src.step_rows;
    for (const auto& [s, e] : src.dependent_rates) {
      r.dependent_rates[speed_of.at(s)] = e.subs(map);
      eliminated_at_[speed_of.at(s)] = k;
    }
    eom_.nodes[k] = r;
  }

  /// Whether the model's `initial` statements place some coordinate (else its start is
  /// the reference configuration, coordinates at 0, assembled).
  bool initial_coordinates_given() const {
    for (const auto* list : {&m_.initial_values, &m_.initial_guesses})
      for (const auto& iv : *list)
        for (const auto& q : m_.coords)
          if (q.name == iv.name) return true;
    return false;
  }

  /// Numeric values of a solve's X at the probe point (for the parents' rank decisions).
  void bind_probe(const ir::Solve& s) {
    Eigen::MatrixXd An(s.n, s.n), Bn(s.n, s.k);
    for (int i = 0; i < s.n; ++i) {
      for (int j = 0; j < s.n; ++j) An(i, j) = probe_.eval(s.A[i * s.n + j]);
      for (int j = 0; j < s.k; ++j) Bn(i, j) = probe_.eval(s.B[i * s.k + j]);
    }
    Eigen::MatrixXd Xn = An.partialPivLu().solve(Bn);
    for (int i = 0; i < s.n; ++i)
      for (int j = 0; j < s.k; ++j) probe_.bind(s.X[i * s.k + j], Xn(i, j));
  }

  bool in_subtree(int speed, int n) const {
    for (int k = m_.speeds[speed].node; k >= 0; k = m_.nodes[k].parent)
      if (k == n) return true;
    return false;
  }

  /// Dependent rates by forward substitution (triangular order) or a small exact solve.
  std::map<int, GiNaC::ex> solve_symbolic(NodeResult& r, const Partition& p, const std::map<int, int>& col) {
    std::map<int, GiNaC::ex> sol;
    if (!p.triangular_order.empty()) {
      // Row i solves for speed s_i: B(i,s_i) y_s + sum_others B(i,j) y_j + b_i = 0.
      // `sol` is in y# only (for C and f); the generated code evaluates the rows in
      // order instead, each reading the rates solved before it (linear, not quadratic).
      for (auto [row, s] : p.triangular_order) {
        GiNaC::ex rest = r.b(row, 0), local = r.b(row, 0);
        for (size_t j = 0; j < r.y.size(); ++j) {
          if (r.y[j] == s || r.B(row, j).is_zero()) continue;
          auto it = sol.find(r.y[j]);
          rest += r.B(row, j) * (it != sol.end() ? it->second : GiNaC::ex(m_.speed_dots[r.y[j]]));
          local += r.B(row, j) * m_.speed_dots[r.y[j]];
        }
        sol[s] = -rest / r.B(row, col.at(s));
        r.rate_steps.push_back({s, -local / r.B(row, col.at(s))});
        r.step_rows.push_back(row);
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
      for (int i = 0; i < nd; ++i) acc += model::normal_if_small(inv(k, i)) * rhs(i, 0);
      sol[p.dependent[k]] = acc;
    }
    return sol;
  }

  /// The dependent rates of a block that is neither triangular nor small: Gaussian
  /// elimination on the pivots that are state-free (numbers and parameters: the unit
  /// entries of joint rows in absolute coordinates), done symbolically, leaves a core
  /// whose pivots all depend on the state (a four-bar's 8x8 block leaves its 2x2 loop
  /// closure). The core is solved numerically in the generated code,
  /// X = A_core^-1 [B#_core | b_core], y*_core = -X [y#; 1], and the eliminated rates
  /// follow by back substitution. Without any state-free pivot the core is the block.
  std::map<int, GiNaC::ex> solve_numeric(NodeResult& r, const std::map<int, int>& col, int n) {
    const int nd = static_cast<int>(r.dependent.size());
    const int ni = static_cast<int>(r.independent.size());
    // Row i: sum_j c_ij y*_j + rest_i = 0, rest_i = sum_l B(i, #l) y#_l + b_i. Every row
    // of B: with rows redundant on the mechanism there are more rows than unknowns.
    const int nr = static_cast<int>(r.B.rows());
    std::vector<LinearRow> rows(static_cast<std::size_t>(nr));
    for (int i = 0; i < nr; ++i) {
      auto& row = rows[static_cast<std::size_t>(i)];
      for (int k = 0; k < nd; ++k) row.c.push_back(r.B(i, col.at(r.dependent[k])));
      row.rest = r.b(i, 0);
      for (int j = 0; j < ni; ++j) row.rest += r.B(i, col.at(r.independent[j])) * m_.speed_dots[r.independent[j]];
    }
    still_deriving(n);
    const Elimination elim = eliminate_state_free_pivots(std::move(rows), m_, probe_);
    still_deriving(n);
    const std::vector<int>& core_vars = elim.core_vars;
    std::map<int, GiNaC::ex> value;  // dependent index -> rate
    if (!core_vars.empty()) {
      GiNaC::exmap zero_indep;
      for (int s : r.independent) zero_indep[m_.speed_dots[s]] = 0;
      const std::string tag = sanitize(m_.nodes[n].name.empty() ? "top" : m_.nodes[n].name);
      const auto blocks = core_blocks(elim);
      int index = 0;  // running core position: X names as for one block
      for (std::size_t b = 0; b < blocks.size(); ++b) {
        const auto& block = blocks[b];
        const int nb = static_cast<int>(block.vars.size());
        ir::Solve solve;
        solve.label = static_cast<int>(core_vars.size()) == nd
                          ? fmt::format("subsystem '{}': dependent block B*", m_.label(n))
                          : fmt::format("subsystem '{}': dependent block B*, core left by {} state-free pivots", m_.label(n),
                                        nd - static_cast<int>(core_vars.size()));
        if (blocks.size() > 1) solve.label += fmt::format(", part {} of {}", b + 1, blocks.size());
        solve.n = nb;
        solve.k = ni + 1;
        solve.gains = ni;
        for (int i : block.rows) {
          still_deriving(n);
          const LinearRow& row = elim.rows[static_cast<std::size_t>(i)];
          for (int j : block.vars) solve.A.push_back(row.c[static_cast<std::size_t>(j)]);
          for (int l = 0; l < ni; ++l) solve.B.push_back(row.rest.diff(m_.speed_dots[r.independent[l]]));
          solve.B.push_back(row.rest.subs(zero_indep, GiNaC::subs_options::no_pattern));
        }
        if (block.rows.size() > block.vars.size()) {
          // Rows redundant on the mechanism: least squares. The normal equations' condition
          // number is the square of the block's, so the conditioning reports its root.
          to_normal_equations(solve.A, solve.B, static_cast<int>(block.rows.size()), nb, ni + 1);
          solve.label += ", least squares (normal equations) over " + std::to_string(block.rows.size()) + " rows";
          solve.report_power = GiNaC::numeric(1, 2);
        }
        for (int k = 0; k < nb; ++k, ++index) {
          GiNaC::ex acc = 0;
          for (int l = 0; l <= ni; ++l) {
            GiNaC::symbol x(fmt::format("X_{}_{}_{}", tag, index, l));
            solve.X.push_back(x);
            acc -= x * (l < ni ? GiNaC::ex(m_.speed_dots[r.independent[l]]) : GiNaC::ex(1));
          }
          value[block.vars[static_cast<std::size_t>(k)]] = acc;
        }
        bind_probe(solve);
        r.solves.push_back(solve);
        eom_.solves.push_back(solve);
        eom_.pre_steps.push_back(solve);
      }
    }
    r.symbolic_complement = core_vars.empty();
    r.numeric_core = static_cast<int>(core_vars.size());
    back_substitute(elim, value);
    std::map<int, GiNaC::ex> sol;
    for (int j = 0; j < nd; ++j) sol[r.dependent[static_cast<std::size_t>(j)]] = value.at(j);
    return sol;
  }

  static std::string sanitize(const std::string& s) {
    std::string out;
    for (char c : s) out += (std::isalnum(static_cast<unsigned char>(c)) ? c : '_');
    return out;
  }

  /// Cholesky of the symmetric part of Mn, one diagonal block (connected set of speeds
  /// coupled by nonzero entries) at a time: the same pivots as the whole matrix's, as
  /// the entries between blocks are zero, but linear in the number of blocks for a
  /// model of many separate bodies instead of cubic in its degrees of freedom.
  static bool positive_definite_by_blocks(const Eigen::MatrixXd& Mn) {
    const int nd = static_cast<int>(Mn.rows());
    std::vector<std::vector<int>> coupled(static_cast<std::size_t>(nd));
    for (int j = 0; j < nd; ++j)
      for (int i = 0; i < nd; ++i)
        if (i != j && (Mn(i, j) != 0.0 || Mn(j, i) != 0.0)) coupled[static_cast<std::size_t>(j)].push_back(i);
    std::vector<int> block(static_cast<std::size_t>(nd), -1);
    for (int start = 0; start < nd; ++start) {
      if (block[static_cast<std::size_t>(start)] >= 0) continue;
      std::vector<int> members{start};
      block[static_cast<std::size_t>(start)] = start;
      for (std::size_t k = 0; k < members.size(); ++k)
        for (int i : coupled[static_cast<std::size_t>(members[k])])
          if (block[static_cast<std::size_t>(i)] < 0) {
            block[static_cast<std::size_t>(i)] = start;
            members.push_back(i);
          }
      std::sort(members.begin(), members.end());
      const auto nb = static_cast<Eigen::Index>(members.size());
      Eigen::MatrixXd sub(nb, nb);
      for (Eigen::Index a = 0; a < nb; ++a)
        for (Eigen::Index b = 0; b < nb; ++b) {
          const int i = members[static_cast<std::size_t>(a)], j = members[static_cast<std::size_t>(b)];
          sub(a, b) = 0.5 * (Mn(i, j) + Mn(j, i));
        }
      if (Eigen::LLT<Eigen::MatrixXd>(sub).info() != Eigen::Success) return false;
    }
    return true;
  }

  // ---- root: fbar = -M z' + h, and the top-down dependent rates ----
  bool assemble_root() {
    const NodeResult& root = eom_.nodes[m_.root()];
    eom_.independent = root.independent;
    const int nd = static_cast<int>(root.independent.size());
    eom_.M = DeferredMatrix([C = root.C, My = root.My] { return reduced_mass(C.get(), My); });
    eom_.h = root.h;
    // Dependent rates, root to leaves (reverse post-order); the massless check below
    // follows them.
    for (int n = m_.root(); n >= 0; --n) {
      const NodeResult& r = eom_.nodes[n];
      if (!r.rate_steps.empty()) {
        for (const auto& [s, e] : r.rate_steps) eom_.top_down.push_back(ir::Define{m_.speed_dots[s], e});
      } else {
        for (int s : r.dependent) eom_.top_down.push_back(ir::Define{m_.speed_dots[s], r.dependent_rates.at(s)});
      }
    }
    // Sanity: M must be symmetric positive definite at the probe point.
    if (nd > 0) {
      const Eigen::MatrixXd Mn = numeric_reduced_mass(root);
      eom_.mass_matrix_spd = Mn.allFinite() && positive_definite_by_blocks(Mn);
      // Massless bodies are allowed while M stays positive definite; when they leave it
      // singular, the error is theirs (at their mass or inertia).
      if (!eom_.mass_matrix_spd && report_massless_directions(m_, eom_, probe_, Mn, diags_)) return false;
      if (!eom_.mass_matrix_spd) {
        diags_.warning(m_.nodes[m_.root()].pos, "the reduced mass matrix is not positive definite at a generic configuration "
                                               "(massless directions or a singular independent set)");
      } else {
        // Regular there, massless bodies may still leave it singular where the model starts.
        eom_.mass_at_reference = check_massless_at_reference(m_, eom_, reference_, diags_);
      }
    }
    return true;
  }

  // ---- energy: bodies' kinetic and gravitational potential, plus user terms ----
  void energy() {
    GiNaC::ex T = 0, V = 0;
    bool ok = true;
    for (const auto& node : m_.nodes) {
      const bool body = model::is_body(node.kind) && node.kind != LeafKind::Rigid2dNodal;  // nodal: node.kinetic
      if (node.kind == LeafKind::Rigid3d) {
        T += fz(model::rigid3d::kinetic_energy(m_, node));
        V += fz(model::rigid3d::gravity_potential(m_, node));
      } else if (body) {
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
  ManifoldPoints manifold_;  // the assembled initial state and points near it (ranks on the mechanism)
  Probe reference_;  // coordinates at 0: where the automatic independent set is chosen (then checked at the start)
  std::string start_name_ = kReferenceName;  // what messages call the start
  Eom eom_;
  GiNaC::exmap frozen_;
  std::vector<int> eliminated_at_;
};

/// Every expression of the model must stay defined with the frozen values put in
/// (--freeze l=0 under a 1/l is an error at that expression, not deep in the derivation).
bool frozen_values_defined(const model::Model& m, const std::map<std::string, double>& frozen, Diagnostics& diags) {
  GiNaC::exmap values;
  for (const auto& p : m.params) {
    const auto it = frozen.find(p.name);
    if (it != frozen.end()) values[p.sym] = model::exact_decimal(it->second);
  }
  if (values.empty()) return true;
  GiNaC::exmap formals;
  for (const auto& [name, f] : m.formals) formals[f.sym] = f.value;
  bool ok = true;
  auto check = [&](const GiNaC::ex& e, const SourcePos& pos, const std::string& what) {
    // Guarded (model/exact_guard.hpp): a frozen exponent must not make GiNaC fold 3^(10^12).
    std::string why;
    std::optional<GiNaC::ex> v = e;
    for (int pass = 0; pass < 4 && !formals.empty() && v; ++pass) v = model::guarded_subs(*v, formals, why);
    if (v) v = model::guarded_subs(*v, values, why);
    std::string names;
    for (const auto& [name, value] : frozen) names += fmt::format(" {}={}", name, value);
    if (!v) {
      diags.error(pos, fmt::format("{} is undefined with --freeze{} ({})", what, names, why));
      ok = false;
      return;
    }
    // The frozen values are folded into the code: what they make must be a value it can
    // compute with (sqrt(a) with a = -1 is the complex I; a*a with a = 1e20 is 1e40).
    if (const auto problem = model::value_problem(*v)) {
      diags.error(pos, fmt::format("{} with --freeze{}: {}", what, names, problem->text()));
      ok = false;
    }
  };
  for (const auto& c : m.constraints) check(c.residual, c.pos, fmt::format("constraint '{}'", c.name));
  for (const auto& f : m.forces) check(f.value, f.pos, fmt::format("the force on '{}'", m.speeds[f.speed].name));
  for (const auto& o : m.outputs) check(o.value, o.pos, fmt::format("output '{}'", o.name));
  for (const auto& n : m.nodes) {
    const std::string label = m.label(static_cast<int>(&n - m.nodes.data()));
    check(n.mass, n.mass_pos, fmt::format("the mass of '{}'", label));
    check(n.inertia, n.pos, fmt::format("the inertia of '{}'", label));
    check(n.kinetic, n.pos, fmt::format("the kinetic energy of '{}'", label));
    check(n.potential, n.pos, fmt::format("the potential energy of '{}'", label));
  }
  for (std::size_t q = 0; q < m.coord_rates.size(); ++q)
    check(m.coord_rates[q], m.coords[q].pos, fmt::format("the rate of coordinate '{}'", m.coords[q].name));
  for (const auto& g : m.gravity) check(g, m.gravity_pos, "gravity");
  return ok;
}

}  // namespace

std::optional<Eom> derive(const model::Model& model, const Options& options, Diagnostics& diags) {
  for (const auto& [name, v] : options.frozen) {
    bool found = false;
    for (const auto& p : model.params) found = found || p.name == name;
    if (!found) {
      diags.error(SourcePos{model.nodes.empty() ? std::string() : model.nodes.back().pos.file, 0, 0},
                  fmt::format("--freeze: model '{}' has no parameter '{}'", model.name, name));
      return std::nullopt;
    }
  }
  // Parameters that shaped the model's structure (loop bounds, indices) are frozen at
  // the value the expansion used.
  Options with_structure = options;
  for (const auto& [name, v] : model.structural) with_structure.frozen.emplace(name, v);
  if (!frozen_values_defined(model, options.frozen, diags)) return std::nullopt;
  try {
    Deriver d(model, with_structure, diags);
    return d.run();
  } catch (const std::exception& e) {
    diags.error(model.nodes.empty() ? SourcePos{} : model.nodes.back().pos,
                std::string("internal error while deriving the equations: ") + e.what());
    return std::nullopt;
  }
}

}  // namespace mbsc::sym
