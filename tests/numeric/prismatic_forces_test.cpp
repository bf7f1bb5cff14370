// SPDX-License-Identifier: GPL-2.0-or-later
// The prismatic joint's reaction forces in the multipliers formulation against the
// AMESim paper's vector form ([P] eqs 15-18 and 22), on tests/data/planar/prismatic_pair.mbs
// (a carrier with a slot and a block sliding in it at the fixed relative angle phi, both
// moving), at random consistent states:
//  - reaction_forces() (A^T lambda) equals the generalized forces of eq 16 built from the
//    joint's geometry and the multipliers that multipliers() returns;
//  - with those forces each body obeys Newton-Euler (eq 5) with the accelerations of rhs().
//
// Body i of [P] is the carrier (M the slot's point, x_i1 the unit slot direction,
// y_i1 = z0 x x_i1), body j the block (N its point, x_j1 = R(theta_j - phi) d/|d| fixed in
// it, y_j1 = z0 x x_j1). Mapping of mbsc's rows to the paper's constraints:
//  - guide.normal = d_world x (r_N - r_M) = |d| (MN . y_i1) = |d| f1 of eq 21: the
//    paper's multiplier of f1 is |d| lambda_normal;
//  - guide.angle = theta_j - theta_i - phi. It is the paper's alternative second row
//    f2' = x_j1 . y_i1 (stated after eq 21) up to sin: f2' = sin(theta_j - theta_i - phi),
//    with the same gradient wherever the angle constraint holds, so its multiplier is
//    lambda_angle. (The paper's own f2 = MN . y_j1 is not used by mbsc.)
// Signs: mbsc solves My q1' - A^T lambda = hy, i.e. My q1' = hy + A^T lambda, so A^T lambda
// is the paper's Q of eq 5 (m x'' = Q_x, ...) with lambda_k multiplying df_k/dq (eq 15):
// no sign flip. Gravity is along -y0 in both.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "prismatic_pair_mult/prismatic_pair_mult.hpp"
#include "test_support.hpp"

using mbsc_test::index_of;

namespace {

namespace P = mbsc_gen::prismatic_pair_mult;

struct V2 {
  double x, y;
};
V2 operator+(V2 a, V2 b) { return {a.x + b.x, a.y + b.y}; }
V2 operator-(V2 a, V2 b) { return {a.x - b.x, a.y - b.y}; }
V2 operator*(double s, V2 a) { return {s * a.x, s * a.y}; }
double dot(V2 a, V2 b) { return a.x * b.x + a.y * b.y; }
double cross(V2 a, V2 b) { return a.x * b.y - a.y * b.x; }  // (a x b) . z0
V2 zcross(V2 a) { return {-a.y, a.x}; }                      // z0 x a
V2 rot(double th, V2 a) { return {std::cos(th) * a.x - std::sin(th) * a.y, std::sin(th) * a.x + std::cos(th) * a.y}; }
double norm(V2 a) { return std::sqrt(dot(a, a)); }

// Geometry of tests/data/planar/prismatic_pair.mbs in body coordinates, relative to each
// body's mass centre (point - com).
const V2 kSlotPoint{0.1 - 0.15, -0.05 - 0.05}, kSlotDir{2.0, 1.0}, kSpringPoint{0.5 - 0.15, 0.2 - 0.05};
const V2 kBlockPoint{-0.1 - 0.02, 0.08 + 0.03}, kAnchor{0.2, 1.0};

double par(const char* n) { return P::kParamDefaults[index_of(P::kParamNames, P::kNp, n)]; }
std::size_t ix(const char* n) { return static_cast<std::size_t>(index_of(P::kStateNames, P::kNx, n)); }

/// Generalized forces (Q_x, Q_y, Q_theta) on one body from a force F at a point at GM from
/// its mass centre and a torque C_z ([P] eqs 9 and 18).
struct Q3 {
  double x, y, th;
};
Q3 generalized(V2 F, double Cz, V2 GM) { return {F.x, F.y, Cz + dot(F, zcross(GM))}; }

}  // namespace

