// SPDX-License-Identifier: GPL-2.0-or-later
// The prismatic joint's invariants, symbolically (tests/data/planar/prismatic_pair.mbs,
// a joint between two moving rigid2d bodies):
//  - the library's position rows are the joint's vector form ([P] eq 21, first row, and
//    the relative angle): n . (r_N - r_M) with n = R(theta_1) (-d_y, d_x), and
//    theta_2 - theta_1 - phi;
//  - the order-1 and order-2 invariants mbsc uses for them (sym::velocity_residuals; the
//    root's B y' + b of the complement method; the multipliers form's A q1' + b) are
//    exactly their first and second time derivatives.
// The derivatives are taken here without sym::time_derivative: every coordinate q is
// replaced by its Taylor polynomial q + q' t + q'' t^2 / 2 along the bodies' kinematics
// (x' = u, y' = v, theta' = w, so q'' is the speed's rate) and the residual is
// differentiated in t at t = 0 by GiNaC. Differences must vanish after expand/normal.
#include <catch2/catch.hpp>

#include "mbsc/driver/pipeline.hpp"
#include "mbsc/sym/multipliers.hpp"

namespace {

using GiNaC::ex;

struct Loaded {
  std::optional<mbsc::model::Model> m;
  std::optional<mbsc::sym::Eom> eom;
};

Loaded load_prismatic_pair() {
  Loaded d;
  mbsc::Diagnostics diags;
  d.m = mbsc::driver::load_model(std::string(MBSC_SOURCE_DIR) + "/tests/data/planar/prismatic_pair.mbs", diags);
  INFO(diags.format());
  REQUIRE(d.m);
  d.eom = mbsc::sym::derive(*d.m, {}, diags);
  INFO(diags.format());
  REQUIRE(d.eom);
  return d;
}

ex var(const std::vector<mbsc::model::Variable>& vars, const std::string& name) {
  for (const auto& v : vars)
    if (v.name == name) return v.sym;
  FAIL("no variable " << name);
  return 0;
}

int constraint_index(const mbsc::model::Model& m, const std::string& name) {
  for (std::size_t i = 0; i < m.constraints.size(); ++i)
    if (m.constraints[i].name == name) return static_cast<int>(i);
  FAIL("no constraint " << name);
  return -1;
}

bool identically_zero(const ex& e) { return GiNaC::normal(GiNaC::expand(e)).is_zero(); }

/// d^order/dt^order of a residual g(q0) along the model's kinematics, from the Taylor
/// polynomials of the coordinates (each coordinate's rate must be one speed).
ex along_motion(const mbsc::model::Model& m, const ex& g, int order) {
  const GiNaC::symbol t("t_taylor");
  GiNaC::exmap path;
  for (std::size_t i = 0; i < m.coords.size(); ++i) {
    int speed = -1;
    for (std::size_t j = 0; j < m.speeds.size(); ++j)
      if (m.coord_rates[i].is_equal(m.speeds[j].sym)) speed = static_cast<int>(j);
    REQUIRE(speed >= 0);
    path[m.coords[i].sym] = m.coords[i].sym + m.speeds[speed].sym * t + m.speed_dots[speed] * t * t / 2;
  }
  return g.subs(path).diff(t, order).subs(t == 0);
}

}  // namespace

TEST_CASE("prismatic joint: position rows are the vector form", "[sym][planar][prismatic]") {
  const Loaded d = load_prismatic_pair();
  const auto& m = *d.m;
  REQUIRE(m.constraints.size() == 2);
  const auto& normal = m.constraints[constraint_index(m, "guide.normal")];
  const auto& angle = m.constraints[constraint_index(m, "guide.angle")];
  REQUIRE(normal.level == mbsc::model::Constraint::Level::Position);
  REQUIRE(angle.level == mbsc::model::Constraint::Level::Position);

  const ex x1 = var(m.coords, "carrier.x"), y1 = var(m.coords, "carrier.y"), th1 = var(m.coords, "carrier.theta");
  const ex x2 = var(m.coords, "block.x"), y2 = var(m.coords, "block.y"), th2 = var(m.coords, "block.theta");
  const ex phi = var(m.params, "phi");
  auto rotate = [](const ex& th, const ex& px, const ex& py) {
    return std::make_pair(cos(th) * px - sin(th) * py, sin(th) * px + cos(th) * py);
  };
  using GiNaC::numeric;
  // M: the slot's point (0.1, -0.05) on the carrier, mass centre (0.15, 0.05); slot
  // direction d = R(theta_1) (2, 1). N: (-0.1, 0.08) on the block, mass centre (0.02, -0.03).
  const auto gm = rotate(th1, numeric(1, 10) - numeric(15, 100), numeric(-5, 100) - numeric(5, 100));
  const auto d1 = rotate(th1, 2, 1);
  const auto gn = rotate(th2, numeric(-1, 10) - numeric(2, 100), numeric(8, 100) + numeric(3, 100));
  const ex mnx = (x2 + gn.first) - (x1 + gm.first), mny = (y2 + gn.second) - (y1 + gm.second);
  // n = z x d (the slot's normal, of length |d|).
  const ex nx = -d1.second, ny = d1.first;
  CHECK(identically_zero(normal.residual - (nx * mnx + ny * mny)));
  CHECK(identically_zero(angle.residual - (th2 - th1 - phi)));
}

TEST_CASE("prismatic joint: velocity and acceleration invariants are the derivatives of its position rows",
          "[sym][planar][prismatic]") {
  const Loaded d = load_prismatic_pair();
  const auto& m = *d.m;
  const auto order1 = mbsc::sym::velocity_residuals(m);
  const auto form = mbsc::sym::multiplier_form(m);
  const auto& root = d.eom->nodes[m.root()];
  REQUIRE(root.rows.size() == m.constraints.size());  // no row dropped as redundant
  for (const char* name : {"guide.normal", "guide.angle"}) {
    INFO(name);
    const int c = constraint_index(m, name);
    const ex g = m.constraints[c].residual;
    const ex first = along_motion(m, g, 1), second = along_motion(m, g, 2);
    REQUIRE(!first.is_zero());
    // Order 1: the residuals of velocity_constraints and the rows of A (multipliers).
    CHECK(identically_zero(order1[c] - first));
    ex a_q1 = 0;
    for (std::size_t j = 0; j < m.speeds.size(); ++j) a_q1 += form.A(c, j) * m.speeds[j].sym;
    CHECK(identically_zero(a_q1 - first));
    CHECK(identically_zero(form.velocity(c, 0) - first));
    // Order 2, multipliers: A q1' + b.
    ex a_q1dot = form.b(c, 0);
    for (std::size_t j = 0; j < m.speeds.size(); ++j) a_q1dot += form.A(c, j) * m.speed_dots[j];
    CHECK(identically_zero(a_q1dot - second));
    // Order 2, complement method: the root's row B y' + b (the bodies are leaves, so y is
    // every speed and no child's rate is composed in).
    std::size_t row = 0;
    while (row < root.rows.size() && root.rows[row] != c) ++row;
    REQUIRE(row < root.rows.size());
    ex b_y = root.b(row, 0);
    for (std::size_t k = 0; k < root.y.size(); ++k) b_y += root.B(row, k) * m.speed_dots[root.y[k]];
    CHECK(identically_zero(b_y - second));
  }
}
