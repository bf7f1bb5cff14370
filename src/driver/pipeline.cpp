// SPDX-License-Identifier: GPL-2.0-or-later
#include "mbsc/driver/pipeline.hpp"

#include <fmt/format.h>

#include "mbsc/model/expr_convert.hpp"

#include <algorithm>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

#include "../ir/identifiers.hpp"
#include "mbsc/diag/activity.hpp"
#include "mbsc/diag/name_suggestions.hpp"
#include "mbsc/driver/derivative_specs.hpp"
#include "mbsc/driver/mass_matrix_factors.hpp"
#include "mbsc/driver/linear_parts.hpp"
#include "mbsc/model/build.hpp"
#include "mbsc/model/rigid3d.hpp"
#include "mbsc/parse/parse.hpp"
#include "mbsc/sym/probe.hpp"
#include "mbsc/sym/symbol_set.hpp"
#include "mbsc/sym/tidy.hpp"

namespace mbsc::driver {

const std::vector<std::string>& all_function_names() {
  static const std::vector<std::string> names = {"rhs",
                                                 "mass_matrix",
                                                 "forcing",
                                                 "inverse_dynamics",
                                                 "position_constraints",
                                                 "velocity_constraints",
                                                 "constraint_jacobian",
                                                 "position_jacobian",
                                                 "constraint_jacobian_values",
                                                 "position_jacobian_values",
                                                 "energy",
                                                 "outputs",
                                                 "full_state",
                                                 "multipliers",
                                                 "reaction_forces",
                                                 "conditioning"};
  return names;
}

std::string unknown_function_message(const std::set<std::string>& functions) {
  std::vector<std::string> known = all_function_names();
  known.push_back("linear_parts");  // on request only (driver/linear_parts.hpp)
  known.push_back("rhs_jacobian");  // on request only (driver/derivative_specs.hpp)
  known.push_back("inverse_dynamics_jacobian");
  for (const auto& name : functions)
    if (std::find(known.begin(), known.end(), name) == known.end())
      return fmt::format("--outputs: unknown function '{}'{} (known: {})", name, did_you_mean(name, known),
                         fmt::join(known, ", "));
  return "";
}

std::string text_hash(const std::string& text) {
  std::uint64_t h = 1469598103934665603ULL;
  for (unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ULL;
  }
  return fmt::format("{:016x}", h);
}

std::optional<model::Model> load_model(const std::string& path, Diagnostics& diags,
                                      const std::map<std::string, double>& overrides, const std::string& generated_name,
                                      std::vector<std::string>* sources) {
  checkpoint("reading", "the model", SourcePos{path, 0, 0}, 0, 0);
  auto file = parse::parse_file(path, diags, overrides);
  if (!file) return std::nullopt;
  auto m = model::build(*file, diags, overrides);
  if (!m) return std::nullopt;
  if (!check_model_name(*m, generated_name, diags)) return std::nullopt;
  m->source_text_hash = text_hash(file->main_source);
  if (sources) *sources = file->sources;
  return m;
}

bool check_model_name(const model::Model& m, const std::string& generated_name, Diagnostics& diags) {
  // The name becomes a C++ namespace and a file stem: `check` refuses what `generate` could not write.
  if (!generated_name.empty()) return true;  // --name, checked by the command line
  const std::string why = ir::namespace_name_problem(m.name);
  if (why.empty()) return true;
  diags.error(m.name_pos, fmt::format("model name '{}' {}; the generated code is named after it (rename the model, or "
                                      "give another name with --name)",
                                      m.name, why));
  return false;
}

namespace {

/// The substitutions finalize applies (formals by their values, frozen parameters by
/// theirs), built once per model and options rather than once per expression: finalize
/// runs on every entry of every output, and rebuilding them each time made the whole
/// pass quadratic in the number of parameters times the number of entries.
struct FinalSubstitutions {
  GiNaC::ex time;  // a fresh symbol per model: tells models apart
  std::string key;
  GiNaC::exmap formals, frozen;
};

// What identifies the substitutions: the model (its address, sizes, and its first and
// last parameter and formal, symbols no other model shares) and the frozen values. O(1)
// in the model's size but for the frozen list: finalize runs for every expression, and a
// key over every parameter made a big model's generation quadratic.
std::string substitution_key(const model::Model& m, const sym::Eom& eom) {
  std::string key = fmt::format("{}/{}/{}", static_cast<const void*>(&m), m.params.size(), m.formals.size());
  if (!m.params.empty()) key += fmt::format("/{}/{}", m.params.front().sym.gethash(), m.params.back().sym.gethash());
  if (!m.formals.empty())
    key += fmt::format("/{}/{}", m.formals.begin()->second.sym.gethash(), m.formals.rbegin()->second.sym.gethash());
  for (const auto& [name, v] : eom.options.frozen) key += fmt::format("/{}={}", name, v);
  return key;
}

const FinalSubstitutions& final_substitutions(const model::Model& m, const sym::Eom& eom) {
  thread_local FinalSubstitutions cache;
  std::string key = substitution_key(m, eom);
  if (cache.time.is_equal(m.time) && cache.key == key) return cache;
  cache.time = m.time;
  cache.key = std::move(key);
  cache.formals.clear();
  cache.frozen.clear();
  for (const auto& [name, f] : m.formals) cache.formals[f.sym] = f.value;
  for (const auto& p : m.params) {
    auto it = eom.options.frozen.find(p.name);
    if (it != eom.options.frozen.end()) cache.frozen[p.sym] = model::exact_decimal(it->second);
  }
  return cache;
}

}  // namespace

GiNaC::ex finalize(const model::Model& m, const sym::Eom& eom, const GiNaC::ex& e) {
  if (GiNaC::is_a<GiNaC::numeric>(e)) return e;  // most entries of big matrices: 0
  const FinalSubstitutions& subs = final_substitutions(m, eom);
  GiNaC::ex out = e;
  if (!subs.formals.empty()) {
    // Formals of nested instances may refer to outer formals: substitute to a fixed point.
    for (int pass = 0; pass < 16; ++pass) {
      GiNaC::ex next = out.subs(subs.formals);
      if (next.is_equal(out)) break;
      out = next;
    }
  }
  return subs.frozen.empty() ? out : out.subs(subs.frozen);
}

std::vector<ir::Binding> bindings(const model::Model& m, const sym::Eom& eom, const sym::MinimalState* minimal) {
  std::vector<ir::Binding> b;
  b.push_back({m.time, "t"});
  if (minimal) {
    // x = (kept coordinates, independent speeds z); the rest are Defines (rebuilt).
    const size_t nk = minimal->kept_coords.size();
    for (size_t i = 0; i < nk; ++i) b.push_back({m.coords[minimal->kept_coords[i]].sym, fmt::format("x[{}]", i)});
    for (size_t j = 0; j < eom.independent.size(); ++j)
      b.push_back({m.speeds[eom.independent[j]].sym, fmt::format("x[{}]", nk + j)});
  } else {
    const size_t nq = m.coords.size();
    for (size_t i = 0; i < nq; ++i) b.push_back({m.coords[i].sym, fmt::format("x[{}]", i)});
    for (size_t j = 0; j < m.speeds.size(); ++j) b.push_back({m.speeds[j].sym, fmt::format("x[{}]", nq + j)});
  }
  for (size_t k = 0; k < m.inputs.size(); ++k) b.push_back({m.inputs[k].sym, fmt::format("u[{}]", k)});
  for (size_t k = 0; k < eom.free_params.size(); ++k) b.push_back({m.params[eom.free_params[k]].sym, fmt::format("p[{}]", k), true});
  return b;
}

namespace {

/// Steps shared by rhs, mass_matrix and forcing: every node's numeric solve and e_ variable.
std::vector<ir::Step> solve_steps(const model::Model& m, const sym::Eom& eom) {
  std::vector<ir::Step> steps;
  for (const auto& step : eom.pre_steps) {
    if (const auto* d = std::get_if<ir::Define>(&step)) {
      steps.push_back(ir::Define{d->sym, sym::tidy(finalize(m, eom, d->value)), d->named});
      continue;
    }
    ir::Solve f = std::get<ir::Solve>(step);
    for (auto& e : f.A) e = sym::tidy(finalize(m, eom, e));
    for (auto& e : f.B) e = sym::tidy(finalize(m, eom, e));
    steps.push_back(f);
  }
  return steps;
}

ir::LoweredFunction undefined_energy(const model::Model& m) {
  // Kept in the common ABI for a model whose energy is not defined (a custom leaf without
  // 'kinetic'): NaN values and status 4, never a number that looks right.
  ir::LoweredFunction f;
  f.name = "energy";
  f.doc = fmt::format("energy: not defined for model '{}' (a custom leaf has no 'kinetic' term)", m.name);
  f.returns = "Returns 4 (not defined for this model), with NaN in OUT.";
  f.out_name = "E";
  f.out_shape = "3";
  f.nout = 3;
  f.body = "  OUT[0] = std::nan(\"\");\n  OUT[1] = std::nan(\"\");\n  OUT[2] = std::nan(\"\");\n  return 4;";
  return f;
}

// Whether any step reads an input (then the blocks the forcing is built on depend on u,
// and h is not h0 + H u with H = dh/du).
// The inverse dynamics computes the inputs, so none of its steps may read them. A named
// intermediate that reads an input (a joint torque turned into a body's frame, issue 26)
// is taken out of `steps` and returned as a substitution, its value written in the
// inputs and the names before it, for the forcing h to be read through. False when a
// solve reads an input: then h is not known to be affine in them.
bool inline_input_steps(const model::Model& m, std::vector<ir::Step>& steps, GiNaC::exmap& inlined) {
  auto reads = [&](const GiNaC::ex& e) {
    for (const auto& in : m.inputs)
      if (e.has(in.sym)) return true;
    return false;
  };
  auto through = [&](const GiNaC::ex& e) { return inlined.empty() ? e : e.subs(inlined, GiNaC::subs_options::no_pattern); };
  // A step kept reads the inlined names' values: their inputs may cancel in it (a
  // reaction passed from a child to its parent with the opposite sign).
  std::vector<ir::Step> kept;
  for (auto& step : steps) {
    if (auto* d = std::get_if<ir::Define>(&step)) {
      const GiNaC::ex value = through(d->value);
      if (reads(value)) {
        inlined[d->sym] = value;
        continue;
      }
      d->value = value;
      kept.push_back(std::move(step));
      continue;
    }
    auto& solve = std::get<ir::Solve>(step);
    for (auto* entries : {&solve.A, &solve.B})
      for (auto& e : *entries) {
        e = through(e);
        if (reads(e)) return false;
      }
    kept.push_back(std::move(step));
  }
  steps = std::move(kept);
  return true;
}

// inverse_dynamics(t, x, zdot, p, u): the inputs that give the independent accelerations
// zdot. The forcing is affine in the inputs, h = h0 + H u (H = dh/du, h0 = h at u = 0),
// so M zdot = h becomes H u = M zdot - h0 = r, solved in the generated code: by LU when
// there are as many inputs as degrees of freedom; with fewer, least squares through the
// normal equations H^T H u = H^T r; with more, the smallest inputs u = H^T y,
// H H^T y = r. A model whose forcing is not affine in its inputs gets a function that
// returns 4.
ir::FunctionSpec inverse_dynamics_spec(const model::Model& m, const sym::Eom& eom, std::vector<ir::Step> steps,
                                       const std::function<GiNaC::ex(const GiNaC::ex&)>& fin) {
  const int nd = eom.ndof(), nin = static_cast<int>(m.inputs.size());
  ir::FunctionSpec f{"inverse_dynamics",
                     "inputs u (kInputNames) that give the independent accelerations zdot (kDofNames): the solution of\n"
                     "H u = M zdot - h0, with M z' = h0 + H u the reduced equations (H = dh/du); by LU when kNin ==\n"
                     "kNdof; least squares when kNin < kNdof; the smallest such u when kNin > kNdof",
                     "u", "kNin", {}, {}};
  f.third_arg = "zdot";
  if (nin == 0) return f;
  if (nd == 0) {
    // Nothing to move: every input gives the (empty) motion; the smallest is zero.
    for (int k = 0; k < nin; ++k) f.outputs.push_back(0);
    return f;
  }
  f.steps = std::move(steps);
  std::vector<GiNaC::ex> h0(static_cast<std::size_t>(nd)), H(static_cast<std::size_t>(nd * nin));
  GiNaC::exmap zero_inputs;
  for (const auto& in : m.inputs) zero_inputs[in.sym] = 0;
  GiNaC::exmap inlined;
  bool affine = inline_input_steps(m, f.steps, inlined);
  for (int i = 0; i < nd && affine; ++i) {
    const GiNaC::ex h = fin(inlined.empty() ? eom.h(i, 0) : eom.h(i, 0).subs(inlined, GiNaC::subs_options::no_pattern));
    h0[static_cast<std::size_t>(i)] = h.subs(zero_inputs);
    for (int k = 0; k < nin; ++k) {
      const GiNaC::ex d = fin(h.diff(m.inputs[static_cast<std::size_t>(k)].sym));
      for (const auto& in : m.inputs) affine = affine && !d.has(in.sym);
      H[static_cast<std::size_t>(i * nin + k)] = d;
    }
  }
  if (!affine) {
    f.steps.clear();
    f.outputs.assign(static_cast<std::size_t>(nin), GiNaC::ex(0));
    f.undefined_reason = fmt::format("the forcing of model '{}' is not affine in its inputs", m.name);
    return f;
  }
  // r = M zdot - h0, with zdot the independent speeds' rates (bound to zdot[i]).
  std::vector<GiNaC::ex> r(static_cast<std::size_t>(nd));
  for (int i = 0; i < nd; ++i) {
    GiNaC::ex sum = -h0[static_cast<std::size_t>(i)];
    for (int j = 0; j < nd; ++j) sum += fin(eom.M(i, j)) * m.speed_dots[static_cast<std::size_t>(eom.independent[static_cast<std::size_t>(j)])];
    r[static_cast<std::size_t>(i)] = sum;
  }
  // Inputs that act one each on the independent speeds (H = I: a torque at each
  // independent joint) need no solve.
  bool identity = nin == nd;
  for (int i = 0; i < nd && identity; ++i)
    for (int k = 0; k < nin; ++k) identity = identity && H[static_cast<std::size_t>(i * nin + k)].is_equal(GiNaC::ex(i == k ? 1 : 0));
  if (identity) {
    f.outputs = r;
    return f;
  }
  ir::Solve solve;
  solve.label = "inputs: H u = M zdot - h0";
  solve.reported = false;
  solve.n = std::min(nin, nd);
  solve.k = 1;
  for (int k = 0; k < solve.n; ++k) solve.X.push_back(GiNaC::symbol(fmt::format("u_{}", k)));
  if (nin == nd) {
    solve.A = H;
    solve.B = r;
  } else if (nin > nd) {
    // More inputs than degrees of freedom: the smallest, u = H^T y with H H^T y = r.
    for (int a = 0; a < nd; ++a) {
      for (int b = 0; b < nd; ++b) {
        GiNaC::ex sum = 0;
        for (int k = 0; k < nin; ++k) sum += H[static_cast<std::size_t>(a * nin + k)] * H[static_cast<std::size_t>(b * nin + k)];
        solve.A.push_back(sum);
      }
      solve.B.push_back(r[static_cast<std::size_t>(a)]);
    }
    f.steps.push_back(solve);
    for (int k = 0; k < nin; ++k) {
      GiNaC::ex sum = 0;
      for (int i = 0; i < nd; ++i) sum += H[static_cast<std::size_t>(i * nin + k)] * solve.X[static_cast<std::size_t>(i)];
      f.outputs.push_back(sum);
    }
    return f;
  } else {
    for (int a = 0; a < nin; ++a) {
      for (int b = 0; b < nin; ++b) {
        GiNaC::ex sum = 0;
        for (int i = 0; i < nd; ++i) sum += H[static_cast<std::size_t>(i * nin + a)] * H[static_cast<std::size_t>(i * nin + b)];
        solve.A.push_back(sum);
      }
      GiNaC::ex sum = 0;
      for (int i = 0; i < nd; ++i) sum += H[static_cast<std::size_t>(i * nin + a)] * r[static_cast<std::size_t>(i)];
      solve.B.push_back(sum);
    }
  }
  f.steps.push_back(solve);
  for (const auto& x : solve.X) f.outputs.push_back(x);
  return f;
}

// A function this model cannot compute (FunctionSpec::undefined_reason): NaN outputs and
// status 4, never a number that looks right.
ir::LoweredFunction undefined_function(const ir::FunctionSpec& spec) {
  ir::LoweredFunction f;
  f.name = spec.name;
  f.doc = spec.name + ": not defined here (" + spec.undefined_reason + ")";
  f.returns = "Returns 4 (not defined for this model), with NaN in OUT.";
  f.out_name = spec.out_name;
  f.out_shape = spec.out_shape;
  f.third_arg = spec.third_arg;
  f.nout = static_cast<int>(spec.outputs.size());
  f.body = fmt::format("  for (int i = 0; i < {}; ++i) OUT[i] = std::nan(\"\");\n  return 4;", f.nout);
  return f;
}

}  // namespace

namespace {

/// The defines in an order where each comes after the defines its value reads, otherwise
/// in the given order (the first ready one each time: deterministic). A cycle, which the
/// callers do not make, keeps the rest in the given order.
std::vector<ir::Define> dependency_order(std::vector<ir::Define> defines) {
  const std::size_t n = defines.size();
  std::map<GiNaC::ex, std::size_t, GiNaC::ex_is_less> index;
  for (std::size_t i = 0; i < n; ++i) index.emplace(defines[i].sym, i);
  std::vector<std::vector<std::size_t>> reads(n);
  bool ordered = true;
  for (std::size_t i = 0; i < n; ++i) {
    std::set<std::size_t> in;
    for (GiNaC::const_preorder_iterator it = defines[i].value.preorder_begin(); it != defines[i].value.preorder_end(); ++it) {
      if (!GiNaC::is_a<GiNaC::symbol>(*it)) continue;
      const auto at = index.find(*it);
      if (at != index.end() && at->second != i) in.insert(at->second);
    }
    reads[i].assign(in.begin(), in.end());
    if (!in.empty() && *in.rbegin() > i) ordered = false;
  }
  if (ordered) return defines;
  std::vector<bool> done(n, false);
  std::vector<ir::Define> out;
  out.reserve(n);
  while (out.size() < n) {
    std::size_t pick = n;
    for (std::size_t i = 0; i < n && pick == n; ++i)
      if (!done[i] && std::all_of(reads[i].begin(), reads[i].end(), [&](std::size_t r) { return done[r]; })) pick = i;
    if (pick == n)  // a cycle: the rest as given
      for (std::size_t i = 0; i < n && pick == n; ++i)
        if (!done[i]) pick = i;
    done[pick] = true;
    out.push_back(std::move(defines[pick]));
  }
  return out;
}

}  // namespace

namespace {

// The residual of the system the tree recursion solved, with the multipliers defined
// (the implicit form of rhs_jacobian); nullopt when the recursion with multipliers fails.
std::optional<TreeResidual> tree_residual(const model::Model& m, const sym::Eom& eom, const sym::KktSystem& sys,
                                          const std::vector<GiNaC::ex>& c, const std::vector<GiNaC::symbol>& lambda,
                                          const std::function<std::vector<ir::Step>(std::vector<ir::Step>)>& with_rebuild,
                                          const std::function<GiNaC::ex(const GiNaC::ex&)>& fin) {
  std::string why;
  const auto tree = rhs_solve_steps(m, eom, sys, c, lambda, /*with_multipliers=*/true, why);
  if (!tree || !tree->tree) return std::nullopt;
  TreeResidual r;
  r.steps = with_rebuild(sparse_steps_reported(*tree, GiNaC::numeric(1, 3)));
  r.tree = tree->tree;
  const std::size_t ns = m.speeds.size();
  for (std::size_t s = 0; s < ns; ++s) {
    GiNaC::ex f = fin(sys.hy[s]);
    for (const auto& e : sys.My[s]) f -= fin(e.value) * m.speed_dots[static_cast<std::size_t>(e.col)];
    r.forces.push_back(f);
  }
  for (std::size_t row = 0; row < sys.A.size(); ++row) {
    GiNaC::ex g = fin(c[row]);
    for (const auto& e : sys.A[row]) {
      const GiNaC::ex a = fin(e.value);
      g -= a * m.speed_dots[static_cast<std::size_t>(e.col)];
      r.forces[static_cast<std::size_t>(e.col)] += a * lambda[row];
    }
    r.rows.push_back(g);
  }
  for (const auto& s : m.speed_dots) r.held.push_back(s);
  for (const auto& l : lambda) r.held.push_back(l);
  return r;
}

}  // namespace

std::vector<ir::FunctionSpec> function_specs(const model::Model& m, const sym::Eom& eom, const GenerateOptions& opt,
                                             Diagnostics& diags, const sym::MinimalState* minimal,
                                             std::optional<TreeResidual>* residual) {
  std::vector<ir::FunctionSpec> specs;
  // (The commands check the names before any work; this is for other callers.)
  if (const std::string unknown = unknown_function_message(opt.functions); !unknown.empty()) {
    diags.error(SourcePos{m.name_pos.file, 0, 0}, unknown);
    return {};
  }
  auto wanted = [&](const std::string& n) { return opt.functions.empty() || opt.functions.count(n); };
  const int nd = eom.ndof();
  auto fin = [&](const GiNaC::ex& e) { return sym::tidy(finalize(m, eom, e)); };

  // Every function of the common ABI is emitted whatever the model holds (README, "The
  // generated ABI"): one with nothing to compute has zero outputs and no steps.
  // --state minimal: coordinates and speeds outside the state come first in every function.
  std::vector<ir::Step> rebuild;
  {
    // Kinematic names (named body rotations, docs/formulation.md) and the rebuilt
    // coordinates first, each after what it reads: a rebuilt mass centre reads names, and
    // a name reads joint angles, one of which a position constraint may rebuild.
    std::vector<ir::Define> defines;
    for (const auto& k : m.kinematic_names) defines.push_back(ir::Define{k.sym, fin(k.value), true});
    if (minimal)
      for (const auto& d : minimal->coords) defines.push_back(ir::Define{d.sym, fin(d.value), true});
    for (auto& d : dependency_order(std::move(defines))) rebuild.push_back(std::move(d));
  }
  if (minimal) {
    for (const auto& step : minimal->speeds) {
      if (const auto* d = std::get_if<ir::Define>(&step)) {
        rebuild.push_back(ir::Define{d->sym, fin(d->value), true});
        continue;
      }
      ir::Solve solve = std::get<ir::Solve>(step);
      for (auto& e : solve.A) e = fin(e);
      for (auto& e : solve.B) e = fin(e);
      rebuild.push_back(solve);
    }
  }
  auto with_rebuild = [&](std::vector<ir::Step> steps) {
    steps.insert(steps.begin(), rebuild.begin(), rebuild.end());
    return steps;
  };

  // The expressions of every function are finalized (formals, frozen values) and tidied here.
  std::size_t prepared = 0;
  auto preparing = [&](const char* name) {
    checkpoint("preparing", fmt::format("function '{}'", name), m.name_pos, prepared++, all_function_names().size());
  };
  if (wanted("rhs")) {
    preparing("rhs");
    const std::string doc =
        minimal ? "state derivative: xdot = (kept q0 rates, z rates)" : "state derivative: xdot = (q0 rates, q1 rates)";
    std::vector<GiNaC::ex> outputs;
    if (minimal) {
      for (int c : minimal->kept_coords) outputs.push_back(fin(m.coord_rates[c]));
      for (int s : eom.independent) outputs.push_back(m.speed_dots[s]);
    } else {
      for (const auto& r : m.coord_rates) outputs.push_back(fin(r));
      for (const auto& s : m.speed_dots) outputs.push_back(s);
    }
    // The reduced equations M z' = h solved by Cholesky (dense, the modular method's own form).
    std::optional<ir::FunctionSpec> dense_built;  // built once: auto may count it, then keep it
    auto dense = [&]() -> ir::FunctionSpec {
      if (dense_built) return *dense_built;
      ir::FunctionSpec f{"rhs", doc, "xdot", "kNx", with_rebuild(solve_steps(m, eom)), outputs};
      ir::Solve final_solve;
      final_solve.label = "reduced mass matrix M z' = h";
      final_solve.spd = eom.mass_matrix_spd;
      final_solve.n = nd;
      final_solve.k = 1;
      for (int i = 0; i < nd; ++i) {
        for (int j = 0; j < nd; ++j) final_solve.A.push_back(fin(eom.M(i, j)));
        final_solve.B.push_back(fin(eom.h(i, 0)));
        final_solve.X.push_back(m.speed_dots[eom.independent[i]]);
      }
      // `conditioning` reports it unless it is constant (a constant M cannot degrade).
      final_solve.reported = false;
      for (const auto& e : final_solve.A) final_solve.reported = final_solve.reported || !sym::is_state_free(e, m);
      if (nd > 0) f.steps.push_back(final_solve);
      if (!minimal)
        for (const auto& d : eom.top_down) f.steps.push_back(ir::Define{d.sym, fin(d.value)});
      dense_built = f;
      return f;
    };
    // Or the same accelerations from the system over all speeds, A q1' = -b, eliminated
    // in a tree order (O(N); the two agree to rounding, tests/numeric/sparse_rhs_test.cpp).
    std::optional<ir::FunctionSpec> chosen;
    if (!redundancy_allows_sparse(m, eom, opt, diags)) return {};
    if (opt.solver != Solver::Dense && nd > 0 && eom.redundant_on_manifold.empty()) {
      const sym::KktSystem sys = sym::kkt_system(m);
      std::vector<GiNaC::ex> c;
      std::vector<GiNaC::symbol> lambda;
      for (std::size_t r = 0; r < sys.b.size(); ++r) {
        c.push_back(-sys.b[r]);
        lambda.emplace_back(fmt::format("lambda_{}", r));
      }
      std::string why;
      const auto sparse = rhs_solve_steps(m, eom, sys, c, lambda, /*with_multipliers=*/false, why);
      if (!sparse && opt.solver == Solver::Sparse) {
        diags.error(m.name_pos, fmt::format("--solver sparse: model '{}' cannot be solved in a tree order: {}", m.name, why));
        return {};
      }
      if (sparse) {
        // The power only on the elimination's own pivots, before the rebuilt minimal
        // state's dependent-speed solves join: those keep their own measure. A speeds-first
        // loop's pivots fall like the cube of what the complement's dependent blocks' do.
        ir::FunctionSpec f{"rhs", doc, "xdot", "kNx", with_rebuild(sparse_steps_reported(*sparse, GiNaC::numeric(1, 3))),
                           outputs};
        if (prefer_sparse(m, opt, *sparse, f, dense, bindings(m, eom, minimal))) chosen = std::move(f);
        if (chosen && sparse->tree && residual && m.frictions.empty())
          *residual = tree_residual(m, eom, sys, c, lambda, with_rebuild, fin);
      }
    }
    if (chosen) specs.push_back(std::move(*chosen));
    else specs.push_back(dense());
  }
  if (wanted("mass_matrix")) {
    preparing("mass_matrix");
    // From its factors when asked, or (auto) when the symbolic M would be big; the
    // symbolic form otherwise (and where the root has no such factors).
    ir::FunctionSpec f{"mass_matrix", "reduced mass matrix M (row-major) over the independent speeds kDofNames",
                       "M", "kNdof*kNdof", nd > 0 ? with_rebuild(solve_steps(m, eom)) : std::vector<ir::Step>{}, {}};
    const sym::NodeResult& root = eom.nodes[static_cast<std::size_t>(m.root())];
    const bool factors = nd > 0 && (opt.mass_matrix == MassMatrixForm::Factors ||
                                    (opt.mass_matrix == MassMatrixForm::Auto &&
                                     std::max(congruence_products(root.C.get(), root.My), static_cast<long>(nd) * nd) >
                                         kFactorFormMinWork));
    if (!(factors && form_mass_matrix_from_factors(f, m, eom, fin)))
      for (int i = 0; i < nd; ++i)
        for (int j = 0; j < nd; ++j) f.outputs.push_back(fin(eom.M(i, j)));
    specs.push_back(std::move(f));
  }
  if (wanted("forcing")) {
    preparing("forcing");
    ir::FunctionSpec f{"forcing", "forcing h with M z' = h (z = independent speeds)", "h", "kNdof",
                       nd > 0 ? with_rebuild(solve_steps(m, eom)) : std::vector<ir::Step>{}, {}};
    for (int i = 0; i < nd; ++i) f.outputs.push_back(fin(eom.h(i, 0)));
    specs.push_back(std::move(f));
  }
  if (wanted("inverse_dynamics")) {
    preparing("inverse_dynamics");
    specs.push_back(inverse_dynamics_spec(m, eom, nd > 0 ? with_rebuild(solve_steps(m, eom)) : std::vector<ir::Step>{}, fin));
  }
  std::vector<GiNaC::ex> pos, vel;
  for (const auto& c : m.constraints)
    if (c.level == model::Constraint::Level::Position) pos.push_back(fin(c.residual));
  for (const auto& v : sym::velocity_residuals(m)) vel.push_back(fin(v));
  // The rebuilt state only where something reads it.
  auto rebuild_for = [&](bool any) { return any ? rebuild : std::vector<ir::Step>{}; };
  if (wanted("position_constraints")) {
    preparing("position_constraints");
    ir::FunctionSpec f{"position_constraints", "position constraint residuals (kPositionConstraintNames)", "r",
                       "kNposc", rebuild_for(!pos.empty()), pos};
    specs.push_back(std::move(f));
  }
  if (wanted("velocity_constraints")) {
    preparing("velocity_constraints");
    ir::FunctionSpec f{"velocity_constraints", "velocity-level residuals of all constraints (kConstraintNames)", "r", "kNc",
                       rebuild_for(!vel.empty()), vel};
    specs.push_back(std::move(f));
  }
  // The Jacobians are over every speed / every coordinate (the full layout, kFullStateNames):
  // with --state minimal they are evaluated at the rebuilt full state.
  if (wanted("constraint_jacobian") || wanted("constraint_jacobian_values")) {  // the values: add_sparse_jacobians
    preparing("constraint_jacobian");
    ir::FunctionSpec f{"constraint_jacobian", "A = d(velocity residuals)/d(q1) over all speeds, row-major kNc x kNuFull",
                       "A", "kNc*kNuFull", rebuild_for(!vel.empty()), {}};
    f.outputs.reserve(vel.size() * m.speeds.size());
    for (const auto& v : vel) {
      const sym::SymbolSet in_v(v);  // most entries are zero: no diff for those
      for (const auto& s : m.speeds) f.outputs.push_back(in_v.diff(v, s.sym));
    }
    specs.push_back(std::move(f));
  }
  if (wanted("position_jacobian") || wanted("position_jacobian_values")) {
    preparing("position_jacobian");
    ir::FunctionSpec f{"position_jacobian",
                       "d(position residuals)/d(q0) over all coordinates, row-major kNposc x kNqFull (for assembly)", "J",
                       "kNposc*kNqFull", rebuild_for(!pos.empty()), {}};
    f.outputs.reserve(pos.size() * m.coords.size());
    // Partial derivatives by the coordinates must see through the kinematic names (named
    // body rotations, docs/formulation.md): the rows are written out first.
    const GiNaC::exmap names = model::kinematic_name_values(m);
    for (const auto& named : pos) {
      const GiNaC::ex g = names.empty() ? named : named.subs(names, GiNaC::subs_options::no_pattern);
      const sym::SymbolSet in_g(g);
      for (const auto& q : m.coords) f.outputs.push_back(in_g.diff(g, q.sym));
    }
    specs.push_back(std::move(f));
  }
  if (wanted("energy") && eom.has_energy) {
    preparing("energy");
    ir::FunctionSpec f{"energy", "energy: {kinetic T, potential V, total T + V}", "E", "3", rebuild, {}};
    f.outputs = {fin(eom.kinetic), fin(eom.potential), fin(eom.kinetic + eom.potential)};
    specs.push_back(std::move(f));
  } else if (!opt.functions.empty() && opt.functions.count("energy") && !eom.has_energy) {
    diags.error(SourcePos{m.name_pos.file, 0, 0}, fmt::format("--outputs energy: model '{}' has a custom leaf without a 'kinetic' term, so its "
                                         "energy is not defined", m.name));
  }
  if (wanted("outputs")) {
    preparing("outputs");
    ir::FunctionSpec f{"outputs", "named outputs (kOutputNames)", "y", "kNy", rebuild_for(!m.outputs.empty()), {}};
    for (const auto& o : m.outputs) f.outputs.push_back(fin(o.value));
    specs.push_back(std::move(f));
  }
  if (opt.linear_parts || opt.functions.count("linear_parts")) {
    preparing("linear_parts");
    specs.push_back(linear_parts_spec(m, fin, rebuild));
  }
  if (wanted("full_state")) {
    preparing("full_state");
    ir::FunctionSpec f{"full_state",
                       minimal ? "the full state (all q0, all q1; kFullStateNames) rebuilt from the minimal one"
                               : "the full state (all q0, all q1; kFullStateNames): a copy of x in the full layout",
                       "x_full", "kNxFull", rebuild, {}};
    for (const auto& q : m.coords) f.outputs.push_back(q.sym);
    for (const auto& u : m.speeds) f.outputs.push_back(u.sym);
    specs.push_back(std::move(f));
  }
  return specs;
}

void define_kinematic_names(const model::Model& m, const sym::Eom& eom, std::vector<ir::FunctionSpec>& specs) {
  // The names (named body rotations, docs/formulation.md) first, in definition order;
  // the lowering drops the ones a function does not read.
  if (m.kinematic_names.empty()) return;
  const auto fin = [&](const GiNaC::ex& e) { return sym::tidy(finalize(m, eom, e)); };
  std::vector<ir::Step> names;
  for (const auto& k : m.kinematic_names) names.push_back(ir::Define{k.sym, fin(k.value), true});
  for (auto& f : specs) {
    bool has = false;
    for (const auto& step : f.steps)
      if (const auto* d = std::get_if<ir::Define>(&step); d && d->sym.is_equal(m.kinematic_names.front().sym)) has = true;
    if (has || !f.undefined_reason.empty()) continue;
    f.steps.insert(f.steps.begin(), names.begin(), names.end());
  }
}

std::optional<emit::GeneratedModel> generate(const model::Model& m, const sym::Eom& eom, const GenerateOptions& opt,
                                             Diagnostics& diags) {
  std::optional<sym::MinimalState> minimal;
  if (opt.minimal_state) {
    minimal = sym::minimal_state(m, eom, diags);
    if (!minimal) return std::nullopt;
  }
  const sym::MinimalState* ms = minimal ? &*minimal : nullptr;
  if (opt.multipliers && ms) {
    diags.error(SourcePos{m.name_pos.file, 0, 0}, "--formulation multipliers integrates the full state (all coordinates and speeds); "
                             "drop --state minimal");
    return std::nullopt;
  }
  const BaumgarteGains gains;
  std::vector<ir::FunctionSpec> specs;
  std::optional<TreeResidual> residual;  // filled by a tree's rhs: the implicit rhs_jacobian
  // A derivative is taken of its function: built here even when only the derivative is asked.
  const auto asked = [&](const std::string& n) {
    return opt.derivatives || (n == "rhs_jacobian" && opt.rhs_jacobian) || opt.functions.count(n) > 0;
  };
  std::set<std::string> primal_only_for_derivative;
  GenerateOptions built = opt;
  for (const auto& [function, derivative] : {std::pair<const char*, const char*>{"rhs", "rhs_jacobian"},
                                             {"inverse_dynamics", "inverse_dynamics_jacobian"}})
    if (!opt.functions.empty() && asked(derivative) && !opt.functions.count(function)) {
      built.functions.insert(function);
      primal_only_for_derivative.insert(function);
    }
  if (opt.multipliers) {
    // The functions both formulations share, the reduced M z' = h of the declared
    // independent set included (the common ABI).
    GenerateOptions rest = built;
    if (rest.functions.empty())
      for (const auto& n : all_function_names()) rest.functions.insert(n);
    for (const char* own : {"rhs", "multipliers", "reaction_forces", "conditioning"}) rest.functions.erase(own);
    if (opt.functions.empty() && !eom.has_energy) rest.functions.erase("energy");  // undefined_energy below
    specs = multiplier_specs(m, eom, built, gains, diags);
    if (rest.functions.empty() && rest.linear_parts) rest.functions = {"linear_parts"};  // (empty would mean all)
    if (!rest.functions.empty())
      for (auto& f : function_specs(m, eom, rest, diags, nullptr)) specs.push_back(std::move(f));
  } else {
    for (const char* own : {"multipliers", "reaction_forces"})
      if (opt.functions.count(own))
        diags.error(SourcePos{m.name_pos.file, 0, 0}, fmt::format("--outputs {}: only --formulation multipliers has multipliers", own));
    // The residual only where the implicit rhs_jacobian is taken (it reruns the recursion).
    if (!diags.has_errors()) specs = function_specs(m, eom, built, diags, ms, asked("rhs_jacobian") ? &residual : nullptr);
  }
  if (diags.has_errors()) return std::nullopt;
  std::optional<std::vector<ir::Step>> friction_closure;
  close_friction(m, eom, opt.multipliers, gains, specs, friction_closure);
  add_derivative_specs(m, eom, ms, asked("rhs_jacobian"), asked("inverse_dynamics_jacobian"), opt.rhs_jacobian_max_ops,
                       residual ? &*residual : nullptr, specs);
  specs.erase(std::remove_if(specs.begin(), specs.end(),
                             [&](const ir::FunctionSpec& f) { return primal_only_for_derivative.count(f.name) > 0; }),
              specs.end());
  const std::vector<SparseJacobian> sparse = add_sparse_jacobians(m, opt, specs);

  // Conditioning of the solved blocks, and the partitions the run time can switch
  // between (docs/formulation.md "Re-selecting the independent set").
  int npart = m.partition_count();
  if (npart > 1 && opt.multipliers) {
    // The multipliers formulation has no independent set to switch.
    for (const auto& node : m.nodes)
      if (!node.alternative_pos.empty())
        diags.warning(node.alternative_pos.front(), "'alternative' independent sets do not apply to --formulation "
                                                    "multipliers (it has no independent set)");
    npart = 1;
  }
  if (npart > 1 && ms) {
    // The minimal state is made of one set's speeds: only the declared set is generated.
    for (const auto& node : m.nodes)
      if (!node.alternative_pos.empty())
        diags.warning(node.alternative_pos.front(), "'alternative' independent sets are ignored with --state minimal (its "
                                                    "state is made of one set's speeds); use --state full to switch sets");
    npart = 1;
  }
  auto wanted = [&](const char* n) { return opt.functions.empty() || opt.functions.count(n); };
  std::optional<PartitionSpecs> partitions;
  if (wanted("conditioning") && wanted("rhs")) {
    const auto rhs = std::find_if(specs.begin(), specs.end(), [](const ir::FunctionSpec& f) { return f.name == "rhs"; });
    if (rhs == specs.end()) throw std::logic_error("generate: rhs was requested but not built");
    partitions = partition_specs(m, eom, opt, npart, *rhs, diags);
    if (!partitions) return std::nullopt;
    specs.insert(specs.end(), partitions->specs.begin(), partitions->specs.end());
    close_friction(m, eom, opt.multipliers, gains, specs, friction_closure);
  }

  // Kinematic names: every function that does not define them yet (conditioning,
  // partitions) gets them first.
  define_kinematic_names(m, eom, specs);

  emit::GeneratedModel g;
  g.name = opt.name.empty() ? m.name : opt.name;
  g.source_hash = m.source_text_hash;
  g.tool_version = MBSC_VERSION;
  for (const auto& [name, v] : opt.frozen) g.banner_notes.push_back(fmt::format("frozen parameter: {} = {}", name, emit::format_double(v)));
  for (const auto& [name, v] : m.structural)
    if (!opt.frozen.count(name))
      g.banner_notes.push_back(fmt::format("structural parameter (loop bound or index): {} = {}", name, emit::format_double(v)));
  if (ms) g.banner_notes.push_back("minimal state: x = (kept coordinates, independent speeds)");
  if (opt.multipliers)
    g.banner_notes.push_back("formulation: Lagrange multipliers with Baumgarte stabilization (p[] ends with alpha, beta)");
  const long nq_full = static_cast<long>(m.coords.size()), nu_full = static_cast<long>(m.speeds.size());
  const long nq = ms ? static_cast<long>(ms->kept_coords.size()) : nq_full;
  const long nu = ms ? static_cast<long>(eom.ndof()) : nu_full;
  long nposc = 0;
  for (const auto& c : m.constraints) nposc += c.level == model::Constraint::Level::Position;
  g.int_constants = {{"kNq", nq},
                     {"kNu", nu},
                     {"kNx", nq + nu},
                     {"kNdof", eom.ndof()},
                     {"kNin", static_cast<long>(m.inputs.size())},
                     {"kNp", static_cast<long>(eom.free_params.size()) + (opt.multipliers ? 2 : 0)},
                     {"kNc", static_cast<long>(m.constraints.size())},
                     {"kNposc", nposc},
                     {"kNy", static_cast<long>(m.outputs.size())}};
  std::vector<std::string> state, full_state, dof, inputs, params, cons, outs;
  for (const auto& q : m.coords) full_state.push_back(q.name);
  for (const auto& u : m.speeds) full_state.push_back(u.name);
  if (ms) {
    for (int c : ms->kept_coords) state.push_back(m.coords[c].name);
    for (int s : eom.independent) state.push_back(m.speeds[s].name);
  } else {
    state = full_state;
  }
  for (int s : eom.independent) dof.push_back(m.speeds[s].name);
  for (const auto& in : m.inputs) inputs.push_back(in.name);
  std::vector<double> defaults;
  for (int k : eom.free_params) {
    params.push_back(m.params[k].name);
    defaults.push_back(m.param_defaults[k]);
  }
  std::vector<std::string> position_cons;
  for (const auto& c : m.constraints) {
    cons.push_back(c.name);
    if (c.level == model::Constraint::Level::Position) position_cons.push_back(c.name);
  }
  for (const auto& o : m.outputs) outs.push_back(o.name);
  if (opt.multipliers) {
    params.push_back(gains.alpha.get_name());
    params.push_back(gains.beta.get_name());
    defaults.push_back(BaumgarteGains::kDefault);
    defaults.push_back(BaumgarteGains::kDefault);
  }
  g.name_lists = {{"kStateNames", state},   {"kDofNames", dof},         {"kInputNames", inputs},
                  {"kParamNames", params},  {"kConstraintNames", cons}, {"kPositionConstraintNames", position_cons},
                  {"kOutputNames", outs}};
  g.double_lists = {{"kParamDefaults", defaults}};
  // The full layout (what full_state returns, what the Jacobians are taken over), in
  // every model: equal to kNq, kNu, kNx with --state full.
  g.int_constants.push_back({"kNqFull", nq_full});
  g.int_constants.push_back({"kNuFull", nu_full});
  g.int_constants.push_back({"kNxFull", nq_full + nu_full});
  g.name_lists.push_back({"kFullStateNames", full_state});
  if (opt.linear_parts || opt.functions.count("linear_parts")) {
    g.int_constants.push_back({"kLinearPartsSize", linear_parts_size(m)});
    g.int_constants.push_back({"kLinearWSize", static_cast<long>(m.inputs.size() + m.speeds.size() + m.constraints.size())});
    // Every unit quaternion of the full layout (kNquaternions counts those the state keeps).
    g.int_constants.push_back({"kLinearQuaternions", static_cast<long>(unit_quaternion_coords(m).size())});
  }
  // The CSR patterns of the Jacobians (constraint_jacobian_values, position_jacobian_values).
  for (const SparseJacobian& sj : sparse) {
    g.int_constants.push_back({sj.prefix + "Nnz", static_cast<long>(sj.col_idx.size())});
    g.int_lists.push_back({sj.prefix + "RowPtr", sj.row_ptr});
    g.int_lists.push_back({sj.prefix + "ColIdx", sj.col_idx});
  }
  if (partitions) {
    g.int_constants.push_back({"kNpartitions", npart});
    g.int_constants.push_back({"kNblocks", static_cast<long>(partitions->block_labels.size())});
    g.name_lists.push_back({"kPartitionNames", partitions->names});
    g.name_lists.push_back({"kBlockNames", partitions->block_labels});
    g.partitions = partitions->table;
  }
  // The unit quaternions of rigid3d bodies as state indices, four per body (e0 first):
  // what an app hands to SimulationOptions::unit_quaternions. A quaternion is listed when
  // its four components are in the state (--state minimal may keep fewer).
  std::vector<long> quaternions;
  for (const auto& names : model::rigid3d::unit_quaternion_names(m)) {
    std::vector<long> at;
    for (const auto& n : names) {
      const auto it = std::find(state.begin(), state.end(), n);
      if (it != state.end()) at.push_back(static_cast<long>(it - state.begin()));
    }
    if (at.size() == 4) quaternions.insert(quaternions.end(), at.begin(), at.end());
  }
  g.int_constants.push_back({"kNquaternions", static_cast<long>(quaternions.size() / 4)});
  g.int_lists.push_back({"kQuaternionIndices", quaternions});
  auto binds = bindings(m, eom, ms);
  if (opt.multipliers) {
    const std::size_t np = eom.free_params.size();
    binds.push_back({gains.alpha, fmt::format("p[{}]", np), true});
    binds.push_back({gains.beta, fmt::format("p[{}]", np + 1), true});
  }
  // Lowered last to first, each taken out of the list and freed once lowered: rhs, the
  // largest lowering, then runs with the other functions' expressions already gone (a big
  // model's dense Jacobians and M need not outlive their own lowering). Each lowering is
  // independent of the others, so the order does not change the code.
  std::vector<std::optional<ir::LoweredFunction>> lowered(specs.size());
  for (std::size_t i = specs.size(); i-- > 0;) {
    const ir::FunctionSpec spec = std::move(specs[i]);
    specs.pop_back();
    checkpoint("generating", fmt::format("function '{}'", spec.name), m.name_pos, lowered.size() - 1 - i, lowered.size());
    if (!spec.undefined_reason.empty()) {
      lowered[i] = undefined_function(spec);
      continue;
    }
    std::vector<ir::Binding> spec_binds = binds;
    if (!spec.third_bindings.empty()) {  // w replaces u
      spec_binds.erase(std::remove_if(spec_binds.begin(), spec_binds.end(),
                                      [](const ir::Binding& b) { return b.cpp.rfind("u[", 0) == 0; }),
                       spec_binds.end());
      spec_binds.insert(spec_binds.end(), spec.third_bindings.begin(), spec.third_bindings.end());
    }
    if (spec.third_arg == "zdot")  // the independent speeds' rates, given
      for (std::size_t k = 0; k < eom.independent.size(); ++k)
        spec_binds.push_back({m.speed_dots[static_cast<std::size_t>(eom.independent[k])], fmt::format("zdot[{}]", k)});
    try {
      lowered[i] = ir::lower(spec, spec_binds);
      if (spec.name == "rhs_jacobian" && opt.rhs_jacobian_max_ops > 0 && lowered[i]->ops.total() > opt.rhs_jacobian_max_ops) {
        ir::FunctionSpec capped = spec;
        capped.undefined_reason = fmt::format("{} operations, more than the {} this compile allows", lowered[i]->ops.total(),
                                              opt.rhs_jacobian_max_ops);
        lowered[i] = undefined_function(capped);
      }
    } catch (const std::exception& e) {
      diags.error(m.name_pos, fmt::format("cannot generate function '{}' of model '{}': {}", spec.name, m.name, e.what()));
      return std::nullopt;
    }
  }
  for (auto& f : lowered) g.functions.push_back(std::move(*f));
  if (opt.functions.empty() && !eom.has_energy) g.functions.push_back(undefined_energy(m));
  return g;
}

}  // namespace mbsc::driver
