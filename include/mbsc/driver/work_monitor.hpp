// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// Watches the symbolic work of one command: its time and memory budgets, and a
/// progress line on stderr when it runs long. The stages report what they work on with
/// mbsc::checkpoint (diag/activity.hpp).
///
/// * Time: past `seconds` from the command's start, the next checkpoint throws BudgetExceeded naming the element
///   (the command reports it, exit 1). A single GiNaC call that does not come back to a
///   checkpoint is stopped by the watcher thread a grace period later: it prints the
///   same message and ends the process with exit code 1.
/// * Memory: past `memory_mib` of resident memory the watcher ends the process at once
///   the same way (a runaway expansion can take gigabytes a second).
/// Both happen before any output file is written (the command stops the monitor first),
/// so nothing is ever half-written.
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <mutex>
#include <string>
#include <thread>

#include "mbsc/diag/activity.hpp"

namespace mbsc::driver {

/// The default memory budget: 8192 MiB, or three quarters of the memory this process may
/// use if that is less (the machine's, or its container's cgroup limit), so that the
/// budget, not the kernel's out-of-memory killer, stops a runaway.
std::size_t default_memory_mib();

/// The budget of one command, from its start: the symbolic work, the C++ compiler and
/// the integration all spend the same seconds.
struct WorkBudget {
  double seconds = 300;                         // --budget
  std::size_t memory_mib = default_memory_mib();  // --max-memory
  std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();

  double elapsed() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); }
  double seconds_left() const { return seconds - elapsed(); }
};

enum class ProgressMode {
  Auto,    // a progress line on stderr once the work has run a second, if stderr is a terminal
  Never,   // --quiet
  Always,  // --progress: also when stderr is not a terminal (one line per update)
};

class WorkMonitor : public ActivityWatcher {
 public:
  /// `what` names the work in the budget messages ("the symbolic work"; a command that
  /// also compiles and integrates watches itself as a whole, "the command"). A monitor
  /// made while another is installed takes the checkpoints until it stops, then hands
  /// them back.
  WorkMonitor(const WorkBudget& budget, ProgressMode mode, std::string what = "the symbolic work");

  /// The watch over a whole command (run, inverse, bench, linearize, eig): its thread ends
  /// the process past the memory budget or a grace period past the time budget, whatever
  /// the command is doing (the compiler and the integration stop themselves at the time
  /// budget); its checkpoints only record, never throw. No progress line.
  static WorkMonitor whole_command(const WorkBudget& budget);
  ~WorkMonitor() override;
  WorkMonitor(const WorkMonitor&) = delete;
  WorkMonitor& operator=(const WorkMonitor&) = delete;

  void on_checkpoint(const Activity& a) override;
  /// Records what the work is on now, for the messages, without checking the budget.
  void note(const std::string& stage, const std::string& element);

  /// Stops watching (joins the thread, clears the progress line); idempotent.
  void stop();

 private:
  WorkMonitor(const WorkBudget& budget, ProgressMode mode, std::string what, bool checkpoints_stop);
  void watch();
  std::string budget_message(const Activity& a, bool memory) const;
  void draw(const Activity& a, double elapsed);
  void clear_line();

  WorkBudget budget_;
  std::string what_;
  bool checkpoints_stop_ = true;  // a checkpoint past the time budget throws BudgetExceeded
  ActivityWatcher* previous_ = nullptr;  // the watcher this one stands in for while it runs
  bool show_;       // progress wanted at all
  bool terminal_;   // stderr is a terminal: redraw one line
  std::mutex mutex_;
  std::condition_variable wake_;
  Activity current_;
  bool stopping_ = false;
  bool line_drawn_ = false;
  double last_drawn_ = -1;
  std::thread thread_;
};

/// Resident memory of this process in MiB (0 when unknown).
std::size_t resident_mib();

}  // namespace mbsc::driver
