// SPDX-License-Identifier: GPL-2.0-or-later
// Eigenvalue sweeps (include/mbsc/run/eigen_sweep.hpp) against closed forms and the
// benchmark bicycle of Meijaard, Papadopoulos, Ruina and Schwab, Proc. R. Soc. A 463
// (2007) 1955-1982: its weave and capsize speeds and its eigenvalues at 5 m/s (Table 2).
#include <catch2/catch.hpp>
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdlib>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "mbsc/run/eigen_sweep.hpp"

using mbsc::run::MatrixAt;
using mbsc::run::StabilityCrossing;
using mbsc::run::TrackedSweep;
using Complex = std::complex<double>;

namespace {

std::vector<double> grid(double from, double step, int points) {
  std::vector<double> g;
  for (int i = 0; i < points; ++i) g.push_back(from + i * step);
  return g;
}

TrackedSweep sweep(const MatrixAt& A, const std::vector<double>& g) {
  TrackedSweep s;
  std::string error;
  INFO(error);
  REQUIRE(mbsc::run::sweep_eigenvalues(A, g, s, error, "v"));
  REQUIRE(s.values.size() == g.size());
  return s;
}

std::vector<StabilityCrossing> crossings(const MatrixAt& A, const TrackedSweep& s) {
  std::vector<StabilityCrossing> c;
  std::string error;
  INFO(error);
  REQUIRE(mbsc::run::stability_crossings(A, s, c, error, 1e-12, "v"));
  return c;
}

/// A damped oscillator x'' = (c0 - v) x' - k x: its damping changes sign at v = c0.
MatrixAt oscillator(double k, double c0, double sign) {
  return [=](double v, Eigen::MatrixXd& A, std::string&) {
    A.resize(2, 2);
    A << 0, 1, -k, sign * (c0 - v);
    return true;
  };
}

// --- The benchmark bicycle (Meijaard et al. 2007, section 5 and appendix A) -----------------
struct Bicycle {
  Eigen::Matrix2d M, C1, K0, K2;
  double g = 9.81;
  Bicycle() {
    M << 80.81722, 2.31941332208709, 2.31941332208709, 0.29784188199686;
    C1 << 0, 33.86641391492494, -0.85035641456978, 1.68540397397560;
    K0 << -80.95, -2.59951685249872, -2.59951685249872, -0.80329488458618;
    K2 << 0, 76.59734589573222, 0, 2.65431523794604;
  }
  /// The state (lean, steer, lean rate, steer rate) and A(v) = [[0, I], [-M^-1 K, -M^-1 v C1]].
  MatrixAt matrix() const {
    return [this](double v, Eigen::MatrixXd& A, std::string&) {
      const Eigen::Matrix2d Minv = M.inverse();
      A = Eigen::MatrixXd::Zero(4, 4);
      A.block<2, 2>(0, 2) = Eigen::Matrix2d::Identity();
      A.block<2, 2>(2, 0) = -Minv * (g * K0 + v * v * K2);
      A.block<2, 2>(2, 2) = -Minv * (v * C1);
      return true;
    };
  }
};

constexpr double kWeaveSpeed = 4.29238253634111;    // the paper's v_w
constexpr double kCapsizeSpeed = 6.02426201538837;  // the paper's v_c

/// The mode (in the sweep's numbering) whose value at point k is nearest `x`.
int mode_near(const TrackedSweep& s, std::size_t k, Complex x) {
  int best = 0;
  for (int i = 1; i < s.modes(); ++i)
    if (std::abs(s.values[k][i] - x) < std::abs(s.values[k][best] - x)) best = i;
  return best;
}

}  // namespace

