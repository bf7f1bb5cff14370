// SPDX-License-Identifier: GPL-2.0-or-later WITH mbsc-runtime-exception
// (see LICENSE: this header may be included in applications under any terms)
#pragma once
/// Classical RK4 with a fixed step (StepperOptions::h) behind the Stepper interface, for
/// the simulation loop and for speed-versus-error comparisons at a known cost (four rhs
/// evaluations per step: the derivative at the end of a step is the next step's first
/// stage). Output between steps is the cubic Hermite interpolant through both ends'
/// states and derivatives (3rd order, continuous with continuous first derivative). No
/// error control: the step is the user's choice; only the last step before t_stop is
/// shortened to land on it.
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "mbsc/runtime/adaptive_rk.hpp"  // rhs_status_meaning, format_number

namespace mbsc::runtime {

class Rk4Stepper : public Stepper {
 public:
  Rk4Stepper(Rhs f, int n, StepperOptions o = {})
      : f_(std::move(f)), n_(static_cast<std::size_t>(n)), o_(o), k1_(n_), k2_(n_), k3_(n_), k4_(n_), y_(n_) {}

  Status reset(double t, const std::vector<double>& x) override {
    if (!(o_.h > 0.0)) {
      message_ = "rk4: the fixed step h must be positive (got " + format_number(o_.h) + ")";
      return Status::SolverFailed;
    }
    t_ = t_begin_ = t;
    x_ = x;
    x_.resize(n_);
    x0_ = x_;
    f_end_.assign(n_, 0.0);
    stepped_ = false;
    if (!eval(t_, x_.data(), k1_.data())) return failed("at the start, t = " + format_number(t_));
    f_begin_ = k1_;
    f_end_ = k1_;
    return Status::Ok;
  }

  Status step(double t_stop) override {
    if (!(t_stop > t_)) return Status::Ok;
    if (stats_.steps >= o_.max_steps) {
      message_ = "rk4: more than " + std::to_string(o_.max_steps) + " steps (max_steps) at t = " + format_number(t_);
      return Status::TooManySteps;
    }
    double h = o_.h;
    const bool last = t_ + h * (1.0 + 1e-9) >= t_stop;
    if (last) h = t_stop - t_;
    ++stats_.steps;
    const double t = t_;
    for (std::size_t i = 0; i < n_; ++i) y_[i] = x_[i] + 0.5 * h * k1_[i];
    if (!eval(t + 0.5 * h, y_.data(), k2_.data())) return failed("in a step from t = " + format_number(t));
    for (std::size_t i = 0; i < n_; ++i) y_[i] = x_[i] + 0.5 * h * k2_[i];
    if (!eval(t + 0.5 * h, y_.data(), k3_.data())) return failed("in a step from t = " + format_number(t));
    for (std::size_t i = 0; i < n_; ++i) y_[i] = x_[i] + h * k3_[i];
    if (!eval(t + h, y_.data(), k4_.data())) return failed("in a step from t = " + format_number(t));
    for (std::size_t i = 0; i < n_; ++i) y_[i] = x_[i] + h / 6.0 * (k1_[i] + 2.0 * k2_[i] + 2.0 * k3_[i] + k4_[i]);
    const double t_new = last ? t_stop : t + h;
    std::vector<double> f_new(n_);
    if (!eval(t_new, y_.data(), f_new.data())) return failed("at the end of a step, t = " + format_number(t_new));
    ++stats_.accepted;
    x0_ = x_;
    f_begin_ = k1_;
    x_ = y_;
    k1_ = f_new;
    f_end_ = f_new;
    t_begin_ = t;
    t_ = t_new;
    stepped_ = true;
    return Status::Ok;
  }

  double t() const override { return t_; }
  const std::vector<double>& x() const override { return x_; }
  double t_begin() const override { return t_begin_; }
  void interpolate(double t, std::vector<double>& out) const override {
    out.resize(n_);
    const double h = t_ - t_begin_;
    if (!stepped_ || h <= 0.0) {
      out = x_;
      return;
    }
    // Cubic Hermite basis on theta in [0, 1].
    const double s = std::min(1.0, std::max(0.0, (t - t_begin_) / h)), s2 = s * s, s3 = s2 * s;
    const double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2, h11 = s3 - s2;
    for (std::size_t i = 0; i < n_; ++i)
      out[i] = h00 * x0_[i] + h10 * h * f_begin_[i] + h01 * x_[i] + h11 * h * f_end_[i];
  }
  const StepperStats& stats() const override { return stats_; }
  std::string message() const override { return message_; }
  std::string name() const override { return "rk4"; }

 private:
  bool eval(double t, const double* x, double* xdot) {
    ++stats_.rhs_evals;
    status_ = f_(t, x, xdot);
    return status_ == 0;
  }
  Status failed(const std::string& where) {
    message_ = "rk4: the right-hand side failed (" + rhs_status_meaning(status_) + ") " + where;
    return Status::RhsFailed;
  }

  Rhs f_;
  std::size_t n_;
  StepperOptions o_;
  double t_ = 0.0, t_begin_ = 0.0;
  std::vector<double> x_, x0_, f_begin_, f_end_, k1_, k2_, k3_, k4_, y_;
  StepperStats stats_;
  std::string message_;
  int status_ = 0;
  bool stepped_ = false;
};

}  // namespace mbsc::runtime
