// SPDX-License-Identifier: GPL-2.0-or-later
// An input read from a CSV column and interpolated in t (include/mbsc/run/input_table.hpp).
#include "mbsc/run/input_table.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "mbsc/diag/diagnostics.hpp"

namespace mbsc::run {

namespace {

// The fields of one CSV line (no quoting: the tables mbsc writes have none), with the
// 1-based column where each starts.
std::vector<std::pair<std::string, int>> fields(const std::string& line) {
  std::vector<std::pair<std::string, int>> out;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    std::string f = line.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    // Surrounding blanks are not part of a name or a number.
    const std::size_t a = f.find_first_not_of(" \t"), b = f.find_last_not_of(" \t");
    out.emplace_back(a == std::string::npos ? "" : f.substr(a, b - a + 1), static_cast<int>(start) + 1);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

}  // namespace

bool InputTable::read(const std::string& name, const std::string& spec, Interpolation how, std::string& error) {
  name_ = name;
  how_ = how;
  // "@FILE:COLUMN": the last ':' splits them when what follows names no folder.
  std::string path = spec.substr(1);
  column_ = name;
  const std::size_t colon = path.rfind(':');
  std::error_code ec;
  if (colon != std::string::npos && path.find('/', colon) == std::string::npos &&
      !std::filesystem::is_regular_file(path, ec)) {  // a file whose name holds ':' is read whole
    column_ = path.substr(colon + 1);
    path = path.substr(0, colon);
  }
  file_ = path;
  const std::string what = fmt::format("--input {}", name);
  if (path.empty()) {
    error = fmt::format("mbsc: error: {}: '@' takes a CSV file: {}=@FILE or {}=@FILE:COLUMN", what, name, name);
    return false;
  }
  if (column_.empty()) {
    error = fmt::format("mbsc: error: {}: no column after ':' in '{}' (write @FILE:COLUMN, or @FILE for the column '{}')", what,
                        spec, name);
    return false;
  }
  std::ifstream in(path);
  if (!in) {
    error = fmt::format("mbsc: error: {}: cannot read the table '{}': {}", what, path, std::strerror(errno));
    return false;
  }
  std::string line;
  if (!std::getline(in, line)) {
    error = fmt::format("{}:1:1: error: the table for {} is empty (it needs a header with 't' and '{}')", path, what,
                        column_);
    return false;
  }
  if (!line.empty() && line.back() == '\r') line.pop_back();
  if (line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);  // a byte-order mark (spreadsheet exports)
  const auto header = fields(line);
  int t_col = -1, v_col = -1;
  for (std::size_t i = 0; i < header.size(); ++i) {
    if (header[i].first == "t" && t_col < 0) t_col = static_cast<int>(i);
    if (header[i].first == column_ && v_col < 0) v_col = static_cast<int>(i);
  }
  if (t_col < 0) {
    error = fmt::format("{}:1:1: error: the table for {} has no column 't' (the times)", path, what);
    return false;
  }
  if (v_col < 0) {
    std::string known;
    for (const auto& h : header)
      if (h.first != "t") known += (known.empty() ? "" : ", ") + h.first;
    error = fmt::format("{}:1:1: error: the table for {} has no column '{}' (its columns: {})", path, what, column_,
                        known.size() > 400 ? known.substr(0, 400) + ", ..." : known);
    return false;
  }
  int line_no = 1;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find_first_not_of(" \t") == std::string::npos) continue;
    const auto row = fields(line);
    if (row.size() != header.size()) {
      error = fmt::format("{}:{}:1: error: the row has {} field(s), the header {}", path, line_no, row.size(),
                          header.size());
      return false;
    }
    double values[2];
    const int cols[2] = {t_col, v_col};
    for (int k = 0; k < 2; ++k) {
      const auto& [text, col] = row[static_cast<std::size_t>(cols[k])];
      char* end = nullptr;
      errno = 0;
      values[k] = std::strtod(text.c_str(), &end);
      // (An underflow to a subnormal number sets ERANGE too; it is a number, and kept.)
      if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(values[k])) {
        error = fmt::format("{}:{}:{}: error: '{}' in column '{}' is not a finite number", printable(path), line_no, col,
                            printable(text.substr(0, 40)), printable(header[static_cast<std::size_t>(cols[k])].first));
        return false;
      }
    }
    if (!t_.empty() && !(values[0] > t_.back())) {
      error = fmt::format("{}:{}:{}: error: the times must increase: t = {} follows t = {}", path, line_no,
                          row[static_cast<std::size_t>(t_col)].second, values[0], t_.back());
      return false;
    }
    t_.push_back(values[0]);
    v_.push_back(values[1]);
  }
  if (t_.size() < 2) {
    error = fmt::format("{}:{}:1: error: the table for {} has {} row(s); interpolation needs at least two", path,
                        line_no, what, t_.size());
    return false;
  }
  if (how_ == Interpolation::Cubic) {
    // Natural cubic spline: second derivatives c_i with c_0 = c_n = 0 from the
    // tridiagonal system h_{i-1} c_{i-1} + 2 (h_{i-1} + h_i) c_i + h_i c_{i+1} = 6 (s_i - s_{i-1}),
    // s_i the slope of interval i (Thomas algorithm, diagonally dominant).
    const std::size_t n = t_.size();
    curvature_.assign(n, 0.0);
    std::vector<double> rhs(n, 0.0), upper(n, 0.0);
    for (std::size_t i = 1; i + 1 < n; ++i) {
      const double h0 = t_[i] - t_[i - 1], h1 = t_[i + 1] - t_[i];
      const double s0 = (v_[i] - v_[i - 1]) / h0, s1 = (v_[i + 1] - v_[i]) / h1;
      const double lower = h0, d = 2 * (h0 + h1) - lower * upper[i - 1];
      upper[i] = h1 / d;
      rhs[i] = (6 * (s1 - s0) - lower * rhs[i - 1]) / d;
    }
    for (std::size_t i = n - 1; i-- > 1;) curvature_[i] = rhs[i] - upper[i] * curvature_[i + 1];
  }
  return true;
}

bool InputTable::covers(double t0, double t1, std::string& error) const {
  const double slack = 1e-9 * std::max(1.0, t_.back() - t_.front());
  if (t_.front() <= t0 + slack && t_.back() >= t1 - slack) return true;
  error = fmt::format("mbsc: error: --input {}: the table '{}' covers t = {} .. {}, and the run needs t = {} .. {} (a table "
                      "input is not extrapolated)",
                      name_, file_, t_.front(), t_.back(), t0, t1);
  return false;
}

double InputTable::at(double t) const {
  if (std::isnan(t)) return NAN;
  if (t <= t_.front()) return v_.front();
  if (t >= t_.back()) return v_.back();
  const std::size_t i = static_cast<std::size_t>(std::upper_bound(t_.begin(), t_.end(), t) - t_.begin()) - 1;
  const double h = t_[i + 1] - t_[i], a = (t_[i + 1] - t) / h, b = (t - t_[i]) / h;
  double v = a * v_[i] + b * v_[i + 1];
  if (how_ == Interpolation::Cubic)
    v += ((a * a * a - a) * curvature_[i] + (b * b * b - b) * curvature_[i + 1]) * h * h / 6;
  return v;
}

}  // namespace mbsc::run
