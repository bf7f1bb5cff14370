// SPDX-License-Identifier: GPL-2.0-or-later
#include "planar_library.hpp"
#include "mbsc/model/exact_guard.hpp"
#include "mbsc/model/expr_convert.hpp"

#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "mbsc/diag/name_suggestions.hpp"

#include <tuple>

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
  if (node != kGround && !is_rigid2d(m_.nodes[node].kind)) {
    diags_.error(pos, fmt::format("point '{}': points belong to rigid2d bodies and the ground (a particle2d body is "
                                  "itself a point: name the body)",
                                  full));
    return;
  }
  if (points_.count(full) || axes_.count(full)) {
    diags_.error(pos, fmt::format("point '{}' is declared twice{}", full, first_declared(full, pos)));
    return;
  }
  points_[full] = Point{node, ex, ey, pos};
}

std::string PlanarLibrary::first_declared(const std::string& full, const SourcePos& here) const {
  const auto p = points_.find(full);
  const auto a = axes_.find(full);
  const char* what = p != points_.end() ? "a point" : "an axis";
  const SourcePos first = p != points_.end() ? p->second.pos : a != axes_.end() ? a->second.pos : SourcePos{};
  if (first.line <= 0) return fmt::format(" (as {} built into the ground)", what);
  return fmt::format(" (as {} at {}{}:{})", what, first.file == here.file ? "" : first.file + ":", first.line, first.col);
}

void PlanarLibrary::add_failed(int node, const std::string& name) {
  failed_.insert(join(node == kGround ? "ground" : m_.nodes[node].name, name));
}

bool PlanarLibrary::failed(int owner, const std::string& path) const {
  const auto dot = path.rfind('.');
  if (dot == std::string::npos) return false;
  const auto b = body(owner, path.substr(0, dot));
  return b && failed_.count(join(*b == kGround ? "ground" : m_.nodes[*b].name, path.substr(dot + 1)));
}

