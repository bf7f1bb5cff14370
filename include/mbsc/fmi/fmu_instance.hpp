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
/// Initialization assembles the state as `mbsc run` does (runtime/assemble.hpp): the
/// entries the model's `initial` statements give (initial="exact") are kept, with the
/// values the importer set; the others (initial="approx") are solved from the
/// constraints, what the importer set for them serving as the first guess. It happens
/// once per change, when initialization mode ends or an initial unknown is read in it.
/// Model exchange: between the importer's steps the FMU re-selects the independent
/// speeds (models with `alternative` sets), and asks for a step event where the
/// constraint residuals or a unit quaternion's norm drifted beyond the tolerance; in the
/// event it projects the state back (runtime/projection.hpp) and normalizes.
/// Co-simulation: each doStep integrates with the runtime's simulation loop
/// (runtime/simulate.hpp: an embedded Runge-Kutta method, projection, unit quaternions,
/// re-selection of the independent speeds), inputs held constant over the step.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <functional>
#include <initializer_list>
#include <string>
#include <vector>

#include "mbsc/runtime/assemble.hpp"
#include "mbsc/runtime/model_table.hpp"
#include "mbsc/runtime/partition_selector.hpp"
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

  FmuInstance(const FmuModel& m, Kind kind, Log log)
      : m_(m), kind_(kind), log_(std::move(log)),
        selector_(runtime::PartitionFunctions{m.table.npartitions, m.table.rhs_partition, m.table.conditioning_partition}) {
    reset();
  }

  const FmuModel& model() const { return m_; }
  Kind kind() const { return kind_; }
  Mode mode() const { return mode_; }
  void set_logging(bool on) { logging_ = on; }

  /// Back to the state right after instantiation (also from a failure).
  void reset() {
    const auto& T = m_.table;
    x_.assign(m_.start, m_.start + T.nx);
    u_.assign(static_cast<std::size_t>(std::max(1, T.nin)), 0.0);
    p_.assign(T.param_defaults, T.param_defaults + T.np);
    t_ = 0.0;
    rtol_ = 1e-6;
    event_pending_ = false;
    assembled_ = false;
    dirty_ = true;
    selector_.set_active(0);
    mode_ = Mode::Instantiated;
  }

  /// The experiment's tolerance and start time (FMI 2.0: after instantiation only).
  Status setup(bool tolerance_defined, double tolerance, double start_time) {
    if (mode_ != Mode::Instantiated) return refuse("set up the experiment", "after instantiation or reset");
    if (!std::isfinite(start_time)) return refuse("start at a time that is not finite", "at a finite time");
    if (tolerance_defined && tolerance > 0 && std::isfinite(tolerance)) rtol_ = tolerance;
    t_ = start_time;
    dirty_ = true;
    return kOK;
  }
  Status enter_initialization() {
    if (mode_ != Mode::Instantiated) return refuse("enter initialization mode", "after instantiation or reset");
    mode_ = Mode::Initialization;
    return kOK;
  }
  /// Assembles the state (see the file's comment) unless done since the last change,
  /// checks the rhs there, then enters event mode (model exchange) or step mode
  /// (co-simulation).
  Status exit_initialization() {
    if (mode_ != Mode::Initialization) return refuse("exit initialization mode", "in initialization mode");
    if (!ensure_assembled()) return kError;
    if (reselects()) selector_.update(t_, x_.data(), u_.data(), p_.data());  // the start may be singular for set 0
    dirty_ = true;
    if (!evaluate()) return fail("at the start (t = " + number(t_) + "): " + failure_);
    mode_ = kind_ == Kind::ModelExchange ? Mode::Event : Mode::Step;
    return kOK;
  }
  Status terminate() {
    if (mode_ == Mode::Failed || mode_ == Mode::Instantiated || mode_ == Mode::Terminated)
      return refuse("terminate", "after initialization, before a failure");
    mode_ = Mode::Terminated;
    return kOK;
  }

  // ---- values ----
  Status get_real(const unsigned* vr, std::size_t n, double* values) {
    const FmuLayout L = m_.layout();
    // In initialization mode the initial unknowns (the states assembly solves, the
    // derivatives, the outputs) are those of the assembled state.
    if (mode_ == Mode::Initialization && !ensure_assembled()) return kError;
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
    if (mode_ == Mode::Failed || mode_ == Mode::Terminated) return refuse("set a value", "before termination or a failure");
    const FmuLayout L = m_.layout();
    const bool before_start = mode_ == Mode::Instantiated || mode_ == Mode::Initialization;
    for (std::size_t k = 0; k < n; ++k) {
      const unsigned r = vr[k];
      const double v = values[k];
      if (r >= L.count()) return unknown(r);
      if (!std::isfinite(v)) return refuse("set '" + name_of(r) + "' to a value that is not finite", "to finite values");
      if (r < L.derivative(0)) {
        if (!before_start) return refuse("set the state variable '" + name_of(r) + "'", "before initialization ends");
        x_[r] = v;
      } else if (r >= L.input(0) && r < L.param(0)) {
        u_[r - L.input(0)] = v;
      } else if (r >= L.param(0) && r < L.output(0)) {
        if (!before_start) return refuse("set the parameter '" + name_of(r) + "'", "before initialization ends (it is fixed)");
        p_[r - L.param(0)] = v;
      } else {
        return refuse("set '" + name_of(r) + "'", "never: it is calculated");
      }
      if (before_start) assembled_ = false;
      dirty_ = true;
    }
    return kOK;
  }

  // ---- model exchange ----
  Status set_time(double t) {
    if (!in_model_exchange({Mode::Event, Mode::Continuous}, "set the time")) return kError;
    if (!std::isfinite(t)) return refuse("set a time that is not finite", "finite times");
    t_ = t;
    dirty_ = true;
    return kOK;
  }
  Status set_states(const double* x, std::size_t n) {
    if (!in_model_exchange({Mode::Event, Mode::Continuous}, "set the continuous states")) return kError;
    if (n != x_.size()) return refuse("set " + std::to_string(n) + " states", std::to_string(x_.size()) + " at once");
    std::copy(x, x + n, x_.begin());
    dirty_ = true;
    return kOK;
  }
  Status get_states(double* x, std::size_t n) {
    if (n != x_.size()) return refuse("get " + std::to_string(n) + " states", std::to_string(x_.size()) + " at once");
    if (mode_ == Mode::Initialization && !ensure_assembled()) return kError;
    std::copy(x_.begin(), x_.end(), x);
    return kOK;
  }
  Status get_derivatives(double* xdot, std::size_t n) {
    if (n != x_.size()) return refuse("get " + std::to_string(n) + " derivatives", std::to_string(x_.size()) + " at once");
    if (mode_ == Mode::Instantiated || mode_ == Mode::Failed)
      return refuse("get the derivatives", "after entering initialization, before a failure");
    if (mode_ == Mode::Initialization && !ensure_assembled()) return kError;
    if (!evaluate()) return fail("at t = " + number(t_) + ": " + failure_);
    std::copy(xdot_.begin(), xdot_.end(), xdot);
    return kOK;
  }
  Status get_nominals(double* nominal, std::size_t n) const {
    std::fill(nominal, nominal + n, 1.0);
    return kOK;
  }
  Status enter_event_mode() {
    if (!in_model_exchange({Mode::Event, Mode::Continuous}, "enter event mode")) return kError;
    mode_ = Mode::Event;
    return kOK;
  }
  Status enter_continuous_time_mode() {
    if (!in_model_exchange({Mode::Event}, "enter continuous-time mode")) return kError;
    mode_ = Mode::Continuous;
    return kOK;
  }
  /// Between the importer's steps: re-selects the independent speeds (no event: the
  /// state is unchanged), and asks for a step event where the constraints drifted beyond
  /// the tolerance or a unit quaternion's norm left 1 by more.
  Status completed_integrator_step(bool& enter_event_mode) {
    enter_event_mode = false;
    if (!in_model_exchange({Mode::Continuous}, "complete an integrator step")) return kError;
    if (reselects() && selector_.update(t_, x_.data(), u_.data(), p_.data()) == 0) dirty_ = true;
    const double tolerance = rtol_ * (1.0 + max_abs(x_));
    if (projects()) {
      double position = 0, velocity = 0;
      if (!runtime::constraint_residuals(m_.table, t_, x_.data(), u_.data(), p_.data(), position, velocity))
        return fail("the constraint residuals are not finite at t = " + number(t_));
      if (position > tolerance || velocity > tolerance) event_pending_ = true;
    }
    for (int b = 0; b < m_.nquaternions; ++b)
      if (std::fabs(quaternion_norm(b) - 1.0) > rtol_) event_pending_ = true;
    enter_event_mode = event_pending_;
    return kOK;
  }
  /// Event iteration: the projection (and normalization) completed_integrator_step asked for.
  Status update_discrete_states(bool& values_changed) {
    values_changed = false;
    if (!in_model_exchange({Mode::Event}, "update the discrete states")) return kError;
    if (!event_pending_) return kOK;
    event_pending_ = false;
    if (projects()) {
      const runtime::ProjectionReport r = runtime::project(m_.table, t_, x_, u_.data(), p_.data());
      if (!r.ok()) return fail("the projection onto the constraints failed at t = " + number(t_) + ": " + r.message);
    }
    if (!normalize_quaternions()) return kError;
    dirty_ = true;
    values_changed = true;
    return kOK;
  }

  // ---- co-simulation ----
  /// Integrates from t to t + h (t must be this instance's time).
  Status do_step(double t, double h) {
    if (kind_ != Kind::CoSimulation || mode_ != Mode::Step)
      return refuse("take a step", "in co-simulation's step mode (after initialization)");
    if (!(h > 0) || !std::isfinite(h)) return refuse("take the communication step " + number(h), "positive steps");
    if (!std::isfinite(t) || std::fabs(t - t_) > 1e-9 * std::max(1.0, std::fabs(t_)))
      return refuse("step from t = " + number(t), "from the FMU's time t = " + number(t_));
    const auto& T = m_.table;
    const std::vector<double> u = u_;
    runtime::ModelDynamics dyn(T, p_, [&u](double, double* out) {
      std::copy(u.begin(), u.end(), out);
      return 0;
    });
    dyn.selector() = selector_;  // the independent set goes on from the last step
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
    selector_ = dyn.selector();
    dirty_ = true;
    return kOK;
  }
  double time() const { return t_; }

  // ---- snapshots (get/set/serialize FMU state) ----
  struct Snapshot {
    std::vector<double> x, u, p;
    double t, rtol;
    Mode mode;
    Kind kind;
    bool event_pending, assembled;
    int partition;
  };
  Snapshot snapshot() const {
    return {x_, u_, p_, t_, rtol_, mode_, kind_, event_pending_, assembled_, selector_.active()};
  }
  Status restore(const Snapshot& s) {
    if (s.kind != kind_ || s.x.size() != x_.size() || s.u.size() != u_.size() || s.p.size() != p_.size())
      return refuse("restore a state of another instance kind or model", "states of this FMU and kind");
    x_ = s.x;
    u_ = s.u;
    p_ = s.p;
    t_ = s.t;
    rtol_ = s.rtol;
    mode_ = s.mode;
    event_pending_ = s.event_pending;
    assembled_ = s.assembled;
    selector_.set_active(s.partition);
    dirty_ = true;
    return kOK;
  }
  /// A snapshot as bytes: a tag, the sizes, then every number (the layout of this
  /// model's build only; a different model's bytes are refused by the tag and sizes).
  std::vector<unsigned char> serialize(const Snapshot& s) const {
    std::vector<double> v = {kTag,
                             static_cast<double>(s.x.size()),
                             static_cast<double>(s.u.size()),
                             static_cast<double>(s.p.size()),
                             s.t,
                             s.rtol,
                             static_cast<double>(static_cast<int>(s.mode)),
                             static_cast<double>(static_cast<int>(s.kind)),
                             s.event_pending ? 1.0 : 0.0,
                             s.assembled ? 1.0 : 0.0,
                             static_cast<double>(s.partition)};
    v.insert(v.end(), s.x.begin(), s.x.end());
    v.insert(v.end(), s.u.begin(), s.u.end());
    v.insert(v.end(), s.p.begin(), s.p.end());
    std::vector<unsigned char> bytes(v.size() * sizeof(double));
    std::memcpy(bytes.data(), v.data(), bytes.size());
    return bytes;
  }
  /// The snapshot `bytes` hold, or false when they are not one of this FMU's (the tag,
  /// the sizes, the mode and kind, finite numbers).
  bool deserialize(const unsigned char* bytes, std::size_t size, Snapshot& s) const {
    constexpr std::size_t kHead = 11;
    const std::size_t nx = x_.size(), nu = u_.size(), np = p_.size();
    const std::size_t count = kHead + nx + nu + np;
    if (size != count * sizeof(double)) return false;
    std::vector<double> v(count);
    std::memcpy(v.data(), bytes, size);
    for (double e : v)
      if (!std::isfinite(e)) return false;
    const auto in = [&](std::size_t i, double lo, double hi) { return v[i] >= lo && v[i] <= hi && v[i] == std::floor(v[i]); };
    if (v[0] != kTag || v[1] != static_cast<double>(nx) || v[2] != static_cast<double>(nu) ||
        v[3] != static_cast<double>(np) || !(v[5] > 0) || !in(6, 0, static_cast<int>(Mode::Failed)) || !in(7, 0, 1) ||
        !in(10, 0, std::max(0, m_.table.npartitions - 1)))
      return false;
    s.t = v[4];
    s.rtol = v[5];
    s.mode = static_cast<Mode>(static_cast<int>(v[6]));
    s.kind = static_cast<Kind>(static_cast<int>(v[7]));
    s.event_pending = v[8] != 0;
    s.assembled = v[9] != 0;
    s.partition = static_cast<int>(v[10]);
    std::size_t at = kHead;
    s.x.assign(v.begin() + static_cast<long>(at), v.begin() + static_cast<long>(at + nx));
    at += nx;
    s.u.assign(v.begin() + static_cast<long>(at), v.begin() + static_cast<long>(at + nu));
    at += nu;
    s.p.assign(v.begin() + static_cast<long>(at), v.begin() + static_cast<long>(at + np));
    return true;
  }

  // ---- FMU states as both C interfaces pass them: opaque pointers to snapshots ----
  Status get_fmu_state(void** state) const {
    if (!state) return kError;
    delete static_cast<Snapshot*>(*state);
    *state = new Snapshot(snapshot());
    return kOK;
  }
  Status set_fmu_state(const void* state) {
    if (!state) return refuse("restore a null FMU state", "states the FMU gave");
    return restore(*static_cast<const Snapshot*>(state));
  }
  static Status free_fmu_state(void** state) {
    if (state) {
      delete static_cast<Snapshot*>(*state);
      *state = nullptr;
    }
    return kOK;
  }
  Status serialized_size(const void* state, std::size_t* size) const {
    if (!state || !size) return kError;
    *size = serialize(*static_cast<const Snapshot*>(state)).size();
    return kOK;
  }
  Status serialize_into(const void* state, unsigned char* bytes, std::size_t size) {
    if (!state || !bytes) return kError;
    const auto data = serialize(*static_cast<const Snapshot*>(state));
    if (data.size() != size)
      return refuse("serialize into a buffer of " + std::to_string(size) + " bytes", std::to_string(data.size()));
    std::memcpy(bytes, data.data(), size);
    return kOK;
  }
  Status deserialize_into(const unsigned char* bytes, std::size_t size, void** state) {
    if (!bytes || !state) return kError;
    Snapshot s;
    if (!deserialize(bytes, size, s)) return refuse("restore these bytes", "bytes serialized by this FMU");
    delete static_cast<Snapshot*>(*state);
    *state = new Snapshot(std::move(s));
    return kOK;
  }

  /// Logs an error and fails the instance: every later call but reset, free, getting
  /// values and FMU states is refused.
  Status fail(const std::string& message) {
    log(kError, "logError", message);
    mode_ = Mode::Failed;
    return kError;
  }
  /// A call the standard does not allow now, or a bad argument: an error, the instance
  /// unharmed.
  Status refuse(const std::string& what, const std::string& when) {
    log(kError, "logError", "cannot " + what + " now: only " + when);
    return kError;
  }
  void log(Status s, const char* category, const std::string& message) const {
    if (log_ && (logging_ || s >= kWarning)) log_(s, category, message);
  }

 private:
  static constexpr double kTag = 20261206.0;  // marks a serialized mbsc FMU state (format 2)

  /// Whether the state has constraints to assemble and project onto (the full state).
  bool projects() const {
    const auto& T = m_.table;
    return T.full_state_layout() && (T.nposc > 0 || T.nc > 0);
  }
  bool reselects() const {
    const auto& T = m_.table;
    return T.npartitions > 1 && T.rhs_partition && T.conditioning_partition;
  }
  bool in_model_exchange(std::initializer_list<Mode> modes, const char* what) {
    bool ok = kind_ == Kind::ModelExchange;
    if (ok) {
      ok = false;
      for (Mode m : modes) ok = ok || m == mode_;
    }
    if (!ok) refuse(what, "in model exchange's event or continuous-time mode, as the standard orders the calls");
    return ok;
  }
  double quaternion_norm(int b) const {
    double n2 = 0;
    for (int k = 0; k < 4; ++k) {
      const double e = x_[static_cast<std::size_t>(m_.quaternion_indices[4 * b + k])];
      n2 += e * e;
    }
    return std::sqrt(n2);
  }
  /// Divides each unit quaternion of the state by its norm; one that is all zero fails.
  bool normalize_quaternions() {
    for (int b = 0; b < m_.nquaternions; ++b) {
      const double n = quaternion_norm(b);
      if (!(n > 0) || !std::isfinite(n)) {
        fail(std::string("the unit quaternion of '") + m_.table.state_names[m_.quaternion_indices[4 * b]] +
             "' is zero or not finite: no rotation");
        return false;
      }
      for (int k = 0; k < 4; ++k) x_[static_cast<std::size_t>(m_.quaternion_indices[4 * b + k])] /= n;
    }
    return true;
  }
  /// The start the values set so far give: quaternions made unit, then (full state with
  /// constraints) the coordinates and speeds the model does not give solved from the
  /// constraints, the others' values kept. Once per change.
  bool ensure_assembled() {
    if (assembled_) return true;
    if (!normalize_quaternions()) return false;
    if (projects()) {
      const auto& T = m_.table;
      const runtime::AssemblyModel am = runtime::assembly_model_of(T, m_.quaternion_indices, m_.nquaternions);
      std::vector<bool> given_q(static_cast<std::size_t>(T.nq)), given_u(static_cast<std::size_t>(T.nu));
      for (int i = 0; i < T.nx; ++i) {
        if (i < T.nq) given_q[static_cast<std::size_t>(i)] = m_.given[i] != 0;
        else given_u[static_cast<std::size_t>(i - T.nq)] = m_.given[i] != 0;
      }
      const runtime::AssemblyResult a = runtime::assemble(am, t_, x_, given_q, given_u, u_.data(), p_.data());
      if (!a.ok()) {
        fail("the initial state is inconsistent: " + a.message);
        return false;
      }
      if (a.near_singular) log(kWarning, "logWarning", "the initial state is " + a.message);
    }
    assembled_ = true;
    dirty_ = true;
    return true;
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
    return "value reference " + std::to_string(r);
  }
  Status unknown(unsigned r) {
    log(kError, "logError", "no variable has the value reference " + std::to_string(r));
    return kError;
  }
  /// The derivatives and outputs at the current (t, x, u, p), once per change, through
  /// the active independent set.
  bool evaluate() {
    if (!dirty_) return true;
    const auto& T = m_.table;
    xdot_.assign(static_cast<std::size_t>(T.nx), 0.0);
    y_.assign(static_cast<std::size_t>(std::max(1, T.ny)), 0.0);
    const int s = reselects() ? selector_.rhs(t_, x_.data(), u_.data(), p_.data(), xdot_.data())
                              : T.rhs(t_, x_.data(), u_.data(), p_.data(), xdot_.data());
    if (s != 0) {
      failure_ = "the rhs failed: " + std::string(runtime::rhs_status_meaning(s));
      return false;
    }
    if (T.ny > 0) {
      if (const int so = T.outputs(t_, x_.data(), u_.data(), p_.data(), y_.data()); so != 0) {
        failure_ = "the outputs failed: " + std::string(runtime::rhs_status_meaning(so));
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
  double t_ = 0.0, rtol_ = 1e-6;
  bool dirty_ = true, event_pending_ = false, assembled_ = false;
  runtime::PartitionSelector selector_;
  std::string failure_;
};

}  // namespace mbsc::fmi
