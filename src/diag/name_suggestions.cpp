// SPDX-License-Identifier: GPL-2.0-or-later
#include "mbsc/diag/name_suggestions.hpp"

#include <algorithm>

namespace mbsc {

namespace {

/// The edit distance when it is at most `limit`, else limit + 1. Only the band of the
/// table within `limit` of its diagonal is filled (a cell outside it is over the limit
/// anyway), and the work stops once two rows in a row are over the limit (a swap reads
/// two rows back, so nothing later can come back under it): comparing a name with a
/// long list, or two very long names, costs a few cells per character.
std::size_t bounded_distance(const std::string& a, const std::string& b, std::size_t limit) {
  // Optimal string alignment: the Levenshtein table plus a swap of neighbours, kept in
  // three rows, every value saturated at cap.
  const std::size_t n = a.size(), m = b.size(), cap = limit + 1;
  if ((n > m ? n - m : m - n) > limit) return cap;
  std::vector<std::size_t> two_back(m + 1, cap), prev(m + 1, cap), cur(m + 1, cap);
  for (std::size_t j = 0; j <= std::min(m, limit); ++j) prev[j] = j;
  std::size_t prev_min = 0;
  for (std::size_t i = 1; i <= n; ++i) {
    const std::size_t lo = i > limit ? i - limit : 1, hi = std::min(m, i + limit);
    cur[lo - 1] = lo == 1 ? std::min(i, cap) : cap;  // the cells beside the band
    if (hi < m) cur[hi + 1] = cap;
    std::size_t row_min = cur[lo - 1];
    for (std::size_t j = lo; j <= hi; ++j) {
      const std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
      std::size_t v = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) v = std::min(v, two_back[j - 2] + 1);
      cur[j] = std::min(v, cap);
      row_min = std::min(row_min, cur[j]);
    }
    if (row_min >= cap && prev_min >= cap) return cap;
    prev_min = row_min;
    two_back.swap(prev);
    prev.swap(cur);
  }
  return std::min(prev[m], cap);
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
  if (const auto best = closest_name(written, candidates)) return " (did you mean '" + *best + "'?)";
  // A name written without the subsystem it belongs to: "theta" for "load.theta".
  std::vector<std::string> within;
  for (const auto& c : candidates)
    if (!written.empty() && c.size() > written.size() + 1 && c.compare(c.size() - written.size(), written.size(), written) == 0 &&
        c[c.size() - written.size() - 1] == '.')
      within.push_back("'" + c + "'");
  if (within.empty() || within.size() > 6) return "";
  std::string options = within[0];
  for (std::size_t i = 1; i < within.size(); ++i) options += (i + 1 == within.size() ? " or " : ", ") + within[i];
  return " (did you mean " + options + "?)";
}

std::string declared_name(const std::string& written) {
  // name[3] is how a loop's instance is written in the model; the language declares it
  // as name_3 (docs/language.md, "Repeated structure").
  std::string out;
  for (std::size_t i = 0; i < written.size(); ++i) {
    if (written[i] == '[' && i > 0 && written[i - 1] != '.' && written[i - 1] != '[') {
      const std::size_t close = written.find(']', i);
      const std::string index = close == std::string::npos ? "" : written.substr(i + 1, close - i - 1);
      if (!index.empty() && index.find_first_not_of("0123456789") == std::string::npos) {
        out += "_" + index;
        i = close;
        continue;
      }
    }
    out += written[i];
  }
  return out;
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
