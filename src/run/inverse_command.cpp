// SPDX-License-Identifier: GPL-2.0-or-later
// mbsc inverse: prescribed expressions -> Prescription callbacks -> InverseDynamics along
// the output grid -> a table (and its CSV). The command line (main.cpp) parses the
// options and loads the model; this file does the rest.
#include "inverse_command.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <optional>
#include <vector>

#include "mbsc/diag/diagnostics.hpp"
#include "mbsc/diag/name_suggestions.hpp"
#include "mbsc/driver/staged_file.hpp"
#include "mbsc/runtime/inverse_dynamics.hpp"
#include "prescribed_motion.hpp"

namespace mbsc::run {

namespace {

/// The output times: every dt_out from t_start, and t_end when the span is not a whole
/// number of dt_out.
std::vector<double> output_times(const InverseCommandOptions& opt) {
  const long steps = std::lround(std::floor((opt.t_end - opt.t_start) / opt.dt_out * (1 + 1e-12)));
  const bool extra = opt.t_start + steps * opt.dt_out < opt.t_end - 1e-9 * opt.dt_out;
  std::vector<double> times;
  for (long k = 0; k <= steps + (extra ? 1 : 0); ++k)
    times.push_back(k > steps || (k == steps && opt.t_start + steps * opt.dt_out > opt.t_end) ? opt.t_end
                                                                                             : opt.t_start + k * opt.dt_out);
  return times;
}

/// A prescription evaluated at every output time before the solve (so that one undefined
/// there is a bad option, exit 1, not a failure half way): q, q', q'' per time.
struct SampledMotion {
  PrescribedMotion motion;
  std::vector<double> times;
  std::vector<std::array<double, 3>> values;
};

/// As `mbsc run`'s CSV (run/csv_table.hpp): the shortest text that reads back to the same
/// double, and 0 for -0.
std::string number_text(double v) { return fmt::format("{}", v == 0.0 ? 0.0 : v); }

/// The first friction joint that the solved sample holds at rest: slide rate v = 0 and
/// its rate v' = 0, v' by a central difference along the state's rates (the motion).
/// Rest is judged against the sample's speeds and rates (1e-9 and 1e-6 of them); a joint
/// that only reverses (v = 0, v' != 0) is sliding either side, and the rhs's law, with
/// sign(0) = 0, gives its force there. Empty when none is; a joint whose slide rate does
/// not evaluate there is an error too (rest cannot be ruled out), said so.
std::string held_at_rest(const std::vector<InverseCommandOptions::FrictionJoint>& joints, const runtime::InverseSample& s,
                         const std::vector<double>& p, int nq) {
  if (joints.empty()) return "";
  double speeds = 1.0, rates = 1.0;
  for (std::size_t i = static_cast<std::size_t>(nq); i < s.x.size(); ++i) {
    speeds = std::max(speeds, std::fabs(s.x[i]));
    rates = std::max(rates, std::fabs(s.xdot[i]));
  }
  double motion = 1.0;
  for (double r : s.xdot) motion = std::max(motion, std::fabs(r));
  const double eps = 1e-5 / motion;
  std::vector<double> ahead = s.x, behind = s.x;
  for (std::size_t i = 0; i < s.x.size(); ++i) {
    ahead[i] += eps * s.xdot[i];
    behind[i] -= eps * s.xdot[i];
  }
  for (const auto& j : joints) {
    const double v = j.slide_rate(s.t, s.x, s.inputs, p);
    const double a = (j.slide_rate(s.t + eps, ahead, s.inputs, p) - j.slide_rate(s.t - eps, behind, s.inputs, p)) / (2 * eps);
    if (!std::isfinite(v) || !std::isfinite(a))
      return fmt::format("the slide rate of joint '{}' does not evaluate to a number, so whether its Coulomb friction "
                         "sticks there (and the inputs are not determined) cannot be told",
                         j.name);
    if (std::fabs(v) <= 1e-9 * speeds && std::fabs(a) <= 1e-6 * rates)
      return fmt::format("the prescribed motion holds joint '{}' at rest (its slide rate and that rate's rate are 0): its "
                         "Coulomb friction may then be any force up to mu |N| (stiction), so the inputs are not "
                         "determined; prescribe a motion that slides it there, or start the table where it slides "
                         "(--t-start)",
                         j.name);
  }
  return "";
}

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
  // The solve below reads the inputs off rhs: affine in them, or made not affine by the
  // Coulomb friction the rhs closes (then solved by Newton steps). A model whose own
  // inverse_dynamics is not defined (status 4 without computing) for another reason has
  // a forcing not affine in its inputs: refused.
  if (m.inverse_dynamics != nullptr && m.nin > 0 && m.ndof > 0 && opt.friction_joints.empty()) {
    std::vector<double> x0(static_cast<std::size_t>(m.nx), 0.0), zdot(static_cast<std::size_t>(m.ndof), 0.0),
        u0(static_cast<std::size_t>(m.nin), 0.0);
    if (m.inverse_dynamics(0.0, x0.data(), zdot.data(), m.param_defaults, u0.data()) == 4)
      return bad(fmt::format("mbsc inverse: error: the forcing of model {} is not affine in its inputs: its inverse "
                             "dynamics is not defined (several inputs, or none, may give the same motion)",
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
  const std::vector<double> times = output_times(opt);
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
    auto motion = read_prescribed_motion(name, text, params, error);
    if (!motion) return bad(error);
    auto sampled = std::make_shared<SampledMotion>(SampledMotion{std::move(*motion), times, {}});
    sampled->values.resize(times.size());
    for (std::size_t k = 0; k < times.size(); ++k)
      if (!motion_at(sampled->motion, times[k], sampled->values[k], error))
        return bad(fmt::format("--prescribe {}: error: '{}': {}; a prescribed motion must be defined and twice "
                               "differentiable at every output time (--t-start to --t-end, every --dt-out)",
                               name, printable(text), error));
    prescribed.push_back({c, [sampled](double t, double& q, double& qd, double& qdd) {
                            // The sampled times first; another time (none in this command) is evaluated.
                            const auto& ts = sampled->times;
                            const auto at = std::lower_bound(ts.begin(), ts.end(), t);
                            std::array<double, 3> v = {NAN, NAN, NAN};
                            std::string why;
                            if (at != ts.end() && *at == t) v = sampled->values[static_cast<std::size_t>(at - ts.begin())];
                            else motion_at(sampled->motion, t, v, why);
                            q = v[0];
                            qd = v[1];
                            qdd = v[2];
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

  runtime::InverseOptions solver;
  solver.quaternion_indices = opt.quaternion_indices;
  runtime::InverseDynamics inv(m, prescribed, unknowns, p, fixed, solver);
  if (!inv.setup_error().empty()) return bad("mbsc inverse: error: " + inv.setup_error());

  // The table's columns.
  out.table.columns.push_back("t");
  for (int i = 0; i < m.nx; ++i) out.table.columns.push_back(m.state_names[i]);
  for (int i = 0; i < m.nin; ++i) out.table.columns.push_back(m.input_names[i]);
  const bool reactions = m.multipliers && m.reaction_forces != nullptr && m.nc > 0;
  if (reactions)
    for (int j = 0; j < m.nu; ++j) out.table.columns.push_back(std::string("reaction:") + m.state_names[m.nq + j]);

  for (const double t : times) {
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
    const std::string stuck = held_at_rest(opt.friction_joints, s, p, m.nq);
    if (!stuck.empty()) {
      out.exit_code = 2;
      out.message = fmt::format("mbsc inverse: error: at t = {}: {}", t, stuck);
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
