// SPDX-License-Identifier: GPL-2.0-or-later
// mbsc eig: a linear model per grid point (the reference re-assembled there, a steady
// motion re-found from the previous point's), the minimal state fixed at the first point,
// eigenvalues tracked (run/eigen_sweep.hpp), stability crossings refined, CSV and plot.
#include "mbsc/run/eig_command.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <fstream>
#include <map>
#include <ostream>
#include <sstream>

#include "mbsc/diag/diagnostics.hpp"
#include "mbsc/driver/work_monitor.hpp"
#include "mbsc/diag/name_suggestions.hpp"
#include "mbsc/driver/staged_file.hpp"
#include "mbsc/run/eigen_sweep.hpp"
#include "mbsc/run/gnuplot_plot.hpp"
#include "mbsc/run/linear_reference.hpp"
#include "mbsc/run/output_guard.hpp"
#include "mbsc/run/run_setup.hpp"

namespace mbsc::run {

bool parse_sweep(const std::string& text, std::string& name, std::vector<double>& grid, std::string& error) {
  const auto eq = text.find('=');
  std::vector<double> v;
  std::string rest = eq == std::string::npos ? "" : text.substr(eq + 1);
  for (std::size_t start = 0; eq != std::string::npos;) {
    const auto colon = rest.find(':', start);
    const std::string part = rest.substr(start, colon == std::string::npos ? std::string::npos : colon - start);
    char* end = nullptr;
    const double x = std::strtod(part.c_str(), &end);
    if (part.empty() || end != part.c_str() + part.size()) {
      v.clear();
      break;
    }
    v.push_back(x);
    if (colon == std::string::npos) break;
    start = colon + 1;
  }
  if (eq == std::string::npos || eq == 0 || v.size() != 3) {
    error = fmt::format("--sweep expects NAME=FROM:TO:STEP (e.g. v=0:10:0.01), got '{}'", printable(text));
    return false;
  }
  name = text.substr(0, eq);
  const double from = v[0], to = v[1], step = v[2];
  if (!std::isfinite(from) || !std::isfinite(to) || !std::isfinite(step)) {
    error = fmt::format("--sweep {}: the range and the step must be finite numbers", printable(name));
    return false;
  }
  if (step == 0.0 || (to - from) / step < 0.0 || from == to) {
    error = fmt::format("--sweep {}: the range {}:{} with step {} is empty (the step must be nonzero and go from FROM "
                        "toward TO, and TO differ from FROM)", printable(name), from, to, step);
    return false;
  }
  const double count = std::floor((to - from) / step * (1 + 1e-12)) + 1;
  if (count > 1e5) {
    error = fmt::format("--sweep {}: {:.0f} points; at most 100 000", printable(name), count);
    return false;
  }
  grid.clear();
  for (long k = 0; k < static_cast<long>(count); ++k) grid.push_back(from + static_cast<double>(k) * step);
  if (grid.size() < 2) {
    error = fmt::format("--sweep {}: the range {}:{} holds one point with step {}; a sweep needs two", printable(name), from,
                        to, step);
    return false;
  }
  return true;
}

int run_eig(const EigArgs& a, std::ostream& out, std::ostream& err) {
  // The budgets cover the whole command: past them its watcher ends the process.
  const auto watch = driver::WorkMonitor::whole_command(a.work.budget);
  auto fail = [&](const std::string& message) {
    err << "mbsc: error: " << message << "\n";
    return 1;
  };
  std::string name, error;
  std::vector<double> grid;
  if (!parse_sweep(a.sweep, name, grid, error)) return fail(error);
  if (!a.plot.empty() && plot_format(a.plot).empty()) return fail(fmt::format("--plot: '{}' should end in .svg or .png", printable(a.plot)));
  std::vector<std::string> sources;
  const std::optional<model::Model> m = read_model(a.model, a.work, sources, err);
  if (!m) return 1;
  const bool to_stdout = a.csv == "-";
  const std::string csv_path = a.csv.empty() ? m->name + "_eig.csv" : a.csv;
  if (!a.plot.empty() && to_stdout) return fail("--plot needs the CSV in a file (-o FILE), not on standard output");
  if (!check_outputs({{"-o", csv_path}, {"--plot", a.plot}}, sources, error)) return fail(error);
  if (!a.plot.empty() && !gnuplot_available(error)) return fail("--plot: " + error);

  ReferenceRequest req;
  req.model_path = a.model;
  req.lets = a.lets, req.sets = a.sets, req.inits = a.inits, req.inputs = a.inputs;
  req.t = a.t;
  req.cache_dir = a.cache_dir;
  req.work = a.work;
  int code = 1;
  const auto compiled = compile_for_linearization(req, *m, sources, err, code);
  if (!compiled) return code;
  const runtime::ModelTable& T = compiled->table();
  // The swept name: a --let, a parameter or a state component (then an --init).
  {
    std::map<std::string, double> lets;
    if (!parse_assignments(a.lets, "--let", lets, error)) return fail(error);
    std::vector<std::string> pool = runtime::ModelTable::names_of(T.param_names, T.np);
    for (const auto& [n, v] : lets) pool.push_back(n);
    for (int i = 0; i < T.nx; ++i) pool.push_back(T.state_names[i]);
    if (std::find(pool.begin(), pool.end(), name) == pool.end())
      return fail(fmt::format("--sweep: '{}' is not a --let name, a parameter or a coordinate or speed of the model{}",
                              printable(name), did_you_mean(name, pool)));
  }
  const auto state_names = runtime::ModelTable::names_of(T.state_names, T.nx);
  if (a.find.size() != a.steady.size()) return fail(find_steady_count_error(a.find.size(), a.steady.size()));
  if (std::find(a.find.begin(), a.find.end(), name) != a.find.end())
    return fail(fmt::format("--find {}: that is the swept value; a steady motion solves for other unknowns", printable(name)));

  // The steady motion found at each grid point (continuation: each starts from the nearest
  // point solved before).
  std::map<double, std::map<std::string, double>> found;
  std::vector<int> sel, cyclic, kept;  // kept, cyclic: positions in sel
  std::vector<std::string> cyclic_names;
  LinearReference first_ref;  // the first point's, for the steadiness check
  auto linear_at = [&](double value, runtime::LinearModel& lin, std::string& why, bool first = false) {
    if (a.work.budget.seconds_left() <= 0) {
      why = fmt::format("the time budget of {:g} s for the whole command ran out (raise it with --budget SECONDS)",
                        a.work.budget.seconds);
      return false;
    }
    ReferenceRequest r = req;
    r.overrides[name] = value;
    LinearReference ref;
    if (!a.find.empty()) {
      if (!found.empty()) {
        auto near = found.lower_bound(value);
        if (near == found.end() || (near != found.begin() && std::fabs(std::prev(near)->first - value) < std::fabs(near->first - value)))
          near = std::prev(near);
        for (const auto& [n, v] : near->second) r.overrides[n] = v;
      }
      if (!find_steady(*m, *compiled, r, a.find, a.steady, ref, why)) return false;
      std::map<std::string, double> solution;
      for (const auto& n : a.find) solution[n] = r.overrides.at(n);
      found[value] = solution;
    } else if (!reference_state(*m, *compiled, r, ref, why)) {
      return false;
    }
    if (runtime::linear_model(parts_of(*compiled, *m), a.t, ref.x.data(), ref.u.data(), ref.p.data(), lin, why) != 0) return false;
    if (first) first_ref = ref;
    return true;
  };
  // The minimal state, chosen at the first point and kept along the sweep (so that
  // eigenvectors keep their meaning).
  {
    runtime::LinearModel lin;
    if (!linear_at(grid.front(), lin, error, true)) return fail(fmt::format("at {} = {}: {}", name, grid.front(), error));
    if (!minimal_state(lin, T, a.keep, sel, error)) return fail(error);
    const double rate = model_rate(parts_of(*compiled, *m), T, a.t, first_ref, sel);
    if (const std::string w = model_rate_warning(rate); !w.empty() && !a.work.quiet)
      err << fmt::format("mbsc: warning: at {} = {}: {} (try --keep)\n", name, grid.front(), w);

    // Cyclic components (exact zero eigenvalues, Jordan blocks that rounding would split
    // into eps^(1/k) noise around zero) are left out of the sweep.
    std::vector<double> Am, Bm;
    if (!runtime::restrict_to(lin, sel, Am, Bm)) return fail("the minimal state does not parametrize the linearized constraints");
    const int n = static_cast<int>(sel.size());
    cyclic = runtime::cyclic_components(Am, n);
    for (int i : cyclic) cyclic_names.push_back(state_names[static_cast<std::size_t>(sel[static_cast<std::size_t>(i)])]);
    for (int i = 0; i < n; ++i)
      if (!std::binary_search(cyclic.begin(), cyclic.end(), i)) kept.push_back(i);
  }
  std::vector<std::string> sel_names;  // the components the eigenvectors have
  for (int i : kept) sel_names.push_back(state_names[static_cast<std::size_t>(sel[static_cast<std::size_t>(i)])]);
  if (!cyclic.empty() && !a.work.quiet)
    err << fmt::format("mbsc: left out of the sweep (cyclic: nothing depends on them, eigenvalue 0): {}\n", fmt::join(cyclic_names, ", "));
  struct RatioSpec {
    std::string label;
    int num = 0, den = 0;
  };
  std::vector<RatioSpec> ratios;
  for (const auto& spec : a.ratios) {
    const auto slash = spec.find('/');
    RatioSpec r{spec, -1, -1};
    if (slash != std::string::npos) {
      for (std::size_t k = 0; k < sel_names.size(); ++k) {
        if (sel_names[k] == spec.substr(0, slash)) r.num = static_cast<int>(k);
        if (sel_names[k] == spec.substr(slash + 1)) r.den = static_cast<int>(k);
      }
    }
    if (slash == std::string::npos || r.num < 0 || r.den < 0)
      return fail(fmt::format("--ratio {}: expects NUM/DEN, two components of the minimal state ({}; add others with --keep)",
                              printable(spec), fmt::join(sel_names, ", ")));
    ratios.push_back(r);
  }
  const MatrixAt matrix_at = [&](double value, Eigen::MatrixXd& A, std::string& why) {
    runtime::LinearModel lin;
    if (!linear_at(value, lin, why)) return false;
    std::vector<double> Am, Bm;
    if (!runtime::restrict_to(lin, sel, Am, Bm)) {
      why = fmt::format("the minimal state chosen at the first point ({}) no longer parametrizes the linearized constraints",
                        fmt::join(sel_names, ", "));
      return false;
    }
    const int n = static_cast<int>(sel.size()), k = static_cast<int>(kept.size());
    double scale = 0.0;
    for (double e : Am) scale = std::max(scale, std::fabs(e));
    for (int i : kept)
      for (int j : cyclic)
        if (std::fabs(Am[static_cast<std::size_t>(i * n + j)]) > 1e-10 * scale) {
          why = fmt::format("{} is no longer cyclic here ({}' depends on it)", state_names[static_cast<std::size_t>(sel[static_cast<std::size_t>(j)])],
                            state_names[static_cast<std::size_t>(sel[static_cast<std::size_t>(i)])]);
          return false;
        }
    A.resize(k, k);
    for (int i = 0; i < k; ++i)
      for (int j = 0; j < k; ++j) A(i, j) = Am[static_cast<std::size_t>(kept[static_cast<std::size_t>(i)] * n + kept[static_cast<std::size_t>(j)])];
    return true;
  };
  TrackedSweep sweep;
  if (!sweep_eigenvalues(matrix_at, grid, sweep, error, name)) return fail(error);
  {
    // Zeros that are not cyclic in the chosen components (a symmetry spread over several of
    // them) stay in the sweep as a Jordan block, split by rounding into eps^(1/k) noise.
    double big = 0.0;
    for (const auto& z : sweep.values.front()) big = std::max(big, std::abs(z));
    int small = 0;
    for (const auto& z : sweep.values.front()) small += std::abs(z) <= 1e-5 * big;
    if (small > 1 && !a.work.quiet)
      err << fmt::format("mbsc: warning: {} eigenvalues are near zero at the first point and are not cyclic components of the "
                         "state ({}): roots near zero may be less accurate; choose components with --keep so that the "
                         "symmetric coordinates become cyclic\n",
                         small, fmt::join(sel_names, ", "));
  }
  std::vector<StabilityCrossing> crossings;
  if (!stability_crossings(matrix_at, sweep, crossings, error, 1e-12, name)) return fail(error);

  // The CSV: the parameter, the steady motion's unknowns, each mode's real and imaginary
  // parts, then the ratios' magnitude and phase (degrees) per mode.
  std::ostringstream eig_csv;
  write_sweep_csv(eig_csv, sweep, name);
  std::istringstream lines(eig_csv.str());
  std::string line;
  std::getline(lines, line);
  std::vector<std::string> columns;
  {
    std::istringstream header(line);
    for (std::string c; std::getline(header, c, ',');) columns.push_back(c);
  }
  columns.insert(columns.begin() + 1, a.find.begin(), a.find.end());
  const int nmodes = sweep.modes();
  for (const auto& r : ratios)
    for (int k = 0; k < nmodes; ++k) {
      columns.push_back(fmt::format("abs({})_{}", r.label, k + 1));
      columns.push_back(fmt::format("arg({})_{}", r.label, k + 1));
    }
  std::string text = fmt::format("{}\n", fmt::join(columns, ","));
  for (std::size_t p = 0; std::getline(lines, line); ++p) {
    const auto comma = line.find(',');
    std::string row = line.substr(0, comma);
    for (const auto& n : a.find) row += "," + fmt::format("{:.17g}", found.count(grid[p]) ? found[grid[p]].at(n) : NAN);
    row += line.substr(comma);
    for (const auto& r : ratios)
      for (int k = 0; k < nmodes; ++k) {
        const std::complex<double> z = ratio(sweep.vectors[p][static_cast<std::size_t>(k)], r.num, r.den);
        row += fmt::format(",{:.17g},{:.17g}", std::abs(z), std::arg(z) * 180.0 / M_PI);
      }
    text += row + "\n";
  }
  std::ostream& report = to_stdout ? err : out;
  if (crossings.empty()) report << fmt::format("no mode changes stability for {} in [{}, {}]\n", name, grid.front(), grid.back());
  for (const auto& c : crossings)
    report << fmt::format("mode {} becomes {} at {} = {:.15g} (eigenvalue {:.10g} {:+.10g}i)\n", c.mode + 1,
                          c.becomes_stable ? (c.marginal ? "marginally stable" : "stable")
                                           : (c.marginal ? "unstable (from marginally stable)" : "unstable"),
                          name, c.param, c.value.real(), c.value.imag());
  if (to_stdout) {
    out << text;
    return 0;
  }
  driver::StagedFile file;
  if (!file.stage(csv_path, text, "-o", error) || !file.commit(error)) {
    err << error << "\n";
    return 1;
  }
  if (!a.work.quiet) err << fmt::format("mbsc: wrote {} ({} points, {} modes)\n", printable(csv_path), grid.size(), nmodes);
  if (!a.plot.empty()) {
    std::vector<PlotPanel> panels = {{"Re(lambda), 1/s", {}}, {"Im(lambda), rad/s", {}}};
    const int first = 1 + static_cast<int>(a.find.size());
    for (int k = 0; k < nmodes; ++k) {
      panels[0].ycols.push_back(first + 2 * k);
      panels[1].ycols.push_back(first + 2 * k + 1);
    }
    for (std::size_t r = 0; r < ratios.size(); ++r) {
      PlotPanel panel{"|" + ratios[r].label + "|", {}};
      for (int k = 0; k < nmodes; ++k) panel.ycols.push_back(first + 2 * nmodes + static_cast<int>(r) * 2 * nmodes + 2 * k);
      panels.push_back(panel);
    }
    if (!plot_panels(csv_path, columns, 0, panels, a.plot, m->name + ": eigenvalues against " + name, error))
      return fail("--plot: " + error);
    if (!a.work.quiet) err << fmt::format("mbsc: wrote {}\n", printable(a.plot));
  }
  return 0;
}

}  // namespace mbsc::run
