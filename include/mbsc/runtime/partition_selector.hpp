// SPDX-License-Identifier: GPL-2.0-or-later WITH mbsc-runtime-exception
// (see LICENSE: this header may be included in applications under any terms)
#pragma once
/// Run-time re-selection of the independent set (docs/formulation.md, "Re-selecting the
/// independent set"). A model with `alternative` statements is generated with one rhs per
/// partition (independent set) and, for each, a conditioning report: the smallest
/// reciprocal condition number of the blocks that partition solves. The selector keeps
/// one partition active and, between integration steps, switches to the best-conditioned
/// one when the active one degrades - which is how a linkage runs through the toggle
/// positions where any single choice of independent speeds fails. Header-only, standard
/// library only.
///
///   using namespace mbsc_gen::four_bar_toggle;
///   mbsc::runtime::PartitionSelector sel({kNpartitions, &rhs_partition, &conditioning_partition});
///   sel.update(t, x, u, p);                 // before each step
///   sel.rhs(t, x, u, p, xdot);              // inside the step
#include <vector>

namespace mbsc::runtime {

/// What a generated model offers for re-selection (kNpartitions, rhs_partition,
/// conditioning_partition of its namespace).
struct PartitionFunctions {
  using Fn = int (*)(int, double, const double*, const double*, const double*, double*);
  int count = 1;
  Fn rhs = nullptr;
  Fn conditioning = nullptr;
};

struct SelectorSettings {
  /// The active partition is re-examined when its reciprocal condition number falls
  /// below this; rounding errors in the rhs grow like eps / rcond.
  double switch_below = 1e-2;
  /// ...and replaced only by a partition at least this much better conditioned
  /// (hysteresis: no chattering between two partitions of similar quality).
  double gain = 4.0;
};

class PartitionSelector {
 public:
  explicit PartitionSelector(PartitionFunctions f, SelectorSettings s = {}) : f_(f), s_(s) {}

  /// Checks the active partition at (t, x) and switches when it has degraded. Returns 0,
  /// or 1 when every partition is singular here (e.g. a rank drop of the constraints:
  /// no choice of independent speeds helps).
  int update(double t, const double* x, const double* u, const double* p) {
    rcond_ = condition(active_, t, x, u, p);
    if (rcond_ >= s_.switch_below) return 0;
    int best = active_;
    double best_rcond = rcond_;
    for (int k = 0; k < f_.count; ++k) {
      if (k == active_) continue;
      const double r = condition(k, t, x, u, p);
      if (r > best_rcond) {
        best = k;
        best_rcond = r;
      }
    }
    if (best != active_ && best_rcond >= s_.gain * rcond_) {
      active_ = best;
      rcond_ = best_rcond;
      ++switches_;
      history_.push_back({t, best});
    }
    return rcond_ > 0.0 ? 0 : 1;
  }

  /// The state derivative with the active partition.
  int rhs(double t, const double* x, const double* u, const double* p, double* xdot) const {
    return f_.rhs(active_, t, x, u, p, xdot);
  }

  int active() const { return active_; }
  /// Makes partition k active (a restored snapshot's); out of range is ignored.
  void set_active(int k) {
    if (k >= 0 && k < f_.count) active_ = k;
  }
  /// The active partition's reciprocal condition number at the last update.
  double rcond() const { return rcond_; }
  int switches() const { return switches_; }
  struct Switch {
    double t;
    int to;
  };
  const std::vector<Switch>& history() const { return history_; }

 private:
  double condition(int k, double t, const double* x, const double* u, const double* p) const {
    double r = 0.0;
    return f_.conditioning(k, t, x, u, p, &r) == 0 ? r : 0.0;
  }

  PartitionFunctions f_;
  SelectorSettings s_;
  int active_ = 0;
  double rcond_ = 1.0;
  int switches_ = 0;
  std::vector<Switch> history_;
};

}  // namespace mbsc::runtime
