// SPDX-License-Identifier: GPL-2.0-or-later
// `mbsc bench` (include/mbsc/run/bench_command.hpp): work against precision.
#include "mbsc/run/bench_command.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <fstream>
#include <optional>
#include <ostream>
#include <sstream>

#include "mbsc/diag/diagnostics.hpp"
#include "mbsc/driver/work_monitor.hpp"
#include "mbsc/diag/name_suggestions.hpp"
#include "mbsc/driver/staged_file.hpp"
#include "mbsc/run/compiled_model.hpp"
#include "mbsc/run/csv_table.hpp"
#include "mbsc/run/gnuplot_plot.hpp"
#include "mbsc/run/integrators.hpp"
#include "mbsc/run/model_integration.hpp"
#include "mbsc/run/output_guard.hpp"
#include "mbsc/run/run_setup.hpp"

namespace mbsc::run {

namespace {

/// The rows of a CSV file: header names and numeric/text cells.
struct CsvFile {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
};

bool read_csv(const std::string& path, CsvFile& f, std::string& error) {
  std::ifstream in(path);
  if (!in) {
    error = fmt::format("cannot read '{}'", printable(path));
    return false;
  }
  auto split = [](const std::string& line) {
    std::vector<std::string> cells;
    std::string cur;
    for (char c : line) {
      if (c == ',') cells.push_back(cur), cur.clear();
      else if (c != '\r') cur += c;
    }
    cells.push_back(cur);
    return cells;
  };
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (f.header.empty()) f.header = split(line);
    else f.rows.push_back(split(line));
  }
  if (f.header.empty()) {
    error = fmt::format("'{}' has no header line", printable(path));
    return false;
  }
  return true;
}

bool to_number(const std::string& s, double& v) {
  char* end = nullptr;
  v = std::strtod(s.c_str(), &end);
  return !s.empty() && end && *end == '\0' && std::isfinite(v);
}

struct Row {
  std::string tool = "mbsc", formulation, method;
  double tol = 0, cpu = 0, err_final = NAN, err_max = NAN, pos_res = 0, vel_res = 0, drift = NAN;
  long steps = 0, rhs = 0;
  std::string status = "ok";
};

}  // namespace

