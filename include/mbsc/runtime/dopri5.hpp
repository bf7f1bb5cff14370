// SPDX-License-Identifier: GPL-2.0-or-later WITH mbsc-runtime-exception
// (see LICENSE: this header may be included in applications under any terms)
#pragma once
/// Dormand-Prince 5(4): the explicit Runge-Kutta pair of Dormand and Prince (1980),
/// seven stages with the last one at the new point (first-same-as-last, so six rhs
/// evaluations per accepted step), local extrapolation (the step is advanced with the
/// 5th-order solution, the 4th-order one only estimates the error), and Shampine's
/// 4th-order continuous extension for output between steps. A PI step-size controller
/// (beta = 0.04) keeps the step from oscillating on mildly stiff stretches.
///
///   mbsc::runtime::Dopri5 s(rhs, n, {1e-8, 1e-10});
///   s.reset(0.0, x0);
///   while (s.t() < t_end) if (s.step(t_end) != Stepper::Status::Ok) { ... s.message() ... }
#include <vector>

#include "mbsc/runtime/adaptive_rk.hpp"

namespace mbsc::runtime {

class Dopri5 : public AdaptiveRungeKutta {
 public:
  Dopri5(Rhs f, int n, StepperOptions o = {})
      : AdaptiveRungeKutta(std::move(f), n, o, ControllerSettings{5, 0.04, 0.9, 0.2, 10.0}),
        k2_(n_), k3_(n_), k4_(n_), k5_(n_), k6_(n_), y_(n_), e_(n_), r_(5, std::vector<double>(n_)) {}
  std::string name() const override { return "dopri5"; }

 protected:
  int attempt(double h, double& err) override {
    // Tableau (Dormand & Prince 1980); stage 7 evaluates at the 5th-order result.
    constexpr double c2 = 1.0 / 5, c3 = 3.0 / 10, c4 = 4.0 / 5, c5 = 8.0 / 9;
    constexpr double a21 = 1.0 / 5;
    constexpr double a31 = 3.0 / 40, a32 = 9.0 / 40;
    constexpr double a41 = 44.0 / 45, a42 = -56.0 / 15, a43 = 32.0 / 9;
    constexpr double a51 = 19372.0 / 6561, a52 = -25360.0 / 2187, a53 = 64448.0 / 6561, a54 = -212.0 / 729;
    constexpr double a61 = 9017.0 / 3168, a62 = -355.0 / 33, a63 = 46732.0 / 5247, a64 = 49.0 / 176,
                     a65 = -5103.0 / 18656;
    constexpr double b1 = 35.0 / 384, b3 = 500.0 / 1113, b4 = 125.0 / 192, b5 = -2187.0 / 6784, b6 = 11.0 / 84;
    // 5th minus 4th-order weights: the error estimate.
    constexpr double e1 = 71.0 / 57600, e3 = -71.0 / 16695, e4 = 71.0 / 1920, e5 = -17253.0 / 339200, e6 = 22.0 / 525,
                     e7 = -1.0 / 40;
    const std::vector<double>& x = x_;
    const std::vector<double>& k1 = f0_;
    int s;
    for (std::size_t i = 0; i < n_; ++i) y_[i] = x[i] + h * a21 * k1[i];
    if ((s = eval_status(t_ + c2 * h, y_.data(), k2_.data())) != 0) return s;
    for (std::size_t i = 0; i < n_; ++i) y_[i] = x[i] + h * (a31 * k1[i] + a32 * k2_[i]);
    if ((s = eval_status(t_ + c3 * h, y_.data(), k3_.data())) != 0) return s;
    for (std::size_t i = 0; i < n_; ++i) y_[i] = x[i] + h * (a41 * k1[i] + a42 * k2_[i] + a43 * k3_[i]);
    if ((s = eval_status(t_ + c4 * h, y_.data(), k4_.data())) != 0) return s;
    for (std::size_t i = 0; i < n_; ++i) y_[i] = x[i] + h * (a51 * k1[i] + a52 * k2_[i] + a53 * k3_[i] + a54 * k4_[i]);
    if ((s = eval_status(t_ + c5 * h, y_.data(), k5_.data())) != 0) return s;
    for (std::size_t i = 0; i < n_; ++i)
      y_[i] = x[i] + h * (a61 * k1[i] + a62 * k2_[i] + a63 * k3_[i] + a64 * k4_[i] + a65 * k5_[i]);
    if ((s = eval_status(t_ + h, y_.data(), k6_.data())) != 0) return s;
    for (std::size_t i = 0; i < n_; ++i)
      x_new_[i] = x[i] + h * (b1 * k1[i] + b3 * k3_[i] + b4 * k4_[i] + b5 * k5_[i] + b6 * k6_[i]);
    if ((s = eval_status(t_ + h, x_new_.data(), f_new_.data())) != 0) return s;  // k7, reused as the next k1
    for (std::size_t i = 0; i < n_; ++i)
      e_[i] = h * (e1 * k1[i] + e3 * k3_[i] + e4 * k4_[i] + e5 * k5_[i] + e6 * k6_[i] + e7 * f_new_[i]);
    err = error_norm(e_);
    return 0;
  }

  int finish(double h) override {
    // Shampine's dense output: x(t + theta h) = r0 + theta (r1 + (1-theta) (r2 + theta (r3 + (1-theta) r4))).
    constexpr double d1 = -12715105075.0 / 11282082432, d3 = 87487479700.0 / 32700410799,
                     d4 = -10690763975.0 / 1880347072, d5 = 701980252875.0 / 199316789632,
                     d6 = -1453857185.0 / 822651844, d7 = 69997945.0 / 29380423;
    for (std::size_t i = 0; i < n_; ++i) {
      const double dx = x_new_[i] - x_[i], bspl = h * f0_[i] - dx;
      r_[0][i] = x_[i];
      r_[1][i] = dx;
      r_[2][i] = bspl;
      r_[3][i] = dx - h * f_new_[i] - bspl;
      r_[4][i] = h * (d1 * f0_[i] + d3 * k3_[i] + d4 * k4_[i] + d5 * k5_[i] + d6 * k6_[i] + d7 * f_new_[i]);
    }
    return 0;
  }

  void dense(double th, std::vector<double>& out) const override {
    const double th1 = 1.0 - th;
    for (std::size_t i = 0; i < n_; ++i)
      out[i] = r_[0][i] + th * (r_[1][i] + th1 * (r_[2][i] + th * (r_[3][i] + th1 * r_[4][i])));
  }

 private:
  std::vector<double> k2_, k3_, k4_, k5_, k6_, y_, e_;
  std::vector<std::vector<double>> r_;
};

}  // namespace mbsc::runtime
