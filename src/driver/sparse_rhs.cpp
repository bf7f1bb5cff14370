// SPDX-License-Identifier: GPL-2.0-or-later
// The O(N) right-hand side in the pipeline: the sparse elimination's steps prepared for
// emission, and the choice between them and the dense solve (include/mbsc/driver/pipeline.hpp).
#include <fmt/format.h>

#include "mbsc/driver/pipeline.hpp"
#include "mbsc/sym/probe.hpp"
#include "mbsc/sym/tidy.hpp"
#include "mbsc/sym/tree_recursion.hpp"

namespace mbsc::driver {

Solver solver_named(const std::string& name) {
  return name == "dense" ? Solver::Dense : name == "sparse" ? Solver::Sparse : Solver::Auto;
}

std::optional<sym::KktElimination> sparse_solve_steps(const model::Model& m, const sym::Eom& eom,
                                                      const sym::KktSystem& sys, const std::vector<GiNaC::ex>& c,
                                                      const std::vector<GiNaC::symbol>& lambda, std::string& why) {
  const std::function<GiNaC::ex(const GiNaC::ex&)> fin = [&](const GiNaC::ex& e) { return sym::tidy(finalize(m, eom, e)); };
  // The generic probe point (pseudo-random state, parameter values): a pivot that is
  // definite there is definite almost everywhere.
  const sym::Probe probe(m, eom.param_values);
  // A loop is eliminated speeds first whenever it can be (forced or auto alike): that
  // order is as regular as the dense forms, so auto may take it too.
  return sym::eliminate_kkt(m, sys, c, lambda, fin, probe, /*loops_speeds_first=*/true, why);
}

std::optional<sym::KktElimination> rhs_solve_steps(const model::Model& m, const sym::Eom& eom, const sym::KktSystem& sys,
                                                   const std::vector<GiNaC::ex>& c, const std::vector<GiNaC::symbol>& lambda,
                                                   bool with_multipliers, std::string& why) {
  const std::function<GiNaC::ex(const GiNaC::ex&)> fin = [&](const GiNaC::ex& e) { return sym::tidy(finalize(m, eom, e)); };
  const sym::Probe probe(m, eom.param_values);
  std::string not_a_tree;
  if (auto tree = sym::tree_recursion(m, sys, c, fin, probe, with_multipliers ? &lambda : nullptr, not_a_tree)) return tree;
  auto sparse = sparse_solve_steps(m, eom, sys, c, lambda, why);
  if (!sparse) why += fmt::format(" (not a tree recursion either: {})", not_a_tree);
  return sparse;
}

std::vector<ir::Step> sparse_steps_reported(const sym::KktElimination& sparse, const GiNaC::numeric& power) {
  // A loop eliminated speeds first: its constraint pivots are blocks of A My^-1 A^T, whose
  // conditioning falls faster than the dense forms' (ir::Solve::report_power). Its speed
  // pivots are not reported; a tree's or a forced fewest-neighbours order's pivots keep
  // their own measure (they vanish like the distance).
  std::vector<ir::Step> steps = sparse.steps;
  if (sparse.speeds_first)
    for (auto& step : steps)
      if (auto* s = std::get_if<ir::Solve>(&step); s && s->reported) s->report_power = power;
  return steps;
}

namespace {

/// What auto compares: the operations, each multiply-add of a numeric solve weighted
/// kSolveFlopWeight times a straight-line operation. A solve helper's flop runs through
/// loops over stack arrays with pivot checks; callgrind (docs/benchmarks.md, "The solver
/// auto's cost model") measures 3-5 instructions per solve flop against 1.5-2 per
/// straight-line operation, and the sparse form trades straight-line work for many small
/// solves (the Whipple bicycle: 9 050 operations sparse, 9 721 dense, yet 25 % more
/// instructions sparse).
constexpr long kSolveFlopWeight = 4;

long run_time_cost(const ir::OpCount& ops) { return ops.total() + (kSolveFlopWeight - 1) * ops.solve_flops; }

}  // namespace

bool redundancy_allows_sparse(const model::Model& m, const sym::Eom& eom, const GenerateOptions& opt, Diagnostics& diags) {
  if (eom.redundant_on_manifold.empty() || opt.solver != Solver::Sparse) return true;
  diags.error(m.name_pos, fmt::format("--solver sparse: model '{}' has constraint rows that are redundant on the mechanism "
                                      "('{}' first), which leave a tree order's pivots singular; use --solver dense or auto",
                                      m.name, m.constraints[static_cast<std::size_t>(eom.redundant_on_manifold.front())].name));
  return false;
}

bool prefer_sparse(const model::Model& m, const GenerateOptions& opt, const sym::KktElimination& sparse,
                   const ir::FunctionSpec& sparse_rhs, const std::function<ir::FunctionSpec()>& dense,
                   const std::vector<ir::Binding>& binds) {
  if (opt.solver != Solver::Auto) return opt.solver == Solver::Sparse;
  // A closed loop eliminated in the fewest-neighbours order stays dense: a pivot that
  // joins the loop's two open parts vanishes where they fold (crank parallel to rocker),
  // where the mechanism itself is regular. Speeds first, every constraint pivot is a
  // Schur complement of -A My^-1 A^T: it fails only where A loses rank, where the dense
  // forms fail too (docs/formulation.md, "O(N) right-hand side").
  if (!sparse.regular()) return false;
  if (m.speeds.size() > 64) return true;
  // Counted before a friction force is closed (the same steps join either rhs): it is a
  // given value here, like an input.
  std::vector<ir::Binding> counted = binds;
  for (std::size_t k = 0; k < m.frictions.size(); ++k) counted.push_back({m.frictions[k].force, fmt::format("friction_{}", k), false});
  // A form that cannot be lowered (a constant beyond a double) is not preferred; if the
  // other fails too, generate reports it where it lowers the chosen one.
  long sparse_cost = 0, dense_cost = 0;
  try {
    sparse_cost = run_time_cost(ir::lower(sparse_rhs, counted).ops);
  } catch (const std::exception&) {
    return false;
  }
  try {
    dense_cost = run_time_cost(ir::lower(dense(), counted).ops);
  } catch (const std::exception&) {
    return true;
  }
  return sparse_cost < dense_cost;
}

}  // namespace mbsc::driver
