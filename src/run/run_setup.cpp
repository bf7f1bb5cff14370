// SPDX-License-Identifier: GPL-2.0-or-later
// Parameters and the initial state of a run (include/mbsc/run/run_setup.hpp).
#include "mbsc/run/run_setup.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <fmt/format.h>
#include <ginac/ginac.h>
#include <ostream>

#include "mbsc/diag/diagnostics.hpp"
#include "mbsc/diag/activity.hpp"
#include "mbsc/diag/name_suggestions.hpp"
#include "mbsc/driver/pipeline.hpp"
#include "mbsc/driver/work_monitor.hpp"
#include "mbsc/model/expr_convert.hpp"
#include "mbsc/model/option_expression.hpp"
#include "mbsc/model/rigid3d.hpp"
#include "mbsc/model/value_bound.hpp"

namespace mbsc::run {

std::optional<model::Model> read_model(const std::string& path, const driver::WorkArgs& work,
                                       std::vector<std::string>& sources, std::ostream& err) {
  Diagnostics diags;
  std::optional<model::Model> m;
  {
    driver::WorkMonitor monitor(work.budget, work.progress);
    try {
      m = driver::load_model(path, diags, {}, "", &sources);
    } catch (const BudgetExceeded& b) {
      diags.error(b.pos, b.message);
    }
    monitor.stop();
  }
  err << diags.format();
  if (!m || diags.has_errors()) return std::nullopt;
  return m;
}

bool parse_assignments(const std::vector<std::string>& items, const std::string& flag,
                       std::map<std::string, double>& out, std::string& error) {
  return parse_assignments(items, flag, out, error, {});
}

bool parse_assignments(const std::vector<std::string>& items, const std::string& flag,
                       std::map<std::string, double>& out, std::string& error, const std::map<std::string, double>& known) {
  model::OptionNames names;
  for (const auto& [name, v] : known) names[name] = model::exact_decimal(v);
  const std::string what = known.empty() ? "numbers and pi" : "numbers, pi and the --let names";
  for (const auto& item : items) {
    const auto eq = item.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == item.size()) {
      error = fmt::format("{} expects name=value, got '{}'", flag, printable(item));
      return false;
    }
    const std::string name = declared_name(item.substr(0, eq));
    double v = 0;
    std::string why;
    if (!model::option_value(item.substr(eq + 1), names, what, v, why)) {
      error = fmt::format("{} {}: {}", flag, printable(name), why);
      return false;
    }
    if (out.count(name)) {
      error = fmt::format("{} {} is given twice", flag, printable(name));
      return false;
    }
    out[name] = v;
  }
  return true;
}

bool check_names(const model::Model& m, const std::map<std::string, double>& sets,
                 const std::map<std::string, double>& inits, bool multipliers, std::string& error) {
  std::vector<std::string> params, state;
  for (const auto& v : m.params)
    if (!m.structural.count(v.name)) params.push_back(v.name);
  if (multipliers) params.insert(params.end(), {"baumgarte_alpha", "baumgarte_beta"});
  for (const auto& v : m.coords) state.push_back(v.name);
  for (const auto& v : m.speeds) state.push_back(v.name);
  for (const auto& [name, value] : sets)
    if (std::find(params.begin(), params.end(), name) == params.end()) {
      const bool structural = m.structural.count(name) > 0;
      error = structural ? fmt::format("--set: '{}' sets how many bodies the model's loops make; it is fixed when the "
                                       "model is read (change its default in the model)",
                                       printable(name))
                         : fmt::format("--set: the model has no parameter named '{}'{} ({})", printable(name),
                                       did_you_mean(name, params),
                                       params.empty() ? "it has no run-time parameters"
                                                      : "its parameters: " + list_names(params));
      return false;
    }
  for (const auto& [name, value] : inits)
    if (std::find(state.begin(), state.end(), name) == state.end()) {
      error = fmt::format("--init: the model has no coordinate or speed named '{}'{}", printable(name),
                          did_you_mean(name, state));
      return false;
    }
  return true;
}

