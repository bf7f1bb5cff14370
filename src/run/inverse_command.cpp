// SPDX-License-Identifier: GPL-2.0-or-later
// mbsc inverse: prescribed expressions -> Prescription callbacks -> InverseDynamics along
// the output grid -> a table (and its CSV). The command line (main.cpp) parses the
// options and loads the model; this file does the rest.
#include "inverse_command.hpp"

#include <fmt/format.h>
#include <ginac/ginac.h>

#include <cmath>
#include <memory>
#include <optional>

#include "mbsc/diag/diagnostics.hpp"
#include "mbsc/diag/name_suggestions.hpp"
#include "mbsc/driver/staged_file.hpp"
#include "mbsc/model/expr_convert.hpp"
#include "mbsc/parse/parse.hpp"
#include "mbsc/runtime/inverse_dynamics.hpp"

namespace mbsc::run {

namespace {

// q(t), q'(t), q''(t) of one prescribed coordinate: GiNaC expressions in the symbol t.
struct MotionExpressions {
  GiNaC::symbol t;
  GiNaC::ex q, qd, qdd;
};

// The statement the expression is wrapped in, so the model language's own parser and
// converter read it (same syntax, functions and messages); its columns are shifted back.
constexpr const char* kWrapHead = "model prescribed\noutput value = ";


// Reads `text` as an expression of t and the parameters; the error is
// "--prescribe NAME:COL: error: ..." (columns of the expression as given).
std::optional<MotionExpressions> read_expression(const std::string& coord, const std::string& text,
                                                 const std::map<std::string, double>& params, std::string& error) {
  const std::string where = "--prescribe " + coord;
  if (text.find_first_of("\n\r;") != std::string::npos) {
    error = where + ": error: the expression must be one line (no newline or ';')";
    return std::nullopt;
  }
  const std::size_t shift = std::string(kWrapHead).size() - std::string("model prescribed\n").size();
  auto report = [&](const Diagnostics& diags) {
    for (const auto& d : diags.all())
      if (d.severity == Severity::Error) {
        const int col = d.pos.line == 2 ? d.pos.col - static_cast<int>(shift) : 0;
        error = where + (col > 0 ? ":" + std::to_string(col) : std::string()) + ": error: " + printable(d.message) + " in '" +
                printable(text) + "'";
        return;
      }
    error = where + ": error: cannot read the expression '" + printable(text) + "'";
  };
  Diagnostics diags;
  const auto file = parse::parse_text(kWrapHead + text + "\n", where, diags);
  if (!file || diags.has_errors() || file->statements.size() != 2 ||
      file->statements[1]->kind != ast::Statement::Kind::Output || !file->statements[1]->value) {
    report(diags);
    return std::nullopt;
  }
  MotionExpressions m{GiNaC::symbol("t"), 0, 0, 0};
  std::vector<std::string> known = {"t", "pi"};
  for (const auto& [name, value] : params) known.push_back(name);
  model::ExprConverter conv(diags);
  conv.lookup = [&](const std::string& path, const SourcePos& pos, bool primed) -> std::optional<GiNaC::ex> {
    if (primed) {
      diags.error(pos, fmt::format("{}': a prescribed motion is written as a function of t, without derivatives", path));
      return std::nullopt;
    }
    if (path == "t") return GiNaC::ex(m.t);
    const auto it = params.find(path);
    if (it != params.end()) return GiNaC::ex(model::exact_decimal(it->second));
    diags.error(pos, fmt::format("unknown name '{}' (a prescribed motion is a function of t and the model's parameters){}", path,
                                 did_you_mean(path, known)));
    return std::nullopt;
  };
  const auto q = conv.convert(*file->statements[1]->value);
  if (!q || diags.has_errors()) {
    report(diags);
    return std::nullopt;
  }
  try {
    m.q = *q;
    m.qd = m.q.diff(m.t);
    m.qdd = m.qd.diff(m.t);
  } catch (const std::exception& e) {
    error = where + ": error: cannot differentiate '" + printable(text) + "': " + e.what();
    return std::nullopt;
  }
  return m;
}

double value_at(const GiNaC::ex& e, const GiNaC::symbol& t, double time) {
  double v = NAN;
  if (!model::evaluate_number(e.subs(t == model::exact_decimal(time)), v)) return NAN;
  return v;
}

std::string number_text(double v) { return fmt::format("{:.17g}", v); }

}  // namespace

std::string inverse_csv(const InverseTable& table) {
  std::string out;
  for (std::size_t i = 0; i < table.columns.size(); ++i) out += (i ? "," : "") + table.columns[i];
  out += "\n";
  for (const auto& row : table.rows) {
    for (std::size_t i = 0; i < row.size(); ++i) out += (i ? "," : "") + number_text(row[i]);
    out += "\n";
  }
  return out;
}

InverseOutcome inverse_command(const runtime::ModelTable& m, const InverseCommandOptions& opt, const std::string& model_label) {
  InverseOutcome out;
  auto bad = [&](std::string message) {
    out.exit_code = 1;
    out.message = std::move(message);
    return out;
  };
  if (!m.full_state_layout()) return bad("mbsc inverse: error: the model must be generated with the full state (--state full)");
  // The solve below reads the inputs off rhs, which it takes for affine in them. A model
  // whose own inverse_dynamics is not defined (status 4 without computing: Coulomb
  // friction closed inside rhs, or a forcing not affine in the inputs) breaks that.
  if (m.inverse_dynamics != nullptr && m.nin > 0 && m.ndof > 0) {
    std::vector<double> x0(static_cast<std::size_t>(m.nx), 0.0), zdot(static_cast<std::size_t>(m.ndof), 0.0),
        u0(static_cast<std::size_t>(m.nin), 0.0);
    if (m.inverse_dynamics(0.0, x0.data(), zdot.data(), m.param_defaults, u0.data()) == 4)
      return bad(fmt::format("mbsc inverse: error: model {} is not affine in its inputs (Coulomb friction closed in its "
                             "rhs, or a forcing not affine in them): its inverse dynamics is not defined",
                             model_label));
  }
  if (!(opt.dt_out > 0.0) || !std::isfinite(opt.dt_out)) return bad("--dt-out: error: must be a positive number");
  if (!(opt.t_end > opt.t_start) || !std::isfinite(opt.t_end) || !std::isfinite(opt.t_start))
    return bad("--t-end: error: must be a number after the start time");

  // Parameters: the defaults, then --set.
  const auto param_names = runtime::ModelTable::names_of(m.param_names, m.np);
  std::map<std::string, double> params;
  std::vector<double> p(m.param_defaults, m.param_defaults + m.np);
  for (int k = 0; k < m.np; ++k) params[m.param_names[k]] = p[static_cast<std::size_t>(k)];
  for (const auto& [name, value] : opt.params) {
    const int k = runtime::ModelTable::find(m.param_names, m.np, name.c_str());
    if (k < 0) return bad(fmt::format("--set {}: error: model {} has no parameter '{}'{}", name, model_label, name, did_you_mean(name, param_names)));
    p[static_cast<std::size_t>(k)] = value;
    params[name] = value;
  }

  // Prescriptions.
  const auto coord_names = runtime::ModelTable::names_of(m.state_names, m.nq);
  if (static_cast<int>(opt.prescribe.size()) != m.ndof)
    return bad(fmt::format("--prescribe: error: model {} has {} degree(s) of freedom, so exactly {} coordinate(s) must be prescribed "
                           "({} given)",
                           model_label, m.ndof, m.ndof, opt.prescribe.size()));
  std::vector<runtime::Prescription> prescribed;
  for (const auto& [name, text] : opt.prescribe) {
    const int c = runtime::ModelTable::find(m.state_names, m.nq, name.c_str());
    if (c < 0) {
      const bool is_speed = runtime::ModelTable::find(m.state_names + m.nq, m.nu, name.c_str()) >= 0;
      return bad(fmt::format("--prescribe {}: error: model {} has no coordinate '{}'{}", name, model_label, name,
                             is_speed ? " (it is a speed: prescribe the coordinate it is the rate of)" : did_you_mean(name, coord_names)));
    }
    std::string error;
    auto motion = read_expression(name, text, params, error);
    if (!motion) return bad(error);
    auto shared = std::make_shared<MotionExpressions>(*motion);
    prescribed.push_back({c, [shared](double t, double& q, double& qd, double& qdd) {
                            q = value_at(shared->q, shared->t, t);
                            qd = value_at(shared->qd, shared->t, t);
                            qdd = value_at(shared->qdd, shared->t, t);
                          }});
  }

  // Unknown and fixed inputs.
  const auto input_names = runtime::ModelTable::names_of(m.input_names, m.nin);
  std::vector<int> unknowns;
  for (const auto& name : opt.unknowns) {
    const int k = runtime::ModelTable::find(m.input_names, m.nin, name.c_str());
    if (k < 0 || m.nin == 0)
      return bad(fmt::format("--unknowns {}: error: model {} has no input '{}'{}", name, model_label, name, did_you_mean(name, input_names)));
    unknowns.push_back(k);
  }
  if (opt.unknowns.empty())
    for (int k = 0; k < m.nin; ++k) unknowns.push_back(k);
  if (unknowns.empty()) return bad(fmt::format("mbsc inverse: error: model {} has no inputs to solve for", model_label));
  std::vector<double> fixed(static_cast<std::size_t>(std::max(m.nin, 1)), 0.0);
  for (const auto& [name, value] : opt.fixed_inputs) {
    const int k = runtime::ModelTable::find(m.input_names, m.nin, name.c_str());
    if (k < 0 || m.nin == 0)
      return bad(fmt::format("--input {}: error: model {} has no input '{}'{}", name, model_label, name, did_you_mean(name, input_names)));
    fixed[static_cast<std::size_t>(k)] = value;
  }

  // The guess that picks the branch.
  std::vector<double> x(static_cast<std::size_t>(m.nx), 0.0);
  const auto state_names = runtime::ModelTable::names_of(m.state_names, m.nx);
  for (const auto& [name, value] : opt.guess) {
    const int k = runtime::ModelTable::find(m.state_names, m.nx, name.c_str());
    if (k < 0) return bad(fmt::format("--init {}: error: model {} has no coordinate or speed '{}'{}", name, model_label, name, did_you_mean(name, state_names)));
    x[static_cast<std::size_t>(k)] = value;
  }

  runtime::InverseDynamics inv(m, prescribed, unknowns, p, fixed);
  if (!inv.setup_error().empty()) return bad("mbsc inverse: error: " + inv.setup_error());

  // The table's columns.
  out.table.columns.push_back("t");
  for (int i = 0; i < m.nx; ++i) out.table.columns.push_back(m.state_names[i]);
  for (int i = 0; i < m.nin; ++i) out.table.columns.push_back(m.input_names[i]);
  const bool reactions = m.multipliers && m.reaction_forces != nullptr && m.nc > 0;
  if (reactions)
    for (int j = 0; j < m.nu; ++j) out.table.columns.push_back(std::string("reaction:") + m.state_names[m.nq + j]);

  const long steps = std::lround(std::floor((opt.t_end - opt.t_start) / opt.dt_out * (1 + 1e-12)));
  // Rows every dt_out, and one at t_end when the span is not a whole number of dt_out.
  const bool extra = opt.t_start + steps * opt.dt_out < opt.t_end - 1e-9 * opt.dt_out;
  for (long k = 0; k <= steps + (extra ? 1 : 0); ++k) {
    const double t = k > steps || (k == steps && opt.t_start + steps * opt.dt_out > opt.t_end)
                         ? opt.t_end
                         : opt.t_start + k * opt.dt_out;
    if (opt.seconds_left && opt.seconds_left() <= 0) {
      out.exit_code = 1;
      out.message = fmt::format("mbsc inverse: error: the time budget of the command ran out at t = {} (raise it with "
                                "--budget SECONDS)",
                                t);
      break;
    }
    runtime::InverseSample s;
    if (!inv.solve(t, x, s)) {
      out.exit_code = 2;
      out.message = fmt::format("mbsc inverse: error: at t = {}: {}", t, s.message);
      break;
    }
    std::vector<double> row = {t};
    row.insert(row.end(), s.x.begin(), s.x.end());
    for (int i = 0; i < m.nin; ++i) row.push_back(s.inputs[static_cast<std::size_t>(i)]);
    if (reactions) row.insert(row.end(), s.reactions.begin(), s.reactions.end());
    out.table.rows.push_back(std::move(row));
  }

  if (!opt.output_csv.empty()) {
    // All or nothing: a complete table replaces the destination; the rows computed before
    // a failure stay in a temporary beside it, named in the message.
    driver::StagedFile file;
    std::string error;
    if (!file.stage(opt.output_csv, inverse_csv(out.table), "-o", error) ||
        (out.exit_code == 0 && !file.commit(error))) {
      out.message = (out.message.empty() ? std::string() : out.message + "\n") + error;
      out.exit_code = out.exit_code == 0 ? 1 : out.exit_code;
      return out;
    }
    if (out.exit_code != 0)
      out.message += fmt::format("\nmbsc inverse: note: {} was left as it was; {} holds the {} row(s) computed before "
                                 "the failure",
                                 printable(opt.output_csv), printable(file.keep()), out.table.rows.size());
  }
  return out;
}

}  // namespace mbsc::run
