// SPDX-License-Identifier: GPL-2.0-or-later
// Time derivatives along the model's kinematics: d/dt e(t, q0, q1) =
//   de/dt + sum_i de/dq0_i * rate_i(t, q0, q1) + sum_j de/dq1_j * q1dot_j.
#include "mbsc/sym/eom.hpp"
#include "mbsc/sym/symbol_set.hpp"

#include <algorithm>
#include <unordered_map>
#include <vector>

namespace mbsc::sym {

namespace {

/// Where each coordinate, speed and kinematic name of a model sits: kind (0 coordinate,
/// 1 speed, 2 name) and index. Built once per model and thread (a big model's rows are
/// differentiated one by one, and looking up every variable for every row was quadratic
/// in its size); recognised by its sizes and its first and last symbols, which no other
/// model shares.
struct VariableIndex {
  std::unordered_map<GiNaC::ex, std::pair<int, int>, ExHash, GiNaC::ex_is_equal> of;
  std::size_t coords = 0, speeds = 0, names = 0;
  GiNaC::ex first, last;
};

const VariableIndex& variable_index(const model::Model& m) {
  thread_local VariableIndex index;
  const GiNaC::ex first = m.coords.empty() ? GiNaC::ex(0) : GiNaC::ex(m.coords.front().sym);
  const GiNaC::ex last = !m.kinematic_names.empty() ? GiNaC::ex(m.kinematic_names.back().sym)
                         : !m.speeds.empty()        ? GiNaC::ex(m.speeds.back().sym)
                                                    : GiNaC::ex(0);
  if (index.coords == m.coords.size() && index.speeds == m.speeds.size() && index.names == m.kinematic_names.size() &&
      index.first.is_equal(first) && index.last.is_equal(last))
    return index;
  index.of.clear();
  for (std::size_t i = 0; i < m.coords.size(); ++i) index.of.emplace(m.coords[i].sym, std::make_pair(0, static_cast<int>(i)));
  for (std::size_t j = 0; j < m.speeds.size(); ++j) index.of.emplace(m.speeds[j].sym, std::make_pair(1, static_cast<int>(j)));
  for (std::size_t k = 0; k < m.kinematic_names.size(); ++k)
    index.of.emplace(m.kinematic_names[k].sym, std::make_pair(2, static_cast<int>(k)));
  index.coords = m.coords.size();
  index.speeds = m.speeds.size();
  index.names = m.kinematic_names.size();
  index.first = first;
  index.last = last;
  return index;
}

}  // namespace

GiNaC::ex time_derivative(const model::Model& model, const GiNaC::ex& e) {
  const SymbolSet in_e(e);  // one traversal; then only the variables e reads
  const VariableIndex& index = variable_index(model);
  std::vector<std::pair<int, int>> read;
  for (const auto& s : in_e.symbols())
    if (const auto it = index.of.find(s); it != index.of.end()) read.push_back(it->second);
  std::sort(read.begin(), read.end());  // model order: coordinates, speeds, names
  GiNaC::ex result = in_e.diff(e, model.time);
  for (const auto& [kind, i] : read) {
    const auto k = static_cast<std::size_t>(i);
    if (kind == 0) result += e.diff(model.coords[k].sym) * model.coord_rates[k];
    else if (kind == 1) result += e.diff(model.speeds[k].sym) * model.speed_dots[k];
    // Kinematic names (issue 25): d/dt R = R [w]x, never through the ancestors' angles.
    else result += e.diff(model.kinematic_names[k].sym) * model.kinematic_names[k].rate;
  }
  return result;
}

std::vector<GiNaC::ex> velocity_residuals(const model::Model& model) {
  std::vector<GiNaC::ex> out;
  out.reserve(model.constraints.size());
  for (const auto& c : model.constraints)
    out.push_back(c.level == model::Constraint::Level::Position ? time_derivative(model, c.residual) : c.residual);
  return out;
}

}  // namespace mbsc::sym
