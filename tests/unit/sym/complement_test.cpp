// SPDX-License-Identifier: GPL-2.0-or-later
// Orthogonal complements against the thesis's published forms:
//  - Ex 4.1 Cartesian pendulum, S = [-y -z; x 0; 0 x] up to the scaling 1/x (x dependent);
//  - Ex 4.2 ring and disc, C_S of (g) with independent (theta', w2);
//  - Ex 2.7 arm H_K, C of (i) (with the mass centre of each bar at mid-length).
#include <catch2/catch.hpp>
#include <Eigen/Dense>
#include <cmath>

#include "mbsc/driver/pipeline.hpp"
#include "bind_solves.hpp"
#include "mbsc/sym/probe.hpp"

namespace {

struct Derived {
  std::optional<mbsc::model::Model> m;
  std::optional<mbsc::sym::Eom> eom;
};

Derived derive(const std::string& file) {
  Derived d;
  mbsc::Diagnostics diags;
  d.m = mbsc::driver::load_model(std::string(MBSC_SOURCE_DIR) + "/models/" + file, diags);
  REQUIRE(d.m);
  d.eom = mbsc::sym::derive(*d.m, {}, diags);
  INFO(diags.format());
  REQUIRE(d.eom);
  return d;
}

void bind_solves(mbsc::sym::Probe& p, const Derived& d) { mbsc_test::bind_solves(p, *d.m, *d.eom); }

GiNaC::ex sym_of(const mbsc::model::Model& m, const std::string& name) {
  for (const auto& q : m.coords)
    if (q.name == name) return q.sym;
  for (const auto& p : m.params)
    if (p.name == name) return p.sym;
  FAIL("no symbol " << name);
  return 0;
}

}  // namespace

TEST_CASE("Ex 4.1: complement of the Cartesian pendulum", "[sym][complement]") {
  Derived d = derive("spherical_pendulum_cartesian.mbs");
  const auto& r = d.eom->nodes[d.m->root()];
  REQUIRE(r.y.size() == 3);
  REQUIRE(r.independent.size() == 2);
  for (unsigned seed : {5u, 6u, 7u}) {
    mbsc::sym::Probe p(*d.m, {}, seed);
    bind_solves(p, d);
    const double x = p.eval(sym_of(*d.m, "bob.x")), y = p.eval(sym_of(*d.m, "bob.y")), z = p.eval(sym_of(*d.m, "bob.z"));
    // Rows (u, v, w), columns (v, w): the thesis S divided by x.
    const double expected[3][2] = {{-y / x, -z / x}, {1, 0}, {0, 1}};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 2; ++j) CHECK(p.eval(r.C(i, j)) == Approx(expected[i][j]).margin(1e-12));
  }
}

TEST_CASE("Ex 4.2(g): complement of the ring and disc", "[sym][complement]") {
  Derived d = derive("ring_disc.mbs");
  const auto& r = d.eom->nodes[d.m->root()];
  std::vector<std::string> y;
  for (int s : r.y) y.push_back(d.m->speeds[s].name);
  REQUIRE(y == std::vector<std::string>{"dtheta", "R.u", "R.v", "R.w", "D.u", "D.v", "D.w"});
  for (unsigned seed : {1u, 2u, 3u}) {
    mbsc::sym::Probe p(*d.m, {}, seed);
    bind_solves(p, d);
    const double r1 = p.eval(sym_of(*d.m, "r1")), r2 = p.eval(sym_of(*d.m, "r2"));
    const double xi = p.eval(sym_of(*d.m, "xi")), th = p.eval(sym_of(*d.m, "theta"));
    const double c = std::cos(xi - th), s = std::sin(xi - th);
    const double expected[7][2] = {{1, 0},
                                   {r1 - r2, -r2},
                                   {0, 0},
                                   {r2 / r1 - 1, r2 / r1},
                                   {-(c - 1) * (r1 - r2), -r2},
                                   {-s * (r1 - r2), 0},
                                   {0, 1}};
    for (int i = 0; i < 7; ++i)
      for (int j = 0; j < 2; ++j) {
        INFO(y[i] << ", column " << j);
        CHECK(p.eval(r.C(i, j)) == Approx(expected[i][j]).margin(1e-12));
      }
  }
}

TEST_CASE("Ex 2.7(i): complement of an arm of the five-bar (symbolic)", "[sym][complement]") {
  Derived d = derive("five_bar.mbs");
  int arm = -1;
  for (size_t n = 0; n < d.m->nodes.size(); ++n)
    if (d.m->nodes[n].name == "linkage.left") arm = static_cast<int>(n);
  REQUIRE(arm >= 0);
  const auto& r = d.eom->nodes[arm];
  REQUIRE(r.symbolic_complement);
  auto fin = [&](const GiNaC::ex& e) { return mbsc::driver::finalize(*d.m, *d.eom, e); };
  const GiNaC::ex th = sym_of(*d.m, "linkage.left.theta"), ph = sym_of(*d.m, "linkage.left.phi");
  const GiNaC::ex aU = sym_of(*d.m, "aUL"), aB = sym_of(*d.m, "aBL");
  // Rows in y order: dtheta, dphi, upper (u, v, w), lower (u, v, w); columns (dtheta, dphi).
  const GiNaC::ex half = GiNaC::numeric(1, 2);
  const GiNaC::ex expected[8][2] = {{1, 0},
                                    {0, 1},
                                    {-half * aU * sin(th), 0},
                                    {half * aU * cos(th), 0},
                                    {1, 0},
                                    {-aU * sin(th), -half * aB * sin(ph)},
                                    {aU * cos(th), half * aB * cos(ph)},
                                    {0, 1}};
  REQUIRE(r.C.rows() == 8);
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 2; ++j) {
      INFO("row " << i << " column " << j << ": " << fin(r.C(i, j)));
      CHECK((fin(r.C(i, j)) - expected[i][j]).expand().is_zero());
    }
}
