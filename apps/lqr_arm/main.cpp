// SPDX-License-Identifier: GPL-2.0-or-later
// Holds a two-link arm (a URDF, apps/lqr_arm/two_link_arm.urdf) at a tilted pose that it
// would fall from, with an LQR controller designed from the generated derivatives:
//
//   1. the holding torques u* at the pose x* from the generated inverse_dynamics;
//   2. the linear model x' ~ A (x - x*) + B (u - u*) from the generated rhs_jacobian;
//   3. the LQR gain K of that model for the step dt (the discrete Riccati equation of
//      x+ = (I + dt A) x + dt B u, iterated to convergence);
//   4. the nonlinear arm under u = u* - K (x - x*) from a push away from the pose,
//      integrated by RK4, beside the same start without feedback.
//
// Writes t, the joint angles and the torques of both runs as CSV (to the file named by
// the first argument, else stdout), and returns 0 when the controlled arm settles at x*
// to 1e-6 while the uncontrolled one leaves it, else 1.
#include <array>
#include <cmath>
#include <cstdio>
#include <vector>

#include "two_link_arm/two_link_arm.hpp"

namespace arm = mbsc_gen::two_link_arm;

namespace {

constexpr int n = arm::kNx, m = arm::kNin;
using State = std::array<double, n>;
using Input = std::array<double, m>;
using Matrix = std::vector<double>;  // row-major

// C (a x c) = A (a x b) B (b x c); At: A is given transposed (b x a).
Matrix product(const Matrix& A, const Matrix& B, int a, int b, int c, bool At = false) {
  Matrix C(static_cast<std::size_t>(a * c), 0.0);
  for (int i = 0; i < a; ++i)
    for (int k = 0; k < b; ++k) {
      const double x = At ? A[static_cast<std::size_t>(k * a + i)] : A[static_cast<std::size_t>(i * b + k)];
      for (int j = 0; j < c; ++j) C[static_cast<std::size_t>(i * c + j)] += x * B[static_cast<std::size_t>(k * c + j)];
    }
  return C;
}

// X = S^-1 Y for a symmetric positive definite m x m S (Gaussian elimination; m is small).
Matrix solve(Matrix S, Matrix Y, int cols) {
  for (int c = 0; c < m; ++c)
    for (int r = c + 1; r < m; ++r) {
      const double f = S[static_cast<std::size_t>(r * m + c)] / S[static_cast<std::size_t>(c * m + c)];
      for (int j = 0; j < m; ++j) S[static_cast<std::size_t>(r * m + j)] -= f * S[static_cast<std::size_t>(c * m + j)];
      for (int j = 0; j < cols; ++j) Y[static_cast<std::size_t>(r * cols + j)] -= f * Y[static_cast<std::size_t>(c * cols + j)];
    }
  for (int r = m - 1; r >= 0; --r)
    for (int j = 0; j < cols; ++j) {
      double s = Y[static_cast<std::size_t>(r * cols + j)];
      for (int k = r + 1; k < m; ++k) s -= S[static_cast<std::size_t>(r * m + k)] * Y[static_cast<std::size_t>(k * cols + j)];
      Y[static_cast<std::size_t>(r * cols + j)] = s / S[static_cast<std::size_t>(r * m + r)];
    }
  return Y;
}

// The LQR gain of x+ = Ad x + Bd u with stage cost x'Qx + u'Ru: P iterated to the fixed
// point of the discrete Riccati equation, then K = (R + Bd'P Bd)^-1 Bd'P Ad.
Matrix lqr_gain(const Matrix& Ad, const Matrix& Bd, const Matrix& Q, const Matrix& R) {
  Matrix P = Q, K;
  for (int it = 0; it < 200000; ++it) {
    const Matrix PA = product(P, Ad, n, n, n), PB = product(P, Bd, n, n, m);
    Matrix S = product(Bd, PB, m, n, m, true);
    for (int k = 0; k < m * m; ++k) S[static_cast<std::size_t>(k)] += R[static_cast<std::size_t>(k)];
    K = solve(S, product(Bd, PA, m, n, n, true), n);
    const Matrix APA = product(Ad, PA, n, n, n, true), APB = product(Ad, PB, n, n, m, true);
    const Matrix correction = product(APB, K, n, m, n);
    double change = 0.0, size = 0.0;
    for (int k = 0; k < n * n; ++k) {
      const double next = Q[static_cast<std::size_t>(k)] + APA[static_cast<std::size_t>(k)] - correction[static_cast<std::size_t>(k)];
      change = std::fmax(change, std::fabs(next - P[static_cast<std::size_t>(k)]));
      size = std::fmax(size, std::fabs(next));
      P[static_cast<std::size_t>(k)] = next;
    }
    if (change <= 1e-12 * size) break;
  }
  return K;
}

}  // namespace

