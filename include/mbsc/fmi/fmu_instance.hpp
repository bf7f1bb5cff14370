// SPDX-License-Identifier: GPL-2.0-or-later WITH mbsc-runtime-exception
// (see LICENSE: this header may be included in applications under any terms)
#pragma once
/// One instance of an FMU exported by `mbsc generate --fmi` (docs/fmi.md): the state, the
/// inputs, the parameters and the time of a generated model, and what the FMI calls do
/// with them, written once for FMI 2.0 and 3.0 (fmi2_exports.hpp and fmi3_exports.hpp
/// are thin translations of the standards' C calls into these methods).
///
/// Value references (the same in modelDescription.xml, FmuLayout below): the states x
/// first (kStateNames order), then their derivatives, the inputs, the parameters, the
/// outputs, and last the time (FMI 3.0's independent variable).
///
/// Initialization assembles the state as `mbsc run` does: the entries the model's
/// `initial` statements give, and those the importer set before leaving initialization
/// mode, are kept; the other coordinates and speeds are solved from the constraints
/// (runtime/assemble.hpp). Model exchange: after a completed integrator step whose
/// constraint residuals exceed the tolerance the FMU asks for a step event, in which it
/// projects the state back onto the constraints (runtime/projection.hpp).
/// Co-simulation: each doStep integrates with the runtime's simulation loop
/// (runtime/simulate.hpp: an embedded Runge-Kutta method, projection, re-selection of the
/// independent speeds), inputs held constant over the step.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include "mbsc/runtime/assemble.hpp"
#include "mbsc/runtime/model_table.hpp"
#include "mbsc/runtime/projection.hpp"
#include "mbsc/runtime/simulate.hpp"

namespace mbsc::fmi {

/// The value references of an exported model's variables.
struct FmuLayout {
  int nx, nin, np, ny;
  unsigned state(int i) const { return static_cast<unsigned>(i); }
  unsigned derivative(int i) const { return static_cast<unsigned>(nx + i); }
  unsigned input(int i) const { return static_cast<unsigned>(2 * nx + i); }
  unsigned param(int i) const { return static_cast<unsigned>(2 * nx + nin + i); }
  unsigned output(int i) const { return static_cast<unsigned>(2 * nx + nin + np + i); }
  unsigned time() const { return static_cast<unsigned>(2 * nx + nin + np + ny); }
  unsigned count() const { return time() + 1; }
};

/// What the generated glue (NAME_fmu.cpp) hands to the instance.
struct FmuModel {
  runtime::ModelTable table;
  const double* start;            // nx: the start values of modelDescription.xml
  const unsigned char* given;     // nx: 1 where the model's `initial` fixes the entry
  const int* quaternion_indices;  // 4 per unit quaternion of the state (kQuaternionIndices)
  int nquaternions;
  const char* token;              // FMI 2.0 guid / FMI 3.0 instantiationToken
  FmuLayout layout() const { return {table.nx, table.nin, table.np, table.ny}; }
};

/// The statuses the two standards share (fmi2Status and fmi3Status number them alike).
enum Status { kOK = 0, kWarning = 1, kDiscard = 2, kError = 3, kFatal = 4 };

class FmuInstance {
 public:
  enum class Kind { ModelExchange, CoSimulation };
  enum class Mode { Instantiated, Initialization, Event, Continuous, Step, Terminated, Failed };
  /// Messages to the importer: (status, category, text).
  using Log = std::function<void(Status, const char*, const std::string&)>;

  FmuInstance(const FmuModel& m, Kind kind, Log log) : m_(m), kind_(kind), log_(std::move(log)) { reset(); }

  const FmuModel& model() const { return m_; }
  Kind kind() const { return kind_; }
  Mode mode() const { return mode_; }
  void set_logging(bool on) { logging_ = on; }

  /// Back to the state right after instantiation.
  void reset() {
    const auto& T = m_.table;
    x_.assign(m_.start, m_.start + T.nx);
    u_.assign(static_cast<std::size_t>(std::max(1, T.nin)), 0.0);
    p_.assign(T.param_defaults, T.param_defaults + T.np);
    set_by_user_.assign(static_cast<std::size_t>(T.nx), false);
    t_ = 0.0;
    rtol_ = 1e-6;
    project_next_ = false;
    dirty_ = true;
    mode_ = Mode::Instantiated;
  }