bool parameter_values(const runtime::ModelTable& t, const std::map<std::string, double>& sets, std::vector<double>& p,
                      std::string& error) {
  p.assign(t.param_defaults, t.param_defaults + t.np);
  const auto names = runtime::ModelTable::names_of(t.param_names, t.np);
  for (const auto& [name, value] : sets) {
    const int i = runtime::ModelTable::find(t.param_names, t.np, name.c_str());
    if (i < 0) {
      error = fmt::format("--set: the model has no parameter named '{}'{}", printable(name), did_you_mean(name, names));
      if (t.np == 0) error += " (it has no run-time parameters)";
      return false;
    }
    p[static_cast<std::size_t>(i)] = value;
  }
  return true;
}

std::vector<std::array<int, 4>> unit_quaternion_indices(const model::Model& m, const runtime::ModelTable& t) {
  std::vector<std::array<int, 4>> out;
  for (const auto& names : model::rigid3d::unit_quaternion_names(m)) {
    std::array<int, 4> q{};
    bool found = true;
    for (std::size_t k = 0; k < 4 && found; ++k) {
      q[k] = runtime::ModelTable::find(t.state_names, t.nx, names[k].c_str());
      found = q[k] >= 0;
    }
    if (found) out.push_back(q);
  }
  return out;
}

namespace {

/// Every unit quaternion of the state divided by its norm (its direction is the rotation;
/// a norm off 1 would scale the body). One that nothing gives a value starts at the
/// identity (1, 0, 0, 0), as other coordinates start at 0; all zero when given is no
/// rotation at all, an error.
bool unit_quaternions(const model::Model& m, const runtime::ModelTable& t, InitialState& out, std::string& error) {
  for (const auto& q : unit_quaternion_indices(m, t)) {
    std::array<std::size_t, 4> at{};
    std::array<std::string, 4> names;
    for (std::size_t k = 0; k < 4; ++k) {
      at[k] = static_cast<std::size_t>(q[k]);
      names[k] = t.state_names[q[k]];
    }
    double norm2 = 0;
    for (std::size_t i : at) norm2 += out.x[i] * out.x[i];
    const bool given = std::any_of(names.begin(), names.end(), [&](const std::string& n) {
      return std::find(out.given.begin(), out.given.end(), n) != out.given.end();
    });
    if (norm2 == 0.0 && !given) {
      out.x[at[0]] = 1.0;
      continue;
    }
    const std::string list = fmt::format("{}, {}, {}, {}", names[0], names[1], names[2], names[3]);
    if (!(norm2 > 0) || !std::isfinite(norm2)) {
      error = fmt::format("the quaternion ({}) is {} at the start: give it a unit value, e.g. `initial {} = 1` in the "
                          "model or --init {}=1 (the frames' coinciding attitude)",
                          list, norm2 > 0 ? "not finite" : "all zero", names[0], names[0]);
      return false;
    }
    const double norm = std::sqrt(norm2);
    if (std::fabs(norm - 1.0) <= 1e-14) continue;
    for (std::size_t i : at) out.x[i] /= norm;
    out.normalized.push_back(fmt::format("{} (norm {:.6g})", list, norm));
  }
  return true;
}

}  // namespace

std::string unknown_input_message(const model::Model& m, const std::string& name) {
  std::string known;
  for (const auto& in : m.inputs) known += (known.empty() ? "" : ", ") + in.name;
  return fmt::format("--input: the model has no input named '{}' ({})", printable(name),
                     known.empty() ? "it has no inputs" : "its inputs: " + known);
}

