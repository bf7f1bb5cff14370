// SPDX-License-Identifier: GPL-2.0-or-later
// mbsc linearize: the model compiled with linear_parts, the reference assembled as for
// `mbsc run`, the linear model formed by the runtime (runtime/linear_model.hpp), restricted
// to a minimal state, and written with its eigenvalues.
#include "mbsc/run/linearize_command.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <ostream>
#include <sstream>

#include "mbsc/diag/diagnostics.hpp"
#include "mbsc/diag/name_suggestions.hpp"
#include "mbsc/driver/staged_file.hpp"
#include "mbsc/run/compiled_model.hpp"
#include "mbsc/run/linear_reference.hpp"
#include "mbsc/run/output_guard.hpp"
#include "mbsc/run/run_setup.hpp"

namespace mbsc::run {

namespace {

std::string num(double v) { return fmt::format("{:.17g}", v); }

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

std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    if (static_cast<unsigned char>(c) < 0x20) {
      out += fmt::format("\\u{:04x}", static_cast<int>(c));
      continue;
    }
    out += c;
  }
  return out + "\"";
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

int run_linearize(const LinearizeArgs& a, std::ostream& out, std::ostream& err) {
  auto fail = [&](const std::string& message) {
    err << "mbsc: error: " << message << "\n";
    return 1;
  };
  std::vector<std::string> sources;
  const std::optional<model::Model> m = read_model(a.model, a.work, sources, err);
  if (!m) return 1;
  std::string error;
  if (!check_outputs({{"-o", a.out}}, sources, error)) return fail(error);
  LinearReference ref;
  int code = 1;
  ReferenceRequest req;
  req.model_path = a.model;
  req.sets = a.sets, req.inits = a.inits, req.inputs = a.inputs;
  req.t = a.t;
  req.cache_dir = a.cache_dir;
  req.work = a.work;
  const auto compiled = compile_for_linearization(req, *m, sources, err, code);
  if (!compiled) return code;
  if (!reference_state(*m, *compiled, req, ref, error)) return fail(error);
  const runtime::ModelTable& T = compiled->table();
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
  runtime::LinearModel lin;
  if (runtime::linear_model(parts_of(*compiled), a.t, ref.x.data(), ref.u.data(), ref.p.data(), lin, error) != 0)
    return fail(fmt::format("model {}: cannot linearize at the reference: {}", m->name, error));
  const std::vector<std::string> full_names = runtime::ModelTable::names_of(T.state_names, T.nx);
  const std::vector<std::string> inputs = runtime::ModelTable::names_of(T.input_names, T.nin);

  // The state written: the minimal one (components of the tangent space) or the full layout.
  std::vector<int> sel;
  std::vector<double> A, B;
  if (a.state == "full") {
    for (int i = 0; i < lin.n; ++i) sel.push_back(i);
    A = lin.A, B = lin.B;
  } else {
    std::vector<int> preferred;
    for (const auto& name : a.keep) {
      const int i = runtime::ModelTable::find(T.state_names, T.nx, name.c_str());
      if (i < 0) return fail(fmt::format("--keep: the model has no coordinate or speed named '{}'{}", printable(name), did_you_mean(name, full_names)));
      preferred.push_back(i);
    }
    sel = runtime::minimal_components(lin, preferred);
    for (int i : preferred)
      if (std::find(sel.begin(), sel.end(), i) == sel.end())
        return fail(fmt::format("--keep: {} cannot be part of the minimal state together with the components before it (the "
                                "linearized constraints fix it)", full_names[static_cast<std::size_t>(i)]));
    if (!runtime::restrict_to(lin, sel, A, B)) return fail("the chosen components do not parametrize the linearized constraints");
  }
  const int ns = static_cast<int>(sel.size());
  std::vector<std::string> names;
  for (int i : sel) names.push_back(full_names[static_cast<std::size_t>(i)]);
  const auto eig = sorted_eigenvalues(A, ns);

  std::ostringstream text;
  if (a.format == "json") {
    text << "{\n  \"model\": " << json_string(m->name) << ",\n  \"t\": " << num(a.t) << ",\n  \"reference\": {";
    for (int i = 0; i < T.nx; ++i) text << (i ? ", " : "") << json_string(full_names[static_cast<std::size_t>(i)]) << ": " << num(ref.x[static_cast<std::size_t>(i)]);
    text << "},\n  \"constraint_rank\": " << lin.constraint_rank << ",\n  \"constraints\": " << T.nc;
    text << ",\n  \"state\": " << json_names(names) << ",\n  \"inputs\": " << json_names(inputs);
    text << ",\n  \"A\": " << json_matrix(A, ns, ns) << ",\n  \"B\": " << json_matrix(B, ns, T.nin) << ",\n  \"eigenvalues\": [";
    for (std::size_t i = 0; i < eig.size(); ++i) text << (i ? ", " : "") << "[" << num(eig[i].real()) << ", " << num(eig[i].imag()) << "]";
    text << "]\n}\n";
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
    text << "eigenvalues:\n";
    for (const auto& e : eig) text << fmt::format("  {:>24.16g} {:+.16g}i\n", e.real(), e.imag());
  }
  if (a.out == "-") {
    out << text.str();
    return 0;
  }
  driver::StagedFile file;
  if (!file.stage(a.out, text.str(), "-o", error) || !file.commit(error)) return fail(error);
  if (!a.work.quiet) err << fmt::format("mbsc: wrote {}\n", printable(a.out));
  return 0;
}

}  // namespace mbsc::run