TEST_CASE("eig sweep: a damped oscillator's damping changes sign off the grid", "[run][eig]") {
  const double c0 = 0.3712345678901;  // not a grid point
  for (double sign : {1.0, -1.0}) {
    const MatrixAt A = oscillator(4.0, c0, sign);
    const TrackedSweep s = sweep(A, grid(0.0, 0.1, 11));
    const std::vector<StabilityCrossing> c = crossings(A, s);
    REQUIRE(c.size() == 1);  // a conjugate pair is one crossing
    CHECK(std::abs(c[0].param - c0) < 1e-10);
    CHECK(c[0].becomes_stable == (sign > 0));
    CHECK(std::abs(c[0].value.real()) < 1e-10);
    CHECK(c[0].value.imag() == Approx(2.0).epsilon(1e-9));  // sqrt(k), the Im > 0 member
    CHECK(s.values[0][static_cast<std::size_t>(c[0].mode)].imag() > 0);
  }
  // A real mode: lambda = v - c0 becomes unstable at c0.
  const MatrixAt real_mode = [c0](double v, Eigen::MatrixXd& A, std::string&) {
    A = Eigen::MatrixXd::Constant(1, 1, v - c0);
    return true;
  };
  const std::vector<StabilityCrossing> c = crossings(real_mode, sweep(real_mode, grid(1.0, -0.25, 5)));
  REQUIRE(c.size() == 1);
  CHECK(std::abs(c[0].param - c0) < 1e-10);
  CHECK(c[0].becomes_stable);  // the grid runs downwards
}

TEST_CASE("eig sweep: real parts that cross do not swap the curves", "[run][eig]") {
  const MatrixAt A = [](double v, Eigen::MatrixXd& M, std::string&) {
    M = Eigen::MatrixXd::Zero(2, 2);
    M(0, 0) = 1 - v;  // the eigensolver lists 1 - v first
    M(1, 1) = v;
    return true;
  };
  // Through v = 0.5 exactly (a double eigenvalue there: the eigenvectors decide) and past it.
  for (const std::vector<double>& g : {grid(0.0, 0.1, 11), grid(0.03, 0.1, 10)}) {
    const TrackedSweep s = sweep(A, g);
    for (std::size_t k = 0; k < g.size(); ++k) {
      INFO("v = " << g[k]);
      CHECK(s.values[k][0] == Complex(g[k], 0.0));  // mode 0: the smaller at the first point
      CHECK(s.values[k][1] == Complex(1 - g[k], 0.0));
      CHECK(std::abs(s.vectors[k][0](1)) == 1.0);
    }
    const std::vector<StabilityCrossing> c = crossings(A, s);
    if (g.front() == 0.0) {
      // Mode 0 starts at exactly 0 (marginal) and turns unstable at once, mode 1 ends at
      // exactly 0 at v = 1: changes between unstable and marginal at the grid's two ends.
      REQUIRE(c.size() == 2);
      CHECK(c[0].mode == 0);
      CHECK(c[0].marginal);
      CHECK_FALSE(c[0].becomes_stable);
      // A change from marginal is placed where Re leaves the band |Re| <= 1e-9 |lambda|
      // (kMarginalTolerance): here, where it grows linearly from 0, within 1e-9 of the root.
      CHECK(std::abs(c[0].param) < 2e-9);
      CHECK(c[1].mode == 1);
      CHECK(c[1].marginal);
      CHECK(c[1].becomes_stable);
      CHECK(std::abs(c[1].param - 1.0) < 2e-9);
    } else {
      CHECK(c.empty());  // both stay > 0
    }
  }
}

