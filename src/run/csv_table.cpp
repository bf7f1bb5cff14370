// SPDX-License-Identifier: GPL-2.0-or-later
// The CSV of a run (include/mbsc/run/csv_table.hpp).
#include "mbsc/run/csv_table.hpp"

#include <cerrno>
#include <cstring>
#include <fmt/format.h>

#include "mbsc/diag/diagnostics.hpp"
#include "mbsc/diag/name_suggestions.hpp"

namespace mbsc::run {

CsvTable::~CsvTable() {
  std::string ignored;
  close(ignored);
}

bool CsvTable::open(const std::string& path, const std::vector<std::string>& columns, std::string& error) {
  path_ = path;
  if (path == "-") {
    f_ = stdout;
    owned_ = false;
  } else {
    f_ = std::fopen(path.c_str(), "w");
    owned_ = true;
    if (!f_) {
      error = fmt::format("cannot write '{}': {}", printable(path), std::strerror(errno));
      return false;
    }
  }
  std::string header;
  for (std::size_t i = 0; i < columns.size(); ++i) header += (i ? "," : "") + columns[i];
  std::fprintf(f_, "%s\n", header.c_str());
  return true;
}

void CsvTable::row(const std::vector<double>& values) {
  if (!f_) return;
  std::string line;
  for (std::size_t i = 0; i < values.size(); ++i) line += fmt::format(i ? ",{}" : "{}", values[i]);
  line += '\n';
  std::fwrite(line.data(), 1, line.size(), f_);
  std::fflush(f_);
  ++rows_;
}

bool CsvTable::close(std::string& error) {
  if (!f_) return true;
  bool ok = std::fflush(f_) == 0 && !std::ferror(f_);
  if (owned_ && std::fclose(f_) != 0) ok = false;
  f_ = nullptr;
  if (!ok) error = fmt::format("writing '{}' failed: {}", printable(path_), std::strerror(errno));
  return ok;
}

bool choose_columns(const std::vector<std::string>& available, const std::vector<std::string>& wanted,
                    std::vector<int>& indices, std::string& error) {
  indices.clear();
  for (const auto& w : wanted) {
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

}  // namespace mbsc::run
