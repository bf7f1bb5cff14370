// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// Rigid transforms in doubles for the URDF import: vectors, 3x3 rotations, URDF's
// roll-pitch-yaw. Angles within kSnap of a multiple of pi/2 are taken as that multiple,
// so the rotations URDF files write as 1.5707963267948966 or 3.14159265359 have entries
// that are exactly 0 and +-1 and the written model keeps its numbers as the file has them.
#include <array>
#include <cmath>

namespace mbsc::import {

using Vec3 = std::array<double, 3>;
using Mat3 = std::array<std::array<double, 3>, 3>;

/// How far from a multiple of pi/2 an angle may be and still be taken as one (radians):
/// files round pi/2 to 11 or more digits (1.57079632679 is 4.9e-12 off).
constexpr double kSnap = 1e-10;

inline Mat3 identity() { return {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}}; }

/// cos and sin of `a`, exact where a is a multiple of pi/2 (within kSnap).
inline std::array<double, 2> cos_sin(double a) {
  const double quarter = a / (M_PI / 2);
  const double k = std::round(quarter);
  if (std::abs(a - k * (M_PI / 2)) <= kSnap) {
    static const double table[4][2] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
    const long r = ((static_cast<long>(k) % 4) + 4) % 4;
    return {table[r][0], table[r][1]};
  }
  return {std::cos(a), std::sin(a)};
}

/// True when `a` is taken as a multiple of pi/2 (cos_sin's rule).
inline bool is_quarter_turn(double a) { return std::abs(a - std::round(a / (M_PI / 2)) * (M_PI / 2)) <= kSnap; }

inline Mat3 mul(const Mat3& a, const Mat3& b) {
  Mat3 c{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double s = 0;
      for (int k = 0; k < 3; ++k) s += a[i][k] * b[k][j];
      c[i][j] = s;
    }
  return c;
}

inline Vec3 mul(const Mat3& a, const Vec3& v) {
  Vec3 r{};
  for (int i = 0; i < 3; ++i) r[i] = a[i][0] * v[0] + a[i][1] * v[1] + a[i][2] * v[2];
  return r;
}

inline Mat3 transpose(const Mat3& a) {
  Mat3 t{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) t[i][j] = a[j][i];
  return t;
}

inline Vec3 add(const Vec3& a, const Vec3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
inline Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline Vec3 scale(double s, const Vec3& a) { return {s * a[0], s * a[1], s * a[2]}; }
inline double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

/// URDF's fixed-axis roll, pitch, yaw: R = Rz(yaw) Ry(pitch) Rx(roll).
inline Mat3 rpy_rotation(const Vec3& rpy) {
  const auto [cr, sr] = cos_sin(rpy[0]);
  const auto [cp, sp] = cos_sin(rpy[1]);
  const auto [cy, sy] = cos_sin(rpy[2]);
  const Mat3 rx = {{{1, 0, 0}, {0, cr, -sr}, {0, sr, cr}}};
  const Mat3 ry = {{{cp, 0, sp}, {0, 1, 0}, {-sp, 0, cp}}};
  const Mat3 rz = {{{cy, -sy, 0}, {sy, cy, 0}, {0, 0, 1}}};
  return mul(rz, mul(ry, rx));
}

/// A rigid transform: a point p of the child frame is at rotation * p + position in the parent's.
struct Pose {
  Vec3 position{0, 0, 0};
  Mat3 rotation = identity();
};

/// a then b: the pose of b's frame (given in a's) in the frame a is given in.
inline Pose compose(const Pose& a, const Pose& b) {
  return {add(a.position, mul(a.rotation, b.position)), mul(a.rotation, b.rotation)};
}

/// The unit quaternion (scalar first) of a rotation matrix (Shepperd's choice of pivot).
inline std::array<double, 4> quaternion_of(const Mat3& r) {
  const double tr = r[0][0] + r[1][1] + r[2][2];
  std::array<double, 4> q{};
  if (tr >= r[0][0] && tr >= r[1][1] && tr >= r[2][2]) {
    const double s = 2 * std::sqrt(1 + tr);
    q = {s / 4, (r[2][1] - r[1][2]) / s, (r[0][2] - r[2][0]) / s, (r[1][0] - r[0][1]) / s};
  } else if (r[0][0] >= r[1][1] && r[0][0] >= r[2][2]) {
    const double s = 2 * std::sqrt(1 + r[0][0] - r[1][1] - r[2][2]);
    q = {(r[2][1] - r[1][2]) / s, s / 4, (r[0][1] + r[1][0]) / s, (r[0][2] + r[2][0]) / s};
  } else if (r[1][1] >= r[2][2]) {
    const double s = 2 * std::sqrt(1 + r[1][1] - r[0][0] - r[2][2]);
    q = {(r[0][2] - r[2][0]) / s, (r[0][1] + r[1][0]) / s, s / 4, (r[1][2] + r[2][1]) / s};
  } else {
    const double s = 2 * std::sqrt(1 + r[2][2] - r[0][0] - r[1][1]);
    q = {(r[1][0] - r[0][1]) / s, (r[0][2] + r[2][0]) / s, (r[1][2] + r[2][1]) / s, s / 4};
  }
  if (q[0] < 0)
    for (auto& v : q) v = -v;
  return q;
}

}  // namespace mbsc::import
