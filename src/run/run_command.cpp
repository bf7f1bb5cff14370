// SPDX-License-Identifier: GPL-2.0-or-later
// `mbsc run` (include/mbsc/run/run_command.hpp): the steps of a simulation from the
// command line, each failing with a clear message before anything is written.
#include "mbsc/run/run_command.hpp"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <ctime>
#include <limits>
#include <filesystem>
#include <fmt/format.h>
#include <optional>
#include <ostream>

#include "mbsc/diag/activity.hpp"
#include "mbsc/diag/diagnostics.hpp"
#include "mbsc/diag/name_suggestions.hpp"
#include "mbsc/driver/pipeline.hpp"
#include "mbsc/driver/work_monitor.hpp"
#include "mbsc/run/compiled_model.hpp"
#include "mbsc/run/csv_table.hpp"
#include "mbsc/run/input_table.hpp"
#include "mbsc/run/integration_settings.hpp"
#include "mbsc/run/gnuplot_plot.hpp"
#include "mbsc/run/integrators.hpp"
#include "mbsc/run/model_integration.hpp"
#include "mbsc/run/output_guard.hpp"
#include "mbsc/run/output_rows.hpp"
#include "mbsc/run/run_accuracy.hpp"
#include "mbsc/run/run_setup.hpp"
#include "mbsc/run/start_check.hpp"
#include "mbsc/runtime/simulate.hpp"

namespace fs = std::filesystem;

namespace mbsc::run {

namespace {

/// A progress bar on a terminal for runs longer than a second.
class RunProgress {
 public:
  explicit RunProgress(double t_end, bool quiet) : t_end_(t_end), show_(!quiet && ::isatty(2)) {}
  ~RunProgress() { clear(); }
  void update(double t) {
    if (!show_) return;
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    if (wall < 1.0 || wall - last_ < 0.1) return;
    last_ = wall;
    const int width = 30, filled = static_cast<int>(width * std::min(1.0, t / t_end_));
    std::fprintf(stderr, "\r\x1b[Kmbsc: %5.1f s running [%s%s] t = %g / %g", wall, std::string(filled, '#').c_str(),
                 std::string(width - filled, '.').c_str(), t, t_end_);
    drawn_ = true;
  }
  void clear() {
    if (drawn_) std::fprintf(stderr, "\r\x1b[K");
    drawn_ = false;
  }