  void setup(bool tolerance_defined, double tolerance, double start_time) {
    if (tolerance_defined && tolerance > 0 && std::isfinite(tolerance)) rtol_ = tolerance;
    t_ = start_time;
    dirty_ = true;
  }
  Status enter_initialization() {
    if (mode_ != Mode::Instantiated) return refuse("enter initialization mode", "after instantiation or reset");
    mode_ = Mode::Initialization;
    return kOK;
  }
  /// Assembles the state (see the file's comment), checks the rhs there, then enters
  /// event mode (model exchange) or step mode (co-simulation).
  Status exit_initialization() {
    if (mode_ != Mode::Initialization) return refuse("exit initialization mode", "in initialization mode");
    const auto& T = m_.table;
    if (T.full_state_layout() && (T.nposc > 0 || T.nc > 0)) {
      runtime::AssemblyModel am{T.nq,
                                T.nu,
                                T.nposc,
                                T.nc,
                                T.nposc > 0 ? T.position_constraints : nullptr,
                                T.nposc > 0 ? T.position_jacobian : nullptr,
                                T.velocity_constraints,
                                T.constraint_jacobian,
                                T.position_constraint_names,
                                T.constraint_names,
                                T.state_names,
                                m_.quaternion_indices,
                                m_.nquaternions};
      std::vector<bool> given_q(static_cast<std::size_t>(T.nq)), given_u(static_cast<std::size_t>(T.nu));
      for (int i = 0; i < T.nx; ++i) {
        const bool g = m_.given[i] != 0 || set_by_user_[static_cast<std::size_t>(i)];
        if (i < T.nq) given_q[static_cast<std::size_t>(i)] = g;
        else given_u[static_cast<std::size_t>(i - T.nq)] = g;
      }
      const runtime::AssemblyResult a = runtime::assemble(am, t_, x_, given_q, given_u, u_.data(), p_.data());
      if (!a.ok()) return fail("the initial state is inconsistent: " + a.message);
      if (a.near_singular) log(kWarning, "logWarning", "the initial state is " + a.message);
    }
    dirty_ = true;
    if (!evaluate()) return fail("at the start (t = " + number(t_) + "): " + failure_);
    mode_ = kind_ == Kind::ModelExchange ? Mode::Event : Mode::Step;
    return kOK;
  }
  Status terminate() {
    mode_ = Mode::Terminated;
    return kOK;
  }

  // ---- values ----
  Status get_real(const unsigned* vr, std::size_t n, double* values) {
    const FmuLayout L = m_.layout();
    for (std::size_t k = 0; k < n; ++k) {
      const unsigned r = vr[k];
      if (r < L.derivative(0)) values[k] = x_[r];
      else if (r < L.input(0) || (r >= L.output(0) && r < L.time())) {
        if (mode_ == Mode::Instantiated) return refuse("get a derivative or an output", "after entering initialization");
        if (!evaluate()) return fail("at t = " + number(t_) + ": " + failure_);
        values[k] = r < L.input(0) ? xdot_[r - L.derivative(0)] : y_[r - L.output(0)];
      } else if (r < L.param(0)) values[k] = u_[r - L.input(0)];
      else if (r < L.output(0)) values[k] = p_[r - L.param(0)];
      else if (r == L.time()) values[k] = t_;
      else return unknown(r);
    }
    return kOK;
  }
  Status set_real(const unsigned* vr, std::size_t n, const double* values) {
    const FmuLayout L = m_.layout();
    const bool before_start = mode_ == Mode::Instantiated || mode_ == Mode::Initialization;
    for (std::size_t k = 0; k < n; ++k) {
      const unsigned r = vr[k];
      const double v = values[k];
      if (!std::isfinite(v)) return fail("the value set for '" + name_of(r) + "' is not finite");
      if (r < L.derivative(0)) {
        if (!before_start) return refuse("set the state variable '" + name_of(r) + "'", "before initialization ends");
        x_[r] = v;
        set_by_user_[r] = true;
      } else if (r >= L.input(0) && r < L.param(0)) {
        u_[r - L.input(0)] = v;
      } else if (r >= L.param(0) && r < L.output(0)) {
        if (!before_start) return refuse("set the parameter '" + name_of(r) + "'", "before initialization ends (it is fixed)");
        p_[r - L.param(0)] = v;
      } else if (r < L.count()) {
        return refuse("set '" + name_of(r) + "'", "never: it is calculated");
      } else {
        return unknown(r);
      }
      dirty_ = true;
    }
    return kOK;
  }

