// SPDX-License-Identifier: GPL-2.0-or-later WITH mbsc-runtime-exception
// (see LICENSE: this header may be included in applications under any terms)
#pragma once
/// Crossing an instant where the constraints lose rank (a parallelogram chain's flat
/// pose) without evaluating the rhs near it (docs/formulation.md, "Rank loss: continuing
/// on the branch"). The motion on the branch is smooth through such a pose, but every
/// evaluation near it is ill-conditioned: an adaptive method at a tight tolerance meets
/// amplified residuals in its stages, rejects, shrinks its step and crawls. So the
/// simulation loop (simulate.hpp), when BranchContinuation is on, hands each accepted
/// state to a SingularCrossing, which
///   1. watches the relative conditioning along the run; when it falls below `approach`
///      times the continuation's near threshold and keeps falling, predicts the crossing
///      time t* from its last two values (it falls like |t - t*|^p, p = 1 for the
///      complement form's blocks and 2 for the multipliers form's Schur complement), and
///      from then on lets the stepper go at most half the way to t* per step, so that
///      the states it accepts are spaced like the jump ahead is long;
///   2. after each such step, picks `nodes` accepted states back from the last one, each
///      at least half the distance d = t* - t before the next, and extrapolates the
///      Hermite polynomial through them (values and rates, degree 2 nodes - 1) to
///      t+ = t* + d, as far past the pose as the last state is before it: first from the
///      states as accepted (cheap, to skip tries whose polynomial error is plainly too
///      large), then from the states projected onto the manifold to rounding with the
///      rhs evaluated there;
///   3. projects that extrapolation and the one without the oldest node (two degrees
///      lower) onto the manifold and compares them in the independent speeds and their
///      coordinates; where they agree within `accept` times the run's tolerances (no
///      tighter than 1e-11: the noise of the nodes' rates near the pose) and the state at
///      t+ is as well conditioned as where the jump began, the loop restarts its stepper
///      at t+ (the samples in between come from the polynomial).
/// Otherwise nothing happens and the run steps on (through the continuation's projected
/// and bridged evaluations), to try again after the next step.
///
/// The rates come from the model's rhs, so the extrapolation asks nothing of the model's
/// form, and it holds for any smooth motion: a run that turns back before the pose is
/// extrapolated correctly too (and its error estimate says when the nodes are too sparse).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <deque>
#include <vector>

#include "mbsc/runtime/branch_continuation.hpp"
#include "mbsc/runtime/hermite_polynomial.hpp"

namespace mbsc::runtime {

struct CrossingSettings {
  int nodes = 6;          // accepted states the polynomial goes through (degree 2 nodes - 1)
  double approach = 20.0;  // times the continuation's near threshold: where a crossing is planned
  double rtol = 1e-8;     // the run's tolerances, for the extrapolation's error estimate
  double atol = 1e-10;
  /// The largest error estimate accepted, in units of the tolerances. Not 1: near the pose
  /// the velocity projection leaves a speed along the other branch's tangent of up to
  /// its tolerance over the smallest singular value (a few atol at the first tries).
  double accept = 10.0;
};

class SingularCrossing {
 public:
  /// rhs: the model's rhs as the run evaluates it (inputs at t included).
  /// watched: the state entries the error estimate reads (the independent speeds and
  /// their coordinates; empty: all).
  SingularCrossing(BranchContinuation& bc, Rhs rhs, CrossingSettings s = {}, std::vector<int> watched = {})
      : bc_(bc), rhs_(std::move(rhs)), s_(s), watched_(std::move(watched)) {
    s_.nodes = std::clamp(s_.nodes, 2, static_cast<int>(kHistory));
  }

  /// Drops the states recorded (after the run's state jumped, e.g. across a pose).
  void forget() {
    history_.clear();
    last_rc_ = -1.0;
    limit_ = 0.0;
  }

