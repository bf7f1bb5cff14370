// SPDX-License-Identifier: GPL-2.0-or-later
// The rhs at the start of a run (include/mbsc/run/start_check.hpp).
//
// The generated rhs says only that a value is not finite. The model knows which force it
// added where: each force is evaluated at the start state with GiNaC, in the model's own
// symbols, and the first that is not finite is named with its position in the file.
#include "mbsc/run/start_check.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cmath>
#include <fstream>
#include <optional>

#include "mbsc/diag/diagnostics.hpp"

namespace mbsc::run {

namespace {

// The statement's text at `pos` (its line, from the column on, shortened), or "".
std::string statement_text(const SourcePos& pos) {
  std::ifstream in(pos.file);
  std::string line;
  for (int i = 0; i < pos.line && std::getline(in, line); ++i) {
  }
  if (!in || pos.col < 1 || static_cast<std::size_t>(pos.col) > line.size()) return "";
  std::string text = line.substr(static_cast<std::size_t>(pos.col - 1));
  if (const auto hash = text.find('#'); hash != std::string::npos) text = text.substr(0, hash);
  while (!text.empty() && (text.back() == ' ' || text.back() == '\r')) text.pop_back();
  return text.size() > 70 ? text.substr(0, 67) + "..." : text;
}

// The value of e at the start: NaN where it is not defined there (a division by zero),
// nullopt where it reads a symbol the start does not give (an acceleration of a nodal
// body, a friction force the generated code solves for): such a force is not judged.
std::optional<double> value_at(const GiNaC::ex& e, const GiNaC::exmap& at) {
  try {
    GiNaC::ex v = e;
    for (int pass = 0; pass < 16; ++pass) {  // a component's formals may read outer ones
      const GiNaC::ex next = v.subs(at, GiNaC::subs_options::no_pattern);
      if (next.is_equal(v)) break;
      v = next;
    }
    v = GiNaC::evalf(v);
    if (!GiNaC::is_a<GiNaC::numeric>(v)) return std::nullopt;
    if (!GiNaC::ex_to<GiNaC::numeric>(v).is_real()) return NAN;
    return GiNaC::ex_to<GiNaC::numeric>(v).to_double();
  } catch (const std::exception&) {  // a division by zero, a log of zero
    return NAN;
  }
}

// Binds `sym` to a finite `value` (CLN refuses to hold NaN or infinity); false otherwise.
bool bind_value(GiNaC::exmap& at, const GiNaC::ex& sym, double value) {
  if (!std::isfinite(value)) return false;
  at[sym] = value;
  return true;
}

}  // namespace

bool rhs_finite_at_start(const model::Model& m, const runtime::ModelTable& table, const runtime::ModelTable& full_table,
                         double t, const std::vector<double>& x, const std::vector<double>& full,
                         const std::vector<double>& u, const std::vector<double>& p, std::string& error) {
  std::vector<double> xdot(static_cast<std::size_t>(std::max(1, table.nx)));
  if (table.rhs(t, x.data(), u.data(), p.data(), xdot.data()) != 2) return true;
  // An input that is not finite at the start (1/t at t = 0) is the cause by itself.
  for (std::size_t k = 0; k < m.inputs.size() && k < u.size(); ++k)
    if (!std::isfinite(u[k])) {
      error = fmt::format("mbsc: error: the rhs is not finite at the start (t = {}): the input '{}' is {} there; "
                          "give it a value that is defined at t = {} (--input)",
                          t, m.inputs[k].name, u[k], t);
      return false;
    }
  // The model's symbols at the start: time, state, parameters, inputs, the formals of
  // component instances, then the kinematic names in order.
  GiNaC::exmap at;
  bind_value(at, m.time, t);
  for (const auto* vars : {&m.coords, &m.speeds})
    for (const auto& v : *vars) {
      const int i = runtime::ModelTable::find(full_table.state_names, full_table.nx, v.name.c_str());
      if (i >= 0) bind_value(at, v.sym, full[static_cast<std::size_t>(i)]);
    }
  for (std::size_t j = 0; j < m.params.size(); ++j) {
    const int i = runtime::ModelTable::find(table.param_names, table.np, m.params[j].name.c_str());
    bind_value(at, m.params[j].sym, i >= 0 ? p[static_cast<std::size_t>(i)] : m.param_defaults[j]);
  }
  for (std::size_t k = 0; k < m.inputs.size() && k < u.size(); ++k) bind_value(at, m.inputs[k].sym, u[k]);
  for (const auto& [name, f] : m.formals) at[f.sym] = f.value;
  for (const auto& k : m.kinematic_names)
    if (const auto v = value_at(k.value, at)) bind_value(at, k.sym, *v);
  for (const auto& f : m.forces) {
    const auto v = value_at(f.value, at);
    if (!v || std::isfinite(*v)) continue;
    const std::string text = statement_text(f.pos);
    error = fmt::format("{}:{}:{}: error: the rhs is not finite at the start (t = {}): the force {}on '{}' is {} there (a "
                        "direction between two points that coincide, a division by zero?); start elsewhere (--init) "
                        "or change the model",
                        f.pos.file, f.pos.line, f.pos.col, t, text.empty() ? "" : "of '" + printable(text) + "' ",
                        m.speeds[static_cast<std::size_t>(f.speed)].name, *v);
    return false;
  }
  std::vector<std::string> rates;
  for (int i = 0; i < table.nx; ++i)
    if (!std::isfinite(xdot[static_cast<std::size_t>(i)])) rates.push_back(table.state_names[i]);
  if (rates.empty()) {  // it stopped before writing them: a solve of a matrix that is not finite
    error = fmt::format("mbsc: error: the rhs is not finite at the start (t = {}): a matrix it solves is not finite "
                        "there (no single force is: the inertia or the constraints are not defined there?); start "
                        "elsewhere (--init)",
                        t);
    return false;
  }
  error = fmt::format("mbsc: error: the rhs is not finite at the start (t = {}): the rate{} of {} {} not finite (no single force "
                      "is: the inertia or the constraints are not defined there?); start elsewhere (--init)",
                      t, rates.size() == 1 ? "" : "s", fmt::join(rates, ", "), rates.size() == 1 ? "is" : "are");
  return false;
}

}  // namespace mbsc::run
