// SPDX-License-Identifier: GPL-2.0-or-later
// mbsc command line: flag parsing only; the work is in mbsc::driver.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdlib>
#include <iostream>

#include "mbsc/diag/name_suggestions.hpp"
#include "mbsc/diag/diagnostics.hpp"
#include "mbsc/driver/commands.hpp"
#include "mbsc/driver/import_command.hpp"
#include "mbsc/fmu/fmu_export.hpp"
#include "mbsc/parse/parse.hpp"
#include "mbsc/run/bench_command.hpp"
#include "mbsc/run/eig_command.hpp"
#include "mbsc/run/inverse_cli.hpp"
#include "mbsc/run/linearize_command.hpp"
#include "mbsc/run/run_command.hpp"
#include "mbsc/run/sweep_command.hpp"

// Sanitizer builds: LeakSanitizer reports a one-time 26-byte allocation that libcln
// makes at start-up and never frees. That library's, and nothing else, is suppressed
// here as in tests/lsan.supp, so that a sanitized mbsc also works inside a build
// (mbsc_add_model runs it) where LSAN_OPTIONS is not set.
#if defined(__SANITIZE_ADDRESS__)
#define MBSC_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define MBSC_ASAN 1
#endif
#endif
#ifdef MBSC_ASAN
extern "C" const char* __lsan_default_suppressions();
extern "C" const char* __lsan_default_suppressions() { return "leak:libcln.so\n"; }
#endif

namespace {

/// Splits "a,b c" lists given to --outputs / --what.
std::vector<std::string> split_list(const std::vector<std::string>& items) {
  std::vector<std::string> out;
  for (const auto& item : items) {
    std::string cur;
    for (char c : item + ",") {
      if (c == ',' || c == ' ') {
        if (!cur.empty()) out.push_back(cur);
        cur.clear();
      } else {
        cur += c;
      }
    }
  }
  return out;
}

bool add_freezes(const std::vector<std::string>& items, std::map<std::string, double>& frozen) {
  for (const auto& f : items) {
    std::string name;
    double value = 0;
    std::string why;
    if (!mbsc::driver::parse_assignment(f, name, value, why)) {
      if (why.rfind("number ", 0) == 0)
        std::cerr << "mbsc: error: --freeze " << mbsc::printable(name) << ": " << mbsc::printable(why) << "\n";
      else
        std::cerr << "mbsc: error: --freeze " << why << ", got '" << mbsc::printable(f) << "'\n";
      return false;
    }
    frozen[name] = value;
  }
  return true;
}

/// --budget, --max-memory, --quiet and --progress, on every subcommand.
struct WorkFlags {
  double seconds = mbsc::driver::WorkBudget{}.seconds;
  std::size_t memory_mib = mbsc::driver::WorkBudget{}.memory_mib;
  bool quiet = false, progress = false;

  void add_to(CLI::App* cmd) {
    cmd->add_option("--budget", seconds, "time budget of the symbolic work, in seconds")
        ->check(CLI::Range(0.001, 1e7))
        ->capture_default_str();
    cmd->add_option("--max-memory", memory_mib, "memory budget of the symbolic work, in MiB")
        ->check(CLI::Range(std::size_t{16}, std::size_t{1} << 30))
        ->capture_default_str();
    cmd->add_flag("-q,--quiet", quiet, "no progress line; generate prints nothing on success (errors and warnings still)");
    cmd->add_flag("--progress", progress, "show progress even when stderr is not a terminal");
  }
  mbsc::driver::WorkArgs args() const {
    mbsc::driver::WorkArgs w;
    w.budget.seconds = seconds;
    w.budget.memory_mib = memory_mib;
    w.quiet = quiet;
    w.progress = quiet ? mbsc::driver::ProgressMode::Never
                       : progress ? mbsc::driver::ProgressMode::Always : mbsc::driver::ProgressMode::Auto;
    return w;
  }
};

/// "NAME=EXPR" items of --input / --prescribe split at the first '=', in order; false
/// (with the error printed) for an item without a name or '='.
bool split_name_expr(const std::vector<std::string>& items, const char* flag,
                     std::vector<std::pair<std::string, std::string>>& out) {
  for (const auto& item : items) {
    const auto eq = item.find('=');
    if (eq == std::string::npos || eq == 0) {
      std::cerr << "mbsc: error: " << flag << " expects NAME=EXPR, got '" << mbsc::printable(item) << "'\n";
      return false;
    }
    out.emplace_back(mbsc::declared_name(item.substr(0, eq)), item.substr(eq + 1));
  }
  return true;
}

/// A finite number above `low` (CLI11's range checks let nan through).
CLI::Validator finite_above(double low, const std::string& what) {
  return CLI::Validator(
      [low, what](std::string& text) -> std::string {
        char* end = nullptr;
        const double v = std::strtod(text.c_str(), &end);
        // A number a double does not hold gets the model language's message (1e400 is
        // too large, 1e-320 too small), not "not a positive number".
        const std::string literal = text.substr(!text.empty() && (text[0] == '+' || text[0] == '-') ? 1 : 0);
        if (!literal.empty() && literal.find_first_not_of("0123456789.eE+-") == std::string::npos && end && *end == '\0')
          if (const char* why = mbsc::parse::literal_out_of_double_range(literal))
            return "number '" + mbsc::printable(literal) + "' " + why;
        if (text.empty() || !end || *end != '\0' || !std::isfinite(v) || !(v > low))
          return what + " (got '" + mbsc::printable(text) + "')";
        return "";
      },
      "");
}

}  // namespace

