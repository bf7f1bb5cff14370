// SPDX-License-Identifier: GPL-2.0-or-later
// The planar knife edge (a blade, a skate, the runner of the Chaplygin sleigh): a
// nonholonomic joint between a rigid body and the ground. The material point P of the
// body where the blade touches may move along the blade but not across it:
//   v_P . n = 0,  n = the unit normal of the blade's direction turned with the body,
// one velocity constraint, linear in the body's speeds. P defaults to the mass centre
// and the blade's direction to the body's x axis.
#include <fmt/format.h>

#include "planar_library.hpp"

namespace mbsc::model {

void PlanarLibrary::add_knife_edge(int owner, const Element& e, const std::string& name, const std::string& what) {
  const auto b = body(owner, e.end1);
  if (!b || *b == kGround || !is_rigid2d(m_.nodes[*b].kind)) {
    diags_.error(e.end1_pos, fmt::format("{}: '{}' is not a rigid2d body (the body that carries the blade)", what, e.end1));
    return;
  }
  if (!e.option.empty()) {
    diags_.error(e.option_pos, fmt::format("{} takes no option ('{}'); it is `knife_edge BODY [point P] [axis A]`", what,
                                           e.option));
    return;
  }
  const std::string body_name = m_.nodes[*b].name;
  // The blade's point in body coordinates: a declared point of the body, or its mass centre.
  GiNaC::ex px = 0, py = 0;
  if (const auto c = com_.find(*b); c != com_.end()) {
    px = c->second.first;
    py = c->second.second;
  }
  if (!e.end2.empty()) {
    const auto p = points_.find(body_name + "." + e.end2);
    if (p == points_.end() || p->second.node != *b) {
      if (failed_.count(body_name + "." + e.end2)) return;  // declared but rejected: reported there
      diags_.error(e.end2_pos, fmt::format("{}: '{}' is not a point of body '{}'", what, e.end2, body_name));
      return;
    }
    px = p->second.ex;
    py = p->second.ey;
  }
  // The blade's direction in body coordinates: a declared axis of the body, or its x axis.
  GiNaC::ex dx = 1, dy = 0;
  if (!e.end3.empty()) {
    const auto a = axes_.find(body_name + "." + e.end3);
    if (a == axes_.end() || a->second.node != *b) {
      if (failed_.count(body_name + "." + e.end3)) return;  // declared but rejected (a zero axis): reported there
      diags_.error(e.end3_pos, fmt::format("{}: '{}' is not an axis of body '{}'", what, e.end3, body_name));
      return;
    }
    dx = a->second.dx;
    dy = a->second.dy;
  }
  const GiNaC::ex len = GiNaC::sqrt(dx * dx + dy * dy);  // 1 for the default x axis
  const auto t = rotate(*b, dx, dy);
  const Node& n = m_.nodes[*b];
  if (n.kind == LeafKind::Rigid2d) {
    // v_P = v_c + w z x r (r = R(theta) (P - com)), so t x v_P = t x v_c + w (t . r), and
    // t . r = d . (P - com) does not turn with the body: the rate of the angle keeps a
    // constant coefficient (a state-free pivot when the blade is off the mass centre).
    const GiNaC::ex u = m_.speeds[n.speeds[0]].sym, v = m_.speeds[n.speeds[1]].sym, w = m_.speeds[n.speeds[2]].sym;
    GiNaC::ex cx = 0, cy = 0;
    if (const auto c = com_.find(*b); c != com_.end()) {
      cx = c->second.first;
      cy = c->second.second;
    }
    const GiNaC::ex arm = dx * (px - cx) + dy * (py - cy);
    add_velocity_constraint(owner, name + ".lateral", (t.first * v - t.second * u + arm * w) / len, e.pos);
    return;
  }
  // A nodal body: the velocity of its material point P from its nodes.
  const auto r = world(*b, px, py);
  const auto vp = velocity(*b, r.first, r.second);
  add_velocity_constraint(owner, name + ".lateral", (t.first * vp.second - t.second * vp.first) / len, e.pos);
}

}  // namespace mbsc::model
