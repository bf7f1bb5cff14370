// SPDX-License-Identifier: GPL-2.0-or-later
#include "mbsc/sym/minimal_state.hpp"

#include "mbsc/sym/pivot_elimination.hpp"
#include "mbsc/sym/probe.hpp"
#include "mbsc/sym/symbol_set.hpp"

#include <fmt/format.h>

#include <functional>
#include <map>
#include <set>
#include <unordered_map>

namespace mbsc::sym {

namespace {

class MinimalStateBuilder {
 public:
  MinimalStateBuilder(const model::Model& m, const Eom& eom, Diagnostics& diags)
      : m_(m),
        eom_(eom),
        diags_(diags),
        eliminated_at_(m.speeds.size(), -1),
        order1_(velocity_residuals(m)),
        probe_(m, eom.param_values) {
    for (const auto& r : eom.nodes)
      for (int s : r.dependent) eliminated_at_[static_cast<std::size_t>(s)] = r.node;
  }

  std::optional<MinimalState> run() {
    MinimalState out;
    explicit_coordinates(out);
    std::vector<std::vector<ir::Step>> per_node(m_.nodes.size());
    for (std::size_t n = 0; n < m_.nodes.size(); ++n)
      if (!dependent_speeds(static_cast<int>(n), per_node[n])) return std::nullopt;
    for (int n = m_.root(); n >= 0; --n)
      for (const auto& d : per_node[static_cast<std::size_t>(n)]) out.speeds.push_back(d);
    return out;
  }