int run_bench(const BenchArgs& a, std::ostream& out, std::ostream& err) {
  // The budgets cover the whole command: past them its watcher ends the process.
  const auto watch = driver::WorkMonitor::whole_command(a.work.budget);
  auto fail = [&](const std::string& message) {
    err << "mbsc: error: " << message << "\n";
    return 1;
  };
  if (!(a.t_end > 0) || !std::isfinite(a.t_end)) return fail("--t-end must be a positive number of seconds");
  const double dt_out = a.dt_out > 0 ? a.dt_out : a.t_end / 100;
  if (a.t_end / dt_out > 1e6) return fail("--dt-out gives more than a million samples");
  const auto known = available_integrators();
  std::vector<std::string> integrators = a.integrators;
  if (integrators.empty())
    for (const char* s : {"dopri5", "dop853", "bdf"})
      if (std::find(known.begin(), known.end(), s) != known.end()) integrators.push_back(s);
  for (const auto& i : integrators)
    if (std::find(known.begin(), known.end(), i) == known.end())
      return fail(fmt::format("--integrators: unknown method '{}'{} (known: {})", printable(i), did_you_mean(i, known),
                              list_names(known)));
  for (const auto& f : a.formulations)
    if (f != "complement" && f != "multipliers")
      return fail(fmt::format("--formulations: '{}' is neither complement nor multipliers", printable(f)));
  for (double t : a.tolerances)
    if (!(t > 0 && t < 1)) return fail("--tolerances must lie in (0, 1)");
  if (!a.plot.empty() && plot_format(a.plot).empty())
    return fail(fmt::format("--plot: '{}' should end in .svg or .png", printable(a.plot)));

  std::vector<std::string> sources;
  const std::optional<model::Model> m = read_model(a.model, a.work, sources, err);
  if (!m) return 1;
  std::string error;
  std::map<std::string, double> sets, inits;
  if (!parse_assignments(a.sets, "--set", sets, error) || !parse_assignments(a.inits, "--init", inits, error))
    return fail(error);
  const bool with_multipliers =
      std::find(a.formulations.begin(), a.formulations.end(), "multipliers") != a.formulations.end();
  if (!check_names(*m, sets, inits, with_multipliers, error)) return fail(error);
  const std::string csv_path = a.csv.empty() ? m->name + "_bench.csv" : a.csv;
  if (!check_outputs({{"-o", csv_path}, {"--plot", a.plot}}, sources, error)) return fail(error);
  if (!a.plot.empty() && !gnuplot_available(error)) return fail("--plot: " + error);

  // ---- every formulation compiled; the initial state assembled once ----
  std::map<std::string, std::unique_ptr<CompiledModel>> models;
  for (const std::string f : {"complement", "multipliers"}) {
    const bool wanted = f == "complement" || std::find(a.formulations.begin(), a.formulations.end(), f) != a.formulations.end();
    if (!wanted) continue;
    CompileRequest req;
    req.model_path = a.model;
    req.multipliers = f == "multipliers";
    req.input_expressions = a.inputs;
    req.cache_dir = a.cache_dir;
    req.work = a.work;
    int code = 1;
    auto c = compile_model(req, *m, sources, err, code);
    if (!c) return code;
    models[f] = std::move(c);
  }
  const runtime::ModelTable& T = models["complement"]->table();
  std::vector<double> p;
  if (!parameter_values(T, sets, p, error)) return fail(error);
  std::vector<double> u(static_cast<std::size_t>(std::max(1, T.nin)), 0.0);
  models["complement"]->inputs(0.0, p.data(), u.data());
  InitialState init;
  if (!initial_state(*m, T, p, u, inits, 0.0, init, error)) return fail(error);

  // The columns errors are measured on.
  std::vector<std::string> state;
  for (int i = 0; i < T.nx; ++i) state.emplace_back(T.state_names[i]);
  std::vector<int> err_cols;
  if (a.error_columns.empty()) {
    for (int i = 0; i < T.nx; ++i) err_cols.push_back(i);
  } else if (!choose_columns(state, a.error_columns, err_cols, error)) {
    return fail("--error-columns: " + error);
  }

  // ---- the reference ----
  const long n_samples = static_cast<long>(std::floor(a.t_end / dt_out + 1e-9)) + 1;
  std::vector<std::vector<double>> ref_samples;
  std::vector<double> ref_final;
  runtime::SimulationOptions sim;
  sim.t0 = 0.0;
  sim.t_end = a.t_end;
  sim.dt_out = dt_out;
  sim.projection = runtime::SimulationOptions::Projection::Auto;
  // The time budget covers the whole command: a run it cuts short fails (reported below).
  sim.stop_requested = [&](double) { return a.work.budget.seconds_left() <= 0; };
  const std::string ref_method =
      std::find(known.begin(), known.end(), "dop853") != known.end() ? "dop853" : integrators.front();
  if (a.reference.empty()) {
    runtime::StepperOptions so;
    so.rtol = 1e-13;
    so.atol = 1e-15;
    const Integration ref = integrate(*models["complement"], p, init.x, ref_method, so, sim,
                                      [&](double, const std::vector<double>& x) { ref_samples.push_back(x); });
    if (!ref.result.ok())
      return fail(fmt::format("the reference run ({} at rtol 1e-13) failed at t = {:g}: {}", ref_method, ref.result.t,
                              ref.result.message));
    ref_final = ref_samples.back();
  } else {
    CsvFile f;
    if (!read_csv(a.reference, f, error)) return fail("--reference: " + error);
    if (f.rows.empty()) return fail("--reference: the file has no rows");
    ref_final = init.x;
    std::vector<bool> found(static_cast<std::size_t>(T.nx), false);
    for (std::size_t c = 0; c < f.header.size(); ++c) {
      const int i = runtime::ModelTable::find(T.state_names, T.nx, f.header[c].c_str());
      if (i >= 0 && c < f.rows.back().size() && to_number(f.rows.back()[c], ref_final[static_cast<std::size_t>(i)]))
        found[static_cast<std::size_t>(i)] = true;
    }
    for (int i : err_cols)
      if (!found[static_cast<std::size_t>(i)])
        return fail(fmt::format("--reference: the last row of '{}' has no value for '{}'", printable(a.reference),
                                T.state_names[i]));
  }
  auto state_error = [&](const std::vector<double>& x, const std::vector<double>& r) {
    double e = 0.0;
    for (int i : err_cols) e = std::max(e, std::fabs(x[static_cast<std::size_t>(i)] - r[static_cast<std::size_t>(i)]));
    return std::isfinite(e) ? e : INFINITY;
  };

  // ---- the runs ----
  std::vector<Row> rows;
  for (const auto& f : a.formulations) {
    const CompiledModel& cm = *models[f];
    std::vector<double> pf;
    if (!parameter_values(cm.table(), sets, pf, error)) return fail(error);
    runtime::SimulationOptions s = sim;
    s.projection = f == "complement" ? runtime::SimulationOptions::Projection::Auto
                                      : runtime::SimulationOptions::Projection::Off;
    for (const auto& method : integrators)
      for (double tol : a.tolerances) {
        Row row;
        row.formulation = f;
        row.method = method;
        row.tol = tol;
        runtime::StepperOptions so;
        so.rtol = tol;
        so.atol = tol * 1e-2;
        if (method == "rk4") so.h = a.t_end * std::pow(tol, 0.25) / 20;
        long k = 0;
        double err_max = 0.0;
        std::vector<double> last;
        const Integration once = integrate(cm, pf, init.x, method, so, s, [&](double, const std::vector<double>& x) {
          if (!ref_samples.empty() && k < static_cast<long>(ref_samples.size()))
            err_max = std::max(err_max, state_error(x, ref_samples[static_cast<std::size_t>(k)]));
          ++k;
          last = x;
        });
        row.steps = once.stats.steps;
        row.rhs = once.stats.rhs_evals;
        row.pos_res = once.result.max_position_residual;
        row.vel_res = once.result.max_velocity_residual;
        if (!once.result.ok()) {
          row.status = fmt::format("failed at t = {:g}: {}", once.result.t, once.result.message);
          rows.push_back(row);
          continue;
        }
        row.err_final = state_error(last, ref_final);
        row.err_max = ref_samples.empty() || k != n_samples ? NAN : err_max;
        double e0[3], e1[3];
        const runtime::ModelTable& Tf = cm.table();
        std::vector<double> u0(u.size()), u1(u.size());
        cm.inputs(0.0, pf.data(), u0.data());
        cm.inputs(a.t_end, pf.data(), u1.data());
        if (Tf.energy(0.0, init.x.data(), u0.data(), pf.data(), e0) == 0 &&
            Tf.energy(a.t_end, last.data(), u1.data(), pf.data(), e1) == 0)
          row.drift = std::fabs(e1[2] - e0[2]);
        // Timing: the same run again until enough CPU time has passed, no observer work.
        double cpu = once.cpu_seconds;
        int reps = 1;
        while (cpu < a.min_cpu && reps < 200) {
          cpu += integrate(cm, pf, init.x, method, so, s, [](double, const std::vector<double>&) {}).cpu_seconds;
          ++reps;
        }
        row.cpu = cpu / reps;
        rows.push_back(row);
      }
  }

  // ---- peers ----
  for (const auto& path : a.peers) {
    CsvFile f;
    if (!read_csv(path, f, error)) return fail("--peer: " + error);
    auto col = [&](const char* name) {
      for (std::size_t c = 0; c < f.header.size(); ++c)
        if (f.header[c] == name) return static_cast<int>(c);
      return -1;
    };
    const int ctool = col("tool"), cmethod = col("method"), ctol = col("tol"), ccpu = col("cpu_s"), csteps = col("steps");
    if (cmethod < 0 || ctol < 0 || ccpu < 0)
      return fail(fmt::format("--peer: '{}' needs the columns method, tol and cpu_s", printable(path)));
    std::vector<std::pair<int, int>> compared;  // (csv column, state index)
    for (std::size_t c = 0; c < f.header.size(); ++c) {
      const int i = runtime::ModelTable::find(T.state_names, T.nx, f.header[c].c_str());
      if (i >= 0) compared.emplace_back(static_cast<int>(c), i);
    }
    if (compared.empty())
      return fail(fmt::format("--peer: '{}' has no column named like a coordinate or speed of the model", printable(path)));
    for (const auto& cells : f.rows) {
      if (cells.size() < f.header.size()) continue;
      Row row;
      row.tool = ctool >= 0 ? cells[static_cast<std::size_t>(ctool)] : "peer";
      row.formulation = row.tool;
      row.method = cells[static_cast<std::size_t>(cmethod)];
      double v = 0;
      if (!to_number(cells[static_cast<std::size_t>(ctol)], row.tol) || !to_number(cells[static_cast<std::size_t>(ccpu)], row.cpu))
        continue;
      if (csteps >= 0 && to_number(cells[static_cast<std::size_t>(csteps)], v)) row.steps = static_cast<long>(v);
      double e = 0.0;
      for (const auto& [c, i] : compared) {
        if (!to_number(cells[static_cast<std::size_t>(c)], v)) e = INFINITY;
        else e = std::max(e, std::fabs(v - ref_final[static_cast<std::size_t>(i)]));
      }
      row.err_final = e;
      rows.push_back(row);
    }
  }

  // ---- CSV, table, plot ----
  {
    std::string text =
        "tool,model,formulation,method,tol,cpu_s,steps,rhs_evals,err_final,err_max,position_residual,"
        "velocity_residual,energy_drift,status\n";
    for (const auto& r : rows)
      text += fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n", r.tool, m->name, r.formulation, r.method, r.tol,
                          r.cpu, r.steps, r.rhs, r.err_final, r.err_max, r.pos_res, r.vel_res, r.drift, r.status);
    driver::StagedFile file;
    if (!file.stage(csv_path, text, "-o", error) || !file.commit(error)) {
      err << error << "\n";
      return 1;
    }
  }
  out << fmt::format("{} to t = {:g} s; reference: {}; error = max over {} of |x - x_ref|\n\n", m->name, a.t_end,
                     a.reference.empty() ? ref_method + " at rtol 1e-13" : a.reference,
                     err_cols.size() == static_cast<std::size_t>(T.nx) ? "every coordinate and speed"
                                                                        : fmt::format("{} columns", err_cols.size()));
  out << "| tool | formulation | method | tol | CPU s | steps | rhs evals | final error | max error | position res. | "
         "energy drift |\n|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& r : rows)
    out << fmt::format("| {} | {} | {} | {:.0e} | {:.3g} | {} | {} | {:.2e} | {:.2e} | {:.1e} | {:.1e} |{}\n", r.tool,
                       r.formulation, r.method, r.tol, r.cpu, r.steps, r.rhs, r.err_final, r.err_max, r.pos_res, r.drift,
                       r.status == "ok" ? "" : " " + r.status);
  if (!a.plot.empty()) {
    std::vector<PlotSeries> series;
    for (const auto& r : rows) {
      if (r.status != "ok") continue;
      const std::string title = r.tool == "mbsc" ? r.formulation + " " + r.method : r.tool + " " + r.method;
      auto it = std::find_if(series.begin(), series.end(), [&](const PlotSeries& s) { return s.title == title; });
      if (it == series.end()) {
        series.push_back({title, {}, {}});
        it = series.end() - 1;
      }
      it->x.push_back(r.cpu);
      it->y.push_back(std::max(r.err_final, 1e-16));
    }
    if (!plot_loglog(series, "CPU time per run [s]", "error of the final state", a.plot,
                     fmt::format("{}: work against precision, t = 0 .. {:g} s", m->name, a.t_end), error))
      return fail("--plot: " + error);
  }
  if (!a.work.quiet) err << fmt::format("mbsc: wrote {}{}\n", printable(csv_path), a.plot.empty() ? "" : " and " + printable(a.plot));
  return 0;
}

}  // namespace mbsc::run
