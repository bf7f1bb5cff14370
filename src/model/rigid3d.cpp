// SPDX-License-Identifier: GPL-2.0-or-later
#include "mbsc/model/rigid3d.hpp"

namespace mbsc::model::rigid3d {

using GiNaC::ex;

bool valid_sequence(const std::string& seq) {
  if (seq.size() != 3) return false;
  for (char c : seq)
    if (c != 'x' && c != 'y' && c != 'z') return false;
  return seq[0] != seq[1] && seq[1] != seq[2];
}

Vec quaternion_rotation(const Vec& e) {
  const ex &e0 = e[0], &e1 = e[1], &e2 = e[2], &e3 = e[3];
  return {e0 * e0 + e1 * e1 - e2 * e2 - e3 * e3, 2 * (e1 * e2 - e0 * e3), 2 * (e1 * e3 + e0 * e2),
          2 * (e1 * e2 + e0 * e3), e0 * e0 - e1 * e1 + e2 * e2 - e3 * e3, 2 * (e2 * e3 - e0 * e1),
          2 * (e1 * e3 - e0 * e2), 2 * (e2 * e3 + e0 * e1), e0 * e0 - e1 * e1 - e2 * e2 + e3 * e3};
}

namespace {

bool expands_to_zero(const ex& e) { return GiNaC::expand(e).is_zero(); }

int axis_index(char a) { return a - 'x'; }

/// Rotation by angle a about coordinate axis i.
GiNaC::matrix axis_rotation(int i, const ex& a) {
  GiNaC::matrix r(3, 3);
  const int j = (i + 1) % 3, k = (i + 2) % 3;
  r(i, i) = 1;
  r(j, j) = cos(a);
  r(k, k) = cos(a);
  r(j, k) = -sin(a);
  r(k, j) = sin(a);
  return r;
}

Vec entries(const GiNaC::matrix& m) {
  Vec out;
  for (unsigned i = 0; i < m.rows(); ++i)
    for (unsigned j = 0; j < m.cols(); ++j) out.push_back(m(i, j));
  return out;
}

GiNaC::matrix unit(int i) {
  GiNaC::matrix u(3, 1);
  u(static_cast<unsigned>(i), 0) = 1;
  return u;
}

/// sin^2 -> 1 - cos^2 for the angles, then one common denominator: the entries of H^-1
/// come out as short quotients of trigonometric monomials.
ex trig_tidy(const ex& e, const Vec& angles) {
  GiNaC::exmap pyth;
  for (const auto& a : angles) pyth[pow(sin(a), 2)] = 1 - pow(cos(a), 2);
  return GiNaC::normal(GiNaC::expand(e).subs(pyth, GiNaC::subs_options::algebraic));
}

}  // namespace

Vec euler_rotation(const std::string& seq, const Vec& angles) {
  GiNaC::matrix r = axis_rotation(axis_index(seq[0]), angles[0]);
  r = r.mul(axis_rotation(axis_index(seq[1]), angles[1])).mul(axis_rotation(axis_index(seq[2]), angles[2]));
  return entries(r);
}

Vec quaternion_rates(const Vec& e, const Vec& w, bool space_frame) {
  // e' = 1/2 (-ev.w, e0 w + s ev x w), s = +1 for e (0, w), -1 for (0, w) e.
  const Vec ev{e[1], e[2], e[3]};
  const Vec c = cross(ev, w);
  const int s = space_frame ? -1 : 1;
  const ex half = GiNaC::numeric(1, 2);
  return {-half * dot(ev, w), half * (e[0] * w[0] + s * c[0]), half * (e[0] * w[1] + s * c[1]),
          half * (e[0] * w[2] + s * c[2])};
}

Vec euler_rates(const std::string& seq, const Vec& angles, const Vec& w, bool space_frame) {
  const int a = axis_index(seq[0]), b = axis_index(seq[1]), c = axis_index(seq[2]);
  const GiNaC::matrix Ra = axis_rotation(a, angles[0]), Rb = axis_rotation(b, angles[1]), Rc = axis_rotation(c, angles[2]);
  // Columns of H: each angle's rate contributes its axis, in the frame of the speeds.
  GiNaC::matrix cols[3];
  if (space_frame) {
    cols[0] = unit(a);
    cols[1] = Ra.mul(unit(b));
    cols[2] = Ra.mul(Rb).mul(unit(c));
  } else {
    cols[0] = Rc.transpose().mul(Rb.transpose()).mul(unit(a));
    cols[1] = Rc.transpose().mul(unit(b));
    cols[2] = unit(c);
  }
  GiNaC::matrix H(3, 3);
  for (unsigned j = 0; j < 3; ++j)
    for (unsigned i = 0; i < 3; ++i) H(i, j) = trig_tidy(cols[j](i, 0), angles);
  const GiNaC::matrix Hinv = H.inverse();
  Vec out(3, ex(0));
  for (unsigned i = 0; i < 3; ++i)
    for (unsigned j = 0; j < 3; ++j) out[i] += trig_tidy(Hinv(i, j), angles) * w[j];
  return out;
}

Vec mat_vec(const Vec& A, const Vec& v) {
  Vec out(3, ex(0));
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) out[i] += A[3 * i + j] * v[j];
  return out;
}

