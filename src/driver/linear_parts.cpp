// SPDX-License-Identifier: GPL-2.0-or-later
// The generated function linear_parts: the first-order Taylor coefficients of every
// equation of the dependent-coordinate system (kinematics, invariants, dynamic
// equations with their constraint forces), from which the runtime forms the linear
// model about a reference (include/mbsc/runtime/linear_model.hpp; docs/linearization.md).
//
// The third argument w = (u, q1', lambda) carries the reference inputs, the reference
// rates of every speed and the reference multipliers, so that the terms that multiply
// them (the rates in A q1' + b and My q1', the constraint forces A^T lambda) are
// differentiated at the reference as well.
#include "mbsc/driver/linear_parts.hpp"

#include <fmt/format.h>

#include "mbsc/model/rigid3d.hpp"
#include "mbsc/sym/kkt_system.hpp"
#include "mbsc/sym/symbol_set.hpp"

namespace mbsc::driver {

namespace {

// Appends d(rows[i])/d(vars[j]), row-major.
template <class Vars, class Symbol>
void append_jacobian(std::vector<GiNaC::ex>& out, const std::vector<GiNaC::ex>& rows, const Vars& vars, Symbol of) {
  for (const auto& r : rows) {
    const sym::SymbolSet in_r(r);
    for (const auto& v : vars) out.push_back(in_r.diff(r, of(v)));
  }
}

}  // namespace

ir::FunctionSpec linear_parts_spec(const model::Model& m, const std::function<GiNaC::ex(const GiNaC::ex&)>& finalize,
                                   std::vector<ir::Step> rebuild) {
  // Every coefficient here is a partial derivative by the coordinates, which must see
  // through the kinematic names (named body rotations, docs/formulation.md): they are
  // written out first.
  const GiNaC::exmap names = model::kinematic_name_values(m);
  const auto fin = [&](const GiNaC::ex& e) {
    return finalize(names.empty() ? e : e.subs(names, GiNaC::subs_options::no_pattern));
  };
  const std::size_t nin = m.inputs.size(), n1 = m.speeds.size(), nc = m.constraints.size();
  ir::FunctionSpec f{"linear_parts",
                     "the Taylor coefficients the linear model is formed from (runtime/linear_model.hpp), over the\n"
                     "full layout (n0 = kNqFull coordinates, n1 = kNuFull speeds), row-major blocks in this order:\n"
                     "Kq n0 x n0, Kv n0 x n1 (d q0'/d q0, d q0'/d q1); A kNc x n1 (d velocity residual/d q1);\n"
                     "Wq kNc x n0 (d velocity residual/d q0); P (kNposc + kNquaternions) x n0 (d position residual/d q0,\n"
                     "then d|e|^2/d q0 of each unit quaternion);\n"
                     "Gq kNc x n0, Gv kNc x n1 (d(A q1' + b)/d q0, d q1); My n1 x n1;\n"
                     "Fq n1 x n0, Fv n1 x n1, Fu n1 x kNin (d(hy - My q1' + A^T lambda)/d q0, d q1, d u);\n"
                     "r n1 (hy - My q1'); c kNc (A q1' + b)",
                     "parts",
                     "kLinearPartsSize",
                     std::move(rebuild),
                     {}};
  f.third_arg = "w";
  if (!m.frictions.empty()) {
    f.undefined_reason = "the model has Coulomb friction, whose force is not differentiable where a joint slides";
    return f;
  }
  // w = (u, q1' of every speed, lambda of every constraint)
  std::vector<GiNaC::symbol> lambda;
  for (std::size_t k = 0; k < nin; ++k) f.third_bindings.push_back({m.inputs[k].sym, fmt::format("w[{}]", k)});
  for (std::size_t j = 0; j < n1; ++j) f.third_bindings.push_back({m.speed_dots[j], fmt::format("w[{}]", nin + j)});
  for (std::size_t r = 0; r < nc; ++r) {
    lambda.emplace_back(fmt::format("lambda_{}", r));
    f.third_bindings.push_back({lambda.back(), fmt::format("w[{}]", nin + n1 + r)});
  }

  const sym::KktSystem sys = sym::kkt_system(m);
  std::vector<GiNaC::ex> kin, vel, pos, acc, force, own;
  for (const auto& rate : m.coord_rates) kin.push_back(fin(rate));
  for (std::size_t r = 0; r < nc; ++r) {
    vel.push_back(fin(sys.velocity[r]));
    if (m.constraints[r].level == model::Constraint::Level::Position) pos.push_back(fin(m.constraints[r].residual));
    GiNaC::ex a = sys.b[r];
    for (const auto& e : sys.A[r]) a += e.value * m.speed_dots[static_cast<std::size_t>(e.col)];
    acc.push_back(fin(a));
  }
  // A unit quaternion's norm is a first integral of its kinematics, not a constraint: a
  // perturbation of it is no motion of the body (its rotation matrix would scale lengths
  // by |e|^2), so its row joins P and the tangent space leaves that direction out.
  for (const auto& q : unit_quaternion_coords(m)) {
    GiNaC::ex norm = 0;
    for (int i : q) norm += GiNaC::pow(m.coords[static_cast<std::size_t>(i)].sym, 2);
    pos.push_back(norm);
  }
  std::vector<GiNaC::ex> reactions(n1, GiNaC::ex(0));
  for (std::size_t r = 0; r < nc; ++r)
    for (const auto& e : sys.A[r]) reactions[static_cast<std::size_t>(e.col)] += e.value * lambda[r];
  for (std::size_t i = 0; i < n1; ++i) {
    GiNaC::ex o = sys.hy[i];
    for (const auto& e : sys.My[i]) o -= e.value * m.speed_dots[static_cast<std::size_t>(e.col)];
    own.push_back(fin(o));
    force.push_back(fin(o + reactions[i]));
  }
  auto coord = [](const model::Variable& v) { return v.sym; };
  auto input = [](const model::Variable& v) { return v.sym; };
  auto& out = f.outputs;
  append_jacobian(out, kin, m.coords, coord);
  append_jacobian(out, kin, m.speeds, coord);
  append_jacobian(out, vel, m.speeds, coord);
  append_jacobian(out, vel, m.coords, coord);
  append_jacobian(out, pos, m.coords, coord);
  append_jacobian(out, acc, m.coords, coord);
  append_jacobian(out, acc, m.speeds, coord);
  // My: minus the coefficient of each rate in the own forces.
  for (std::size_t i = 0; i < n1; ++i) {
    const sym::SymbolSet in_o(own[i]);
    for (std::size_t j = 0; j < n1; ++j) out.push_back(-in_o.diff(own[i], m.speed_dots[j]));
  }
  append_jacobian(out, force, m.coords, coord);
  append_jacobian(out, force, m.speeds, coord);
  append_jacobian(out, own, m.inputs, input);
  out.insert(out.end(), own.begin(), own.end());
  out.insert(out.end(), acc.begin(), acc.end());
  return f;
}

std::vector<std::vector<int>> unit_quaternion_coords(const model::Model& m) {
  std::vector<std::vector<int>> out;
  for (const auto& names : model::rigid3d::unit_quaternion_names(m)) {
    std::vector<int> at;
    for (const auto& n : names)
      for (std::size_t i = 0; i < m.coords.size(); ++i)
        if (m.coords[i].name == n) at.push_back(static_cast<int>(i));
    if (at.size() == names.size()) out.push_back(at);
  }
  return out;
}

long linear_parts_size(const model::Model& m) {
  long n0 = static_cast<long>(m.coords.size()), n1 = static_cast<long>(m.speeds.size());
  long nc = static_cast<long>(m.constraints.size()), nin = static_cast<long>(m.inputs.size());
  long nposc = static_cast<long>(unit_quaternion_coords(m).size());  // P: position rows, then quaternion norms
  for (const auto& c : m.constraints) nposc += c.level == model::Constraint::Level::Position;
  return n0 * n0 + n0 * n1 + nc * n1 + nc * n0 + nposc * n0 + nc * n0 + nc * n1 + n1 * n1 + n1 * n0 + n1 * n1 +
         n1 * nin + n1 + nc;
}

}  // namespace mbsc::driver
