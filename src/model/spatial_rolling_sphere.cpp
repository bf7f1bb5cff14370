// SPDX-License-Identifier: GPL-2.0-or-later
// A sphere rolling without slip on a fixed surface z = gamma(x, y) of the ground (thesis
// Ex 2.5). The sphere is a rigid3d body whose mass centre G is the sphere's centre. The
// contact point P = (xc, yc, gamma(xc, yc)) has its own two coordinates xc, yc (declared
// with the joint, build_tree.cpp). With gamma_x, gamma_y the surface's slopes at P and
// n^ = (-gamma_x, -gamma_y, 1) / sqrt(1 + gamma_x^2 + gamma_y^2) its unit upward normal:
//   * the centre sits r above P along the normal:
//       .contact_x .contact_y .contact_z    G - P - r n^ = 0          (3 position rows)
//   * the sphere's material point at P moves with v_P = v_G + w x (-r n^); it has no
//     velocity along the surface's two tangents t_x = (1, 0, gamma_x), t_y = (0, 1, gamma_y):
//       .no_slip_x  t_x . v_P = 0,  .no_slip_y  t_y . v_P = 0        (2 velocity rows)
//     (n^ . v_P is the contact rows' rate, so it is not repeated).
// The rows hold while the contact point is unique: the surface's curvature below 1/r.
#include <cmath>

#include <fmt/format.h>

#include "mbsc/model/rigid3d.hpp"
#include "spatial_library.hpp"

namespace mbsc::model {

void SpatialLibrary::add_rolling_sphere(int owner, const PlanarLibrary::Element& e, const std::string& name,
                                        const std::string& what) {
  // The two options, in either order: 'radius r' and 'surface (gamma)'.
  std::optional<GiNaC::ex> radius, surface;
  SourcePos radius_pos = e.kind_pos, surface_pos = e.kind_pos;
  const std::pair<const std::string*, const std::optional<GiNaC::ex>*> options[] = {{&e.option, &e.value},
                                                                                    {&e.option2, &e.value2}};
  const SourcePos option_pos[] = {e.option_pos, e.option2_pos};
  for (int k = 0; k < 2; ++k) {
    const std::string& word = *options[k].first;
    if (word.empty()) continue;
    if (word == "radius" && !radius) {
      radius = *options[k].second;
      radius_pos = option_pos[k];
    } else if (word == "surface" && !surface) {
      surface = *options[k].second;
      surface_pos = option_pos[k];
    } else {
      diags_.error(option_pos[k], fmt::format("{}: unexpected option '{}' (it is `rolling_sphere BODY radius r surface "
                                              "(gamma)`)",
                                              what, word));
      return;
    }
  }
  if (!radius || !surface) {
    diags_.error(e.kind_pos, fmt::format("{} needs '{}' (it is `rolling_sphere BODY radius r surface (gamma)`)", what,
                                         !radius ? "radius r" : "surface (gamma)"));
    return;
  }
  const GiNaC::ex r = *radius;
  if (const std::string varying = varies(r); !varying.empty()) {
    diags_.error(radius_pos, fmt::format("{}: the radius must be a constant (parameters only; it reads {})", what, varying));
    return;
  }
  if (const double rv = at_defaults(r); !std::isnan(rv) && !(rv > 0.0)) {
    diags_.error(radius_pos, fmt::format("{}: the radius must be positive (it is {})", what, rv));
    return;
  }
  const auto node = body(owner, e.end1);
  if (!node) {
    diags_.error(e.end1_pos, fmt::format("{}: unknown body '{}' (the sphere: a rigid3d body)", what, e.end1));
    return;
  }
  if (*node == PlanarLibrary::kGround || m_.nodes[*node].kind != LeafKind::Rigid3d) {
    diags_.error(e.end1_pos, fmt::format("{}: the sphere '{}' must be a rigid3d body (its mass centre is the "
                                         "sphere's centre)",
                                         what, e.end1));
    return;
  }
  const GiNaC::symbol xc = GiNaC::ex_to<GiNaC::symbol>(m_.coords[static_cast<std::size_t>(e.contact[0])].sym);
  const GiNaC::symbol yc = GiNaC::ex_to<GiNaC::symbol>(m_.coords[static_cast<std::size_t>(e.contact[1])].sym);
  // The surface is fixed: it reads x, y and parameters only.
  const GiNaC::ex gamma = *surface;
  if (const std::string varying = varies(gamma, {e.contact[0], e.contact[1]}); !varying.empty()) {
    diags_.error(surface_pos, fmt::format("{}: the surface must be a function of x, y and parameters only (it reads {})",
                                          what, varying));
    return;
  }
  const Node& ball = m_.nodes[*node];
  const GiNaC::ex gx = gamma.diff(xc), gy = gamma.diff(yc);
  const GiNaC::ex norm = GiNaC::sqrt(1 + gx * gx + gy * gy);
  const Vec n = {-gx / norm, -gy / norm, 1 / norm};
  const Vec P = {xc, yc, gamma};
  Vec G, vG;
  for (std::size_t k = 0; k < 3; ++k) {
    G.push_back(m_.coords[static_cast<std::size_t>(ball.coords[k])].sym);
    vG.push_back(m_.speeds[static_cast<std::size_t>(ball.speeds[k])].sym);
  }
  const char* axes[] = {"x", "y", "z"};
  for (std::size_t k = 0; k < 3; ++k)
    row(owner, fmt::format("{}.contact_{}", name, axes[k]), G[k] - P[k] - r * n[k], e.pos);
  const Vec w = rigid3d::angular_velocity_in_space(m_, ball);
  const Vec arm = {-r * n[0], -r * n[1], -r * n[2]};
  const Vec wxa = rigid3d::cross(w, arm);
  const Vec vP = {vG[0] + wxa[0], vG[1] + wxa[1], vG[2] + wxa[2]};
  row(owner, name + ".no_slip_x", rigid3d::dot(Vec{1, 0, gx}, vP), e.pos, Constraint::Level::Velocity);
  row(owner, name + ".no_slip_y", rigid3d::dot(Vec{0, 1, gy}, vP), e.pos, Constraint::Level::Velocity);
}

}  // namespace mbsc::model
