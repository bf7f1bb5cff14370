// SPDX-License-Identifier: GPL-2.0-or-later
// `mbsc sweep` (include/mbsc/run/sweep_command.hpp, docs/sweep.md). The model is read
// and compiled once; then worker threads take rows in turn. A row's start (parameter
// values, assembly of the initial state) uses the model's symbolic expressions, which
// GiNaC does not let two threads touch: it is made under one lock. The integration, the
// long part, runs unlocked on the shared compiled model. Finished rows wait in a buffer
// until every row before them is done, then go to TABLE.partial in row order.
#include "mbsc/run/sweep_command.hpp"

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <limits>
#include <map>
#include <mutex>
#include <optional>
#include <ostream>
#include <sstream>
#include <thread>

#include "mbsc/diag/diagnostics.hpp"
#include "mbsc/diag/name_suggestions.hpp"
#include "mbsc/driver/staged_file.hpp"
#include "mbsc/driver/work_monitor.hpp"
#include "mbsc/run/compiled_model.hpp"
#include "mbsc/run/csv_table.hpp"
#include "mbsc/run/input_table.hpp"
#include "mbsc/run/integration_settings.hpp"
#include "mbsc/run/model_integration.hpp"
#include "mbsc/run/output_guard.hpp"
#include "mbsc/run/output_rows.hpp"
#include "mbsc/run/run_setup.hpp"
#include "mbsc/run/sha256.hpp"
#include "mbsc/run/start_check.hpp"
#include "mbsc/run/sweep_eigen_rows.hpp"
#include "mbsc/run/sweep_plan.hpp"
#include "mbsc/run/sweep_ranks.hpp"

namespace fs = std::filesystem;

namespace mbsc::run {

namespace {

const double kNan = std::numeric_limits<double>::quiet_NaN();

/// A CSV field: quoted when it holds a comma, a quote or a line break.
std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string out = "\"";
  for (char c : text) out += c == '"' ? std::string("\"\"") : std::string(1, c == '\n' || c == '\r' ? ' ' : c);
  return out + "\"";
}

std::string number_text(double v) { return fmt::format("{}", v == 0.0 ? 0.0 : v); }

/// One summary column resolved: which run column (or the energy change) and how.
struct Summary {
  SummarySpec::Kind kind;
  int column;  // into OutputRows::names(); -1: the energy change |E - E0|
  std::string header;
};

/// What one run gives its row.
struct RowResult {
  std::string status = "ok";  // ok, failed, stopped, start_error
  std::string message;
  double t = kNan;
  long steps = 0, rhs_evals = 0;
  double position_residual = kNan, velocity_residual = kNan, energy_change = kNan;
  std::vector<double> summaries;
};

/// The running statistic of one summary over the output rows.
struct Accumulator {
  double value = kNan, sum = 0.0;
  long count = 0;
  void add(SummarySpec::Kind kind, double v) {
    ++count;
    sum += v;
    if (kind == SummarySpec::Kind::Final) {  // the last row's value, whatever came before
      value = v;
      return;
    }
    if (std::isnan(v) || (count > 1 && std::isnan(value))) {
      value = kNan;  // a NaN row makes max, min and the mean NaN
      return;
    }
    switch (kind) {
      case SummarySpec::Kind::Final: value = v; break;
      case SummarySpec::Kind::Max: value = count == 1 ? v : std::max(value, v); break;
      case SummarySpec::Kind::Min: value = count == 1 ? v : std::min(value, v); break;
      case SummarySpec::Kind::MaxAbs: value = count == 1 ? std::fabs(v) : std::max(value, std::fabs(v)); break;
      case SummarySpec::Kind::Mean: value = v; break;
    }
  }
  double result(SummarySpec::Kind kind) const {
    if (count == 0) return kNan;
    return kind == SummarySpec::Kind::Mean && !std::isnan(value) ? sum / static_cast<double>(count) : value;
  }
};

/// The fields of a CSV line (commas outside quotes, plus one).
std::size_t count_fields(const std::string& line) {
  std::size_t n = 1;
  bool quoted = false;
  for (char c : line) {
    if (c == '"') quoted = !quoted;
    else if (c == ',' && !quoted) ++n;
  }
  return n;
}

/// TABLE.partial: the first line names the sweep (a digest of everything that decides
/// its rows), the second is the header, then the rows done, in order.
struct PartialTable {
  std::string path;
  std::FILE* file = nullptr;
  long rows_done = 0;

