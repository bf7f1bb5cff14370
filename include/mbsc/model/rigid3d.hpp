// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// Kinematics and inertia of rigid3d leaves (thesis Ex 2.1, 2.5): rotation matrices of
/// unit quaternions and Euler / Tait-Bryan sequences, the attitude coordinates' rates in
/// terms of the angular speeds (body or space frame), and the body's own generalized
/// inertia forces and energy. Vectors are std::vector<ex> of 3 entries; 3x3 matrices are
/// row-major std::vector<ex> of 9 entries. Spatial joints read points and axes through
/// point_in_space / direction_in_space.
#include <ginac/ginac.h>

#include <string>
#include <vector>

#include "mbsc/model/model.hpp"

namespace mbsc::model::rigid3d {

using Vec = std::vector<GiNaC::ex>;

/// An Euler / Tait-Bryan sequence: three letters of x, y, z, no two neighbours equal
/// (zyx, zxz, xyz, ...).
bool valid_sequence(const std::string& seq);

/// Body-to-space rotation of the quaternion (e0, e1, e2, e3), e0 the scalar part, in its
/// homogeneous form (each entry quadratic in e; a rotation when |e| = 1).
Vec quaternion_rotation(const Vec& e);
/// R = R_a(phi) R_b(theta) R_c(psi) for the sequence "abc" (rotations about the body's
/// successive axes: a then the new b then the newest c).
Vec euler_rotation(const std::string& seq, const Vec& angles);

/// The attitude coordinates' rates given the angular speeds w, measured in the body
/// frame or in the space frame. Quaternion: e' = 1/2 e (0, w) (body) or 1/2 (0, w) e
/// (space). Euler: angles' = H^-1 w with w = H angles' (H singular at gimbal lock).
Vec quaternion_rates(const Vec& e, const Vec& w, bool space_frame);
Vec euler_rates(const std::string& seq, const Vec& angles, const Vec& w, bool space_frame);

Vec mat_vec(const Vec& A, const Vec& v);   // A v
Vec mat_t_vec(const Vec& A, const Vec& v);  // A^T v
Vec cross(const Vec& a, const Vec& b);
GiNaC::ex dot(const Vec& a, const Vec& b);
/// |d|, taken as exactly 1 for a constant direction whose squared length is 1 to double
/// rounding (within 1e-15): a direction written with 16-17 digits, such as a turned axis
/// imported from URDF, is a unit vector to double precision but not as exact rationals,
/// and the square root of its squared length would carry 34-digit constants into every
/// product that reads it.
GiNaC::ex length(const Vec& d);

/// The node's attitude and angular speed symbols.
Vec attitude_coordinates(const Model& m, const Node& node);
Vec angular_speeds(const Model& m, const Node& node);
/// The coordinate names (e0, e1, e2, e3) of every rigid3d body with a quaternion attitude
/// and of every spherical joint written with a quaternion, in model order: the unit
/// quaternions a simulation keeps at |e| = 1.
std::vector<std::vector<std::string>> unit_quaternion_names(const Model& m);
/// The angular velocity in space components.
Vec angular_velocity_in_space(const Model& m, const Node& node);
/// Inertia tensor in the frame of the angular speeds: I (body) or R I R^T (space).
Vec inertia_in_speed_frame(const Node& node);
/// A body point (body coordinates) in space: x + R (p - com).
Vec point_in_space(const Model& m, const Node& node, const Vec& local);
/// A body direction in space: R d. For a body placed by a joint (Rigid3dData::placed)
/// it turns d by the joint angle, then takes the parent's direction_in_space of that:
/// R_parent (R_joint d), with R_joint d = d for d along the joint axis (a wheel's spin
/// axis in space is its frame's hub axis, with no trace of the wheel angle).
Vec direction_in_space(const Model& m, const Node& node, const Vec& local);

/// The factor by which direction_in_space scales lengths: |e|^2 for a quaternion
/// attitude (its homogeneous matrix is |e|^2 times a rotation, exactly, at any e), that of
/// the parent for a body placed by a joint, 1 for Euler angles (an exact rotation). So
/// |R d| = length_scale |d| with no square root of the attitude coordinates.
GiNaC::ex length_scale(const Model& m, const Node& node);

/// v turned by angle q about the unit vector n (Rodrigues):
/// cos q v + sin q (n x v) + (1 - cos q) (n . v) n; v itself when v is a multiple of n.
Vec rotate_about(const Vec& n, const GiNaC::ex& q, const Vec& v);
/// v turned by -q about n (the transpose of rotate_about's turn), written in sin q and
/// cos q rather than of -q, so that the generated code shares them with the turn itself.
Vec rotate_back_about(const Vec& n, const GiNaC::ex& q, const Vec& v);
/// The matrix of rotate_about (row-major 3x3).
Vec rotation_about(const Vec& n, const GiNaC::ex& q);
/// 3x3 row-major product A B.
Vec mat_mat(const Vec& A, const Vec& B);
/// A placed body's joint turns (Rigid3dData::joint_turns), Q = Q_1 Q_2 ...:
/// joint_turn gives Q v (the last turn first), joint_turn_back Q^T v (the first turn
/// first), joint_rotation the matrix Q, each in sin q_i and cos q_i; for a spherical
/// joint with a quaternion (Rigid3dData::joint_quaternion) Q is the quaternion's matrix.
Vec joint_turn(const Rigid3dData& data, const Vec& v);
Vec joint_turn_back(const Rigid3dData& data, const Vec& v);
Vec joint_rotation(const Rigid3dData& data);
/// The child's angular velocity relative to its parent, in the child's frame:
/// sum over turns i of (Q_{i+1} ... Q_k)^T n_i q_i' (Q^T Q' = [that]x); a quaternion
/// joint's own three speeds.
Vec joint_relative_angular_velocity(const Rigid3dData& data);
/// The angular velocity of a placed body's parent in the parent's body frame (0 for the
/// ground): what the joint's velocity rows turn into the child's frame.
Vec parent_angular_velocity_in_parent_frame(const Model& m, const Node& child);

/// The own generalized force along angular speed k (0, 1, 2): the k-th entry of
/// -(J w' + w x J w) with J the inertia in the speeds' frame (Euler's equations; in the
/// space frame they hold with J = R I R^T since J' w = w x J w).
GiNaC::ex angular_inertia_force(const Model& m, const Node& node, int k);
/// Kinetic energy 1/2 m |v|^2 + 1/2 w.J w and gravity's potential -m g.x.
GiNaC::ex kinetic_energy(const Model& m, const Node& node);
GiNaC::ex gravity_potential(const Model& m, const Node& node);

}  // namespace mbsc::model::rigid3d
