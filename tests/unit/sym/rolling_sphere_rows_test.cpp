// SPDX-License-Identifier: GPL-2.0-or-later
// The rolling_sphere joint (src/model/spatial_rolling_sphere.cpp), symbolically, against
// the contact geometry computed here from scratch at random states:
//  - the rows are <joint>.contact_x/_y/_z (position) and .no_slip_x/_y (velocity), and the
//    joint brings the coordinates <joint>.xc, .yc with speeds .xc_dot, .yc_dot;
//  - .contact_* is G - P - r n^ with P = (xc, yc, gamma(xc, yc)) and n^ the unit upward
//    normal, from the surface's slopes written here by hand;
//  - their order-1 rows (sym::velocity_residuals) are the same vector's rate, taken here
//    by central differences along the motion;
//  - .no_slip_* are the tangents (1, 0, gamma_x), (0, 1, gamma_y) dotted with the velocity
//    of the sphere's material point at P, v_P = v_G + w x (P - G).
// Two models: models/sphere_trough.mbs (gamma = y^2/2, space-frame speeds) and
// tests/data/rolling/sphere_saddle.mbs (a non-separable gamma, body-frame speeds, the
// options in the other order).
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "mbsc/driver/pipeline.hpp"
#include "mbsc/sym/eom.hpp"

namespace {

using GiNaC::ex;
using V3 = std::array<double, 3>;

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

V3 cross(const V3& a, const V3& b) { return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}; }
double dot(const V3& a, const V3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

struct Surface {
  std::function<double(double, double)> gamma, gx, gy;
};

/// G - P - r n^ at the centre G and the contact (x, y).
V3 contact(const Surface& s, double r, const V3& G, double x, double y) {
  const double gx = s.gx(x, y), gy = s.gy(x, y), N = std::sqrt(1 + gx * gx + gy * gy);
  return {G[0] - x + r * gx / N, G[1] - y + r * gy / N, G[2] - s.gamma(x, y) - r / N};
}

}  // namespace

