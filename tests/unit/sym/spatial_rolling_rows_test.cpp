// SPDX-License-Identifier: GPL-2.0-or-later
// The spatial rolling joint (src/model/spatial_rolling.cpp), symbolically, against the
// contact kinematics computed here from scratch at random states:
//  - the rows are <joint>.contact (position), <joint>.no_slip and <joint>.no_side_slip
//    (velocity);
//  - .contact is the height above the plane of the rim's lowest point, found here by
//    sampling the rim;
//  - the order-1 row of .contact (sym::velocity_residuals, the compiler's time
//    derivative) is the normal component of the velocity of the disc's material point at
//    the contact, v_P = v_G + w x (P - G);
//  - .no_slip and .no_side_slip are v_P's components along the line where the disc's
//    plane meets the ground's and across it.
// Two models: models/rolling_disc.mbs (quaternion, body-frame speeds, ground plane) and
// tests/data/rolling/disc_tilted.mbs (zyx Euler angles, space-frame speeds, a tilted
// plane, an oblique spin axis off the mass centre).
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "mbsc/driver/pipeline.hpp"
#include "mbsc/sym/eom.hpp"

namespace {

using GiNaC::ex;
using V3 = std::array<double, 3>;
using M3 = std::array<double, 9>;  // row-major

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

V3 mul(const M3& R, const V3& v) {
  return {R[0] * v[0] + R[1] * v[1] + R[2] * v[2], R[3] * v[0] + R[4] * v[1] + R[5] * v[2],
          R[6] * v[0] + R[7] * v[1] + R[8] * v[2]};
}
M3 mul(const M3& A, const M3& B) {
  M3 C{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) C[3 * i + j] += A[3 * i + k] * B[3 * k + j];
  return C;
}
V3 cross(const V3& a, const V3& b) { return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}; }
double dot(const V3& a, const V3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
V3 add(const V3& a, const V3& b, double k = 1.0) { return {a[0] + k * b[0], a[1] + k * b[1], a[2] + k * b[2]}; }
V3 unit(const V3& a) {
  const double n = std::sqrt(dot(a, a));
  return {a[0] / n, a[1] / n, a[2] / n};
}

struct Case {
  const char* file;
  const char* body;
  bool quaternion;          // else zyx Euler angles with space-frame speeds
  V3 A, n;                  // the plane's point and normal
  V3 hub, dir, com;         // the disc's centre and spin axis, the mass centre (body frame)
  const char* radius;       // the radius parameter's name
};

}  // namespace