  ~PartialTable() {
    if (file) std::fclose(file);
  }
  /// Opens it for appending, keeping the rows a killed sweep of the same signature wrote
  /// (an unfinished last line is cut off). False with `error` when it holds another sweep.
  bool open(const std::string& signature_line, const std::string& header, long rows, std::string& error) {
    std::error_code ec;
    const std::string head = signature_line + "\n" + header + "\n";
    bool fresh = !fs::exists(path, ec);
    if (!fresh) {
      std::ifstream in(path, std::ios::binary);
      std::string start(head.size(), '\0');
      in.read(&start[0], static_cast<std::streamsize>(head.size()));
      start.resize(static_cast<std::size_t>(in.gcount()));
      if (start != head) {
        // Killed before its header was whole: nothing to keep. Otherwise another sweep's.
        if (head.compare(0, start.size(), start) != 0) {
          error = fmt::format("'{}' holds the rows of another sweep (other options, or another model text); remove "
                              "it to start this one afresh", printable(path));
          return false;
        }
        fresh = true;
      } else {
        // Complete lines only, each with the header's number of fields and its row number,
        // in order; what follows the last one (a line cut off) is dropped.
        const std::size_t fields = count_fields(header);
        std::size_t end = head.size();
        for (std::string line; rows_done < rows && std::getline(in, line) && !in.eof();) {
          if (line.rfind(std::to_string(rows_done) + ",", 0) != 0 || count_fields(line) != fields) break;
          ++rows_done;
          end += line.size() + 1;
        }
        in.close();
        fs::resize_file(path, end, ec);
        if (ec) {
          error = fmt::format("cannot continue '{}': {}", printable(path), ec.message());
          return false;
        }
        file = std::fopen(path.c_str(), "ab");
      }
    }
    if (fresh) {
      file = std::fopen(path.c_str(), "wb");
      if (file) std::fputs(head.c_str(), file);
    }
    if (!file || std::fflush(file) != 0) {
      error = fmt::format("cannot write '{}': {}", printable(path), std::strerror(errno));
      return false;
    }
    return true;
  }
  bool append(const std::string& line) { return std::fputs(line.c_str(), file) >= 0 && std::fflush(file) == 0; }
};

/// A progress line on a terminal (or always with --progress, never with --quiet).
class SweepProgress {
 public:
  SweepProgress(long rows, long done, driver::ProgressMode mode)
      : rows_(rows), first_(done), always_(mode == driver::ProgressMode::Always),
        show_(mode == driver::ProgressMode::Always || (mode == driver::ProgressMode::Auto && ::isatty(2))) {}
  ~SweepProgress() { clear(); }
  void update(long done, long failed) {
    if (!show_) return;
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    if (done < rows_ && (wall < 1.0 || wall - last_ < (always_ ? 2.0 : 0.2))) return;
    last_ = wall;
    const double rate = (done - first_) / std::max(wall, 1e-9);
    const std::string left = rate > 0 && done < rows_ ? fmt::format(", about {:.0f} s left", (rows_ - done) / rate) : "";
    std::fprintf(stderr, always_ ? "mbsc: sweep %ld / %ld rows, %ld failed, %.1f s%s\n"
                                 : "\r\x1b[Kmbsc: sweep %ld / %ld rows, %ld failed, %.1f s%s",
                 done, rows_, failed, wall, left.c_str());
    drawn_ = !always_;
  }
  void clear() {
    if (drawn_) std::fprintf(stderr, "\r\x1b[K");
    drawn_ = false;
  }

