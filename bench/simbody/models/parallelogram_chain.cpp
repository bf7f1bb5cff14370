// SPDX-License-Identifier: GPL-2.0-or-later
// models/parallelogram_chain.mbs (N = 3) in Simbody: N + 1 cranks on ground pivots L
// apart, coupler j pinned to crank j-1's tip and closed at crank j's tip (two rows per
// coupler). At the flat poses these rows become redundant; Simbody's projections solve
// them in the least-squares sense. Gravity (0, -g).
#include "../mechanism.hpp"

namespace simbench {

using namespace SimTK;

void build_parallelogram_chain(Mechanism& m) {
  const int N = 3;
  const double L = 0.5, a = 0.3, g = 9.81, mc = 0.3, mk = 0.5;
  Force::UniformGravity(m.forces, m.matter, Vec3(0, -g, 0));
  std::vector<MobilizedBody> crank;
  std::vector<int> crank_index;
  for (int i = 0; i <= N; ++i) {
    // Body frame at the bar's centre (its mass centre), O at (-a/2, 0) on the pivot.
    MobilizedBody::Pin c(m.matter.Ground(), at(i * L, 0), planar_body(mc, mc * a * a / 12), at(-a / 2, 0));
    crank.push_back(c);
    crank_index.push_back(m.add_angle("crank_" + std::to_string(i), c));
  }
  for (int j = 1; j <= N; ++j) {
    MobilizedBody& left = crank[static_cast<std::size_t>(j - 1)];
    MobilizedBody::Pin k(left, at(a / 2, 0), planar_body(mk, mk * L * L / 12), at(-L / 2, 0));
    m.add_angle("coupler_" + std::to_string(j), k, crank_index[static_cast<std::size_t>(j - 1)]);
    pin_constraint(m.matter, crank[static_cast<std::size_t>(j)], Vec2(a / 2, 0), k, Vec2(L / 2, 0));
  }
  m.independent = {"crank_0.theta", "crank_0.w"};
}

}  // namespace simbench
