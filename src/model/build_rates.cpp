// SPDX-License-Identifier: GPL-2.0-or-later
// The kinematic transformations: each node's speed definitions s = Y q0' + y solved for
// the rates of its coordinates (leaf kinds give theirs directly), those rates put in for
// q0' in the velocity constraints and forces, and the constraints checked (no input; a
// velocity constraint linear in the speeds unless declared nonlinear).
#include "build_internal.hpp"

#include <fmt/format.h>

#include <exception>

#include "mbsc/diag/activity.hpp"
#include "mbsc/diag/limits.hpp"
#include "mbsc/model/exact_guard.hpp"

namespace mbsc::model::build_detail {

/// Each node's speed definitions s = Y q0' + y are solved for the rates of its own
/// coordinates (a small linear solve per node; leaf kinds give theirs directly).
void Builder::solve_coordinate_rates() {
  m_.coord_rates.assign(m_.coords.size(), GiNaC::ex(0));
  std::vector<bool> done(m_.coords.size(), false);
  GiNaC::exmap known_rates;  // q0' -> its rate, for the coordinates solved so far
  for (auto& [q, rate] : builtin_rates_) {
    m_.coord_rates[q] = rate;
    done[q] = true;
    known_rates[coord_dot_[q]] = rate;
  }
  // Group definitions by the node of their speed.
  std::vector<std::vector<const Definition*>> defs_of(m_.nodes.size());
  for (const auto& d : definitions_) defs_of[static_cast<std::size_t>(m_.speeds[d.speed].node)].push_back(&d);
  for (size_t n = 0; n < m_.nodes.size(); ++n) {
    checkpoint("solving the speed definitions of", fmt::format("subsystem '{}'", m_.label(static_cast<int>(n))),
               m_.nodes[n].pos, n, m_.nodes.size());
    std::vector<int> unknown;
    for (int q : m_.nodes[n].coords)
      if (!done[q]) unknown.push_back(q);
    const std::vector<const Definition*>& defs = defs_of[n];
    if (unknown.empty() && defs.empty()) continue;
    // Rates of coordinates outside this node may appear in definitions: those are known.
    std::vector<GiNaC::ex> values;
    for (const auto* d : defs) values.push_back(subs_present(d->value, known_rates));
    GiNaC::lst eqs, vars;
    for (int q : unknown) vars.append(coord_dot_[q]);
    for (std::size_t k = 0; k < defs.size(); ++k) eqs.append(GiNaC::ex(m_.speeds[defs[k]->speed].sym) == values[k]);
    if (defs.size() != unknown.size()) {
      if (defs.size() < unknown.size()) {
        for (size_t i = 0; i < unknown.size(); ++i) {
          bool used = false;
          for (const auto* d : defs) used = used || d->value.has(coord_dot_[unknown[i]]);
          if (!used || i >= defs.size()) {
            const auto& c = m_.coords[unknown[i]];
            auto leaf = c.name.substr(c.name.rfind('.') == std::string::npos ? 0 : c.name.rfind('.') + 1);
            diags_.error(c.pos, fmt::format("coordinate '{}' has no speed defining its rate (add `speed d{} = {}'`)", c.name, leaf, leaf));
            break;
          }
        }
      } else {
        const auto* d = defs[unknown.size()];
        diags_.error(d->pos, fmt::format("speed '{}' is defined by coordinate rates, but subsystem '{}' has {} coordinate(s) and {} definitions",
                                         m_.speeds[d->speed].name, m_.nodes[n].name, unknown.size(), defs.size()));
      }
      continue;
    }
    // Each definition must be linear in the unknown rates.
    bool linear = true;
    for (std::size_t k = 0; k < defs.size(); ++k)
      for (int q : unknown)
        if (!values[k].diff(coord_dot_[q], 2).is_zero()) {
          diags_.error(defs[k]->pos, fmt::format("definition of speed '{}' is not linear in the coordinate rates",
                                                 m_.speeds[defs[k]->speed].name));
          linear = false;
        }
    if (!linear) continue;
    GiNaC::ex sol;
    if (unknown.size() == 1) {
      // One rate: s = c q' + r gives q' = (s - r) / c directly (lsolve would normalize,
      // expanding a coefficient such as (a + b + ... + th)^40 term by term).
      const GiNaC::ex qd = coord_dot_[unknown[0]];
      const GiNaC::ex c = values[0].diff(GiNaC::ex_to<GiNaC::symbol>(qd));
      if (!c.is_zero())
        sol = GiNaC::lst{qd == (GiNaC::ex(m_.speeds[defs[0]->speed].sym) - values[0].subs(qd == 0)) / c};
      else
        sol = GiNaC::lst{};
    } else {
      bool small = true;
      for (const auto& v : values) small = small && expanded_terms(v) <= limits::kMaxExpandedTerms;
      if (!small) {
        diags_.error(defs.front()->pos, fmt::format("the speed definitions of subsystem '{}' are too large to solve for "
                                                    "the coordinate rates symbolically",
                                                    m_.label(static_cast<int>(n))));
        continue;
      }
      try {
        sol = GiNaC::lsolve(eqs, vars);
      } catch (const std::exception&) {
        sol = GiNaC::lst{};
      }
    }
    if (sol.nops() != unknown.size()) {
      diags_.error(defs.front()->pos, fmt::format("the speed definitions of subsystem '{}' cannot be solved for the coordinate rates",
                                                  m_.label(static_cast<int>(n))));
      continue;
    }
    for (size_t i = 0; i < unknown.size(); ++i) {
      m_.coord_rates[unknown[i]] = normal_if_small(sol.op(i).rhs());
      done[unknown[i]] = true;
      known_rates[coord_dot_[unknown[i]]] = m_.coord_rates[unknown[i]];
    }
  }
}

/// Replace q0' placeholders (velocity constraints, custom forces) by the coordinate rates.
void Builder::substitute_coordinate_rates() {
  GiNaC::exmap rates;
  for (size_t q = 0; q < m_.coords.size(); ++q) rates[coord_dot_[q]] = m_.coord_rates[q];
  // Guarded: a rate with a number in it, put into a power, is folded by GiNaC.
  auto put_rates = [&](GiNaC::ex& e, const SourcePos& pos, const std::string& what) {
    std::string why;
    auto out = guarded_subs(e, rates, why);
    if (!out) {
      diags_.error(pos, fmt::format("{} cannot be written with the coordinate rates: {}", what, why));
      return false;
    }
    e = *out;
    return true;
  };
  for (auto& c : m_.constraints)
    if (put_rates(c.residual, c.pos, fmt::format("constraint '{}'", c.name))) check_constraint(c);
  for (auto& f : m_.forces) put_rates(f.value, f.pos, fmt::format("the force on '{}'", m_.speeds[f.speed].name));
}

void Builder::check_constraint(const Constraint& c) {
  // Inputs have no known rates, so a constraint cannot be differentiated through them.
  for (const auto& in : m_.inputs)
    if (c.residual.has(in.sym)) {
      diags_.error(c.pos, fmt::format("constraint '{}' depends on input '{}'; constraints may use coordinates, speeds, "
                                      "parameters and t only (prescribe motions as functions of t)",
                                      c.name, in.name));
      return;
    }
  if (c.level == Constraint::Level::Position) {
    return;
  }
  bool has_speed = false;
  for (size_t u = 0; u < m_.speeds.size(); ++u) {
    if (!c.residual.has(m_.speeds[u].sym)) continue;
    has_speed = true;
    if (!c.nonlinear && !c.residual.diff(m_.speeds[u].sym, 2).is_zero()) {
      diags_.error(c.pos, fmt::format("velocity constraint '{}' is not linear in the speed '{}'; write it in a "
                                      "`constraint velocity nonlinear` block",
                                      c.name, m_.speeds[u].name));
      return;
    }
  }
  if (!has_speed)
    diags_.error(c.pos, fmt::format("velocity constraint '{}' contains no speed; write it as a position constraint", c.name));
}

}  // namespace mbsc::model::build_detail
