// SPDX-License-Identifier: GPL-2.0-or-later
// models/four_bar.mbs and models/four_bar_toggle.mbs in Simbody: crank and rocker on
// ground pivots, the coupler pinned to the crank tip, the loop closed at the
// coupler-rocker pin. Uniform bars, mass centres at mid-length, gravity (0, -g).
#include "../mechanism.hpp"

namespace simbench {

using namespace SimTK;

namespace {

// Lengths a (crank), b (coupler), c (rocker), ground pivots (0, 0) and (d, 0).
void build_four_bar_like(Mechanism& m, double a, double b, double c, double d, double m1, double m2, double m3,
                         double g) {
  Force::UniformGravity(m.forces, m.matter, Vec3(0, -g, 0));
  // Body frames at each bar's first end, x along the bar: mbsc's theta is the x axis angle.
  MobilizedBody::Pin crank(m.matter.Ground(), at(0, 0), planar_body(m1, m1 * a * a / 12, a / 2), at(0, 0));
  MobilizedBody::Pin coupler(crank, at(a, 0), planar_body(m2, m2 * b * b / 12, b / 2), at(0, 0));
  MobilizedBody::Pin rocker(m.matter.Ground(), at(d, 0), planar_body(m3, m3 * c * c / 12, c / 2), at(0, 0));
  pin_constraint(m.matter, coupler, Vec2(b, 0), rocker, Vec2(c, 0));
  const int ic = m.add_angle("crank", crank);
  m.add_angle("coupler", coupler, ic);
  m.add_angle("rocker", rocker);
  m.independent = {"crank.theta", "crank.w"};
}

}  // namespace

// parameter a = 0.3, b = 1.0, c = 0.8, d = 0.9, g = 9.81; m1 = 0.3, m2 = 1.0, m3 = 0.8; tau0 = 0
void build_four_bar(Mechanism& m) { build_four_bar_like(m, 0.3, 1.0, 0.8, 0.9, 0.3, 1.0, 0.8, 9.81); }

// parameter a = 0.6, b = 0.6, c = 0.9, d = 1.0, g = 9.81; m1 = 0.6, m2 = 0.6, m3 = 0.9
void build_four_bar_toggle(Mechanism& m) { build_four_bar_like(m, 0.6, 0.6, 0.9, 1.0, 0.6, 0.6, 0.9, 9.81); }

}  // namespace simbench
