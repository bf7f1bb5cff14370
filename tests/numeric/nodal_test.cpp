// SPDX-License-Identifier: GPL-2.0-or-later
// The two parametrizations of a planar rigid body give the same mechanism: the four-bar
// of tests/data/planar/four_bar_joints.mbs (absolute: each bar's mass centre and angle)
// and tests/data/planar/four_bar_nodal.mbs (the same bars as rigid2d_nodal: the world
// positions of their points). A state of the first maps onto the second (node positions
// and velocities from the rigid motion); at such states the angular accelerations and
// every node's acceleration agree, and so does the energy. Over a run, the nodal model
// keeps its rigidity invariants and conserves energy (motor torque off), and its
// multipliers form follows its complement form.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "four_bar_joints/four_bar_joints.hpp"
#include "four_bar_nodal/four_bar_nodal.hpp"
#include "four_bar_nodal_mult/four_bar_nodal_mult.hpp"
#include "rail_block/rail_block.hpp"
#include "rail_block_nodal/rail_block_nodal.hpp"
#include "mbsc/runtime/assemble.hpp"
#include "mbsc/runtime/rk4.hpp"
#include "test_support.hpp"

namespace A = mbsc_gen::four_bar_joints;
namespace N = mbsc_gen::four_bar_nodal;
namespace NM = mbsc_gen::four_bar_nodal_mult;
using mbsc_test::index_of;

namespace {

double param(const char* n) { return A::kParamDefaults[index_of(A::kParamNames, A::kNp, n)]; }

struct BodyPoint {
  const char* body;
  const char* point;
  double bx, by;  // body coordinates (the models' frames start at the first point)
};

std::vector<BodyPoint> points() {
  const double a = param("a"), b = param("b"), c = param("c");
  return {{"crank", "O", 0, 0},   {"crank", "A", a, 0},     {"coupler", "A", 0, 0}, {"coupler", "B", b, 0},
          {"coupler", "T", b / 2, 0.2}, {"rocker", "Q", 0, 0}, {"rocker", "B", c, 0}};
}

double com_of(const std::string& body) { return body == "crank" ? param("a") / 2 : body == "coupler" ? param("b") / 2 : param("c") / 2; }

/// The two layouts of one mechanism: absolute state names and nodal state names.
struct Layouts {
  const char* const* abs_names;
  int abs_nx;
  const char* const* nodal_names;
  int nodal_nx;
};

/// Absolute state (and optionally its derivative) -> nodal state (and derivative), for
/// the given points and mass-centre offsets along each body's x axis.
std::vector<double> map_to_nodal(const Layouts& L, const std::vector<BodyPoint>& pts, double (*com)(const std::string&),
                                 const std::vector<double>& xa, const std::vector<double>* xda, std::vector<double>* xdn) {
  auto ga = [&](const std::vector<double>& v, const std::string& n) {
    return v[static_cast<std::size_t>(index_of(L.abs_names, L.abs_nx, n))];
  };
  std::vector<double> xn(static_cast<std::size_t>(L.nodal_nx), 0.0);
  if (xdn) xdn->assign(static_cast<std::size_t>(L.nodal_nx), 0.0);
  auto setn = [&](std::vector<double>& v, const std::string& n, double value) {
    v[static_cast<std::size_t>(index_of(L.nodal_names, L.nodal_nx, n))] = value;
  };
  for (const auto& p : pts) {
    const std::string b = p.body;
    const double x = ga(xa, b + ".x"), y = ga(xa, b + ".y"), th = ga(xa, b + ".theta");
    const double u = ga(xa, b + ".u"), v = ga(xa, b + ".v"), w = ga(xa, b + ".w");
    const double ex = p.bx - com(b), ey = p.by;  // from the mass centre, body frame
    const double rx = std::cos(th) * ex - std::sin(th) * ey, ry = std::sin(th) * ex + std::cos(th) * ey;
    const std::string q = b + "." + p.point;
    setn(xn, q + "_x", x + rx);
    setn(xn, q + "_y", y + ry);
    setn(xn, q + "_u", u - w * ry);
    setn(xn, q + "_v", v + w * rx);
    setn(xn, b + ".w", w);
    if (xda && xdn) {
      // a_P = a_c + alpha z x r - w^2 r
      const double au = ga(*xda, b + ".u"), av = ga(*xda, b + ".v"), al = ga(*xda, b + ".w");
      setn(*xdn, q + "_u", au - al * ry - w * w * rx);
      setn(*xdn, q + "_v", av + al * rx - w * w * ry);
      setn(*xdn, b + ".w", al);
    }
  }
  return xn;
}

std::vector<double> to_nodal(const std::vector<double>& xa, const std::vector<double>* xda, std::vector<double>* xdn) {
  return map_to_nodal({A::kStateNames, A::kNx, N::kStateNames, N::kNx}, points(), com_of, xa, xda, xdn);
}

}  // namespace

