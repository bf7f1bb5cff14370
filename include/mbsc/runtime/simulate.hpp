// SPDX-License-Identifier: GPL-2.0-or-later WITH mbsc-runtime-exception
// (see LICENSE: this header may be included in applications under any terms)
#pragma once
/// The simulation loop of the runtime (docs/simulation.md): a generated model (through a
/// ModelTable), an integrator (a Stepper), inputs u(t) from a callback, and an observer
/// that receives the state at every output time.
///
///   const auto model = MBSC_MODEL_TABLE(mbsc_gen::four_bar);
///   mbsc::runtime::ModelDynamics dyn(model, p);               // p: kNp parameters
///   auto stepper = mbsc::runtime::make_stepper("dopri5", dyn.rhs(), model.nx, {1e-8, 1e-10});
///   mbsc::runtime::SimulationOptions opt;                   // t0, t_end, dt_out, projection...
///   auto result = mbsc::runtime::simulate(dyn, *stepper, opt, x0,
///                                         [](double t, const std::vector<double>& x) { ... });
///   if (!result.ok()) std::cerr << result.message << "\n";
///
/// or in one call: simulate(model, "dopri5", stepper_options, opt, x0, inputs, p, observer).
///
/// Each accepted step: (1) every output time it passed is sampled from the stepper's
/// dense output and handed to the observer; (2) the state is checked (finite, named
/// otherwise), its constraint residuals and energy recorded; (3) when the residuals
/// exceed a threshold the state is projected back onto the constraints (projection.hpp)
/// and the stepper restarted from there; (4) for a model with alternative independent
/// sets, the PartitionSelector checks the active one and a switch restarts the stepper.
/// A failure ends the run with every sample before it delivered, a status, a message
/// naming t and the quantity, and the last good state.
#include <algorithm>
#include <array>
#include <cmath>
#include <ctime>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "mbsc/runtime/make_stepper.hpp"
#include "mbsc/runtime/model_table.hpp"
#include "mbsc/runtime/branch_continuation.hpp"
#include "mbsc/runtime/partition_selector.hpp"
#include "mbsc/runtime/projection.hpp"
#include "mbsc/runtime/singular_crossing.hpp"
#include "mbsc/runtime/stepper.hpp"

namespace mbsc::runtime {

/// Inputs u(t): fills kNin values, returns 0 (non-zero: the run stops, "input failed").
using InputFunction = std::function<int(double t, double* u)>;
/// Called with (t, x) at every output time.
using Observer = std::function<void(double t, const std::vector<double>& x)>;

/// The status a ModelDynamics rhs returns when the input callback failed (beyond the
/// generated functions' 1..4).
constexpr int kInputFailed = 10;

/// A model's right-hand side with its parameters, its inputs and (for a model with
/// `alternative` statements) the partition selector: what a Stepper integrates. It must
/// outlive the stepper made from rhs().
class ModelDynamics {
 public:
  ModelDynamics(const ModelTable& m, std::vector<double> p, InputFunction inputs = {}, SelectorSettings selector = {})
      : m_(m), p_(std::move(p)), inputs_(std::move(inputs)), u_(static_cast<std::size_t>(std::max(1, m.nin)), 0.0),
        selector_(PartitionFunctions{m.npartitions, m.rhs_partition, m.conditioning_partition}, selector) {
    p_.resize(static_cast<std::size_t>(m.np), 0.0);
  }

