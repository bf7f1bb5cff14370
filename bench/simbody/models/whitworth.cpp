// SPDX-License-Identifier: GPL-2.0-or-later
// models/whitworth.mbs in Simbody: the slider (point mass) on a Slider mobilizer along
// y = 0.8, the rod pinned to it, the slotted rocker on the ground pivot (0, 0), the crank
// on the pivot (0, 0.3). Loops closed at the rod-rocker pin (two rows) and by the crank
// pin in the rocker's slot (one PointInPlane row: the pin on the slot's line). No gravity,
// u1 = 0.
#include "../mechanism.hpp"

namespace simbench {

using namespace SimTK;

void build_whitworth(Mechanism& m) {
  const double m1 = 1.0;
  const double m2 = 0.2, I2 = 0.2 * 0.1 * 0.1 / 12, L2 = 0.6800735254367722;
  const double m3 = 0.4, I3 = 0.2 * 0.5 * 0.5 / 12, L3 = 0.6184658438426491;
  const double m4 = 0.2, I4 = 0.2 * 0.1 * 0.1 / 3, L4 = 0.1414213562373095;
  MobilizedBody::Slider slider(m.matter.Ground(), at(0, 0.8), planar_body(m1, 0.0), at(0, 0));
  MobilizedBody::Pin rod(slider, at(0, 0), planar_body(m2, I2, L2 / 2), at(0, 0));
  MobilizedBody::Pin rocker(m.matter.Ground(), at(0, 0), planar_body(m3, I3, L3 / 2), at(0, 0));
  MobilizedBody::Pin crank(m.matter.Ground(), at(0, 0.3), planar_body(m4, I4), at(0, 0));
  pin_constraint(m.matter, rocker, Vec2(L3, 0), rod, Vec2(L2, 0));
  Constraint::PointInPlane(rocker, UnitVec3(0, 1, 0), 0.0, crank, Vec3(L4, 0, 0));
  m.add_slide("slider", slider, 0.0);
  m.add_angle("rod", rod);  // the slider does not turn: the Pin angle is absolute
  m.add_angle("rocker", rocker);
  m.add_angle("crank", crank);
  m.independent = {"crank.theta", "crank.w"};
}

}  // namespace simbench