Vec mat_t_vec(const Vec& A, const Vec& v) {
  Vec out(3, ex(0));
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) out[i] += A[3 * j + i] * v[j];
  return out;
}

Vec cross(const Vec& a, const Vec& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

ex dot(const Vec& a, const Vec& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

ex length(const Vec& d) {
  const ex squared = GiNaC::expand(dot(d, d));
  if (GiNaC::is_a<GiNaC::numeric>(squared)) {
    const GiNaC::numeric& n = GiNaC::ex_to<GiNaC::numeric>(squared);
    if (n.is_real() && GiNaC::abs(n - 1) <= GiNaC::numeric(1, 1000000000000000)) return 1;
  }
  return GiNaC::sqrt(squared);
}

Vec attitude_coordinates(const Model& m, const Node& node) {
  Vec out;
  for (std::size_t k = 3; k < node.coords.size(); ++k) out.push_back(m.coords[static_cast<std::size_t>(node.coords[k])].sym);
  return out;
}

Vec angular_speeds(const Model& m, const Node& node) {
  Vec out;
  for (std::size_t k = 3; k < 6; ++k) out.push_back(m.speeds[static_cast<std::size_t>(node.speeds[k])].sym);
  return out;
}

std::vector<std::vector<std::string>> unit_quaternion_names(const Model& m) {
  std::vector<std::vector<std::string>> out;
  for (const Node& node : m.nodes) {
    if (node.kind != LeafKind::Rigid3d) continue;
    std::vector<std::string> names;
    if (node.rigid3d.sequence == "quaternion" && node.coords.size() >= 7)
      for (std::size_t k = 3; k < 7; ++k) names.push_back(m.coords[static_cast<std::size_t>(node.coords[k])].name);
    for (int c : node.rigid3d.joint_quaternion_coords) names.push_back(m.coords[static_cast<std::size_t>(c)].name);
    if (names.size() == 4) out.push_back(names);
  }
  return out;
}

Vec angular_velocity_in_space(const Model& m, const Node& node) {
  const Vec w = angular_speeds(m, node);
  return node.rigid3d.space_frame ? w : direction_in_space(m, node, w);
}

Vec parent_angular_velocity_in_parent_frame(const Model& m, const Node& child) {
  const int p = child.rigid3d.joint_parent;
  if (p < 0) return {0, 0, 0};
  const Node& parent = m.nodes[static_cast<std::size_t>(p)];
  const Vec w = angular_speeds(m, parent);
  return parent.rigid3d.space_frame ? mat_t_vec(parent.rigid3d.rotation, w) : w;
}

Vec rotate_about(const Vec& n, const ex& q, const Vec& v) {
  const Vec nv = cross(n, v);
  if (expands_to_zero(nv[0]) && expands_to_zero(nv[1]) && expands_to_zero(nv[2])) return v;  // along the axis
  const ex c = cos(q), s = sin(q), along = (1 - c) * dot(n, v);
  return {c * v[0] + s * nv[0] + along * n[0], c * v[1] + s * nv[1] + along * n[1], c * v[2] + s * nv[2] + along * n[2]};
}

Vec rotate_back_about(const Vec& n, const ex& q, const Vec& v) {
  const Vec nv = cross(n, v);
  if (expands_to_zero(nv[0]) && expands_to_zero(nv[1]) && expands_to_zero(nv[2])) return v;  // along the axis
  const ex c = cos(q), s = sin(q), along = (1 - c) * dot(n, v);
  return {c * v[0] - s * nv[0] + along * n[0], c * v[1] - s * nv[1] + along * n[1], c * v[2] - s * nv[2] + along * n[2]};
}

Vec rotation_about(const Vec& n, const ex& q) {
  Vec R(9, ex(0));
  for (int j = 0; j < 3; ++j) {
    Vec e(3, ex(0));
    e[static_cast<std::size_t>(j)] = 1;
    const Vec col = rotate_about(n, q, e);
    for (int i = 0; i < 3; ++i) R[static_cast<std::size_t>(3 * i + j)] = col[static_cast<std::size_t>(i)];
  }
  return R;
}

Vec joint_turn(const Rigid3dData& data, const Vec& v) {
  if (!data.joint_quaternion.empty()) return mat_vec(quaternion_rotation(data.joint_quaternion), v);
  Vec out = v;
  for (auto it = data.joint_turns.rbegin(); it != data.joint_turns.rend(); ++it) out = rotate_about(it->axis, it->angle, out);
  return out;
}

Vec joint_turn_back(const Rigid3dData& data, const Vec& v) {
  if (!data.joint_quaternion.empty()) return mat_t_vec(quaternion_rotation(data.joint_quaternion), v);
  Vec out = v;
  for (const auto& turn : data.joint_turns) out = rotate_back_about(turn.axis, turn.angle, out);
  return out;
}

Vec joint_rotation(const Rigid3dData& data) {
  Vec Q(9, ex(0));
  for (int j = 0; j < 3; ++j) {
    Vec e(3, ex(0));
    e[static_cast<std::size_t>(j)] = 1;
    const Vec col = joint_turn(data, e);
    for (int i = 0; i < 3; ++i) Q[static_cast<std::size_t>(3 * i + j)] = col[static_cast<std::size_t>(i)];
  }
  return Q;
}

Vec joint_relative_angular_velocity(const Rigid3dData& data) {
  if (!data.joint_quaternion.empty()) return data.joint_quaternion_speeds;
  // Each turn's axis n_i q_i', carried into the child's frame by the turns after it.
  Vec w(3, ex(0));
  const std::size_t k = data.joint_turns.size();
  for (std::size_t i = 0; i < k; ++i) {
    Vec term = data.joint_turns[i].axis;
    for (std::size_t j = i + 1; j < k; ++j) term = rotate_back_about(data.joint_turns[j].axis, data.joint_turns[j].angle, term);
    for (std::size_t c = 0; c < 3; ++c) w[c] += term[c] * data.joint_turns[i].rate;
  }
  return w;
}

Vec mat_mat(const Vec& A, const Vec& B) {
  Vec C(9, ex(0));
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) C[static_cast<std::size_t>(3 * i + j)] += A[static_cast<std::size_t>(3 * i + k)] * B[static_cast<std::size_t>(3 * k + j)];
  return C;
}

Vec inertia_in_speed_frame(const Node& node) {
  const Vec& I = node.rigid3d.inertia;
  if (!node.rigid3d.space_frame) return I;
  const Vec& R = node.rigid3d.rotation;
  Vec J(9, ex(0));
  for (int i = 0; i < 3; ++i)
    for (int j = i; j < 3; ++j) {
      ex s = 0;
      for (int k = 0; k < 3; ++k)
        for (int l = 0; l < 3; ++l) s += R[3 * i + k] * I[3 * k + l] * R[3 * j + l];
      J[3 * i + j] = J[3 * j + i] = s;
    }
  return J;
}

Vec point_in_space(const Model& m, const Node& node, const Vec& local) {
  const Vec& c = node.rigid3d.com;
  const Vec d = direction_in_space(m, node, {local[0] - c[0], local[1] - c[1], local[2] - c[2]});
  Vec out;
  for (int k = 0; k < 3; ++k) out.push_back(m.coords[static_cast<std::size_t>(node.coords[k])].sym + d[k]);
  return out;
}

ex length_scale(const Model& m, const Node& node) {
  auto square_norm = [](const Vec& e) { return e[0] * e[0] + e[1] * e[1] + e[2] * e[2] + e[3] * e[3]; };
  if (node.rigid3d.placed()) {
    const Vec& e = node.rigid3d.joint_quaternion;
    const ex own = e.empty() ? ex(1) : square_norm(e);
    const int p = node.rigid3d.joint_parent;
    return p < 0 ? own : own * length_scale(m, m.nodes[static_cast<std::size_t>(p)]);
  }
  if (node.rigid3d.sequence != "quaternion") return 1;
  return square_norm(attitude_coordinates(m, node));
}

Vec direction_in_space(const Model& m, const Node& node, const Vec& local) {
  if (!node.rigid3d.placed()) return mat_vec(node.rigid3d.rotation, local);
  const Vec turned = joint_turn(node.rigid3d, local);
  const int p = node.rigid3d.joint_parent;
  if (node.rigid3d.named_rotation) {
    // The rotation is a matrix of names (R = R_parent Q(q), issue 25): one product, no
    // recursion into the ancestors, except for a direction the joint does not turn in a
    // small model (Rigid3dData::unturned_from_parent).
    bool unturned = node.rigid3d.unturned_from_parent && !node.rigid3d.joint_turns.empty();
    for (std::size_t k = 0; k < 3 && unturned; ++k) unturned = expands_to_zero(turned[k] - local[k]);
    if (!unturned) return mat_vec(node.rigid3d.rotation, local);
  }
  return p < 0 ? turned : direction_in_space(m, m.nodes[static_cast<std::size_t>(p)], turned);
}

GiNaC::ex angular_inertia_force(const Model& m, const Node& node, int k) {
  const Vec J = inertia_in_speed_frame(node);
  const Vec w = angular_speeds(m, node);
  Vec wdot;
  for (std::size_t i = 3; i < 6; ++i) wdot.push_back(m.speed_dots[static_cast<std::size_t>(node.speeds[i])]);
  const Vec Jw = mat_vec(J, w), Jwdot = mat_vec(J, wdot);
  const Vec gyro = cross(w, Jw);
  return -(Jwdot[k] + gyro[k]);
}

GiNaC::ex kinetic_energy(const Model& m, const Node& node) {
  ex T = 0;
  for (int k = 0; k < 3; ++k) {
    const ex u = m.speeds[static_cast<std::size_t>(node.speeds[k])].sym;
    T += GiNaC::numeric(1, 2) * node.mass * u * u;
  }
  const Vec w = angular_speeds(m, node);
  return T + GiNaC::numeric(1, 2) * dot(w, mat_vec(inertia_in_speed_frame(node), w));
}

GiNaC::ex gravity_potential(const Model& m, const Node& node) {
  ex V = 0;
  for (std::size_t k = 0; k < 3 && k < m.gravity.size(); ++k)
    V -= node.mass * m.gravity[k] * m.coords[static_cast<std::size_t>(node.coords[k])].sym;
  return V;
}

}  // namespace mbsc::model::rigid3d

namespace mbsc::model {

GiNaC::exmap kinematic_name_values(const Model& m) {
  // Each name's full expansion, in definition order (values read only earlier names).
  GiNaC::exmap full;
  for (const auto& k : m.kinematic_names) full[k.sym] = k.value.subs(full, GiNaC::subs_options::no_pattern);
  return full;
}

GiNaC::ex expand_kinematic_names(const Model& m, const GiNaC::ex& e) {
  if (m.kinematic_names.empty() || GiNaC::is_a<GiNaC::numeric>(e)) return e;
  return e.subs(kinematic_name_values(m), GiNaC::subs_options::no_pattern);
}

}  // namespace mbsc::model