TEST_CASE("eig sweep: crossings, coalescences and splits follow closed forms", "[run][eig]") {
  // Blocks with closed-form eigenvalues, hidden by a fixed orthogonal change of basis:
  //  oscillator 1: x'' + c x' + x = 0, c = 2.5 - 2v (reals meet at v = 0.25, Re = 0 at 1.25);
  //  two real modes -0.8 + 0.9v and 0.3 - 0.7v (zero at 8/9 and 3/7; they cross at 0.6875);
  //  oscillator 2: c = 0.5, k = 4 + v (always a stable pair);
  //  oscillator 3: c = 2v - 1 (Re = 0 at v = 0.5, the pair splits into reals at 1.5).
  struct Osc {
    double c0, c1, k0, k1;
  };
  const Osc osc[3] = {{2.5, -2.0, 1.0, 0.0}, {0.5, 0.0, 4.0, 1.0}, {-1.0, 2.0, 1.0, 0.0}};
  Eigen::MatrixXd R(8, 8);
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 8; ++j) R(i, j) = std::sin(1.0 + 7 * i + 3 * j * j);
  const Eigen::MatrixXd Q = Eigen::HouseholderQR<Eigen::MatrixXd>(R).householderQ();
  const auto closed = [&](double v) {  // the eight curves, in a fixed order
    std::vector<Complex> l;
    for (const Osc& o : osc) {
      const double c = o.c0 + o.c1 * v, k = o.k0 + o.k1 * v;
      const Complex root = std::sqrt(Complex(c * c - 4 * k, 0.0));  // principal branch
      l.push_back((-c + root) / 2.0);
      l.push_back((-c - root) / 2.0);
    }
    l.push_back(-0.8 + 0.9 * v);
    l.push_back(0.3 - 0.7 * v);
    return l;
  };
  const MatrixAt A = [&](double v, Eigen::MatrixXd& M, std::string&) {
    Eigen::MatrixXd D = Eigen::MatrixXd::Zero(8, 8);
    for (int b = 0; b < 3; ++b) {
      D(2 * b, 2 * b + 1) = 1;
      D(2 * b + 1, 2 * b) = -(osc[b].k0 + osc[b].k1 * v);
      D(2 * b + 1, 2 * b + 1) = -(osc[b].c0 + osc[b].c1 * v);
    }
    D(6, 6) = -0.8 + 0.9 * v;
    D(7, 7) = 0.3 - 0.7 * v;
    M = Q * D * Q.transpose();
    return true;
  };
  const std::vector<double> g = grid(0.003, 0.01, 200);  // no point on a coalescence
  const TrackedSweep s = sweep(A, g);
  REQUIRE(s.modes() == 8);
  // The first point's numbering: ascending real part, then imaginary part.
  for (int i = 1; i < 8; ++i) {
    const Complex x = s.values[0][static_cast<std::size_t>(i) - 1], y = s.values[0][static_cast<std::size_t>(i)];
    CHECK((x.real() < y.real() || (x.real() == y.real() && x.imag() <= y.imag())));
  }
  // Each mode is one closed-form curve all along.
  const std::vector<Complex> first = closed(g[0]);
  for (int i = 0; i < 8; ++i) {
    std::size_t curve = 0;
    for (std::size_t j = 1; j < 8; ++j)
      if (std::abs(first[j] - s.values[0][static_cast<std::size_t>(i)]) <
          std::abs(first[curve] - s.values[0][static_cast<std::size_t>(i)]))
        curve = j;
    double worst = 0.0;
    for (std::size_t k = 0; k < g.size(); ++k)
      worst = std::max(worst, std::abs(s.values[k][static_cast<std::size_t>(i)] - closed(g[k])[curve]));
    INFO("mode " << i << " against curve " << curve);
    CHECK(worst < 1e-8);
  }
  // Real modes have real vectors, conjugate pairs conjugate ones, at every point.
  for (std::size_t k = 0; k < g.size(); ++k)
    for (std::size_t i = 0; i < 8; ++i) {
      const Complex l = s.values[k][i];
      INFO("v = " << g[k] << ", mode " << i << ": " << l);
      CHECK(std::abs(s.vectors[k][i].norm() - 1) < 1e-14);
      if (l.imag() == 0) CHECK(s.vectors[k][i].imag().norm() == 0);
      for (std::size_t j = 0; j < 8; ++j)
        if (l.imag() != 0 && s.values[k][j] == std::conj(l))
          CHECK((s.vectors[k][i] - s.vectors[k][j].conjugate()).norm() == 0);
    }
  // The crossings at their closed-form places: 3/7 stable, 0.5 stable (pair), 8/9 unstable,
  // 1.25 unstable (pair).
  const std::vector<StabilityCrossing> c = crossings(A, s);
  REQUIRE(c.size() == 4);
  const double where[4] = {3.0 / 7.0, 0.5, 8.0 / 9.0, 1.25};
  const bool stable[4] = {true, true, false, false};
  for (int i = 0; i < 4; ++i) {
    CHECK(std::abs(c[static_cast<std::size_t>(i)].param - where[i]) < 1e-10);
    CHECK(c[static_cast<std::size_t>(i)].becomes_stable == stable[i]);
    CHECK(c[static_cast<std::size_t>(i)].value.imag() >= 0);
  }
}