 private:
  long rows_, first_;
  bool always_, show_, drawn_ = false;
  double last_ = 0.0;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

}  // namespace

int run_sweep(const SweepArgs& a, std::ostream& out, std::ostream& err_stream) {
  auto watch = driver::WorkMonitor::whole_command(a.run.work.budget);
  (void)out;
  // Under MPI every rank checks the same input and meets the same errors; rank 0 says so.
  std::string ranks_error;
  const std::unique_ptr<SweepRanks> ranks = sweep_ranks(ranks_error);
  const bool writer = ranks->rank() == 0;
  std::ostringstream other_ranks;
  std::ostream& err = writer ? err_stream : other_ranks;
  if (!ranks_error.empty()) {
    err << "mbsc: error: " << ranks_error << "\n";
    return 1;
  }
  auto fail = [&](const std::string& message) {
    err << "mbsc: error: " << message << "\n";
    return 1;
  };
  const RunArgs& ra = a.run;
  std::string error;
  if (!check_integration_options(ra, error)) return fail(error);
  const double dt_out = output_step(ra);

  // ---- the rows ----
  SweepPlan plan;
  plan.seed = a.seed;
  for (const auto& g : a.grids) {
    SweepGrid grid;
    if (!parse_grid(g, grid, error)) return fail(error);
    plan.grids.push_back(grid);
  }
  for (const auto& s : a.samples) {
    SweepSample sample;
    if (!parse_sample(s, sample, error)) return fail(error);
    plan.samples.push_back(sample);
  }
  if (a.per_point < 0) return fail("-n must be a positive number of rows");
  if (!plan.samples.empty() && a.per_point == 0) return fail("--sample needs -n, the number of rows per grid point");
  if (plan.grids.empty() && plan.samples.empty() && a.per_point == 0)
    return fail("a sweep needs --grid NAME=..., or --sample 'NAME~LAW(A,B)' with -n");
  plan.per_point = a.per_point > 0 ? a.per_point : 1;
  const long rows = plan.rows();
  if (rows > kMaxSweepRows) return fail(fmt::format("the sweep has more than {} rows", kMaxSweepRows));
  const std::vector<std::string> swept = plan.names();
  for (std::size_t i = 0; i < swept.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (swept[i] == swept[j]) return fail(fmt::format("'{}' is swept twice", printable(swept[i])));
  std::vector<SummarySpec> specs;
  if (a.eig) {  // (the rows are eigenvalues, not runs)
    if (!a.summaries.empty()) return fail("--summary: the rows of --eig are eigenvalues, not runs");
    if (!a.trajectories.empty()) return fail("--trajectories: the rows of --eig are eigenvalues, not runs");
    if (ra.multipliers || ra.minimal_state)
      return fail("--eig linearizes the complement form in a minimal state of its own: leave out --formulation and --state");
    if (a.find.size() != a.steady.size()) return fail(find_steady_count_error(a.find.size(), a.steady.size()));
  } else if (!parse_summaries(a.summaries.empty() ? std::vector<std::string>{"final"} : a.summaries, specs, error)) {
    return fail(error);
  }
  if (a.threads < 0) return fail("--threads must be 0 (every core) or more");
  for (const auto& [name, text] : ra.inputs)
    if (is_input_table(text))
      return fail(fmt::format("--input {}: a sweep takes inputs as expressions of t and the parameters, not tables",
                              printable(name)));

  // ---- the model: read, names routed, compiled once ----
  std::vector<std::string> sources;
  const std::optional<model::Model> m = read_model(ra.model, ra.work, sources, err);
  if (!m) return 1;
  std::map<std::string, double> sets, inits;
  if (!parse_assignments(ra.sets, "--set", sets, error) || !parse_assignments(ra.inits, "--init", inits, error))
    return fail(error);
  if (ra.baumgarte_alpha >= 0) sets["baumgarte_alpha"] = ra.baumgarte_alpha;
  if (ra.baumgarte_beta >= 0) sets["baumgarte_beta"] = ra.baumgarte_beta;
  // A swept name is a parameter (a --set of each row) or a coordinate or speed (an --init).
  std::vector<bool> is_parameter;
  for (const auto& name : swept) {
    if (sets.count(name) || inits.count(name))
      return fail(fmt::format("'{}' is swept and also given with --set or --init; give it one way", printable(name)));
    std::string why;
    const bool parameter = check_names(*m, {{name, 0.0}}, {}, ra.multipliers, why);
    if (!parameter && !check_names(*m, {}, {{name, 0.0}}, ra.multipliers, why))
      return fail(fmt::format("--grid/--sample: '{}' is neither a parameter nor a coordinate or speed of model '{}'",
                              printable(name), m->name));
    is_parameter.push_back(parameter);
  }
  if (!check_names(*m, sets, inits, ra.multipliers, error)) return fail(error);
  const std::string table_path = a.out.empty() ? m->name + "_sweep.csv" : a.out;
  const std::string partial_path = table_path + ".partial";
  if (table_path == "-") return fail("-o: a sweep writes its table to a file (it appends as rows finish)");
  if (!check_outputs({{"-o", table_path}, {"-o", partial_path}}, sources, error)) return fail(error);

  const CompileRequest req = compile_request(ra, ra.inputs);  // (the inputs are expressions, checked above)
  const NewtonJacobian newton = newton_jacobian(ra);
  int code = 1;
  // Under MPI rank 0 compiles (or finds the cache) before the others read the cache; a
  // rank that cannot ends them all.
  std::unique_ptr<CompiledModel> compiled, full_model;
  EigenRowOptions eig_options;
  eig_options.base.model_path = ra.model;
  eig_options.base.sets = ra.sets;
  eig_options.base.inits = ra.inits;
  for (const auto& [name, text] : ra.inputs) eig_options.base.inputs.push_back(name + "=" + text);
  eig_options.base.t = a.eig_t;
  eig_options.base.cache_dir = ra.cache_dir;
  eig_options.base.work = ra.work;
  eig_options.find = a.find;
  eig_options.steady = a.steady;
  eig_options.keep = a.keep;
  auto compile = [&] {
    if (a.eig) return static_cast<bool>(compiled = compile_for_linearization(eig_options.base, *m, sources, err, code));
    compiled = compile_model(req, *m, sources, err, code);
    if (compiled && ra.minimal_state) {  // the initial state is assembled on the full state
      CompileRequest full = req;
      full.minimal_state = false;
      full_model = compile_model(full, *m, sources, err, code);
    }
    return compiled && (full_model || !ra.minimal_state);
  };
  bool ready = writer && compile();
  ranks->barrier();
  if (!writer) ready = compile();
  if (ranks->all_min(ready ? 1 : 0) == 0) return ready ? 1 : code;
  const runtime::ModelTable& T = compiled->table();
  const runtime::ModelTable& TA = ra.minimal_state ? full_model->table() : T;

  // ---- the columns a summary may name ----
  bool has_energy = false;
  {
    // energy returns 4 (not defined) for every state when the model has none (a custom leaf without `kinetic`).
    std::vector<double> x(static_cast<std::size_t>(T.nx), 0.0), u0(static_cast<std::size_t>(std::max(1, T.nin)), 0.0), p0;
    double e[3];
    has_energy = parameter_values(T, sets, p0, error) && T.energy(0.0, x.data(), u0.data(), p0.data(), e) != 4;
  }
  const OutputRows columns(T, has_energy);
  const std::vector<std::string>& names = columns.names();
  auto column_index = [&](const std::string& name) {
    const auto it = std::find(names.begin(), names.end(), name);
    return it == names.end() ? -1 : static_cast<int>(it - names.begin());
  };
  const int nfull = T.nq_full + T.nu_full;
  std::vector<Summary> summaries;
  for (const auto& s : specs) {
    if (s.column.empty()) {  // final: every coordinate and speed
      for (int i = 0; i < nfull; ++i) summaries.push_back({s.kind, 1 + i, "final:" + names[static_cast<std::size_t>(1 + i)]});
      continue;
    }
    bool repeated = false;  // final:x beside final
    for (const auto& have : summaries) repeated = repeated || have.header == s.header();
    if (repeated) continue;
    if (s.column == "energy_change" && has_energy) {
      summaries.push_back({s.kind, -1, s.header()});
      continue;
    }
    const int c = column_index(s.column);
    if (c < 0) {
      std::vector<std::string> known = names;
      if (has_energy) known.push_back("energy_change");
      return fail(fmt::format("--summary {}: no column named '{}'{} (columns: {})", printable(s.header()),
                              printable(s.column), did_you_mean(s.column, known), fmt::join(known, ", ")));
    }
    summaries.push_back({s.kind, c, s.header()});
  }
  const bool constrained = !a.eig && T.nposc + T.nc > 0 && T.full_state_layout();
  if (a.eig) has_energy = false;

  // ---- --eig: the columns, from the first row's reference ----
  SweepEigenRows eigen_rows(*m, *compiled, eig_options);
  auto row_values = [&](const std::vector<double>& values) {
    std::map<std::string, double> named;
    for (std::size_t k = 0; k < swept.size(); ++k) named[swept[k]] = values[k];
    return named;
  };
  if (a.eig) {
    std::uint64_t first_seed = 0;
    if (!eigen_rows.prepare(row_values(plan.values(0, first_seed)), error)) return fail(error);
  }

  // ---- the trajectories (--trajectories DIR): each row's CSV, as mbsc run writes it ----
  const bool trajectories = !a.trajectories.empty();
  std::vector<int> trajectory_columns;
  std::vector<std::string> trajectory_names;
  if (!trajectories && !ra.columns.empty()) return fail("--columns: the trajectories' columns; give --trajectories DIR too");
  if (trajectories) {
    if (!csv_columns(names, ra.columns, trajectory_columns, error)) return fail("--columns: " + error);
    for (int c : trajectory_columns) trajectory_names.push_back(names[static_cast<std::size_t>(c)]);
    std::error_code ec;
    if (fs::exists(a.trajectories, ec) && !fs::is_directory(a.trajectories, ec))
      return fail(fmt::format("--trajectories: '{}' is not a folder", printable(a.trajectories)));
    // As mbsc run: output far larger than anyone reads is refused unless asked for.
    const double bytes = static_cast<double>(rows) * csv_bytes(ra.t_end, dt_out, trajectory_names.size());
    if (bytes > kLargeOutputBytes && !ra.large_output)
      return fail(fmt::format("--trajectories: {} rows of trajectories would take about {:.3g} GB; choose a larger "
                              "--dt-out or fewer --columns, or pass --large-output to write them anyway",
                              rows, bytes / 1e9));
  }
  const int row_digits = static_cast<int>(std::to_string(std::max(0L, rows - 1)).size());
  auto trajectory_path = [&](long r) {
    return (fs::path(a.trajectories) / fmt::format("row_{:0{}}.csv", r, row_digits)).string();
  };

  // ---- the table ----
  std::vector<std::string> header = {"row", "seed"};
  for (const auto& n : swept) header.push_back(n);
  for (const auto& s : summaries) header.push_back(s.header);
  if (a.eig) {
    for (const auto& c : eigen_rows.columns()) header.push_back(c);
    header.push_back("status");
  } else {
    for (const char* h : {"status", "t_reached", "steps", "rhs_evaluations"}) header.push_back(h);
  }
  if (constrained) {
    header.push_back("position_residual");
    header.push_back("velocity_residual");
  }
  if (has_energy) header.push_back("energy_change");
  header.push_back("message");
  std::string header_line;
  for (const auto& h : header) header_line += (header_line.empty() ? "" : ",") + csv_field(h);
  // The signature: everything that decides a row's values (the model's text included).
  std::string decided = std::string(MBSC_VERSION) + "\n" + header_line + "\n";
  for (const auto& src : sources) {
    std::ifstream in(src, std::ios::binary);
    decided += std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>()) + "\n";
  }
  for (const auto& g : a.grids) decided += "grid " + g + "\n";
  for (const auto& s : a.samples) decided += "sample " + s + "\n";
  decided += fmt::format("n {} seed {} t_end {} dt_out {} integrator {} rtol {} atol {} h {} formulation {} state {} "
                         "solver {} projection {} newton {} continuation {}\n",
                         plan.per_point, a.seed, ra.t_end, dt_out, ra.integrator, ra.rtol, ra.atol, ra.h,
                         ra.multipliers, ra.minimal_state, ra.solver, ra.projection, ra.newton_jacobian, ra.continuation);
  for (const auto& [k, v] : sets) decided += fmt::format("set {}={}\n", k, v);
  for (const auto& [k, v] : inits) decided += fmt::format("init {}={}\n", k, v);
  for (const auto& [k, v] : ra.inputs) decided += fmt::format("input {}={}\n", k, v);
  if (trajectories) decided += fmt::format("trajectories {} {}\n", a.trajectories, fmt::join(trajectory_names, ","));
  if (a.eig)
    decided += fmt::format("eig t {} find {} steady {} keep {}\n", a.eig_t, fmt::join(a.find, ","), fmt::join(a.steady, ","),
                           fmt::join(a.keep, ","));
  const std::string signature = "# mbsc sweep " + sha256_hex(decided);
  // Every rank needs the trajectories' folder (on a file system they share).
  std::error_code folder_error;
  if (trajectories) fs::create_directories(a.trajectories, folder_error);
  if (ranks->all_min(!trajectories || fs::is_directory(a.trajectories, folder_error) ? 1 : 0) == 0)
    return fail(fmt::format("--trajectories: cannot create the folder '{}'{}", printable(a.trajectories),
                            folder_error ? " (" + folder_error.message() + ")" : std::string()));
  // A sweep killed while rows were writing their trajectories leaves those files'
  // temporaries (.row_R.csv.mbsc-tmp-XXXXXX, driver/staged_file.hpp); rank 0 removes them
  // before any row of this sweep starts (the other ranks wait for it below).
  if (trajectories && writer) {
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(a.trajectories, ec)) {
      const std::string name = entry.path().filename().string();
      if (name.rfind(".row_", 0) == 0 && name.find(".csv.mbsc-tmp-") != std::string::npos && entry.is_regular_file(ec))
        fs::remove(entry.path(), ec);
    }
  }
  PartialTable partial;
  partial.path = partial_path;
  // Rank 0 owns the files; the others learn from it where the sweep starts (-1: it cannot).
  const bool opened = !writer || partial.open(signature, header_line, rows, error);
  const long resumed = ranks->broadcast(opened ? partial.rows_done : -1);
  if (!opened) return fail(error);
  if (resumed < 0) return 1;
  if (resumed > 0 && !ra.work.quiet)
    err << fmt::format("mbsc: continuing the sweep in {}: {} of {} rows done\n", printable(partial_path), resumed, rows);

