// SPDX-License-Identifier: GPL-2.0-or-later
// The interpolation of a table input (include/mbsc/run/input_table.hpp) against closed
// forms: linear data is reproduced by both methods, and sin(t) at a step of 0.1 to the
// orders of the two methods (h^2 / 8 |f''| and about h^4 |f''''| / 384 inside).
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "mbsc/run/input_table.hpp"

using mbsc::run::InputTable;

namespace {

std::string table_file(const std::string& name, double (*f)(double), int n, double h) {
  const std::string path = (std::filesystem::temp_directory_path() / name).string();
  std::ofstream out(path);
  out.precision(17);
  out << "t,other,u\n";
  for (int i = 0; i <= n; ++i) out << i * h << ",7," << f(i * h) << "\n";
  return path;
}

double line(double t) { return 2.0 - 3.0 * t; }
double sine(double t) { return std::sin(t); }

}  // namespace

TEST_CASE("input table: linear data is exact, sin(t) to each method's order", "[input_table]") {
  std::string error;
  for (const auto how : {InputTable::Interpolation::Linear, InputTable::Interpolation::Cubic}) {
    InputTable lin;
    REQUIRE(lin.read("u", "@" + table_file("mbsc_table_line.csv", line, 10, 0.3), how, error));
    for (double t = 0; t <= 3.0; t += 0.0371) CHECK(std::abs(lin.at(t) - line(t)) < 1e-13);
    CHECK(lin.covers(0.0, 3.0, error));
    CHECK_FALSE(lin.covers(0.0, 3.1, error));
  }
  InputTable a, b;
  const std::string path = table_file("mbsc_table_sine.csv", sine, 60, 0.1);
  REQUIRE(a.read("u", "@" + path, InputTable::Interpolation::Linear, error));
  REQUIRE(b.read("v", "@" + path + ":u", InputTable::Interpolation::Cubic, error));
  CHECK(b.column() == "u");
  double worst_linear = 0, worst_cubic = 0;
  for (double t = 1.0; t <= 5.0; t += 0.013) {  // away from the natural ends
    worst_linear = std::max(worst_linear, std::abs(a.at(t) - std::sin(t)));
    worst_cubic = std::max(worst_cubic, std::abs(b.at(t) - std::sin(t)));
  }
  CHECK(worst_linear < 0.1 * 0.1 / 8 * 1.01);
  CHECK(worst_linear > 0.1 * 0.1 / 8 * 0.5);  // the bound is reached: not a finer table
  CHECK(worst_cubic < 1e-6);
  // At the knots both give the table's values.
  CHECK(std::abs(b.at(2.0) - std::sin(2.0)) < 1e-12);
}

TEST_CASE("input table: a byte-order mark, subnormal values, a file name with ':'", "[input_table]") {
  const auto dir = std::filesystem::temp_directory_path() / "mbsc_table_edges";
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "a:b.csv").string();
  {
    std::ofstream out(path);
    out << "\xEF\xBB\xBFt,u\n0,1e-310\n1,2\n";
  }
  InputTable table;
  std::string error;
  REQUIRE(table.read("u", "@" + path, InputTable::Interpolation::Linear, error));
  CHECK(table.column() == "u");
  CHECK(table.at(0.0) == 1e-310);
  CHECK(std::isnan(table.at(std::nan(""))));
  std::filesystem::remove_all(dir);
}