TEST_CASE("eig sweep: identically zero modes are not crossings", "[run][eig]") {
  // Cyclic coordinates: two simple zero eigenvalues (states 0 and 1: nothing drives them)
  // and a defective pair (state 2 drifts at the constant rate of state 3), beside an
  // oscillator that turns unstable at v = 0.6 and a stable real mode, in a dense basis.
  // The eigensolver returns the simple zeros as about 1e-16 and the Jordan pair as about
  // +-1e-8 (the square root of the rounding), real or imaginary, of changing sign.
  Eigen::MatrixXd R(7, 7);
  for (int i = 0; i < 7; ++i)
    for (int j = 0; j < 7; ++j) R(i, j) = std::sin(1.0 + 7 * i + 3 * j * j);
  const Eigen::MatrixXd Q = Eigen::HouseholderQR<Eigen::MatrixXd>(R).householderQ();
  const MatrixAt A = [Q](double v, Eigen::MatrixXd& M, std::string&) {
    Eigen::MatrixXd D = Eigen::MatrixXd::Zero(7, 7);
    D(2, 3) = 1;
    D(4, 5) = 1;
    D(5, 4) = -2 - v;
    D(5, 5) = v - 0.6;
    D(5, 0) = 0.3 * v;  // the cyclic coordinates enter the oscillator
    D(4, 1) = 0.2;
    D(6, 6) = -3;
    M = Q * D * Q.transpose();
    return true;
  };
  const TrackedSweep s = sweep(A, grid(0.0, 0.05, 21));
  int signs = 0;  // the zero modes do change sign along the sweep
  for (std::size_t k = 1; k < s.param.size(); ++k)
    for (std::size_t i = 0; i < 7; ++i)
      if (std::abs(s.values[k][i]) < 1e-6 && (s.values[k][i].real() < 0) != (s.values[k - 1][i].real() < 0)) ++signs;
  CHECK(signs > 0);
  const std::vector<StabilityCrossing> c = crossings(A, s);
  REQUIRE(c.size() == 1);
  CHECK(std::abs(c[0].param - 0.6) < 1e-10);
  CHECK_FALSE(c[0].becomes_stable);
}

