// SPDX-License-Identifier: GPL-2.0-or-later
// The runtime's column-pivoted QR least squares against Eigen's, and its rank.
#include <catch2/catch.hpp>
#include <Eigen/Dense>
#include <random>

#include "mbsc/runtime/least_squares.hpp"

using mbsc::runtime::solve_least_squares;

namespace {
std::vector<double> flat(const Eigen::MatrixXd& A) {
  std::vector<double> v;
  for (int i = 0; i < A.rows(); ++i)
    for (int j = 0; j < A.cols(); ++j) v.push_back(A(i, j));
  return v;
}
}  // namespace

TEST_CASE("least squares: full rank, square and overdetermined, equals Eigen", "[runtime][least_squares]") {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> d(-1.0, 1.0);
  for (int m : {3, 5, 8}) {
    const int n = 3;
    Eigen::MatrixXd A(m, n);
    Eigen::VectorXd b(m);
    for (int i = 0; i < m; ++i) {
      for (int j = 0; j < n; ++j) A(i, j) = d(rng);
      b(i) = d(rng);
    }
    const Eigen::VectorXd ref = A.colPivHouseholderQr().solve(b);
    const auto r = solve_least_squares(flat(A), std::vector<double>(b.data(), b.data() + m), m, n);
    CHECK(r.rank == n);
    for (int j = 0; j < n; ++j) CHECK(r.x[static_cast<std::size_t>(j)] == Approx(ref(j)).margin(1e-12));
  }
}

TEST_CASE("least squares: a repeated row and a dependent column are detected", "[runtime][least_squares]") {
  // Rows 0 and 2 equal (a redundant constraint), column 2 = column 0 + column 1.
  Eigen::MatrixXd A(3, 3);
  A << 1, 2, 3, 0, 1, 1, 1, 2, 3;
  const Eigen::VectorXd x_true = (Eigen::VectorXd(3) << 0.5, -1.0, 0.0).finished();
  const Eigen::VectorXd b = A * x_true;
  const auto r = solve_least_squares(flat(A), std::vector<double>(b.data(), b.data() + 3), 3, 3);
  CHECK(r.rank == 2);
  // A basic solution: consistent data are reproduced exactly.
  Eigen::VectorXd x(3);
  for (int j = 0; j < 3; ++j) x(j) = r.x[static_cast<std::size_t>(j)];
  CHECK((A * x - b).norm() < 1e-12);
  CHECK(r.largest_pivot / r.smallest_pivot < 1e3);
}
