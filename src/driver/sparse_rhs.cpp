// SPDX-License-Identifier: GPL-2.0-or-later
// The O(N) right-hand side in the pipeline: the sparse elimination's steps prepared for
// emission, and the choice between them and the dense solve (include/mbsc/driver/pipeline.hpp).
#include "mbsc/driver/pipeline.hpp"
#include "mbsc/sym/probe.hpp"
#include "mbsc/sym/tidy.hpp"

namespace mbsc::driver {

Solver solver_named(const std::string& name) {
  return name == "dense" ? Solver::Dense : name == "sparse" ? Solver::Sparse : Solver::Auto;
}

std::optional<sym::KktElimination> sparse_solve_steps(const model::Model& m, const sym::Eom& eom,
                                                      const sym::KktSystem& sys, const std::vector<GiNaC::ex>& c,
                                                      const std::vector<GiNaC::symbol>& lambda, Solver solver,
                                                      std::string& why) {
  const std::function<GiNaC::ex(const GiNaC::ex&)> fin = [&](const GiNaC::ex& e) { return sym::tidy(finalize(m, eom, e)); };
  // The generic probe point (pseudo-random state, parameter values): a pivot that is
  // definite there is definite almost everywhere.
  const sym::Probe probe(m, eom.param_values);
  return sym::eliminate_kkt(m, sys, c, lambda, fin, probe, solver == Solver::Sparse, why);
}

bool prefer_sparse(const model::Model& m, const GenerateOptions& opt, const sym::KktElimination& sparse,
                   const ir::FunctionSpec& sparse_rhs, const std::function<ir::FunctionSpec()>& dense,
                   const std::vector<ir::Binding>& binds) {
  if (opt.solver != Solver::Auto) return opt.solver == Solver::Sparse;
  // Closed loops stay dense: a tree order's pivots could vanish where a loop's partial
  // chain folds (a toggle). The speeds-first order is as regular as the dense forms, but
  // its pivots are many small blocks whose condition numbers (1 for a 1x1 block) do not
  // warn `conditioning`'s readers of a coming rank loss as the dense block's does (the
  // 40-window parallelogram chain under --continuation stops at a flat pose with it):
  // it is taken when asked for (--solver sparse).
  if (!sparse.forest) return false;
  if (m.speeds.size() > 64) return true;
  return ir::lower(sparse_rhs, binds).ops.total() < ir::lower(dense(), binds).ops.total();
}

}  // namespace mbsc::driver