  /// xdot = f(t, x) with u = inputs(t), through the active partition where there are several.
  int evaluate(double t, const double* x, double* xdot) {
    ++evals_;
    if (const int s = inputs_at(t); s != 0) return s;
    if (continuation_) {
      continuation_->set_partition(m_.npartitions > 1 ? selector_.active() : 0);
      return continuation_->rhs(t, x, xdot);
    }
    if (m_.npartitions > 1 && m_.rhs_partition) return selector_.rhs(t, x, u_.data(), p_.data(), xdot);
    return m_.rhs(t, x, u_.data(), p_.data(), xdot);
  }
  /// Evaluates the rhs through a BranchContinuation (branch_continuation.hpp): robust where
  /// the constraints lose rank for an instant (a parallelogram chain's flat poses), at
  /// the price of the conditioning report in every evaluation. Off by default.
  void continue_through_rank_loss(BranchSettings s = {}) {
    continuation_ = std::make_unique<BranchContinuation>(m_, u_.data(), p_.data(), s);
  }
  const BranchContinuation* continuation() const { return continuation_.get(); }
  BranchContinuation* continuation() { return continuation_.get(); }
  /// evaluate() as a Stepper's Rhs (holds a pointer to this object).
  Rhs rhs() {
    return [this](double t, const double* x, double* xdot) { return evaluate(t, x, xdot); };
  }
  /// u at t into inputs(); 0 or kInputFailed.
  int inputs_at(double t) {
    if (m_.nin > 0 && inputs_ && inputs_(t, u_.data()) != 0) return kInputFailed;
    return 0;
  }

  const ModelTable& model() const { return m_; }
  const double* params() const { return p_.data(); }
  const double* inputs() const { return u_.data(); }
  PartitionSelector& selector() { return selector_; }
  bool reselects() const { return m_.npartitions > 1 && m_.rhs_partition && m_.conditioning_partition; }
  long evaluations() const { return evals_; }