 private:
  double t_end_;
  bool show_, drawn_ = false;
  double last_ = 0.0;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

}  // namespace

std::vector<std::string> integrator_names() { return available_integrators(); }

bool check_integration_options(const RunArgs& a, std::string& error) {
  auto fail = [&](const std::string& message) {
    error = message;
    return false;
  };
  if (!(a.t_end > 0) || !std::isfinite(a.t_end)) return fail("--t-end must be a positive number of seconds");
  const double dt_out = output_step(a);
  if (!std::isfinite(dt_out) || a.t_end / dt_out > 1e7)
    return fail("--dt-out gives more than 10 million output rows; choose a larger --dt-out");
  const auto known = integrator_names();
  if (std::find(known.begin(), known.end(), a.integrator) == known.end())
    return fail(fmt::format("--integrator: unknown method '{}'{} (known: {})", printable(a.integrator),
                            did_you_mean(a.integrator, known), list_names(known)));
  if (!(a.rtol >= 1e-14 && a.rtol <= 0.1) || !(a.atol > 0 && std::isfinite(a.atol)))
    return fail("--rtol must lie in [1e-14, 0.1] and --atol be a positive number");
  if (a.projection != "auto" && a.projection != "on" && a.projection != "off")
    return fail("--projection takes auto, on or off");
  if (a.h > 0 && a.t_end / a.h > 1e9)
    return fail(fmt::format("--h {:g} makes more than a billion steps to t = {:g}; choose a larger step", a.h, a.t_end));
  if (!a.multipliers && (a.baumgarte_alpha >= 0 || a.baumgarte_beta >= 0))
    return fail("--baumgarte applies to --formulation multipliers");
  return true;
}

int run_simulation(const RunArgs& a, std::ostream& out, std::ostream& err) {
  // The budgets cover the whole command: past them its watcher ends the process.
  auto watch = driver::WorkMonitor::whole_command(a.work.budget);
  (void)out;
  auto fail = [&](const std::string& message) {
    err << "mbsc: error: " << message << "\n";
    return 1;
  };
  // ---- options that need no model ----
  std::string option_error;
  if (!check_integration_options(a, option_error)) return fail(option_error);
  const double dt_out = output_step(a);
  if (!a.plot.empty() && plot_format(a.plot).empty())
    return fail(fmt::format("--plot: '{}' should end in .svg or .png", printable(a.plot)));

  // ---- the model ----
  std::vector<std::string> sources;
  const std::optional<model::Model> m = read_model(a.model, a.work, sources, err);
  if (!m) return 1;
  std::string error;
  std::map<std::string, double> sets, inits;
  if (!parse_assignments(a.sets, "--set", sets, error) || !parse_assignments(a.inits, "--init", inits, error))
    return fail(error);
  if (a.baumgarte_alpha >= 0) sets["baumgarte_alpha"] = a.baumgarte_alpha;
  if (a.baumgarte_beta >= 0) sets["baumgarte_beta"] = a.baumgarte_beta;
  // Names and output paths are checked before anything is compiled or written.
  if (!check_names(*m, sets, inits, a.multipliers, error)) return fail(error);
  const std::string csv_path = a.csv.empty() ? m->name + ".csv" : a.csv;
  if (!a.plot.empty() && csv_path == "-") return fail("--plot needs the CSV in a file (-o FILE), not on standard output");
  if (!check_outputs({{"-o", csv_path}, {"--plot", a.plot}}, sources, error)) return fail(error);
  if (!a.plot.empty() && !gnuplot_available(error)) return fail("--plot: " + error);

  // Inputs from tables (--input NAME=@FILE[:COLUMN]) are read here and set over what the
  // compiled inputs function gives; the expressions are compiled into it.
  std::map<std::string, std::string> input_expressions;
  std::vector<std::pair<std::size_t, InputTable>> tables;  // (index into u, its table)
  for (const auto& [name, text] : a.inputs) {
    if (!is_input_table(text)) {
      input_expressions[name] = text;
      continue;
    }
    const std::string input = name;  // (a structured binding is not captured before C++20)
    const auto in = std::find_if(m->inputs.begin(), m->inputs.end(), [&](const auto& i) { return i.name == input; });
    if (in == m->inputs.end()) return fail(unknown_input_message(*m, name));
    InputTable table;
    const auto how = a.input_interpolation == "cubic" ? InputTable::Interpolation::Cubic : InputTable::Interpolation::Linear;
    if (!table.read(name, text, how, error) || !table.covers(0.0, a.t_end, error)) {
      err << error << "\n";
      return 1;
    }
    tables.emplace_back(static_cast<std::size_t>(in - m->inputs.begin()), std::move(table));
  }

  const CompileRequest req = compile_request(a, input_expressions);
  int code = 1;
  const auto compiled = compile_model(req, *m, sources, err, code);
  if (!compiled) return code;
  const runtime::ModelTable& T = compiled->table();
  // --state minimal: the initial state is assembled on the full state (a second, cached
  // object) and its minimal entries picked by name.
  std::unique_ptr<CompiledModel> full_model;
  if (a.minimal_state) {
    CompileRequest full = req;
    full.minimal_state = false;
    full_model = compile_model(full, *m, sources, err, code);
    if (!full_model) return code;
  }
  const runtime::ModelTable& TA = a.minimal_state ? full_model->table() : T;

  std::vector<double> p;
  if (!parameter_values(T, sets, p, error)) return fail(error);
  std::vector<double> u(static_cast<std::size_t>(std::max(1, T.nin)), 0.0);
  compiled->inputs(0.0, p.data(), u.data());
  for (const auto& [k, table] : tables) u[k] = table.at(0.0);
  InitialState init;
  if (!initial_state(*m, TA, p, u, inits, 0.0, init, error)) return fail(error);
  std::vector<double> x0 = init.x;
  if (a.minimal_state) {
    x0.assign(static_cast<std::size_t>(T.nx), 0.0);
    for (int i = 0; i < T.nx; ++i)
      x0[static_cast<std::size_t>(i)] =
          init.x[static_cast<std::size_t>(runtime::ModelTable::find(TA.state_names, TA.nx, T.state_names[i]))];
  }
  if (init.assembly.near_singular)
    err << "mbsc: warning: the initial state is " << init.assembly.message
        << "; the run may leave the intended branch (give more coordinates with --init)\n";
  for (const auto& q : init.normalized)
    err << "mbsc: note: the quaternion " << q << " starts off unit norm; it was divided by its norm\n";
  // A start where the rhs is not finite is named before anything runs or is written.
  if (!rhs_finite_at_start(*m, T, TA, 0.0, x0, init.x, u, p, error)) {
    err << error << "\n";
    return 1;
  }

  // ---- columns ----
  double e0[3] = {0, 0, 0};
  const bool has_energy = T.energy(0.0, x0.data(), u.data(), p.data(), e0) == 0;
  OutputRows output_rows(T, has_energy);
  output_rows.set_initial_energy(e0[2]);
  const std::vector<std::string>& available = output_rows.names();
  const std::size_t first_output = output_rows.first_output(), first_input = output_rows.first_input();
  std::vector<int> columns;
  if (!csv_columns(available, a.columns, columns, error)) return fail("--columns: " + error);
  std::vector<std::string> column_names;
  for (int c : columns) column_names.push_back(available[static_cast<std::size_t>(c)]);
  std::vector<int> plotted;
  if (!a.plot.empty()) {
    std::vector<std::string> wanted = a.plot_columns;
    if (wanted.empty()) {
      for (std::size_t i = first_output; i < first_input; ++i) wanted.push_back(available[i]);
      if (wanted.empty())
        for (const auto& s : runtime::ModelTable::names_of(T.dof_names, T.ndof)) wanted.push_back(s);
      // Only what the CSV has (--columns may leave them out); else its first columns.
      std::vector<std::string> present;
      for (const auto& w : wanted)
        if (std::find(column_names.begin(), column_names.end(), w) != column_names.end()) present.push_back(w);
      if (present.empty()) present.assign(column_names.begin() + 1, column_names.end());
      wanted = present;
      if (wanted.size() > 6) wanted.resize(6);
    }
    if (!choose_columns(column_names, wanted, plotted, error))
      return fail("--plot-columns: " + error + " (a plotted column must be in the CSV)");
  }
  // A CSV far larger than anyone reads is refused before the run, unless asked for.
  const double rows_expected = std::floor(a.t_end / dt_out) + 2;
  const double bytes_expected = csv_bytes(a.t_end, dt_out, column_names.size());
  if (csv_path != "-" && bytes_expected > kLargeOutputBytes && !a.large_output)
    return fail(fmt::format("-o: the CSV would take about {:.3g} GB ({:.3g} rows of {} columns); choose a larger "
                            "--dt-out or fewer --columns, or pass --large-output to write it anyway",
                            bytes_expected / 1e9, rows_expected, column_names.size()));
  CsvTable csv;
  if (!csv.open(csv_path, column_names, error)) {
    err << error << "\n";
    return 1;
  }
  NonFiniteColumns non_finite(column_names);

  // ---- integrate ----
  const runtime::StepperOptions so = stepper_options(a);
  auto input_fn = [&](double t, double* uu) {
    const int status = compiled->inputs(t, p.data(), uu);
    for (const auto& [k, table] : tables) uu[k] = table.at(t);
    return status;
  };
  const runtime::SimulationOptions sim = simulation_options(a, *m, T);
  const bool projecting =
      sim.projection != runtime::SimulationOptions::Projection::Off && T.nposc + T.nc > 0 && T.full_state_layout();
  RunProgress progress(a.t_end, a.work.quiet);
  std::vector<double> row(columns.size()), all(available.size()), uu(u.size());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto observe = [&](double t, const std::vector<double>& x) {
    if (input_fn(t, uu.data()) != 0) std::fill(uu.begin(), uu.end(), nan);
    output_rows.fill(t, x, uu.data(), p.data(), all);
    for (std::size_t k = 0; k < columns.size(); ++k) row[k] = all[static_cast<std::size_t>(columns[k])];
    csv.row(row);
    non_finite.row(t, row);
    progress.update(t);
  };
  // (The time budget covers the whole command: the run stops where it runs out.)
  watch.note("integrating", "model " + m->name);
  const Integration run =
      integrate(*compiled, p, x0, a.integrator, so, sim, observe, a.continuation, newton_jacobian(a), input_fn);
  const runtime::SimulationResult& r = run.result;
  const double cpu = run.cpu_seconds;
  progress.clear();

  // ---- summary ----
  const auto& st = run.stats;
  err << fmt::format("mbsc: {} {} t = 0 .. {:g}: {} steps ({} accepted, {} rejected), {} rhs evaluations{}, {:.3g} s CPU\n",
                     m->name, run.method, r.t, st.steps, st.accepted, st.rejected, st.rhs_evals,
                     st.jacobian_evals
                         ? fmt::format(", {} Jacobians{}, {} Newton iterations, {} Newton failures", st.jacobian_evals,
                                       st.jacobian_fallbacks ? fmt::format(" ({} by differences)", st.jacobian_fallbacks) : "",
                                       st.newton_iterations, st.newton_failures)
                         : "",
                     cpu);
  RunAccuracy accuracy;
  accuracy.rtol = a.rtol, accuracy.atol = a.atol;
  accuracy.constrained = T.nposc + T.nc > 0;
  auto worst = [](double row, double step) { return std::isnan(row) ? row : std::max(row, step); };
  accuracy.position_residual = worst(output_rows.position_residual(), r.max_position_residual);
  accuracy.velocity_residual = worst(output_rows.velocity_residual(), r.max_velocity_residual);
  if (accuracy.constrained)
    err << fmt::format("mbsc: largest constraint residuals: position {:.3g}, velocity {:.3g} (at step ends {:.3g}, {:.3g}){}\n",
                       accuracy.position_residual, accuracy.velocity_residual, r.max_position_residual,
                       r.max_velocity_residual,
                       run.stats.projections > 0 ? fmt::format("; projected by the method (CVODE) {} times", run.stats.projections)
                       : projecting              ? fmt::format("; projected {} times", r.projections)
                                                 : "");
  if (has_energy) {
    const double max_drift = output_rows.energy_change();
    err << fmt::format("mbsc: energy change: largest |E - E0| = {:.3g} (E0 = {:.6g}{})\n", max_drift, e0[2],
                       a.inputs.empty() ? "" : ", the inputs do work");
    accuracy.energy_defined = std::isfinite(e0[2]);
    accuracy.energy_conserved = energy_is_conserved(*m);
    accuracy.energy_change = max_drift;
    accuracy.energy_scale = std::max({std::fabs(e0[0]), std::fabs(e0[1]), std::fabs(e0[2])});
    if (!(accuracy.energy_scale > 0)) accuracy.energy_scale = 1;
  }
  if (a.continuation)
    err << fmt::format("mbsc: continuation: crossed {} pose(s) where the constraints lose rank, by extrapolation{}; "
                       "{} rhs evaluation(s) at a projected state, {} bridged\n",
                       r.crossings,
                       r.crossings > 0 ? fmt::format(" (largest error estimate {:.2g} of the tolerances)", r.crossing_error) : "",
                       r.projected_evaluations, r.bridged_evaluations);
  if (!r.switches.empty()) {
    std::string list;
    for (const auto& s : r.switches)
      list += fmt::format("{}t = {:g} -> {}", list.empty() ? "" : ", ", s.t, s.name);
    err << fmt::format("mbsc: independent set switched {} times: {}\n", r.switches.size(), list);
  }
  std::vector<std::string> warnings = non_finite.report();
  if (r.ok()) {
    const auto more = accuracy_warnings(accuracy);
    warnings.insert(warnings.end(), more.begin(), more.end());
  }
  for (const auto& w : warnings) err << "mbsc: warning: " << w << "\n";
  if (!r.ok()) {
    // The destination stays as it was; the rows up to the failure are in the temporary.
    const std::string kept = csv.keep();
    const bool budget = r.status == runtime::SimulationResult::Status::Stopped;
    err << fmt::format("mbsc: error: the run {} at t = {:g}{}; {} row(s) up to there are in {}{}\n",
                       budget ? "ran out of its time budget" : "failed", r.t,
                       budget ? fmt::format(" ({:g} s for the whole command; raise it with --budget SECONDS)",
                                            a.work.budget.seconds)
                              : ": " + r.message,
                       csv.rows(), kept == "-" ? std::string("standard output") : printable(kept),
                       a.plot.empty() ? "" : " (no plot drawn)");
    return budget ? 1 : 2;
  }
  if (!csv.close(error)) {
    err << error << "\n";
    return 1;
  }
  if (csv_path != "-" && !a.work.quiet)
    err << fmt::format("mbsc: wrote {} ({} rows, {} columns)\n", printable(csv_path), csv.rows(), columns.size());
  if (!a.plot.empty()) {
    if (!plot_columns(csv_path, column_names, 0, plotted, a.plot, m->name, error))
      return fail(fmt::format("--plot: {} ({} was written)", error, printable(csv_path)));
    if (!a.work.quiet) err << fmt::format("mbsc: wrote {}\n", printable(a.plot));
  }
  if (a.strict && !warnings.empty()) {
    err << fmt::format("mbsc: error: --strict: the run finished with {} warning(s) above\n", warnings.size());
    return 2;
  }
  return 0;
}

}  // namespace mbsc::run
