// SPDX-License-Identifier: GPL-2.0-or-later
// The implicit form of rhs_jacobian (include/mbsc/driver/residual_jacobian.hpp).
//
// One forward-mode pass over the rhs's steps with the rates held gives, per direction,
// the output's own partial derivative and the residual's; one tree sweep per direction
// turns the residual's into the rates'; an output that is a rate reads its column.
#include "mbsc/driver/residual_jacobian.hpp"

#include <map>
#include <set>

#include "mbsc/sym/forward_derivative.hpp"

namespace mbsc::driver {

namespace {

using SymbolSet = std::set<GiNaC::ex, GiNaC::ex_is_less>;

bool reads_any(const GiNaC::ex& e, const SymbolSet& symbols) {
  if (GiNaC::is_a<GiNaC::symbol>(e)) return symbols.count(e) > 0;
  for (std::size_t i = 0; i < e.nops(); ++i)
    if (reads_any(e.op(i), symbols)) return true;
  return false;
}

// The held symbols and every step's symbols that read them, directly or through steps.
SymbolSet moved_by_held(const TreeResidual& r) {
  SymbolSet moved(r.held.begin(), r.held.end());
  for (const ir::Step& step : r.steps) {
    if (const auto* d = std::get_if<ir::Define>(&step)) {
      if (!moved.count(d->sym) && reads_any(d->value, moved)) moved.insert(d->sym);
      continue;
    }
    const auto& s = std::get<ir::Solve>(step);
    bool reads = false;
    for (const auto* entries : {&s.A, &s.B})
      for (const auto& e : *entries) reads = reads || reads_any(e, moved);
    if (reads) moved.insert(s.X.begin(), s.X.end());
  }
  return moved;
}

}  // namespace

ir::FunctionSpec implicit_rhs_jacobian(const ir::FunctionSpec& rhs, const TreeResidual& residual,
                                       const std::vector<std::vector<GiNaC::symbol>>& blocks) {
  const std::size_t ns = residual.forces.size(), nr = residual.rows.size();
  std::map<GiNaC::ex, std::size_t, GiNaC::ex_is_less> rate_of;  // a speed's rate -> its speed
  for (std::size_t s = 0; s < ns; ++s) rate_of[residual.held[s]] = s;
  // Outputs: each is a rate (read from the sweep) or free of the held symbols, directly
  // and through the steps (a step that reads a held symbol, or such a step, is held too).
  const std::set<GiNaC::ex, GiNaC::ex_is_less> moved = moved_by_held(residual);
  std::vector<int> output_rate;
  ir::FunctionSpec partials{rhs.name, "", "", "", residual.steps, {}};
  partials.third_arg = rhs.third_arg;
  for (const GiNaC::ex& o : rhs.outputs) {
    const auto it = rate_of.find(o);
    output_rate.push_back(it == rate_of.end() ? -1 : static_cast<int>(it->second));
    if (it == rate_of.end() && reads_any(o, moved))
      throw sym::NotDifferentiable("an output that mixes the rates with other terms");
    partials.outputs.push_back(it == rate_of.end() ? o : GiNaC::ex(0));
  }
  const std::size_t nout = rhs.outputs.size();
  for (const auto& f : residual.forces) partials.outputs.push_back(f);
  for (const auto& r : residual.rows) partials.outputs.push_back(r);
  ir::FunctionSpec d = sym::forward_derivative(partials, blocks, residual.held);

  // Columns: the directions, block after block.
  std::vector<std::size_t> block_begin;
  std::size_t ncol = 0;
  for (const auto& b : blocks) {
    block_begin.push_back(ncol);
    ncol += b.size();
  }
  const std::size_t nrow_all = partials.outputs.size();
  auto entry = [&](std::size_t row, std::size_t col) -> const GiNaC::ex& {
    std::size_t b = 0;
    while (b + 1 < blocks.size() && col >= block_begin[b + 1]) ++b;
    return d.outputs[block_begin[b] * nrow_all + row * blocks[b].size() + (col - block_begin[b])];
  };
  std::vector<std::vector<GiNaC::ex>> forces(ns), rows(nr);
  for (std::size_t s = 0; s < ns; ++s)
    for (std::size_t j = 0; j < ncol; ++j) forces[s].push_back(entry(nout + s, j));
  for (std::size_t r = 0; r < nr; ++r)
    for (std::size_t j = 0; j < ncol; ++j) rows[r].push_back(entry(nout + ns + r, j));
  const auto rates = sym::solve_columns(*residual.tree, forces, rows, static_cast<int>(ncol), d.steps);

  ir::FunctionSpec out;
  out.third_arg = d.third_arg;
  out.third_bindings = d.third_bindings;
  out.steps = std::move(d.steps);
  for (std::size_t b = 0; b < blocks.size(); ++b)
    for (std::size_t i = 0; i < nout; ++i)
      for (std::size_t j = block_begin[b]; j < block_begin[b] + blocks[b].size(); ++j)
        out.outputs.push_back(output_rate[i] >= 0 ? rates[static_cast<std::size_t>(output_rate[i])][j] : entry(i, j));
  return out;
}

}  // namespace mbsc::driver
