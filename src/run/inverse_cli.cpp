// SPDX-License-Identifier: GPL-2.0-or-later
// `mbsc inverse` from the command line (include/mbsc/run/inverse_cli.hpp): the model
// compiled and loaded as for `mbsc run`, then the inverse-dynamics core.
#include "mbsc/run/inverse_cli.hpp"

#include <cmath>
#include <fmt/format.h>
#include <optional>
#include <ostream>

#include "inverse_command.hpp"
#include "mbsc/diag/diagnostics.hpp"
#include "mbsc/driver/work_monitor.hpp"
#include "mbsc/run/compiled_model.hpp"
#include "mbsc/run/csv_table.hpp"
#include "mbsc/run/gnuplot_plot.hpp"
#include "mbsc/run/output_guard.hpp"
#include "mbsc/run/run_setup.hpp"
#include "mbsc/sym/probe.hpp"

namespace mbsc::run {

namespace {

/// Each `friction` joint of the model with its slide rate evaluated at t and a full state
/// of the table (coordinates and speeds matched by name; inputs in model order, as the
/// table's; parameters from p, by name).
std::vector<InverseCommandOptions::FrictionJoint> friction_joints(const model::Model& m, const runtime::ModelTable& T) {
  std::vector<int> q_at, u_at;  // each model coordinate's and speed's index in the state
  for (const auto& c : m.coords) q_at.push_back(runtime::ModelTable::find(T.state_names, T.nx, c.name.c_str()));
  for (const auto& u : m.speeds) u_at.push_back(runtime::ModelTable::find(T.state_names, T.nx, u.name.c_str()));
  std::vector<InverseCommandOptions::FrictionJoint> out;
  for (const auto& f : m.frictions)
    out.push_back({f.joint, [&m, &T, q_at, u_at, v = f.slide_velocity](double t, const std::vector<double>& x,
                                                                        const std::vector<double>& u, const std::vector<double>& p) {
                     auto pick = [&x](const std::vector<int>& at) {
                       std::vector<double> values;
                       for (int k : at) values.push_back(k >= 0 ? x[static_cast<std::size_t>(k)] : 0.0);
                       return values;
                     };
                     std::map<std::string, double> params;
                     for (int k = 0; k < T.np; ++k) params[T.param_names[k]] = p[static_cast<std::size_t>(k)];
                     sym::Probe at = sym::Probe::configuration(m, params, pick(q_at), pick(u_at));
                     at.bind(m.time, t);  // a slide driven in time, or by an input
                     for (std::size_t k = 0; k < m.inputs.size() && k < u.size(); ++k) at.bind(m.inputs[k].sym, u[k]);
                     return at.eval_double(v);
                   }});
  return out;
}

}  // namespace

int run_inverse(const InverseArgs& a, std::ostream& out, std::ostream& err) {
  // The budgets cover the whole command: past them its watcher ends the process.
  const auto watch = driver::WorkMonitor::whole_command(a.work.budget);
  auto fail = [&](const std::string& message) {
    err << "mbsc: error: " << message << "\n";
    return 1;
  };
  if (a.prescribe.empty()) return fail("--prescribe: give the motion of as many coordinates as the model has degrees of freedom");
  if (!(a.t_end > a.t_start) || !std::isfinite(a.t_end) || !std::isfinite(a.t_start))
    return fail("--t-end must be a number after --t-start");
  const double dt_out = a.dt_out > 0 ? a.dt_out : (a.t_end - a.t_start) / 500;
  if ((a.t_end - a.t_start) / dt_out > 1e7) return fail("--dt-out gives more than 10 million rows");
  if (!a.plot.empty() && plot_format(a.plot).empty())
    return fail(fmt::format("--plot: '{}' should end in .svg or .png", printable(a.plot)));

  std::vector<std::string> sources;
  const std::optional<model::Model> m = read_model(a.model, a.work, sources, err);
  if (!m) return 1;
  std::string error;
  std::map<std::string, double> sets, inits, fixed;
  if (!parse_assignments(a.sets, "--set", sets, error) || !parse_assignments(a.inits, "--init", inits, error) ||
      !parse_assignments(a.fixed_inputs, "--input", fixed, error))
    return fail(error);
  if (!check_names(*m, sets, inits, a.multipliers, error)) return fail(error);
  const bool to_stdout = a.csv == "-";
  const std::string csv_path = a.csv.empty() ? m->name + "_inverse.csv" : a.csv;
  if (!a.plot.empty() && to_stdout) return fail("--plot needs the CSV in a file (-o FILE), not on standard output");
  if (!check_outputs({{"-o", csv_path}, {"--plot", a.plot}}, sources, error)) return fail(error);
  if (!a.plot.empty() && !gnuplot_available(error)) return fail("--plot: " + error);
  CompileRequest req;
  req.model_path = a.model;
  req.multipliers = a.multipliers;
  req.cache_dir = a.cache_dir;
  req.work = a.work;
  int code = 1;
  const auto compiled = compile_model(req, *m, sources, err, code);
  if (!compiled) return code;
  const runtime::ModelTable& T = compiled->table();

  InverseCommandOptions opt;
  opt.prescribe = a.prescribe;
  opt.unknowns = a.unknowns;
  opt.params = sets;
  opt.fixed_inputs = fixed;
  opt.t_start = a.t_start;
  opt.t_end = a.t_end;
  opt.dt_out = dt_out;
  opt.output_csv = to_stdout ? "" : csv_path;
  opt.seconds_left = [&a] { return a.work.budget.seconds_left(); };
  opt.friction_joints = friction_joints(*m, T);
  for (const auto& e : unit_quaternion_indices(*m, T)) opt.quaternion_indices.insert(opt.quaternion_indices.end(), e.begin(), e.end());
  // The branch: where the model's own initial state (and --init) assembles, when it does;
  // else the raw values given.
  std::vector<double> p;
  if (!parameter_values(T, sets, p, error)) return fail(error);
  std::vector<double> u(static_cast<std::size_t>(std::max(1, T.nin)), 0.0);
  InitialState init;
  if (initial_state(*m, T, p, u, inits, a.t_start, init, error)) {
    for (int i = 0; i < T.nq; ++i) opt.guess[T.state_names[i]] = init.x[static_cast<std::size_t>(i)];
  } else {
    opt.guess = inits;
  }
  const InverseOutcome r = inverse_command(T, opt, a.model);
  if (to_stdout && r.exit_code != 1) out << inverse_csv(r.table);
  if (!r.message.empty()) err << r.message << "\n";
  if (r.exit_code != 0) return r.exit_code;
  if (!a.work.quiet && !to_stdout)
    err << fmt::format("mbsc: wrote {} ({} rows, {} columns)\n", printable(opt.output_csv), r.table.rows.size(),
                       r.table.columns.size());
  if (!a.plot.empty()) {
    std::vector<std::string> wanted = a.plot_columns;
    if (wanted.empty()) {
      if (a.unknowns.empty())
        for (int i = 0; i < T.nin; ++i) wanted.emplace_back(T.input_names[i]);
      else
        wanted = a.unknowns;
    }
    std::vector<int> cols;
    if (!choose_columns(r.table.columns, wanted, cols, error)) return fail("--plot-columns: " + error);
    if (!plot_columns(opt.output_csv, r.table.columns, 0, cols, a.plot, m->name + ": inverse dynamics", error))
      return fail("--plot: " + error);
    if (!a.work.quiet) err << fmt::format("mbsc: wrote {}\n", printable(a.plot));
  }
  return 0;
}

}  // namespace mbsc::run
