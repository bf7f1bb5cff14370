// SPDX-License-Identifier: GPL-2.0-or-later
// The functions of `--formulation multipliers` (include/mbsc/sym/multipliers.hpp): rhs,
// multipliers and reaction_forces from one (nu + nc) solve, over the full state.
#include <fmt/format.h>

#include <utility>

#include "mbsc/driver/pipeline.hpp"
#include "mbsc/sym/multipliers.hpp"
#include "mbsc/sym/probe.hpp"
#include "mbsc/sym/tidy.hpp"

namespace mbsc::driver {

std::vector<ir::FunctionSpec> multiplier_specs(const model::Model& m, const sym::Eom& eom, const GenerateOptions& opt,
                                               const BaumgarteGains& gains, Diagnostics& diags) {
  const sym::KktSystem sys = sym::kkt_system(m);  // the dense matrices and the sparse solve share it
  const sym::MultiplierForm form = sym::multiplier_form(m, sys);
  const unsigned nu = form.My.rows(), nc = form.A.rows();
  auto fin = [&](const GiNaC::ex& e) { return sym::tidy(finalize(m, eom, e)); };
  std::vector<GiNaC::symbol> lambda;
  for (unsigned r = 0; r < nc; ++r) lambda.emplace_back(fmt::format("lambda_{}", r));
  // [My  -A^T] [q1'   ]   [hy                                     ]
  // [A    0  ] [lambda] = [-(b + 2 alpha (A q1 + a) + beta^2 g)   ]
  auto kkt = [&]() {
    ir::Solve s;
    s.label = "multipliers: [My -A^T; A 0] [q1'; lambda] = [hy; -(b + 2 alpha f' + beta^2 f)]";
    s.n = static_cast<int>(nu + nc);
    s.k = 1;
    for (unsigned i = 0; i < nu + nc; ++i) {
      for (unsigned j = 0; j < nu + nc; ++j) {
        GiNaC::ex e = 0;
        if (i < nu && j < nu) e = form.My(i, j);
        else if (i < nu) e = -form.A(j - nu, i);
        else if (j < nu) e = form.A(i - nu, j);
        s.A.push_back(fin(e));
      }
      if (i < nu) {
        s.B.push_back(fin(form.hy(i, 0)));
      } else {
        const unsigned r = i - nu;
        s.B.push_back(fin(-(form.b(r, 0) + 2 * gains.alpha * form.velocity(r, 0) + gains.beta * gains.beta * form.g(r, 0))));
      }
    }
    for (unsigned j = 0; j < nu; ++j) s.X.push_back(m.speed_dots[j]);
    for (const auto& l : lambda) s.X.push_back(l);
    return s;
  };
  // With a constant diagonal My (bodies in absolute coordinates, particles) the speeds
  // come out of the first block row, q1' = My^-1 (hy + A^T lambda), and lambda from the
  // nc x nc Schur complement (A My^-1 A^T) lambda = -(b + ...) - A My^-1 hy, symmetric
  // positive definite while A has full row rank: a Cholesky of nc instead of an LU of
  // nu + nc. Otherwise (nodal bodies, custom leaves with coupled inertia) the whole system.
  // A massless body (a mass parameter whose default is 0) has no inverse there: whole system.
  bool diagonal = true;
  const sym::Probe at_defaults(m, eom.param_values);
  for (unsigned i = 0; i < nu && diagonal; ++i)
    for (unsigned j = 0; j < nu && diagonal; ++j) {
      const GiNaC::ex e = fin(form.My(i, j));
      diagonal = i == j ? !e.is_zero() && sym::is_state_free(e, m) && at_defaults.eval(e) != 0.0 : e.is_zero();
    }
  if (!eom.redundant_on_manifold.empty() && !(diagonal && nc > 0)) {
    diags.error(m.name_pos, fmt::format("--formulation multipliers: model '{}' has constraint rows that are redundant on the "
                                        "mechanism ('{}' first), which leave the whole system [My -A^T; A 0] singular; the "
                                        "minimum-norm multipliers are taken from the Schur complement A My^-1 A^T, which needs "
                                        "a constant diagonal My (bodies in absolute coordinates); use the complement formulation",
                                        m.name, m.constraints[static_cast<std::size_t>(eom.redundant_on_manifold.front())].name));
    return {};
  }
  std::optional<std::vector<ir::Step>> dense_built;  // built once: auto may count it, then keep it
  auto dense_steps = [&]() -> std::vector<ir::Step> {
    if (dense_built) return *dense_built;
    std::vector<ir::Step> steps;
    if (diagonal && nc > 0) {
      ir::Solve s;
      s.label = "multipliers: (A My^-1 A^T) lambda = -(b + 2 alpha f' + beta^2 f) - A My^-1 hy";
      s.n = static_cast<int>(nc);
      s.k = 1;
      s.spd = true;
      // Rows redundant on the mechanism leave it semidefinite: the minimum-norm multipliers.
      if (!eom.redundant_on_manifold.empty()) {
        s.rank = static_cast<int>(nc) - static_cast<int>(eom.redundant_on_manifold.size());
        s.label += ", semidefinite (rank " + std::to_string(s.rank) + "): minimum-norm multipliers";
      }
      for (unsigned r = 0; r < nc; ++r) {
        for (unsigned c = 0; c < nc; ++c) {
          GiNaC::ex e = 0;
          for (unsigned j = 0; j < nu; ++j)
            if (!form.A(r, j).is_zero() && !form.A(c, j).is_zero()) e += form.A(r, j) * form.A(c, j) / form.My(j, j);
          s.A.push_back(fin(e));
        }
        GiNaC::ex rhs = -(form.b(r, 0) + 2 * gains.alpha * form.velocity(r, 0) + gains.beta * gains.beta * form.g(r, 0));
        for (unsigned j = 0; j < nu; ++j)
          if (!form.A(r, j).is_zero()) rhs -= form.A(r, j) * form.hy(j, 0) / form.My(j, j);
        s.B.push_back(fin(rhs));
        s.X.push_back(lambda[r]);
      }
      steps.push_back(s);
      for (unsigned j = 0; j < nu; ++j) {
        GiNaC::ex e = form.hy(j, 0);
        for (unsigned r = 0; r < nc; ++r)
          if (!form.A(r, j).is_zero()) e += form.A(r, j) * lambda[r];
        steps.push_back(ir::Define{m.speed_dots[j], fin(e / form.My(j, j))});
      }
    } else {
      steps.push_back(kkt());
    }
    dense_built = steps;
    return steps;
  };
  std::vector<ir::Step> steps;  // every function below starts with them
  const std::string rhs_doc = "state derivative: xdot = (q0 rates, q1 rates), multipliers formulation";
  std::vector<GiNaC::ex> rhs_outputs;
  for (const auto& r : m.coord_rates) rhs_outputs.push_back(fin(r));
  for (const auto& s : m.speed_dots) rhs_outputs.push_back(s);
  // The tree recursion or the sparse elimination of the same system (O(N), docs/formulation.md).
  std::optional<sym::KktElimination> sparse;
  if (!redundancy_allows_sparse(m, eom, opt, diags)) return {};
  if (opt.solver != Solver::Dense && nu > 0 && eom.redundant_on_manifold.empty()) {
    std::vector<GiNaC::ex> c;
    for (unsigned r = 0; r < nc; ++r)
      c.push_back(-(sys.b[r] + 2 * gains.alpha * sys.velocity[r] + gains.beta * gains.beta * sys.g[r]));
    std::string why;
    sparse = rhs_solve_steps(m, eom, sys, c, lambda, /*with_multipliers=*/true, why);
    if (!sparse && opt.solver == Solver::Sparse) {
      diags.error(m.name_pos, fmt::format("--solver sparse: model '{}' cannot be solved in a tree order: {}", m.name, why));
      return {};
    }
  }
  if (sparse) {
    std::vector<ir::Binding> binds = bindings(m, eom);
    const std::size_t np = eom.free_params.size();
    binds.push_back({gains.alpha, fmt::format("p[{}]", np), true});
    binds.push_back({gains.beta, fmt::format("p[{}]", np + 1), true});
    const ir::FunctionSpec sparse_rhs{"rhs", rhs_doc, "xdot", "kNx", sparse->steps, rhs_outputs};
    auto dense = [&]() {
      ir::FunctionSpec f{"rhs", rhs_doc, "xdot", "kNx", {}, rhs_outputs};
      f.steps = dense_steps();
      return f;
    };
    // A speeds-first loop's pivots fall like the 3/2 power of the dense Schur complement's.
    if (prefer_sparse(m, opt, *sparse, sparse_rhs, dense, binds)) steps = sparse_steps_reported(*sparse, GiNaC::numeric(2, 3));
  }
  if (steps.empty()) steps = dense_steps();
  auto wanted = [&](const std::string& n) { return opt.functions.empty() || opt.functions.count(n); };
  std::vector<ir::FunctionSpec> specs;
  if (wanted("rhs")) {
    ir::FunctionSpec f{"rhs", rhs_doc, "xdot", "kNx", steps, rhs_outputs};
    specs.push_back(std::move(f));
  }
  if (wanted("multipliers") && nc > 0) {
    ir::FunctionSpec f{"multipliers", "Lagrange multipliers lambda, one per constraint (kConstraintNames)", "lambda", "kNc",
                       steps, {}};
    for (const auto& l : lambda) f.outputs.push_back(l);
    specs.push_back(std::move(f));
  }
  if (wanted("reaction_forces") && nc > 0) {
    ir::FunctionSpec f{"reaction_forces", "generalized constraint forces A^T lambda along each speed (kStateNames after kNq)",
                       "R", "kNu", steps, {}};
    for (unsigned j = 0; j < nu; ++j) {
      GiNaC::ex e = 0;
      for (unsigned r = 0; r < nc; ++r) e += fin(form.A(r, j)) * lambda[r];
      f.outputs.push_back(e);
    }
    specs.push_back(std::move(f));
  }
  // Every function reads the kinematic names it needs from their definitions.
  define_kinematic_names(m, eom, specs);
  return specs;
}

}  // namespace mbsc::driver
