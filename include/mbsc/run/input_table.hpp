// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// An input fed from a table: `mbsc run --input NAME=@FILE[:COLUMN]` reads the column
/// COLUMN (default: the input's own name) of a CSV whose header names a column `t`, and
/// interpolates it in t, piecewise linearly or by a natural cubic spline
/// (`--input-interpolation`). The CSV `mbsc run` and `mbsc inverse` write reads back as
/// it is: the inverse → forward round trip needs no code (docs/running.md, "Inputs").
#include <string>
#include <vector>

namespace mbsc::run {

class InputTable {
 public:
  enum class Interpolation { Linear, Cubic };

  /// Reads `spec` ("@FILE" or "@FILE:COLUMN") for input `name`. False with `error`, a
  /// whole message line ("FILE:LINE:COL: error: ..." where a value is wrong): no `t` column, an unknown
  /// column, a field that is not a finite number, a row of the wrong length, times that
  /// do not increase, fewer than two rows.
  bool read(const std::string& name, const std::string& spec, Interpolation how, std::string& error);

  /// False with `error` (a whole line) unless the times cover [t0, t1] (to 1e-9 of the span).
  bool covers(double t0, double t1, std::string& error) const;

  /// The value at t (t within the table; the end values just outside it).
  double at(double t) const;

  const std::string& file() const { return file_; }
  const std::string& column() const { return column_; }
  std::size_t rows() const { return t_.size(); }

 private:
  std::string name_, file_, column_;
  Interpolation how_ = Interpolation::Linear;
  std::vector<double> t_, v_;
  std::vector<double> curvature_;  // cubic: the spline's second derivatives at the knots
};

/// True when an --input value names a table ("@FILE[:COLUMN]").
inline bool is_input_table(const std::string& value) { return !value.empty() && value[0] == '@'; }

}  // namespace mbsc::run
