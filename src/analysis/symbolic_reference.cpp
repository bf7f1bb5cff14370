// SPDX-License-Identifier: GPL-2.0-or-later
// The reference of a symbolic linear model (include/mbsc/analysis/symbolic_reference.hpp).
#include "mbsc/analysis/symbolic_reference.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include "mbsc/analysis/symbolic_linear_model.hpp"
#include "mbsc/diag/diagnostics.hpp"
#include "mbsc/model/option_expression.hpp"
#include "mbsc/diag/name_suggestions.hpp"
#include "mbsc/run/run_setup.hpp"

namespace mbsc::analysis {

namespace {

// "NAME=EXPR" -> NAME, EXPR (parse_assignments has checked the form already).
std::map<std::string, std::string> texts_of(const std::vector<std::string>& items) {
  std::map<std::string, std::string> out;
  for (const auto& item : items)
    if (const auto eq = item.find('='); eq != std::string::npos) out[item.substr(0, eq)] = item.substr(eq + 1);
  return out;
}

bool close(double a, double b) { return std::fabs(a - b) <= 1e-9 * (1.0 + std::fabs(a) + std::fabs(b)); }

}  // namespace

bool symbolic_reference(const model::Model& m, const runtime::ModelTable& T, const run::ReferenceRequest& req,
                        const std::vector<std::string>& names, const run::LinearReference& ref, const ReferenceAt& reference_at,
                        const SpeedSolver& solve_speeds, SymbolicReference& out, std::string& error) {
  std::map<std::string, double> lets;
  if (!run::parse_assignments(req.lets, "--let", lets, error)) return false;
  const auto params = runtime::ModelTable::names_of(T.param_names, T.np);
  // The kept names, "all" expanded; each a run-time parameter or a --let name.
  std::vector<std::string> kept;
  for (const auto& name : names) {
    if (name == "all") {
      kept.insert(kept.end(), params.begin(), params.end());
      for (const auto& [n, v] : lets) kept.push_back(n);
      continue;
    }
    if (m.structural.count(name)) {
      error = fmt::format("--symbolic: '{}' is a structural parameter (it sets a bound or an index of the model's "
                          "structure): it cannot be left symbolic",
                          printable(name));
      return false;
    }
    if (runtime::ModelTable::find(T.param_names, T.np, name.c_str()) < 0 && !lets.count(name)) {
      std::vector<std::string> pool = params;
      for (const auto& [n, v] : lets) pool.push_back(n);
      error = fmt::format("--symbolic: '{}' is neither a parameter of the model nor a --let name{}", printable(name),
                          did_you_mean(name, pool));
      return false;
    }
    kept.push_back(name);
  }
  // Symbols: a parameter's own (the model's expressions use it), a new one for a --let name.
  GiNaC::symtab table;
  table["pi"] = GiNaC::Pi;
  table["t"] = exact_number(req.t);
  std::map<std::string, double> nominal_of;
  std::map<std::string, GiNaC::ex> symbol_of;
  for (std::size_t i = 0; i < m.params.size(); ++i) {
    const auto& p = m.params[i];
    const int k = runtime::ModelTable::find(T.param_names, T.np, p.name.c_str());
    const double v = k >= 0 ? ref.p[static_cast<std::size_t>(k)] : m.structural.count(p.name) ? m.structural.at(p.name)
                                                                                                : m.param_defaults.at(i);
    if (k >= 0) nominal_of[p.name] = v, symbol_of[p.name] = p.sym;
    table[p.name] = exact_number(v);
    out.at[p.sym] = exact_number(v);
  }
  for (const auto& [name, v] : lets) {
    nominal_of[name] = v, symbol_of[name] = GiNaC::symbol(name);
    table[name] = exact_number(v);
  }
  for (const auto& name : kept) {
    const GiNaC::ex s = symbol_of.at(name);
    if (out.nominal.count(s)) continue;
    out.symbols.push_back(GiNaC::ex_to<GiNaC::symbol>(s));
    out.nominal[s] = exact_number(nominal_of.at(name));
    table[name] = s;
    out.at.erase(s);
  }
  if (out.symbols.empty()) {
    error = "--symbolic: no names given";
    return false;
  }
  // --set values that are expressions of the symbols (--set m=k/2 with k symbolic).
  {
    for (const auto& [set_name, text] : texts_of(req.sets)) {
      const std::string& name = set_name;  // (a structured binding cannot be captured in C++17)
      const auto p = std::find_if(m.params.begin(), m.params.end(), [&](const model::Variable& v) { return v.name == name; });
      if (p == m.params.end() || out.nominal.count(p->sym)) continue;
      std::string ignored;
      const auto e = model::read_option_expression(text, model::OptionNames(table.begin(), table.end()), "", ignored);
      if (!e) continue;  // the numeric reference has read it: a number
      const GiNaC::ex folded = fold_constants(*e);
      if (!folded.info(GiNaC::info_flags::numeric)) out.at[p->sym] = folded, table[name] = folded;
    }
  }

  // The expressions given for the state and the inputs.
  const model::OptionNames readable(table.begin(), table.end());
  auto parse = [&](const std::string& flag, const std::string& name, const std::string& text, GiNaC::ex& e) {
    std::string why;
    const auto read = model::read_option_expression(text, readable, "the parameters and --let names", why);
    if (!read) {
      error = fmt::format("{} {}: {}", flag, printable(name), why);
      return false;
    }
    e = fold_constants(*read);
    return true;
  };
  std::map<std::string, GiNaC::ex> given;  // state or input name -> expression
  GiNaC::exmap model_values;                // the model's `initial` expressions: parameters as in the table
  for (std::size_t i = 0; i < m.params.size(); ++i) model_values[m.params[i].sym] = table[m.params[i].name];
  for (const auto& v : m.initial_values) given[v.name] = fold_constants(v.value.subs(model_values));
  for (const auto& [name, text] : texts_of(req.inits))
    if (!parse("--init", name, text, given[name])) return false;
  for (const auto& [name, text] : texts_of(req.inputs))
    if (!parse("--input", name, text, given[name])) return false;

  // Which values change with which symbol: the reference again with one symbol moved.
  const auto state_names = runtime::ModelTable::names_of(T.state_names, T.nx);
  const auto input_names = runtime::ModelTable::names_of(T.input_names, T.nin);
  std::vector<std::optional<std::string>> moved_by(state_names.size() + input_names.size());
  for (std::size_t k = 0; k < out.symbols.size(); ++k) {
    const std::string& name = out.symbols[k].get_name();
    const double v = nominal_of.at(name), h = 1e-3 * std::max(1.0, std::fabs(v));
    run::LinearReference moved;
    if (!reference_at({{name, v + h}}, moved, error)) {
      error = fmt::format("--symbolic {}: the reference at {} = {} (to see what depends on it): {}", name, name, v + h, error);
      return false;
    }
    for (std::size_t i = 0; i < state_names.size(); ++i)
      if (!close(moved.x[i], ref.x[i]) && !moved_by[i]) moved_by[i] = name;
    for (std::size_t i = 0; i < input_names.size(); ++i)
      if (!close(moved.u[i], ref.u[i]) && !moved_by[state_names.size() + i]) moved_by[state_names.size() + i] = name;
    GiNaC::exmap at_moved = out.nominal;
    at_moved[out.symbols[k]] = exact_number(v + h);
    out.moved.push_back({name, v + h, at_moved, moved});
  }
  // Whether e follows the reference at the nominal values and at every probe; else `why`.
  auto follows = [&](const GiNaC::ex& e, std::size_t slot, bool input, std::string& why) {
    const double here = input ? ref.u[slot - state_names.size()] : ref.x[slot];
    if (!close(nominal_value(e, out.nominal), here)) {
      why = fmt::format("{} at the nominal values, the reference {}", nominal_value(e, out.nominal), here);
      return false;
    }
    for (const auto& probe : out.moved) {
      const double want = input ? probe.ref.u[slot - state_names.size()] : probe.ref.x[slot];
      if (!close(nominal_value(e, probe.at), want)) {
        why = fmt::format("{} instead of {} when the symbols move", nominal_value(e, probe.at), want);
        return false;
      }
    }
    return true;
  };
  // A value at the rounding level of the assembly (1e-12 of the largest coordinate, or
  // speed) is that of an exact zero: kept, it would leave terms of 1e-16 in every entry.
  double largest_q = 0.0, largest_u = 0.0;
  for (std::size_t i = 0; i < state_names.size(); ++i)
    (i < m.coords.size() ? largest_q : largest_u) = std::max(i < m.coords.size() ? largest_q : largest_u, std::fabs(ref.x[i]));
  auto snapped = [&](double x, std::size_t slot) {
    const double scale = slot < m.coords.size() ? largest_q : slot < state_names.size() ? largest_u : 0.0;
    return std::fabs(x) <= 1e-12 * scale ? 0.0 : x;
  };
  std::vector<int> unresolved;  // speeds left to the velocity constraints
  auto value_of = [&](const std::string& name, std::size_t slot, bool input, GiNaC::ex& e) {
    const double here = input ? ref.u[slot - state_names.size()] : ref.x[slot];
    if (!moved_by[slot]) {
      e = exact_number(snapped(here, slot));
      return true;
    }
    const bool speed = !input && slot >= m.coords.size();
    const auto g = given.find(name);
    std::string why = "not given";
    if (g != given.end() && follows(g->second, slot, input, why)) {
      e = g->second;
      return true;
    }
    if (speed) {
      unresolved.push_back(static_cast<int>(slot));
      return true;
    }
    error = fmt::format("--symbolic {}: the reference value of {} changes with {} but {}: give it as an expression that "
                        "follows it ({} {}=...), or leave {} numeric",
                        *moved_by[slot], name, *moved_by[slot],
                        g == given.end() ? (input ? "no expression is given" : "it is assembled or found numerically")
                                         : "the expression given for it does not (" + why + ")",
                        input ? "--input" : "--init", name, *moved_by[slot]);
    return false;
  };
  for (std::size_t i = 0; i < state_names.size(); ++i) {
    GiNaC::ex e;
    if (!value_of(state_names[i], i, false, e)) return false;
    const auto& sym = i < m.coords.size() ? m.coords[i].sym : m.speeds.at(i - m.coords.size()).sym;
    out.at[sym] = e;
  }
  for (std::size_t i = 0; i < input_names.size(); ++i) {
    GiNaC::ex e;
    if (!value_of(input_names[i], state_names.size() + i, true, e)) return false;
    out.at[m.inputs.at(i).sym] = e;
  }
  out.at[m.time] = exact_number(req.t);
  if (!unresolved.empty()) {
    for (int i : unresolved) out.at.erase(m.speeds.at(static_cast<std::size_t>(i) - m.coords.size()).sym);
    if (!solve_speeds(unresolved, out.at, error)) return false;
    for (int i : unresolved) {
      const std::size_t k = static_cast<std::size_t>(i);
      std::string why;
      if (!follows(out.at[m.speeds.at(k - m.coords.size()).sym], k, false, why)) {
        error = fmt::format("--symbolic {}: the reference value of {} changes with {}; the velocity constraints give it as an "
                            "expression that does not follow it ({}): give it with --init {}=..., or leave {} numeric",
                            *moved_by[k], state_names[k], *moved_by[k], why, state_names[k], *moved_by[k]);
        return false;
      }
    }
  }
  for (std::size_t i = 0; i < state_names.size(); ++i)
    out.state.push_back(out.at[i < m.coords.size() ? m.coords[i].sym : m.speeds.at(i - m.coords.size()).sym]);
  return true;
}

}  // namespace mbsc::analysis
