// SPDX-License-Identifier: GPL-2.0-or-later
// The compiled model and the reference that `mbsc linearize` and `mbsc eig` start from.
#include "mbsc/run/linear_reference.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <map>
#include <ostream>

#include "mbsc/diag/diagnostics.hpp"
#include "mbsc/diag/name_suggestions.hpp"
#include "mbsc/driver/linear_parts.hpp"
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

runtime::LinearParts parts_of(const CompiledModel& c, const model::Model& m) {
  const runtime::ModelTable& t = c.table();
  return runtime::LinearParts{c.linear_parts(), t.nq_full, t.nu_full, t.nc, t.nposc, t.nin,
                              static_cast<int>(driver::unit_quaternion_coords(m).size())};
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
    if (!lets.count(name) && runtime::ModelTable::find(t.state_names, t.nx, name.c_str()) < 0) sets[name] = v;
  if (!check_names(m, sets, {}, false, error)) return false;
  if (!parameter_values(t, sets, ref.p, error)) return false;
  std::map<std::string, double> known = lets;
  for (int i = 0; i < t.np; ++i) known[t.param_names[i]] = ref.p[static_cast<std::size_t>(i)];
  if (!parse_assignments(req.inits, "--init", inits, error, known) || !parse_assignments(req.inputs, "--input", inputs, error, known))
    return false;
  if (!check_names(m, {}, inits, false, error)) return false;
  for (const auto& [name, v] : req.overrides)
    if (!lets.count(name) && !sets.count(name)) inits[name] = v;
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

std::string find_steady_count_error(std::size_t unknowns, std::size_t rates) {
  return fmt::format("--find names {} unknown(s) and --steady {} rate(s): give as many of each", unknowns, rates);
}

bool find_steady(const model::Model& m, const CompiledModel& c, ReferenceRequest& req, const std::vector<std::string>& unknowns,
                 const std::vector<std::string>& steady, LinearReference& ref, std::string& error) {
  const runtime::ModelTable& t = c.table();
  const int k = static_cast<int>(unknowns.size());
  if (k == 0 || static_cast<int>(steady.size()) != k) {
    error = find_steady_count_error(unknowns.size(), steady.size());
    return false;
  }
  const auto state = runtime::ModelTable::names_of(t.state_names, t.nx);
  std::vector<int> rows;
  for (const auto& name : steady) {
    const int i = runtime::ModelTable::find(t.state_names, t.nx, name.c_str());
    if (i < 0) {
      error = fmt::format("--steady: the model has no coordinate or speed named '{}'{}", printable(name), did_you_mean(name, state));
      return false;
    }
    rows.push_back(i);
  }
  // The starting values: the reference the request gives without the search.
  if (!reference_state(m, c, req, ref, error)) return false;
  std::map<std::string, double> lets;
  if (!parse_assignments(req.lets, "--let", lets, error)) return false;
  std::vector<double> z;
  for (const auto& name : unknowns) {
    if (const int i = runtime::ModelTable::find(t.state_names, t.nx, name.c_str()); i >= 0) z.push_back(ref.x[static_cast<std::size_t>(i)]);
    else if (lets.count(name)) z.push_back(req.overrides.count(name) ? req.overrides.at(name) : lets[name]);
    else if (const int p = runtime::ModelTable::find(t.param_names, t.np, name.c_str()); p >= 0) z.push_back(ref.p[static_cast<std::size_t>(p)]);
    else {
      std::vector<std::string> pool = state;
      for (const auto& [n, v] : lets) pool.push_back(n);
      for (int p2 = 0; p2 < t.np; ++p2) pool.push_back(t.param_names[p2]);
      error = fmt::format("--find: '{}' is not a coordinate, a speed, a --let name or a parameter of the model{}", printable(name),
                          did_you_mean(name, pool));
      return false;
    }
  }
  const std::map<std::string, double> base = req.overrides;
  // r(z): the rates of the steady components at the reference with these values.
  auto residual = [&](const std::vector<double>& zz, std::vector<double>& r) {
    req.overrides = base;
    for (int i = 0; i < k; ++i) req.overrides[unknowns[static_cast<std::size_t>(i)]] = zz[static_cast<std::size_t>(i)];
    if (!reference_state(m, c, req, ref, error)) return false;
    std::vector<double> xd(static_cast<std::size_t>(t.nx));
    if (t.rhs(req.t, ref.x.data(), ref.u.data(), ref.p.data(), xd.data()) != 0) {
      error = "the right-hand side cannot be evaluated there";
      return false;
    }
    r.resize(static_cast<std::size_t>(k));
    for (int i = 0; i < k; ++i) r[static_cast<std::size_t>(i)] = xd[static_cast<std::size_t>(rows[static_cast<std::size_t>(i)])];
    return true;
  };
  auto norm = [](const std::vector<double>& v) {
    double s = 0;
    for (double e : v) s = std::max(s, std::fabs(e));
    return s;
  };
  std::vector<double> r;
  if (!residual(z, r)) return false;
  const double tol = 1e-11 * std::max(1.0, norm(r));
  for (int it = 0; it < 60 && !(norm(r) <= tol); ++it) {
    // Jacobian by central differences, then a damped Newton step.
    Eigen::MatrixXd J(k, k);
    Eigen::VectorXd rv(k);
    for (int i = 0; i < k; ++i) rv(i) = r[static_cast<std::size_t>(i)];
    for (int j = 0; j < k; ++j) {
      const double h = 1e-6 * std::max(1.0, std::fabs(z[static_cast<std::size_t>(j)]));
      std::vector<double> zp = z, zm = z, rp, rm;
      zp[static_cast<std::size_t>(j)] += h, zm[static_cast<std::size_t>(j)] -= h;
      if (!residual(zp, rp) || !residual(zm, rm)) return false;
      for (int i = 0; i < k; ++i) J(i, j) = (rp[static_cast<std::size_t>(i)] - rm[static_cast<std::size_t>(i)]) / (2 * h);
    }
    const Eigen::VectorXd step = J.fullPivLu().solve(rv);
    if (!step.allFinite()) break;
    double lambda = 1.0;
    bool better = false;
    for (int tries = 0; tries < 20 && !better; ++tries, lambda /= 2) {
      std::vector<double> zn = z, rn;
      for (int i = 0; i < k; ++i) zn[static_cast<std::size_t>(i)] -= lambda * step(i);
      if (residual(zn, rn) && norm(rn) < norm(r)) z = zn, r = rn, better = true;
    }
    if (!better) break;
  }
  if (!residual(z, r)) return false;
  if (!(norm(r) <= tol)) {
    int worst = 0;
    for (int i = 1; i < k; ++i)
      if (std::fabs(r[static_cast<std::size_t>(i)]) > std::fabs(r[static_cast<std::size_t>(worst)])) worst = i;
    error = fmt::format("--find: no steady motion found from the given values: the rate of {} stays {} (try other starting "
                        "values with --init or --let)",
                        steady[static_cast<std::size_t>(worst)], fmt::format("{:.3g}", r[static_cast<std::size_t>(worst)]));
    return false;
  }
  return true;
}

double model_rate(const runtime::LinearParts& parts, const runtime::ModelTable& t, double time, const LinearReference& ref,
                  const std::vector<int>& sel) {
  std::vector<double> xd(static_cast<std::size_t>(t.nx));
  if (t.rhs(time, ref.x.data(), ref.u.data(), ref.p.data(), xd.data()) != 0) return -1;
  double speed = 0.0;
  for (double v : xd) speed = std::max(speed, std::fabs(v));
  if (speed == 0.0) return 0.0;
  const double h = 1e-5 / std::max(speed, 1.0);  // a step that moves the state by 1e-5 at most
  std::vector<double> A[2];
  double scale = 0.0;
  for (int side = 0; side < 2; ++side) {
    const double s = side == 0 ? -h : h;
    std::vector<double> x = ref.x;
    for (std::size_t i = 0; i < x.size(); ++i) x[i] += s * xd[i];
    runtime::LinearModel lin;
    std::string why;
    std::vector<double> B;
    if (runtime::linear_model(parts, time + s, x.data(), ref.u.data(), ref.p.data(), lin, why) != 0 ||
        !runtime::restrict_to(lin, sel, A[side], B))
      return -1;
    for (double e : A[side]) scale = std::max(scale, std::fabs(e));
  }
  double rate = 0.0;
  for (std::size_t i = 0; i < A[0].size(); ++i) rate = std::max(rate, std::fabs(A[1][i] - A[0][i]) / (2 * h));
  return scale > 0.0 ? rate / scale : 0.0;
}

std::vector<int> default_component_order(const runtime::ModelTable& t) {
  std::vector<int> order, positions;
  for (int i = 0; i < t.nq; ++i) {
    const std::string n = t.state_names[i];
    const bool position = n.size() > 2 && n[n.size() - 2] == '.' && (n.back() == 'x' || n.back() == 'y' || n.back() == 'z');
    (position ? positions : order).push_back(i);
  }
  order.insert(order.end(), positions.begin(), positions.end());
  for (int d = 0; d < t.ndof; ++d) order.push_back(runtime::ModelTable::find(t.state_names, t.nx, t.dof_names[d]));
  return order;
}

std::string model_rate_warning(double rate) {
  if (rate >= 0 && rate <= 1e-4) return "";
  if (rate < 0)
    return "cannot tell whether the linear model in these components changes along the reference motion (the "
           "right-hand side cannot be evaluated there, as where redundant constraints make its solve singular): if the "
           "reference is not steady in them, the eigenvalues are those of a time-varying model frozen at this instant";
  return fmt::format("the linear model in these components changes along the reference motion (relative rate {:.2g}/s): "
                     "its eigenvalues are those of a time-varying model frozen at this instant and depend on the "
                     "components chosen",
                     rate);
}

bool minimal_state(const runtime::LinearModel& lin, const runtime::ModelTable& t, const std::vector<std::string>& keep,
                   std::vector<int>& sel, std::string& error) {
  const auto names = runtime::ModelTable::names_of(t.state_names, t.nx);
  std::vector<int> preferred;
  for (const auto& name : keep) {
    const int i = runtime::ModelTable::find(t.state_names, t.nx, name.c_str());
    if (i < 0) {
      error = fmt::format("--keep: the model has no coordinate or speed named '{}'{}", printable(name), did_you_mean(name, names));
      return false;
    }
    preferred.push_back(i);
  }
  const std::size_t kept = preferred.size();
  for (int i : default_component_order(t)) preferred.push_back(i);
  sel = runtime::minimal_components(lin, preferred);
  preferred.resize(kept);
  for (int i : preferred)
    if (std::find(sel.begin(), sel.end(), i) == sel.end()) {
      error = fmt::format("--keep: {} cannot be part of the minimal state together with the components before it (the "
                          "linearized constraints fix it)",
                          names[static_cast<std::size_t>(i)]);
      return false;
    }
  return true;
}

std::vector<std::complex<double>> sorted_eigenvalues(const std::vector<double>& A, int n) {
  std::vector<std::complex<double>> out;
  if (n == 0) return out;
  Eigen::MatrixXd M(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) M(i, j) = A[static_cast<std::size_t>(i * n + j)];
  Eigen::EigenSolver<Eigen::MatrixXd> es(M, false);
  if (es.info() != Eigen::Success) return std::vector<std::complex<double>>(static_cast<std::size_t>(n), std::complex<double>(NAN, NAN));
  for (int i = 0; i < n; ++i) out.push_back(es.eigenvalues()[i]);
  std::sort(out.begin(), out.end(), [](const std::complex<double>& a, const std::complex<double>& b) {
    return a.real() != b.real() ? a.real() < b.real() : a.imag() < b.imag();
  });
  return out;
}

std::vector<std::complex<double>> eigenvalues_without_cyclic(const std::vector<double>& A, int n, std::vector<int>& cyclic) {
  cyclic = runtime::cyclic_components(A, n);
  std::vector<int> kept;
  for (int i = 0; i < n; ++i)
    if (!std::binary_search(cyclic.begin(), cyclic.end(), i)) kept.push_back(i);
  const int k = static_cast<int>(kept.size());
  std::vector<double> Ak(static_cast<std::size_t>(k * k));
  for (int i = 0; i < k; ++i)
    for (int j = 0; j < k; ++j) Ak[static_cast<std::size_t>(i * k + j)] = A[static_cast<std::size_t>(kept[static_cast<std::size_t>(i)] * n + kept[static_cast<std::size_t>(j)])];
  std::vector<std::complex<double>> out(cyclic.size(), std::complex<double>(0.0, 0.0));
  const auto rest = sorted_eigenvalues(Ak, k);
  out.insert(out.end(), rest.begin(), rest.end());
  return out;
}

}  // namespace mbsc::run