TEST_CASE("nodal and absolute four-bars are the same mechanism", "[numeric][nodal]") {
  REQUIRE(N::kNdof == A::kNdof);
  const auto model = MBSC_TEST_ASSEMBLY_MODEL(A);
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI), rate(-4.0, 4.0);
  for (int k = 0; k < 20; ++k) {
    std::vector<double> xa(A::kNx, 0.0);
    auto ix = [](const char* n) { return static_cast<std::size_t>(index_of(A::kStateNames, A::kNx, n)); };
    xa[ix("crank.theta")] = angle(rng);
    xa[ix("coupler.theta")] = 0.3;
    xa[ix("rocker.theta")] = 1.6;
    xa[ix("coupler.x")] = 0.5;
    xa[ix("coupler.y")] = 0.6;
    xa[ix("rocker.x")] = 0.9;
    xa[ix("rocker.y")] = 0.4;
    xa[ix("crank.w")] = rate(rng);
    std::vector<bool> gq(A::kNq, false), gu(A::kNu, false);
    gq[ix("crank.theta")] = true;
    gu[ix("crank.w") - A::kNq] = true;
    const auto r = mbsc::runtime::assemble(model, 0.0, xa, gq, gu, nullptr, A::kParamDefaults);
    INFO(r.message);
    REQUIRE(r.ok());
    std::vector<double> xda(A::kNx);
    REQUIRE(A::rhs(0.0, xa.data(), nullptr, A::kParamDefaults, xda.data()) == 0);
    std::vector<double> expected;
    const auto xn = to_nodal(xa, &xda, &expected);
    // The mapped state satisfies the nodal model's own invariants.
    std::vector<double> g(N::kNposc), v(N::kNc);
    REQUIRE(N::position_constraints(0.0, xn.data(), nullptr, N::kParamDefaults, g.data()) == 0);
    REQUIRE(N::velocity_constraints(0.0, xn.data(), nullptr, N::kParamDefaults, v.data()) == 0);
    for (double e : g) REQUIRE(std::abs(e) < 1e-10);
    for (double e : v) REQUIRE(std::abs(e) < 1e-10);
    std::vector<double> xdn(N::kNx);
    REQUIRE(N::rhs(0.0, xn.data(), nullptr, N::kParamDefaults, xdn.data()) == 0);
    double scale = 1.0;
    for (double e : expected) scale = std::max(scale, std::abs(e));
    for (int i = N::kNq; i < N::kNx; ++i) {
      INFO(N::kStateNames[i]);
      CHECK(std::abs(xdn[static_cast<std::size_t>(i)] - expected[static_cast<std::size_t>(i)]) < 1e-9 * scale);
    }
    double ea[3], en[3];
    REQUIRE(A::energy(0.0, xa.data(), nullptr, A::kParamDefaults, ea) == 0);
    REQUIRE(N::energy(0.0, xn.data(), nullptr, N::kParamDefaults, en) == 0);
    CHECK(std::abs(ea[0] - en[0]) < 1e-12 * std::max(1.0, ea[0]));
    CHECK(std::abs(ea[1] - en[1]) < 1e-12 * std::max(1.0, std::abs(ea[1])));
  }
}

TEST_CASE("nodal four-bar: rigidity and energy along a run; multipliers agree", "[numeric][nodal]") {
  // Start from a mapped consistent state; motor torque off, so energy is conserved.
  std::vector<double> pa(A::kParamDefaults, A::kParamDefaults + A::kNp);
  pa[static_cast<std::size_t>(index_of(A::kParamNames, A::kNp, "tau"))] = 0.0;
  std::vector<double> xa(A::kNx, 0.0);
  auto ix = [](const char* n) { return static_cast<std::size_t>(index_of(A::kStateNames, A::kNx, n)); };
  xa[ix("crank.theta")] = 1.0;
  xa[ix("coupler.theta")] = 0.3;
  xa[ix("rocker.theta")] = 1.6;
  xa[ix("coupler.x")] = 0.5;
  xa[ix("coupler.y")] = 0.6;
  xa[ix("rocker.x")] = 0.9;
  xa[ix("rocker.y")] = 0.4;
  xa[ix("crank.w")] = 2.0;
  std::vector<bool> gq(A::kNq, false), gu(A::kNu, false);
  gq[ix("crank.theta")] = true;
  gu[ix("crank.w") - A::kNq] = true;
  REQUIRE(mbsc::runtime::assemble(MBSC_TEST_ASSEMBLY_MODEL(A), 0.0, xa, gq, gu, nullptr, pa.data()).ok());
  auto x = to_nodal(xa, nullptr, nullptr);
  auto xm = x;
  std::vector<double> pn(N::kNp);
  for (int i = 0; i < N::kNp; ++i) pn[static_cast<std::size_t>(i)] = pa[static_cast<std::size_t>(index_of(A::kParamNames, A::kNp, N::kParamNames[i]))];
  std::vector<double> pm = pn;
  pm.push_back(10.0);
  pm.push_back(10.0);
  double e0[3];
  REQUIRE(N::energy(0.0, x.data(), nullptr, pn.data(), e0) == 0);
  auto f = [&](double t, const double* s, double* sd) { return N::rhs(t, s, nullptr, pn.data(), sd); };
  auto fm = [&](double t, const double* s, double* sd) { return NM::rhs(t, s, nullptr, pm.data(), sd); };
  double diff = 0.0, closure = 0.0, energy = 0.0;
  std::vector<double> g(N::kNposc);
  for (int step = 0; step < 2000; ++step) {
    REQUIRE(mbsc::runtime::rk4_step(f, step * 5e-4, 5e-4, x) == 0);
    REQUIRE(mbsc::runtime::rk4_step(fm, step * 5e-4, 5e-4, xm) == 0);
    for (std::size_t i = 0; i < x.size(); ++i) diff = std::max(diff, std::abs(x[i] - xm[i]));
    REQUIRE(N::position_constraints(0.0, x.data(), nullptr, pn.data(), g.data()) == 0);
    for (double e : g) closure = std::max(closure, std::abs(e));
    double e[3];
    REQUIRE(N::energy(0.0, x.data(), nullptr, pn.data(), e) == 0);
    energy = std::max(energy, std::abs(e[2] - e0[2]));
  }
  INFO("vs multipliers " << diff << ", closure " << closure << ", energy " << energy);
  CHECK(diff < 1e-7);
  CHECK(closure < 1e-8);
  CHECK(energy < 1e-8);
}