/// The options of one integration, shared by `run` and `sweep`: --t-end .. --cache-dir.
struct IntegrationFlags {
  std::string formulation = "complement", state = "full";
  std::vector<std::string> inputs;  // --input name=EXPR|@FILE
  /// Into `a` what CLI11 does not set directly; false (with the message printed) on a bad --input.
  bool apply(mbsc::run::RunArgs& a) const;
};

void add_integration_options(CLI::App* c, mbsc::run::RunArgs& a, IntegrationFlags& f) {
  c->add_option("--t-end", a.t_end, "end time, s")
      ->check(finite_above(0, "a positive number of seconds"))
      ->capture_default_str();
  c->add_option("--dt-out", a.dt_out, "time between output rows, s (default: t-end / 500)")
      ->check(finite_above(0, "a positive number of seconds"));
  c->add_option("--integrator", a.integrator,
                "integration method: " + [] {
                  std::string s;
                  for (const auto& n : mbsc::run::integrator_names()) s += (s.empty() ? "" : ", ") + n;
                  return s;
                }())
      ->capture_default_str();
  c->add_option("--newton-jacobian", a.newton_jacobian,
                "bdf and ark-dirk: the Jacobian of their Newton matrices: generated (the model's rhs_jacobian), "
                "differences (forward differences of the rhs) or sundials (its own difference quotients)")
      ->check(CLI::IsMember({"generated", "differences", "sundials"}))
      ->capture_default_str();
  c->add_option("--rtol", a.rtol, "relative tolerance of adaptive methods (1e-14 .. 0.1)")
      ->check(finite_above(1e-14 * 0.999, "a relative tolerance of at least 1e-14"))
      ->check(CLI::Range(0.0, 0.1))
      ->capture_default_str();
  c->add_option("--atol", a.atol, "absolute tolerance of adaptive methods")
      ->check(finite_above(0, "a positive number"))
      ->capture_default_str();
  c->add_option("--h", a.h, "step of fixed-step methods, s (default: dt-out / 10)")
      ->check(finite_above(0, "a positive number of seconds"));
  c->add_option("--formulation", f.formulation, "complement or multipliers (as for generate)")
      ->check(CLI::IsMember({"complement", "multipliers"}))
      ->default_val("complement");
  c->add_option("--state", f.state, "full or minimal (as for generate; the CSV shows every coordinate and speed)")
      ->check(CLI::IsMember({"full", "minimal"}))
      ->default_val("full");
  c->add_option("--set", a.sets, "a parameter's value for this run: name=value (repeatable)");
  c->add_option("--init", a.inits,
                "an initial coordinate or speed: name=value (repeatable); the rest follows by assembly");
  c->add_option("--input", f.inputs,
                "an input as an expression of t and the parameters, name=EXPR, or from a CSV column interpolated in t, "
                "name=@FILE[:COLUMN] (the column 'name' by default; FILE has a column 't') (repeatable)");
  c->add_option("--input-interpolation", a.input_interpolation, "how a table input is interpolated: linear or cubic")
      ->check(CLI::IsMember({"linear", "cubic"}))
      ->capture_default_str();
  c->add_option("--projection", a.projection,
                "project onto the constraints after steps: auto (on for the complement form with constraints), on, off")
      ->capture_default_str();
  c->add_flag("--continuation", a.continuation,
              "continue on the branch where the constraints lose rank for an instant (a parallelogram chain's flat "
              "poses): projected and bridged rhs evaluations there; costs a conditioning report per evaluation");
  c->add_option("--solver", a.solver, "auto, dense or sparse (as for generate)")
      ->check(CLI::IsMember({"auto", "dense", "sparse"}))
      ->default_val("auto");
  c->add_option("--baumgarte-alpha", a.baumgarte_alpha, "multipliers form: Baumgarte gain alpha, 1/s (default 10)")
      ->check(finite_above(-1e-300, "a gain of 0 or more"));
  c->add_option("--baumgarte-beta", a.baumgarte_beta, "multipliers form: Baumgarte gain beta, 1/s (default 10)")
      ->check(finite_above(-1e-300, "a gain of 0 or more"));
  c->add_option("--cache-dir", a.cache_dir, "where compiled models are kept (default: $XDG_CACHE_HOME/mbsc or ~/.cache/mbsc)");
}