  // ---- one row ----
  std::mutex symbolic;  // GiNaC: one row's start at a time
  const runtime::StepperOptions stepper = stepper_options(ra);
  const runtime::SimulationOptions simulation = simulation_options(ra, *m, T);  // (the same for every row)
  auto run_row = [&](long r, const std::vector<double>& values) {
    RowResult res;
    if (a.eig) {
      if (ra.work.budget.seconds_left() <= 0) {  // the budget: this row is not done
        res.status = "stopped";
        return res;
      }
      EigenRow e = eigen_rows.row(row_values(values), symbolic);
      res.summaries = std::move(e.values);
      res.status = e.status;
      res.message = without_error_prefix(e.message);
      return res;
    }
    res.summaries.assign(summaries.size(), kNan);
    std::vector<double> p, x0;
    std::vector<double> u(static_cast<std::size_t>(std::max(1, T.nin)), 0.0);
    {
      std::lock_guard<std::mutex> lock(symbolic);
      std::map<std::string, double> row_sets = sets, row_inits = inits;
      for (std::size_t k = 0; k < swept.size(); ++k) (is_parameter[k] ? row_sets : row_inits)[swept[k]] = values[k];
      std::string why;
      InitialState init;
      bool ok = false;
      try {
        ok = parameter_values(T, row_sets, p, why);
        if (ok) {
          compiled->inputs(0.0, p.data(), u.data());
          ok = initial_state(*m, TA, p, u, row_inits, 0.0, init, why);
        }
        if (ok) {
          x0 = init.x;
          if (ra.minimal_state) {
            x0.assign(static_cast<std::size_t>(T.nx), 0.0);
            for (int i = 0; i < T.nx; ++i)
              x0[static_cast<std::size_t>(i)] =
                  init.x[static_cast<std::size_t>(runtime::ModelTable::find(TA.state_names, TA.nx, T.state_names[i]))];
          }
          ok = rhs_finite_at_start(*m, T, TA, 0.0, x0, init.x, u, p, why);
        }
      } catch (const std::exception& e) {
        ok = false;
        why = std::string("internal error: ") + e.what();
      }
      if (!ok) {
        res.status = "start_error";
        res.message = without_error_prefix(why);
        return res;
      }
    }
    // The integration: the compiled model only, no lock.
    auto input_fn = [&](double t, double* uu) { return compiled->inputs(t, p.data(), uu); };
    CsvTable trajectory;  // (uncommitted, e.g. when the budget stops the row, it is removed)
    std::string write_error;
    if (trajectories && !trajectory.open(trajectory_path(r), trajectory_names, write_error)) {
      res.status = "failed";
      res.message = without_error_prefix(write_error);
      return res;
    }
    std::vector<double> trajectory_row(trajectory_columns.size());
    std::vector<Accumulator> acc(summaries.size());
    OutputRows rows_of_run(T, has_energy);
    std::vector<double> all, uu(u.size());
    auto observe = [&](double t, const std::vector<double>& x) {
      if (input_fn(t, uu.data()) != 0) std::fill(uu.begin(), uu.end(), kNan);
      rows_of_run.fill(t, x, uu.data(), p.data(), all);
      const double energy = has_energy ? all[columns.first_energy() + 2] : kNan;
      if (trajectories) {
        for (std::size_t k = 0; k < trajectory_columns.size(); ++k)
          trajectory_row[k] = all[static_cast<std::size_t>(trajectory_columns[k])];
        trajectory.row(trajectory_row);
      }
      for (std::size_t k = 0; k < summaries.size(); ++k) {
        if (summaries[k].column >= 0) acc[k].add(summaries[k].kind, all[static_cast<std::size_t>(summaries[k].column)]);
        else if (!std::isnan(energy)) acc[k].add(summaries[k].kind, std::fabs(energy - rows_of_run.initial_energy()));  // as the column
      }
    };
    const Integration run = integrate(*compiled, p, x0, ra.integrator, stepper, simulation, observe, ra.continuation, newton, input_fn);
    const runtime::SimulationResult& sr = run.result;
    res.t = sr.t;
    res.steps = run.stats.steps;
    res.rhs_evals = run.stats.rhs_evals;
    // As mbsc run reports them: the rows' residuals and those at the step ends.
    auto worst = [](double row, double step) { return std::isnan(row) ? row : std::max(row, step); };
    res.position_residual = worst(rows_of_run.position_residual(), sr.max_position_residual);
    res.velocity_residual = worst(rows_of_run.velocity_residual(), sr.max_velocity_residual);
    res.energy_change = rows_of_run.energy_change();
    for (std::size_t k = 0; k < summaries.size(); ++k) res.summaries[k] = acc[k].result(summaries[k].kind);
    if (!sr.ok()) {
      res.status = sr.status == runtime::SimulationResult::Status::Stopped ? "stopped" : "failed";
      res.message = sr.message;
    }
    // A failed run's trajectory is kept up to the failure, as its row says.
    if (trajectories && res.status != "stopped" && !trajectory.close(write_error)) {
      res.status = "failed";
      res.message = without_error_prefix(write_error);
    }
    return res;
  };
  auto row_text = [&](long r, std::uint64_t row_seed, const std::vector<double>& values, const RowResult& res) {
    std::string line = std::to_string(r) + "," + std::to_string(row_seed);
    for (double v : values) line += "," + number_text(v);
    for (double v : res.summaries) line += "," + number_text(v);
    if (a.eig) return line + "," + res.status + "," + csv_field(res.message) + "\n";
    line += "," + res.status + "," + number_text(res.t) + "," + std::to_string(res.steps) + "," + std::to_string(res.rhs_evals);
    if (constrained) line += "," + number_text(res.position_residual) + "," + number_text(res.velocity_residual);
    if (has_energy) line += "," + number_text(res.energy_change);
    return line + "," + csv_field(res.message) + "\n";
  };

