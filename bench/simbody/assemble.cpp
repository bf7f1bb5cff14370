// SPDX-License-Identifier: GPL-2.0-or-later
#include "assemble.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

namespace simbench {

using namespace SimTK;

namespace {

bool is_coordinate(const Mechanism& m, const std::string& alias) {
  const std::string& name = m.resolve(alias);
  for (const auto& a : m.angles)
    if (a.theta == name) return true;
  for (const auto& sl : m.slides)
    if (sl.x == name) return true;
  return false;
}

bool is_extra(const Mechanism& m, const std::string& alias) {
  for (const auto& e : m.extras)
    if (e.name == m.resolve(alias)) return true;
  return false;
}

double max_abs(const Vector& v) {
  double out = 0.0;
  for (int i = 0; i < v.size(); ++i) out = std::max(out, std::fabs(v[i]));
  return out;
}

}  // namespace

void add_speed_locks(Mechanism& m) {
  for (const auto& name : m.independent) {
    if (is_coordinate(m, name) || is_extra(m, name)) continue;
    bool ground_child = false;
    MobilizedBody body = m.mobilizer_of(name, ground_child);
    if (!ground_child) throw std::runtime_error("independent speed '" + name + "' is not a ground joint's");
    Constraint::ConstantSpeed lock(body, 0.0);
    lock.setDisabledByDefault(true);
    m.speed_locks.emplace_back(name, lock);
  }
}

State assemble_initial_state(Mechanism& m, const InitialState& init) {
  State s = m.system.getDefaultState();
  std::map<std::string, double> positions, speeds;
  for (const auto& [name, v] : init.guess) {
    if (!m.knows(name)) throw std::runtime_error("initial state: unknown name '" + name + "' for " + init.model);
    if (!is_coordinate(m, name)) throw std::runtime_error("initial state: guess '" + name + "' is not a coordinate");
    positions[name] = v;
  }
  Assembler assembler(m.system);
  assembler.setErrorTolerance(1e-13);
  assembler.setAccuracy(1e-14);
  for (const auto& [name, v] : init.given) {
    if (!m.knows(name)) throw std::runtime_error("initial state: unknown name '" + name + "' for " + init.model);
    if (is_coordinate(m, name)) {
      bool ground_child = false;
      const MobilizedBody body = m.mobilizer_of(name, ground_child);
      if (!ground_child) throw std::runtime_error("initial state: given coordinate '" + name + "' is not a ground joint's");
      assembler.lockMobilizer(body.getMobilizedBodyIndex());
      positions[name] = v;
    } else {
      speeds[name] = v;
    }
  }
  m.set_positions(s, positions);
  assembler.assemble(s);
  m.system.realize(s, Stage::Position);
  const double qerr = max_abs(s.getQErr());
  if (!(qerr < 1e-11)) throw std::runtime_error("assembly left a position residual " + std::to_string(qerr));
  for (const auto& [name, v] : positions)  // the locked ones must not have moved
    if (!std::count_if(init.guess.begin(), init.guess.end(), [&](const auto& g) { return g.first == name; }) &&
        std::fabs(m.get(s, name) - v) > 1e-14)
      throw std::runtime_error("assembly moved the given coordinate '" + name + "'");
  // Speeds: hold the given ones, project the rest onto the velocity constraints.
  m.set_speeds(s, speeds);
  for (auto& [name, lock] : m.speed_locks) {
    lock.enable(s);
    lock.setSpeed(s, speeds.count(name) ? speeds.at(name) : 0.0);
  }
  m.system.realize(s, Stage::Velocity);
  m.system.projectU(s, 1e-14);
  for (auto& [name, lock] : m.speed_locks) lock.disable(s);
  m.system.realize(s, Stage::Velocity);
  const double uerr = max_abs(s.getUErr());
  if (!(uerr < 1e-10)) throw std::runtime_error("assembly left a velocity residual " + std::to_string(uerr));
  for (const auto& [name, v] : speeds)
    if (std::fabs(m.get(s, name) - v) > 1e-12) throw std::runtime_error("projection moved the given speed '" + name + "'");
  return s;
}

}  // namespace simbench
