// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// Plots made by gnuplot (Debian gnuplot-nox), driven through its script language on
/// standard input: a time plot of chosen CSV columns (one panel per column, sharing the
/// time axis) and the log-log work-precision plot of `mbsc bench`. The image is
/// written under a temporary name and renamed into place, so a failed plot leaves no
/// half-written file. `.svg` gives SVG, `.png` PNG (cairo).
#include <string>
#include <vector>

namespace mbsc::run {

struct PlotSeries {
  std::string title;
  std::vector<double> x, y;
};

/// Columns `ycols` (0-based) of a CSV file against column `xcol`, one panel each.
bool plot_columns(const std::string& csv, const std::vector<std::string>& names, int xcol,
                  const std::vector<int>& ycols, const std::string& image, const std::string& title,
                  std::string& error);

/// Panels of several CSV columns each against column `xcol` (an eigenvalue sweep: real
/// parts in one panel, imaginary parts in the other), each curve titled by its column.
struct PlotPanel {
  std::string ylabel;
  std::vector<int> ycols;
};
bool plot_panels(const std::string& csv, const std::vector<std::string>& names, int xcol, const std::vector<PlotPanel>& panels,
                 const std::string& image, const std::string& title, std::string& error);

/// Curves on log-log axes (work-precision: error against CPU time), one per series.
bool plot_loglog(const std::vector<PlotSeries>& series, const std::string& xlabel, const std::string& ylabel,
                 const std::string& image, const std::string& title, std::string& error);

/// "svg" or "png" from the file name; "" when neither.
std::string plot_format(const std::string& image);

}  // namespace mbsc::run
