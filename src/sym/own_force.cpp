// SPDX-License-Identifier: GPL-2.0-or-later
#include "mbsc/sym/own_force.hpp"

#include <algorithm>

#include "mbsc/model/rigid3d.hpp"

namespace mbsc::sym {

GiNaC::ex own_force(const model::Model& m, int speed) {
  const model::Node& node = m.nodes[static_cast<std::size_t>(m.speeds[static_cast<std::size_t>(speed)].node)];
  const auto at = std::find(node.speeds.begin(), node.speeds.end(), speed);
  const std::size_t k = static_cast<std::size_t>(at - node.speeds.begin());
  GiNaC::ex f = 0;
  // (A nodal body's inertia and gravity are explicit Force terms, added below.)
  if (model::is_body(node.kind) && node.kind != model::LeafKind::Rigid2dNodal) {
    // Body speeds are (u, v[, w]) = rates of (x, y[, z | theta]).
    const GiNaC::ex rate = m.speed_dots[static_cast<std::size_t>(speed)];
    if (node.kind == model::LeafKind::Rigid3d && k >= 3) {
      // Euler's equations in the angular speeds' frame (model/rigid3d.hpp).
      f += model::rigid3d::angular_inertia_force(m, node, static_cast<int>(k) - 3);
    } else if (node.kind == model::LeafKind::Rigid2d && k == 2) {
      f += -node.inertia * rate;
    } else {
      f += -node.mass * rate;
      if (k < m.gravity.size()) f += node.mass * m.gravity[k];
    }
  }
  for (const auto& force : m.forces)
    if (force.speed == speed) f += force.value;
  return f;
}

}  // namespace mbsc::sym