  // ---- the workers ----
  // Rows are taken in order: alone from one counter; under MPI rank 0 takes its own from
  // it and hands the others theirs when they ask (a few at a time, so a rank that draws
  // long runs takes fewer). The default is every core alone, one thread per rank under MPI
  // (a rank per core).
  const bool under_mpi = ranks->size() > 1;
  const int wanted = a.threads > 0 ? a.threads
                     : under_mpi   ? 1
                                   : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const int threads = static_cast<int>(std::max<long>(1, std::min<long>(rows - resumed, wanted)));
  long next = resumed;  // rank 0: the next row nobody has taken
  std::atomic<bool> stopped{false};
  std::mutex table;  // the buffer, the partial file, the counts, the progress line, the rows handed out
  std::map<long, std::string> waiting;
  long written = resumed, failed = 0;
  bool write_failed = false;
  // Tests kill a sweep here (as a user would) after this many rows in the partial table.
  const char* abort_env = std::getenv("MBSC_SWEEP_ABORT_AFTER_ROWS");
  const long abort_after = abort_env ? std::atol(abort_env) : -1;
  SweepProgress progress(rows, resumed,
                         ra.work.quiet || !writer ? driver::ProgressMode::Never : ra.work.progress);
  watch.note("sweeping", fmt::format("{} rows of model {}", rows, m->name));
  const auto t_start = std::chrono::steady_clock::now();
  // A row is started only while fewer than `ahead` rows (of all ranks) wait behind an
  // unfinished one, so the buffer stays bounded when one row runs long. Under MPI a rank
  // keeps up to kQueued rows per thread queued (see the asks below), inside the window.
  constexpr long kQueued = 256;
  const long ahead = (under_mpi ? 2 * kQueued : 64L) * threads * ranks->size();
  std::condition_variable row_written, rows_came;
  std::deque<long> assigned;  // rank > 0: rows rank 0 handed out, not yet started
  bool no_more_rows = false;  // rank > 0: rank 0 said so
  std::vector<SweepMessage> outbox;  // rank > 0: finished lines for rank 0
  double row_seconds = 0.0;  // the time this rank's rows took, and how many it ran
  long rows_run = 0;
  // A finished row (with `table` held): rank 0 puts it in order into the partial table;
  // the others leave it for the main thread to send.
  auto deliver = [&](long r, std::string line, bool row_failed) {
    failed += row_failed;
    if (!writer) {
      SweepMessage m;
      m.kind = SweepMessage::Kind::Line;
      m.row = r;
      m.line = std::move(line);
      m.failed = row_failed;
      outbox.push_back(std::move(m));
      return;
    }
    waiting[r] = std::move(line);
    for (auto it = waiting.begin(); it != waiting.end() && it->first == written && !write_failed; it = waiting.erase(it)) {
      if (!partial.append(it->second)) {  // (disk full): stop; the rows written so far stay whole
        write_failed = stopped = true;
        break;
      }
      ++written;
      if (abort_after >= 0 && written >= abort_after) std::_Exit(3);
    }
    row_written.notify_all();
    progress.update(written, failed);
  };
  // The next row for a worker of this rank; false when there is none.
  auto take_row = [&](long& r) {
    std::unique_lock<std::mutex> lock(table);
    if (!writer) {
      rows_came.wait(lock, [&] { return stopped || !assigned.empty() || no_more_rows; });
      if (stopped || assigned.empty()) return false;
      r = assigned.front();
      assigned.pop_front();
      return true;
    }
    if (stopped || (r = next++) >= rows) return false;
    row_written.wait(lock, [&] { return stopped || r < written + ahead; });
    return !stopped;
  };
  auto worker = [&] {
    for (long r; take_row(r);) {
      std::uint64_t row_seed = 0;
      const std::vector<double> values = plan.values(r, row_seed);
      RowResult res;
      const auto row_start = std::chrono::steady_clock::now();
      try {
        res = run_row(r, values);
      } catch (const std::exception& e) {  // (a thread must not let one escape)
        res = RowResult();
        res.summaries.assign(a.eig ? eigen_rows.columns().size() : summaries.size(), kNan);
        res.status = "failed";
        res.message = std::string("internal error: ") + e.what();
      }
      std::lock_guard<std::mutex> lock(table);
      if (res.status == "stopped") {  // the budget: this row is not done
        stopped = true;
        row_written.notify_all();
        rows_came.notify_all();
        return;
      }
      deliver(r, row_text(r, row_seed, values, res), res.status != "ok");
      row_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - row_start).count();
      ++rows_run;
    }
  };
  std::vector<std::thread> pool;
  if (!under_mpi) {  // alone: this thread works too
    for (int k = 1; k < threads; ++k) pool.emplace_back(worker);
    worker();
    for (auto& t : pool) t.join();
  } else {
    // Under MPI only this thread talks to MPI. Rank 0 answers asks for rows and takes the
    // other ranks' lines into the table until every rank is done; another rank keeps a few
    // rows queued for its workers and sends their lines.
    std::atomic<int> working{threads};
    for (int k = 0; k < threads; ++k) pool.emplace_back([&] {
      worker();
      --working;
    });
    int ranks_done = 0;
    bool asking = false;
    // An answer without rows (the window is full) is asked again a little later.
    auto ask_from = std::chrono::steady_clock::now();
    for (SweepMessage m;;) {
      bool idle = true;
      while (ranks->poll(m)) {
        idle = false;
        std::lock_guard<std::mutex> lock(table);
        switch (m.kind) {
          case SweepMessage::Kind::Ask: {  // (rank 0) rows in order, inside the window
            SweepMessage reply;
            reply.kind = SweepMessage::Kind::Rows;
            reply.peer = m.peer;
            while (!stopped && static_cast<long>(reply.rows.size()) < m.count && next < rows && next < written + ahead)
              reply.rows.push_back(next++);
            reply.end = stopped || next >= rows;
            ranks->send(reply);
            break;
          }
          case SweepMessage::Kind::Rows:  // (rank > 0)
            assigned.insert(assigned.end(), m.rows.begin(), m.rows.end());
            no_more_rows = m.end;
            asking = false;
            if (m.rows.empty()) ask_from = std::chrono::steady_clock::now() + std::chrono::milliseconds(5);
            rows_came.notify_all();
            break;
          case SweepMessage::Kind::Line: deliver(m.row, std::move(m.line), m.failed); break;
          case SweepMessage::Kind::Done:  // (rank 0) a rank whose budget ran out stops the sweep
            ++ranks_done;
            if (m.stopped) {
              stopped = true;
              row_written.notify_all();
            }
            break;
        }
      }
      std::vector<SweepMessage> lines;
      bool ask = false;
      long ask_count = 0;
      {
        std::lock_guard<std::mutex> lock(table);
        lines.swap(outbox);
        // Enough rows queued for about 20 ms of work (4 per thread until a row has run),
        // asked for when half of them are left: the workers never wait for an answer,
        // and the last rows of a sweep still spread over the ranks.
        const long queued = std::clamp<long>(
            rows_run > 0 ? std::lround(threads * 0.02 * rows_run / std::max(row_seconds, 1e-9)) : 4L * threads,
            4L * threads, kQueued * threads);
        ask = !writer && !asking && !no_more_rows && !stopped && 2 * static_cast<long>(assigned.size()) < queued &&
              std::chrono::steady_clock::now() >= ask_from;
        if (ask) ask_count = queued - static_cast<long>(assigned.size());
      }
      for (auto& line : lines) ranks->send(line);
      if (ask) {
        SweepMessage m_ask;
        m_ask.kind = SweepMessage::Kind::Ask;
        m_ask.count = ask_count;
        ranks->send(m_ask);
        asking = true;
      }
      idle = idle && lines.empty();
      // The workers' end is read before the outbox is: then no line can come after.
      bool finished = working == 0;
      {
        std::lock_guard<std::mutex> lock(table);
        finished = finished && outbox.empty();
      }
      if (finished && (writer ? ranks_done == ranks->size() - 1 : !asking)) break;
      if (idle) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    for (auto& t : pool) t.join();
    if (!writer) {
      SweepMessage done;
      done.kind = SweepMessage::Kind::Done;
      done.stopped = stopped;
      ranks->send(done);
      return stopped ? 1 : 0;
    }
  }
  progress.clear();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  if (write_failed) return fail(fmt::format("writing '{}' failed (disk full?)", printable(partial_path)));
  if (written < rows)
    return fail(fmt::format("the sweep ran out of its time budget ({:g} s, raise it with --budget SECONDS) after {} of "
                            "{} rows; they are in {}; run the same command again to continue",
                            ra.work.budget.seconds, written, rows, printable(partial_path)));

  // ---- the table, whole: the partial one without its signature line ----
  std::fclose(partial.file);
  partial.file = nullptr;
  // Copied in pieces: a table of 10^5 rows of a bicycle's states is a hundred megabytes.
  std::ifstream in(partial_path, std::ios::binary);
  std::string skipped;
  std::getline(in, skipped);
  driver::StagedFile staged;
  if (!staged.open(table_path, "-o", error)) return fail(error);
  std::vector<char> piece(1 << 20);
  while (in) {
    in.read(piece.data(), static_cast<std::streamsize>(piece.size()));
    if (in.gcount() > 0) staged.write(std::string(piece.data(), static_cast<std::size_t>(in.gcount())));
  }
  if (in.bad()) return fail(fmt::format("reading '{}' failed", printable(partial_path)));
  if (!staged.commit(error)) return fail(error);
  std::error_code ec;
  fs::remove(partial_path, ec);
  if (!ra.work.quiet)
    err << fmt::format("mbsc: sweep of {}: {} rows{} on {}{} thread{} in {:.3g} s, {} failed; wrote {}\n", m->name, rows,
                       resumed > 0 ? fmt::format(" ({} from an earlier run)", resumed) : "",
                       under_mpi ? fmt::format("{} ranks of ", ranks->size()) : "", threads, threads == 1 ? "" : "s", wall,
                       failed, printable(table_path));
  return 0;
}

}  // namespace mbsc::run
