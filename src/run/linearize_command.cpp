// SPDX-License-Identifier: GPL-2.0-or-later
// mbsc linearize: the model compiled with linear_parts, the reference assembled as for
// `mbsc run`, the linear model formed by the runtime (runtime/linear_model.hpp), restricted
// to a minimal state, and written with its eigenvalues.
#include "mbsc/run/linearize_command.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <map>
#include <optional>
#include <ostream>
#include <sstream>

#include "mbsc/analysis/symbolic_linearize.hpp"
#include "mbsc/diag/diagnostics.hpp"
#include "mbsc/driver/work_monitor.hpp"
#include "mbsc/diag/name_suggestions.hpp"
#include "mbsc/driver/staged_file.hpp"
#include "mbsc/run/compiled_model.hpp"
#include "mbsc/run/json_text.hpp"
#include "mbsc/run/linear_reference.hpp"
#include "mbsc/run/output_guard.hpp"
#include "mbsc/run/run_setup.hpp"
#include "mbsc/run/second_order_form.hpp"

namespace mbsc::run {

namespace {

std::string num(double v) { return fmt::format("{:.17g}", v == 0.0 ? 0.0 : v); }  // -0 as 0

// Matrix rows x cols (row-major) as text with aligned columns.
std::string matrix_text(const std::vector<double>& M, int rows, int cols, const std::vector<std::string>& row_names,
                        const std::vector<std::string>& col_names) {
  std::size_t w = 0;
  for (const auto& s : row_names) w = std::max(w, s.size());
  std::string out = fmt::format("  {:<{}}", "", w);
  for (const auto& c : col_names) out += fmt::format(" {:>24}", c);
  out += "\n";
  for (int i = 0; i < rows; ++i) {
    out += fmt::format("  {:<{}}", row_names[static_cast<std::size_t>(i)], w);
    for (int j = 0; j < cols; ++j) out += fmt::format(" {:>24.16g}", M[static_cast<std::size_t>(i * cols + j)]);
    out += "\n";
  }
  return out;
}

std::string json_names(const std::vector<std::string>& names) {
  std::string out = "[";
  for (std::size_t i = 0; i < names.size(); ++i) out += (i ? ", " : "") + json_string(names[i]);
  return out + "]";
}

std::string json_matrix(const std::vector<double>& M, int rows, int cols) {
  std::string out = "[";
  for (int i = 0; i < rows; ++i) {
    out += i ? ",\n    [" : "\n    [";
    for (int j = 0; j < cols; ++j) out += (j ? ", " : "") + num(M[static_cast<std::size_t>(i * cols + j)]);
    out += "]";
  }
  return out + (rows ? "\n  ]" : "]");
}

}  // namespace

namespace {

// A k x k matrix in the text output, rows and columns named by the coordinates.
std::string square_text(const char* label, const std::vector<double>& M, const std::vector<std::string>& names) {
  return std::string(label) + ":\n" + matrix_text(M, static_cast<int>(names.size()), static_cast<int>(names.size()), names, names);
}

}  // namespace

int run_linearize(const LinearizeArgs& a, std::ostream& out, std::ostream& err) {
  // The budgets cover the whole command: past them its watcher ends the process.
  const auto watch = driver::WorkMonitor::whole_command(a.work.budget);
  auto fail = [&](const std::string& message) {
    err << "mbsc: error: " << message << "\n";
    return 1;
  };
  if (a.speed.empty() != a.gravity.empty()) return fail("--speed and --gravity go together (the names of v and g)");
  if (!a.speed.empty() && a.second_order.empty()) return fail("--speed and --gravity split the form of --second-order: name its coordinates");
  if (a.format == "latex" && a.symbolic.empty()) return fail("--format latex writes a symbolic model: name its symbols with --symbolic");
  if (!a.symbolic.empty() && a.format == "csv") return fail("--symbolic writes text, latex or json (not --format csv)");
  std::vector<std::string> sources;
  const std::optional<model::Model> m = read_model(a.model, a.work, sources, err);
  if (!m) return 1;
  std::string error;
  if (!check_outputs({{"-o", a.out}}, sources, error)) return fail(error);
  int code = 1;
  ReferenceRequest req;
  req.model_path = a.model;
  req.lets = a.lets, req.sets = a.sets, req.inits = a.inits, req.inputs = a.inputs;
  req.t = a.t;
  req.cache_dir = a.cache_dir;
  req.work = a.work;
  const auto compiled = compile_for_linearization(req, *m, sources, err, code);
  if (!compiled) return code;
  const runtime::ModelTable& T = compiled->table();
  auto write_text = [&](const std::string& text) {
    if (a.out == "-") {
      out << text;
      return 0;
    }
    driver::StagedFile file;
    if (!file.stage(a.out, text, "-o", error) || !file.commit(error)) {
      err << error << "\n";
      return 1;
    }
    if (!a.work.quiet) err << fmt::format("mbsc: wrote {}\n", printable(a.out));
    return 0;
  };
  // The linear model at the reference the request (with overrides) gives.
  auto linearize_at = [&](const std::map<std::string, double>& overrides, LinearReference& ref, runtime::LinearModel& lin) {
    ReferenceRequest r = req;
    for (const auto& [name, v] : overrides) r.overrides[name] = v;
    if (!reference_state(*m, *compiled, r, ref, error)) return false;
    if (runtime::linear_model(parts_of(*compiled, *m), a.t, ref.x.data(), ref.u.data(), ref.p.data(), lin, error) != 0) {
      error = fmt::format("model {}: cannot linearize at the reference: {}", m->name, error);
      return false;
    }
    return true;
  };
  LinearReference ref;
  if (!a.find.empty() || !a.steady.empty()) {
    if (!find_steady(*m, *compiled, req, a.find, a.steady, ref, error)) return fail(error);
    if (!a.work.quiet)
      for (const auto& name : a.find) err << fmt::format("mbsc: steady motion: {} = {}\n", name, num(req.overrides.at(name)));
  }
  runtime::LinearModel lin;
  if (!linearize_at({}, ref, lin)) return fail(error);
  if (a.equilibrium) {
    std::vector<double> xd(static_cast<std::size_t>(T.nx));
    if (T.rhs(a.t, ref.x.data(), ref.u.data(), ref.p.data(), xd.data()) != 0)
      return fail("--equilibrium: the right-hand side cannot be evaluated at the reference");
    int worst = 0;
    for (int i = 1; i < T.nx; ++i)
      if (std::fabs(xd[static_cast<std::size_t>(i)]) > std::fabs(xd[static_cast<std::size_t>(worst)])) worst = i;
    double scale = 1.0;
    for (double v : ref.x) scale = std::max(scale, std::fabs(v));
    if (T.nx > 0 && !(std::fabs(xd[static_cast<std::size_t>(worst)]) <= 1e-8 * scale))
      return fail(fmt::format("--equilibrium: the reference is not at rest: the rate of {} is {} (the largest; a "
                              "steady motion is linearized without --equilibrium)",
                              T.state_names[worst], num(xd[static_cast<std::size_t>(worst)])));
  }
  const std::vector<std::string> full_names = runtime::ModelTable::names_of(T.state_names, T.nx);
  const std::vector<std::string> inputs = runtime::ModelTable::names_of(T.input_names, T.nin);
  auto index_of = [&](const std::string& flag, const std::string& name, bool coordinate, int& i) {
    i = runtime::ModelTable::find(T.state_names, T.nx, name.c_str());
    if (i >= 0 && (!coordinate || i < T.nq)) return true;
    const std::vector<std::string> pool(full_names.begin(), coordinate ? full_names.begin() + T.nq : full_names.end());
    error = i >= 0 ? fmt::format("{}: '{}' is a speed; name coordinates", flag, printable(name))
                   : fmt::format("{}: the model has no {} named '{}'{}", flag, coordinate ? "coordinate" : "coordinate or speed",
                                 printable(name), did_you_mean(name, pool));
    return false;
  };

  // The state written: the minimal one (components of the tangent space) or the full layout.
  std::vector<int> sel;
  std::vector<double> A, B;
  if (a.state == "full") {
    for (int i = 0; i < lin.n; ++i) sel.push_back(i);
    A = lin.A, B = lin.B;
  } else {
    if (!minimal_state(lin, T, a.keep, sel, error)) return fail(error);
    if (!runtime::restrict_to(lin, sel, A, B)) return fail("the chosen components do not parametrize the linearized constraints");
  }
  const int ns = static_cast<int>(sel.size());
  // Whether the reference is steady in these components (then the eigenvalues describe
  // its stability); the full layout's A is the thesis's (4.24) either way.
  const double rate = a.state == "full" ? 0.0 : model_rate(parts_of(*compiled, *m), T, a.t, ref, sel);
  const bool frozen = rate > 1e-4 || rate < 0;
  if (frozen && !a.work.quiet) err << "mbsc: warning: " << model_rate_warning(rate) << " (try --keep, or --state full)\n";
  if (!a.symbolic.empty()) {
    // The same model with names left as symbols; the reference recomputed with one
    // symbol moved at a time shows which values follow them.
    const analysis::ReferenceAt reference_at = [&](const std::map<std::string, double>& moved, LinearReference& r,
                                                   std::string& e) {
      ReferenceRequest q = req;
      for (const auto& [name, v] : moved) q.overrides[name] = v;
      if (!a.find.empty()) return find_steady(*m, *compiled, q, a.find, a.steady, r, e);
      return reference_state(*m, *compiled, q, r, e);
    };
    analysis::NumericLinearModel numeric{&ref, &lin, sel, &A, &B, {}};
    numeric.at_moved = [&](const LinearReference& r, std::vector<double>& Am, std::vector<double>& Bm, std::string& e) {
      runtime::LinearModel l;
      if (runtime::linear_model(parts_of(*compiled, *m), a.t, r.x.data(), r.u.data(), r.p.data(), l, e) != 0) return false;
      if (a.state == "full") return Am = l.A, Bm = l.B, true;
      if (!runtime::restrict_to(l, sel, Am, Bm)) return e = "the minimal state does not parametrize the constraints there", false;
      return true;
    };
    std::string text;
    if (!analysis::symbolic_linear_text(a, *m, T, req, numeric, reference_at, text, error, code)) {
      err << "mbsc: error: " << error << "\n";
      return code;
    }
    return write_text(text);
  }
  std::vector<std::string> names;
  for (int i : sel) names.push_back(full_names[static_cast<std::size_t>(i)]);
  std::vector<int> cyclic;
  const auto eig = eigenvalues_without_cyclic(A, ns, cyclic);
  std::vector<std::string> cyclic_names;
  for (int i : cyclic) cyclic_names.push_back(names[static_cast<std::size_t>(i)]);
  if (!a.find.empty()) {
    // A steady motion that --find landed on may be an unstable one (a pendulum upright):
    // say so, and how to ask for another.
    double largest = 0.0, size = 0.0;
    for (const auto& l : eig) {
      largest = std::max(largest, l.real());
      size = std::max(size, std::abs(l));
    }
    if (largest > 1e-9 * std::max(1.0, size))
      err << fmt::format("mbsc: note: the steady motion found is unstable (an eigenvalue with real part {:.6g}); "
                         "--find starts from the model's initial values and --init, so give a guess near the one "
                         "you want (--init NAME=VALUE) to find another\n",
                         largest);
  }

  // The second-order form, and its split in v and g.
  std::vector<int> coords;
  for (const auto& name : a.second_order) {
    int i = 0;
    if (!index_of("--second-order", name, true, i)) return fail(error);
    coords.push_back(i);
  }
  SecondOrderForm form;
  if (!coords.empty() && !second_order_form(lin, T.nq, coords, form, error)) return fail("--second-order: " + error);
  struct Split {
    double v = 0, g = 0;
    std::vector<double> C1, K0, K2;
    double residual = 0;  // the form's prediction at v/2 against the linear model there
  };
  std::optional<Split> split;
  if (!a.speed.empty()) {
    Split sp;
    auto value_of = [&](const std::string& flag, const std::string& name, double& v) {
      std::map<std::string, double> lets;
      if (!parse_assignments(a.lets, "--let", lets, error)) return false;
      if (lets.count(name)) return v = lets[name], true;
      const int k = runtime::ModelTable::find(T.param_names, T.np, name.c_str());
      if (k >= 0) return v = ref.p[static_cast<std::size_t>(k)], true;
      error = fmt::format("{}: '{}' is neither a --let name nor a parameter of the model{}", flag, printable(name),
                          did_you_mean(name, runtime::ModelTable::names_of(T.param_names, T.np)));
      return false;
    };
    if (!value_of("--speed", a.speed, sp.v) || !value_of("--gravity", a.gravity, sp.g)) return fail(error);
    if (sp.v == 0.0 || sp.g == 0.0) return fail("--speed and --gravity: the split needs v and g nonzero at the reference");
    auto form_at = [&](double v, SecondOrderForm& f) {
      LinearReference r;
      runtime::LinearModel l;
      if (!linearize_at({{a.speed, v}}, r, l)) return false;
      if (!second_order_form(l, T.nq, coords, f, error)) {
        error = fmt::format("--second-order at {} = {}: {}", a.speed, num(v), error);
        return false;
      }
      return true;
    };
    SecondOrderForm at_rest, half;
    if (!form_at(0.0, at_rest) || !form_at(sp.v / 2, half)) return fail(error);
    const std::size_t kk = form.M.size();
    sp.C1.resize(kk), sp.K0.resize(kk), sp.K2.resize(kk);
    double scale = 0;
    for (std::size_t i = 0; i < kk; ++i) {
      sp.C1[i] = form.C[i] / sp.v;
      sp.K0[i] = at_rest.K[i] / sp.g;
      sp.K2[i] = (form.K[i] - at_rest.K[i]) / (sp.v * sp.v);
      scale = std::max({scale, std::fabs(form.K[i]), std::fabs(form.C[i]), std::fabs(form.M[i])});
    }
    for (std::size_t i = 0; i < kk; ++i) {
      const double h = sp.v / 2;
      sp.residual = std::max({sp.residual, std::fabs(half.K[i] - (sp.g * sp.K0[i] + h * h * sp.K2[i])),
                              std::fabs(half.C[i] - h * sp.C1[i]), std::fabs(half.M[i] - form.M[i]),
                              std::fabs(at_rest.M[i] - form.M[i]), std::fabs(at_rest.C[i])});
    }
    sp.residual /= std::max(scale, 1e-300);
    split = sp;
  }

  std::ostringstream text;
  if (a.format == "json") {
    text << "{\n  \"model\": " << json_string(m->name) << ",\n  \"t\": " << num(a.t) << ",\n  \"reference\": {";
    for (int i = 0; i < T.nx; ++i) text << (i ? ", " : "") << json_string(full_names[static_cast<std::size_t>(i)]) << ": " << num(ref.x[static_cast<std::size_t>(i)]);
    text << "},\n  \"constraint_rank\": " << lin.constraint_rank << ",\n  \"constraints\": " << T.nc;
    text << ",\n  \"state\": " << json_names(names) << ",\n  \"inputs\": " << json_names(inputs);
    text << ",\n  \"A\": " << json_matrix(A, ns, ns) << ",\n  \"B\": " << json_matrix(B, ns, T.nin) << ",\n  \"eigenvalues\": [";
    for (std::size_t i = 0; i < eig.size(); ++i) text << (i ? ", " : "") << "[" << num(eig[i].real()) << ", " << num(eig[i].imag()) << "]";
    text << "],\n  \"cyclic\": " << json_names(cyclic_names) << ",\n  \"model_rate\": " << num(rate);
    if (!coords.empty()) {
      const int k = form.k;
      text << ",\n  \"second_order\": {\n  \"coordinates\": " << json_names(a.second_order) << ",\n  \"M\": "
           << json_matrix(form.M, k, k) << ",\n  \"C\": " << json_matrix(form.C, k, k) << ",\n  \"K\": "
           << json_matrix(form.K, k, k) << ",\n  \"coupling\": " << num(form.coupling);
      if (split)
        text << ",\n  \"v\": " << num(split->v) << ",\n  \"g\": " << num(split->g) << ",\n  \"C1\": "
             << json_matrix(split->C1, k, k) << ",\n  \"K0\": " << json_matrix(split->K0, k, k) << ",\n  \"K2\": "
             << json_matrix(split->K2, k, k) << ",\n  \"split_residual\": " << num(split->residual);
      text << "}";
    }
    text << "\n}\n";
  } else if (a.format == "csv") {
    text << "row";
    for (const auto& n : names) text << "," << n;
    for (const auto& n : inputs) text << "," << n;
    text << "\n";
    for (int i = 0; i < ns; ++i) {
      text << names[static_cast<std::size_t>(i)] << "'";
      for (int j = 0; j < ns; ++j) text << "," << num(A[static_cast<std::size_t>(i * ns + j)]);
      for (int j = 0; j < T.nin; ++j) text << "," << num(B[static_cast<std::size_t>(i * T.nin + j)]);
      text << "\n";
    }
  } else {
    text << fmt::format("linear model of {} about t = {} ({} state, {} of {} components)\n", m->name, num(a.t),
                        a.state == "full" ? "full" : "minimal", ns, lin.n);
    text << "reference:\n";
    for (int i = 0; i < T.nx; ++i) text << fmt::format("  {} = {}\n", full_names[static_cast<std::size_t>(i)], num(ref.x[static_cast<std::size_t>(i)]));
    if (lin.constraint_rank < T.nc)
      text << fmt::format("constraints: {} of rank {} at the reference ({} redundant: least-squares complement)\n", T.nc,
                          lin.constraint_rank, T.nc - lin.constraint_rank);
    text << "A = d(x')/dx:\n" << matrix_text(A, ns, ns, names, names);
    if (T.nin > 0) text << "B = d(x')/du:\n" << matrix_text(B, ns, T.nin, names, inputs);
    text << (rate > 1e-4  ? "eigenvalues (frozen at this instant: the model changes along the reference):\n"
             : rate < 0   ? "eigenvalues (whether the model changes along the reference could not be measured):\n"
                          : "eigenvalues:\n");
    if (!cyclic.empty())
      text << fmt::format("  0 (x{}: the cyclic components {}, which nothing depends on)\n", cyclic.size(), fmt::join(cyclic_names, ", "));
    for (std::size_t i = cyclic.size(); i < eig.size(); ++i) text << fmt::format("  {:>24.16g} {:+.16g}i\n", eig[i].real(), eig[i].imag());
    if (!coords.empty()) {
      text << fmt::format("second-order form M q'' + C q' + K q = T, q = ({}):\n", fmt::join(a.second_order, ", "));
      text << square_text("M", form.M, a.second_order) << square_text("C", form.C, a.second_order)
           << square_text("K", form.K, a.second_order);
      text << fmt::format("coupling to the rest of the state: {:.3g} (relative)\n", form.coupling);
      if (split) {
        text << fmt::format("split at {} = {}, {} = {}: M q'' + v C1 q' + (g K0 + v^2 K2) q = T\n", a.speed, num(split->v),
                            a.gravity, num(split->g));
        text << square_text("C1", split->C1, a.second_order) << square_text("K0", split->K0, a.second_order)
             << square_text("K2", split->K2, a.second_order);
        text << fmt::format("the split predicts the form at v/2 to {:.3g} (relative)\n", split->residual);
      }
    }
  }
  return write_text(text.str());
}

}  // namespace mbsc::run
