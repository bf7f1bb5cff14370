// SPDX-License-Identifier: GPL-2.0-or-later
// The spatial S-S-S-P mechanism of models/sssp.mbs against thesis Examples 2.2-2.4:
//  - 2 degrees of freedom (Ex 2.2);
//  - the rank of the constraint matrix A: full (11 = 6 midpoint rows + the thesis's 5)
//    at generic configurations, one less at the four singular configurations (d) of
//    Ex 2.2; in the variant of Ex 2.3 (l1 = 1, l2 = 2, prismatic axis y = 1) one less at
//    its two symmetric configurations and two less at the third;
//  - Ex 2.4: the independent speeds (z1', x2') are regular while y1 != 0; at y1 = 0 (a
//    regular configuration of the mechanism) the complement form's solve is singular
//    (status 1) while the multipliers form, which needs no independent set, still solves;
//  - complement, multipliers and --state minimal give the same accelerations at random
//    assembled states (1e-9), and energy is conserved over a run;
//  - the same mechanism built from rigid3d rods on spherical joints and a prismatic joint
//    (tests/data/rigid3d/sssp_rigid.mbs), started without spin, gives the same
//    accelerations of p1 and of the slider: the spatial joints against the thesis's
//    invariants, and the point-mass rods against rigid slender ones.
#include <catch2/catch.hpp>
#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "mbsc/runtime/dop853.hpp"
#include "mbsc/runtime/model_table.hpp"
#include "sssp/sssp.hpp"
#include "sssp_min/sssp_min.hpp"
#include "sssp_mult/sssp_mult.hpp"
#include "sssp_rigid/sssp_rigid.hpp"
#include "test_support.hpp"

using mbsc::runtime::ModelTable;
using mbsc_test::index_of;
namespace S = mbsc_gen::sssp;

