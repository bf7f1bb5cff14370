// SPDX-License-Identifier: GPL-2.0-or-later
// Spatial joints (src/model/spatial_library.cpp), symbolically, on the test chains of
// tests/data/spatial_joints/: body a (zyx Euler angles, space-frame speeds) hangs from
// the ground by a spherical joint and body b (quaternion, body-frame speeds) is joined
// to a by each joint kind in turn.
//  - each joint adds the rows of its vector form, named <joint>.<row>, all at position level;
//  - the order-1 rows mbsc uses (sym::velocity_residuals) are the time derivatives of
//    the position rows: at random states, the row equals grad(g) . q' with q' from
//    kinematics written here independently of the compiler (x' = u; a's angle rates
//    chosen freely and its space-frame angular velocity built from them as
//    phi' z + theta' Rz(phi) y + psi' Rz(phi) Ry(theta) x; b's e' = 1/2 e (0, w)).
#include <catch2/catch.hpp>

#include <cmath>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "mbsc/driver/pipeline.hpp"
#include "mbsc/sym/eom.hpp"

namespace {

using GiNaC::ex;

ex var(const std::vector<mbsc::model::Variable>& vars, const std::string& name) {
  for (const auto& v : vars)
    if (v.name == name) return v.sym;
  FAIL("no variable " << name);
  return 0;
}

double value(const ex& e) {
  const ex v = GiNaC::evalf(e);
  REQUIRE(GiNaC::is_a<GiNaC::numeric>(v));
  return GiNaC::ex_to<GiNaC::numeric>(v).to_double();
}

}  // namespace

TEST_CASE("spatial joints: rows of the vector forms, velocity rows are their derivatives", "[sym][spatial_joints]") {
  const std::map<std::string, std::vector<std::string>> rows = {
      {"spherical", {"x", "y", "z"}},
      {"revolute", {"x", "y", "z", "align1", "align2"}},
      {"universal", {"x", "y", "z", "cross"}},
      {"cylindrical", {"n1", "n2", "align1", "align2"}},
      {"prismatic", {"n1", "n2", "align1", "align2", "twist"}},
      {"weld", {"x", "y", "z", "rx", "ry", "rz"}},
      {"point_on_line", {"n1", "n2"}},
      {"point_on_plane", {"normal"}},
  };
  std::mt19937 rng(1202);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  for (const auto& [kind, names] : rows) {
    SECTION(kind) {
      mbsc::Diagnostics diags;
      const auto m = mbsc::driver::load_model(std::string(MBSC_SOURCE_DIR) + "/tests/data/spatial_joints/chain_" + kind + ".mbs",
                                              diags);
      INFO(diags.format());
      REQUIRE(m);
      // hang.x, hang.y, hang.z, then the joint's rows in its vector forms' order.
      REQUIRE(m->constraints.size() == 3 + names.size());
      for (std::size_t k = 0; k < names.size(); ++k) {
        CHECK(m->constraints[3 + k].name == "link." + names[k]);
        CHECK(m->constraints[3 + k].level == mbsc::model::Constraint::Level::Position);
      }
      const auto order1 = mbsc::sym::velocity_residuals(*m);
      REQUIRE(order1.size() == m->constraints.size());
      for (int trial = 0; trial < 4; ++trial) {
        GiNaC::exmap at;   // the state
        std::map<std::string, double> rate;  // each coordinate's rate
        for (const char* c : {"a.x", "a.y", "a.z", "b.x", "b.y", "b.z"}) {
          at[var(m->coords, c)] = U(rng);
          rate[c] = U(rng);
        }
        for (const char* c : {"a.u", "a.v", "a.w"}) at[var(m->speeds, c)] = rate[std::string("a.") + "xyz"[c[2] - 'u']];
        for (const char* c : {"b.u", "b.v", "b.w"}) at[var(m->speeds, c)] = rate[std::string("b.") + "xyz"[c[2] - 'u']];
        // a: zyx angles and their rates; w_space = phi' z + theta' Rz y + psi' Rz Ry x.
        const double phi = U(rng), th = U(rng), psi = U(rng);
        const double dphi = U(rng), dth = U(rng), dpsi = U(rng);
        at[var(m->coords, "a.phi")] = phi, at[var(m->coords, "a.theta")] = th, at[var(m->coords, "a.psi")] = psi;
        rate["a.phi"] = dphi, rate["a.theta"] = dth, rate["a.psi"] = dpsi;
        const double cz = std::cos(phi), sz = std::sin(phi), cy = std::cos(th), sy = std::sin(th);
        at[var(m->speeds, "a.wx")] = -sz * dth + cz * cy * dpsi;
        at[var(m->speeds, "a.wy")] = cz * dth + sz * cy * dpsi;
        at[var(m->speeds, "a.wz")] = dphi - sy * dpsi;
        // b: a unit quaternion and body-frame speeds; e' = 1/2 e (0, w).
        double e[4] = {1.0 + U(rng), U(rng), U(rng), U(rng)};
        const double n = std::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2] + e[3] * e[3]);
        for (double& v : e) v /= n;
        const double w[3] = {U(rng), U(rng), U(rng)};
        const double de[4] = {-0.5 * (e[1] * w[0] + e[2] * w[1] + e[3] * w[2]),
                              0.5 * (e[0] * w[0] + e[2] * w[2] - e[3] * w[1]),
                              0.5 * (e[0] * w[1] + e[3] * w[0] - e[1] * w[2]),
                              0.5 * (e[0] * w[2] + e[1] * w[1] - e[2] * w[0])};
        const char* const qe[4] = {"b.e0", "b.e1", "b.e2", "b.e3"};
        for (int k = 0; k < 4; ++k) at[var(m->coords, qe[k])] = e[k], rate[qe[k]] = de[k];
        at[var(m->speeds, "b.wx")] = w[0], at[var(m->speeds, "b.wy")] = w[1], at[var(m->speeds, "b.wz")] = w[2];
        for (std::size_t r = 0; r < m->constraints.size(); ++r) {
          const ex g = m->constraints[r].residual;
          double along = 0.0;
          for (const auto& [name, dq] : rate) along += value(g.diff(GiNaC::ex_to<GiNaC::symbol>(var(m->coords, name))).subs(at)) * dq;
          INFO(m->constraints[r].name << " trial " << trial);
          CHECK(value(order1[r].subs(at)) == Approx(along).margin(1e-12));
        }
      }
    }
  }
}