TEST_CASE("eig sweep: the benchmark bicycle's weave and capsize speeds", "[run][eig][bicycle]") {
  const Bicycle bike;
  const MatrixAt A = bike.matrix();
  const std::vector<double> g = [] {
    std::vector<double> v;
    for (int i = 0; i <= 1000; ++i) v.push_back(i / 100.0);
    return v;
  }();
  const TrackedSweep s = sweep(A, g);
  REQUIRE(s.modes() == 4);

  // Table 2 of the paper at 5 m/s (point 500).
  const std::size_t k5 = 500;
  REQUIRE(g[k5] == 5.0);
  const int weave = mode_near(s, k5, Complex(-0.775341882195845, 4.464867713788234));
  const int capsize = mode_near(s, k5, Complex(-0.322866429004087, 0));
  const int castering = mode_near(s, k5, Complex(-14.0783896927982, 0));
  CHECK(std::abs(s.values[k5][static_cast<std::size_t>(weave)] - Complex(-0.775341882195845, 4.464867713788234)) <
        1e-10);
  CHECK(std::abs(s.values[k5][static_cast<std::size_t>(capsize)] - Complex(-0.322866429004087, 0)) < 1e-10);
  CHECK(std::abs(s.values[k5][static_cast<std::size_t>(castering)] - Complex(-14.0783896927982, 0)) < 1e-10);

  // Continuity: no step of a mode is much larger than the steps beside it (a swap is a jump
  // of the distance between two modes between small steps); the weave pair stays a pair
  // from its coalescence on, and its two real parents (v = 0) coalesce near 0.68 m/s.
  for (int i = 0; i < 4; ++i)
    for (std::size_t k = 1; k + 1 < g.size(); ++k) {
      const auto step = [&](std::size_t j) {
        return std::abs(s.values[j][static_cast<std::size_t>(i)] - s.values[j - 1][static_cast<std::size_t>(i)]);
      };
      const double local = std::max(step(k > 1 ? k - 1 : k + 1), step(k + 1));
      INFO("mode " << i << " at v = " << g[k]);
      CHECK(step(k) <= 4 * local + 1e-12);
    }
  int partner = -1;
  for (int i = 0; i < 4; ++i)
    if (s.values[k5][static_cast<std::size_t>(i)] == std::conj(s.values[k5][static_cast<std::size_t>(weave)]))
      partner = i;
  REQUIRE(partner >= 0);
  std::size_t first_complex = g.size();
  for (std::size_t k = 0; k < g.size(); ++k) {
    const Complex w = s.values[k][static_cast<std::size_t>(weave)];
    if (w.imag() != 0 && first_complex == g.size()) first_complex = k;
    if (first_complex <= k) {
      INFO("v = " << g[k]);
      CHECK(w.imag() > 0);
      CHECK(s.values[k][static_cast<std::size_t>(partner)] == std::conj(w));
    }
  }
  CHECK(g[first_complex] > 0.6);
  CHECK(g[first_complex] < 0.8);
  CHECK(s.values[0][static_cast<std::size_t>(weave)].imag() == 0);
  CHECK(s.values[0][static_cast<std::size_t>(partner)].imag() == 0);

  // The crossings: the weave pair turns stable at v_w, the capsize mode unstable at v_c.
  const std::vector<StabilityCrossing> c = crossings(A, s);
  REQUIRE(c.size() == 2);
  INFO(std::setprecision(17) << "v_w " << c[0].param << ", v_c " << c[1].param);
  CHECK(c[0].mode == weave);
  CHECK(c[0].becomes_stable);
  CHECK(std::abs(c[0].param - kWeaveSpeed) < 1e-9);
  CHECK(c[0].value.imag() > 0);
  CHECK(c[1].mode == capsize);
  CHECK_FALSE(c[1].becomes_stable);
  CHECK(std::abs(c[1].param - kCapsizeSpeed) < 1e-9);
}

TEST_CASE("eig sweep: the weave's steer-to-lean ratio against the null vector", "[run][eig][bicycle]") {
  const Bicycle bike;
  const TrackedSweep s = sweep(bike.matrix(), {4.9, 4.95, 5.0});
  const std::size_t k = 2;
  const int weave = mode_near(s, k, Complex(-0.78, 4.46));
  const Complex l = s.values[k][static_cast<std::size_t>(weave)];
  const Complex r = mbsc::run::ratio(s.vectors[k][static_cast<std::size_t>(weave)], 1, 0);
  // (l^2 M + l v C1 + g K0 + v^2 K2) (lean, steer) = 0; its first row gives steer / lean.
  const double v = 5.0;
  const Eigen::Matrix2cd P = (l * l) * bike.M.cast<Complex>() + (l * v) * bike.C1.cast<Complex>() +
                             (bike.g * bike.K0 + v * v * bike.K2).cast<Complex>();
  const Complex expected = -P(0, 0) / P(0, 1);
  INFO("ratio " << r << " expected " << expected);
  CHECK(std::isfinite(std::abs(r)));
  CHECK(std::abs(r - expected) < 1e-9 * std::abs(expected));
  // The ratio of the state's rates equals that of the coordinates.
  const Complex rates = mbsc::run::ratio(s.vectors[k][static_cast<std::size_t>(weave)], 3, 2);
  CHECK(std::abs(rates - r) < 1e-9 * std::abs(r));
  CHECK_THROWS_AS(mbsc::run::ratio(s.vectors[k][0], 4, 0), std::out_of_range);
}

