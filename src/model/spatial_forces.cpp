// SPDX-License-Identifier: GPL-2.0-or-later
// Force elements in space: joint actuators, springs and dampers between points, and
// rotational springs and dampers about a revolute axis. Every element is a force at a
// point and a torque on each of its two bodies (equal and opposite), and every one turns
// into generalized forces the same way, by the virtual power of apply_wrench: the
// partial velocities of the point and the partial angular velocities of the body.
#include <stdexcept>

#include <fmt/format.h>

#include "mbsc/model/rigid3d.hpp"
#include "spatial_library.hpp"

namespace mbsc::model {

namespace {
using Vec = SpatialLibrary::Vec;
Vec sub(const Vec& a, const Vec& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec scale(const GiNaC::ex& s, const Vec& a) { return {s * a[0], s * a[1], s * a[2]}; }
Vec neg(const Vec& a) { return scale(-1, a); }
const Vec kZero{0, 0, 0};
}  // namespace

Vec SpatialLibrary::unit_axis(const End& a) const {
  // Only an axis end has a direction (a point end's d is empty and d_length 0).
  if (a.d.size() != 3 || a.d_length.is_zero())
    throw std::logic_error("unit_axis asked for the direction of a point end (not an axis)");
  return scale(1 / a.d_length, a.d);
}

Vec SpatialLibrary::angular_velocity(int node) const {
  if (node == PlanarLibrary::kGround) return kZero;
  return rigid3d::angular_velocity_in_space(m_, m_.nodes[static_cast<std::size_t>(node)]);
}

Vec SpatialLibrary::point_velocity(int node, const Vec& P) const {
  if (node == PlanarLibrary::kGround) return kZero;
  // v_P = v_G + omega x (P - x_G), G the mass centre (coordinates x, y, z; speeds u, v, w).
  const Node& n = m_.nodes[static_cast<std::size_t>(node)];
  Vec arm, vg;
  for (std::size_t k = 0; k < 3; ++k) {
    arm.push_back(P[k] - m_.coords[static_cast<std::size_t>(n.coords[k])].sym);
    vg.push_back(m_.speeds[static_cast<std::size_t>(n.speeds[k])].sym);
  }
  const Vec w = rigid3d::cross(angular_velocity(node), arm);
  return {vg[0] + w[0], vg[1] + w[1], vg[2] + w[2]};
}

void SpatialLibrary::apply_wrench(int node, const Vec& P, const Vec& F, const Vec& tau, const SourcePos& pos) {
  if (node == PlanarLibrary::kGround) return;
  const Vec v = point_velocity(node, P), w = angular_velocity(node);
  for (int s : m_.nodes[static_cast<std::size_t>(node)].speeds) {
    const GiNaC::symbol& u = m_.speeds[static_cast<std::size_t>(s)].sym;
    GiNaC::ex q = 0;
    for (std::size_t k = 0; k < 3; ++k) q += v[k].diff(u) * F[k] + w[k].diff(u) * tau[k];
    if (!q.is_zero()) m_.forces.push_back(Force{s, q, pos});
  }
}

bool SpatialLibrary::add_actuators(const PlanarLibrary::Element& e, const std::string& what, const std::string& rows,
                                   const End& a, const End& b) {
  // Which options each kind takes: a torque about a joint axis the joint lets turn, a
  // force along one it lets slide.
  auto allowed = [&](const std::string& opt) {
    if (opt == "torque") return e.kind == "revolute" || e.kind == "cylindrical";
    if (opt == "force") return e.kind == "prismatic" || e.kind == "cylindrical";
    if (opt == "friction") return e.kind == "prismatic" || e.kind == "cylindrical";
    return false;
  };
  const char* const takes = e.kind == "revolute"      ? "a revolute joint takes 'torque'"
                            : e.kind == "prismatic"   ? "a prismatic joint takes 'force' and 'friction'"
                            : e.kind == "cylindrical" ? "a cylindrical joint takes 'force', 'torque' and 'friction'"
                                                      : "only revolute (torque), prismatic (force) and cylindrical (both) "
                                                        "spatial joints take an actuator";
  for (const auto& [opt, pos] : {std::pair{e.option, e.option_pos}, std::pair{e.option2, e.option2_pos}}) {
    if (opt.empty() || allowed(opt)) continue;
    if (opt == "friction") {
      diags_.error(pos, fmt::format("{}: 'friction' is available on spatial prismatic and cylindrical joints only (a {} "
                                    "joint has no single slide with a normal reaction)",
                                    what, e.kind));
      return false;
    }
    diags_.error(pos, fmt::format("{}: option '{}' is not available on a spatial {} joint ({})", what, opt, e.kind, takes));
    return false;
  }
  if (!e.option2.empty() && e.option2 == e.option) {
    diags_.error(e.option2_pos, fmt::format("{}: option '{}' given twice", what, e.option));
    return false;
  }
  // The axis is the first end's (the second's is parallel to it while the joint holds).
  const Vec n = unit_axis(a);
  for (const auto& [opt, value, pos] : {std::tuple{e.option, e.value, e.option_pos}, std::tuple{e.option2, e.value2, e.option2_pos}}) {
    if (opt.empty() || !value) continue;
    if (opt == "friction") {
      add_friction(what, rows, *value, pos, a, b);
    } else if (opt == "torque") {  // tau n on the second body, -tau n on the first
      apply_wrench(b.node, b.p, kZero, scale(*value, n), pos);
      apply_wrench(a.node, b.p, kZero, scale(-*value, n), pos);
    } else {  // F n at the second body's point, -F n on the first at the same place
      apply_wrench(b.node, b.p, scale(*value, n), kZero, pos);
      apply_wrench(a.node, b.p, scale(-*value, n), kZero, pos);
    }
  }
  return true;
}

void SpatialLibrary::add_friction(const std::string& what, const std::string& rows, const GiNaC::ex& mu,
                                  const SourcePos& pos, const End& a, const End& b) {
  // The coefficient is a constant: the generated code solves the law at each state with
  // mu fixed, and a negative one would push the slider along its motion.
  if (const std::string varying = varies(mu); !varying.empty()) {
    diags_.error(pos, fmt::format("{}: the friction coefficient must be a constant (parameters only; it reads {})", what,
                                  varying));
    return;
  }
  if (const double v = at_defaults(mu); !std::isnan(v) && v < 0.0) {
    diags_.error(pos, fmt::format("{}: the friction coefficient must not be negative (it is {})", what, v));
    return;
  }
  // The force F n on the second end at its point, -F n on the first, like the actuator
  // (a cylindrical joint's slide the same way: its turning about the axis has no
  // friction); the slide's rate is that point's velocity on b relative to the same place
  // on a. Several joints may have friction: the generated code solves their laws together.
  Friction f;
  f.joint = rows;
  f.pos = pos;
  f.force = GiNaC::symbol(rows + ".friction");
  f.mu = mu;
  const Vec n = unit_axis(a);
  f.slide_velocity = rigid3d::dot(n, sub(point_velocity(b.node, b.p), point_velocity(a.node, b.p)));
  f.weight1 = rigid3d::dot(a.n1, a.n1);
  f.weight2 = rigid3d::dot(a.n2, a.n2);
  f.row1 = rows + ".n1";
  f.row2 = rows + ".n2";
  apply_wrench(b.node, b.p, scale(f.force, n), kZero, pos);
  apply_wrench(a.node, b.p, scale(-f.force, n), kZero, pos);
  m_.frictions.push_back(f);
}

void SpatialLibrary::add_force_element(int owner, const PlanarLibrary::Element& e) {
  const bool rotational = e.kind == "rotational_spring" || e.kind == "rotational_damper";
  const bool spring = e.kind == "spring" || e.kind == "rotational_spring";
  const std::string what = fmt::format("{} '{}'", spring ? "spring" : "damper", e.name);
  // Ends: two points, or (rotational) two axes, e.g. those of a revolute joint.
  const char* const noun = spring ? "spring" : "damper";
  const auto a = end(owner, e.end1, rotational, e.end1_pos, what, noun);
  const auto b = end(owner, e.end2, rotational, e.end2_pos, what, noun);
  if (!a || !b) return;
  if (a->node == b->node) {
    diags_.error(e.end2_pos, fmt::format("{} connects '{}' to itself", what,
                                         a->node == PlanarLibrary::kGround ? std::string("ground") : m_.label(a->node)));
    return;
  }
  // Its joint is looked for once every element is in (finish(): it may come later).
  if (rotational) rotational_.push_back({what, noun, e.end1, e.end2, e.pos, *axis_key(owner, e.end1), *axis_key(owner, e.end2)});
  const GiNaC::ex coef = *e.value;
  if (rotational) {
    // About the first axis n: the rate (omega_b - omega_a) . n and the angle theta from the
    // first axis's reference normal n1 to the second's, turning about n: theta = atan2(y, x).
    // The spring needs theta - theta0, taken in (-pi, pi] around the rest angle (the
    // normal n1 of the second end turned back by theta0), so that it wraps opposite the
    // rest angle, not at theta = +-pi: a rest angle near pi swings smoothly across pi.
    const Vec n = unit_axis(*a);
    const Vec wa = angular_velocity(a->node), wb = angular_velocity(b->node);
    GiNaC::ex tau;
    if (spring) {
      const GiNaC::ex x = rigid3d::dot(a->n1, b->n1), y = rigid3d::dot(n, rigid3d::cross(a->n1, b->n1));
      const GiNaC::ex th0 = e.length ? *e.length : GiNaC::ex(0);
      const GiNaC::ex twist =
          GiNaC::atan2(y * GiNaC::cos(th0) - x * GiNaC::sin(th0), x * GiNaC::cos(th0) + y * GiNaC::sin(th0));
      tau = -coef * twist;
      m_.nodes[static_cast<std::size_t>(owner)].potential += coef * twist * twist / 2;
    } else {
      tau = -coef * rigid3d::dot(sub(wb, wa), n);
    }
    apply_wrench(b->node, b->p, kZero, scale(tau, n), e.pos);
    apply_wrench(a->node, b->p, kZero, scale(-tau, n), e.pos);
    return;
  }
  // Along the line d = P_b - P_a. Spring: F_b = -k (L - L0) d / L, potential k (L - L0)^2 / 2
  // (no rest length: F_b = -k d, k |d|^2 / 2, no square root). Damper: F_b = -c L' d / L
  // with L' L = d . (v_b - v_a).
  const Vec d = sub(b->p, a->p);
  const GiNaC::ex d2 = rigid3d::dot(d, d);
  GiNaC::ex along;  // F_b = along * d
  if (spring && e.length) {
    const GiNaC::ex L = GiNaC::sqrt(d2);
    along = -coef * (L - *e.length) / L;
    m_.nodes[static_cast<std::size_t>(owner)].potential += coef * GiNaC::pow(L - *e.length, 2) / 2;
  } else if (spring) {
    along = -coef;
    m_.nodes[static_cast<std::size_t>(owner)].potential += coef * d2 / 2;
  } else {
    along = -coef * rigid3d::dot(d, sub(point_velocity(b->node, b->p), point_velocity(a->node, a->p))) / d2;
  }
  apply_wrench(b->node, b->p, scale(along, d), kZero, e.pos);
  apply_wrench(a->node, a->p, neg(scale(along, d)), kZero, e.pos);
}

}  // namespace mbsc::model
