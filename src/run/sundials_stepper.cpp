// SPDX-License-Identifier: GPL-2.0-or-later
// runtime::Stepper over CVODE (BDF, Adams) and ARKODE (ARKStep implicit, ERKStep explicit).
// One class, switching on the method where the two packages' calls differ.
#include "sundials_stepper.hpp"

#ifdef MBSC_HAVE_SUNDIALS

#include <arkode/arkode_arkstep.h>
#include <arkode/arkode_erkstep.h>
#include <cvode/cvode.h>
#include <cvode/cvode_proj.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_config.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "mbsc/runtime/rhs_jacobian.hpp"

namespace mbsc::run {
namespace {

using runtime::Stepper;
using runtime::StepperOptions;
using runtime::StepperStats;

enum class Method { Bdf, Adams, ArkDirk, ArkErk };

std::string format_number(double v) {
  if (std::isnan(v)) return "nan";  // never "-nan"
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

class SundialsStepper final : public Stepper {
 public:
  SundialsStepper(Method method, std::string name, runtime::Rhs f, int n, const StepperOptions& options,
                  const SundialsOptions& extra)
      : method_(method), name_(std::move(name)), f_(std::move(f)), n_(n), options_(options), extra_(extra),
        x_(n), scale_(n) {
    SUNContext_Create(nullptr, &ctx_);
    y_ = N_VNew_Serial(n_, ctx_);
    weights_ = N_VNew_Serial(n_, ctx_);
  }

  ~SundialsStepper() override {
    release();
    if (weights_) N_VDestroy(weights_);
    if (y_) N_VDestroy(y_);
    if (ctx_) SUNContext_Free(&ctx_);
  }

  Status reset(double t, const std::vector<double>& x) override {
    if (static_cast<int>(x.size()) != n_) return fail(Status::SolverFailed, "reset with a state of the wrong size");
    if (mem_) base_ = stats_;  // keep counting across restarts
    solver_errors_.clear();
    x_ = x;
    t_ = t_begin_ = t;
    stepped_ = false;
    tiny_steps_ = 0;
    message_.clear();
    std::copy(x.begin(), x.end(), NV_DATA_S(y_));
    int flag = mem_ ? reinit(t) : create(t);
    if (flag < 0) return fail(Status::SolverFailed, "cannot (re)start the integrator at t = " + format_number(t));
    return Status::Ok;
  }

  Status step(double t_stop) override {
    if (!mem_) return fail(Status::SolverFailed, "step before reset");
    if (t_stop <= t_) return Status::Ok;
    if (stats_.accepted >= options_.max_steps)
      return fail(Status::TooManySteps, "step budget of " + std::to_string(options_.max_steps) +
                                            " steps spent at t = " + format_number(t_) +
                                            " (last step " + format_number(last_step()) + ")");
    solver_errors_.clear();
    rhs_status_ = 0;
    double t_reached = t_;
    int flag = one_step(t_stop, &t_reached);
    update_stats();
    if (flag < 0) return fail(classify(flag), describe(flag));
    // A step below h_min, or one that no longer moves t (below 1e-14 |t|), is a failure
    // (unless it only closes the gap to t_stop). Adams' fixed-point iteration, for one,
    // treats a failing rhs as recoverable and creeps towards the failing time. Near t = 0
    // a step below 1e-14 is only a failure with a failing rhs behind it or when 50 come in
    // a row: BDF's first steps on a stiff model at tight tolerances are that small and
    // then grow (tests/data/stiff/stiff_pendulums.mbs at rtol 1e-12 started with 5e-15 and
    // was stopped).
    const double h = std::fabs(last_step());
    const bool tiny = h <= 1e-14 * std::max(1.0, std::fabs(t_reached));
    tiny_steps_ = tiny ? tiny_steps_ + 1 : 0;
    const bool stuck = h <= 1e-14 * std::fabs(t_reached) || (tiny && (rhs_status_ != 0 || tiny_steps_ >= 50));
    if (flag != stop_time_return() && (h < options_.h_min || stuck)) {
      if (rhs_status_ != 0) return fail(Status::RhsFailed, rhs_detail_ + " at t = " + format_number(rhs_t_));
      return fail(Status::StepTooSmall, "the step size fell to " + format_number(h) + " at t = " + format_number(t_reached));
    }
    t_begin_ = t_;
    t_ = (flag == stop_time_return() || t_reached > t_stop) ? t_stop : t_reached;
    std::copy(NV_DATA_S(y_), NV_DATA_S(y_) + n_, x_.begin());
    stepped_ = true;
    return Status::Ok;
  }

  double t() const override { return t_; }
  const std::vector<double>& x() const override { return x_; }
  double t_begin() const override { return t_begin_; }

  void interpolate(double t, std::vector<double>& out) const override {
    out.resize(n_);
    if (!stepped_ || t >= t_) {
      out = x_;
      return;
    }
    N_Vector dky = N_VMake_Serial(n_, out.data(), ctx_);
    int flag = 0;
    switch (method_) {
      case Method::Bdf:
      case Method::Adams: flag = CVodeGetDky(mem_, t, 0, dky); break;
      case Method::ArkDirk: flag = ARKStepGetDky(mem_, t, 0, dky); break;
      case Method::ArkErk: flag = ERKStepGetDky(mem_, t, 0, dky); break;
    }
    N_VDestroy(dky);
    if (flag < 0) out = x_;  // outside the last step: nothing better to give
  }

  const StepperStats& stats() const override { return stats_; }
  std::string message() const override { return message_; }
  std::string name() const override { return name_; }

 private:
  // --- SUNDIALS callbacks -------------------------------------------------------------
  static int rhs_callback(realtype t, N_Vector y, N_Vector ydot, void* self) {
    return static_cast<SundialsStepper*>(self)->call_rhs(t, NV_DATA_S(y), NV_DATA_S(ydot));
  }

  static int jacobian_callback(realtype t, N_Vector y, N_Vector fy, SUNMatrix J, void* self, N_Vector, N_Vector,
                               N_Vector) {
    return static_cast<SundialsStepper*>(self)->call_jacobian(t, NV_DATA_S(y), NV_DATA_S(fy), SM_DATA_D(J));
  }

  // A projection that fails is recoverable: CVODE retries the step with a smaller one.
  static int projection_callback(realtype t, N_Vector y, N_Vector correction, realtype, N_Vector, void* self) {
    auto* s = static_cast<SundialsStepper*>(self);
    ++s->projections_;
    return s->extra_.projection(t, NV_DATA_S(y), NV_DATA_S(correction)) == 0 ? 0 : 1;
  }

  static void error_callback(int, const char* module, const char* function, char* msg, void* self) {
    auto* s = static_cast<SundialsStepper*>(self);
    if (!s->solver_errors_.empty()) s->solver_errors_ += "; ";
    s->solver_errors_ += std::string(module) + "::" + function + ": " + msg;
  }

  // A failing or non-finite rhs ends the run (unrecoverable for SUNDIALS: as a recoverable
  // error the integrator would creep towards the failing time in ever smaller steps); the
  // failure is kept for the message.
  int call_rhs(double t, const double* x, double* xdot) {
    ++stats_.rhs_evals;
    if (int s = f_(t, x, xdot); s != 0) {
      rhs_status_ = s;
      rhs_t_ = t;
      rhs_detail_ = "the right-hand side returned status " + std::to_string(s);
      return -1;
    }
    for (int i = 0; i < n_; ++i)
      if (!std::isfinite(xdot[i])) {
        rhs_status_ = -1;
        rhs_t_ = t;
        rhs_detail_ = "the right-hand side gave xdot[" + std::to_string(i) + "] = " + format_number(xdot[i]);
        return -1;
      }
    return 0;
  }

  // A user Jacobian that fails at this state (a generated one not defined for the model,
  // status 4, or a singular solve) gives way to difference quotients for this call.
  int call_jacobian(double t, const double* x, const double* fx, double* J) {
    if (extra_.jacobian_source == JacobianSource::User) {
      if (extra_.jacobian(t, x, fx, J) == 0) return 0;
      ++fallbacks_;
    }
    // Typical sizes from the error weights: 1/w_i = rtol |x_i| + atol.
    int flag = is_cvode() ? CVodeGetErrWeights(mem_, weights_) : ARKStepGetErrWeights(mem_, weights_);
    const double* w = NV_DATA_S(weights_);
    for (int i = 0; i < n_; ++i) scale_[i] = (flag >= 0 && w[i] > 0.0) ? 1.0 / w[i] : 1.0;
    auto f = [this](double tt, const double* xx, double* out) { return call_rhs(tt, xx, out); };
    return runtime::rhs_jacobian_x(f, t, x, fx, n_, J, scale_.data()) == 0 ? 0 : 1;
  }

  // --- the two packages ---------------------------------------------------------------
  bool is_cvode() const { return method_ == Method::Bdf || method_ == Method::Adams; }
  bool implicit_newton() const { return method_ == Method::Bdf || method_ == Method::ArkDirk; }

  int create(double t) {
    int flag = 0;
    switch (method_) {
      case Method::Bdf:
      case Method::Adams:
        mem_ = CVodeCreate(method_ == Method::Bdf ? CV_BDF : CV_ADAMS, ctx_);
        if (!mem_) return -1;
        CVodeSetErrHandlerFn(mem_, error_callback, this);
        flag = CVodeInit(mem_, rhs_callback, t, y_);
        if (flag < 0) return flag;
        CVodeSetUserData(mem_, this);
        CVodeSStolerances(mem_, options_.rtol, options_.atol);
        if (options_.h > 0) CVodeSetInitStep(mem_, options_.h);
        if (options_.h_min > 0) CVodeSetMinStep(mem_, options_.h_min);
        if (options_.h_max > 0) CVodeSetMaxStep(mem_, options_.h_max);
        if (method_ == Method::Adams) {
          nls_ = SUNNonlinSol_FixedPoint(y_, 0, ctx_);
          flag = CVodeSetNonlinearSolver(mem_, nls_);
        } else {
          attach_dense_solver();
          flag = CVodeSetLinearSolver(mem_, ls_, A_);
          if (flag >= 0 && extra_.jacobian_source != JacobianSource::Sundials)
            flag = CVodeSetJacFn(mem_, jacobian_callback);
          if (flag >= 0 && extra_.projection) {
            flag = CVodeSetProjFn(mem_, projection_callback);
            // The error estimate is not projected (it would need the tangent space's
            // projector): CVODE's test then sees the unprojected local error.
            if (flag >= 0) flag = CVodeSetProjErrEst(mem_, SUNFALSE);
          }
        }
        return flag;
      case Method::ArkDirk:
        mem_ = ARKStepCreate(nullptr, rhs_callback, t, y_, ctx_);
        if (!mem_) return -1;
        ARKStepSetErrHandlerFn(mem_, error_callback, this);
        ARKStepSetUserData(mem_, this);
        ARKStepSStolerances(mem_, options_.rtol, options_.atol);
        if (options_.h > 0) ARKStepSetInitStep(mem_, options_.h);
        if (options_.h_min > 0) ARKStepSetMinStep(mem_, options_.h_min);
        if (options_.h_max > 0) ARKStepSetMaxStep(mem_, options_.h_max);
        attach_dense_solver();
        flag = ARKStepSetLinearSolver(mem_, ls_, A_);
        // ARKODE's default rebuilds the Newton matrix I - gamma J only every 20 steps; on a
        // lightly damped oscillator its Newton iterations then stopped short and the global
        // error was 1e4 times rtol (8.6e-6 at rtol 1e-9). Rebuilding it every step (J itself
        // is still reused while it serves) gives 1e-11 for 1.5 times the rhs calls.
        ARKStepSetLSetupFrequency(mem_, 1);
        if (flag >= 0 && extra_.jacobian_source != JacobianSource::Sundials)
          flag = ARKStepSetJacFn(mem_, jacobian_callback);
        return flag;
      case Method::ArkErk:
        mem_ = ERKStepCreate(rhs_callback, t, y_, ctx_);
        if (!mem_) return -1;
        ERKStepSetErrHandlerFn(mem_, error_callback, this);
        ERKStepSetUserData(mem_, this);
        ERKStepSStolerances(mem_, options_.rtol, options_.atol);
        ERKStepSetTableNum(mem_, ARKODE_DORMAND_PRINCE_7_4_5);
        if (options_.h > 0) ERKStepSetInitStep(mem_, options_.h);
        if (options_.h_min > 0) ERKStepSetMinStep(mem_, options_.h_min);
        if (options_.h_max > 0) ERKStepSetMaxStep(mem_, options_.h_max);
        return 0;
    }
    return -1;
  }

  void attach_dense_solver() {
    A_ = SUNDenseMatrix(n_, n_, ctx_);
    ls_ = SUNLinSol_Dense(y_, A_, ctx_);
  }

  int reinit(double t) {
    switch (method_) {
      case Method::Bdf:
      case Method::Adams: return CVodeReInit(mem_, t, y_);
      case Method::ArkDirk: return ARKStepReInit(mem_, nullptr, rhs_callback, t, y_);
      case Method::ArkErk: return ERKStepReInit(mem_, rhs_callback, t, y_);
    }
    return -1;
  }

  int one_step(double t_stop, double* t_reached) {
    realtype tr = t_;
    int flag = 0;
    switch (method_) {
      case Method::Bdf:
      case Method::Adams:
        CVodeSetStopTime(mem_, t_stop);
        flag = CVode(mem_, t_stop, y_, &tr, CV_ONE_STEP);
        break;
      case Method::ArkDirk:
        ARKStepSetStopTime(mem_, t_stop);
        flag = ARKStepEvolve(mem_, t_stop, y_, &tr, ARK_ONE_STEP);
        break;
      case Method::ArkErk:
        ERKStepSetStopTime(mem_, t_stop);
        flag = ERKStepEvolve(mem_, t_stop, y_, &tr, ARK_ONE_STEP);
        break;
    }
    *t_reached = tr;
    return flag;
  }

  int stop_time_return() const { return is_cvode() ? CV_TSTOP_RETURN : ARK_TSTOP_RETURN; }

  double last_step() const {
    realtype h = 0;
    switch (method_) {
      case Method::Bdf:
      case Method::Adams: CVodeGetLastStep(mem_, &h); break;
      case Method::ArkDirk: ARKStepGetLastStep(mem_, &h); break;
      case Method::ArkErk: ERKStepGetLastStep(mem_, &h); break;
    }
    return h;
  }

  void update_stats() {
    long nst = 0, netf = 0, ncfn = 0, nje = 0, nni = 0;
    switch (method_) {
      case Method::Bdf:
      case Method::Adams:
        CVodeGetNumSteps(mem_, &nst);
        CVodeGetNumErrTestFails(mem_, &netf);
        CVodeGetNumNonlinSolvConvFails(mem_, &ncfn);
        CVodeGetNumNonlinSolvIters(mem_, &nni);
        if (method_ == Method::Bdf) CVodeGetNumJacEvals(mem_, &nje);
        break;
      case Method::ArkDirk:
        ARKStepGetNumSteps(mem_, &nst);
        ARKStepGetNumErrTestFails(mem_, &netf);
        ARKStepGetNumNonlinSolvConvFails(mem_, &ncfn);
        ARKStepGetNumNonlinSolvIters(mem_, &nni);
        ARKStepGetNumJacEvals(mem_, &nje);
        break;
      case Method::ArkErk:
        ERKStepGetNumSteps(mem_, &nst);
        ERKStepGetNumErrTestFails(mem_, &netf);
        break;
    }
    const long rhs = stats_.rhs_evals;  // counted by call_rhs across restarts
    stats_ = base_;
    stats_.accepted += nst;
    stats_.rejected += netf + ncfn;
    stats_.steps += nst + netf + ncfn;
    stats_.jacobian_evals += nje;
    stats_.newton_iterations += nni;
    stats_.newton_failures += ncfn;
    stats_.jacobian_fallbacks = fallbacks_;  // counted by call_jacobian across restarts
    stats_.rhs_evals = rhs;
    stats_.projections = projections_;  // counted by projection_callback across restarts
  }

  Status classify(int flag) const {
    if (rhs_status_ != 0) return Status::RhsFailed;
    if (is_cvode()) {
      switch (flag) {
        case CV_TOO_MUCH_WORK: return Status::TooManySteps;
        case CV_TOO_MUCH_ACC:
        case CV_ERR_FAILURE: return Status::StepTooSmall;
        case CV_RHSFUNC_FAIL:
        case CV_FIRST_RHSFUNC_ERR:
        case CV_REPTD_RHSFUNC_ERR:
        case CV_UNREC_RHSFUNC_ERR: return Status::RhsFailed;
        default: return Status::SolverFailed;
      }
    }
    switch (flag) {
      case ARK_TOO_MUCH_WORK: return Status::TooManySteps;
      case ARK_TOO_MUCH_ACC:
      case ARK_ERR_FAILURE: return Status::StepTooSmall;
      case ARK_RHSFUNC_FAIL:
      case ARK_FIRST_RHSFUNC_ERR:
      case ARK_REPTD_RHSFUNC_ERR:
      case ARK_UNREC_RHSFUNC_ERR: return Status::RhsFailed;
      default: return Status::SolverFailed;
    }
  }

  std::string describe(int flag) const {
    const double t_now = t_;
    std::string what;
    if (rhs_status_ != 0) {
      what = rhs_detail_ + " at t = " + format_number(rhs_t_);
    } else {
      char* flag_name = is_cvode() ? CVodeGetReturnFlagName(flag) : ARKStepGetReturnFlagName(flag);
      std::string reason;
      switch (classify(flag)) {
        case Status::StepTooSmall: reason = "the step size fell to " + format_number(std::fabs(last_step())); break;
        case Status::TooManySteps: reason = "too many internal steps"; break;
        default: reason = "the solver failed"; break;
      }
      what = reason + " at t = " + format_number(t_now) + " (" + (flag_name ? flag_name : "?") + ")";
      std::free(flag_name);
    }
    if (!solver_errors_.empty()) what += " [" + solver_errors_ + "]";
    return what;
  }

  Status fail(Status s, const std::string& what) {
    message_ = name_ + ": " + what;
    return s;
  }

  void release() {
    if (mem_) {
      switch (method_) {
        case Method::Bdf:
        case Method::Adams: CVodeFree(&mem_); break;
        case Method::ArkDirk: ARKStepFree(&mem_); break;
        case Method::ArkErk: ERKStepFree(&mem_); break;
      }
    }
    if (ls_) SUNLinSolFree(ls_);
    if (A_) SUNMatDestroy(A_);
    if (nls_) SUNNonlinSolFree(nls_);
    mem_ = nullptr;
    ls_ = nullptr;
    A_ = nullptr;
    nls_ = nullptr;
  }

  Method method_;
  std::string name_;
  runtime::Rhs f_;
  int n_;
  StepperOptions options_;
  SundialsOptions extra_;

  SUNContext ctx_ = nullptr;
  void* mem_ = nullptr;
  N_Vector y_ = nullptr, weights_ = nullptr;
  SUNMatrix A_ = nullptr;
  SUNLinearSolver ls_ = nullptr;
  SUNNonlinearSolver nls_ = nullptr;

  double t_ = 0.0, t_begin_ = 0.0;
  std::vector<double> x_, scale_;
  bool stepped_ = false;
  StepperStats stats_, base_;
  std::string message_, solver_errors_, rhs_detail_;
  int rhs_status_ = 0;
  double rhs_t_ = 0.0;
  long projections_ = 0;
  long fallbacks_ = 0;  // user Jacobians that failed and gave way to differences
  int tiny_steps_ = 0;  // steps in a row below 1e-14 max(1, |t|)
};

}  // namespace

const std::vector<std::string>& sundials_stepper_names() {
  static const std::vector<std::string> names = {"bdf", "adams", "ark-dirk", "ark-erk"};
  return names;
}

std::string sundials_version() { return SUNDIALS_VERSION; }

std::unique_ptr<runtime::Stepper> make_sundials_stepper(const std::string& name, runtime::Rhs f, int n,
                                                        const runtime::StepperOptions& options,
                                                        const SundialsOptions& extra) {
  Method m;
  if (name == "bdf") m = Method::Bdf;
  else if (name == "adams") m = Method::Adams;
  else if (name == "ark-dirk") m = Method::ArkDirk;
  else if (name == "ark-erk") m = Method::ArkErk;
  else return nullptr;
  if (n <= 0 || !f) return nullptr;
  if (extra.jacobian_source == JacobianSource::User && !extra.jacobian) return nullptr;
  return std::make_unique<SundialsStepper>(m, name, std::move(f), n, options, extra);
}

}  // namespace mbsc::run

#else  // no SUNDIALS: the names are empty, the factory gives nothing

namespace mbsc::run {

const std::vector<std::string>& sundials_stepper_names() {
  static const std::vector<std::string> names;
  return names;
}

std::string sundials_version() { return ""; }

std::unique_ptr<runtime::Stepper> make_sundials_stepper(const std::string&, runtime::Rhs, int,
                                                        const runtime::StepperOptions&, const SundialsOptions&) {
  return nullptr;
}

}  // namespace mbsc::run

#endif
