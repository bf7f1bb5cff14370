// SPDX-License-Identifier: GPL-2.0-or-later
// mbsc names on a Simbody state, and the helpers the model files share.
#include "mechanism.hpp"

#include <stdexcept>

namespace simbench {

using namespace SimTK;

bool Mechanism::knows(const std::string& alias) const {
  const std::string& name = resolve(alias);
  for (const auto& a : angles)
    if (a.theta == name || a.w == name) return true;
  for (const auto& sl : slides)
    if (sl.x == name || sl.u == name) return true;
  for (const auto& e : extras)
    if (e.name == name) return true;
  return false;
}

namespace {

// Absolute angles and rates of every rotating body, parents first.
std::vector<double> absolute(const Mechanism& m, const State& s, bool rates) {
  std::vector<double> out(m.angles.size());
  for (std::size_t i = 0; i < m.angles.size(); ++i) {
    const auto& a = m.angles[i];
    const double own = rates ? a.body.getOneU(s, MobilizerUIndex(0)) : a.body.getOneQ(s, MobilizerQIndex(0));
    out[i] = own + (a.parent >= 0 ? out[static_cast<std::size_t>(a.parent)] : 0.0);
  }
  return out;
}

void write_absolute(const Mechanism& m, State& s, const std::vector<double>& abs, bool rates) {
  for (std::size_t i = 0; i < m.angles.size(); ++i) {
    const auto& a = m.angles[i];
    const double v = abs[i] - (a.parent >= 0 ? abs[static_cast<std::size_t>(a.parent)] : 0.0);
    if (rates)
      a.body.setOneU(s, MobilizerUIndex(0), v);
    else
      a.body.setOneQ(s, MobilizerQIndex(0), v);
  }
}

}  // namespace

double Mechanism::get(const State& s, const std::string& alias) const {
  const std::string& name = resolve(alias);
  for (std::size_t i = 0; i < angles.size(); ++i) {
    if (angles[i].theta == name) return absolute(*this, s, false)[i];
    if (angles[i].w == name) return absolute(*this, s, true)[i];
  }
  for (const auto& sl : slides) {
    if (sl.x == name) return sl.body.getOneQ(s, MobilizerQIndex(0)) + sl.offset;
    if (sl.u == name) return sl.body.getOneU(s, MobilizerUIndex(0));
  }
  for (const auto& e : extras)
    if (e.name == name) return e.get(s);
  throw std::runtime_error("unknown state name '" + name + "'");
}

void Mechanism::set_positions(State& s, const std::map<std::string, double>& values) const {
  std::vector<double> abs = absolute(*this, s, false);
  for (const auto& [alias, v] : values) {
    const std::string& name = resolve(alias);
    bool found = false;
    for (std::size_t i = 0; i < angles.size(); ++i)
      if (angles[i].theta == name) abs[i] = v, found = true;
    for (const auto& sl : slides)
      if (sl.x == name) sl.body.setOneQ(s, MobilizerQIndex(0), v - sl.offset), found = true;
    if (!found) throw std::runtime_error("'" + name + "' is not a coordinate of this mechanism");
  }
  write_absolute(*this, s, abs, false);
}

void Mechanism::set_speeds(State& s, const std::map<std::string, double>& values) const {
  std::vector<double> abs = absolute(*this, s, true);
  for (const auto& [alias, v] : values) {
    const std::string& name = resolve(alias);
    bool found = false;
    for (std::size_t i = 0; i < angles.size(); ++i)
      if (angles[i].w == name) abs[i] = v, found = true;
    for (const auto& sl : slides)
      if (sl.u == name) sl.body.setOneU(s, MobilizerUIndex(0), v), found = true;
    for (const auto& e : extras)
      if (e.name == name) e.set(s, v), found = true;
    if (!found) throw std::runtime_error("'" + name + "' is not a speed of this mechanism");
  }
  write_absolute(*this, s, abs, true);
}

MobilizedBody Mechanism::mobilizer_of(const std::string& alias, bool& ground_child) const {
  const std::string& name = resolve(alias);
  for (const auto& a : angles)
    if (a.theta == name || a.w == name) {
      ground_child = a.parent < 0 && a.body.getParentMobilizedBody().isGround();
      return a.body;
    }
  for (const auto& sl : slides)
    if (sl.x == name || sl.u == name) {
      ground_child = sl.body.getParentMobilizedBody().isGround();
      return sl.body;
    }
  throw std::runtime_error("'" + name + "' has no mobilizer of its own");
}

Body::Rigid planar_body(double m, double Jc, double cx, double cy) {
  const Vec3 com(cx, cy, 0);
  // Central inertia (Jc, Jc, Jc), moved to the body origin (parallel axes).
  const Inertia about_origin = Inertia(Vec3(Jc, Jc, Jc)).shiftFromMassCenter(-com, m);
  return Body::Rigid(MassProperties(m, com, about_origin));
}

void pin_constraint(SimbodyMatterSubsystem& matter, MobilizedBody& a, Vec2 pa, MobilizedBody& b, Vec2 pb) {
  (void)matter;
  Constraint::PointInPlane(a, UnitVec3(1, 0, 0), pa[0], b, Vec3(pb[0], pb[1], 0));
  Constraint::PointInPlane(a, UnitVec3(0, 1, 0), pa[1], b, Vec3(pb[0], pb[1], 0));
}

}  // namespace simbench