TEST_CASE("prismatic joint: reaction forces are [P]'s lambda * df/dq, and Newton-Euler holds",
          "[numeric][planar][prismatic]") {
  REQUIRE(P::kNc == 2);
  REQUIRE(std::string(P::kConstraintNames[0]) == "guide.normal");
  REQUIRE(std::string(P::kConstraintNames[1]) == "guide.angle");
  const double m1 = par("m1"), J1 = par("J1"), m2 = par("m2"), J2 = par("J2"), k = par("k"), phi = par("phi"),
               g = par("g");
  std::mt19937 rng(53);
  std::uniform_real_distribution<double> pos(-1.0, 1.0), ang(-3.1, 3.1), slide(-0.8, 0.8), rate(-4.0, 4.0);
  for (int trial = 0; trial < 20; ++trial) {
    // A consistent state: the carrier anywhere, the block's point on the slot at arc
    // parameter s (r_N = r_M + s d_world), turned by phi from the carrier.
    const V2 G1{pos(rng), pos(rng)};
    const double th1 = ang(rng), th2 = th1 + phi, s = slide(rng);
    const V2 v1{rate(rng), rate(rng)};
    const double w1 = rate(rng), w2 = w1, sdot = rate(rng);
    const V2 GM = rot(th1, kSlotPoint), D = rot(th1, kSlotDir), M = G1 + GM;
    const V2 N = M + s * D, NG2 = rot(th2, kBlockPoint), G2 = N - NG2;
    // v_N = v_M + s' d + s w1 (z0 x d); v_G2 = v_N - w2 (z0 x (r_N - r_G2)).
    const V2 vM = v1 + w1 * zcross(GM), vN = vM + sdot * D + s * w1 * zcross(D), v2 = vN - w2 * zcross(NG2);
    std::vector<double> x(P::kNx, 0.0);
    x[ix("carrier.x")] = G1.x, x[ix("carrier.y")] = G1.y, x[ix("carrier.theta")] = th1;
    x[ix("block.x")] = G2.x, x[ix("block.y")] = G2.y, x[ix("block.theta")] = th2;
    x[ix("carrier.u")] = v1.x, x[ix("carrier.v")] = v1.y, x[ix("carrier.w")] = w1;
    x[ix("block.u")] = v2.x, x[ix("block.v")] = v2.y, x[ix("block.w")] = w2;
    std::vector<double> pc(P::kNposc), vc(P::kNc);
    REQUIRE(P::position_constraints(0.0, x.data(), nullptr, P::kParamDefaults, pc.data()) == 0);
    REQUIRE(P::velocity_constraints(0.0, x.data(), nullptr, P::kParamDefaults, vc.data()) == 0);
    for (double r : pc) REQUIRE(std::abs(r) < 1e-13);
    for (double r : vc) REQUIRE(std::abs(r) < 1e-12);

    std::vector<double> lambda(P::kNc), R(P::kNu), xd(P::kNx);
    REQUIRE(P::multipliers(0.0, x.data(), nullptr, P::kParamDefaults, lambda.data()) == 0);
    REQUIRE(P::reaction_forces(0.0, x.data(), nullptr, P::kParamDefaults, R.data()) == 0);
    REQUIRE(P::rhs(0.0, x.data(), nullptr, P::kParamDefaults, xd.data()) == 0);

    // [P]'s axes and multipliers.
    const V2 xi1 = (1.0 / norm(D)) * D, yi1 = zcross(xi1);
    const V2 xj1 = rot(th2 - phi, (1.0 / norm(kSlotDir)) * kSlotDir);
    const double L1 = norm(D) * lambda[0];  // multiplier of f1 = MN . y_i1
    const double L2 = lambda[1];            // multiplier of f2' = x_j1 . y_i1
    const V2 MN = N - M;
    // Eq 22, the lambda_1 terms (f1 of eq 21):
    //   F_i = -L1 y_i1, C_zi = -L1 [(ON - OM) x y_i1] . z0;  F_j = L1 y_i1, C_zj = 0.
    // Eq 17 for f2' (df/dy_i1 = x_j1, df/dx_j1 = y_i1, no dependence on OM, ON):
    //   F = 0, C_zi = -L2 (x_j1 x y_i1) . z0, C_zj = -L2 (y_i1 x x_j1) . z0.
    const V2 Fi = -L1 * yi1, Fj = L1 * yi1;
    const double Czi = -L1 * cross(MN, yi1) - L2 * cross(xj1, yi1);
    const double Czj = -L2 * cross(yi1, xj1);
    // Eq 16 = eq 17 + eq 18: the moments of the forces about the mass centres.
    const Q3 Qi = generalized(Fi, Czi, GM), Qj = generalized(Fj, Czj, N - G2);

    const double scale = std::max({1.0, std::abs(Qi.x), std::abs(Qi.y), std::abs(Qi.th), std::abs(Qj.x), std::abs(Qj.y),
                                   std::abs(Qj.th)});
    auto r = [&](const char* n) { return R[ix(n) - P::kNq]; };
    CHECK(std::abs(r("carrier.u") - Qi.x) < 1e-10 * scale);
    CHECK(std::abs(r("carrier.v") - Qi.y) < 1e-10 * scale);
    CHECK(std::abs(r("carrier.w") - Qi.th) < 1e-10 * scale);
    CHECK(std::abs(r("block.u") - Qj.x) < 1e-10 * scale);
    CHECK(std::abs(r("block.v") - Qj.y) < 1e-10 * scale);
    CHECK(std::abs(r("block.w") - Qj.th) < 1e-10 * scale);

    // Newton-Euler with the paper's forces ([P] eq 5): the block carries only the joint's
    // action and its weight; the carrier also the zero-length spring F = -k (r_T - anchor).
    const V2 GT = rot(th1, kSpringPoint), Fs = -k * (G1 + GT - kAnchor);
    const double f_scale = std::max({scale, m1 * g, m2 * g, k * norm(G1 + GT - kAnchor)});
    CHECK(std::abs(m2 * xd[ix("block.u")] - Qj.x) < 1e-10 * f_scale);
    CHECK(std::abs(m2 * xd[ix("block.v")] - (Qj.y - m2 * g)) < 1e-10 * f_scale);
    CHECK(std::abs(J2 * xd[ix("block.w")] - Qj.th) < 1e-10 * f_scale);
    CHECK(std::abs(m1 * xd[ix("carrier.u")] - (Qi.x + Fs.x)) < 1e-10 * f_scale);
    CHECK(std::abs(m1 * xd[ix("carrier.v")] - (Qi.y + Fs.y - m1 * g)) < 1e-10 * f_scale);
    CHECK(std::abs(J1 * xd[ix("carrier.w")] - (Qi.th + dot(Fs, zcross(GT)))) < 1e-10 * f_scale);
  }
}
