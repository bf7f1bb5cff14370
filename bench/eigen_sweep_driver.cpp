// SPDX-License-Identifier: GPL-2.0-or-later
// Timing of the eigenvalue sweep (include/mbsc/run/eigen_sweep.hpp): the benchmark
// bicycle of [MPRS07] over v = 0..10 m/s (1001 points, 4x4) and dense stable families of
// 8x8 and 20x20 matrices (1000 points), each against Eigen's eigensolver alone on the same
// matrices (the tracking's own share is the difference). Best of 7 runs, thread CPU time. Prints a
// markdown table; bench/run_eigen_sweep.sh builds and runs it.
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <string>
#include <vector>

#include "mbsc/run/eigen_sweep.hpp"

using mbsc::run::MatrixAt;

namespace {

/// CPU time of the thread (the machine is shared: wall time would count other processes).
double cpu_ms() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return 1e3 * static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_nsec);
}

double best_ms(const std::function<void()>& f) {
  double best = 1e300;
  for (int rep = 0; rep < 7; ++rep) {
    const double t0 = cpu_ms();
    f();
    best = std::min(best, cpu_ms() - t0);
  }
  return best;
}

void row(const std::string& name, const MatrixAt& A, const std::vector<double>& grid) {
  mbsc::run::TrackedSweep s;
  std::vector<mbsc::run::StabilityCrossing> c;
  std::string error;
  const double sweep = best_ms([&] {
    if (!mbsc::run::sweep_eigenvalues(A, grid, s, error)) std::printf("error: %s\n", error.c_str());
  });
  const double cross = best_ms([&] { mbsc::run::stability_crossings(A, s, c, error); });
  const double eigen = best_ms([&] {
    Eigen::MatrixXd M;
    std::string why;
    for (double p : grid) {
      A(p, M, why);
      Eigen::EigenSolver<Eigen::MatrixXd> solver(M, true);
      if (solver.info() != Eigen::Success) std::printf("no convergence\n");
    }
  });
  double max_re = -1e300;
  for (const auto& point : s.values)
    for (const auto& x : point) max_re = std::max(max_re, x.real());
  std::printf("| %s | %zu | %.2f | %.3f | %.2f | %zu | %.3g |\n", name.c_str(), grid.size(), sweep, cross, eigen,
              c.size(), max_re);
}

}  // namespace

int main() {
  Eigen::Matrix2d M, C1, K0, K2;
  M << 80.81722, 2.31941332208709, 2.31941332208709, 0.29784188199686;
  C1 << 0, 33.86641391492494, -0.85035641456978, 1.68540397397560;
  K0 << -80.95, -2.59951685249872, -2.59951685249872, -0.80329488458618;
  K2 << 0, 76.59734589573222, 0, 2.65431523794604;
  const Eigen::Matrix2d Minv = M.inverse();
  const MatrixAt bicycle = [&](double v, Eigen::MatrixXd& A, std::string&) {
    A = Eigen::MatrixXd::Zero(4, 4);
    A.block<2, 2>(0, 2).setIdentity();
    A.block<2, 2>(2, 0) = -Minv * (9.81 * K0 + v * v * K2);
    A.block<2, 2>(2, 2) = -Minv * (v * C1);
    return true;
  };
  std::vector<double> speeds;
  for (int i = 0; i <= 1000; ++i) speeds.push_back(i / 100.0);

  std::printf("| family | points | sweep (ms) | crossings (ms) | Eigen alone (ms) | crossings | max Re |\n");
  std::printf("|---|---|---|---|---|---|---|\n");
  row("bicycle 4x4", bicycle, speeds);
  for (int n : {8, 20}) {
    // A(p) = B0 + p B1 - (2 sqrt(n) + 1.2 p) I with fixed dense B0, B1 of full rank, their
    // entries scattered in [-1, 1] by the fractional part of a large multiple of a sine.
    const auto scattered = [](double x) {
      const double y = std::sin(x) * 43758.5453;
      return 2 * (y - std::floor(y)) - 1;
    };
    Eigen::MatrixXd B0(n, n), B1(n, n);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        B0(i, j) = scattered(12.9898 * i + 78.233 * j);
        B1(i, j) = scattered(39.3468 * i + 11.135 * j + 1.0);
      }
    const double shift = 2.0 * std::sqrt(static_cast<double>(n));
    const MatrixAt family = [&](double p, Eigen::MatrixXd& A, std::string&) {
      A = B0 + p * B1 - (shift + 1.2 * p) * Eigen::MatrixXd::Identity(n, n);
      return true;
    };
    std::vector<double> grid;
    for (int i = 0; i < 1000; ++i) grid.push_back(i / 999.0);
    row("dense " + std::to_string(n) + "x" + std::to_string(n), family, grid);
  }
}