void PlanarLibrary::set_com(int node, const GiNaC::ex& ex, const GiNaC::ex& ey, const SourcePos& pos) {
  if (!is_rigid2d(m_.nodes[node].kind)) {
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
  if (node != kGround && !is_rigid2d(m_.nodes[node].kind)) {
    diags_.error(pos, fmt::format("axis '{}': axes belong to rigid2d bodies and the ground", full));
    return;
  }
  if (points_.count(full) || axes_.count(full)) {
    diags_.error(pos, fmt::format("axis '{}' is declared twice{}", full, first_declared(full, pos)));
    return;
  }
  // A direction of length zero defines no line (checked with the parameters' defaults).
  if (at_defaults(dx * dx + dy * dy) == 0.0) {
    diags_.error(pos, fmt::format("axis '{}' has a zero direction vector", full));
    failed_.insert(full);  // a joint naming it says no more
    return;
  }
  axes_[full] = Axis{node, px, py, dx, dy, pos};
}

double PlanarLibrary::at_defaults(const GiNaC::ex& e) const {
  try {
    if (defaults_.size() != m_.params.size()) {  // the parameters are all declared before any geometry
      defaults_.clear();
      for (std::size_t i = 0; i < m_.params.size(); ++i) defaults_[m_.params[i].sym] = m_.param_defaults[i];
    }
    double value = std::numeric_limits<double>::quiet_NaN();
    return evaluate_number(GiNaC::evalf(subs_present(e, defaults_)), value) ? value
                                                                             : std::numeric_limits<double>::quiet_NaN();
  } catch (const std::exception&) {
    return std::numeric_limits<double>::quiet_NaN();
  }
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

std::size_t PlanarLibrary::node_count(int node) const {
  std::size_t n = 0;
  for (const auto& [name, p] : points_) n += p.node == node;
  return n;
}

std::vector<PlanarLibrary::Node2> PlanarLibrary::nodes_of(int node) const {
  // Coordinates come in pairs P_x, P_y (declaration order), speeds P_u, P_v, then w;
  // coordinates and speeds the body declares itself follow.
  const Node& b = m_.nodes[node];
  std::vector<Node2> out;
  const std::size_t n_nodes = node_count(node);
  for (std::size_t k = 0; k < 2 * n_nodes && k + 1 < b.coords.size(); k += 2) {
    const std::string& qx = m_.coords[b.coords[k]].name;  // "body.P_x"
    const auto it = points_.find(qx.substr(0, qx.size() - 2));
    if (it == points_.end()) break;  // a point that failed (reported): the body is not used
    const Point& p = it->second;
    out.push_back(Node2{p.ex, p.ey, m_.coords[b.coords[k]].sym, m_.coords[b.coords[k + 1]].sym, m_.speeds[b.speeds[k]].sym,
                        m_.speeds[b.speeds[k + 1]].sym});
  }
  return out;
}

std::pair<GiNaC::ex, GiNaC::ex> PlanarLibrary::rotate(int node, const GiNaC::ex& dx, const GiNaC::ex& dy) const {
  if (node == kGround) return {dx, dy};
  const Node& b = m_.nodes[node];
  if (b.kind == LeafKind::Rigid2d) {
    const GiNaC::ex th = m_.coords[b.coords[2]].sym;
    return {GiNaC::cos(th) * dx - GiNaC::sin(th) * dy, GiNaC::sin(th) * dx + GiNaC::cos(th) * dy};
  }
  if (b.kind == LeafKind::Rigid2dNodal) {
    // The rotation taking the body-frame delta = b2 - b1 to the world Delta = p2 - p1
    // (equal lengths on the rigidity invariant): d = a delta + c z x delta maps to
    // a Delta + c z x Delta. Polynomial in the nodal coordinates: no angle needed.
    const auto n = nodes_of(node);
    if (n.size() < 2) return {dx, dy};  // a point of the body failed (reported): any value will do
    const GiNaC::ex ddx = n[1].bx - n[0].bx, ddy = n[1].by - n[0].by, l2 = ddx * ddx + ddy * ddy;
    if (l2.is_zero()) return {dx, dy};  // coincident frame nodes: reported by finish_nodal
    const GiNaC::ex Dx = n[1].x - n[0].x, Dy = n[1].y - n[0].y;
    const GiNaC::ex a = (ddx * dx + ddy * dy) / l2, c = (ddx * dy - ddy * dx) / l2;
    return {a * Dx - c * Dy, a * Dy + c * Dx};
  }
  return {dx, dy};
}

std::optional<int> PlanarLibrary::omega_speed(int node) const {
  if (node == kGround) return std::nullopt;
  const Node& b = m_.nodes[node];
  if (b.kind == LeafKind::Rigid2d) return b.speeds[2];
  if (b.kind == LeafKind::Rigid2dNodal) return b.speeds[2 * node_count(node)];
  return std::nullopt;
}

std::pair<GiNaC::ex, GiNaC::ex> PlanarLibrary::world(int node, const GiNaC::ex& px, const GiNaC::ex& py) const {
  if (node == kGround) return {px, py};
  const Node& b = m_.nodes[node];
  if (b.kind == LeafKind::Rigid2dNodal) {
    // A node is where its coordinates say; any other point follows the first node.
    const auto n = nodes_of(node);
    if (n.size() < 2) return {px, py};  // a point of the body failed (reported)
    for (const auto& k : n)
      if (expand_if_small(k.bx - px).is_zero() && expand_if_small(k.by - py).is_zero()) return {k.x, k.y};
    const auto d = rotate(node, px - n[0].bx, py - n[0].by);
    return {n[0].x + d.first, n[0].y + d.second};
  }
  const GiNaC::ex x = m_.coords[b.coords[0]].sym, y = m_.coords[b.coords[1]].sym;
  if (b.kind != LeafKind::Rigid2d) return {x + px, y + py};
  auto c = com_.find(node);
  const auto d = rotate(node, px - (c == com_.end() ? GiNaC::ex(0) : c->second.first),
                        py - (c == com_.end() ? GiNaC::ex(0) : c->second.second));
  return {x + d.first, y + d.second};
}

std::optional<GiNaC::ex> PlanarLibrary::angle(int node) const {
  if (node == kGround) return GiNaC::ex(0);
  const Node& b = m_.nodes[node];
  if (b.kind == LeafKind::Rigid2dNodal) {
    // The turn of the first two nodes' line from its body-frame direction (it jumps by
    // 2 pi where either atan2 does: joints and springs use relative_angle instead).
    const auto n = nodes_of(node);
    if (n.size() < 2) return GiNaC::ex(0);  // a point of the body failed (reported)
    return GiNaC::atan2(n[1].y - n[0].y, n[1].x - n[0].x) - GiNaC::atan2(n[1].by - n[0].by, n[1].bx - n[0].bx);
  }
  if (b.kind != LeafKind::Rigid2d) return std::nullopt;
  return GiNaC::ex(m_.coords[b.coords[2]].sym);
}

bool PlanarLibrary::nodal(int node) const { return node != kGround && m_.nodes[node].kind == LeafKind::Rigid2dNodal; }

GiNaC::ex PlanarLibrary::relative_angle(int a, int b) const {
  // Bodies in absolute coordinates: the difference of their angle coordinates. With a
  // nodal body there is no angle coordinate; the turn from a's frame to b's is read off
  // their rotated x directions, atan2(e_a x e_b, e_a . e_b): continuous as each body
  // turns, where a difference of two atan2 would jump by 2 pi.
  if (!nodal(a) && !nodal(b)) return *angle(b) - *angle(a);
  const auto ea = rotate(a, 1, 0), eb = rotate(b, 1, 0);
  return GiNaC::atan2(ea.first * eb.second - ea.second * eb.first, ea.first * eb.first + ea.second * eb.second);
}

GiNaC::ex PlanarLibrary::angle_residual(int a, int b, const GiNaC::ex& rel) const {
  // theta_b - theta_a = rel. With a nodal body, as sin(theta_b - theta_a - rel) = 0 in
  // the rotated x directions (polynomial in the nodes, no branch cut).
  if (!nodal(a) && !nodal(b)) return *angle(b) - *angle(a) - rel;
  const auto ea = rotate(a, 1, 0), eb = rotate(b, 1, 0);
  const GiNaC::ex cross = ea.first * eb.second - ea.second * eb.first, dot = ea.first * eb.first + ea.second * eb.second;
  return rel.is_zero() ? cross : cross * GiNaC::cos(rel) - dot * GiNaC::sin(rel);
}

std::pair<GiNaC::ex, GiNaC::ex> PlanarLibrary::velocity(int node, const GiNaC::ex& x, const GiNaC::ex& y) const {
  if (node == kGround) return {0, 0};
  const Node& b = m_.nodes[node];
  if (b.kind == LeafKind::Rigid2dNodal) {
    // v_P = v_1 + w z x (r_P - p_1), from the first node.
    const auto n = nodes_of(node);
    if (n.empty()) return {0, 0};  // a point of the body failed (reported)
    const GiNaC::ex w = m_.speeds[*omega_speed(node)].sym;
    return {n[0].u - w * (y - n[0].y), n[0].v + w * (x - n[0].x)};
  }
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
  if (failed(owner, path)) return std::nullopt;  // its declaration's error is reported
  diags_.error(pos, fmt::format("unknown point '{}'{} (a point of a rigid2d body or the ground, or a particle2d body)", path,
                                suggest_element(owner, path, true)));
  return std::nullopt;
}

std::optional<std::pair<PlanarLibrary::Located, std::pair<GiNaC::ex, GiNaC::ex>>> PlanarLibrary::axis(int owner,
                                                                                                      const std::string& path,
                                                                                                      const SourcePos& pos) {
  int node = kGround;
  if (const Axis* a = element_of(owner, path, axes_, node)) {
    auto base = world(node, a->px, a->py);
    // The direction turns with the body.
    return std::make_pair(Located{node, base.first, base.second}, rotate(node, a->dx, a->dy));
  }
  if (failed(owner, path)) return std::nullopt;  // its declaration's error is reported
  diags_.error(pos, fmt::format("unknown axis '{}'{} (an axis of a rigid2d body or the ground)", path,
                                suggest_element(owner, path, false)));
  return std::nullopt;
}

std::string PlanarLibrary::suggest_element(int owner, const std::string& path, bool point) const {
  // A full name as written at `owner`: relative to the innermost scope that holds it.
  auto written = [&](const std::string& full) {
    for (int n = owner; n >= 0; n = m_.nodes[n].parent) {
      const std::string& scope = m_.nodes[n].name;
      if (!scope.empty() && full.rfind(scope + ".", 0) == 0) return full.substr(scope.size() + 1);
      if (m_.nodes[n].parent < 0) break;
    }
    return full;
  };
  const auto dot = path.rfind('.');
  const std::optional<int> b = dot == std::string::npos ? std::nullopt : body(owner, path.substr(0, dot));
  std::vector<std::string> candidates;
  auto add = [&](const std::string& full, int node) {
    if (!b) candidates.push_back(written(full));
    else if (node == *b) candidates.push_back(path.substr(0, dot) + full.substr(full.rfind('.')));
  };
  if (point) {
    for (const auto& [full, p] : points_) add(full, p.node);
    if (!b)
      for (const auto& n : m_.nodes)
        if (n.kind == LeafKind::Particle2d) candidates.push_back(written(n.name));
  } else {
    for (const auto& [full, a] : axes_) add(full, a.node);
  }
  return did_you_mean(path, candidates);
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
  if (const auto w = omega_speed(node)) m_.forces.push_back(Force{*w, tau, pos});
}

void PlanarLibrary::add_constraint(int owner, const std::string& name, const GiNaC::ex& residual, const SourcePos& pos,
                                   Constraint::Level level, int explicit_coordinate) {
  Constraint c;
  c.explicit_coordinate = explicit_coordinate;
  c.name = join(m_.nodes[owner].name, name);
  c.node = owner;
  c.level = level;
  c.residual = residual;
  c.pos = pos;
  m_.nodes[owner].constraints.push_back(static_cast<int>(m_.constraints.size()));
  m_.constraints.push_back(c);
}

void PlanarLibrary::add_velocity_constraint(int owner, const std::string& name, const GiNaC::ex& residual,
                                            const SourcePos& pos) {
  add_constraint(owner, name, residual, pos, Constraint::Level::Velocity);
}

// ---- bodies in nodal coordinates (thesis Ex 2.6, Mo2DPack RigidBody) ----

void PlanarLibrary::finish_nodal(int node) {
  Node& b = m_.nodes[node];
  const auto n = nodes_of(node);
  if (n.size() < 2) return;  // fewer than two nodes: reported where the body is declared
  const GiNaC::ex ddx = n[1].bx - n[0].bx, ddy = n[1].by - n[0].by, l2 = ddx * ddx + ddy * ddy;
  if (at_defaults(l2) == 0.0) {
    diags_.error(b.pos, fmt::format("rigid2d_nodal body '{}': its first two points coincide (they set its frame)", b.name));
    return;
  }
  const std::string owner_name = "rigid";
  // Rigidity: the first two nodes keep their distance; every further node sits where the
  // body frame of the first two puts it (two linear rows, never degenerate).
  const GiNaC::ex Dx = n[1].x - n[0].x, Dy = n[1].y - n[0].y;
  add_constraint(node, owner_name + ".length", Dx * Dx + Dy * Dy - l2, b.pos);
  for (std::size_t k = 2; k < n.size(); ++k) {
    const auto d = rotate(node, n[k].bx - n[0].bx, n[k].by - n[0].by);
    const std::string& qx = m_.coords[b.coords[2 * k]].name;
    const std::string tag = qx.substr(b.name.size() + 1, qx.size() - b.name.size() - 3);
    add_constraint(node, owner_name + "." + tag + ".x", n[k].x - n[0].x - d.first, b.pos);
    add_constraint(node, owner_name + "." + tag + ".y", n[k].y - n[0].y - d.second, b.pos);
  }
  // The angular speed: w |delta|^2 = Delta x Delta'.
  const int w_speed = *omega_speed(node);
  const GiNaC::ex w = m_.speeds[w_speed].sym, wdot = m_.speed_dots[w_speed];
  add_velocity_constraint(node, owner_name + ".w", w * l2 - (Dx * (n[1].v - n[0].v) - Dy * (n[1].u - n[0].u)), b.pos);

  // Mass centre r* = p1 + g Delta + h z x Delta (g, h from the body frame), and its
  // velocity from the first two nodes' speeds with constant coefficients, so the nodal
  // mass matrix is constant: v* = (1 - g) v1 + g v2 + h z x (v2 - v1).
  auto c = com_.find(node);
  const GiNaC::ex cx = (c == com_.end() ? GiNaC::ex(0) : c->second.first) - n[0].bx;
  const GiNaC::ex cy = (c == com_.end() ? GiNaC::ex(0) : c->second.second) - n[0].by;
  const GiNaC::ex g = (cx * ddx + cy * ddy) / l2, h = (ddx * cy - ddy * cx) / l2;
  const GiNaC::ex rx = n[0].x + g * Dx - h * Dy, ry = n[0].y + g * Dy + h * Dx;
  auto cm_velocity = [&](const GiNaC::ex& u1, const GiNaC::ex& v1, const GiNaC::ex& u2, const GiNaC::ex& v2) {
    return std::make_pair((1 - g) * u1 + g * u2 - h * (v2 - v1), (1 - g) * v1 + g * v2 + h * (u2 - u1));
  };
  const auto vs = cm_velocity(n[0].u, n[0].v, n[1].u, n[1].v);
  auto dot_of = [&](int k) { return m_.speed_dots[static_cast<std::size_t>(b.speeds[static_cast<std::size_t>(k)])]; };
  const auto as = cm_velocity(dot_of(0), dot_of(1), dot_of(2), dot_of(3));
  const GiNaC::ex gx = m_.gravity.size() > 0 ? m_.gravity[0] : GiNaC::ex(0);
  const GiNaC::ex gy = m_.gravity.size() > 1 ? m_.gravity[1] : GiNaC::ex(0);
  // Effective forces (m g - m a*) . d v*/d q1 over the first two nodes' speeds, -J w' on w.
  const GiNaC::ex fx = b.mass * (gx - as.first), fy = b.mass * (gy - as.second);
  for (int k : {b.speeds[0], b.speeds[1], b.speeds[2], b.speeds[3]}) {
    const GiNaC::ex q = vs.first.diff(m_.speeds[k].sym) * fx + vs.second.diff(m_.speeds[k].sym) * fy;
    if (!q.is_zero()) m_.forces.push_back(Force{k, q, b.pos});
  }
  m_.forces.push_back(Force{w_speed, -b.inertia * wdot, b.pos});
  b.kinetic = GiNaC::numeric(1, 2) * b.mass * (vs.first * vs.first + vs.second * vs.second) +
              GiNaC::numeric(1, 2) * b.inertia * w * w;
  b.has_kinetic = true;
  b.potential += -b.mass * (gx * rx + gy * ry);
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
    const auto w = omega_speed(n);
    return w ? GiNaC::ex(m_.speeds[*w].sym) : GiNaC::ex(0);
  };
  if (e.kind == "gear") {
    // w_b = -ratio w_a (external mesh), as a velocity constraint between the bodies.
    if (e.option != "ratio") {
      diags_.error(e.kind_pos, fmt::format("{} needs 'ratio r' (w_{} = -r w_{})", what, e.end2, e.end1));
      return;
    }
    add_velocity_constraint(owner, name + ".ratio", rate(*b) + *e.value * rate(*a), e.pos);
    return;
  }
  if (e.kind == "rotational_spring") {
    const GiNaC::ex twist = relative_angle(*a, *b) - (e.length ? *e.length : GiNaC::ex(0));
    apply_torque(*b, -*e.value * twist, e.pos);
    apply_torque(*a, *e.value * twist, e.pos);
    m_.nodes[owner].potential += *e.value * twist * twist / 2;
  } else {
    const GiNaC::ex tau = -*e.value * (rate(*b) - rate(*a));
    apply_torque(*b, tau, e.pos);
    apply_torque(*a, -tau, e.pos);
  }
}

// ---- discs rolling without slipping: on a line, inside a ring ----

// A disc (a rigid2d body whose mass centre is its centre) on a line of the ground or of
// another body. Vector form: n . (c - p0) = r (contact) and (v_disc(P) - v_line(P)) . t = 0
// at the contact point P = c - r n (no slip); t the unit line direction, n its left normal.
void PlanarLibrary::add_rolling(int owner, const Element& e, const std::string& name, const std::string& what) {
  auto a = axis(owner, e.end1, e.end1_pos);
  if (!a) return;
  const auto disc = body(owner, e.end2);
  if (disc && nodal(*disc)) {
    diags_.error(e.end2_pos, fmt::format("{}: the disc '{}' is in nodal coordinates (rigid2d_nodal or `parametrization "
                                         "nodal`); rolling needs a rigid2d disc in absolute coordinates",
                                         what, e.end2));
    return;
  }
  if (!disc || *disc == kGround || m_.nodes[*disc].kind != LeafKind::Rigid2d) {
    diags_.error(e.end2_pos, fmt::format("{}: '{}' is not a rigid2d body (the disc; its mass centre is its centre)", what, e.end2));
    return;
  }
  if (*disc == a->first.node) {
    diags_.error(e.end2_pos, fmt::format("{} connects '{}' to itself", what, m_.label(*disc)));
    return;
  }
  if (e.option != "radius") {
    diags_.error(e.kind_pos, fmt::format("{} needs 'radius r'", what));
    return;
  }
  const Node& b = m_.nodes[*disc];
  const GiNaC::ex cx = m_.coords[b.coords[0]].sym, cy = m_.coords[b.coords[1]].sym, r = *e.value;
  const GiNaC::ex len = GiNaC::sqrt(a->second.first * a->second.first + a->second.second * a->second.second);
  const GiNaC::ex tx = a->second.first / len, ty = a->second.second / len;  // world direction of the line
  const GiNaC::ex nx = -ty, ny = tx;
  add_constraint(owner, name + ".contact", nx * (cx - a->first.x) + ny * (cy - a->first.y) - r, e.pos);
  const GiNaC::ex px = cx - r * nx, py = cy - r * ny;
  const auto vd = velocity(*disc, px, py), vl = velocity(a->first.node, px, py);
  add_velocity_constraint(owner, name + ".no_slip", tx * (vd.first - vl.first) + ty * (vd.second - vl.second), e.pos);
}

// A disc inside a ring (both rigid2d, mass centre = centre), touching at one point.
// Vector form: |c_disc - c_ring| = R - r (contact), and the contact point P = c_ring + R n
// (n the unit vector from the ring's centre to the disc's) has the same velocity along
// the tangent t = n rotated by +90 degrees on both bodies (no slip).
void PlanarLibrary::add_rolling_inside(int owner, const Element& e, const std::string& name, const std::string& what) {
  const auto ring = body(owner, e.end1), disc = body(owner, e.end2);
  for (auto [b, path, pos] : {std::tuple{ring, e.end1, e.end1_pos}, std::tuple{disc, e.end2, e.end2_pos}}) {
    if (b && nodal(*b)) {
      diags_.error(pos, fmt::format("{}: '{}' is in nodal coordinates (rigid2d_nodal or `parametrization nodal`); "
                                    "ring and disc must be rigid2d bodies in absolute coordinates",
                                    what, path));
      return;
    }
    if (!b || *b == kGround || m_.nodes[*b].kind != LeafKind::Rigid2d) {
      diags_.error(pos, fmt::format("{}: '{}' is not a rigid2d body (ring and disc are rigid2d bodies centred on their "
                                    "mass centres)",
                                    what, path));
      return;
    }
  }
  if (*ring == *disc) {
    diags_.error(e.end2_pos, fmt::format("{} connects '{}' to itself", what, m_.label(*disc)));
    return;
  }
  if (e.option != "radius" || e.option2 != "ring") {
    diags_.error(e.kind_pos, fmt::format("{} needs 'radius r ring R' (the disc's radius, then the ring's)", what));
    return;
  }
  {
    // Only a gap that evaluates (at the defaults) is checked, as before at_defaults.
    const double gap = at_defaults(*e.value2 - *e.value);
    if (!std::isnan(gap) && !(gap > 0.0)) {
      diags_.error(e.option2_pos, fmt::format("{}: the ring's radius must exceed the disc's (ring - radius = {})", what, gap));
      return;
    }
  }
  const Node& R = m_.nodes[*ring];
  const Node& D = m_.nodes[*disc];
  const GiNaC::ex rx = m_.coords[R.coords[0]].sym, ry = m_.coords[R.coords[1]].sym;
  const GiNaC::ex dx = m_.coords[D.coords[0]].sym - rx, dy = m_.coords[D.coords[1]].sym - ry;
  const GiNaC::ex r = *e.value, big_r = *e.value2;
  add_constraint(owner, name + ".contact", dx * dx + dy * dy - (big_r - r) * (big_r - r), e.pos);
  // n = (dx, dy) / (R - r) on the constraint, t = (-n_y, n_x). At P the disc's point moves
  // with v_disc + r w_disc t and the ring's with v_ring + R w_ring t.
  const GiNaC::ex tx = -dy / (big_r - r), ty = dx / (big_r - r);
  const GiNaC::ex du = m_.speeds[D.speeds[0]].sym - m_.speeds[R.speeds[0]].sym;
  const GiNaC::ex dv = m_.speeds[D.speeds[1]].sym - m_.speeds[R.speeds[1]].sym;
  const GiNaC::ex wr = m_.speeds[R.speeds[2]].sym, wd = m_.speeds[D.speeds[2]].sym;
  add_velocity_constraint(owner, name + ".no_slip", tx * du + ty * dv + r * wd - big_r * wr, e.pos);
}

// ---- joints, springs, dampers ----

void PlanarLibrary::add_element(int owner, const Element& e) {
  const bool joint = e.kind == "revolute" || e.kind == "prismatic" || e.kind == "weld" || e.kind == "pin_in_slot" ||
                     e.kind == "gear" || e.kind == "rolling" || e.kind == "rolling_inside" || e.kind == "knife_edge";
  if (!joint && e.kind != "spring" && e.kind != "damper" && e.kind != "rotational_spring" && e.kind != "rotational_damper") {
    const std::vector<std::string> kinds = {"revolute", "prismatic", "pin_in_slot", "weld",
                                            "gear",     "rolling",   "rolling_inside", "knife_edge",
                                            "spherical", "universal", "cylindrical", "point_on_line", "point_on_plane", "rolling_sphere"};
    diags_.error(e.kind_pos, fmt::format("unknown joint kind '{}'{} (known: {})", e.kind, did_you_mean(e.kind, kinds),
                                         fmt::join(kinds, ", ")));
    return;
  }
  const std::string name = e.name.empty() ? fmt::format("{}{}", e.kind, ++unnamed_) : e.name;
  const std::string what = fmt::format("{} '{}'", joint ? "joint" : e.kind == "rotational_spring"   ? "spring"
                                                                   : e.kind == "rotational_damper" ? "damper"
                                                                                                   : e.kind,
                                       name);
  const bool relative = e.coordinate >= 0;
  if (relative && e.kind != "revolute" && e.kind != "prismatic") {
    diags_.error(e.coordinate_pos, fmt::format("{}: only revolute and prismatic joints take a coordinate (a {} joint has no "
                                               "angle or slide of its own)",
                                               what, e.kind));
    return;
  }
  if (relative && e.coordinates.size() > 1) {
    diags_.error(e.coordinate_positions[1], fmt::format("{}: a planar {} joint takes one coordinate (its {}), not {}", what,
                                                        e.kind, e.kind == "revolute" ? "angle" : "slide",
                                                        e.coordinates.size()));
    return;
  }
  if (relative && !e.sequence.empty()) {
    diags_.error(e.sequence_pos, fmt::format("{}: 'euler' names the sequence of a spatial spherical joint's three angles; "
                                             "a planar joint has one coordinate",
                                             what));
    return;
  }
  if (e.kind == "knife_edge") {
    add_knife_edge(owner, e, name, what);
    return;
  }
  if (e.kind == "gear" || e.kind == "rotational_spring" || e.kind == "rotational_damper") {
    add_rotational(owner, e, name, what);
    return;
  }
  if (!e.option2.empty() && e.kind != "rolling_inside") {
    diags_.error(e.option2_pos, fmt::format("{} takes one option ('{}' is a second one)", what, e.option2));
    return;
  }
  if (e.kind == "rolling") {
    add_rolling(owner, e, name, what);
    return;
  }
  if (e.kind == "rolling_inside") {
    add_rolling_inside(owner, e, name, what);
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
  if ((e.kind == "revolute" && !relative) || e.kind == "weld") {
    add_constraint(owner, name + ".x", dx, e.pos);
    add_constraint(owner, name + ".y", dy, e.pos);
  }
  if ((e.kind == "prismatic" && !relative) || e.kind == "pin_in_slot") {
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
  if (relative) {
    if (!add_relative_rows(owner, e, name, what, *p1, *p2, rel)) return;
  } else if (locks_angle) {
    add_constraint(owner, name + ".angle", angle_residual(p1->node, p2->node, rel), e.pos);
  }

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