 private:
  // ---- coordinates given explicitly by a position constraint ----
  void explicit_coordinates(MinimalState& out) {
    const std::size_t nq = m_.coords.size();
    std::set<int> dependent_speed_syms;
    for (std::size_t s = 0; s < m_.speeds.size(); ++s)
      if (eliminated_at_[s] >= 0) dependent_speed_syms.insert(static_cast<int>(s));
    // A coordinate whose rate is a dependent speed is the natural one to eliminate.
    auto rate_is_dependent = [&](std::size_t c) {
      for (int s : dependent_speed_syms)
        if (m_.coord_rates[c].is_equal(m_.speeds[static_cast<std::size_t>(s)].sym)) return true;
      return false;
    };
    std::map<int, GiNaC::ex> direct;  // coordinate -> value as solved (may read eliminated ones)
    // Eliminated coordinate -> the coordinates not (yet) eliminated that its value reads,
    // through the eliminated ones it reads: a new value may not read its own coordinate
    // that way (circular). Sets, not substituted values: substituting every earlier value
    // was cubic in a chain's length.
    std::map<int, std::set<int>> reads;
    auto coordinate_of = [&](const GiNaC::ex& sym) {
      const auto it = coord_index_.find(sym);
      return it == coord_index_.end() ? -1 : it->second;
    };
    for (std::size_t q = 0; q < nq; ++q) coord_index_[m_.coords[q].sym] = static_cast<int>(q);
    // A kinematic name (a named body rotation entry, Model::kinematic_names) stands for an
    // expression in the joint angles above its body: it reads the coordinates its value
    // reads, through earlier names (a value reads only earlier ones).
    std::map<GiNaC::ex, std::set<int>, GiNaC::ex_is_less> name_reads;
    for (const auto& k : m_.kinematic_names) {
      std::set<int>& set = name_reads[k.sym];
      for (GiNaC::const_preorder_iterator it = k.value.preorder_begin(); it != k.value.preorder_end(); ++it) {
        if (!GiNaC::is_a<GiNaC::symbol>(*it)) continue;
        const auto n = name_reads.find(*it);
        if (n != name_reads.end()) set.insert(n->second.begin(), n->second.end());
        if (const int x = coordinate_of(*it); x >= 0) set.insert(x);
      }
    }
    auto a_name_reads = [&](const GiNaC::ex& e, int q) {
      if (name_reads.empty()) return false;
      for (GiNaC::const_preorder_iterator it = e.preorder_begin(); it != e.preorder_end(); ++it) {
        const auto n = name_reads.find(*it);
        if (n != name_reads.end() && n->second.count(q)) return true;
      }
      return false;
    };
    auto reads_of = [&](const GiNaC::ex& value) {
      std::set<int> out;
      for (GiNaC::const_preorder_iterator it = value.preorder_begin(); it != value.preorder_end(); ++it) {
        if (!GiNaC::is_a<GiNaC::symbol>(*it)) continue;
        const auto n = name_reads.find(*it);
        std::set<int> xs;
        if (n != name_reads.end()) xs = n->second;
        else if (const int x = coordinate_of(*it); x >= 0) xs.insert(x);
        for (const int x : xs) {
          const auto r = reads.find(x);
          if (r == reads.end()) out.insert(x);
          else out.insert(r->second.begin(), r->second.end());
        }
      }
      return out;
    };
    // Sweep 0: the rows written for one coordinate (a joint with a coordinate places its
    // second body), so a tree of such joints keeps exactly the joint coordinates whatever
    // the order of its rows and of the other rows that read its bodies (a loop closure).
    // Sweep 1: the other rows in model order, dependent rates first, then any.
    std::vector<bool> used(m_.constraints.size(), false);
    for (int sweep = 0; sweep < 2; ++sweep)
      for (std::size_t ci = 0; ci < m_.constraints.size(); ++ci) {
        const auto& c = m_.constraints[ci];
        if (c.level != model::Constraint::Level::Position || used[ci]) continue;
        if (sweep == 0 && c.explicit_coordinate < 0) continue;
        int pick = -1;
        GiNaC::ex pick_value;
        std::set<int> pick_reads;
        const SymbolSet in_residual(c.residual);
        for (int pass = sweep == 0 ? -1 : 0; pass < (sweep == 0 ? 0 : 2) && pick < 0; ++pass) {
          for (std::size_t q = 0; q < nq && pick < 0; ++q) {
            const GiNaC::symbol& sym = m_.coords[q].sym;
            if (direct.count(static_cast<int>(q)) || !in_residual.contains(sym)) continue;
            if (pass == -1 && static_cast<int>(q) != c.explicit_coordinate) continue;
            if (pass <= 0 && !rate_is_dependent(q)) continue;
            const GiNaC::ex a = c.residual.diff(sym);
            if (!GiNaC::is_a<GiNaC::numeric>(a) || a.is_zero()) continue;
            // Linear in the coordinate through the names too: none of them reads it.
            if (a_name_reads(c.residual, static_cast<int>(q))) continue;
            const GiNaC::ex value = -c.residual.subs(sym == 0) / a;
            std::set<int> value_reads = reads_of(value);
            if (value_reads.count(static_cast<int>(q))) continue;  // would be circular
            pick = static_cast<int>(q);
            pick_value = value;
            pick_reads = std::move(value_reads);
          }
        }
        if (pick < 0) continue;
        used[ci] = true;
        for (auto& [k, set] : reads)
          if (set.erase(pick)) set.insert(pick_reads.begin(), pick_reads.end());
        reads[pick] = std::move(pick_reads);
        direct[pick] = pick_value;
      }
    // Evaluation order: each after the eliminated coordinates it reads (depth first).
    std::set<int> done;
    std::function<void(int)> visit = [&](int q) {
      if (done.count(q)) return;
      done.insert(q);
      const SymbolSet in_value(direct.at(q));
      for (const auto& entry : direct)
        if (in_value.contains(m_.coords[static_cast<std::size_t>(entry.first)].sym)) visit(entry.first);
      out.coords.push_back(ir::Define{m_.coords[static_cast<std::size_t>(q)].sym, direct.at(q), true});
      out.eliminated_coords.push_back(q);
    };
    for (const auto& [q, v] : direct) visit(q);
    for (std::size_t q = 0; q < nq; ++q)
      if (!direct.count(static_cast<int>(q))) out.kept_coords.push_back(static_cast<int>(q));
  }

  // ---- dependent speeds at order 1 ----
  /// Speed s in terms of the speeds `avail` (a node's y), composing the order-1
  /// relations of the descendants where s was eliminated.
  GiNaC::ex express(int s, const std::set<int>& avail, std::map<int, GiNaC::ex>& memo) {
    if (avail.count(s)) return m_.speeds[static_cast<std::size_t>(s)].sym;
    auto it = memo.find(s);
    if (it != memo.end()) return it->second;
    const int d = eliminated_at_[static_cast<std::size_t>(s)];
    const NodeResult& r = eom_.nodes[static_cast<std::size_t>(d)];
    auto rel = relation_.find(s);
    if (rel == relation_.end()) throw NestedNumeric{d};
    GiNaC::ex e = rel->second;
    GiNaC::exmap sub;
    for (int t : r.y)
      if (!avail.count(t) && e.has(m_.speeds[static_cast<std::size_t>(t)].sym))
        sub[m_.speeds[static_cast<std::size_t>(t)].sym] = express(t, avail, memo);
    if (!sub.empty()) e = e.subs(sub, GiNaC::subs_options::no_pattern);
    memo[s] = e;
    return e;
  }

