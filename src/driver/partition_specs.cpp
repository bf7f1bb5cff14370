// SPDX-License-Identifier: GPL-2.0-or-later
// The functions behind run-time re-selection of the independent set: each partition's
// rhs and the conditioning of the blocks it solves (docs/formulation.md, "Re-selecting
// the independent set").
#include <fmt/format.h>

#include "mbsc/driver/pipeline.hpp"

namespace mbsc::driver {

ir::FunctionSpec conditioning_spec(const ir::FunctionSpec& rhs, const std::string& name) {
  ir::FunctionSpec f{name, "reciprocal condition number of each block the rhs solves (kBlockNames)", "rcond",
                     "kNblocks", {}, {}};
  int block = 0;
  for (const auto& step : rhs.steps) {
    f.steps.push_back(step);
    const auto* s = std::get_if<ir::Solve>(&step);
    if (!s || !s->reported || s->condition) continue;
    ir::Solve c;
    c.label = s->label;
    c.n = s->n;
    c.A = s->A;
    c.spd = s->spd;
    c.rank = s->rank;
    c.condition = true;
    // The gain columns: a block that is regular but small next to them amplifies the
    // independent rates into huge dependent ones (a 1x1 block's plain rcond is always 1).
    c.k = s->gains;
    for (int i = 0; i < s->n; ++i)
      for (int j = 0; j < s->gains; ++j) c.B.push_back(s->B[static_cast<std::size_t>(i * s->k + j)]);
    c.X = {GiNaC::symbol(fmt::format("rcond_{}", block++))};
    f.outputs.push_back(s->report_power.is_equal(1) ? GiNaC::ex(c.X[0]) : GiNaC::pow(c.X[0], s->report_power));
    f.steps.push_back(c);
  }
  return f;
}

std::vector<std::string> conditioning_labels(const ir::FunctionSpec& conditioning) {
  std::vector<std::string> labels;
  for (const auto& step : conditioning.steps)
    if (const auto* s = std::get_if<ir::Solve>(&step); s && s->condition) labels.push_back(s->label);
  return labels;
}

std::optional<PartitionSpecs> partition_specs(const model::Model& m, const sym::Eom& eom, const GenerateOptions& opt,
                                             int npart, const ir::FunctionSpec& rhs0, Diagnostics& diags) {
  PartitionSpecs out;
  for (int k = 0; k < npart; ++k) {
    // Partition 0 is the model as derived; the others are derived again with each
    // node's k-th alternative.
    std::optional<sym::Eom> alt;
    const sym::Eom* e = &eom;
    if (k > 0) {
      sym::Options o = eom.options;
      o.partition = k;
      alt = sym::derive(m, o, diags);
      if (!alt) return std::nullopt;
      e = &*alt;
    }
    std::string dofs;
    for (int s : e->independent) dofs += (dofs.empty() ? "" : ", ") + m.speeds[static_cast<std::size_t>(s)].name;
    out.names.push_back(dofs);
    ir::FunctionSpec rhs = rhs0;
    if (k > 0) {
      GenerateOptions only_rhs = opt;
      only_rhs.functions = {"rhs"};
      rhs = function_specs(m, *e, only_rhs, diags, nullptr).at(0);
      rhs.name = fmt::format("rhs_alt{}", k);
      rhs.doc = fmt::format("state derivative computed with partition {} (independent: {}); see rhs_partition", k, dofs);
      out.specs.push_back(rhs);
    }
    ir::FunctionSpec cond = conditioning_spec(rhs, k == 0 ? "conditioning" : fmt::format("conditioning_alt{}", k));
    if (k > 0) cond.doc = fmt::format("conditioning of the blocks rhs_alt{} solves", k);
    if (k == 0) out.block_labels = conditioning_labels(cond);
    out.table.rhs.push_back(rhs.name);
    out.table.conditioning.push_back(cond.outputs.empty() ? std::string() : cond.name);
    if (!cond.outputs.empty()) {
      out.specs.push_back(cond);
    } else if (k == 0) {
      // `conditioning` is in the common ABI: with no block to watch it has zero outputs.
      cond.steps.clear();
      out.specs.push_back(cond);
    }
  }
  return out;
}

}  // namespace mbsc::driver
