// SPDX-License-Identifier: GPL-2.0-or-later
// ir::lower: FunctionSpec -> canonical DAG -> scheduled Program -> printed body.
#include <algorithm>
#include <cctype>
#include <memory>
#include <stdexcept>

#include "from_ginac.hpp"
#include "program_ir.hpp"

namespace mbsc::ir {

namespace {

// Identifier tokens of a C++ text ("p[kG]" -> p, kG): names a local must not shadow.
void add_identifiers(const std::string& text, std::vector<std::string>& out) {
  for (std::size_t b = 0; b < text.size();) {
    const auto ident = [&](std::size_t j) {
      return std::isalnum(static_cast<unsigned char>(text[j])) != 0 || text[j] == '_';
    };
    if (!ident(b)) {
      ++b;
      continue;
    }
    std::size_t e = b;
    while (e < text.size() && ident(e)) ++e;
    out.push_back(text.substr(b, e - b));
    b = e;
  }
}

}  // namespace

LoweredFunction lower(const FunctionSpec& spec, const std::vector<Binding>& bindings) {
  auto prog = std::make_unique<Program>();
  GinacConverter conv(prog->dag, spec, bindings);
  const int nsteps = static_cast<int>(spec.steps.size());

  // Outputs first: converting them marks the Defines and Solves they read as live.
  std::vector<NodeId> outputs;
  outputs.reserve(spec.outputs.size());
  for (const GiNaC::ex& e : spec.outputs) outputs.push_back(conv.convert(e, nsteps));

  // Solves and named Defines from last to first: converting a live one can only make
  // earlier steps live.
  std::vector<std::vector<NodeId>> solve_a(spec.steps.size()), solve_b(spec.steps.size());
  prog->define_ref_value.assign(spec.steps.size(), -1);
  for (int j = nsteps - 1; j >= 0; --j) {
    const auto& step = spec.steps[static_cast<std::size_t>(j)];
    if (const auto* d = std::get_if<Define>(&step)) {
      if (d->named && conv.define_referenced(j)) prog->define_ref_value[static_cast<std::size_t>(j)] = conv.convert(d->value, j);
      continue;
    }
    const auto& s = std::get<Solve>(step);
    if (!conv.solve_live(j)) continue;
    for (const GiNaC::ex& e : s.A) solve_a[static_cast<std::size_t>(j)].push_back(conv.convert(e, j));
    for (const GiNaC::ex& e : s.B) solve_b[static_cast<std::size_t>(j)].push_back(conv.convert(e, j));
  }

  // Roots in step order (live steps only), then the outputs.
  std::vector<std::string> define_names(spec.steps.size());
  prog->roots.reserve(spec.steps.size() + outputs.size());
  for (int j = 0; j < nsteps; ++j) {
    const auto& step = spec.steps[static_cast<std::size_t>(j)];
    if (const auto* d = std::get_if<Define>(&step)) {
      define_names[static_cast<std::size_t>(j)] = d->sym.get_name();
      const NodeId named_value = prog->define_ref_value[static_cast<std::size_t>(j)];
      if (named_value >= 0) prog->roots.push_back({Root::Kind::Define, j, named_value});
      else if (conv.define_live(j)) prog->roots.push_back({Root::Kind::Define, j, conv.define_node(j)});
    } else if (conv.solve_live(j)) {
      const auto& s = std::get<Solve>(step);
      SolveBlock block;
      block.step = j;
      block.number = static_cast<int>(prog->solves.size());
      block.n = s.n;
      block.k = s.k;
      block.label = s.label;
      block.spd = s.spd;
      block.rank = s.rank;
      block.condition = s.condition;
      block.A = std::move(solve_a[static_cast<std::size_t>(j)]);
      block.B = std::move(solve_b[static_cast<std::size_t>(j)]);
      prog->roots.push_back({Root::Kind::Solve, block.number, -1});
      prog->solves.push_back(std::move(block));
    }
  }
  for (std::size_t i = 0; i < outputs.size(); ++i)
    prog->roots.push_back({Root::Kind::Output, static_cast<int>(i), outputs[i]});
  prog->nout = static_cast<int>(outputs.size());
  if (spec.congruence) prog->out_array = "factor_";  // the factors' values; OUT is formed from them

  // Names a Define's temporary must avoid: the parameters, the loop index, std, lu_solve,
  // and every identifier the bindings' texts use.
  std::vector<std::string> reserved = {"t", "x", "u", "p", "OUT", "i", "std", "lu_solve", "chol_solve", "rcond_1norm", "solve_1x1", "chol_1x1", "lu_solve_2x2", "psd_factor", "psd_min_norm_solve", "psd_rcond"};
  if (spec.congruence)
    for (const char* n : {"factor_", "c_row_ptr_", "c_col_", "c_value_", "my_row_", "my_col_", "my_value_"}) reserved.push_back(n);
  for (const Binding& b : bindings) add_identifiers(b.cpp, reserved);

  schedule(*prog, define_names, reserved);

  LoweredFunction out;
  out.name = spec.name;
  out.doc = spec.doc;
  out.out_name = spec.out_name;
  out.out_shape = spec.out_shape;
  out.nout = prog->nout;
  out.body = print_program(*prog, out.ops);
  if (spec.congruence) {
    // The values first (into factor_), then the loop over the pattern in place of `return 0;`.
    const std::string tail = "  return 0;";
    if (out.body.size() < tail.size() || out.body.compare(out.body.size() - tail.size(), tail.size(), tail) != 0)
      throw std::logic_error("lower: a function body that does not end with its status");
    out.body.resize(out.body.size() - tail.size());
    out.body = "  double factor_[" + std::to_string(std::max(prog->nout, 1)) + "];\n" + out.body +
               congruence_loop(*spec.congruence, out.ops) + tail;
    out.nout = spec.congruence->nd * spec.congruence->nd;
  }
  out.used_args = prog->used_args;
  out.third_arg = spec.third_arg;
  return out;
}

}  // namespace mbsc::ir