TEST_CASE("rolling sphere: the rows are the contact geometry and kinematics", "[sym][rolling_sphere]") {
  const std::string src = MBSC_SOURCE_DIR;
  const double a = 0.3, b = 0.1, c = 0.2, d = 0.05;  // sphere_saddle.mbs's defaults
  struct Case {
    const char* file;
    const char* radius;
    bool body_speeds;
    Surface s;
  };
  const Case cases[] = {
      {"/models/sphere_trough.mbs", "r", false,
       {[](double, double y) { return y * y / 2; }, [](double, double) { return 0.0; }, [](double, double y) { return y; }}},
      {"/tests/data/rolling/sphere_saddle.mbs", "rho", true,
       {[=](double x, double y) { return a * x * x + b * x * y - c * y * y + d * x; },
        [=](double x, double y) { return 2 * a * x + b * y + d; }, [=](double x, double y) { return b * x - 2 * c * y; }}},
  };
  std::mt19937 rng(1213);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  for (const Case& k : cases) {
    SECTION(k.file) {
      mbsc::Diagnostics diags;
      const auto m = mbsc::driver::load_model(src + k.file, diags);
      INFO(diags.format());
      REQUIRE(m);
      REQUIRE(m->constraints.size() == 5);
      using Level = mbsc::model::Constraint::Level;
      const char* names[] = {"roll.contact_x", "roll.contact_y", "roll.contact_z", "roll.no_slip_x", "roll.no_slip_y"};
      for (std::size_t i = 0; i < 5; ++i) {
        CHECK(m->constraints[i].name == names[i]);
        CHECK(m->constraints[i].level == (i < 3 ? Level::Position : Level::Velocity));
      }
      const auto order1 = mbsc::sym::velocity_residuals(*m);
      REQUIRE(order1.size() == 5);
      GiNaC::exmap params;
      double r = 0.0;
      for (std::size_t i = 0; i < m->params.size(); ++i) {
        params[m->params[i].sym] = m->param_defaults[i];
        if (m->params[i].name == k.radius) r = m->param_defaults[i];
      }
      REQUIRE(r > 0.0);
      for (int trial = 0; trial < 6; ++trial) {
        GiNaC::exmap at = params;
        V3 G{}, v{}, w{};
        for (int i = 0; i < 3; ++i) {
          G[i] = U(rng), v[i] = U(rng), w[i] = U(rng);
          at[var(m->coords, std::string("ball.") + "xyz"[i])] = G[i];
          at[var(m->speeds, std::string("ball.") + "uvw"[i])] = v[i];
          at[var(m->speeds, std::string("ball.w") + "xyz"[i])] = w[i];
        }
        const double xc = 0.5 * U(rng), yc = 0.5 * U(rng), xr = U(rng), yr = U(rng);
        at[var(m->coords, "roll.xc")] = xc, at[var(m->coords, "roll.yc")] = yc;
        at[var(m->speeds, "roll.xc_dot")] = xr, at[var(m->speeds, "roll.yc_dot")] = yr;
        double e[4] = {1.0 + U(rng), U(rng), U(rng), U(rng)};
        const double en = std::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2] + e[3] * e[3]);
        for (int i = 0; i < 4; ++i) e[i] /= en, at[var(m->coords, "ball.e" + std::to_string(i))] = e[i];
        V3 w_space = w;
        if (k.body_speeds) {
          const double e0 = e[0], e1 = e[1], e2 = e[2], e3 = e[3];
          const V3 R0{1 - 2 * (e2 * e2 + e3 * e3), 2 * (e1 * e2 - e0 * e3), 2 * (e1 * e3 + e0 * e2)};
          const V3 R1{2 * (e1 * e2 + e0 * e3), 1 - 2 * (e1 * e1 + e3 * e3), 2 * (e2 * e3 - e0 * e1)};
          const V3 R2{2 * (e1 * e3 - e0 * e2), 2 * (e2 * e3 + e0 * e1), 1 - 2 * (e1 * e1 + e2 * e2)};
          w_space = {dot(R0, w), dot(R1, w), dot(R2, w)};
        }
        INFO(k.file << " trial " << trial);
        const V3 g = contact(k.s, r, G, xc, yc);
        for (int i = 0; i < 3; ++i) CHECK(value(m->constraints[static_cast<std::size_t>(i)].residual.subs(at)) == Approx(g[static_cast<std::size_t>(i)]).margin(1e-12));
        // The rate along the motion (G moves at v, the contact at (xr, yr)).
        const double h = 1e-6;
        const V3 Gp{G[0] + h * v[0], G[1] + h * v[1], G[2] + h * v[2]}, Gm{G[0] - h * v[0], G[1] - h * v[1], G[2] - h * v[2]};
        const V3 gp = contact(k.s, r, Gp, xc + h * xr, yc + h * yr), gm = contact(k.s, r, Gm, xc - h * xr, yc - h * yr);
        for (int i = 0; i < 3; ++i)
          CHECK(value(order1[static_cast<std::size_t>(i)].subs(at)) == Approx((gp[static_cast<std::size_t>(i)] - gm[static_cast<std::size_t>(i)]) / (2 * h)).margin(1e-8));
        const double gx = k.s.gx(xc, yc), gy = k.s.gy(xc, yc), N = std::sqrt(1 + gx * gx + gy * gy);
        const V3 arm{r * gx / N, r * gy / N, -r / N};  // P - G = -r n^
        const V3 wa = cross(w_space, arm);
        const V3 vP{v[0] + wa[0], v[1] + wa[1], v[2] + wa[2]};
        CHECK(value(m->constraints[3].residual.subs(at)) == Approx(dot({1, 0, gx}, vP)).margin(1e-12));
        CHECK(value(m->constraints[4].residual.subs(at)) == Approx(dot({0, 1, gy}, vP)).margin(1e-12));
      }
    }
  }
}