namespace {

const ModelTable kFull = MBSC_MODEL_TABLE(S);
const ModelTable kMult = MBSC_MODEL_TABLE_MULTIPLIERS(mbsc_gen::sssp_mult);
const ModelTable kMin = MBSC_MODEL_TABLE(mbsc_gen::sssp_min);

struct Config {  // the thesis's coordinates and their rates
  double x1, y1, z1, x2, y2, z2, theta;
  double dx1 = 0, dy1 = 0, dz1 = 0, dx2 = 0, dtheta = 0;
};

std::vector<double> params(const ModelTable& M, double l1, double l2, double h) {
  std::vector<double> p(M.param_defaults, M.param_defaults + M.np);
  p[static_cast<std::size_t>(index_of(M.param_names, M.np, "l1"))] = l1;
  p[static_cast<std::size_t>(index_of(M.param_names, M.np, "l2"))] = l2;
  p[static_cast<std::size_t>(index_of(M.param_names, M.np, "h"))] = h;
  return p;
}

/// The model's state for a configuration (midpoints and their rates follow).
std::vector<double> state(const ModelTable& M, const Config& c) {
  std::vector<double> x(static_cast<std::size_t>(M.nx), 0.0);
  auto put = [&](const char* name, double v) {
    const int i = ModelTable::find(M.state_names, M.nx, name);
    if (i >= 0) x[static_cast<std::size_t>(i)] = v;
  };
  put("tip1.x", c.x1), put("tip1.y", c.y1), put("tip1.z", c.z1);
  put("slider.x", c.x2), put("slider.y", c.y2), put("slider.z", c.z2);
  put("mid1.x", c.x1 / 2), put("mid1.y", c.y1 / 2), put("mid1.z", c.z1 / 2);
  put("mid2.x", (c.x1 + c.x2) / 2), put("mid2.y", (c.y1 + c.y2) / 2), put("mid2.z", (c.z1 + c.z2) / 2);
  put("theta", c.theta);
  put("tip1.u", c.dx1), put("tip1.v", c.dy1), put("tip1.w", c.dz1);
  put("slider.u", c.dx2);
  put("mid1.u", c.dx1 / 2), put("mid1.v", c.dy1 / 2), put("mid1.w", c.dz1 / 2);
  put("mid2.u", (c.dx1 + c.dx2) / 2), put("mid2.v", c.dy1 / 2), put("mid2.w", c.dz1 / 2);
  put("dtheta", c.dtheta);
  return x;
}

/// An assembled configuration of Ex 2.2 (axis through p0): given x2, z1 and the sign of
/// y1, and the independent rates z1', x2', everything else follows from the invariants.
Config assembled(double l1, double l2, double x2, double z1, double sign_y1, double dz1, double dx2) {
  Config c{};
  c.x2 = x2, c.y2 = 0, c.z2 = 0, c.z1 = z1;
  c.x1 = (l1 * l1 - l2 * l2 + x2 * x2) / (2 * x2);  // 2 p1.p2 = l1^2 - l2^2 + |p2|^2
  c.y1 = sign_y1 * std::sqrt(l1 * l1 - c.x1 * c.x1 - z1 * z1);
  c.theta = std::acos((x2 * x2 - l1 * l1 - l2 * l2) / (2 * l1 * l2));
  c.dz1 = dz1, c.dx2 = dx2;
  c.dx1 = (x2 - c.x1) * dx2 / x2;                    // from rows 1 and 2
  c.dy1 = -(c.x1 * c.dx1 + z1 * dz1) / c.y1;          // row 1
  c.dtheta = -x2 * dx2 / (l1 * l2 * std::sin(c.theta));  // row 5
  return c;
}

/// Numeric rank of the kNc x kNu matrix A (Gaussian elimination, full pivoting).
int rank_of(std::vector<double> A, int rows, int cols) {
  double scale = 0;
  for (double v : A) scale = std::max(scale, std::fabs(v));
  int r = 0;
  for (int col = 0; col < cols && r < rows; ++col) {
    int best = r;
    for (int i = r; i < rows; ++i)
      if (std::fabs(A[static_cast<std::size_t>(i * cols + col)]) > std::fabs(A[static_cast<std::size_t>(best * cols + col)])) best = i;
    if (std::fabs(A[static_cast<std::size_t>(best * cols + col)]) <= 1e-10 * scale) continue;
    for (int j = 0; j < cols; ++j) std::swap(A[static_cast<std::size_t>(r * cols + j)], A[static_cast<std::size_t>(best * cols + j)]);
    for (int i = r + 1; i < rows; ++i) {
      const double f = A[static_cast<std::size_t>(i * cols + col)] / A[static_cast<std::size_t>(r * cols + col)];
      for (int j = col; j < cols; ++j) A[static_cast<std::size_t>(i * cols + j)] -= f * A[static_cast<std::size_t>(r * cols + j)];
    }
    ++r;
  }
  return r;
}

int rank_at(const Config& c, const std::vector<double>& p) {
  const auto x = state(kFull, c);
  std::vector<double> A(static_cast<std::size_t>(S::kNc * S::kNuFull));
  REQUIRE(S::constraint_jacobian(0.0, x.data(), nullptr, p.data(), A.data()) == 0);
  std::vector<double> r(static_cast<std::size_t>(S::kNposc));
  REQUIRE(S::position_constraints(0.0, x.data(), nullptr, p.data(), r.data()) == 0);
  for (double v : r) REQUIRE(std::fabs(v) < 1e-12);  // the configuration is assembled
  return rank_of(A, S::kNc, S::kNuFull);
}

double speed_rate(const ModelTable& M, const std::vector<double>& xd, const char* name) {
  return xd[static_cast<std::size_t>(index_of(M.state_names, M.nx, name))];
}

}  // namespace

TEST_CASE("sssp: 2 degrees of freedom (thesis Ex 2.2)", "[numeric][sssp]") {
  CHECK(S::kNdof == 2);
  CHECK(S::kNc == 11);
  CHECK(std::string(S::kDofNames[0]) == "tip1.w");  // Ex 2.4's independent z1', x2'
  CHECK(std::string(S::kDofNames[1]) == "slider.u");
}