TEST_CASE("eig sweep: the CSV reads back to the same numbers", "[run][eig][csv]") {
  const MatrixAt A = oscillator(4.0, 0.37, 1.0);
  const TrackedSweep s = sweep(A, grid(0.0, 0.1, 7));
  std::ostringstream os;
  mbsc::run::write_sweep_csv(os, s, "v");
  std::istringstream is(os.str());
  std::string line;
  REQUIRE(std::getline(is, line));
  CHECK(line == "v,re_1,im_1,re_2,im_2");
  std::size_t rows = 0;
  while (std::getline(is, line)) {
    std::vector<double> cells;
    std::stringstream row(line);
    std::string cell;
    while (std::getline(row, cell, ',')) cells.push_back(std::strtod(cell.c_str(), nullptr));
    REQUIRE(cells.size() == 5);
    CHECK(cells[0] == s.param[rows]);
    for (std::size_t m = 0; m < 2; ++m) {
      CHECK(cells[1 + 2 * m] == s.values[rows][m].real());
      CHECK(cells[2 + 2 * m] == s.values[rows][m].imag());
    }
    ++rows;
  }
  CHECK(rows == 7);
  std::ostringstream again;
  mbsc::run::write_sweep_csv(again, sweep(A, grid(0.0, 0.1, 7)), "v");
  CHECK(again.str() == os.str());
}

TEST_CASE("eig sweep: bad input is a clear error", "[run][eig][errors]") {
  const MatrixAt good = oscillator(1.0, 0.5, 1.0);
  const auto fails = [](const MatrixAt& A, const std::vector<double>& g, const std::string& part) {
    TrackedSweep s;
    std::string error;
    CHECK_FALSE(mbsc::run::sweep_eigenvalues(A, g, s, error, "v"));
    INFO(error);
    CHECK(error.find(part) != std::string::npos);
    CHECK(s.values.empty());
  };
  fails(good, {}, "grid is empty");
  fails(good, {0.0, 0.1, 0.1, 0.2}, "not strictly monotonic: v = 0.1 (point 3) follows 0.1 (point 2)");
  fails(good, {0.0, 0.2, 0.1}, "not strictly monotonic");
  fails(good, {0.0, std::nan("")}, "non-finite value");
  fails(
      [](double v, Eigen::MatrixXd& A, std::string& why) {
        if (v > 0.25 && v < 0.35) {
          why = "the reference state has no solution";
          return false;
        }
        A = Eigen::MatrixXd::Identity(2, 2);
        return true;
      },
      {0.0, 0.3, 0.6}, "cannot form the state matrix at v = 0.3: the reference state has no solution");
  fails(
      [](double, Eigen::MatrixXd& A, std::string&) {
        A = Eigen::MatrixXd::Zero(2, 3);
        return true;
      },
      {1.0}, "at v = 1 is 2x3, not a non-empty square matrix");
  fails(
      [](double v, Eigen::MatrixXd& A, std::string&) {
        A = Eigen::MatrixXd::Identity(v < 0.5 ? 2 : 3, v < 0.5 ? 2 : 3);
        return true;
      },
      {0.0, 1.0}, "at v = 1 is 3x3, but 2x2 at the sweep's first point");
  fails(
      [](double v, Eigen::MatrixXd& A, std::string&) {
        A = Eigen::MatrixXd::Identity(2, 2);
        if (v > 0.5) A(1, 0) = std::numeric_limits<double>::infinity();
        return true;
      },
      {0.0, 1.0}, "at v = 1 has a non-finite entry inf at row 2, column 1");
}
