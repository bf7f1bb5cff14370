// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// A time budget for one fuzz input, enforced at the compiler's checkpoints as the
// command line's WorkMonitor does (but without its watcher thread: a single call that
// never returns to a checkpoint shows up as a libFuzzer timeout, which is a finding).
#include <chrono>

#include "mbsc/diag/activity.hpp"

namespace mbsc_fuzz {

class Budget : public mbsc::ActivityWatcher {
 public:
  explicit Budget(double seconds) : seconds_(seconds), start_(std::chrono::steady_clock::now()) {
    mbsc::set_activity_watcher(this);
  }
  ~Budget() override { mbsc::set_activity_watcher(nullptr); }
  Budget(const Budget&) = delete;
  Budget& operator=(const Budget&) = delete;

  void on_checkpoint(const mbsc::Activity& a) override {
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    if (elapsed > seconds_) throw mbsc::BudgetExceeded{a.pos, "fuzz budget"};
  }

 private:
  double seconds_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace mbsc_fuzz
