// SPDX-License-Identifier: GPL-2.0-or-later
#include "planar_library.hpp"

#include <fmt/format.h>

namespace mbsc::model {

namespace {
std::string join(const std::string& a, const std::string& b) { return a.empty() ? b : a + "." + b; }
}  // namespace

PlanarLibrary::PlanarLibrary(Model& m, Diagnostics& diags) : m_(m), diags_(diags) {
  // The ground's built-ins: its origin and the two coordinate axes.
  points_["ground.origin"] = Point{kGround, 0, 0};
  axes_["ground.x_axis"] = Axis{kGround, 0, 0, 1, 0};
  axes_["ground.y_axis"] = Axis{kGround, 0, 0, 0, 1};
}

// ---- declarations ----

void PlanarLibrary::add_point(int node, const std::string& name, const GiNaC::ex& ex, const GiNaC::ex& ey,
                              const SourcePos& pos) {
  const std::string full = join(node == kGround ? "ground" : m_.nodes[node].name, name);
  if (node != kGround && m_.nodes[node].kind != LeafKind::Rigid2d) {
    diags_.error(pos, fmt::format("point '{}': points belong to rigid2d bodies and the ground (a particle2d body is "
                                  "itself a point: name the body)",
                                  full));
    return;
  }
  if (points_.count(full) || axes_.count(full)) {
    diags_.error(pos, fmt::format("point '{}' is declared twice", full));
    return;
  }
  points_[full] = Point{node, ex, ey};
}

void PlanarLibrary::set_com(int node, const GiNaC::ex& ex, const GiNaC::ex& ey, const SourcePos& pos) {
  if (m_.nodes[node].kind != LeafKind::Rigid2d) {
    diags_.error(pos, fmt::format("'com' is only allowed in rigid2d bodies ('{}' is not one)", m_.label(node)));
    return;
  }
  if (com_.count(node)) {
    diags_.error(pos, fmt::format("the mass centre of '{}' is given twice", m_.label(node)));
    return;
  }
  com_[node] = {ex, ey};
}

void PlanarLibrary::add_axis(int node, const std::string& name, const GiNaC::ex& px, const GiNaC::ex& py,
                             const GiNaC::ex& dx, const GiNaC::ex& dy, const SourcePos& pos) {
  const std::string full = join(node == kGround ? "ground" : m_.nodes[node].name, name);
  if (node != kGround && m_.nodes[node].kind != LeafKind::Rigid2d) {
    diags_.error(pos, fmt::format("axis '{}': axes belong to rigid2d bodies and the ground", full));
    return;
  }
  if (points_.count(full) || axes_.count(full)) {
    diags_.error(pos, fmt::format("axis '{}' is declared twice", full));
    return;
  }
  // A direction of length zero defines no line (checked with the parameters' defaults).
  GiNaC::exmap defaults;
  for (std::size_t i = 0; i < m_.params.size(); ++i) defaults[m_.params[i].sym] = m_.param_defaults[i];
  const GiNaC::ex len2 = GiNaC::evalf((dx * dx + dy * dy).subs(defaults));
  if (GiNaC::is_a<GiNaC::numeric>(len2) && GiNaC::ex_to<GiNaC::numeric>(len2).to_double() == 0.0) {
    diags_.error(pos, fmt::format("axis '{}' has a zero direction vector", full));
    return;
  }
  axes_[full] = Axis{node, px, py, dx, dy};
}

// ---- poses ----

std::optional<int> PlanarLibrary::body(int owner, const std::string& path) const {
  if (path == "ground") return kGround;
  for (int n = owner; n >= 0; n = m_.nodes[n].parent) {
    const std::string full = join(m_.nodes[n].name, path);
    for (std::size_t k = 0; k < m_.nodes.size(); ++k)
      if (m_.nodes[k].name == full && is_body(m_.nodes[k].kind)) return static_cast<int>(k);
    if (m_.nodes[n].parent < 0) break;
  }
  return std::nullopt;
}

std::pair<GiNaC::ex, GiNaC::ex> PlanarLibrary::world(int node, const GiNaC::ex& px, const GiNaC::ex& py) const {
  if (node == kGround) return {px, py};
  const Node& b = m_.nodes[node];
  const GiNaC::ex x = m_.coords[b.coords[0]].sym, y = m_.coords[b.coords[1]].sym;
  if (b.kind != LeafKind::Rigid2d) return {x + px, y + py};
  const GiNaC::ex th = m_.coords[b.coords[2]].sym;
  auto c = com_.find(node);
  const GiNaC::ex ax = px - (c == com_.end() ? GiNaC::ex(0) : c->second.first);
  const GiNaC::ex ay = py - (c == com_.end() ? GiNaC::ex(0) : c->second.second);
  return {x + GiNaC::cos(th) * ax - GiNaC::sin(th) * ay, y + GiNaC::sin(th) * ax + GiNaC::cos(th) * ay};
}

std::optional<GiNaC::ex> PlanarLibrary::angle(int node) const {
  if (node == kGround) return GiNaC::ex(0);
  const Node& b = m_.nodes[node];
  if (b.kind != LeafKind::Rigid2d) return std::nullopt;
  return GiNaC::ex(m_.coords[b.coords[2]].sym);
}

std::pair<GiNaC::ex, GiNaC::ex> PlanarLibrary::velocity(int node, const GiNaC::ex& x, const GiNaC::ex& y) const {
  if (node == kGround) return {0, 0};
  const Node& b = m_.nodes[node];
  const GiNaC::ex u = m_.speeds[b.speeds[0]].sym, v = m_.speeds[b.speeds[1]].sym;
  if (b.kind != LeafKind::Rigid2d) return {u, v};
  // v_P = v_c + w x (r_P - r_c)
  const GiNaC::ex w = m_.speeds[b.speeds[2]].sym;
  const GiNaC::ex rx = x - m_.coords[b.coords[0]].sym, ry = y - m_.coords[b.coords[1]].sym;
  return {u - w * ry, v + w * rx};
}

// "body.name" seen from `owner`: the body's node and the declaration in `table`, or null.
template <class Decl>
const Decl* PlanarLibrary::element_of(int owner, const std::string& path, const std::map<std::string, Decl>& table,
                                      int& node) const {
  const auto dot = path.rfind('.');
  if (dot == std::string::npos) return nullptr;
  const auto b = body(owner, path.substr(0, dot));
  if (!b) return nullptr;
  auto it = table.find(join(*b == kGround ? "ground" : m_.nodes[*b].name, path.substr(dot + 1)));
  if (it == table.end()) return nullptr;
  node = *b;
  return &it->second;
}

std::optional<PlanarLibrary::Located> PlanarLibrary::point(int owner, const std::string& path, const SourcePos& pos) {
  // A particle2d body is a point itself.
  if (auto b = body(owner, path); b && *b != kGround && m_.nodes[*b].kind == LeafKind::Particle2d) {
    auto r = world(*b, 0, 0);
    return Located{*b, r.first, r.second};
  }
  int node = kGround;
  if (const Point* p = element_of(owner, path, points_, node)) {
    auto r = world(node, p->ex, p->ey);
    return Located{node, r.first, r.second};
  }
  diags_.error(pos, fmt::format("unknown point '{}' (a point of a rigid2d body or the ground, or a particle2d body)", path));
  return std::nullopt;
}

std::optional<std::pair<PlanarLibrary::Located, std::pair<GiNaC::ex, GiNaC::ex>>> PlanarLibrary::axis(int owner,
                                                                                                      const std::string& path,
                                                                                                      const SourcePos& pos) {
  int node = kGround;
  if (const Axis* a = element_of(owner, path, axes_, node)) {
    auto base = world(node, a->px, a->py);
    // The direction turns with the body: R(theta) d.
    const auto th = angle(node);
    const GiNaC::ex c = th ? GiNaC::cos(*th) : GiNaC::ex(1), s = th ? GiNaC::sin(*th) : GiNaC::ex(0);
    return std::make_pair(Located{node, base.first, base.second}, std::make_pair(c * a->dx - s * a->dy, s * a->dx + c * a->dy));
  }
  diags_.error(pos, fmt::format("unknown axis '{}' (an axis of a rigid2d body or the ground)", path));
  return std::nullopt;
}

// ---- forces ----

void PlanarLibrary::apply_force(int node, const GiNaC::ex& x, const GiNaC::ex& y, const GiNaC::ex& fx, const GiNaC::ex& fy,
                                const SourcePos& pos) {
  if (node == kGround) return;
  // Q_j = (d v_P / d q1_j) . F over the body's speeds.
  const auto v = velocity(node, x, y);
  for (int s : m_.nodes[node].speeds) {
    const GiNaC::ex q = v.first.diff(m_.speeds[s].sym) * fx + v.second.diff(m_.speeds[s].sym) * fy;
    if (!q.is_zero()) m_.forces.push_back(Force{s, q, pos});
  }
}

void PlanarLibrary::apply_torque(int node, const GiNaC::ex& tau, const SourcePos& pos) {
  if (node == kGround || m_.nodes[node].kind != LeafKind::Rigid2d) return;
  m_.forces.push_back(Force{m_.nodes[node].speeds[2], tau, pos});
}

void PlanarLibrary::add_constraint(int owner, const std::string& name, const GiNaC::ex& residual, const SourcePos& pos) {
  Constraint c;
  c.name = join(m_.nodes[owner].name, name);
  c.node = owner;
  c.level = Constraint::Level::Position;
  c.residual = residual;
  c.pos = pos;
  m_.nodes[owner].constraints.push_back(static_cast<int>(m_.constraints.size()));
  m_.constraints.push_back(c);
}

// ---- between two bodies' angles: gear pairs, rotational springs and dampers ----

void PlanarLibrary::add_rotational(int owner, const Element& e, const std::string& name, const std::string& what) {
  const auto a = body(owner, e.end1), b = body(owner, e.end2);
  if (!a || !b) {
    diags_.error(!a ? e.end1_pos : e.end2_pos,
                 fmt::format("{}: unknown body '{}' (a rigid2d body or ground)", what, !a ? e.end1 : e.end2));
    return;
  }
  const auto tha = angle(*a), thb = angle(*b);
  if (!tha || !thb || *a == *b) {
    diags_.error(e.end2_pos, fmt::format("{} needs two different rigid bodies (or a rigid body and the ground)", what));
    return;
  }
  auto rate = [&](int n) {
    return n == kGround ? GiNaC::ex(0) : GiNaC::ex(m_.speeds[m_.nodes[n].speeds[2]].sym);
  };
  if (e.kind == "gear") {
    // w_b = -ratio w_a (external mesh), as a velocity constraint between the bodies.
    if (e.option != "ratio") {
      diags_.error(e.kind_pos, fmt::format("{} needs 'ratio r' (w_{} = -r w_{})", what, e.end2, e.end1));
      return;
    }
    Constraint c;
    c.name = join(m_.nodes[owner].name, name + ".ratio");
    c.node = owner;
    c.level = Constraint::Level::Velocity;
    c.residual = rate(*b) + *e.value * rate(*a);
    c.pos = e.pos;
    m_.nodes[owner].constraints.push_back(static_cast<int>(m_.constraints.size()));
    m_.constraints.push_back(c);
    return;
  }
  if (e.kind == "rotational_spring") {
    const GiNaC::ex twist = *thb - *tha - (e.length ? *e.length : GiNaC::ex(0));
    apply_torque(*b, -*e.value * twist, e.pos);
    apply_torque(*a, *e.value * twist, e.pos);
    m_.nodes[owner].potential += *e.value * twist * twist / 2;
  } else {
    const GiNaC::ex tau = -*e.value * (rate(*b) - rate(*a));
    apply_torque(*b, tau, e.pos);
    apply_torque(*a, -tau, e.pos);
  }
}

// ---- a disc rolling without slipping on a fixed line ----

void PlanarLibrary::add_rolling(int owner, const Element& e, const std::string& name, const std::string& what) {
  auto a = axis(owner, e.end1, e.end1_pos);
  if (!a) return;
  if (a->first.node != kGround) {
    diags_.error(e.end1_pos, fmt::format("{}: rolling on a moving body's line is not supported yet; use a ground axis", what));
    return;
  }
  const auto disc = body(owner, e.end2);
  if (!disc || *disc == kGround || m_.nodes[*disc].kind != LeafKind::Rigid2d) {
    diags_.error(e.end2_pos, fmt::format("{}: '{}' is not a rigid2d body (the disc; its mass centre is its centre)", what, e.end2));
    return;
  }
  if (e.option != "radius") {
    diags_.error(e.kind_pos, fmt::format("{} needs 'radius r'", what));
    return;
  }
  const Node& b = m_.nodes[*disc];
  const GiNaC::ex cx = m_.coords[b.coords[0]].sym, cy = m_.coords[b.coords[1]].sym, r = *e.value;
  // Unit tangent t along the axis, the disc on its left (normal n = (-t_y, t_x)).
  const GiNaC::ex len = GiNaC::sqrt(a->second.first * a->second.first + a->second.second * a->second.second);
  const GiNaC::ex tx = a->second.first / len, ty = a->second.second / len;
  // Contact: the centre is r from the line. No slip: the contact point is at rest,
  // v_c . t + r w = 0.
  add_constraint(owner, name + ".contact", -ty * (cx - a->first.x) + tx * (cy - a->first.y) - r, e.pos);
  Constraint c;
  c.name = join(m_.nodes[owner].name, name + ".no_slip");
  c.node = owner;
  c.level = Constraint::Level::Velocity;
  c.residual = tx * m_.speeds[b.speeds[0]].sym + ty * m_.speeds[b.speeds[1]].sym + r * m_.speeds[b.speeds[2]].sym;
  c.pos = e.pos;
  m_.nodes[owner].constraints.push_back(static_cast<int>(m_.constraints.size()));
  m_.constraints.push_back(c);
}

// ---- joints, springs, dampers ----

void PlanarLibrary::add_element(int owner, const Element& e) {
  const bool joint = e.kind == "revolute" || e.kind == "prismatic" || e.kind == "weld" || e.kind == "pin_in_slot" ||
                     e.kind == "gear" || e.kind == "rolling";
  if (!joint && e.kind != "spring" && e.kind != "damper" && e.kind != "rotational_spring" && e.kind != "rotational_damper") {
    diags_.error(e.kind_pos,
                 fmt::format("unknown joint kind '{}' (known: revolute, prismatic, pin_in_slot, weld, gear, rolling)", e.kind));
    return;
  }
  const std::string name = e.name.empty() ? fmt::format("{}{}", e.kind, ++unnamed_) : e.name;
  const std::string what = fmt::format("{} '{}'", joint ? "joint" : e.kind == "rotational_spring"   ? "spring"
                                                                   : e.kind == "rotational_damper" ? "damper"
                                                                                                   : e.kind,
                                       name);
  if (e.kind == "gear" || e.kind == "rotational_spring" || e.kind == "rotational_damper") {
    add_rotational(owner, e, name, what);
    return;
  }
  if (e.kind == "rolling") {
    add_rolling(owner, e, name, what);
    return;
  }
  // Ends: two points, or (prismatic) an axis and a point.
  std::optional<Located> p1, p2;
  std::pair<GiNaC::ex, GiNaC::ex> dir;
  if (e.kind == "prismatic" || e.kind == "pin_in_slot") {
    auto a = axis(owner, e.end1, e.end1_pos);
    if (!a) return;
    p1 = a->first;
    dir = a->second;
  } else {
    p1 = point(owner, e.end1, e.end1_pos);
  }
  p2 = point(owner, e.end2, e.end2_pos);
  if (!p1 || !p2) return;
  if (p1->node == p2->node) {
    diags_.error(e.end2_pos, fmt::format("{} connects '{}' to itself", what,
                                         p1->node == kGround ? std::string("ground") : m_.label(p1->node)));
    return;
  }
  const auto th1 = angle(p1->node), th2 = angle(p2->node);
  const GiNaC::ex dx = p2->x - p1->x, dy = p2->y - p1->y;

  if (e.kind == "weld" && (!th1 || !th2)) {
    diags_.error(e.kind_pos, fmt::format("{} needs two rigid bodies (or a rigid body and the ground)", what));
    return;
  }
  if (e.kind == "revolute" || e.kind == "weld") {
    add_constraint(owner, name + ".x", dx, e.pos);
    add_constraint(owner, name + ".y", dy, e.pos);
  }
  if (e.kind == "prismatic" || e.kind == "pin_in_slot") {
    // The point stays on the line: the normal component of r_Q - r_A vanishes.
    add_constraint(owner, name + ".normal", dir.first * dy - dir.second * dx, e.pos);
  }
  const bool locks_angle = e.kind == "weld" || (e.kind == "prismatic" && th1 && th2);
  GiNaC::ex rel = 0;
  if (e.option == "angle") {
    if (!locks_angle) {
      diags_.error(e.option_pos, fmt::format("{} fixes no relative angle, so 'angle' does not apply", what));
      return;
    }
    rel = *e.value;
  }
  if (locks_angle) add_constraint(owner, name + ".angle", *th2 - *th1 - rel, e.pos);

  // Actuators: a torque across a revolute joint, a force along a prismatic one.
  if (e.option == "torque") {
    const bool rotates = (p1->node != kGround && th1) || (p2->node != kGround && th2);
    if (e.kind != "revolute" || !rotates) {
      diags_.error(e.option_pos, fmt::format("{} has no rotation for a torque to act on ({} allows {})", what, e.kind,
                                             e.kind == "prismatic" ? "a force" : "no actuator"));
      return;
    }
    apply_torque(p2->node, *e.value, e.option_pos);
    apply_torque(p1->node, -*e.value, e.option_pos);
  } else if (e.option == "force") {
    if (e.kind != "prismatic" && e.kind != "pin_in_slot") {
      diags_.error(e.option_pos, fmt::format("{} has no sliding motion for a force to act along ({} allows {})", what, e.kind,
                                             e.kind == "revolute" ? "a torque" : "no actuator"));
      return;
    }
    const GiNaC::ex len = GiNaC::sqrt(dir.first * dir.first + dir.second * dir.second);
    const GiNaC::ex fx = *e.value * dir.first / len, fy = *e.value * dir.second / len;
    apply_force(p2->node, p2->x, p2->y, fx, fy, e.option_pos);
    apply_force(p1->node, p2->x, p2->y, -fx, -fy, e.option_pos);
  } else if (joint && !e.option.empty() && e.option != "angle") {
    diags_.error(e.option_pos, fmt::format("{}: unknown option '{}' (torque, force or angle)", what, e.option));
    return;
  }

  if (e.kind == "spring") {
    // F on the second end = -k (L - L0) d / L; with no rest length, -k d (no square root).
    const GiNaC::ex k = *e.value;
    GiNaC::ex fx = -k * dx, fy = -k * dy, V = k * (dx * dx + dy * dy) / 2;
    if (e.length) {
      const GiNaC::ex L = GiNaC::sqrt(dx * dx + dy * dy);
      fx = -k * (L - *e.length) * dx / L;
      fy = -k * (L - *e.length) * dy / L;
      V = k * GiNaC::pow(L - *e.length, 2) / 2;
    }
    apply_force(p2->node, p2->x, p2->y, fx, fy, e.pos);
    apply_force(p1->node, p1->x, p1->y, -fx, -fy, e.pos);
    m_.nodes[owner].potential += V;
  } else if (e.kind == "damper") {
    // F on the second end = -c (d . d') d / |d|^2: it resists the rate of the distance.
    const auto v1 = velocity(p1->node, p1->x, p1->y), v2 = velocity(p2->node, p2->x, p2->y);
    const GiNaC::ex rate = (dx * (v2.first - v1.first) + dy * (v2.second - v1.second)) / (dx * dx + dy * dy);
    const GiNaC::ex fx = -*e.value * rate * dx, fy = -*e.value * rate * dy;
    apply_force(p2->node, p2->x, p2->y, fx, fy, e.pos);
    apply_force(p1->node, p1->x, p1->y, -fx, -fy, e.pos);
  }
}

}  // namespace mbsc::model
