// SPDX-License-Identifier: GPL-2.0-or-later
// models/three_rrr.mbs in Simbody: three legs (proximal link on a ground pivot, distal
// link pinned at the elbow), the platform pinned to leg A's distal link, legs B and C
// closed at the platform (two rows each). No gravity, u1 = u2 = u3 = 0.
#include "../mechanism.hpp"

#include <cmath>

namespace simbench {

using namespace SimTK;

void build_three_rrr(Mechanism& m) {
  const double m1 = 1.0, I1 = 0.25, m2 = 0.5, I2 = 1.0 / 6, m3 = 0.5, I3 = 2.0 / 3;
  const double h = std::sqrt(3.0) / 2;
  const Vec2 base[3] = {Vec2(3, 0), Vec2(-1.5, 3 * h), Vec2(-1.5, -3 * h)};
  const Vec2 joint[3] = {Vec2(1, 0), Vec2(-0.5, h), Vec2(-0.5, -h)};  // on the platform
  const char* leg[3] = {"HA", "HB", "HC"};
  std::vector<MobilizedBody> distal;
  for (int k = 0; k < 3; ++k) {
    // Proximal: mass centre at the base pivot (its frame origin), point E (2, 0).
    MobilizedBody::Pin prox(m.matter.Ground(), at(base[k][0], base[k][1]), planar_body(m3, I3), at(0, 0));
    // Distal: frame origin at P (the platform end), E at (2, 0), mass centre (1, 0).
    MobilizedBody::Pin dist(prox, at(2, 0), planar_body(m2, I2, 1.0), at(2, 0));
    const int ip = m.add_angle(std::string(leg[k]) + ".proximal", prox);
    m.add_angle(std::string(leg[k]) + ".distal", dist, ip);
    distal.push_back(dist);
  }
  MobilizedBody::Pin platform(distal[0], at(0, 0), planar_body(m1, I1), at(joint[0][0], joint[0][1]));
  m.add_angle("platform", platform, 1);  // parent: HA.distal
  for (int k = 1; k < 3; ++k) pin_constraint(m.matter, platform, joint[k], distal[static_cast<std::size_t>(k)], Vec2(0, 0));
  m.independent = {"HA.proximal.theta", "HB.proximal.theta", "HC.proximal.theta",
                   "HA.proximal.w",     "HB.proximal.w",     "HC.proximal.w"};
}

}  // namespace simbench
