// SPDX-License-Identifier: GPL-2.0-or-later
// A disc rolling without slip on a plane of the ground (a knife-edge wheel: the disc's
// thickness is zero, it touches the plane at one point of its rim). The plane is a ground
// axis: its point A lies on the plane, its direction n is the normal pointing to the
// disc's side. The disc is an axis of a rigid3d body: its point C is the disc's centre and
// its direction d the normal of the disc's plane (the spin axis). With the unit vectors
// n^ = n / |n|, d^ = d / |d| and c = n^ . d^, s = sqrt(1 - c^2) (the sine of the angle
// between the two planes):
//   * the rim's point nearest the plane is P = C + r k, k = (c d^ - n^) / s (the steepest
//     descent within the disc's plane), at height n^ . (C - A) - r s above the plane:
//       .contact       n^ . (C - A) - r s = 0                       (position)
//   * the disc's material point at P moves with v_P = v_C + w x (r k); it has no velocity
//     along the line where the disc's plane meets the ground's, t = (d^ x n^) / s, nor
//     across it within the ground's plane, b = n^ x t = (d^ - c n^) / s. Since
//     k x t = -d^ and k x b = s t, the two rows reduce to
//       .no_slip       t . v_C - r w . d^ = 0                       (velocity)
//       .no_side_slip  b . v_C + r s w . t = 0                      (velocity)
// (the normal component n^ . v_P is the contact row's rate, so it is not repeated).
// All three are singular where s = 0: the disc lies flat on the plane, the contact point
// is then anywhere on the rim.
#include <cmath>

#include <fmt/format.h>

#include "mbsc/model/rigid3d.hpp"
#include "spatial_library.hpp"

namespace mbsc::model {

namespace {
using Vec = SpatialLibrary::Vec;
Vec scaled(const Vec& a, const GiNaC::ex& k) { return {a[0] * k, a[1] * k, a[2] * k}; }
Vec plus(const Vec& a, const Vec& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
Vec sub(const Vec& a, const Vec& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
}  // namespace

void SpatialLibrary::add_rolling(int owner, const PlanarLibrary::Element& e, const std::string& name,
                                 const std::string& what) {
  if (e.option != "radius") {
    diags_.error(e.option.empty() ? e.kind_pos : e.option_pos,
                 fmt::format("{} needs 'radius r' (it is `rolling PLANE DISC radius r`){}", what,
                             e.option.empty() ? std::string() : fmt::format(", not '{}'", e.option)));
    return;
  }
  if (!e.option2.empty()) {
    diags_.error(e.option2_pos, fmt::format("{} takes one option ('{}' is a second one)", what, e.option2));
    return;
  }
  if (!e.end3.empty()) {
    diags_.error(e.end3_pos, fmt::format("{} has two ends", what));
    return;
  }
  const GiNaC::ex r = *e.value;
  if (const std::string varying = varies(r); !varying.empty()) {
    diags_.error(e.option_pos, fmt::format("{}: the radius must be a constant (parameters only; it reads {})", what, varying));
    return;
  }
  if (const double rv = at_defaults(r); !std::isnan(rv) && !(rv > 0.0)) {
    diags_.error(e.option_pos, fmt::format("{}: the radius must be positive (it is {})", what, rv));
    return;
  }
  const auto plane = end(owner, e.end1, true, e.end1_pos, what + " (the plane)", "joint");
  const auto disc = end(owner, e.end2, true, e.end2_pos, what + " (the disc)", "joint");
  if (!plane || !disc) return;
  if (plane->node != PlanarLibrary::kGround) {
    diags_.error(e.end1_pos, fmt::format("{}: the plane '{}' must be an axis of the ground (its point on the plane, its "
                                         "direction the plane's normal)",
                                         what, e.end1));
    return;
  }
  for (const auto* v : {&plane->p, &plane->d})
    for (const GiNaC::ex& x : *v)
      if (const std::string varying = varies(x); !varying.empty()) {
        diags_.error(e.end1_pos, fmt::format("{}: the plane '{}' moves (it reads {}); the rolling rows need a fixed plane",
                                             what, e.end1, varying));
        return;
      }
  if (disc->node == PlanarLibrary::kGround) {
    diags_.error(e.end2_pos, fmt::format("{}: the disc '{}' must be an axis of a rigid3d body (its centre and spin axis)",
                                         what, e.end2));
    return;
  }
  const Node& body = m_.nodes[disc->node];
  // Unit normal of the plane and unit spin axis. The spin axis in space is R d: of length
  // |d| (a constant) for an attitude by angles or by joints; for a quaternion attitude
  // |e|^2 |d| at any e, so it is divided by its own length in space, which keeps c in
  // [-1, 1] even off the unit quaternions. (Dividing by the polynomial |e|^2 |d| instead
  // makes the exact solves of `mbsc print` run GiNaC's polynomial gcd on it: minutes.)
  const Vec n = scaled(plane->d, 1 / GiNaC::sqrt(rigid3d::dot(plane->d, plane->d)));
  const bool constant_length = rigid3d::length_scale(m_, body).is_equal(1);
  const Vec d = scaled(disc->d, 1 / (constant_length ? disc->d_length : GiNaC::sqrt(rigid3d::dot(disc->d, disc->d))));
  const GiNaC::ex c = rigid3d::dot(n, d);
  const GiNaC::ex s = GiNaC::sqrt(1 - c * c);
  row(owner, name + ".contact", rigid3d::dot(n, sub(disc->p, plane->p)) - r * s, e.pos);
  // The centre's velocity: the mass centre's plus w x (C - mass centre).
  const Vec w = rigid3d::angular_velocity_in_space(m_, body);
  Vec vc, arm;
  for (std::size_t k = 0; k < 3; ++k) {
    vc.push_back(m_.speeds[static_cast<std::size_t>(body.speeds[k])].sym);
    arm.push_back(disc->p[k] - m_.coords[static_cast<std::size_t>(body.coords[k])].sym);
  }
  vc = plus(vc, rigid3d::cross(w, arm));
  const Vec t = scaled(rigid3d::cross(d, n), 1 / s);
  const Vec b = scaled(plus(d, scaled(n, -c)), 1 / s);
  row(owner, name + ".no_slip", rigid3d::dot(t, vc) - r * rigid3d::dot(w, d), e.pos, Constraint::Level::Velocity);
  row(owner, name + ".no_side_slip", rigid3d::dot(b, vc) + r * rigid3d::dot(w, rigid3d::cross(d, n)), e.pos,
      Constraint::Level::Velocity);
}

}  // namespace mbsc::model
