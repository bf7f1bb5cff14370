// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// What the compiler is working on right now. Long stages call checkpoint() once per
/// element (a subsystem, a function, a matrix); a watcher installed by the command line
/// (driver/work_monitor.hpp) shows it as progress and stops the work when the budget of
/// time runs out, naming the element. Without a watcher a checkpoint costs one atomic load.
#include <cstddef>
#include <string>

#include "mbsc/diag/diagnostics.hpp"

namespace mbsc {

/// One checkpoint: `done` of `total` elements of `stage` ("deriving"), now at `element`
/// ("subsystem 'arm.link3'") declared at `pos`.
struct Activity {
  std::string stage;
  std::string element;
  SourcePos pos;
  std::size_t done = 0;
  std::size_t total = 0;
};

/// Thrown by checkpoint() when the budget is spent: `message` says which budget and
/// what was being worked on, `pos` where that element is declared. Deliberately not a
/// std::exception, so that the stages' own handlers (which turn GiNaC's exceptions into
/// diagnostics) let it through to the command, which reports it and exits with 1.
struct BudgetExceeded {
  SourcePos pos;
  std::string message;
};

/// Receives checkpoints (one at a time: installed by the command line, not by a library user).
class ActivityWatcher {
 public:
  virtual ~ActivityWatcher() = default;
  /// Records the activity; throws BudgetExceeded when the budget is spent.
  virtual void on_checkpoint(const Activity& a) = 0;
};

/// Installs `w` (nullptr: none). Returns the previous watcher.
ActivityWatcher* set_activity_watcher(ActivityWatcher* w);

/// Reports the start of work on an element. Throws BudgetExceeded past the budget.
void checkpoint(const char* stage, const std::string& element, const SourcePos& pos, std::size_t done,
                std::size_t total);

}  // namespace mbsc