TEST_CASE("sssp: singular configurations of Ex 2.2 and Ex 2.3 by the rank of A", "[numeric][sssp]") {
  const double l1 = 1, l2 = 2;
  const auto p = params(kFull, l1, l2, 0);
  // Generic: full rank.
  CHECK(rank_at(assembled(l1, l2, 2.2, 0.4, 1, 0, 0), p) == 11);
  CHECK(rank_at(assembled(l1, l2, -1.7, -0.2, -1, 0, 0), p) == 11);
  // Ex 2.2 (d): sin(theta) = 0, the rods in line along x: rank 4 of the thesis's 5 rows.
  const double pi = std::acos(-1.0);
  for (const Config& c : {Config{l1, 0, 0, l1 + l2, 0, 0, 0}, Config{-l1, 0, 0, -l1 - l2, 0, 0, 0},
                          Config{l1, 0, 0, l1 - l2, 0, 0, pi}, Config{-l1, 0, 0, -l1 + l2, 0, 0, pi}}) {
    INFO("x1 = " << c.x1 << " x2 = " << c.x2 << " theta = " << c.theta);
    CHECK(rank_at(c, p) == 10);
  }
  // Ex 2.3: the axis y = 1, z = 0; the two symmetric configurations lose one rank, the
  // third (p1 = (0, -1, 0), p2 = (0, 1, 0), rods folded) two.
  const auto p3 = params(kFull, 1, 2, 1);
  const double r8 = std::sqrt(8.0);
  CHECK(rank_at(Config{-r8 / 3, 1.0 / 3, 0, -r8, 1, 0, 0}, p3) == 10);
  CHECK(rank_at(Config{r8 / 3, 1.0 / 3, 0, r8, 1, 0, 0}, p3) == 10);
  CHECK(rank_at(Config{0, -1, 0, 0, 1, 0, pi}, p3) == 9);
  // A regular configuration of the variant: full rank (p1 on both spheres, off the plane z = 0).
  {
    const double x2 = 1.5, c = (1 - 4 + x2 * x2 + 1) / 2;  // x1 x2 + y1 = c (2 p1.p2 = l1^2 - l2^2 + |p2|^2)
    const double x1 = 0.3, y1 = c - x1 * x2, z1 = std::sqrt(1 - x1 * x1 - y1 * y1);
    const double theta = std::acos((x2 * x2 + 1 - 1 - 4) / 4);
    CHECK(rank_at(Config{x1, y1, z1, x2, 1, 0, theta}, p3) == 11);
  }
}

TEST_CASE("sssp: Ex 2.4's independent speeds fail only where y1 = 0", "[numeric][sssp]") {
  const double l1 = 1, l2 = 2;
  const auto p = params(kFull, l1, l2, 0);
  const auto pm = params(kMult, l1, l2, 0);
  // y1 = 0 with z1 != 0: x1 = (1 - 4 + x2^2) / (2 x2), z1 = sqrt(1 - x1^2).
  const double x2 = 2.2, x1 = (l1 * l1 - l2 * l2 + x2 * x2) / (2 * x2);
  const Config c{x1, 0, std::sqrt(1 - x1 * x1), x2, 0, 0, std::acos((x2 * x2 - 5) / 4)};
  CHECK(rank_at(c, p) == 11);  // the mechanism is regular there
  std::vector<double> xd(static_cast<std::size_t>(S::kNx));
  CHECK(S::rhs(0.0, state(kFull, c).data(), nullptr, p.data(), xd.data()) == 1);
  std::vector<double> xdm(static_cast<std::size_t>(kMult.nx));
  CHECK(kMult.rhs(0.0, state(kMult, c).data(), nullptr, pm.data(), xdm.data()) == 0);
  // Next to it (y1 != 0) the complement form solves again.
  CHECK(S::rhs(0.0, state(kFull, assembled(l1, l2, x2, c.z1 - 0.01, 1, 0.3, 0.2)).data(), nullptr, p.data(), xd.data()) == 0);
}

TEST_CASE("sssp: complement, multipliers and minimal state agree at random assembled states", "[numeric][sssp]") {
  std::mt19937 rng(22);
  std::uniform_real_distribution<double> u(-1, 1);
  const double l1 = 1, l2 = 2;
  int compared = 0;
  for (int trial = 0; trial < 20; ++trial) {
    // x2 in (1, 3) or (-3, -1) (|l2 - l1| < |x2| < l1 + l2), z1 inside the circle.
    const double x2 = (trial % 2 ? 1 : -1) * (1.2 + 1.6 * (u(rng) + 1) / 2);
    const double x1 = (l1 * l1 - l2 * l2 + x2 * x2) / (2 * x2);
    const double z1 = 0.8 * u(rng) * std::sqrt(l1 * l1 - x1 * x1);
    const Config c = assembled(l1, l2, x2, z1, u(rng) > 0 ? 1 : -1, 2 * u(rng), 2 * u(rng));
    std::vector<double> out[3];
    const ModelTable* models[3] = {&kFull, &kMult, &kMin};
    for (int k = 0; k < 3; ++k) {
      const auto p = params(*models[k], l1, l2, 0);
      const auto x = state(*models[k], c);
      out[k].resize(x.size());
      REQUIRE(models[k]->rhs(0.0, x.data(), nullptr, p.data(), out[k].data()) == 0);
    }
    INFO("trial " << trial << " x2 = " << x2 << " z1 = " << z1);
    for (const char* name : {"tip1.w", "slider.u"}) {
      const double a = speed_rate(kFull, out[0], name);
      CHECK(std::fabs(speed_rate(kMult, out[1], name) - a) < 1e-9 * (1 + std::fabs(a)));
      CHECK(std::fabs(speed_rate(kMin, out[2], name) - a) < 1e-9 * (1 + std::fabs(a)));
      ++compared;
    }
    for (const char* name : {"tip1.u", "tip1.v", "dtheta"}) {
      const double a = speed_rate(kFull, out[0], name);
      CHECK(std::fabs(speed_rate(kMult, out[1], name) - a) < 1e-9 * (1 + std::fabs(a)));
    }
  }
  CHECK(compared == 40);
}

