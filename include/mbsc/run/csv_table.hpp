// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// The CSV a run writes: a header of column names, then one row per output time, each
/// number in the shortest form that reads back to the same double ("nan", "inf" and
/// "-inf" for values that are not finite). The rows go to a temporary file beside the
/// destination (driver/staged_file.hpp), opened before the run starts (an unwritable
/// path is an error before any work); close() renames it into place. A run that fails
/// calls keep() instead: the destination is left as it was and the temporary, with every
/// row up to the failure, stays for the message to name.
#include <string>
#include <vector>

#include "mbsc/driver/staged_file.hpp"

namespace mbsc::run {

class CsvTable {
 public:
  CsvTable() = default;
  CsvTable(const CsvTable&) = delete;
  CsvTable& operator=(const CsvTable&) = delete;

  /// Opens `path` ("-" for standard output) and writes the header. False with `error`
  /// (a whole "mbsc: error: ..." line).
  bool open(const std::string& path, const std::vector<std::string>& columns, std::string& error);
  void row(const std::vector<double>& values);
  /// Moves the file into place; false with `error` when a write failed (disk full).
  bool close(std::string& error);
  /// Leaves the destination alone and the rows in the temporary; returns its path ("-"
  /// for standard output).
  std::string keep();
  long rows() const { return rows_; }
  const std::string& path() const { return path_; }

 private:
  driver::StagedFile file_;
  bool to_stdout_ = false;
  long rows_ = 0;
  std::string path_;
};

/// "t,th1,..." column names resolved against the available ones; false with `error`
/// naming an unknown column (and the closest known one).
bool choose_columns(const std::vector<std::string>& available, const std::vector<std::string>& wanted,
                    std::vector<int>& indices, std::string& error);

/// A run's CSV columns (--columns): every available one when `wanted` is empty, else t
/// (first, whether named or not) and those named; false with choose_columns' `error`.
bool csv_columns(const std::vector<std::string>& available, const std::vector<std::string>& wanted,
                 std::vector<int>& indices, std::string& error);

/// A CSV far larger than anyone reads is refused before the run unless asked for
/// (--large-output): above this many bytes, as estimated by csv_bytes (about a gigabyte:
/// 10^7 rows of a bicycle's 50 columns are 11 GB).
constexpr double kLargeOutputBytes = 1e9;

/// About how many bytes a run's CSV takes: its rows (t = 0, then every dt_out to t_end)
/// of `columns` numbers of up to 21 characters.
double csv_bytes(double t_end, double dt_out, std::size_t columns);

}  // namespace mbsc::run