int main(int argc, char** argv) {
  const double* p = arm::kParamDefaults;
  // 1. The pose to hold (kStateNames: the two angles, then their rates) and its torques.
  const State target = {0.4, -0.9, 0.0, 0.0};
  const double zdot0[arm::kNdof] = {};
  Input hold{};
  if (arm::inverse_dynamics(0.0, target.data(), zdot0, p, hold.data()) != 0) return 1;

  // 2. The linear model there: J = (dxdot/dx, n x n | dxdot/du, n x m).
  std::vector<double> J(static_cast<std::size_t>(n * (n + m)));
  if (arm::rhs_jacobian(0.0, target.data(), hold.data(), p, J.data()) != 0) return 1;

  // 3. The gain for the controller's step.
  const double dt = 1e-3;
  Matrix Ad(static_cast<std::size_t>(n * n)), Bd(static_cast<std::size_t>(n * m)), Q(static_cast<std::size_t>(n * n), 0.0),
      R(static_cast<std::size_t>(m * m), 0.0);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) Ad[static_cast<std::size_t>(i * n + j)] = (i == j ? 1.0 : 0.0) + dt * J[static_cast<std::size_t>(i * n + j)];
  for (int k = 0; k < n * m; ++k) Bd[static_cast<std::size_t>(k)] = dt * J[static_cast<std::size_t>(n * n + k)];
  for (int i = 0; i < n; ++i) Q[static_cast<std::size_t>(i * n + i)] = dt * (i < n / 2 ? 100.0 : 1.0);
  for (int i = 0; i < m; ++i) R[static_cast<std::size_t>(i * m + i)] = dt * 0.1;
  const Matrix K = lqr_gain(Ad, Bd, Q, R);

  // 4. Both arms from the same push, 4 s by RK4 at the controller's step.
  auto torques = [&](const State& x, bool feedback) {
    Input u = hold;
    if (feedback)
      for (int i = 0; i < m; ++i)
        for (int j = 0; j < n; ++j) u[static_cast<std::size_t>(i)] -= K[static_cast<std::size_t>(i * n + j)] * (x[static_cast<std::size_t>(j)] - target[static_cast<std::size_t>(j)]);
    return u;
  };
  auto rk4 = [&](State& x, const Input& u) {
    State k[4], y;
    for (int s = 0; s < 4; ++s) {
      for (int i = 0; i < n; ++i)
        y[static_cast<std::size_t>(i)] = x[static_cast<std::size_t>(i)] + (s == 0 ? 0.0 : (s == 3 ? dt : dt / 2)) * k[s == 0 ? 0 : s - 1][static_cast<std::size_t>(i)];
      if (arm::rhs(0.0, y.data(), u.data(), p, k[s].data()) != 0) return false;
    }
    for (int i = 0; i < n; ++i)
      x[static_cast<std::size_t>(i)] += dt / 6 * (k[0][static_cast<std::size_t>(i)] + 2 * k[1][static_cast<std::size_t>(i)] +
                                                  2 * k[2][static_cast<std::size_t>(i)] + k[3][static_cast<std::size_t>(i)]);
    return true;
  };
  std::FILE* out = argc > 1 ? std::fopen(argv[1], "w") : stdout;
  if (!out) return 1;
  std::fprintf(out, "t,%s,%s,%s,%s,open_%s,open_%s\n", arm::kStateNames[0], arm::kStateNames[1], arm::kInputNames[0],
               arm::kInputNames[1], arm::kStateNames[0], arm::kStateNames[1]);
  State controlled = target, open = target;
  controlled[0] += 0.3, controlled[1] -= 0.3, open[0] += 0.3, open[1] -= 0.3;
  double open_departure = 0.0;
  bool ok = true;
  const int steps = 4000;
  for (int k = 0; k <= steps && ok; ++k) {
    const Input u = torques(controlled, true);
    if (k % 20 == 0)
      std::fprintf(out, "%.3f,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n", k * dt, controlled[0], controlled[1], u[0], u[1], open[0],
                   open[1]);
    if (k == steps) break;
    ok = rk4(controlled, u) && rk4(open, hold);
    open_departure = std::fmax(open_departure, std::fabs(open[0] - target[0]) + std::fabs(open[1] - target[1]));
  }
  if (out != stdout) std::fclose(out);
  double settled = 0.0;
  for (int i = 0; i < n; ++i) settled = std::fmax(settled, std::fabs(controlled[static_cast<std::size_t>(i)] - target[static_cast<std::size_t>(i)]));
  std::fprintf(stderr, "lqr_arm: holding torques (%.6g, %.6g) N m; with LQR the arm is %.3g from the pose after 4 s, "
               "without it left the pose by %.3g rad\n", hold[0], hold[1], settled, open_departure);
  return ok && settled < 1e-6 && open_departure > 0.5 ? 0 : 1;
}