  struct NestedNumeric {
    int node;  // the descendant whose dependent speeds are only known numerically
  };

  bool dependent_speeds(int n, std::vector<ir::Step>& steps) {
    const NodeResult& r = eom_.nodes[static_cast<std::size_t>(n)];
    if (r.dependent.empty()) return true;
    // Order-1 rows with the descendants' dependent speeds composed in.
    const std::set<int> avail(r.y.begin(), r.y.end());
    std::map<int, GiNaC::ex> memo;
    std::vector<GiNaC::ex> rows;
    try {
      for (int ci : r.rows) {
        GiNaC::ex g = order1_[static_cast<std::size_t>(ci)];
        GiNaC::exmap sub;
        const SymbolSet in_g(g);
        for (std::size_t j = 0; j < m_.speeds.size(); ++j)
          if (eliminated_at_[j] >= 0 && !avail.count(static_cast<int>(j)) && in_g.contains(m_.speeds[j].sym))
            sub[m_.speeds[j].sym] = express(static_cast<int>(j), avail, memo);
        rows.push_back(sub.empty() ? g : g.subs(sub, GiNaC::subs_options::no_pattern));
      }
    } catch (const NestedNumeric& e) {
      diags_.error(m_.nodes[static_cast<std::size_t>(n)].pos,
                   fmt::format("--state minimal: subsystem '{}' needs the dependent speeds of '{}' in closed form, "
                               "but those are solved numerically; use --state full",
                               m_.label(n), m_.label(e.node)));
      return false;
    }
    // Only rows affine in the dependent speeds can be solved for them (not a `nonlinear` block).
    // (Symbol sets: a row reads a few speeds, and has() per pair was cubic in a chain.)
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const SymbolSet in_row(rows[i]);
      for (int s : r.dependent) {
        if (!in_row.contains(m_.speeds[static_cast<std::size_t>(s)].sym)) continue;
        const GiNaC::ex slope = rows[i].diff(m_.speeds[static_cast<std::size_t>(s)].sym);
        const SymbolSet in_slope(slope);
        bool affine = true;
        for (int t : r.dependent) affine = affine && !in_slope.contains(m_.speeds[static_cast<std::size_t>(t)].sym);
        if (affine) continue;
        const auto& c = m_.constraints[static_cast<std::size_t>(r.rows[i])];
        diags_.error(c.pos, fmt::format("--state minimal: constraint '{}' is not linear in the speed '{}', so that "
                                        "speed cannot be rebuilt from the independent ones; use --state full",
                                        c.name, m_.speeds[static_cast<std::size_t>(s)].name));
        return false;
      }
    }
    if (!r.symbolic_complement) {
      // The state-free pivots symbolically (as for the rates), then X = the core's
      // speeds: A X = -(rows at X = 0), A = d rows / d X; the pivots' speeds follow.
      GiNaC::exmap zero;
      for (int s : r.dependent) zero[m_.speeds[static_cast<std::size_t>(s)].sym] = 0;
      std::vector<LinearRow> linear;
      for (const auto& g : rows) {
        LinearRow row;
        for (int s : r.dependent) row.c.push_back(g.diff(m_.speeds[static_cast<std::size_t>(s)].sym));
        row.rest = g.subs(zero, GiNaC::subs_options::no_pattern);
        linear.push_back(row);
      }
      const Elimination elim = eliminate_state_free_pivots(std::move(linear), m_, probe_);
      auto speed_of = [&](int j) { return m_.speeds[static_cast<std::size_t>(r.dependent[static_cast<std::size_t>(j)])].sym; };
      const auto blocks = elim.core_vars.empty() ? std::vector<CoreBlock>{} : core_blocks(elim);
      for (std::size_t b = 0; b < blocks.size(); ++b) {
        ir::Solve solve;
        solve.label = fmt::format("subsystem '{}': dependent speeds", m_.label(n));
        if (blocks.size() > 1) solve.label += fmt::format(", part {} of {}", b + 1, blocks.size());
        solve.n = static_cast<int>(blocks[b].vars.size());
        solve.k = 1;
        for (int i : blocks[b].rows) {
          const LinearRow& row = elim.rows[static_cast<std::size_t>(i)];
          for (int j : blocks[b].vars) solve.A.push_back(row.c[static_cast<std::size_t>(j)]);
          solve.B.push_back(-row.rest);
        }
        if (blocks[b].rows.size() > blocks[b].vars.size()) {  // rows redundant on the mechanism
          to_normal_equations(solve.A, solve.B, static_cast<int>(blocks[b].rows.size()), solve.n, 1);
          solve.label += ", least squares";
        }
        for (int j : blocks[b].vars) solve.X.push_back(speed_of(j));
        steps.push_back(solve);
      }
      std::map<int, GiNaC::ex> value;
      for (int j : elim.core_vars) value[j] = speed_of(j);
      for (const auto& p : elim.pivots) value[p.var] = speed_of(p.var);  // read as variables once defined
      for (auto it = elim.pivots.rbegin(); it != elim.pivots.rend(); ++it)
        steps.push_back(ir::Define{speed_of(it->var), pivot_value(*it, value), true});
      return true;
    }
    GiNaC::exmap solved;  // in y# only, for the ancestors
    if (!r.rate_steps.empty()) {
      // Same rows and order as the rates: each step reads the speeds solved before it.
      for (std::size_t k = 0; k < r.rate_steps.size(); ++k) {
        const int s = r.rate_steps[k].first;
        const GiNaC::symbol& u = m_.speeds[static_cast<std::size_t>(s)].sym;
        const GiNaC::ex& g = rows[static_cast<std::size_t>(r.step_rows[k])];
        const GiNaC::ex value = -g.subs(u == 0) / g.diff(u);
        steps.push_back(ir::Define{u, value, true});
        const GiNaC::ex in_independent = value.subs(solved, GiNaC::subs_options::no_pattern);
        relation_[s] = in_independent;
        solved[u] = in_independent;
      }
      return true;
    }
    // Small block with a state-free determinant: exact solve.
    GiNaC::lst equations, unknowns;
    for (const auto& g : rows) equations.append(g == 0);
    for (int s : r.dependent) unknowns.append(m_.speeds[static_cast<std::size_t>(s)].sym);
    const GiNaC::ex solution = GiNaC::lsolve(equations, unknowns);
    if (solution.nops() != unknowns.nops()) {
      diags_.error(m_.nodes[static_cast<std::size_t>(n)].pos,
                   fmt::format("--state minimal: the velocity constraints of subsystem '{}' do not determine its "
                               "dependent speeds",
                               m_.label(n)));
      return false;
    }
    for (std::size_t i = 0; i < solution.nops(); ++i) {
      const int s = r.dependent[i];
      const GiNaC::ex value = solution.op(i).rhs();
      steps.push_back(ir::Define{m_.speeds[static_cast<std::size_t>(s)].sym, value, true});
      relation_[s] = value;
    }
    return true;
  }

  const model::Model& m_;
  const Eom& eom_;
  Diagnostics& diags_;
  std::vector<int> eliminated_at_;    // speed -> node where it is dependent (-1: root independent)
  std::vector<GiNaC::ex> order1_;     // order-1 residual of every constraint, model order
  Probe probe_;                       // decides which pivots are nonzero (parameter defaults)
  std::map<int, GiNaC::ex> relation_;  // dependent speed -> value in its node's y#
  std::unordered_map<GiNaC::ex, int, ExHash, GiNaC::ex_is_equal> coord_index_;  // coordinate symbol -> index
};

}  // namespace

std::optional<MinimalState> minimal_state(const model::Model& m, const Eom& eom, Diagnostics& diags) {
  try {
    return MinimalStateBuilder(m, eom, diags).run();
  } catch (const std::exception& e) {
    diags.error(m.nodes.empty() ? SourcePos{} : m.nodes.back().pos,
                std::string("internal error while building the minimal state: ") + e.what());
    return std::nullopt;
  }
}

}  // namespace mbsc::sym