TEST_CASE("spatial rolling: the rows are the contact kinematics", "[sym][spatial_rolling]") {
  const std::string src = MBSC_SOURCE_DIR;
  const Case cases[] = {
      {"/models/rolling_disc.mbs", "disc", true, {0, 0, 0}, {0, 0, 1}, {0, 0, 0}, {0, 0, 1}, {0, 0, 0}, "r"},
      {"/tests/data/rolling/disc_tilted.mbs", "wheel", false, {0.1, -0.2, 0.3}, {0.2, -0.3, 1.1}, {0.01, 0.02, -0.04},
       {0.3, 1.2, -0.5}, {0.05, -0.02, 0.03}, "rho"},
  };
  std::mt19937 rng(1212);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  for (const Case& c : cases) {
    SECTION(c.file) {
      mbsc::Diagnostics diags;
      const auto m = mbsc::driver::load_model(src + c.file, diags);
      INFO(diags.format());
      REQUIRE(m);
      REQUIRE(m->constraints.size() == 3);
      using Level = mbsc::model::Constraint::Level;
      CHECK(m->constraints[0].name == "roll.contact");
      CHECK(m->constraints[0].level == Level::Position);
      CHECK(m->constraints[1].name == "roll.no_slip");
      CHECK(m->constraints[1].level == Level::Velocity);
      CHECK(m->constraints[2].name == "roll.no_side_slip");
      CHECK(m->constraints[2].level == Level::Velocity);
      const auto order1 = mbsc::sym::velocity_residuals(*m);
      REQUIRE(order1.size() == 3);
      GiNaC::exmap params;
      double r = 0.0;
      for (std::size_t k = 0; k < m->params.size(); ++k) {
        params[m->params[k].sym] = m->param_defaults[k];
        if (m->params[k].name == c.radius) r = m->param_defaults[k];
      }
      REQUIRE(r > 0.0);
      const std::string b = std::string(c.body) + ".";
      const V3 n = unit(c.n);
      for (int trial = 0; trial < 6; ++trial) {
        GiNaC::exmap at = params;
        V3 x{}, v{}, w{};
        for (int k = 0; k < 3; ++k) {
          x[k] = U(rng), v[k] = U(rng), w[k] = U(rng);
          at[var(m->coords, b + "xyz"[k])] = x[k];
          at[var(m->speeds, b + "uvw"[k])] = v[k];
          at[var(m->speeds, b + "w" + "xyz"[k])] = w[k];
        }
        M3 R{};
        V3 w_space = w;
        if (c.quaternion) {
          double e[4] = {1.0 + U(rng), U(rng), U(rng), U(rng)};
          const double en = std::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2] + e[3] * e[3]);
          for (int k = 0; k < 4; ++k) e[k] /= en, at[var(m->coords, b + "e" + std::to_string(k))] = e[k];
          const double e0 = e[0], e1 = e[1], e2 = e[2], e3 = e[3];
          R = {1 - 2 * (e2 * e2 + e3 * e3), 2 * (e1 * e2 - e0 * e3),     2 * (e1 * e3 + e0 * e2),
               2 * (e1 * e2 + e0 * e3),     1 - 2 * (e1 * e1 + e3 * e3), 2 * (e2 * e3 - e0 * e1),
               2 * (e1 * e3 - e0 * e2),     2 * (e2 * e3 + e0 * e1),     1 - 2 * (e1 * e1 + e2 * e2)};
          w_space = mul(R, w);  // body-frame speeds
        } else {
          const double phi = U(rng), th = U(rng), psi = U(rng);
          at[var(m->coords, b + "phi")] = phi, at[var(m->coords, b + "theta")] = th, at[var(m->coords, b + "psi")] = psi;
          const M3 Rz{std::cos(phi), -std::sin(phi), 0, std::sin(phi), std::cos(phi), 0, 0, 0, 1};
          const M3 Ry{std::cos(th), 0, std::sin(th), 0, 1, 0, -std::sin(th), 0, std::cos(th)};
          const M3 Rx{1, 0, 0, 0, std::cos(psi), -std::sin(psi), 0, std::sin(psi), std::cos(psi)};
          R = mul(mul(Rz, Ry), Rx);
        }
        // The disc's centre and spin axis in space. The rim is C + r (cos a e1 + sin a e2);
        // its height n . (rim - A) is lowest where (cos a, sin a) is against (n.e1, n.e2).
        const V3 C = add(x, mul(R, add(c.hub, c.com, -1.0)));
        const V3 d = unit(mul(R, c.dir));
        const V3 e1 = unit(cross(d, {0.3, 0.5, 0.7})), e2 = cross(d, e1);
        const double rho = std::hypot(dot(n, e1), dot(n, e2));
        const V3 P = add(add(C, e1, -r * dot(n, e1) / rho), e2, -r * dot(n, e2) / rho);
        const double lowest = dot(n, add(P, c.A, -1.0));
        double sampled = 1e300;  // and no rim point is lower
        for (int k = 0; k < 3600; ++k) {
          const double a = 2 * 3.14159265358979323846 * k / 3600;
          sampled = std::min(sampled, dot(n, add(add(add(C, e1, r * std::cos(a)), e2, r * std::sin(a)), c.A, -1.0)));
        }
        INFO(c.file << " trial " << trial);
        CHECK(sampled >= lowest - 1e-12);
        CHECK(sampled - lowest < 1e-5);
        const V3 vP = add(v, cross(w_space, add(P, x, -1.0)));
        const V3 t = unit(cross(d, n));  // along the line the two planes share
        const V3 across = cross(n, t);
        CHECK(value(m->constraints[0].residual.subs(at)) == Approx(lowest).margin(1e-12));
        CHECK(value(order1[0].subs(at)) == Approx(dot(n, vP)).margin(1e-12));
        CHECK(value(m->constraints[1].residual.subs(at)) == Approx(dot(t, vP)).margin(1e-12));
        CHECK(value(m->constraints[2].residual.subs(at)) == Approx(dot(across, vP)).margin(1e-12));
      }
    }
  }
}