  // ---- model exchange ----
  Status set_time(double t) {
    t_ = t;
    dirty_ = true;
    return kOK;
  }
  Status set_states(const double* x, std::size_t n) {
    if (n != x_.size()) return fail("expected " + std::to_string(x_.size()) + " states, got " + std::to_string(n));
    std::copy(x, x + n, x_.begin());
    dirty_ = true;
    return kOK;
  }
  Status get_states(double* x, std::size_t n) const {
    if (n != x_.size()) return kError;
    std::copy(x_.begin(), x_.end(), x);
    return kOK;
  }
  Status get_derivatives(double* xdot, std::size_t n) {
    if (n != x_.size()) return fail("expected " + std::to_string(x_.size()) + " derivatives, got " + std::to_string(n));
    if (!evaluate()) return fail("at t = " + number(t_) + ": " + failure_);
    std::copy(xdot_.begin(), xdot_.end(), xdot);
    return kOK;
  }
  Status get_nominals(double* nominal, std::size_t n) const {
    std::fill(nominal, nominal + n, 1.0);
    return kOK;
  }
  Status enter_event_mode() {
    mode_ = Mode::Event;
    return kOK;
  }
  Status enter_continuous_time_mode() {
    mode_ = Mode::Continuous;
    return kOK;
  }
  /// A step event where the constraints drifted beyond the tolerance (full state only).
  Status completed_integrator_step(bool& enter_event_mode) {
    enter_event_mode = false;
    if (!projects()) return kOK;
    double position = 0, velocity = 0;
    if (!runtime::constraint_residuals(m_.table, t_, x_.data(), u_.data(), p_.data(), position, velocity))
      return fail("the constraint residuals are not finite at t = " + number(t_));
    const double scale = 1.0 + max_abs(x_);
    if (position > rtol_ * scale || velocity > rtol_ * scale) project_next_ = enter_event_mode = true;
    return kOK;
  }
  /// Event iteration: the projection asked for by completed_integrator_step.
  Status update_discrete_states(bool& values_changed) {
    values_changed = false;
    if (!project_next_) return kOK;
    project_next_ = false;
    const runtime::ProjectionReport r = runtime::project(m_.table, t_, x_, u_.data(), p_.data());
    if (!r.ok()) return fail("the projection onto the constraints failed at t = " + number(t_) + ": " + r.message);
    dirty_ = true;
    values_changed = true;
    return kOK;
  }

  // ---- co-simulation ----
  /// Integrates from t to t + h (t must be this instance's time).
  Status do_step(double t, double h) {
    if (mode_ != Mode::Step) return refuse("take a step", "in step mode (after initialization)");
    if (!(h > 0) || !std::isfinite(h)) return fail("the communication step " + number(h) + " is not positive");
    if (std::fabs(t - t_) > 1e-9 * std::max(1.0, std::fabs(t_)))
      return fail("doStep at t = " + number(t) + " but the FMU is at t = " + number(t_));
    const auto& T = m_.table;
    const std::vector<double> u = u_;
    runtime::ModelDynamics dyn(T, p_, [&u](double, double* out) {
      std::copy(u.begin(), u.end(), out);
      return 0;
    });
    runtime::StepperOptions so;
    so.rtol = rtol_;
    so.atol = rtol_ * 1e-3;
    auto stepper = runtime::make_stepper("dopri5", dyn.rhs(), T.nx, so);
    runtime::SimulationOptions o;
    o.t0 = t_;
    o.t_end = t_ + h;
    o.dt_out = 0.0;
    o.track_energy = false;
    o.unit_quaternions = runtime::unit_quaternions_of(m_.quaternion_indices, m_.nquaternions);
    const runtime::SimulationResult r = runtime::simulate(dyn, *stepper, o, x_);
    if (!r.ok()) return fail("the step from t = " + number(t_) + " failed: " + r.message);
    x_ = r.x;
    t_ = t_ + h;
    dirty_ = true;
    return kOK;
  }
  double time() const { return t_; }