bool initial_state(const model::Model& m, const runtime::ModelTable& t, const std::vector<double>& p,
                   const std::vector<double>& u0, const std::map<std::string, double>& inits, double t0,
                   InitialState& out, std::string& error) {
  const auto state = runtime::ModelTable::names_of(t.state_names, t.nx);
  out.x.assign(static_cast<std::size_t>(t.nx), 0.0);
  std::vector<bool> given(static_cast<std::size_t>(t.nx), false);
  out.given.clear();
  // The model's `initial` values, with this run's parameters.
  GiNaC::exmap values;
  for (std::size_t i = 0; i < m.params.size(); ++i) {
    const int k = runtime::ModelTable::find(t.param_names, t.np, m.params[i].name.c_str());
    if (k >= 0) values[m.params[i].sym] = p[static_cast<std::size_t>(k)];
    else if (m.structural.count(m.params[i].name)) values[m.params[i].sym] = m.structural.at(m.params[i].name);
    else if (i < m.param_defaults.size()) values[m.params[i].sym] = m.param_defaults[i];
  }
  auto set = [&](const std::string& name, double v) {
    const int k = runtime::ModelTable::find(t.state_names, t.nx, name.c_str());
    out.x[static_cast<std::size_t>(k)] = v;
    if (!given[static_cast<std::size_t>(k)]) out.given.push_back(name);
    given[static_cast<std::size_t>(k)] = true;
  };
  // --init naming a coordinate turns the model's fixed coordinates into guesses (the
  // user chose another configuration); naming a speed drops the model's speeds.
  bool init_q = false, init_u = false;
  for (const auto& [name, v] : inits) {
    const int k = runtime::ModelTable::find(t.state_names, t.nx, name.c_str());
    if (k < 0) {
      error = fmt::format("--init: the model has no coordinate or speed named '{}'{}", printable(name),
                          did_you_mean(name, state));
      return false;
    }
    (k < t.nq ? init_q : init_u) = true;
  }
  std::vector<std::pair<GiNaC::ex, double>> numbers;
  for (const auto& [sym, value] : values)
    if (GiNaC::is_a<GiNaC::numeric>(value)) numbers.emplace_back(sym, GiNaC::ex_to<GiNaC::numeric>(value).to_double());
  auto value_of = [&](const model::NamedExpr& iv, double& v) {
    auto not_finite = [&] {
      error = fmt::format("{}:{}:{}: the initial value of '{}' is not a finite number with these parameters",
                          iv.pos.file, iv.pos.line, iv.pos.col, iv.name);
      return false;
    };
    // Undefined in double arithmetic (a division by zero at these parameters): refused
    // before GiNaC meets it, which throws from inside its constructors and leaks what
    // they had built. Otherwise the exact value, evaluated by GiNaC.
    if (const auto d = model::value_at(iv.value, numbers); d && !std::isfinite(*d)) return not_finite();
    GiNaC::ex e;
    try {
      e = GiNaC::evalf(iv.value.subs(values));
    } catch (const std::exception&) {  // (what the walk does not know)
      e = GiNaC::ex();
    }
    if (!GiNaC::is_a<GiNaC::numeric>(e) || !std::isfinite(GiNaC::ex_to<GiNaC::numeric>(e).to_double())) return not_finite();
    v = GiNaC::ex_to<GiNaC::numeric>(e).to_double();
    return true;
  };
  for (const auto* list : {&m.initial_guesses, &m.initial_values})
    for (const auto& iv : *list) {
      const int k = runtime::ModelTable::find(t.state_names, t.nx, iv.name.c_str());
      if (k < 0) continue;  // (a name the generated state does not carry)
      double v = 0;
      if (!value_of(iv, v)) return false;
      const bool is_q = k < t.nq;
      if (list == &m.initial_guesses || (is_q && init_q)) out.x[static_cast<std::size_t>(k)] = v;  // a guess
      else if (!(!is_q && init_u)) set(iv.name, v);
    }
  for (const auto& [name, v] : inits) set(name, v);
  if (!unit_quaternions(m, t, out, error)) return false;
  // Assembly: the given entries stay, the others follow from the constraints (the unit
  // quaternions kept unit).
  std::vector<int> quaternions;
  for (const auto& e : unit_quaternion_indices(m, t)) quaternions.insert(quaternions.end(), e.begin(), e.end());
  const runtime::AssemblyModel am =
      runtime::assembly_model_of(t, quaternions.data(), static_cast<int>(quaternions.size() / 4));
  std::vector<bool> given_q(given.begin(), given.begin() + t.nq), given_u(given.begin() + t.nq, given.end());
  out.assembly = runtime::assemble(am, t0, out.x, given_q, given_u, u0.empty() ? nullptr : u0.data(), p.data());
  if (!out.assembly.ok()) {
    std::string list;
    for (const auto& g : out.given) list += (list.empty() ? "" : ", ") + g;
    error = fmt::format("the initial state is inconsistent: {} (given: {})", out.assembly.message,
                        list.empty() ? "nothing; every coordinate was guessed 0" : list);
    return false;
  }
  for (double v : out.x)
    if (!std::isfinite(v)) {
      error = "the initial state is not finite after assembly";
      return false;
    }
  return true;
}

}  // namespace mbsc::run
