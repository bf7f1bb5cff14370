// SPDX-License-Identifier: GPL-2.0-or-later
#include "mbsc/diag/activity.hpp"

#include <atomic>

namespace mbsc {

namespace {
std::atomic<ActivityWatcher*> g_watcher{nullptr};
}  // namespace

ActivityWatcher* set_activity_watcher(ActivityWatcher* w) { return g_watcher.exchange(w); }

void checkpoint(const char* stage, const std::string& element, const SourcePos& pos, std::size_t done,
                std::size_t total) {
  ActivityWatcher* w = g_watcher.load(std::memory_order_acquire);
  if (!w) return;
  w->on_checkpoint(Activity{stage, element, pos, done, total});
}

}  // namespace mbsc
