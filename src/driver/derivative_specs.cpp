// SPDX-License-Identifier: GPL-2.0-or-later
// rhs_jacobian and inverse_dynamics_jacobian (include/mbsc/driver/derivative_specs.hpp).
#include "mbsc/driver/derivative_specs.hpp"

#include <fmt/format.h>

#include <optional>

#include "mbsc/driver/pipeline.hpp"
#include "mbsc/sym/forward_derivative.hpp"

namespace mbsc::driver {

namespace {

// The state's symbols in x order (what bindings() binds to x[i]).
std::vector<GiNaC::symbol> state_symbols(const model::Model& m, const sym::Eom& eom, const sym::MinimalState* minimal) {
  std::vector<GiNaC::symbol> x;
  for (const ir::Binding& b : bindings(m, eom, minimal))
    if (b.cpp.rfind("x[", 0) == 0) x.push_back(b.sym);
  return x;
}

// The derivative of `f` over the blocks, or a function returning 4 (with NaN) where
// `f` cannot be computed or forward mode cannot differentiate it. With a tree's
// `residual`, the implicit form where it applies; its documentation is then
// `implicit_doc` instead of the shell's.
ir::FunctionSpec derivative(const ir::FunctionSpec& f, const std::vector<std::vector<GiNaC::symbol>>& blocks,
                            ir::FunctionSpec shell, long max_ops = 0, const TreeResidual* residual = nullptr,
                            const std::string& implicit_doc = "") {
  std::size_t columns = 0;
  for (const auto& b : blocks) columns += b.size();
  auto undefined = [&](std::string why) {
    shell.steps.clear();
    shell.outputs.assign(f.outputs.size() * columns, GiNaC::ex(0));
    shell.undefined_reason = std::move(why);
    return shell;
  };
  if (!f.undefined_reason.empty()) return undefined(f.undefined_reason);
  const long entries = static_cast<long>(f.outputs.size() * columns);
  if (max_ops > 0 && 4 * entries > max_ops)
    return undefined(fmt::format("{} entries, more than the {} operations this compile allows", entries, max_ops));
  try {
    // The implicit form where the rhs is a tree's; forward mode through the rhs where it
    // is not, or where the implicit form does not apply to the rhs's outputs.
    std::optional<ir::FunctionSpec> implicit;
    if (residual) try {
        implicit = implicit_rhs_jacobian(f, *residual, blocks);
      } catch (const sym::NotDifferentiable&) {
      }
    ir::FunctionSpec d = implicit ? std::move(*implicit) : sym::forward_derivative(f, blocks);
    if (implicit) shell.doc = implicit_doc;
    shell.steps = std::move(d.steps);
    shell.outputs = std::move(d.outputs);
    return shell;
  } catch (const sym::NotDifferentiable& e) {
    return undefined(fmt::format("forward mode does not differentiate {} (take difference quotients of {})", e.what(),
                                 f.name));
  } catch (const std::exception& e) {
    // A spec forward mode does not expect (a step reading a later one) or a GiNaC error
    // (a log of zero): the function is written undefined rather than failing generate.
    return undefined(fmt::format("its forward-mode derivative failed: {} (take difference quotients of {})", e.what(),
                                 f.name));
  }
}

}  // namespace

ir::FunctionSpec rhs_jacobian_spec(const model::Model& m, const sym::Eom& eom, const sym::MinimalState* minimal,
                                   const ir::FunctionSpec& rhs, long max_ops, const TreeResidual* residual) {
  std::vector<GiNaC::symbol> u;
  for (const auto& in : m.inputs) u.push_back(in.sym);
  const std::string what =
      "derivatives of the state derivative: OUT = (J_x = dxdot/dx, kNx x kNx, then J_u = dxdot/du,\n"
      "kNx x kNin), both row-major (J_u at OUT + kNx*kNx)";
  ir::FunctionSpec shell{"rhs_jacobian", what + "; forward-mode derivatives of rhs", "J", "kNx*kNx + kNx*kNin", {}, {}};
  return derivative(rhs, {state_symbols(m, eom, minimal), u}, std::move(shell), max_ops, residual,
                    what + ";\nimplicit form: the residual's forward-mode derivatives solved with the tree recursion's pivots");
}

ir::FunctionSpec inverse_dynamics_jacobian_spec(const model::Model& m, const sym::Eom& eom,
                                                const sym::MinimalState* minimal, const ir::FunctionSpec& inverse_dynamics) {
  std::vector<GiNaC::symbol> zdot;
  for (int s : eom.independent) zdot.push_back(m.speed_dots[static_cast<std::size_t>(s)]);
  ir::FunctionSpec shell{"inverse_dynamics_jacobian",
                         "derivatives of the inverse dynamics: OUT = (du/dx, kNin x kNx, then du/dzdot, kNin x kNdof),\n"
                         "both row-major (du/dzdot at OUT + kNin*kNx); forward-mode derivatives of inverse_dynamics",
                         "J", "kNin*kNx + kNin*kNdof", {}, {}};
  shell.third_arg = "zdot";
  return derivative(inverse_dynamics, {state_symbols(m, eom, minimal), zdot}, std::move(shell));
}

void add_derivative_specs(const model::Model& m, const sym::Eom& eom, const sym::MinimalState* minimal, bool rhs_jacobian,
                          bool inverse_dynamics_jacobian, long rhs_jacobian_max_ops, const TreeResidual* residual,
                          std::vector<ir::FunctionSpec>& specs) {
  auto find = [&](const char* name) -> const ir::FunctionSpec& {
    for (const auto& f : specs)
      if (f.name == name) return f;
    throw std::logic_error(fmt::format("generate: {} is differentiated but was not built", name));
  };
  std::vector<ir::FunctionSpec> added;
  if (rhs_jacobian) added.push_back(rhs_jacobian_spec(m, eom, minimal, find("rhs"), rhs_jacobian_max_ops, residual));
  if (inverse_dynamics_jacobian)
    added.push_back(inverse_dynamics_jacobian_spec(m, eom, minimal, find("inverse_dynamics")));
  for (auto& f : added) specs.push_back(std::move(f));
}

}  // namespace mbsc::driver
