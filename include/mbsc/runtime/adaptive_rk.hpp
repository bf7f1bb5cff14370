// SPDX-License-Identifier: GPL-2.0-or-later WITH mbsc-runtime-exception
// (see LICENSE: this header may be included in applications under any terms)
#pragma once
/// What every embedded explicit Runge-Kutta pair of the runtime shares (dopri5.hpp,
/// dop853.hpp): the weighted error norm, the first step, the step-size controller and
/// the bookkeeping of the Stepper interface. A method supplies one attempted step
/// (`attempt`: the new state and its error estimate) and its dense output.
///
/// Error norm (per component i, over the step from x to x_new):
///   err = sqrt(mean_i (e_i / (atol + rtol max(|x_i|, |x_new_i|)))^2),
/// a step is accepted when err <= 1. The next step is h (1/err)^(1/q) times a safety
/// factor, bounded in [fac_min, fac_max], with a proportional-integral correction by the
/// previous accepted error (exponent beta; 0 for a plain controller). After a rejection
/// the step does not grow again at once. A stage whose rhs fails (a singular solve, a
/// non-finite value) is treated like a rejection with a step four times smaller: a step
/// that jumped over a place where the model is defined is retried; a failure that
/// persists down to the smallest step is reported with its t.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "mbsc/runtime/stepper.hpp"

namespace mbsc::runtime {

/// What a generated function's non-zero status means (README, "The generated ABI").
inline std::string rhs_status_meaning(int status) {
  switch (status) {
    case 1: return "a linear solve is singular";
    case 2: return "a non-finite value (NaN or infinite)";
    case 3: return "the partition index is out of range";
    case 4: return "not defined for this model";
    case 10: return "the input function failed";
    default: return "status " + std::to_string(status);
  }
}

/// A number for messages (six significant digits).
inline std::string format_number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

struct ControllerSettings {
  int order = 5;          // q: the error estimate behaves like h^q
  double beta = 0.0;      // PI part (0.04 for dopri5, 0 for dop853)
  double safety = 0.9;
  double fac_min = 0.2;   // the step shrinks at most 5x per rejection...
  double fac_max = 10.0;  // ...and grows at most this much per step
};

class AdaptiveRungeKutta : public Stepper {
 public:
  AdaptiveRungeKutta(Rhs f, int n, StepperOptions o, ControllerSettings c)
      : f_(std::move(f)), n_(static_cast<std::size_t>(n)), o_(o), c_(c), x_(n_), f0_(n_), x_new_(n_), f_new_(n_) {}

  Status reset(double t, const std::vector<double>& x) override {
    const bool continuation = started_ && t == t_ && h_ > 0.0;
    t_ = t_begin_ = t;
    x_ = x;
    x_.resize(n_);
    stepped_ = false;
    started_ = true;
    if (!eval(t_, x_.data(), f0_.data())) return fail(Status::RhsFailed, "at the start, t = " + format_number(t_));
    if (!continuation) {
      h_ = o_.h > 0.0 ? o_.h : initial_step();
      err_old_ = 1e-4;
      if (h_ < 0.0) return fail(Status::RhsFailed, "while choosing the first step");
    }
    rejected_last_ = false;
    return Status::Ok;
  }

  Status step(double t_stop) override {
    if (!started_) return fail(Status::SolverFailed, "step() before reset()");
    if (!(t_stop > t_)) return Status::Ok;
    int rhs_failures = 0, last_status = 0;
    for (;;) {
      if (stats_.steps >= o_.max_steps)
        return fail(Status::TooManySteps,
                    "after " + std::to_string(stats_.steps) + " steps (max_steps) at t = " + format_number(t_) +
                        " with step size " + format_number(h_));
      double h = h_;
      if (o_.h_max > 0.0) h = std::min(h, o_.h_max);
      // Land on t_stop exactly, and never leave a sliver shorter than 1% of a step.
      const bool last = t_ + 1.01 * h >= t_stop;
      if (last) h = t_stop - t_;
      const double h_floor = std::max(o_.h_min, 16.0 * std::numeric_limits<double>::epsilon() * std::max(1.0, std::fabs(t_)));
      if (h < h_floor && (!last || rhs_failures > 0))
        return fail(rhs_failures > 0 ? Status::RhsFailed : Status::StepTooSmall,
                    rhs_failures > 0 ? "the right-hand side failed (" + rhs_status_meaning(last_status) + ") at t = " +
                                           format_number(t_) + " for every step down to " + format_number(h)
                                     : "step size " + format_number(h) + " at t = " + format_number(t_) +
                                           " is below the smallest allowed (" + format_number(h_floor) + ")");
      ++stats_.steps;
      double err = 0.0;
      const int s = attempt(h, err);
      if (s != 0) {  // a stage failed: retry smaller
        ++stats_.rejected;
        ++rhs_failures;
        last_status = s;
        h_ = h / 4.0;
        rejected_last_ = true;
        continue;
      }
      if (!(err <= 1.0)) {  // rejected (also when err is NaN)
        ++stats_.rejected;
        const double shrink = std::isfinite(err) ? std::max(c_.fac_min, c_.safety * std::pow(err, -1.0 / c_.order)) : 0.25;
        h_ = h * shrink;
        rejected_last_ = true;
        continue;
      }
      // Accepted.
      ++stats_.accepted;
      if (finish(h) != 0) return fail(Status::RhsFailed, "at the end of a step from t = " + format_number(t_));
      h_last_ = h;
      t_begin_ = t_;
      t_ = last ? t_stop : t_ + h;
      x_old_.swap(x_);
      x_ = x_new_;
      f_old_.swap(f0_);
      f0_ = f_new_;
      stepped_ = true;
      double fac = c_.safety / (err > 0.0 ? std::pow(err, 1.0 / c_.order - c_.beta * 0.75) : 0.0);
      if (c_.beta > 0.0) fac *= std::pow(err_old_, c_.beta);
      if (!std::isfinite(fac) || err == 0.0) fac = c_.fac_max;
      fac = std::clamp(fac, c_.fac_min, c_.fac_max);
      if (rejected_last_) fac = std::min(fac, 1.0);
      h_ = h * fac;
      err_old_ = std::max(err, 1e-4);
      rejected_last_ = false;
      return Status::Ok;
    }
  }