bool IntegrationFlags::apply(mbsc::run::RunArgs& a) const {
  a.multipliers = formulation == "multipliers";
  a.minimal_state = state == "minimal";
  std::vector<std::pair<std::string, std::string>> pairs;
  if (!split_name_expr(inputs, "--input", pairs)) return false;
  for (const auto& [name, expr] : pairs) a.inputs[name] = expr;
  return true;
}

int main(int argc, char** argv) {
  CLI::App app{"mbsc: symbolic equations of motion for multibody systems, as standalone C++"};
  app.set_version_flag("--version", std::string("mbsc ") + MBSC_VERSION);
  app.require_subcommand(1);

  mbsc::driver::CheckArgs check;
  auto* c = app.add_subcommand("check", "validate a model; print its tree, variables, ranks and degrees of freedom");
  c->add_option("model", check.model, "model file (.mbs, or a robot's .urdf)")->required();
  std::vector<std::string> check_freeze;
  c->add_option("--freeze", check_freeze, "check with a parameter folded in, as generate --freeze would: name=value");
  WorkFlags check_work;
  check_work.add_to(c);

  mbsc::driver::PrintArgs print;
  std::vector<std::string> what, print_freeze, print_outputs;
  auto* p = app.add_subcommand("print", "print the matrices and equations of a subsystem (text or LaTeX)");
  p->add_option("model", print.model, "model file (.mbs, or a robot's .urdf)")->required();
  p->add_option("--node", print.node, "subsystem (dotted name); default: the whole model");
  p->add_option("--what", what,
                "comma-separated: M h eom invariants rates A B C S f fbar (default: M h eom invariants, then rates B C fbar)");
  p->add_flag("--latex", print.latex, "LaTeX for a document that loads amsmath, instead of plain text");
  p->add_flag("--standalone", print.standalone, "a complete LaTeX document (pdflatex or lualatex); implies --latex");
  p->add_flag("--expand", print.expand,
              "closed form: substitute the named intermediates (e_, r_) and the small numeric solves (X_)");
  p->add_flag("--stats", print.stats, "operation counts of the generated functions");
  p->add_option("--freeze", print_freeze, "fold a parameter into the equations: name=value (repeatable)");
  p->add_option("--outputs", print_outputs, "with --stats: only these functions");
  std::string print_state = "full";
  p->add_option("--state", print_state, "with --stats: full or minimal (as for generate)")
      ->check(CLI::IsMember({"full", "minimal"}))
      ->default_val("full");
  p->add_option("--solver", print.solver, "with --stats: auto, dense or sparse (as for generate)")
      ->check(CLI::IsMember({"auto", "dense", "sparse"}))
      ->default_val("auto");
  WorkFlags print_work;
  print_work.add_to(p);

  mbsc::driver::GenerateArgs gen;
  std::vector<std::string> outputs, freeze;
  auto* g = app.add_subcommand("generate", "write standalone C++ for a model into OUT/<model>/");
  g->add_option("model", gen.model, "model file (.mbs, or a robot's .urdf)")->required();
  g->add_option("-o,--out", gen.out_dir, "output folder (default: generated)")->default_val("generated");
  g->add_option("--outputs", outputs,
                "only these functions (comma-separated): rhs mass_matrix forcing inverse_dynamics position_constraints "
                "velocity_constraints constraint_jacobian position_jacobian constraint_jacobian_values position_jacobian_values "
                "energy outputs full_state multipliers "
                "reaction_forces");
  std::string formulation = "complement";
  g->add_option("--formulation", formulation,
                "complement: the modular method, reduced to the independent speeds; multipliers: all speeds with "
                "Lagrange multipliers and Baumgarte stabilization (gains alpha, beta at the end of p[])")
      ->check(CLI::IsMember({"complement", "multipliers"}))
      ->default_val("complement");
  std::string state = "full";
  g->add_option("--state", state,
                "full: x = (all coordinates, all speeds); minimal: x = (coordinates not given explicitly by a "
                "position constraint, independent speeds), the rest rebuilt in every function")
      ->check(CLI::IsMember({"full", "minimal"}))
      ->default_val("full");
  g->add_option("--solver", gen.solver,
                "how rhs solves for the accelerations: dense (the reduced mass matrix by Cholesky; multipliers: the "
                "Schur complement), sparse (O(N): block elimination over all speeds in a tree order), auto (sparse "
                "when it is cheaper and as regular as dense: a tree of bodies, or a loop of massive bodies "
                "eliminated speeds first)")
      ->check(CLI::IsMember({"auto", "dense", "sparse"}))
      ->default_val("auto");
  g->add_option("--mass-matrix", gen.mass_matrix,
                "how mass_matrix forms M = C^T My C: symbolic (every entry, simplified and shared), factors (the "
                "nonzeros of C and My and a loop in the generated code: linear code size for long chains), auto "
                "(factors when the product is big)")
      ->check(CLI::IsMember({"auto", "symbolic", "factors"}))
      ->default_val("auto");
  g->add_option("--name", gen.name, "C++ namespace and file stem (default: the model's name)");
  g->add_option("--freeze", freeze, "fold a parameter into the code: name=value (repeatable)");
  g->add_flag("--derivatives", gen.derivatives,
              "also emit rhs_jacobian (dxdot/dx, dxdot/du) and inverse_dynamics_jacobian (du/dx, du/dzdot), "
              "derived by forward-mode differentiation (docs/derivatives.md)");
  g->add_flag("--linear-parts", gen.linear_parts,
              "also emit linear_parts, the Taylor coefficients include/mbsc/runtime/linear_model.hpp forms the linear model from");
  g->add_flag("--python", gen.python,
              "also write OUT/<name>/<name>.py: a ctypes + numpy module over the extern \"C\" functions (README, \"Using it\")");
  std::vector<std::string> batch;
  g->add_option("--batch", batch,
                "also emit NAME_at and NAME_batch for these functions (comma-separated; default rhs, or none with --outputs; none for none): "
                "evaluation of many states and parameter sets in struct-of-arrays layout, on CPU threads or a GPU "
                "(docs/batched.md)");
  g->add_flag("--force", gen.force,
              "write into OUT/<name> even when mbsc did not write that folder (only its own files are replaced)");
  int fmi_version = 0;
  std::string fmi_kind = "both";
  g->add_option("--fmi", fmi_version,
                "also write OUT/<name>/<name>.fmu, a Functional Mock-up Unit of FMI 2.0 or 3.0 for Modelica tools, "
                "Simulink and other importers (docs/fmi.md): modelDescription.xml, a binary for this machine (compiled "
                "with $CXX) and the sources")
      ->check(CLI::IsMember({2, 3}))
      ->type_name("2|3");
  g->add_option("--fmi-kind", fmi_kind,
                "with --fmi: me (model exchange: the importer integrates the derivatives), cs (co-simulation: the FMU "
                "integrates its own steps) or both")
      ->check(CLI::IsMember({"me", "cs", "both"}))
      ->default_val("both");
  g->add_option("--depfile", gen.depfile,
                "also write a make-style depfile: the generated files depend on the model and every file it includes")
      ->type_name("FILE");
  WorkFlags gen_work;
  gen_work.add_to(g);

  mbsc::run::RunArgs run;
  IntegrationFlags run_flags;
  std::vector<std::string> run_columns, run_plot_columns;
  auto* r = app.add_subcommand("run", "simulate a model: compile it (cached), assemble the initial state, integrate, "
                                      "write CSV and a plot");
  r->add_option("model", run.model, "model file (.mbs, or a robot's .urdf)")->required();
  add_integration_options(r, run, run_flags);
  r->add_option("-o,--out", run.csv, "CSV file (default: <model name>.csv; - for standard output)");
  r->add_option("--columns", run_columns, "CSV columns (default: t, every coordinate and speed, outputs, inputs, energy)");
  r->add_option("--plot", run.plot, "also plot to FILE.svg or FILE.png (gnuplot)");
  r->add_option("--plot-columns", run_plot_columns, "columns to plot against t (default: the outputs, else the dof speeds)");
  r->add_flag("--strict", run.strict,
              "exit with code 2 when the summary warns: a column not finite, constraint residuals or an energy change "
              "far beyond the tolerances");
  r->add_flag("--large-output", run.large_output, "write a CSV even when it is estimated above a gigabyte");
  WorkFlags run_work;
  run_work.add_to(r);

  mbsc::run::SweepArgs sweep;
  IntegrationFlags sweep_flags;
  std::vector<std::string> sweep_summaries;
  auto* sw = app.add_subcommand("sweep", "many runs of one model, each with its own parameters and initial values, on "
                                         "every core, or across the ranks of mpirun: a table row per run (docs/sweep.md)");
  sw->add_option("model", sweep.run.model, "model file (.mbs, or a robot's .urdf)")->required();
  sw->add_option("--grid", sweep.grids,
                 "a swept parameter, coordinate or speed: NAME=FROM:TO:STEP, NAME=FROM:TO:logN (N points, log-spaced) or "
                 "NAME=V1,V2,... (repeatable: every combination)");
  sw->add_option("--sample", sweep.samples,
                 "a sampled one: 'NAME~uniform(LO,HI)', 'NAME~normal(MEAN,SD)', 'NAME~loguniform(LO,HI)', "
                 "'NAME~lognormal(MU,SIGMA)' (repeatable; -n rows per grid point)");
  sw->add_option("-n", sweep.per_point, "rows per grid point, each with its own samples (default 1)")
      ->check(CLI::Range(1L, 100000000L));
  sw->add_option("--seed", sweep.seed, "the sweep's seed; row r draws from a generator seeded by (seed, r), its seed "
                                       "column")
      ->capture_default_str();
  sw->add_option("--summary", sweep_summaries,
                 "columns per run (comma-separated): final (every coordinate and speed at the end), final:NAME, "
                 "max:NAME, min:NAME, mean:NAME, maxabs:NAME over the output rows; NAME a column of run's CSV or "
                 "energy_change (default: final)");
  sw->add_option("--threads", sweep.threads, "worker threads (default 0: every core; one per rank under mpirun)")->check(CLI::Range(0, 4096));
  sw->add_option("-o,--out", sweep.out, "the table (default: <model name>_sweep.csv); rows go to TABLE.partial first");
  std::vector<std::string> sweep_columns;
  sw->add_option("--trajectories", sweep.trajectories,
                 "also each row's trajectory, the CSV mbsc run writes, to DIR/row_R.csv (R the row, zero-padded)");
  sw->add_option("--columns", sweep_columns, "the trajectories' columns (default: those of mbsc run)");
  sw->add_flag("--large-output", sweep.run.large_output, "write the trajectories even when estimated above a gigabyte");
  std::vector<std::string> sweep_find, sweep_steady, sweep_keep;
  sw->add_flag("--eig", sweep.eig, "each row: the eigenvalues of the linear model at its values (as mbsc linearize), not a run");
  sw->add_option("--find", sweep_find, "with --eig: a steady motion per row, the unknowns (with --steady)");
  sw->add_option("--steady", sweep_steady, "with --eig and --find: the state components whose rates must vanish");
  sw->add_option("--keep", sweep_keep, "with --eig: components the minimal state takes first (e.g. lean,steer)");
  sw->add_option("--t", sweep.eig_t, "with --eig: the reference time, s")->check(finite_above(-1e300, "a number of seconds"));
  add_integration_options(sw, sweep.run, sweep_flags);
  WorkFlags sweep_work;
  sweep_work.add_to(sw);

  mbsc::run::BenchArgs bench;
  std::vector<std::string> bench_formulations, bench_integrators, bench_tolerances, bench_inputs, bench_errcols;
  auto* b = app.add_subcommand("bench", "speed against error: every formulation x integrator x tolerance against a "
                                        "reference run; CSV, markdown table and work-precision plot");
  b->add_option("model", bench.model, "model file (.mbs, or a robot's .urdf)")->required();
  b->add_option("--t-end", bench.t_end, "end time, s")
      ->check(finite_above(0, "a positive number of seconds"))
      ->capture_default_str();
  b->add_option("--dt-out", bench.dt_out, "spacing of the trajectory's error samples, s (default t-end / 100)")
      ->check(finite_above(0, "a positive number of seconds"));
  b->add_option("--formulations", bench_formulations, "complement, multipliers (default both)");
  b->add_option("--integrators", bench_integrators, "methods to compare (default: dopri5, dop853 and bdf when built)");
  b->add_option("--tolerances", bench_tolerances, "relative tolerances (default 1e-4,1e-6,1e-8,1e-10)");
  b->add_option("--set", bench.sets, "a parameter's value: name=value (repeatable)");
  b->add_option("--init", bench.inits, "an initial coordinate or speed: name=value (repeatable)");
  b->add_option("--input", bench_inputs, "an input as an expression of t and the parameters: name=EXPR (repeatable)");
  b->add_option("--error-columns", bench_errcols, "coordinates and speeds the error is measured on (default: all)");
  b->add_option("--reference", bench.reference, "a CSV (as mbsc run writes) whose last row is the reference final state");
  b->add_option("--peer", bench.peers, "a peer tool's CSV (method, tol, cpu_s and final state columns) to plot alongside");
  b->add_option("-o,--out", bench.csv, "CSV of the results (default: <model>_bench.csv)");
  b->add_option("--plot", bench.plot, "work-precision plot, FILE.svg or FILE.png (gnuplot)");
  b->add_option("--min-cpu", bench.min_cpu, "repeat each run until this much CPU time, s")
      ->check(finite_above(-1e-300, "0 or more seconds"))
      ->capture_default_str();
  b->add_option("--cache-dir", bench.cache_dir, "where compiled models are kept");
  WorkFlags bench_work;
  bench_work.add_to(b);

  mbsc::run::InverseArgs inv;
  std::vector<std::string> inv_prescribe, inv_unknowns, inv_plot_columns;
  std::string inv_formulation = "complement";
  auto* iv = app.add_subcommand("inverse", "inverse dynamics: prescribe coordinates as functions of t, solve for the "
                                           "inputs (and reactions) along the motion; CSV and plot");
  iv->add_option("model", inv.model, "model file (.mbs, or a robot's .urdf)")->required();
  iv->add_option("--prescribe", inv_prescribe,
                 "a coordinate's motion: NAME=EXPR of t and the parameters (repeatable; as many as degrees of freedom)");
  iv->add_option("--unknowns", inv_unknowns, "inputs to solve for (default: every input)");
  iv->add_option("--input", inv.fixed_inputs, "the value of an input that is not an unknown: NAME=VALUE (default 0)");
  iv->add_option("--set", inv.sets, "a parameter's value: name=value (repeatable)");
  iv->add_option("--init", inv.inits, "a coordinate's value near the start, to pick the assembly branch: name=value");
  iv->add_option("--formulation", inv_formulation, "complement or multipliers (multipliers adds the reactions)")
      ->check(CLI::IsMember({"complement", "multipliers"}))
      ->default_val("complement");
  iv->add_option("--t-start", inv.t_start, "start time, s")->check(finite_above(-1e300, "a number of seconds"))->capture_default_str();
  iv->add_option("--t-end", inv.t_end, "end time, s")->check(finite_above(-1e300, "a number of seconds"))->capture_default_str();
  iv->add_option("--dt-out", inv.dt_out, "time between rows, s (default: the span / 500)")
      ->check(finite_above(0, "a positive number of seconds"));
  iv->add_option("-o,--out", inv.csv, "CSV file (default: <model name>_inverse.csv)");
  iv->add_option("--plot", inv.plot, "also plot to FILE.svg or FILE.png (gnuplot)");
  iv->add_option("--plot-columns", inv_plot_columns, "columns to plot against t (default: the unknown inputs)");
  iv->add_option("--cache-dir", inv.cache_dir, "where compiled models are kept");
  WorkFlags inv_work;
  inv_work.add_to(iv);

  mbsc::run::LinearizeArgs lin;
  std::vector<std::string> lin_keep, lin_second, lin_find, lin_steady, lin_symbolic;
  auto* li = app.add_subcommand("linearize", "linear model about a reference state (thesis section 4.5): A, B and the "
                                             "eigenvalues, as text, CSV or JSON");
  li->add_option("model", lin.model, "model file (.mbs, or a robot's .urdf)")->required();
  li->add_option("--init", lin.inits, "a coordinate or speed of the reference: name=value (repeatable; the rest is "
                                      "assembled from the model's initial values)");
  li->add_option("--let", lin.lets, "a name for a value the other options' expressions may use: name=value (e.g. v=5)");
  li->add_option("--set", lin.sets, "a parameter's value: name=value (repeatable)");
  li->add_option("--second-order", lin_second, "also M q'' + C q' + K q = T in these coordinates (e.g. lean,steer)");
  li->add_option("--speed", lin.speed, "with --gravity: the --let or parameter that is the forward speed v: split the "
                                       "second-order form as M q'' + v C1 q' + (g K0 + v^2 K2) q = T");
  li->add_option("--gravity", lin.gravity, "with --speed: the --let or parameter that is g");
  li->add_option("--input", lin.inputs, "an input's reference value: NAME=VALUE (default 0)");
  li->add_option("--t", lin.t, "the reference time, s")->check(finite_above(-1e300, "a number of seconds"))->capture_default_str();
  li->add_option("--find", lin_find, "a steady motion: the unknowns to solve for (coordinates, speeds, --let names or "
                                     "parameters; with --steady)");
  li->add_option("--steady", lin_steady, "with --find: the state components whose rates must vanish (as many as unknowns)");
  li->add_flag("--equilibrium", lin.equilibrium, "the reference must be at rest (every rate 0): an error otherwise");
  li->add_option("--state", lin.state, "minimal (a state of the motions the constraints allow) or full (every q0 and q1)")
      ->check(CLI::IsMember({"minimal", "full"}))
      ->default_val("minimal");
  li->add_option("--keep", lin_keep, "components the minimal state takes first (e.g. lean,steer)");
  li->add_option("--format", lin.format, "text, csv or json; latex with --symbolic")
      ->check(CLI::IsMember({"text", "csv", "json", "latex"}))
      ->default_val("text");
  auto* lin_symbolic_option = li->add_option("--symbolic", lin_symbolic, "parameters or --let names left as symbols in A and B (comma-separated, or "
                                             "all): the model written symbolically");
  li->add_option("-o,--out", lin.out, "output file (default: standard output)");
  li->add_option("--cache-dir", lin.cache_dir, "where compiled models are kept");
  WorkFlags lin_work;
  lin_work.add_to(li);

  mbsc::run::EigArgs eig;
  std::vector<std::string> eig_keep, eig_find, eig_steady, eig_ratio;
  auto* ei = app.add_subcommand("eig", "eigenvalues of the linear model along a parameter sweep: modes tracked, the values "
                                       "where a mode changes stability found by root finding; CSV and plot");
  ei->add_option("model", eig.model, "model file (.mbs, or a robot's .urdf)")->required();
  ei->add_option("--sweep", eig.sweep, "NAME=FROM:TO:STEP: a --let name, a parameter or a coordinate or speed")->required();
  ei->add_option("--let", eig.lets, "a name for a value the other options' expressions may use: name=value");
  ei->add_option("--set", eig.sets, "a parameter's value: name=value (repeatable)");
  ei->add_option("--init", eig.inits, "a coordinate or speed of the reference: name=value, an expression of the parameters "
                                      "and --let names (repeatable)");
  ei->add_option("--input", eig.inputs, "an input's reference value: NAME=VALUE (default 0)");
  ei->add_option("--find", eig_find, "a steady motion at every point: the unknowns (with --steady)");
  ei->add_option("--steady", eig_steady, "with --find: the state components whose rates must vanish");
  ei->add_option("--keep", eig_keep, "components the minimal state takes first (e.g. lean,steer)");
  ei->add_option("--ratio", eig_ratio, "NUM/DEN: an eigenvector component ratio per mode (magnitude and phase columns)");
  ei->add_option("--t", eig.t, "the reference time, s")->check(finite_above(-1e300, "a number of seconds"))->capture_default_str();
  ei->add_option("-o,--out", eig.csv, "CSV file (default: <model name>_eig.csv; - for standard output)");
  ei->add_option("--plot", eig.plot, "also plot real and imaginary parts (and ratios) to FILE.svg or FILE.png (gnuplot)");
  ei->add_option("--cache-dir", eig.cache_dir, "where compiled models are kept");
  WorkFlags eig_work;
  eig_work.add_to(ei);

  mbsc::driver::ImportArgs import_args;
  auto* im = app.add_subcommand("import", "read a robot's URDF file and write it as a model (docs/urdf.md)");
  im->add_option("urdf", import_args.urdf, "robot description (.urdf)")->required();
  im->add_option("-o,--out", import_args.output, "model file to write (default, or -: standard output)");
  im->add_flag("--floating-base", import_args.options.floating_base,
               "the root link as a free body (quaternion attitude) instead of fixed to the ground");
  bool no_inputs = false;
  im->add_flag("--no-inputs", no_inputs, "no input per actuated joint (the joints move freely, damping aside)");
  im->add_flag("--force", import_args.force, "replace the output file if it exists");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 1;
  }
  auto dispatch = [&]() -> int {
    if (*im) {
      import_args.options.joint_inputs = !no_inputs;
      return mbsc::driver::run_import(import_args, std::cout, std::cerr);
    }
    if (*c) {
      check.work = check_work.args();
      if (!add_freezes(check_freeze, check.frozen)) return 1;
      return mbsc::driver::run_check(check, std::cout, std::cerr);
    }
    if (*p) {
      print.work = print_work.args();
      print.what = split_list(what);
      print.what_given = p->count("--what") > 0;
      for (const auto& o : split_list(print_outputs)) print.functions.insert(o);
      print.minimal_state = print_state == "minimal";
      if (!add_freezes(print_freeze, print.frozen)) return 1;
      return mbsc::driver::run_print(print, std::cout, std::cerr);
    }
    if (*r) {
      run.work = run_work.args();
      run.columns = split_list(run_columns);
      run.plot_columns = split_list(run_plot_columns);
      if (!run_flags.apply(run)) return 1;
      return mbsc::run::run_simulation(run, std::cout, std::cerr);
    }
    if (*sw) {
      sweep.run.work = sweep_work.args();
      // A sweep has no time limit unless --budget sets one (then it covers the whole sweep).
      if (sw->count("--budget") == 0) sweep.run.work.budget.seconds = 1e9;
      sweep.summaries = split_list(sweep_summaries);
      sweep.run.columns = split_list(sweep_columns);
      sweep.find = split_list(sweep_find);
      sweep.steady = split_list(sweep_steady);
      sweep.keep = split_list(sweep_keep);
      if (!sweep.eig && (sw->count("--find") + sw->count("--steady") + sw->count("--keep") + sw->count("--t") > 0)) {
        std::cerr << "mbsc: error: --find, --steady, --keep and --t belong to --eig (the eigenvalues of each row)\n";
        return 1;
      }
      if (!sweep_flags.apply(sweep.run)) return 1;
      return mbsc::run::run_sweep(sweep, std::cout, std::cerr);
    }
    if (*ei) {
      eig.work = eig_work.args();
      eig.keep = split_list(eig_keep);
      eig.find = split_list(eig_find);
      eig.steady = split_list(eig_steady);
      eig.ratios = split_list(eig_ratio);
      return mbsc::run::run_eig(eig, std::cout, std::cerr);
    }
    if (*li) {
      lin.work = lin_work.args();
      lin.keep = split_list(lin_keep);
      lin.second_order = split_list(lin_second);
      lin.symbolic = split_list(lin_symbolic);
      if (lin_symbolic_option->count() > 0 && lin.symbolic.empty()) {
        std::cerr << "mbsc: error: --symbolic: no names given (parameters or --let names, comma-separated, or all)\n";
        return 1;
      }
      lin.find = split_list(lin_find);
      lin.steady = split_list(lin_steady);
      return mbsc::run::run_linearize(lin, std::cout, std::cerr);
    }
    if (*iv) {
      inv.work = inv_work.args();
      inv.multipliers = inv_formulation == "multipliers";
      inv.unknowns = split_list(inv_unknowns);
      inv.plot_columns = split_list(inv_plot_columns);
      if (!split_name_expr(inv_prescribe, "--prescribe", inv.prescribe)) return 1;
      return mbsc::run::run_inverse(inv, std::cout, std::cerr);
    }
    if (*b) {
      bench.work = bench_work.args();
      if (!bench_formulations.empty()) bench.formulations = split_list(bench_formulations);
      bench.integrators = split_list(bench_integrators);
      bench.error_columns = split_list(bench_errcols);
      if (!bench_tolerances.empty()) {
        bench.tolerances.clear();
        for (const auto& t : split_list(bench_tolerances)) {
          std::string n;
          double v = 0;
          std::string why;
          if (!mbsc::driver::parse_assignment("tol=" + t, n, v, why)) {
            std::cerr << "mbsc: error: --tolerances: "
                      << (why.rfind("number ", 0) == 0 ? mbsc::printable(why) : "'" + mbsc::printable(t) + "' is not a number")
                      << "\n";
            return 1;
          }
          bench.tolerances.push_back(v);
        }
      }
      std::vector<std::pair<std::string, std::string>> inputs;
      if (!split_name_expr(bench_inputs, "--input", inputs)) return 1;
      for (const auto& [name, expr] : inputs) bench.inputs[name] = expr;
      return mbsc::run::run_bench(bench, std::cout, std::cerr);
    }
    for (const auto& o : split_list(outputs)) gen.functions.insert(o);
    if (g->count("--batch") > 0) gen.batch = split_list(batch);
    gen.minimal_state = state == "minimal";
    gen.multipliers = formulation == "multipliers";
    gen.work = gen_work.args();
    if (!add_freezes(freeze, gen.frozen)) return 1;
    if (fmi_version == 0 && g->count("--fmi-kind") > 0) {
      std::cerr << "mbsc: error: --fmi-kind needs --fmi 2 or --fmi 3\n";
      return 1;
    }
    if (fmi_version != 0) {
      if (!gen.functions.empty()) {
        std::cerr << "mbsc: error: --fmi needs every function of the model (its FMI calls use rhs, the constraints, "
                     "outputs and more): leave out --outputs\n";
        return 1;
      }
      mbsc::fmu::FmuOptions fmu;
      fmu.version = fmi_version;
      fmu.model_exchange = fmi_kind != "cs";
      fmu.co_simulation = fmi_kind != "me";
      gen.extra_outputs = [fmu, &gen](const mbsc::driver::GenerateArgs::Made& made,
                                      std::vector<mbsc::driver::OutputFile>& files, std::ostream& err) {
        return mbsc::fmu::add_fmu(fmu, gen, made, files, err);
      };
    }
    return mbsc::driver::run_generate(gen, std::cout, std::cerr);
  };
  // The stages report what a user did wrong as diagnostics; what escapes them is ours.
  try {
    return dispatch();
  } catch (const std::bad_alloc&) {
    std::cerr << "mbsc: error: out of memory (lower the model's size, or raise --max-memory if the machine has more)\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "mbsc: internal error: " << mbsc::printable(e.what()) << "\n";
    return 2;
  }
}
