// SPDX-License-Identifier: GPL-2.0-or-later
#include "mbsc/sym/massless_check.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace mbsc::sym {

namespace {

bool is_zero_at(const Probe& probe, const GiNaC::ex& e) { return probe.eval(e) == 0.0; }

/// The motion of every speed (index-aligned with m.speeds) when the independent speeds
/// move as z: the dependent rates of eom.top_down are affine in the independent ones,
/// so their value at z minus their value at 0 is the linear part C z.
std::vector<double> motion_of(const model::Model& m, const Eom& eom, const Probe& probe, const Eigen::VectorXd& z) {
  auto rates = [&](bool with_z) {
    Probe p = probe;
    std::vector<double> out(m.speeds.size(), 0.0);
    for (std::size_t j = 0; j < eom.independent.size(); ++j) {
      const double v = with_z ? z(static_cast<Eigen::Index>(j)) : 0.0;
      p.bind(m.speed_dots[static_cast<std::size_t>(eom.independent[j])], v);
      out[static_cast<std::size_t>(eom.independent[j])] = v;
    }
    for (const auto& d : eom.top_down) {
      const double v = p.eval(d.value);
      p.bind(d.sym, v);
      for (std::size_t s = 0; s < m.speeds.size(); ++s)
        if (m.speed_dots[s].is_equal(d.sym)) out[s] = v;
    }
    return out;
  };
  const auto a = rates(true), b = rates(false);
  std::vector<double> out(a.size());
  for (std::size_t s = 0; s < a.size(); ++s) out[s] = a[s] - b[s];
  return out;
}

/// ", with --freeze m2=0" for the frozen parameters e holds (the file alone looks right), or "".
std::string frozen_note(const model::Model& m, const Eom& eom, const GiNaC::ex& e) {
  std::string names;
  for (const auto& p : m.params) {
    const auto it = eom.options.frozen.find(p.name);
    if (it == eom.options.frozen.end() || m.structural.count(p.name) || !e.has(p.sym)) continue;
    names += fmt::format("{}{}={}", names.empty() ? "" : " ", p.name, it->second);
  }
  return names.empty() ? "" : ", with --freeze " + names;
}

}  // namespace

std::vector<std::string> massless_bodies(const model::Model& m, const Probe& probe) {
  std::vector<std::string> out;
  for (const auto& node : m.nodes) {
    if (!model::is_body(node.kind)) continue;
    const bool no_mass = is_zero_at(probe, node.mass);
    const bool no_inertia = model::is_rigid2d(node.kind) && is_zero_at(probe, node.inertia);
    if (!no_mass && !no_inertia) continue;
    out.push_back(fmt::format("{} ({}{}{})", node.name, no_mass ? "mass 0" : "", no_mass && no_inertia ? ", " : "",
                              no_inertia ? "inertia 0" : ""));
  }
  return out;
}

bool report_massless_directions(const model::Model& m, const Eom& eom, const Probe& probe, const Eigen::MatrixXd& Mn,
                                Diagnostics& diags) {
  if (massless_bodies(m, probe).empty() || !Mn.allFinite()) return false;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(0.5 * (Mn + Mn.transpose()));
  if (eig.info() != Eigen::Success) return false;
  const double scale = std::max(1.0, eig.eigenvalues().cwiseAbs().maxCoeff());
  // Over every null motion, per body: the independent speeds of the motions that move it
  // and its speeds that move without inertia (translation against its mass, the angular
  // speed of a rigid body against its inertia).
  struct Blame {
    std::vector<std::string> direction, translation, rotation;
  };
  std::vector<Blame> blame(m.nodes.size());
  auto add = [](std::vector<std::string>& v, const std::string& s) {
    if (std::find(v.begin(), v.end(), s) == v.end()) v.push_back(s);
  };
  for (Eigen::Index k = 0; k < eig.eigenvalues().size(); ++k) {
    if (eig.eigenvalues()(k) > 1e-10 * scale) break;  // ascending: the rest carry inertia
    const Eigen::VectorXd z = eig.eigenvectors().col(k);
    const auto motion = motion_of(m, eom, probe, z);
    for (std::size_t n = 0; n < m.nodes.size(); ++n) {
      const auto& node = m.nodes[n];
      if (!model::is_body(node.kind)) continue;
      const bool no_mass = is_zero_at(probe, node.mass);
      const bool no_inertia = model::is_rigid2d(node.kind) && is_zero_at(probe, node.inertia);
      bool moves = false;
      for (std::size_t k2 = 0; k2 < node.speeds.size(); ++k2) {
        const auto s = static_cast<std::size_t>(node.speeds[k2]);
        if (std::abs(motion[s]) <= 1e-9) continue;
        const bool angular = model::is_rigid2d(node.kind) && k2 + 1 == node.speeds.size();
        if (angular && no_inertia) add(blame[n].rotation, m.speeds[s].name);
        if (!angular && no_mass) add(blame[n].translation, m.speeds[s].name);
        moves = moves || (angular ? no_inertia : no_mass);
      }
      if (!moves) continue;
      for (Eigen::Index j = 0; j < z.size(); ++j)
        if (std::abs(z(j)) > 1e-6)
          add(blame[n].direction, m.speeds[static_cast<std::size_t>(eom.independent[static_cast<std::size_t>(j)])].name);
    }
  }
  auto list = [](const std::vector<std::string>& v) {
    std::string out;
    for (const auto& s : v) out += (out.empty() ? "" : ", ") + s;
    return out;
  };
  bool reported = false;
  for (std::size_t n = 0; n < m.nodes.size(); ++n) {
    const auto& node = m.nodes[n];
    const Blame& b = blame[n];
    if (!b.translation.empty())
      diags.error(node.mass_pos,
                  fmt::format("body '{}' is massless (mass 0{}) and the reduced mass matrix is singular: the motion along "
                              "{} moves it ({}) and nothing with inertia; give it a mass or constrain that motion",
                              node.name, frozen_note(m, eom, node.mass), list(b.direction), list(b.translation)));
    if (!b.rotation.empty())
      diags.error(node.inertia_pos.line != 0 ? node.inertia_pos : node.pos,
                  fmt::format("body '{}' has no rotational inertia (inertia 0{}) and the reduced mass matrix is singular: "
                              "the motion along {} turns it ({}) and moves nothing with inertia; give it an inertia or "
                              "constrain that rotation",
                              node.name, frozen_note(m, eom, node.inertia), list(b.direction), list(b.rotation)));
    reported = reported || !b.translation.empty() || !b.rotation.empty();
  }
  return reported;
}

}  // namespace mbsc::sym
