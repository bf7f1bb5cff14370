// SPDX-License-Identifier: GPL-2.0-or-later
#include "mbsc/driver/work_monitor.hpp"

#include <fmt/format.h>
#include <poll.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace mbsc::driver {

namespace {

/// Seconds a GiNaC call may run past the time budget before the process is ended.
double grace_seconds(double budget) { return std::max(2.0, 0.1 * budget); }

/// Writes straight to fd 2 (the watcher thread must not share std::cerr's buffer), and
/// only while fd 2 takes it within `wait_ms`: a terminal stopped with Ctrl-S or a pipe
/// nobody reads must not stop the watcher, whose job is to end runaway work.
void write_stderr(const std::string& text, int wait_ms = 0) {
  std::size_t off = 0;
  while (off < text.size()) {
    struct pollfd p {2, POLLOUT, 0};
    if (::poll(&p, 1, wait_ms) != 1 || !(p.revents & POLLOUT)) return;
    const ssize_t n = ::write(2, text.data() + off, text.size() - off);
    if (n <= 0) return;
    off += static_cast<std::size_t>(n);
  }
}

}  // namespace

std::size_t resident_mib() {
  std::FILE* f = std::fopen("/proc/self/statm", "r");
  unsigned long size = 0, resident = 0;
  const int got = f ? std::fscanf(f, "%lu %lu", &size, &resident) : 0;
  if (f) std::fclose(f);
  if (got == 2) {
    const long page = ::sysconf(_SC_PAGESIZE);
    return static_cast<std::size_t>(resident) * static_cast<std::size_t>(page > 0 ? page : 4096) >> 20;
  }
  // No /proc: the peak resident size (never below the current one) keeps the check on.
  struct rusage usage {};
  if (::getrusage(RUSAGE_SELF, &usage) != 0) return 0;
  return static_cast<std::size_t>(usage.ru_maxrss) >> 10;  // KiB on Linux
}

std::size_t default_memory_mib() {
  std::size_t limit = 8192;
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
  std::size_t available = pages > 0 && page > 0 ? (static_cast<std::size_t>(pages) * static_cast<std::size_t>(page)) >> 20 : 0;
  // A container's limit: cgroup v2, else v1 ("max" or a huge number when unlimited).
  for (const char* file : {"/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory/memory.limit_in_bytes"}) {
    std::FILE* f = std::fopen(file, "r");
    if (!f) continue;
    unsigned long long bytes = 0;
    const int got = std::fscanf(f, "%llu", &bytes);
    std::fclose(f);
    if (got == 1 && bytes > 0 && (bytes >> 20) < available) available = static_cast<std::size_t>(bytes >> 20);
    break;
  }
  if (available > 0) limit = std::min(limit, std::max<std::size_t>(available / 4 * 3, 256));
  return limit;
}

WorkMonitor::WorkMonitor(const WorkBudget& budget, ProgressMode mode, std::string what)
    : WorkMonitor(budget, mode, std::move(what), true) {}

WorkMonitor WorkMonitor::whole_command(const WorkBudget& budget) {
  return WorkMonitor(budget, ProgressMode::Never, "the command", false);
}

WorkMonitor::WorkMonitor(const WorkBudget& budget, ProgressMode mode, std::string what, bool checkpoints_stop)
    : budget_(budget),
      what_(std::move(what)),
      checkpoints_stop_(checkpoints_stop),
      show_(mode != ProgressMode::Never && (mode == ProgressMode::Always || ::isatty(2))),
      terminal_(::isatty(2) != 0) {
  current_.stage = "reading";
  current_.element = "the model";
  previous_ = set_activity_watcher(this);
  thread_ = std::thread([this] { watch(); });
}

WorkMonitor::~WorkMonitor() { stop(); }

void WorkMonitor::stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (stopping_) return;
    stopping_ = true;
  }
  set_activity_watcher(previous_);
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
  clear_line();
}

void WorkMonitor::on_checkpoint(const Activity& a) {
  const double elapsed = budget_.elapsed();
  {
    std::lock_guard<std::mutex> lock(mutex_);
    current_ = a;
  }
  if (checkpoints_stop_ && elapsed > budget_.seconds) throw BudgetExceeded{a.pos, budget_message(a, false)};
}

void WorkMonitor::note(const std::string& stage, const std::string& element) {
  std::lock_guard<std::mutex> lock(mutex_);
  current_.stage = stage;
  current_.element = element;
}

std::string WorkMonitor::budget_message(const Activity& a, bool memory) const {
  const std::string where = a.element.empty() ? a.stage : a.stage + " " + a.element;
  if (memory)
    return fmt::format("{} took more than the memory budget of {} MiB while {} (is the model much larger "
                       "than intended? raise the budget with --max-memory MIB)",
                       what_, budget_.memory_mib, where);
  return fmt::format("{} took more than the time budget of {:g} s while {} (is the model much larger "
                     "than intended? raise the budget with --budget SECONDS)",
                     what_, budget_.seconds, where);
}

void WorkMonitor::watch() {
  for (;;) {
    Activity now;
    {
      // The lock only guards current_ and stopping_; nothing is written while holding it,
      // so a checkpoint never waits for stderr.
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait_for(lock, std::chrono::milliseconds(50));
      if (stopping_) return;
      now = current_;
    }
    const double elapsed = budget_.elapsed();
    const bool memory = budget_.memory_mib > 0 && resident_mib() > budget_.memory_mib;
    if (memory || elapsed > budget_.seconds + grace_seconds(budget_.seconds)) {
      // The main thread is inside one long call: end the process from here. No output
      // file exists yet (the command writes only after stopping the monitor).
      clear_line();
      write_stderr(printable(to_string(now.pos)) + ": error: " + printable(budget_message(now, memory)) + "\n", 500);
      ::_exit(1);
    }
    if (show_ && elapsed >= 1.0) draw(now, elapsed);
  }
}

void WorkMonitor::draw(const Activity& a, double elapsed) {
  // On a terminal: one line redrawn in place, 20 times a second at most. Otherwise
  // (--progress into a file or pipe): a line per second.
  if (!terminal_ && elapsed - last_drawn_ < 1.0) return;
  last_drawn_ = elapsed;
  std::string bar;
  if (a.total > 0) {
    const std::size_t width = 20, filled = std::min(width, a.done * width / a.total);
    bar = fmt::format(" [{}{}] {}/{}", std::string(filled, '#'), std::string(width - filled, '.'), a.done, a.total);
  }
  std::string line = fmt::format("mbsc: {:5.1f} s {}{} {}", elapsed, a.stage, bar, a.element);
  if (line.size() > 100) line = line.substr(0, 97) + "...";
  write_stderr(terminal_ ? "\r\x1b[K" + line : line + "\n");
  line_drawn_ = terminal_;
}

void WorkMonitor::clear_line() {
  if (!line_drawn_) return;
  write_stderr("\r\x1b[K");
  line_drawn_ = false;
}

}  // namespace mbsc::driver
