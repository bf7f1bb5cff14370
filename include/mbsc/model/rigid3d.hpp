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

/// The node's attitude and angular speed symbols.
Vec attitude_coordinates(const Model& m, const Node& node);
Vec angular_speeds(const Model& m, const Node& node);
/// The coordinate names (e0, e1, e2, e3) of every rigid3d body with a quaternion attitude,
/// in model order: the unit quaternions a simulation keeps at |e| = 1.
std::vector<std::vector<std::string>> unit_quaternion_names(const Model& m);
/// The angular velocity in space components.
Vec angular_velocity_in_space(const Model& m, const Node& node);
/// Inertia tensor in the frame of the angular speeds: I (body) or R I R^T (space).
Vec inertia_in_speed_frame(const Node& node);
/// A body point (body coordinates) in space: x + R (p - com).
Vec point_in_space(const Model& m, const Node& node, const Vec& local);
/// A body direction in space: R d.
Vec direction_in_space(const Node& node, const Vec& local);

/// The own generalized force along angular speed k (0, 1, 2): the k-th entry of
/// -(J w' + w x J w) with J the inertia in the speeds' frame (Euler's equations; in the
/// space frame they hold with J = R I R^T since J' w = w x J w).
GiNaC::ex angular_inertia_force(const Model& m, const Node& node, int k);
/// Kinetic energy 1/2 m |v|^2 + 1/2 w.J w and gravity's potential -m g.x.
GiNaC::ex kinetic_energy(const Model& m, const Node& node);
GiNaC::ex gravity_potential(const Model& m, const Node& node);

}  // namespace mbsc::model::rigid3d
