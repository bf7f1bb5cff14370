// SPDX-License-Identifier: GPL-2.0-or-later
#include "mbsc/sym/probe.hpp"

#include "mbsc/model/exact_guard.hpp"

#include <cmath>
#include <limits>
#include <random>

namespace mbsc::sym {

Probe::Probe(const model::Model& model, const std::map<std::string, double>& param_values, unsigned seed) {
  // mt19937's sequence is fixed by the standard, so the probe point is the same on every run.
  std::mt19937 rng(seed);
  auto next = [&rng](double lo, double hi) { return lo + (hi - lo) * (static_cast<double>(rng()) / 4294967296.0); };
  values_[model.time] = next(0.1, 1.0);
  for (const auto& q : model.coords) values_[q.sym] = next(-1.3, 1.3);
  for (const auto& u : model.speeds) values_[u.sym] = next(-1.3, 1.3);
  for (const auto& in : model.inputs) values_[in.sym] = next(-1.0, 1.0);
  bind_parameters(model, param_values);
}

Probe Probe::reference(const model::Model& model, const std::map<std::string, double>& param_values) {
  Probe p;
  p.values_[model.time] = 0.0;
  for (const auto& q : model.coords) p.values_[q.sym] = 0.0;
  for (const auto& u : model.speeds) p.values_[u.sym] = 0.0;
  for (const auto& in : model.inputs) p.values_[in.sym] = 0.0;
  p.bind_parameters(model, param_values);
  return p;
}

void Probe::bind_parameters(const model::Model& model, const std::map<std::string, double>& param_values) {
  for (size_t i = 0; i < model.params.size(); ++i) {
    auto it = param_values.find(model.params[i].name);
    values_[model.params[i].sym] = it != param_values.end() ? it->second : model.param_defaults[i];
  }
  // Formals may refer to parameters: bind them to their argument values.
  for (int pass = 0; pass < 4; ++pass)
    for (const auto& [name, f] : model.formals) values_[f.sym] = f.value.subs(values_);
}

double Probe::eval(const GiNaC::ex& e) const {
  try {
    // Only the symbols e holds (model::subs_present): linear in the model's size.
    GiNaC::ex v = GiNaC::evalf(model::subs_present(e, values_));
    if (!GiNaC::is_a<GiNaC::numeric>(v)) return std::numeric_limits<double>::quiet_NaN();
    const auto& n = GiNaC::ex_to<GiNaC::numeric>(v);
    if (!n.is_real()) return std::numeric_limits<double>::quiet_NaN();
    return n.to_double();
  } catch (const std::exception&) {
    return std::numeric_limits<double>::quiet_NaN();
  }
}

namespace {
bool has_any(const GiNaC::ex& e, const std::vector<model::Variable>& vars) {
  for (const auto& v : vars)
    if (e.has(v.sym)) return true;
  return false;
}
}  // namespace

bool is_state_free(const GiNaC::ex& e, const model::Model& model) {
  if (e.has(model.time) || has_any(e, model.coords) || has_any(e, model.speeds) || has_any(e, model.inputs)) return false;
  for (const auto& s : model.speed_dots)
    if (e.has(s)) return false;
  // Any other symbol must be a parameter or a formal.
  for (GiNaC::const_preorder_iterator it = e.preorder_begin(); it != e.preorder_end(); ++it) {
    if (!GiNaC::is_a<GiNaC::symbol>(*it)) continue;
    const std::string& name = GiNaC::ex_to<GiNaC::symbol>(*it).get_name();
    bool known = false;
    const auto f = model.formals.find(name);
    known = f != model.formals.end() && it->is_equal(f->second.sym);
    for (std::size_t i = 0; !known && i < model.params.size(); ++i) known = it->is_equal(model.params[i].sym);
    if (!known) return false;
  }
  return true;
}

}  // namespace mbsc::sym
