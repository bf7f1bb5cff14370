// SPDX-License-Identifier: GPL-2.0-or-later
// models/slider_crank.mbs in Simbody: the crank on a ground pivot, the rod pinned to the
// crank tip, the slider (a point mass) on a Slider mobilizer along the ground's x axis,
// the loop closed at the wrist pin (rod tip on the slider). Inputs tau = F_load = 0.
#include "../mechanism.hpp"

namespace simbench {

using namespace SimTK;

// parameter r = 0.15, l = 0.30, m1 = 0.36, J1 = 0.002727, m2 = 0.151104,
//           J2 = 0.0045339259, m3 = 0.075552, g = 9.81
void build_slider_crank(Mechanism& m) {
  const double r = 0.15, l = 0.30, m1 = 0.36, J1 = 0.002727, m2 = 0.151104, J2 = 0.0045339259, m3 = 0.075552;
  Force::UniformGravity(m.forces, m.matter, Vec3(0, -9.81, 0));
  MobilizedBody::Pin crank(m.matter.Ground(), at(0, 0), planar_body(m1, J1, r / 2), at(0, 0));
  MobilizedBody::Pin rod(crank, at(r, 0), planar_body(m2, J2, l / 2), at(0, 0));
  // A particle: it never turns (Slider), so its rotational inertia plays no part.
  MobilizedBody::Slider slider(m.matter.Ground(), at(0, 0), planar_body(m3, 0.0), at(0, 0));
  pin_constraint(m.matter, slider, Vec2(0, 0), rod, Vec2(l, 0));
  const int ic = m.add_angle("crank", crank);
  m.add_angle("rod", rod, ic);
  m.add_slide("slider", slider, 0.0);
  m.independent = {"crank.theta", "crank.w"};
}

}  // namespace simbench
