// SPDX-License-Identifier: GPL-2.0-or-later
// The compiled model and the reference that `mbsc linearize` and `mbsc eig` start from.
#include "mbsc/run/linear_reference.hpp"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <map>
#include <ostream>

#include "mbsc/diag/diagnostics.hpp"
#include "mbsc/diag/name_suggestions.hpp"
#include "mbsc/run/run_setup.hpp"

namespace mbsc::run {

std::unique_ptr<CompiledModel> compile_for_linearization(const ReferenceRequest& req, const model::Model& m,
                                                         const std::vector<std::string>& sources, std::ostream& err,
                                                         int& exit_code) {
  exit_code = 1;
  if (!m.frictions.empty()) {
    err << fmt::format("{}:{}:{}: error: model '{}' has Coulomb friction: its linear model is not defined (the friction "
                       "force is not differentiable where a joint slides)\n",
                       m.name_pos.file, m.name_pos.line, m.name_pos.col, m.name);
    return nullptr;
  }
  CompileRequest c;
  c.model_path = req.model_path;
  c.cache_dir = req.cache_dir;
  c.work = req.work;
  c.linear_parts = true;
  return compile_model(c, m, sources, err, exit_code);
}

runtime::LinearParts parts_of(const CompiledModel& c) {
  const runtime::ModelTable& t = c.table();
  return runtime::LinearParts{c.linear_parts(), t.nq_full, t.nu_full, t.nc, t.nposc, t.nin};
}

bool reference_state(const model::Model& m, const CompiledModel& c, const ReferenceRequest& req, LinearReference& ref,
                     std::string& error) {
  const runtime::ModelTable& t = c.table();
  std::map<std::string, double> lets, sets, inits, inputs;
  if (!parse_assignments(req.lets, "--let", lets, error)) return false;
  for (const auto& [name, v] : lets)
    for (const auto& p : m.params)
      if (p.name == name) {
        error = fmt::format("--let {}: the model has a parameter of that name (set it with --set)", printable(name));
        return false;
      }
  for (const auto& [name, v] : req.overrides)
    if (lets.count(name)) lets[name] = v;
  if (!parse_assignments(req.sets, "--set", sets, error, lets)) return false;
  for (const auto& [name, v] : req.overrides)
    if (!lets.count(name)) sets[name] = v;
  if (!check_names(m, sets, {}, false, error)) return false;
  if (!parameter_values(t, sets, ref.p, error)) return false;
  std::map<std::string, double> known = lets;
  for (int i = 0; i < t.np; ++i) known[t.param_names[i]] = ref.p[static_cast<std::size_t>(i)];
  if (!parse_assignments(req.inits, "--init", inits, error, known) || !parse_assignments(req.inputs, "--input", inputs, error, known))
    return false;
  if (!check_names(m, {}, inits, false, error)) return false;
  ref.u.assign(static_cast<std::size_t>(std::max(1, t.nin)), 0.0);
  const auto input_names = runtime::ModelTable::names_of(t.input_names, t.nin);
  for (const auto& [name, value] : inputs) {
    const int k = runtime::ModelTable::find(t.input_names, t.nin, name.c_str());
    if (k < 0) {
      error = t.nin == 0 ? fmt::format("--input: the model has no inputs (got '{}')", printable(name))
                         : fmt::format("--input: the model has no input named '{}'{}", printable(name), did_you_mean(name, input_names));
      return false;
    }
    ref.u[static_cast<std::size_t>(k)] = value;
  }
  InitialState init;
  if (!initial_state(m, t, ref.p, ref.u, inits, req.t, init, error)) {
    const std::string was = "the initial state";
    if (error.rfind(was, 0) == 0) error = "the reference state" + error.substr(was.size());
    return false;
  }
  ref.x = init.x;
  return true;
}

std::vector<std::complex<double>> sorted_eigenvalues(const std::vector<double>& A, int n) {
  std::vector<std::complex<double>> out;
  if (n == 0) return out;
  Eigen::MatrixXd M(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) M(i, j) = A[static_cast<std::size_t>(i * n + j)];
  Eigen::EigenSolver<Eigen::MatrixXd> es(M, false);
  for (int i = 0; i < n; ++i) out.push_back(es.eigenvalues()[i]);
  std::sort(out.begin(), out.end(), [](const std::complex<double>& a, const std::complex<double>& b) {
    return a.real() != b.real() ? a.real() < b.real() : a.imag() < b.imag();
  });
  return out;
}

}  // namespace mbsc::run