  // ---- snapshots (get/set/serialize FMU state) ----
  struct Snapshot {
    std::vector<double> x, u, p;
    std::vector<bool> set_by_user;
    double t, rtol;
    Mode mode;
    bool project_next;
  };
  Snapshot snapshot() const { return {x_, u_, p_, set_by_user_, t_, rtol_, mode_, project_next_}; }
  void restore(const Snapshot& s) {
    x_ = s.x;
    u_ = s.u;
    p_ = s.p;
    set_by_user_ = s.set_by_user;
    t_ = s.t;
    rtol_ = s.rtol;
    mode_ = s.mode;
    project_next_ = s.project_next;
    dirty_ = true;
  }
  /// A snapshot as bytes: a tag, the sizes, then every number (the layout of this
  /// model's build only; a different model's bytes are refused by the tag and sizes).
  std::vector<unsigned char> serialize(const Snapshot& s) const {
    std::vector<double> v = {kTag, static_cast<double>(s.x.size()), static_cast<double>(s.u.size()),
                             static_cast<double>(s.p.size()), s.t, s.rtol, static_cast<double>(static_cast<int>(s.mode)),
                             s.project_next ? 1.0 : 0.0};
    v.insert(v.end(), s.x.begin(), s.x.end());
    v.insert(v.end(), s.u.begin(), s.u.end());
    v.insert(v.end(), s.p.begin(), s.p.end());
    for (bool b : s.set_by_user) v.push_back(b ? 1.0 : 0.0);
    std::vector<unsigned char> bytes(v.size() * sizeof(double));
    std::memcpy(bytes.data(), v.data(), bytes.size());
    return bytes;
  }
  bool deserialize(const unsigned char* bytes, std::size_t size, Snapshot& s) const {
    const std::size_t nx = x_.size(), nu = u_.size(), np = p_.size();
    const std::size_t count = 8 + 2 * nx + nu + np;
    if (size != count * sizeof(double)) return false;
    std::vector<double> v(count);
    std::memcpy(v.data(), bytes, size);
    if (v[0] != kTag || v[1] != static_cast<double>(nx) || v[2] != static_cast<double>(nu) ||
        v[3] != static_cast<double>(np) || v[6] < 0 || v[6] > static_cast<double>(static_cast<int>(Mode::Failed)))
      return false;
    s.t = v[4];
    s.rtol = v[5];
    s.mode = static_cast<Mode>(static_cast<int>(v[6]));
    s.project_next = v[7] != 0;
    std::size_t at = 8;
    s.x.assign(v.begin() + static_cast<long>(at), v.begin() + static_cast<long>(at + nx));
    at += nx;
    s.u.assign(v.begin() + static_cast<long>(at), v.begin() + static_cast<long>(at + nu));
    at += nu;
    s.p.assign(v.begin() + static_cast<long>(at), v.begin() + static_cast<long>(at + np));
    at += np;
    s.set_by_user.assign(nx, false);
    for (std::size_t i = 0; i < nx; ++i) s.set_by_user[i] = v[at + i] != 0;
    return true;
  }

  /// Logs an error and fails the instance (every later call but free and reset is refused).
  Status fail(const std::string& message) {
    log(kError, "logError", message);
    mode_ = Mode::Failed;
    return kError;
  }
  /// A call the standard does not allow in this mode: an error, the instance unharmed.
  Status refuse(const std::string& what, const std::string& when) {
    log(kError, "logError", "cannot " + what + " now: only " + when);
    return kError;
  }
  void log(Status s, const char* category, const std::string& message) const {
    if (log_ && (logging_ || s >= kWarning)) log_(s, category, message);
  }

 private:
  static constexpr double kTag = 20260301.0;  // marks a serialized mbsc FMU state

  bool projects() const {
    const auto& T = m_.table;
    return T.full_state_layout() && (T.nposc > 0 || T.nc > 0);
  }
  static double max_abs(const std::vector<double>& v) {
    double m = 0;
    for (double e : v) m = std::max(m, std::fabs(e));
    return m;
  }
  static std::string number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.9g", v);
    return buf;
  }
  std::string name_of(unsigned r) const {
    const FmuLayout L = m_.layout();
    const auto& T = m_.table;
    if (r < L.derivative(0)) return T.state_names[r];
    if (r < L.input(0)) return std::string("der(") + T.state_names[r - L.derivative(0)] + ")";
    if (r < L.param(0)) return T.input_names[r - L.input(0)];
    if (r < L.output(0)) return T.param_names[r - L.param(0)];
    if (r < L.time()) return T.output_names[r - L.output(0)];
    if (r == L.time()) return "time";
    return "#" + std::to_string(r);
  }
  Status unknown(unsigned r) {
    log(kError, "logError", "no variable has the value reference " + std::to_string(r));
    return kError;
  }
  /// The derivatives and outputs at the current (t, x, u, p), once per change.
  bool evaluate() {
    if (!dirty_) return true;
    const auto& T = m_.table;
    xdot_.assign(static_cast<std::size_t>(T.nx), 0.0);
    y_.assign(static_cast<std::size_t>(std::max(1, T.ny)), 0.0);
    if (const int s = T.rhs(t_, x_.data(), u_.data(), p_.data(), xdot_.data()); s != 0) {
      failure_ = "the rhs failed: " + std::string(runtime::rhs_status_meaning(s));
      return false;
    }
    if (T.ny > 0) {
      if (const int s = T.outputs(t_, x_.data(), u_.data(), p_.data(), y_.data()); s != 0) {
        failure_ = "the outputs failed: " + std::string(runtime::rhs_status_meaning(s));
        return false;
      }
    }
    dirty_ = false;
    return true;
  }

  const FmuModel& m_;
  Kind kind_;
  Log log_;
  bool logging_ = false;
  Mode mode_ = Mode::Instantiated;
  std::vector<double> x_, u_, p_, xdot_, y_;
  std::vector<bool> set_by_user_;
  double t_ = 0.0, rtol_ = 1e-6;
  bool dirty_ = true, project_next_ = false;
  std::string failure_;
};

}  // namespace mbsc::fmi