TEST_CASE("nodal and absolute rail with a sliding block: prismatic angle row and rotational spring", "[numeric][nodal]") {
  namespace RA = mbsc_gen::rail_block;
  namespace RN = mbsc_gen::rail_block_nodal;
  REQUIRE(RA::kNdof == 2);
  REQUIRE(RN::kNdof == 2);
  const std::vector<BodyPoint> pts = {{"rail", "O", 0, 0}, {"rail", "E", 1, 0}, {"block", "P", 0, 0}, {"block", "Q", 0.2, 0}};
  auto com = [](const std::string& b) { return b == "rail" ? 0.5 : 0.1; };
  const Layouts L{RA::kStateNames, RA::kNx, RN::kStateNames, RN::kNx};
  auto ix = [](const char* n) { return static_cast<std::size_t>(index_of(RA::kStateNames, RA::kNx, n)); };
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> angle(-3.1, 3.1), along(0.1, 0.9), rate(-2.0, 2.0);
  for (int k = 0; k < 20; ++k) {
    // Rail angles all round (through +-pi, where a difference of atan2 would jump).
    const double phi = angle(rng), s = along(rng), w = rate(rng), sd = rate(rng);
    const double c = std::cos(phi), sn = std::sin(phi);
    std::vector<double> xa(RA::kNx, 0.0);
    xa[ix("rail.theta")] = phi, xa[ix("rail.x")] = 0.5 * c, xa[ix("rail.y")] = 0.5 * sn, xa[ix("rail.w")] = w;
    xa[ix("rail.u")] = -0.5 * sn * w, xa[ix("rail.v")] = 0.5 * c * w;
    const double r = s + 0.1;  // the block's mass centre along the rail
    xa[ix("block.theta")] = phi, xa[ix("block.x")] = r * c, xa[ix("block.y")] = r * sn, xa[ix("block.w")] = w;
    xa[ix("block.u")] = sd * c - r * sn * w, xa[ix("block.v")] = sd * sn + r * c * w;
    std::vector<double> g(RA::kNposc), vr(RA::kNc);
    REQUIRE(RA::position_constraints(0.0, xa.data(), nullptr, RA::kParamDefaults, g.data()) == 0);
    REQUIRE(RA::velocity_constraints(0.0, xa.data(), nullptr, RA::kParamDefaults, vr.data()) == 0);
    for (double e : g) REQUIRE(std::abs(e) < 1e-12);
    for (double e : vr) REQUIRE(std::abs(e) < 1e-12);
    std::vector<double> xda(RA::kNx), expected, xdn(RN::kNx);
    REQUIRE(RA::rhs(0.0, xa.data(), nullptr, RA::kParamDefaults, xda.data()) == 0);
    const auto xn = map_to_nodal(L, pts, +com, xa, &xda, &expected);
    std::vector<double> gn(RN::kNposc);
    REQUIRE(RN::position_constraints(0.0, xn.data(), nullptr, RN::kParamDefaults, gn.data()) == 0);
    for (double e : gn) REQUIRE(std::abs(e) < 1e-12);
    REQUIRE(RN::rhs(0.0, xn.data(), nullptr, RN::kParamDefaults, xdn.data()) == 0);
    double scale = 1.0;
    for (double e : expected) scale = std::max(scale, std::abs(e));
    for (int i = RN::kNq; i < RN::kNx; ++i) {
      INFO(RN::kStateNames[i] << " at rail angle " << phi);
      CHECK(std::abs(xdn[static_cast<std::size_t>(i)] - expected[static_cast<std::size_t>(i)]) < 1e-9 * scale);
    }
    double ea[3], en[3];
    REQUIRE(RA::energy(0.0, xa.data(), nullptr, RA::kParamDefaults, ea) == 0);
    REQUIRE(RN::energy(0.0, xn.data(), nullptr, RN::kParamDefaults, en) == 0);
    CHECK(std::abs(ea[2] - en[2]) < 1e-12 * std::max(1.0, std::abs(ea[2])));
  }
}
