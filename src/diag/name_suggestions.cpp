// SPDX-License-Identifier: GPL-2.0-or-later
#include "mbsc/diag/name_suggestions.hpp"

#include <algorithm>

namespace mbsc {

namespace {

/// The edit distance, or any value above `limit` as soon as every entry of a row of the
/// table is above it (the distance cannot come back down): a long list of candidates
/// costs little more than their first few characters each.
std::size_t bounded_distance(const std::string& a, const std::string& b, std::size_t limit) {
  // Optimal string alignment: the Levenshtein table plus a swap of neighbours, kept in
  // three rows (the swap looks two rows back).
  const std::size_t n = a.size(), m = b.size();
  std::vector<std::size_t> two_back(m + 1), prev(m + 1), cur(m + 1);
  for (std::size_t j = 0; j <= m; ++j) prev[j] = j;
  for (std::size_t i = 1; i <= n; ++i) {
    cur[0] = i;
    std::size_t row_min = cur[0];
    for (std::size_t j = 1; j <= m; ++j) {
      const std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) cur[j] = std::min(cur[j], two_back[j - 2] + 1);
      row_min = std::min(row_min, cur[j]);
    }
    // A swap reaches back two rows, so stop only when this row and the one before it are both over.
    if (row_min > limit && i > 1 && *std::min_element(prev.begin(), prev.end()) > limit) return limit + 1;
    two_back.swap(prev);
    prev.swap(cur);
  }
  return prev[m];
}

}  // namespace

std::size_t edit_distance(const std::string& a, const std::string& b) {
  return bounded_distance(a, b, std::max(a.size(), b.size()));
}

std::size_t typo_distance_limit(std::size_t length) {
  const std::size_t limit = length <= 4 ? 1 : length <= 8 ? 2 : 3;
  return std::min(limit, length == 0 ? 0 : length - 1);
}

std::optional<std::string> closest_name(const std::string& written, const std::vector<std::string>& candidates) {
  const std::size_t limit = typo_distance_limit(written.size());
  std::optional<std::string> best;
  std::size_t best_distance = limit + 1;
  for (const auto& c : candidates) {
    if (c == written) continue;
    // Lengths alone bound the distance from below: skip the table when they differ too much.
    const std::size_t gap = c.size() > written.size() ? c.size() - written.size() : written.size() - c.size();
    if (gap >= best_distance) continue;
    const std::size_t d = bounded_distance(written, c, best_distance - 1);
    if (d < best_distance) {
      best_distance = d;
      best = c;
    }
  }
  return best;
}

std::string did_you_mean(const std::string& written, const std::vector<std::string>& candidates) {
  const auto best = closest_name(written, candidates);
  return best ? " (did you mean '" + *best + "'?)" : std::string();
}

std::string list_names(const std::vector<std::string>& names) {
  std::string out;
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (i > 0) out += i + 1 == names.size() ? " and " : ", ";
    out += names[i];
  }
  return out;
}

}  // namespace mbsc