  /// An accepted state; true when it plans a crossing (then call `cross`).
  bool accepted(double t, const std::vector<double>& x) {
    history_.push_back(Node{t, x, {}, {}, {}});
    while (history_.size() > kHistory) history_.pop_front();
    const double rc = bc_.relative_conditioning(t, x.data());
    const double before = last_rc_, t_before = last_t_;
    last_rc_ = rc;
    last_t_ = t;
    planned_ = false;
    limit_ = 0.0;
    if (!(before > 0.0) || !(rc > 0.0) || !(rc < before) || !(rc < s_.approach * bc_.near_threshold())) {
      failed_tries_ = 0;  // away from a pose (or leaving one): the next approach tries afresh
      return false;
    }
    // A crossing that keeps failing (a model whose states do not project to rounding)
    // stops limiting the steps: the continuation's evaluations carry the run on.
    if (failed_tries_ >= kMaxTries) return false;
    // rc ~ |t* - t|^p: (d + dt) / d = (before / rc)^(1/p).
    const double ratio = std::pow(before / rc, 1.0 / bc_.conditioning_power());
    const double d = (t - t_before) / (ratio - 1.0);
    if (!(d > 0.0) || !std::isfinite(d)) return false;
    t_star_ = t + d;
    limit_ = 0.5 * d;  // the next steps at most half the way: nodes as dense as the jump is long
    planned_ = true;
    return true;
  }

  /// How far the next step may go: to t_end, or while a crossing is planned half the way
  /// to the pose, so that the states the polynomial goes through are spaced like the jump.
  double step_stop(double t, double t_end) const { return limit_ > 0.0 ? std::min(t_end, t + limit_) : t_end; }

  /// Extrapolates across the pose planned by `accepted`, to t+ = min(2 t* - t, t_end): true
  /// with the projected state there in x_plus (the loop then restarts at t_plus()).
  bool cross(double t_end, std::vector<double>& x_plus) {
    if (!planned_) return false;
    planned_ = false;
    ++failed_tries_;  // until it succeeds below
    const double t_last = history_.back().t, d = t_star_ - t_last;
    t_plus_ = std::min(t_star_ + d, t_end);
    if (!(t_plus_ > t_last)) return false;
    // The nodes: the last state and earlier ones each at least d/2 before the one after
    // (nodes much closer than the jump is long would amplify their rounding), oldest first.
    std::vector<Node*> picked = {&history_.back()};
    for (auto it = history_.rbegin(); it != history_.rend() && static_cast<int>(picked.size()) < s_.nodes; ++it)
      if (picked.back()->t - it->t >= 0.5 * d) picked.push_back(&*it);
    if (static_cast<int>(picked.size()) < s_.nodes) return false;
    std::reverse(picked.begin(), picked.end());
    // First a cheap look, at the nodes as accepted: while the jump is long the polynomial's
    // own error dominates, and the projections below would be spent for nothing.
    std::vector<double> low;
    if (!extrapolate(picked, /*on_manifold=*/false, x_plus, low)) return false;
    if (!(estimate(x_plus, low, kRawFloor) <= 10.0 * s_.accept)) return false;
    // Then from the nodes on the manifold to rounding, both results projected too, and
    // compared in the independent speeds and their coordinates, which fix the state there:
    // near the pose the rest carry what the velocity projection cannot resolve along the
    // other branch's tangent (a coupler's rate, 0 on the branch, at 1e-10 after
    // projecting to 1e-15), not the jump's error.
    if (!extrapolate(picked, /*on_manifold=*/true, x_plus, low)) return false;
    if (bc_.project_tight(t_plus_, x_plus.data()) != 0 || bc_.project_tight(t_plus_, low.data()) != 0) return false;
    const double err = estimate(x_plus, low);
    if (!(estimate(x_plus, low, kProjectedFloor) <= s_.accept)) return false;
    // Past the pose, as conditioned as where the jump began (a prediction far off leaves
    // the state nearer the pose: then the run steps on).
    const double rc = bc_.relative_conditioning(t_plus_, x_plus.data());
    if (!(rc >= 0.25 * last_rc_)) return false;
    for (double v : x_plus)
      if (!std::isfinite(v)) return false;
    error_estimate_ = std::max(error_estimate_, err);
    ++crossings_;
    forget();
    failed_tries_ = 0;
    return true;
  }

