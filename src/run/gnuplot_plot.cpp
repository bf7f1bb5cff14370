// SPDX-License-Identifier: GPL-2.0-or-later
// Plots through gnuplot (include/mbsc/run/gnuplot_plot.hpp).
#include "mbsc/run/gnuplot_plot.hpp"

#include <filesystem>
#include <fmt/format.h>
#include <algorithm>
#include <cstdlib>
#include <cmath>
#include <fstream>

#include "mbsc/diag/diagnostics.hpp"
#include "mbsc/driver/staged_file.hpp"
#include "mbsc/run/process.hpp"

namespace fs = std::filesystem;

namespace mbsc::run {

namespace {

/// A gnuplot string literal for a label: single quotes, a quote doubled (gnuplot reads
/// nothing else inside single quotes as special) and control characters, which could end
/// the string and the command, replaced by spaces.
std::string quoted(const std::string& s) {
  std::string out = "'";
  for (char c : s) {
    const auto b = static_cast<unsigned char>(c);
    out += c == '\'' ? std::string("''") : b < 0x20 || b == 0x7f ? std::string(" ") : std::string(1, c);
  }
  return out + "'";
}

std::string terminal(const std::string& format, int width, int height) {
  return format == "png" ? fmt::format("set terminal pngcairo size {},{} noenhanced font 'sans,10'\n", width, height)
                         : fmt::format("set terminal svg size {},{} noenhanced font 'sans,11' background '#ffffff'\n",
                                       width, height);
}

/// A data file's name for a gnuplot script: absolute (so never '<' or '|', which gnuplot
/// reads as a command to run), quoted, and refused when it holds a control character
/// (a line break would end the string and start a command). False with `error`.
bool data_file_name(const std::string& csv, std::string& quoted_name, std::string& error) {
  for (unsigned char c : csv)
    if (c < 0x20 || c == 0x7f) {
      error = fmt::format("the file name '{}' holds a control character, which mbsc does not pass to gnuplot",
                          printable(csv));
      return false;
    }
  std::error_code ec;
  const fs::path absolute = fs::absolute(csv, ec);
  if (ec) {
    error = fmt::format("cannot resolve '{}': {}", printable(csv), ec.message());
    return false;
  }
  quoted_name = quoted(absolute.string());
  return true;
}

/// Runs the script with the image on gnuplot's standard output (gnuplot opens no file of
/// ours for writing), then writes the image all or nothing.
bool render(const std::string& script_body, const std::string& format, int width, int height, const std::string& image,
            std::string& error) {
  ProcessOptions options;
  options.input = terminal(format, width, height) + "set output\n" + script_body + "unset output\n";
  options.separate_errors = true;
  options.timeout_seconds = 300;
  const ProcessResult r = run_process({"gnuplot"}, options);
  if (r.exit_code != 0 || r.output.empty()) {
    if (!r.spawn_error.empty() || r.exit_code == 127)
      error = "gnuplot is needed for --plot and was not found (install the Debian package gnuplot-nox)";
    else if (r.timed_out)
      error = "gnuplot did not finish within 300 s";
    else
      error = fmt::format("gnuplot failed (exit code {}): {}", r.exit_code, printable(r.errors.substr(0, 2000)));
    return false;
  }
  driver::StagedFile file;
  if (!file.stage(image, r.output, "--plot", error) || !file.commit(error)) {
    error = without_error_prefix(error);
    return false;
  }
  return true;
}

// The smallest and largest finite value of each column of the CSV (after its header).
std::vector<std::pair<double, double>> column_ranges(const std::string& csv, std::size_t columns) {
  std::vector<std::pair<double, double>> range(columns, {INFINITY, -INFINITY});
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);  // the header
  while (std::getline(in, line)) {
    std::size_t start = 0;
    for (std::size_t c = 0; c < columns; ++c) {
      const std::size_t comma = line.find(',', start);
      const double v = std::strtod(line.c_str() + start, nullptr);
      if (std::isfinite(v)) range[c] = {std::min(range[c].first, v), std::max(range[c].second, v)};
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
  }
  return range;
}

// A column that is constant to about the ninth digit (a conserved quantity, a coordinate
// that a constraint holds): gnuplot would stretch the rounding noise over the panel and
// label every tick 1.000000000; it is drawn in a band of 1e-6 of its size instead.
std::string y_range(const std::pair<double, double>& r) {
  if (!(r.first <= r.second)) return "set autoscale y\nset format y '% h'\n";
  const double size = std::max(std::abs(r.first), std::abs(r.second));
  if (r.second - r.first > 1e-9 * size && r.second - r.first > 1e-300) return "set autoscale y\nset format y '% h'\n";
  const double mid = 0.5 * (r.first + r.second), half = std::max(1e-6 * size, 1e-12);
  return fmt::format("set yrange [{:.17g}:{:.17g}]\nset format y '%.7g'\n", mid - half, mid + half);
}

}  // namespace

std::string plot_format(const std::string& image) {
  const std::string ext = fs::path(image).extension().string();
  if (ext == ".svg" || ext == ".SVG") return "svg";
  if (ext == ".png" || ext == ".PNG") return "png";
  return "";
}

bool plot_columns(const std::string& csv, const std::vector<std::string>& names, int xcol,
                  const std::vector<int>& ycols, const std::string& image, const std::string& title,
                  std::string& error) {
  const std::string format = plot_format(image);
  if (format.empty()) {
    error = fmt::format("--plot: '{}' should end in .svg or .png", printable(image));
    return false;
  }
  std::string data;
  if (!data_file_name(csv, data, error)) return false;
  const int n = static_cast<int>(ycols.size());
  const auto ranges = column_ranges(csv, names.size());
  std::string s = "set datafile separator ','\nset grid\nunset key\n";
  s += fmt::format("set multiplot layout {},1 title {}\n", n, quoted(title));
  for (int k = 0; k < n; ++k) {
    s += y_range(ranges[static_cast<std::size_t>(ycols[static_cast<std::size_t>(k)])]);
    s += fmt::format("set ylabel {}\n", quoted(names[static_cast<std::size_t>(ycols[static_cast<std::size_t>(k)])]));
    s += k == n - 1 ? fmt::format("set xlabel {}\n", quoted(names[static_cast<std::size_t>(xcol)])) : "unset xlabel\n";
    s += fmt::format("plot {} using {}:{} every ::1 with lines lw 1.5\n", data, xcol + 1,
                     ycols[static_cast<std::size_t>(k)] + 1);
  }
  s += "unset multiplot\n";
  return render(s, format, 900, std::max(300, 220 * n), image, error);
}

bool plot_panels(const std::string& csv, const std::vector<std::string>& names, int xcol, const std::vector<PlotPanel>& panels,
                 const std::string& image, const std::string& title, std::string& error) {
  const std::string format = plot_format(image);
  if (format.empty()) {
    error = fmt::format("--plot: '{}' should end in .svg or .png", printable(image));
    return false;
  }
  std::string data;
  if (!data_file_name(csv, data, error)) return false;
  const int n = static_cast<int>(panels.size());
  std::string s = "set datafile separator ','\nset grid\nset key outside right\n";
  s += fmt::format("set multiplot layout {},1 title {}\n", n, quoted(title));
  for (int k = 0; k < n; ++k) {
    const PlotPanel& panel = panels[static_cast<std::size_t>(k)];
    s += fmt::format("set ylabel {}\n", quoted(panel.ylabel));
    s += k == n - 1 ? fmt::format("set xlabel {}\n", quoted(names[static_cast<std::size_t>(xcol)])) : "unset xlabel\n";
    std::string plot = "plot ";
    for (std::size_t c = 0; c < panel.ycols.size(); ++c)
      plot += fmt::format("{}{} using {}:{} every ::1 with lines lw 1.5 title {}", c ? ", " : "", data, xcol + 1,
                          panel.ycols[c] + 1, quoted(names[static_cast<std::size_t>(panel.ycols[c])]));
    s += panel.ycols.empty() ? "plot 0 notitle\n" : plot + "\n";
  }
  s += "unset multiplot\n";
  return render(s, format, 1000, std::max(350, 300 * n), image, error);
}

bool plot_loglog(const std::vector<PlotSeries>& series, const std::string& xlabel, const std::string& ylabel,
                 const std::string& image, const std::string& title, std::string& error) {
  const std::string format = plot_format(image);
  if (format.empty()) {
    error = fmt::format("'{}' should end in .svg or .png", printable(image));
    return false;
  }
  std::string s = "set logscale xy\nset grid\nset key outside right\nset format y '%.0e'\nset format x '%g'\n";
  s += fmt::format("set title {}\nset xlabel {}\nset ylabel {}\n", quoted(title), quoted(xlabel), quoted(ylabel));
  std::string plot = "plot ";
  std::string data;
  bool any = false;
  for (std::size_t i = 0; i < series.size(); ++i) {
    const auto& c = series[i];
    std::string block;
    for (std::size_t k = 0; k < c.x.size(); ++k)
      if (c.x[k] > 0 && c.y[k] > 0) block += fmt::format("{} {}\n", c.x[k], c.y[k]);
    if (block.empty()) continue;
    plot += fmt::format("{}'-' using 1:2 with linespoints lw 1.5 pt {} title {}", any ? ", " : "", 1 + i % 12,
                        quoted(c.title));
    data += block + "e\n";
    any = true;
  }
  if (!any) {
    error = "nothing to plot (no positive errors and times)";
    return false;
  }
  s += plot + "\n" + data;
  return render(s, format, 1000, 650, image, error);
}

}  // namespace mbsc::run
