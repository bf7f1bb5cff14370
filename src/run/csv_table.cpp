// SPDX-License-Identifier: GPL-2.0-or-later
// The CSV of a run (include/mbsc/run/csv_table.hpp).
#include "mbsc/run/csv_table.hpp"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fmt/format.h>

#include "mbsc/diag/diagnostics.hpp"
#include "mbsc/diag/name_suggestions.hpp"

namespace mbsc::run {

bool CsvTable::open(const std::string& path, const std::vector<std::string>& columns, std::string& error) {
  path_ = path;
  to_stdout_ = path == "-";
  std::string header;
  for (std::size_t i = 0; i < columns.size(); ++i) header += (i ? "," : "") + columns[i];
  header += '\n';
  if (to_stdout_) {
    std::fwrite(header.data(), 1, header.size(), stdout);
    return true;
  }
  if (!file_.open(path, "-o", error)) return false;
  file_.write(header);
  return true;
}

void CsvTable::row(const std::vector<double>& values) {
  std::string line;
  // -0 is written as 0: a reader (or a diff) need not tell the two zeros apart.
  for (std::size_t i = 0; i < values.size(); ++i) line += fmt::format(i ? ",{}" : "{}", values[i] == 0.0 ? 0.0 : values[i]);
  line += '\n';
  if (to_stdout_) {
    std::fwrite(line.data(), 1, line.size(), stdout);
    std::fflush(stdout);
  } else {
    file_.write(line);
  }
  ++rows_;
}

bool CsvTable::close(std::string& error) {
  if (!to_stdout_) return file_.commit(error);
  if (std::fflush(stdout) == 0 && !std::ferror(stdout)) return true;
  error = fmt::format("mbsc: error: writing the CSV to standard output failed: {}", std::strerror(errno));
  return false;
}

std::string CsvTable::keep() {
  if (to_stdout_) {
    std::fflush(stdout);
    return "-";
  }
  return file_.keep();
}

bool choose_columns(const std::vector<std::string>& available, const std::vector<std::string>& wanted,
                    std::vector<int>& indices, std::string& error) {
  indices.clear();
  for (const auto& written : wanted) {
    const std::string w = declared_name(written);
    int found = -1;
    for (std::size_t i = 0; i < available.size(); ++i)
      if (available[i] == w) found = static_cast<int>(i);
    if (found < 0) {
      error = fmt::format("no column named '{}'{} (columns: {})", printable(w), did_you_mean(w, available),
                          list_names(available));
      return false;
    }
    indices.push_back(found);
  }
  return true;
}

bool csv_columns(const std::vector<std::string>& available, const std::vector<std::string>& wanted,
                 std::vector<int>& indices, std::string& error) {
  if (wanted.empty()) {
    indices.clear();
    for (std::size_t i = 0; i < available.size(); ++i) indices.push_back(static_cast<int>(i));
    return true;
  }
  std::vector<std::string> named = wanted;
  if (named.front() != "t") named.insert(named.begin(), "t");
  return choose_columns(available, named, indices, error);
}

double csv_bytes(double t_end, double dt_out, std::size_t columns) {
  return (std::floor(t_end / dt_out) + 2) * (static_cast<double>(columns) * 21.0 + 1.0);
}

}  // namespace mbsc::run