  double t_plus() const { return t_plus_; }
  /// The polynomial of the last crossing, for the samples between its ends.
  void interpolate(double t, std::vector<double>& out) const { poly_.evaluate(t, out); }
  long crossings() const { return crossings_; }
  /// The largest error estimate of an accepted crossing, in units of the tolerances.
  double error_estimate() const { return error_estimate_; }

 private:
  struct Node {
    double t;
    std::vector<double> x;
    // Filled when first used: the rate at x, and x projected to rounding with its rate.
    std::vector<double> rate, on_manifold, rate_on_manifold;
  };

  /// The Hermite polynomial through the nodes (as accepted, or projected) into poly_, and
  /// its value at t+ with that of the one without the oldest node (two degrees lower).
  bool extrapolate(const std::vector<Node*>& picked, bool on_manifold, std::vector<double>& high, std::vector<double>& low) {
    std::vector<double> ts;
    std::vector<std::vector<double>> xs, fs;
    for (Node* n : picked) {
      if (on_manifold && n->on_manifold.empty()) {
        std::vector<double> y = n->x, f(y.size());
        if (bc_.project_tight(n->t, y.data()) != 0 || rhs_(n->t, y.data(), f.data()) != 0) return false;
        n->on_manifold = std::move(y);
        n->rate_on_manifold = std::move(f);
      }
      if (!on_manifold && n->rate.empty()) {
        std::vector<double> f(n->x.size());
        if (rhs_(n->t, n->x.data(), f.data()) != 0) return false;
        n->rate = std::move(f);
      }
      ts.push_back(n->t);
      xs.push_back(on_manifold ? n->on_manifold : n->x);
      fs.push_back(on_manifold ? n->rate_on_manifold : n->rate);
    }
    poly_ = HermitePolynomial(ts, xs, fs);
    const HermitePolynomial lower(std::vector<double>(ts.begin() + 1, ts.end()),
                                  std::vector<std::vector<double>>(xs.begin() + 1, xs.end()),
                                  std::vector<std::vector<double>>(fs.begin() + 1, fs.end()));
    poly_.evaluate(t_plus_, high);
    lower.evaluate(t_plus_, low);
    return true;
  }

  /// The largest difference of the watched entries, in units of the tolerances (or of
  /// `floor` where that is larger).
  double estimate(const std::vector<double>& high, const std::vector<double>& low, double floor = 0.0) const {
    const double atol = std::max(s_.atol, floor), rtol = std::max(s_.rtol, floor);
    double err = 0.0;
    auto weigh = [&](std::size_t i) {
      const double e = std::fabs(high[i] - low[i]) / (atol + rtol * std::fabs(high[i]));
      if (!(e <= err)) err = e;  // a NaN wins
    };
    if (watched_.empty())
      for (std::size_t i = 0; i < high.size(); ++i) weigh(i);
    for (int i : watched_) weigh(static_cast<std::size_t>(i));
    return err;
  }
  BranchContinuation& bc_;
  Rhs rhs_;
  CrossingSettings s_;
  std::vector<int> watched_;
  static constexpr std::size_t kHistory = 64;  // accepted states kept to pick the nodes from
  static constexpr int kMaxTries = 24;          // failed crossings of one approach before giving up on it
  int failed_tries_ = 0;
  // The first look, from the nodes as accepted, judges at tolerances no tighter than this:
  // their residuals, amplified near the pose, leave noise of about 1e-10 in the rates.
  static constexpr double kRawFloor = 1e-9;
  // And the jump itself no tighter than this: from projected nodes the noise is about
  // 1e-11 (measured on the 40-window chain); a run at tighter tolerances is told the
  // estimate in units of its own (SimulationResult::crossing_error).
  static constexpr double kProjectedFloor = 1e-11;
  std::deque<Node> history_;
  double last_rc_ = -1.0, last_t_ = 0.0, limit_ = 0.0;
  bool planned_ = false;
  double t_star_ = 0.0, t_plus_ = 0.0;
  HermitePolynomial poly_;
  long crossings_ = 0;
  double error_estimate_ = 0.0;
};

}  // namespace mbsc::runtime