 private:
  const ModelTable& m_;
  std::vector<double> p_;
  InputFunction inputs_;
  std::vector<double> u_;
  PartitionSelector selector_;
  std::unique_ptr<BranchContinuation> continuation_;
  long evals_ = 0;
};

struct SimulationOptions {
  double t0 = 0.0;
  double t_end = 1.0;
  double dt_out = 0.01;  // output every dt_out from t0 (and at t_end); <= 0: at t0 and t_end only
  enum class Projection { Auto, On, Off };
  /// Auto: on for a full-state model with constraints (off for --state minimal, where the
  /// state has no constraints to drift from).
  Projection projection = Projection::Auto;
  /// Project only when the largest |g| or |A v + b| exceeds this; then restart the stepper.
  double projection_threshold = 1e-10;
  ProjectionOptions projection_options;
  /// Complement form, when true: the projection keeps the active independent speeds and
  /// the coordinates whose rates they are, and corrects only the dependent ones. Better
  /// where the independent motion is integrated on its own (a pendulum's angle: phase
  /// error as without projection), worse where every coordinate feeds the dynamics (a
  /// four-bar); measured in docs/simulation.md. False (the default), or for the
  /// multipliers form: the shortest correction in all coordinates and speeds.
  bool projection_keeps_independent = false;
  /// Names of further coordinates and speeds (kStateNames) the projection keeps. An
  /// unknown name is a BadSetup result.
  std::vector<std::string> projection_hold;
  /// Re-select the independent set between steps (models with kNpartitions > 1).
  bool reselect = true;
  /// Record the total energy's drift (when the model defines energy).
  bool track_energy = true;
  /// Unit quaternions in the state (the indices of e0..e3 of each rigid3d body with a
  /// quaternion attitude: the generated header's kQuaternionIndices, see
  /// unit_quaternions_of; `mbsc run` fills them): their norm is an invariant of the
  /// kinematics only, so the integrator's error moves it; after an accepted step a
  /// quaternion whose |e| is off 1 by more than projection_threshold is divided by |e|
  /// (the nearest unit quaternion) and the stepper restarts. Leave it empty to let them
  /// drift (`mbsc run --projection off` does).
  std::vector<std::array<int, 4>> unit_quaternions;
  /// Asked after every step with its time: true ends the run there (status Stopped), e.g.
  /// when a time budget is spent (`mbsc run --budget`). Empty: never.
  std::function<bool(double t)> stop_requested;
  /// With the dynamics' BranchContinuation on: cross each pose where the constraints lose
  /// rank by extrapolation (singular_crossing.hpp; set its rtol and atol to the
  /// stepper's). nodes = 0 turns it off (the continuation's evaluations alone).
  CrossingSettings crossing;
};

/// The unit quaternions of a generated model, from its kQuaternionIndices (four state
/// indices per body, e0 first) and kNquaternions:
///   options.unit_quaternions = unit_quaternions_of(m::kQuaternionIndices, m::kNquaternions);
inline std::vector<std::array<int, 4>> unit_quaternions_of(const int* indices, int count) {
  std::vector<std::array<int, 4>> out(static_cast<std::size_t>(count > 0 ? count : 0));
  for (std::size_t b = 0; b < out.size(); ++b)
    for (std::size_t k = 0; k < 4; ++k) out[b][k] = indices[4 * b + k];
  return out;
}

struct PartitionSwitch {
  double t;
  int to;            // partition index
  std::string name;  // kPartitionNames[to]: the independent speeds of the new partition
};

struct SimulationResult {
  enum class Status { Ok, BadSetup, RhsFailed, NonFiniteState, StepTooSmall, TooManySteps, ProjectionFailed, SolverFailed, Stopped };
  Status status = Status::Ok;
  std::string message;    // empty when Ok; else what happened, with t and the quantity
  double t = 0.0;         // where the run ended (t_end, or the last good state's time)
  std::vector<double> x;  // the state there
  StepperStats stats;     // of the stepper (steps, accepted, rejected, rhs evaluations)
  long rhs_evals = 0;     // rhs evaluations in this run (ModelDynamics::evaluate calls)
  double cpu_seconds = 0.0;
  long samples = 0;       // observer calls
  // Constraint residuals at the end of every accepted step, before any projection:
  double max_position_residual = 0.0;
  double max_velocity_residual = 0.0;
  long projections = 0;
  long normalizations = 0;  // quaternions brought back to |e| = 1 (unit_quaternions)
  long crossings = 0;       // poses of rank loss crossed by extrapolation (SimulationOptions::crossing)
  double crossing_error = 0.0;  // the largest error estimate of those, in units of the tolerances
  long projected_evaluations = 0;  // BranchContinuation: rhs evaluations at a projected state
  long bridged_evaluations = 0;    // and bridged ones (branch_continuation.hpp)
  // Energy (kinetic + potential, the generated energy()'s entry 2): defined unless the
  // model's energy() reports status 4.
  bool energy_defined = false;
  double energy_initial = 0.0;
  double energy_drift = 0.0;           // max |E(t) - E(t0)| over accepted steps
  double energy_relative_drift = 0.0;  // energy_drift / max(|E(t0)|, |T(t0)|, |V(t0)|)
  std::vector<PartitionSwitch> switches;
  /// What the run went on with but the caller should know: a starting state off the
  /// position constraints (the integration keeps the offset; runtime/assemble.hpp
  /// completes a consistent state).
  std::vector<std::string> warnings;
  bool ok() const { return status == Status::Ok; }
};

namespace detail {

inline SimulationResult::Status from_stepper(Stepper::Status s) {
  switch (s) {
    case Stepper::Status::Ok: return SimulationResult::Status::Ok;
    case Stepper::Status::RhsFailed: return SimulationResult::Status::RhsFailed;
    case Stepper::Status::StepTooSmall: return SimulationResult::Status::StepTooSmall;
    case Stepper::Status::TooManySteps: return SimulationResult::Status::TooManySteps;
    default: return SimulationResult::Status::SolverFailed;
  }
}

/// The first non-finite entry of x, or -1.
inline int first_non_finite(const std::vector<double>& x) {
  for (std::size_t i = 0; i < x.size(); ++i)
    if (!std::isfinite(x[i])) return static_cast<int>(i);
  return -1;
}

/// For each speed j, the coordinate i whose rate is that speed alone (q0_i' = q1_j, as
/// for an angle and its angular speed), found from the rhs at x by differences; -1 where
/// there is none (quasi-speeds, a quaternion's rates).
inline std::vector<int> coordinate_of_speed(ModelDynamics& dyn, double t, const std::vector<double>& x) {
  const ModelTable& m = dyn.model();
  const std::size_t nq = static_cast<std::size_t>(m.nq), nu = static_cast<std::size_t>(m.nu);
  std::vector<int> pair(nu, -1);
  std::vector<double> f0(x.size()), f1(x.size()), xp = x;
  if (dyn.evaluate(t, x.data(), f0.data()) != 0) return pair;
  // d(rate_i)/d(u_j), column by column.
  std::vector<double> D(nq * nu, 0.0);
  for (std::size_t j = 0; j < nu; ++j) {
    const double h = 1e-6 * std::max(1.0, std::fabs(x[nq + j]));
    xp[nq + j] = x[nq + j] + h;
    const int s = dyn.evaluate(t, xp.data(), f1.data());
    xp[nq + j] = x[nq + j];
    if (s != 0) return std::vector<int>(nu, -1);
    for (std::size_t i = 0; i < nq; ++i) D[i * nu + j] = (f1[i] - f0[i]) / h;
  }
  for (std::size_t i = 0; i < nq; ++i) {
    int only = -1;
    bool clean = true;
    for (std::size_t j = 0; j < nu; ++j) {
      const double d = D[i * nu + j];
      if (std::fabs(d - 1.0) < 1e-6 && only < 0) only = static_cast<int>(j);
      else if (std::fabs(d) > 1e-6) clean = false;
    }
    if (clean && only >= 0 && pair[static_cast<std::size_t>(only)] < 0) pair[static_cast<std::size_t>(only)] = static_cast<int>(i);
  }
  return pair;
}

/// The state indices of the speeds a comma-separated list names (kPartitionNames[k]).
inline std::vector<int> speeds_named(const ModelTable& m, const std::string& list) {
  std::vector<int> out;
  std::size_t start = 0;
  while (start <= list.size()) {
    std::size_t end = list.find(',', start);
    if (end == std::string::npos) end = list.size();
    std::string name = list.substr(start, end - start);
    while (!name.empty() && name.front() == ' ') name.erase(name.begin());
    while (!name.empty() && name.back() == ' ') name.pop_back();
    const int i = ModelTable::find(m.state_names, m.nx, name.c_str());
    if (i >= m.nq) out.push_back(i - m.nq);
    start = end + 1;
  }
  return out;
}

}  // namespace detail

/// Runs the loop described at the top of this file. x0 is the state at o.t0 (kNx entries,
/// consistent with the constraints: see assemble.hpp).
inline SimulationResult simulate(ModelDynamics& dyn, Stepper& stepper, const SimulationOptions& o, std::vector<double> x0,
                                 const Observer& observe = {}) {
  const ModelTable& m = dyn.model();
  SimulationResult res;
  const std::clock_t cpu0 = std::clock();
  const long evals0 = dyn.evaluations();
  res.t = o.t0;
  res.x = x0;
  std::unique_ptr<SingularCrossing> crossing;  // made once the start is checked (below)
  auto finish = [&](SimulationResult::Status s, const std::string& msg) {
    res.status = s;
    res.message = msg;
    if (crossing) {
      res.crossings = crossing->crossings();
      res.crossing_error = crossing->error_estimate();
    }
    if (const BranchContinuation* bc = dyn.continuation()) {
      res.projected_evaluations = bc->projected();
      res.bridged_evaluations = bc->bridged();
    }
    res.stats = stepper.stats();
    res.rhs_evals = dyn.evaluations() - evals0;
    res.cpu_seconds = static_cast<double>(std::clock() - cpu0) / CLOCKS_PER_SEC;
    return res;
  };
  if (static_cast<int>(x0.size()) != m.nx)
    return finish(SimulationResult::Status::BadSetup,
                  "the initial state has " + std::to_string(x0.size()) + " entries, the model " + std::to_string(m.nx));
  if (!(o.t_end >= o.t0)) return finish(SimulationResult::Status::BadSetup, "t_end is before t0");
  for (const auto& q : o.unit_quaternions)
    for (int i : q)
      if (i < 0 || i >= m.nx) return finish(SimulationResult::Status::BadSetup, "unit_quaternions: an index outside the state");
  if (const int bad = detail::first_non_finite(x0); bad >= 0)
    return finish(SimulationResult::Status::NonFiniteState,
                  std::string("the initial value of '") + m.state_names[bad] + "' is not finite");

  const bool constrained = m.nposc > 0 || m.nc > 0;
  if (m.full_state_layout() && m.nposc > 0) {
    // A start off the position constraints: the run keeps the offset (or the projection
    // moves the start), so say which row and by how much.
    std::vector<double> g(static_cast<std::size_t>(m.nposc));
    if (m.position_constraints(o.t0, x0.data(), dyn.inputs(), dyn.params(), g.data()) == 0) {
      std::size_t worst = 0;
      for (std::size_t i = 1; i < g.size(); ++i)
        if (std::abs(g[i]) > std::abs(g[worst])) worst = i;
      double scale = 1.0;
      for (int i = 0; i < m.nq; ++i) scale = std::max(scale, std::abs(x0[static_cast<std::size_t>(i)]));
      if (std::abs(g[worst]) > 1e-6 * scale)
        res.warnings.push_back(std::string("the initial state is off position constraint '") +
                               m.position_constraint_names[worst] + "' by " + std::to_string(g[worst]) +
                               " (assemble a consistent state first: runtime/assemble.hpp)");
    }
  }
  const bool project_on = constrained && m.full_state_layout() &&
                          (o.projection == SimulationOptions::Projection::On ||
                           o.projection == SimulationOptions::Projection::Auto);
  const bool reselect = o.reselect && dyn.reselects();
  // What the projection keeps: the names given, and (complement form) the active
  // independent speeds with their coordinates.
  ProjectionOptions given_hold = o.projection_options;
  given_hold.hold_q.resize(static_cast<std::size_t>(m.nq), false);
  given_hold.hold_u.resize(static_cast<std::size_t>(m.nu), false);
  for (const std::string& name : o.projection_hold) {
    const int i = ModelTable::find(m.state_names, m.nx, name.c_str());
    if (i < 0)
      return finish(SimulationResult::Status::BadSetup,
                    "projection_hold: the model has no coordinate or speed '" + name + "'");
    if (i < m.nq)
      given_hold.hold_q[static_cast<std::size_t>(i)] = true;
    else
      given_hold.hold_u[static_cast<std::size_t>(i - m.nq)] = true;
  }
  const bool keep_independent = project_on && o.projection_keeps_independent && !m.multipliers;
  std::vector<int> coordinate_of;  // per speed; filled at the start when needed
  auto projection_options = [&]() {
    ProjectionOptions po = given_hold;
    if (!keep_independent) return po;
    const std::string names = reselect ? std::string(m.partition_names[dyn.selector().active()]) : std::string();
    std::vector<int> speeds;
    if (reselect)
      speeds = detail::speeds_named(m, names);
    else
      for (int k = 0; k < m.ndof; ++k) {
        const int i = ModelTable::find(m.state_names, m.nx, m.dof_names[k]);
        if (i >= m.nq) speeds.push_back(i - m.nq);
      }
    for (int j : speeds) {
      po.hold_u[static_cast<std::size_t>(j)] = true;
      if (!coordinate_of.empty() && coordinate_of[static_cast<std::size_t>(j)] >= 0)
        po.hold_q[static_cast<std::size_t>(coordinate_of[static_cast<std::size_t>(j)])] = true;
    }
    return po;
  };
  const double* p = dyn.params();

  // Partition: choose the best one for the start.
  auto check_partition = [&](double t, const std::vector<double>& x) -> bool {
    if (!reselect) return false;
    const int before = dyn.selector().active();
    if (dyn.inputs_at(t) != 0) return false;
    dyn.selector().update(t, x.data(), dyn.inputs(), p);
    if (dyn.selector().active() == before) return false;
    const int to = dyn.selector().active();
    res.switches.push_back({t, to, m.partition_names[to]});
    return true;
  };
  // Energy.
  double energy_scale = 1.0;
  auto track_energy = [&](double t, const std::vector<double>& x, bool first) {
    if (!o.track_energy) return;
    if (!first && !res.energy_defined) return;
    double e[3];
    if (dyn.inputs_at(t) != 0) return;
    const int s = m.energy(t, x.data(), dyn.inputs(), p, e);
    if (first) {
      res.energy_defined = s == 0 && std::isfinite(e[2]);
      res.energy_initial = e[2];
      energy_scale = std::max({std::fabs(e[0]), std::fabs(e[1]), std::fabs(e[2])});
      if (!(energy_scale > 0.0)) energy_scale = 1.0;
      return;
    }
    if (s == 0) res.energy_drift = std::max(res.energy_drift, std::fabs(e[2] - res.energy_initial));
    res.energy_relative_drift = res.energy_drift / energy_scale;
  };

  std::vector<double> x = x0;
  if (dyn.continuation() != nullptr && o.crossing.nodes > 0 && m.full_state_layout()) {
    // (It projects, which needs the full state.) Its error estimate reads the independent speeds and the coordinates they are rates of.
    std::vector<int> watched;
    const std::vector<int> pair = detail::coordinate_of_speed(dyn, o.t0, x);
    for (int k = 0; k < m.ndof; ++k) {
      const int i = ModelTable::find(m.state_names, m.nx, m.dof_names[k]);
      if (i < m.nq) continue;
      watched.push_back(i);
      if (pair[static_cast<std::size_t>(i - m.nq)] >= 0) watched.push_back(pair[static_cast<std::size_t>(i - m.nq)]);
    }
    crossing = std::make_unique<SingularCrossing>(*dyn.continuation(), dyn.rhs(), o.crossing, watched);
  }
  check_partition(o.t0, x);
  if (keep_independent) coordinate_of = detail::coordinate_of_speed(dyn, o.t0, x);
  track_energy(o.t0, x, true);
  if (constrained) {
    double gp = 0, gv = 0;
    if (dyn.inputs_at(o.t0) == 0 && constraint_residuals(m, o.t0, x.data(), dyn.inputs(), p, gp, gv)) {
      res.max_position_residual = gp;
      res.max_velocity_residual = gv;
    }
  }
  Stepper::Status st = stepper.reset(o.t0, x);
  if (st != Stepper::Status::Ok) return finish(detail::from_stepper(st), stepper.message());

  // Output times t0 + k dt_out (computed from k, so they do not drift), then t_end.
  long k_out = 0;
  const double span = o.t_end - o.t0;
  auto next_output = [&]() -> double {
    if (o.dt_out <= 0.0) return k_out == 0 ? o.t0 : o.t_end;
    const double tk = o.t0 + static_cast<double>(k_out) * o.dt_out;
    return tk >= o.t_end - 1e-12 * std::max(1.0, std::fabs(o.t_end)) ? o.t_end : tk;
  };
  auto emit = [&](double t, const std::vector<double>& xs) {
    if (observe) observe(t, xs);
    ++res.samples;
  };
  emit(o.t0, x);
  ++k_out;
  if (span == 0.0) {
    res.t = o.t0;
    res.x = x;
    return finish(SimulationResult::Status::Ok, "");
  }

  std::vector<double> sample;
  // Every output time before t, sampled from `interpolate`; returns the first one not before t.
  auto sample_before = [&](double t, const auto& interpolate) {
    double tk = next_output();
    for (; tk < t; tk = next_output()) {
      interpolate(tk, sample);
      emit(tk, sample);
      ++k_out;
    }
    return tk;
  };
  // The run is at (t, xs): the result so far, a sample when the output time tk is t (the
  // state itself, projected), the energy recorded. True at t_end.
  auto arrive = [&](double t, const std::vector<double>& xs, double tk) {
    res.t = t;
    res.x = xs;
    bool end = false;
    if (tk == t) {
      emit(t, xs);
      ++k_out;
      end = t >= o.t_end;
    }
    track_energy(t, xs, false);
    return end;
  };
  bool done = false;
  while (!done) {
    st = stepper.step(crossing ? crossing->step_stop(stepper.t(), o.t_end) : o.t_end);
    if (st != Stepper::Status::Ok) return finish(detail::from_stepper(st), stepper.message());
    double t = stepper.t();
    // (1) the samples inside this step, from the dense output.
    double tk = sample_before(t, [&](double s, std::vector<double>& out) { stepper.interpolate(s, out); });
    // (2) the new state.
    x = stepper.x();
    if (const int bad = detail::first_non_finite(x); bad >= 0)
      return finish(SimulationResult::Status::NonFiniteState,
                    std::string("'") + m.state_names[bad] + "' is not finite at t = " + format_number(t));
    if (o.stop_requested && o.stop_requested(t)) {
      res.t = t;
      res.x = x;
      return finish(SimulationResult::Status::Stopped, "stopped at t = " + format_number(t));
    }
    bool restart = false;
    if (constrained && dyn.inputs_at(t) == 0) {
      double gp = 0, gv = 0;
      if (constraint_residuals(m, t, x.data(), dyn.inputs(), p, gp, gv)) {
        res.max_position_residual = std::max(res.max_position_residual, gp);
        res.max_velocity_residual = std::max(res.max_velocity_residual, gv);
        // (3) projection.
        if (project_on && (gp > o.projection_threshold || gv > o.projection_threshold)) {
          const std::vector<double> unprojected = x;
          ProjectionReport pr = project(m, t, x, dyn.inputs(), p, projection_options());
          if (keep_independent && (!pr.ok() || pr.position_after > o.projection_threshold ||
                                   pr.velocity_after > o.projection_threshold)) {
            // The kept variables leave the rest unable to close the constraints (near a
            // singular dependent block): the shortest correction in all of them instead.
            x = unprojected;
            pr = project(m, t, x, dyn.inputs(), p, given_hold);
          }
          if (pr.status == ProjectionReport::Status::EvaluationFailed)
            return finish(SimulationResult::Status::ProjectionFailed, pr.message);
          ++res.projections;
          restart = true;
        }
      }
    }
    // (3b) unit quaternions.
    for (const auto& q : o.unit_quaternions) {
      double n2 = 0.0;
      for (int i : q) n2 += x[static_cast<std::size_t>(i)] * x[static_cast<std::size_t>(i)];
      const double n = std::sqrt(n2);
      if (!(n > 0.0) || std::fabs(n - 1.0) <= o.projection_threshold) continue;
      for (int i : q) x[static_cast<std::size_t>(i)] /= n;
      ++res.normalizations;
      restart = true;
    }
    done = arrive(t, x, tk);
    if (done) break;
    // (3c) across a pose of rank loss ahead, by extrapolation: the samples on the way
    // from the polynomial, the run on from the far side.
    if (crossing && crossing->accepted(t, x)) {
      std::vector<double> x_plus;
      if (crossing->cross(o.t_end, x_plus)) {
        t = crossing->t_plus();
        tk = sample_before(t, [&](double s, std::vector<double>& out) { crossing->interpolate(s, out); });
        x = x_plus;
        done = arrive(t, x, tk);
        if (done) break;
        restart = true;
      }
    }
    // (4) the independent set.
    if (check_partition(t, x)) restart = true;
    if (restart) {
      st = stepper.reset(t, x);
      if (st != Stepper::Status::Ok) return finish(detail::from_stepper(st), stepper.message());
    }
  }
  return finish(SimulationResult::Status::Ok, "");
}

/// The same in one call: the stepper by name (make_stepper), the inputs and parameters.
/// An unknown integrator name is a BadSetup result listing the known ones.
inline SimulationResult simulate(const ModelTable& m, const std::string& integrator, const StepperOptions& so,
                                 const SimulationOptions& o, std::vector<double> x0, const InputFunction& inputs,
                                 const double* p, const Observer& observe = {}) {
  ModelDynamics dyn(m, std::vector<double>(p, p + m.np), inputs);
  auto stepper = make_stepper(integrator, dyn.rhs(), m.nx, so);
  if (!stepper) {
    SimulationResult res;
    res.status = SimulationResult::Status::BadSetup;
    res.message = "unknown integrator '" + integrator + "' (known:";
    for (const auto& n : stepper_names()) res.message += " " + n;
    res.message += ")";
    return res;
  }
  return simulate(dyn, *stepper, o, std::move(x0), observe);
}

}  // namespace mbsc::runtime