TEST_CASE("sssp: energy is conserved", "[numeric][sssp]") {
  const auto p = params(kFull, 1, 2, 0);
  auto x = state(kFull, assembled(1, 2, 2.2, 0.6, 1, 0.5, -0.4));
  mbsc::runtime::StepperOptions o;
  o.rtol = o.atol = 1e-12;
  auto rhs = [&](double t, const double* s, double* sd) { return S::rhs(t, s, nullptr, p.data(), sd); };
  mbsc::runtime::Dop853 stepper(rhs, S::kNx, o);
  REQUIRE(stepper.reset(0.0, x) == mbsc::runtime::Stepper::Status::Ok);
  std::array<double, 3> e0{}, e{};
  REQUIRE(S::energy(0.0, x.data(), nullptr, p.data(), e0.data()) == 0);
  double worst = 0, lowest = e0[1];
  std::vector<double> s(x.size());
  while (stepper.t() < 1.0) {
    REQUIRE(stepper.step(1.0) == mbsc::runtime::Stepper::Status::Ok);
    stepper.interpolate(stepper.t(), s);
    REQUIRE(S::energy(stepper.t(), s.data(), nullptr, p.data(), e.data()) == 0);
    worst = std::max(worst, std::fabs(e[2] - e0[2]));
    lowest = std::min(lowest, e[1]);
  }
  INFO("energy drift " << worst << ", potential fell by " << e0[1] - lowest);
  CHECK(worst < 1e-8 * std::fabs(e0[2]));
  CHECK(e0[1] - lowest > 1.0);  // the mechanism falls: energy really moves
}

namespace {

namespace SR = mbsc_gen::sssp_rigid;
using V3 = std::array<double, 3>;
V3 cross3(const V3& a, const V3& b) { return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}; }

/// A rigid rod from a to b (length l) turning without spin: quaternion taking x to the
/// rod's direction n by the shortest turn, mass centre and its velocity, body-frame rates.
void put_rod(std::vector<double>& x, const std::string& rod, const V3& a, const V3& b, const V3& va, const V3& vb, double l) {
  auto at = [&](const std::string& n) -> double& { return x[static_cast<std::size_t>(index_of(SR::kStateNames, SR::kNx, rod + "." + n))]; };
  const V3 n{(b[0] - a[0]) / l, (b[1] - a[1]) / l, (b[2] - a[2]) / l};
  // Shortest turn from x to n: axis x cross n = (0, -n_z, n_y), angle acos(n_x).
  const double half = std::acos(n[0]) / 2, s = std::hypot(n[1], n[2]);
  const double e0 = std::cos(half), e1 = 0, e2 = s > 0 ? -n[2] / s * std::sin(half) : 0, e3 = s > 0 ? n[1] / s * std::sin(half) : 0;
  at("e0") = e0, at("e1") = e1, at("e2") = e2, at("e3") = e3;
  const V3 dv{(vb[0] - va[0]) / l, (vb[1] - va[1]) / l, (vb[2] - va[2]) / l};
  const V3 w = cross3(n, dv);  // no spin: w . n = 0
  // Body-frame rates R^T w with R of the unit quaternion.
  const double R[3][3] = {{1 - 2 * (e2 * e2 + e3 * e3), 2 * (e1 * e2 - e0 * e3), 2 * (e1 * e3 + e0 * e2)},
                          {2 * (e1 * e2 + e0 * e3), 1 - 2 * (e1 * e1 + e3 * e3), 2 * (e2 * e3 - e0 * e1)},
                          {2 * (e1 * e3 - e0 * e2), 2 * (e2 * e3 + e0 * e1), 1 - 2 * (e1 * e1 + e2 * e2)}};
  const char* wn[3] = {"wx", "wy", "wz"};
  const char* cn[3] = {"x", "y", "z"};
  const char* vn[3] = {"u", "v", "w"};
  for (int i = 0; i < 3; ++i) {
    double wb = 0;
    for (int k = 0; k < 3; ++k) wb += R[k][i] * w[static_cast<std::size_t>(k)];
    at(wn[i]) = wb;
    at(cn[i]) = (a[static_cast<std::size_t>(i)] + b[static_cast<std::size_t>(i)]) / 2;
    at(vn[i]) = (va[static_cast<std::size_t>(i)] + vb[static_cast<std::size_t>(i)]) / 2;
  }
}

}  // namespace