  double t() const override { return t_; }
  const std::vector<double>& x() const override { return x_; }
  double t_begin() const override { return t_begin_; }
  void interpolate(double t, std::vector<double>& out) const override {
    out.resize(n_);
    if (!stepped_ || h_last_ <= 0.0) {
      out = x_;
      return;
    }
    dense(std::clamp((t - t_begin_) / h_last_, 0.0, 1.0), out);
  }
  const StepperStats& stats() const override { return stats_; }
  std::string message() const override { return message_; }
  /// The step the controller proposes next.
  double next_step() const { return h_; }

 protected:
  /// One attempted step of size h from (t_, x_) with f0_ = f(t_, x_): fills x_new_ and
  /// sets err (the weighted norm); returns a failed rhs status or 0.
  virtual int attempt(double h, double& err) = 0;
  /// After acceptance: f_new_ = f(t_ + h, x_new_) (unless the method already has it) and
  /// the dense-output coefficients. Called while x_, f0_ still hold the step's start.
  virtual int finish(double h) = 0;
  /// The state at theta in [0, 1] of the last accepted step (t_begin_ + theta h_last_).
  virtual void dense(double theta, std::vector<double>& out) const = 0;

  /// The rhs, counted; false when it failed (status kept for the message).
  bool eval(double t, const double* x, double* xdot) {
    ++stats_.rhs_evals;
    status_ = f_(t, x, xdot);
    return status_ == 0;
  }
  int eval_status(double t, const double* x, double* xdot) { return eval(t, x, xdot) ? 0 : status_; }

  /// The weighted RMS norm of e (an error of the step x_ -> x_new_).
  double error_norm(const std::vector<double>& e) const {
    double s = 0.0;
    for (std::size_t i = 0; i < n_; ++i) {
      const double sk = o_.atol + o_.rtol * std::max(std::fabs(x_[i]), std::fabs(x_new_[i]));
      s += (e[i] / sk) * (e[i] / sk);
    }
    return n_ > 0 ? std::sqrt(s / static_cast<double>(n_)) : 0.0;
  }
  double scale(std::size_t i) const { return o_.atol + o_.rtol * std::max(std::fabs(x_[i]), std::fabs(x_new_[i])); }

  Rhs f_;
  std::size_t n_;
  StepperOptions o_;
  ControllerSettings c_;
  double t_ = 0.0, t_begin_ = 0.0, h_ = 0.0, h_last_ = 0.0, err_old_ = 1e-4;
  std::vector<double> x_, f0_, x_new_, f_new_, x_old_, f_old_;  // x_old_, f_old_: start of the last step
  StepperStats stats_;
  int status_ = 0;

 private:
  /// Hairer's starting step: from |x|, |f| and a trial Euler step's change of f.
  double initial_step() {
    double d0 = 0.0, d1 = 0.0;
    std::vector<double> sk(n_);
    for (std::size_t i = 0; i < n_; ++i) {
      sk[i] = o_.atol + o_.rtol * std::fabs(x_[i]);
      d0 += (x_[i] / sk[i]) * (x_[i] / sk[i]);
      d1 += (f0_[i] / sk[i]) * (f0_[i] / sk[i]);
    }
    const double nn = std::max<double>(1.0, static_cast<double>(n_));
    d0 = std::sqrt(d0 / nn);
    d1 = std::sqrt(d1 / nn);
    double h0 = (d0 < 1e-5 || d1 < 1e-5) ? 1e-6 : 0.01 * d0 / d1;
    if (o_.h_max > 0.0) h0 = std::min(h0, o_.h_max);
    std::vector<double> x1(n_), f1(n_);
    for (std::size_t i = 0; i < n_; ++i) x1[i] = x_[i] + h0 * f0_[i];
    if (!eval(t_ + h0, x1.data(), f1.data())) return h0 * 1e-3;  // a bad trial point: start small, step() retries
    double d2 = 0.0;
    for (std::size_t i = 0; i < n_; ++i) d2 += ((f1[i] - f0_[i]) / sk[i]) * ((f1[i] - f0_[i]) / sk[i]);
    d2 = std::sqrt(d2 / nn) / h0;
    const double dm = std::max(d1, d2);
    const double h1 = dm <= 1e-15 ? std::max(1e-6, h0 * 1e-3) : std::pow(0.01 / dm, 1.0 / c_.order);
    double h = std::min(100.0 * h0, h1);
    if (o_.h_max > 0.0) h = std::min(h, o_.h_max);
    return h;
  }

  Status fail(Status s, const std::string& what) {
    if (s == Status::RhsFailed && what.rfind("the right-hand side", 0) != 0)
      message_ = name() + ": the right-hand side failed (" + rhs_status_meaning(status_) + ") " + what +
                 (what.find("t =") == std::string::npos ? " at t = " + format_number(t_) : "");
    else
      message_ = name() + ": " + what;
    return s;
  }

  std::string message_;
  bool started_ = false, stepped_ = false, rejected_last_ = false;
};

}  // namespace mbsc::runtime
