// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// The CSV a run writes: a header of column names, then one row per output time, each
/// number in the shortest form that reads back to the same double. The file is opened
/// before the run starts (an unwritable path is an error before any work) and flushed
/// row by row, so a run that fails keeps every row up to the failure.
#include <cstdio>
#include <string>
#include <vector>

namespace mbsc::run {

class CsvTable {
 public:
  CsvTable() = default;
  ~CsvTable();
  CsvTable(const CsvTable&) = delete;
  CsvTable& operator=(const CsvTable&) = delete;

  /// Opens `path` ("-" for standard output) and writes the header. False with `error`.
  bool open(const std::string& path, const std::vector<std::string>& columns, std::string& error);
  void row(const std::vector<double>& values);
  /// Flushes and closes; false with `error` when a write failed (disk full).
  bool close(std::string& error);
  long rows() const { return rows_; }
  const std::string& path() const { return path_; }

 private:
  std::FILE* f_ = nullptr;
  bool owned_ = false;
  long rows_ = 0;
  std::string path_;
};

/// "t,th1,..." column names resolved against the available ones; false with `error`
/// naming an unknown column (and the closest known one).
bool choose_columns(const std::vector<std::string>& available, const std::vector<std::string>& wanted,
                    std::vector<int>& indices, std::string& error);

}  // namespace mbsc::run
