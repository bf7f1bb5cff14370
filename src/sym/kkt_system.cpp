// SPDX-License-Identifier: GPL-2.0-or-later
#include "mbsc/sym/kkt_system.hpp"

#include <algorithm>

#include "mbsc/sym/own_force.hpp"
#include "mbsc/sym/symbol_set.hpp"

namespace mbsc::sym {

std::vector<int> symbols_in(const GiNaC::ex& e, const GiNaC::exmap& index) {
  std::vector<int> out;
  for (auto it = e.preorder_begin(); it != e.preorder_end(); ++it) {
    if (!GiNaC::is_a<GiNaC::symbol>(*it)) continue;
    const auto found = index.find(*it);
    if (found != index.end()) out.push_back(GiNaC::ex_to<GiNaC::numeric>(found->second).to_int());
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

namespace {

// symbol -> its index in `syms`, as the exmap symbols_in reads.
template <class Vars>
GiNaC::exmap index_of(const Vars& vars) {
  GiNaC::exmap index;
  for (std::size_t i = 0; i < vars.size(); ++i) index[vars[i].sym] = static_cast<int>(i);
  return index;
}

GiNaC::exmap index_of_symbols(const std::vector<GiNaC::symbol>& syms) {
  GiNaC::exmap index;
  for (std::size_t i = 0; i < syms.size(); ++i) index[syms[i]] = static_cast<int>(i);
  return index;
}

// d/dt of e along the kinematics (as sym/eom.hpp's time_derivative), differentiating only
// with respect to the coordinates and speeds e contains (found by one traversal).
GiNaC::ex sparse_time_derivative(const model::Model& m, const GiNaC::exmap& coords, const GiNaC::exmap& speeds,
                                 const GiNaC::ex& e) {
  GiNaC::ex result = e.diff(m.time);
  for (int i : symbols_in(e, coords)) result += e.diff(m.coords[static_cast<std::size_t>(i)].sym) * m.coord_rates[static_cast<std::size_t>(i)];
  for (int j : symbols_in(e, speeds)) result += e.diff(m.speeds[static_cast<std::size_t>(j)].sym) * m.speed_dots[static_cast<std::size_t>(j)];
  if (!m.kinematic_names.empty()) {
    const SymbolSet in_e(e);
    for (const auto& k : m.kinematic_names)
      if (in_e.contains(k.sym)) result += e.diff(k.sym) * k.rate;
  }
  return result;
}

}  // namespace

KktSystem kkt_system(const model::Model& m) {
  const std::size_t nu = m.speeds.size(), nc = m.constraints.size();
  const GiNaC::exmap coord_index = index_of(m.coords), speed_index = index_of(m.speeds), rate_index = index_of_symbols(m.speed_dots);
  GiNaC::exmap no_rates;
  for (const auto& s : m.speed_dots) no_rates[s] = 0;
  KktSystem out;
  out.My.resize(nu);
  out.hy.resize(nu);
  for (std::size_t i = 0; i < nu; ++i) {
    const GiNaC::ex f = own_force(m, static_cast<int>(i));
    for (int j : symbols_in(f, rate_index)) {
      const GiNaC::ex e = -f.diff(m.speed_dots[static_cast<std::size_t>(j)]);
      if (!e.is_zero()) out.My[i].push_back({j, e});
    }
    out.hy[i] = f.subs(no_rates, GiNaC::subs_options::no_pattern);
  }
  out.A.resize(nc);
  out.velocity.resize(nc);
  out.b.resize(nc);
  out.g.resize(nc);
  for (std::size_t r = 0; r < nc; ++r) {
    const auto& c = m.constraints[r];
    const bool position = c.level == model::Constraint::Level::Position;
    const GiNaC::ex order1 = position ? sparse_time_derivative(m, coord_index, speed_index, c.residual) : c.residual;
    out.velocity[r] = order1;
    for (int j : symbols_in(order1, speed_index)) {
      const GiNaC::ex e = order1.diff(m.speeds[static_cast<std::size_t>(j)].sym);
      if (!e.is_zero()) out.A[r].push_back({j, e});
    }
    out.b[r] = sparse_time_derivative(m, coord_index, speed_index, order1).subs(no_rates, GiNaC::subs_options::no_pattern);
    out.g[r] = position ? c.residual : GiNaC::ex(0);
  }
  return out;
}

}  // namespace mbsc::sym