TEST_CASE("sssp: rigid3d rods on spatial joints give the same motion", "[numeric][sssp]") {
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> u(-1, 1);
  const double l1 = 1, l2 = 2;
  const auto p = params(kFull, l1, l2, 0);
  for (int trial = 0; trial < 10; ++trial) {
    const double x2 = (trial % 2 ? 1 : -1) * (1.2 + 1.6 * (u(rng) + 1) / 2);
    const double x1 = (l1 * l1 - l2 * l2 + x2 * x2) / (2 * x2);
    const double z1 = 0.8 * u(rng) * std::sqrt(l1 * l1 - x1 * x1);
    const Config c = assembled(l1, l2, x2, z1, u(rng) > 0 ? 1 : -1, 2 * u(rng), 2 * u(rng));
    std::vector<double> xs = state(kFull, c), xsd(xs.size());
    REQUIRE(S::rhs(0.0, xs.data(), nullptr, p.data(), xsd.data()) == 0);
    std::vector<double> xr(static_cast<std::size_t>(SR::kNx), 0.0), xrd(xr.size());
    const V3 p0{0, 0, 0}, p1{c.x1, c.y1, c.z1}, p2{c.x2, 0, 0};
    const V3 v0{0, 0, 0}, v1{c.dx1, c.dy1, c.dz1}, v2{c.dx2, 0, 0};
    put_rod(xr, "rod1", p0, p1, v0, v1, l1);
    put_rod(xr, "rod2", p1, p2, v1, v2, l2);
    xr[static_cast<std::size_t>(index_of(SR::kStateNames, SR::kNx, "slider.e0"))] = 1;
    xr[static_cast<std::size_t>(index_of(SR::kStateNames, SR::kNx, "slider.x"))] = c.x2;
    xr[static_cast<std::size_t>(index_of(SR::kStateNames, SR::kNx, "slider.u"))] = c.dx2;
    std::vector<double> r(static_cast<std::size_t>(SR::kNc));
    REQUIRE(SR::velocity_constraints(0.0, xr.data(), nullptr, SR::kParamDefaults, r.data()) == 0);
    for (double v : r) REQUIRE(std::fabs(v) < 1e-12);  // the rigid state is consistent
    REQUIRE(SR::rhs(0.0, xr.data(), nullptr, SR::kParamDefaults, xrd.data()) == 0);
    auto rigid = [&](const char* n) { return xrd[static_cast<std::size_t>(index_of(SR::kStateNames, SR::kNx, n))]; };
    INFO("trial " << trial);
    // p1 = 2 x_rod1 (rod 1 starts at the origin): z1'' = 2 rod1.w'; x2'' = slider.u'.
    CHECK(2 * rigid("rod1.w") == Approx(speed_rate(kFull, xsd, "tip1.w")).epsilon(1e-9).margin(1e-9));
    CHECK(2 * rigid("rod1.u") == Approx(speed_rate(kFull, xsd, "tip1.u")).epsilon(1e-9).margin(1e-9));
    CHECK(2 * rigid("rod1.v") == Approx(speed_rate(kFull, xsd, "tip1.v")).epsilon(1e-9).margin(1e-9));
    CHECK(rigid("slider.u") == Approx(speed_rate(kFull, xsd, "slider.u")).epsilon(1e-9).margin(1e-9));
    // No spin is started: the rods' axial rates stay 0.
    CHECK(std::fabs(rigid("rod1.wx")) < 1e-9);
    CHECK(std::fabs(rigid("rod2.wx")) < 1e-9);
  }
}
