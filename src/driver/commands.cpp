// SPDX-License-Identifier: GPL-2.0-or-later
#include "mbsc/driver/commands.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "../ir/identifiers.hpp"
#include "mbsc/diag/activity.hpp"
#include "mbsc/diag/name_suggestions.hpp"
#include "mbsc/driver/depfile.hpp"
#include "mbsc/driver/output_folder.hpp"
#include "mbsc/driver/pipeline.hpp"
#include "mbsc/driver/staged_file.hpp"
#include "mbsc/emit/python_module_names.hpp"
#include "mbsc/parse/parse.hpp"
#include "mbsc/print/latex_layout.hpp"
#include "mbsc/print/latex_names.hpp"
#include "mbsc/print/print_matrix.hpp"

namespace mbsc::driver {
namespace fs = std::filesystem;

bool parse_assignment(const std::string& text, std::string& name, double& value, std::string& why) {
  why = "expects name=value with a finite number";
  auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0) return false;
  name = text.substr(0, eq);
  const std::string v = text.substr(eq + 1);
  if (v.empty() || v.find_first_not_of("0123456789+-.eE") != std::string::npos) return false;  // no nan, inf, hex
  char* end = nullptr;
  value = std::strtod(v.c_str(), &end);
  if (!end || *end != '\0') return false;
  // The range a model's literals have, with their message: 1e400 is too large for a
  // double, 1e-320 too small (subnormal: finite, but not a double's full precision).
  const std::string literal = v.substr(v[0] == '+' || v[0] == '-' ? 1 : 0);
  if (const char* out_of_range = parse::literal_out_of_double_range(literal)) {
    why = fmt::format("number '{}' {}", literal, out_of_range);
    return false;
  }
  return true;
}

const std::vector<std::string>& print_items() {
  static const std::vector<std::string> items = {"eom", "M", "h", "invariants", "rates", "A", "B", "C", "S", "f", "fbar"};
  return items;
}

namespace {

/// Option values that need no model are checked before any work: "mbsc: error: ..." on
/// `err` and false for the first unknown --what item or --outputs function.
bool known_option_values(const std::vector<std::string>& what, const std::set<std::string>& functions,
                         std::ostream& err) {
  for (const auto& w : what)
    if (std::find(print_items().begin(), print_items().end(), w) == print_items().end()) {
      err << fmt::format("mbsc: error: --what: unknown item '{}'{} (known: {})\n", printable(w),
                         did_you_mean(w, print_items()), fmt::join(print_items(), " "));
      return false;
    }
  if (const std::string unknown = unknown_function_message(functions); !unknown.empty()) {
    err << "mbsc: error: " << printable(unknown) << "\n";
    return false;
  }
  return true;
}

std::string speed_names(const model::Model& m, const std::vector<int>& speeds) {
  std::vector<std::string> v;
  for (int s : speeds) v.push_back(m.speeds[s].name);
  return fmt::format("{}", fmt::join(v, ", "));
}

/// Where `check` says the reduced mass matrix of a model with massless bodies was
/// checked: at a generic configuration (parameter values, a generic state) and at the
/// reference configuration (coordinates, speeds and t at 0).
std::string where_positive_definite(const sym::Eom& eom) {
  using sym::MassAtReference;
  if (!eom.mass_matrix_spd) return "NOT positive definite at a generic configuration";
  const std::string generic = "positive definite at a generic configuration";
  switch (eom.mass_at_reference) {
    case MassAtReference::PositiveDefinite: return generic + " and at the reference configuration";
    case MassAtReference::SingularMassless:
      return generic + " but singular at the reference configuration, where massless bodies carry a motion (see the warning)";
    case MassAtReference::SingularOtherwise:
      return generic + " but singular at the reference configuration, in a motion that moves no massless body";
    case MassAtReference::NotEvaluated:
      return generic + " (the reference configuration was not checked: the constraints cannot be solved there)";
    case MassAtReference::NotChecked: break;
  }
  return generic;
}

/// Loads and derives into `diags`. Returns false (exit 1) on user errors. The
/// `alternative` independent sets are derived too, so their mistakes are reported here;
/// `partitions` (when given) receives each partition's independent speeds, `sources` the
/// files read.
bool load_and_derive(const std::string& path, const std::map<std::string, double>& frozen, std::optional<model::Model>& m,
                     std::optional<sym::Eom>& eom, Diagnostics& diags, std::vector<std::string>* partitions = nullptr,
                     const std::string& generated_name = "", std::vector<std::string>* sources = nullptr) {
  m = load_model(path, diags, frozen, generated_name, sources);
  if (m) {
    sym::Options opt;
    opt.frozen = frozen;
    eom = sym::derive(*m, opt, diags);
    if (eom && partitions) partitions->push_back(speed_names(*m, eom->independent));
    for (int k = 1; eom && k < m->partition_count(); ++k) {
      checkpoint("deriving", fmt::format("the independent set of alternative {}", k), m->nodes.back().pos,
                 static_cast<std::size_t>(k), static_cast<std::size_t>(m->partition_count()));
      opt.partition = k;
      auto alt = sym::derive(*m, opt, diags);
      if (alt && partitions) partitions->push_back(speed_names(*m, alt->independent));
    }
  }
  return m && eom && !diags.has_errors();
}

/// Runs `work` under a WorkMonitor: a spent budget becomes an error in `diags`. The
/// monitor is stopped (its progress line cleared) before the diagnostics are printed.
template <class Work>
bool monitored(const WorkArgs& args, Diagnostics& diags, std::ostream& err, Work&& work) {
  bool ok = false;
  {
    WorkMonitor monitor(args.budget, args.progress);
    try {
      ok = work();
    } catch (const BudgetExceeded& b) {
      diags.error(b.pos, b.message);
      ok = false;
    }
    monitor.stop();
  }
  err << diags.format();
  return ok && !diags.has_errors();
}

}  // namespace

int run_check(const CheckArgs& a, std::ostream& out, std::ostream& err) {
  std::optional<model::Model> m;
  std::optional<sym::Eom> eom;
  std::vector<std::string> partitions;
  Diagnostics diags;
  if (!monitored(a.work, diags, err, [&] {
        if (!load_and_derive(a.model, a.frozen, m, eom, diags, &partitions)) return false;
        // What generate would refuse, check refuses: generate's work with its default
        // options, short of writing (a constant the lowering cannot hold, ...).
        GenerateOptions opt;
        opt.frozen = a.frozen;
        return generate(*m, *eom, opt, diags).has_value();
      }))
    return 1;
  out << fmt::format("model {}: {} degree(s) of freedom\n", m->name, eom->ndof());
  out << fmt::format("  coordinates q0 ({}):", m->coords.size());
  for (const auto& q : m->coords) out << " " << q.name;
  out << fmt::format("\n  speeds q1 ({}):", m->speeds.size());
  for (const auto& u : m->speeds) out << " " << u.name;
  out << fmt::format("\n  parameters ({}), inputs ({}), constraints ({}), outputs ({})\n", m->params.size(), m->inputs.size(),
                     m->constraints.size(), m->outputs.size() + (m->output_energy ? 1 : 0));
  out << fmt::format("  independent speeds: {}\n", speed_names(*m, eom->independent));
  if (!m->constraints.empty())
    out << fmt::format("  ranks: at a generic configuration and {}\n",
                       eom->start_missing.empty()
                           ? "at the initial state (assembled at generation time) and two configurations near it"
                           : "not on the mechanism (" + eom->start_missing + ")");
  if (!eom->redundant_on_manifold.empty()) {
    std::vector<std::string> rows;
    for (int c : eom->redundant_on_manifold) rows.push_back(m->constraints[static_cast<std::size_t>(c)].name);
    out << fmt::format("  redundant on the mechanism: {} (independent at a generic configuration, dependent wherever the "
                       "constraints hold); {} degree(s) of freedom; the dependent speeds are solved in the least-squares "
                       "sense, and the multipliers formulation reports the minimum-norm reactions (those of redundant rows "
                       "are not unique)\n",
                       fmt::join(rows, ", "), eom->ndof());
  }
  if (!eom->massless.empty())
    out << fmt::format("  massless bodies: {}; the reduced mass matrix is {}\n", fmt::join(eom->massless, ", "),
                       where_positive_definite(*eom));
  if (partitions.size() > 1)
    out << fmt::format("  partitions for run-time re-selection (rhs_partition): {}\n", fmt::join(partitions, " | "));
  out << "subsystem tree (leaves to root):\n";
  for (size_t n = 0; n < m->nodes.size(); ++n) {
    const auto& node = m->nodes[n];
    const auto& r = eom->nodes[n];
    int depth = 0;
    for (int p = node.parent; p >= 0; p = m->nodes[p].parent) ++depth;
    std::string kind = node.kind == model::LeafKind::Node ? (node.component.empty() ? "node" : "component " + node.component)
                                                          : model::to_string(node.kind);
    out << fmt::format("  {}{} [{}]: {} variable(s) in y, {} constraint(s), rank {}, {} dof", std::string(2 * depth, ' '),
                       m->label(static_cast<int>(n)), kind, r.y.size(), r.rows.size(), r.rank, r.independent.size());
    if (!r.rows.empty())
      out << fmt::format("; independent: {}; complement: {}", speed_names(*m, r.independent),
                         r.symbolic_complement ? "symbolic"
                         : r.numeric_core < static_cast<int>(r.dependent.size())
                             ? fmt::format("{} rates by state-free pivots, the other {} by {} in generated code",
                                           r.dependent.size() - static_cast<std::size_t>(r.numeric_core), r.numeric_core,
                                           r.redundant.empty() ? "LU" : "least squares")
                             : std::string(r.redundant.empty() ? "numeric (LU in generated code)"
                                                               : "numeric (least squares in generated code)"));
    if (r.from_component_cache) out << "; reused from the first instance of its component";
    out << "\n";
  }
  return 0;
}

namespace {

/// Two names of the model that print as one symbol in LaTeX (th1 and theta1 are both
/// \theta_{1}) would read as one variable: a warning at the second, naming the first.
void warn_same_latex_symbols(const model::Model& m, Diagnostics& diags) {
  std::map<std::string, std::string> seen;  // symbol -> the first name printed so
  for (const auto* vars : {&m.params, &m.inputs, &m.coords, &m.speeds})
    for (const auto& v : *vars) {
      const std::string symbol = print::latex_symbol(v.name, m.latex_symbols);
      const auto [it, fresh] = seen.emplace(symbol, v.name);
      if (!fresh)
        diags.warning(v.pos, fmt::format("'{}' and '{}' both print as {} in LaTeX; give one of them its own symbol "
                                         "with latex {} \"...\"",
                                         it->second, v.name, symbol, v.name));
    }
}

/// The text `print` writes, into `text`; false (errors in diags) otherwise.
bool print_text(const PrintArgs& a, const model::Model& m, const sym::Eom& eom, std::string& text, Diagnostics& diags) {
  const SourcePos file{a.model, 0, 0};
  int node = m.root();
  if (!a.node.empty()) {
    node = -1;
    for (size_t n = 0; n < m.nodes.size(); ++n)
      if (m.nodes[n].name == a.node) node = static_cast<int>(n);
    if (node < 0) {
      diags.error(file, fmt::format("model '{}' has no subsystem '{}' (--node)", m.name, a.node));
      return false;
    }
  }
  if (a.stats) {
    GenerateOptions opt;
    opt.frozen = a.frozen;
    opt.functions = a.functions;
    opt.minimal_state = a.minimal_state;
    opt.solver = solver_named(a.solver);
    auto g = generate(m, eom, opt, diags);
    if (!g) return false;
    text += fmt::format("{:<22} {:>8} {:>8} {:>8} {:>8} {:>11} {:>9}\n", "function", "adds", "muls", "divs", "calls",
                        "solve_flops", "total");
    for (const auto& f : g->functions)
      text += fmt::format("{:<22} {:>8} {:>8} {:>8} {:>8} {:>11} {:>9}\n", f.name, f.ops.adds, f.ops.muls, f.ops.divs,
                          f.ops.calls, f.ops.solve_flops, f.ops.total());
    if (a.standalone) text = print::latex_document(m.name, a.node, "\\begin{verbatim}\n" + text + "\\end{verbatim}\n");
    return true;
  }
  if (a.latex || a.standalone) warn_same_latex_symbols(m, diags);
  // `--what ''` (an empty variable in a script) is a mistake, not a request for the default.
  if (a.what_given && a.what.empty()) {
    diags.error(file, "--what: no item given (known: eom M h invariants rates A B C S f fbar); leave --what out for the "
                      "default set");
    return false;
  }
  std::vector<std::string> what = a.what;
  // What users look for first (M, h, M z' = h, the constraints), then the method's letters.
  if (what.empty()) what = node == m.root() ? std::vector<std::string>{"M", "h", "eom", "invariants", "rates", "B", "C", "fbar"}
                                            : std::vector<std::string>{"M", "h", "eom", "invariants", "B", "C", "fbar"};
  try {
    text += print::print_node(m, eom, node, what, a.latex || a.standalone, a.expand);
  } catch (const std::invalid_argument& e) {
    diags.error(file, e.what());
    return false;
  }
  if (a.standalone) text = print::latex_document(m.name, a.node, text);
  return true;
}

}  // namespace

int run_print(const PrintArgs& a, std::ostream& out, std::ostream& err) {
  if (!known_option_values(a.stats ? std::vector<std::string>{} : a.what, a.functions, err)) return 1;
  std::optional<model::Model> m;
  std::optional<sym::Eom> eom;
  std::string text;
  Diagnostics diags;
  const bool ok = monitored(a.work, diags, err, [&] {
    if (!load_and_derive(a.model, a.frozen, m, eom, diags)) return false;
    return print_text(a, *m, *eom, text, diags);
  });
  if (!ok) return 1;
  out << text;
  return 0;
}

namespace {

/// Stages the depfile of `generate`: every output file in `final_dir` depends on every
/// source file. False (with `error`) when it cannot be written, would overwrite an
/// output or a source, or lies inside OUT/NAME. Run after the output folder's checks.
bool stage_depfile(const std::string& path, const std::string& final_dir, const std::vector<OutputFile>& outputs,
                   const std::vector<std::string>& sources, StagedFile& staged, std::string& error) {
  std::vector<std::string> targets;
  for (const auto& f : outputs) targets.push_back((fs::path(final_dir) / f.name).string());
  // The same file by path, or by inode when both exist (a hard link has a path of its own).
  auto same_file = [](const fs::path& x, const fs::path& y) {
    std::error_code ec;
    if (fs::exists(x, ec) && fs::exists(y, ec) && fs::equivalent(x, y, ec) && !ec) return true;
    const fs::path cx = fs::weakly_canonical(fs::absolute(x, ec), ec);
    return !ec && cx == fs::weakly_canonical(fs::absolute(y, ec), ec) && !ec;
  };
  std::vector<std::string> written = targets;
  written.push_back((fs::path(final_dir) / kMarkerName).string());
  for (const auto& w : written)
    if (same_file(path, w)) {
      error = fmt::format("mbsc: error: --depfile '{}' is one of the files generate writes; name another file",
                          printable(path));
      return false;
    }
  for (const auto& s : sources)
    if (same_file(path, s)) {
      error = fmt::format("mbsc: error: --depfile '{}' is the model or a file it includes; name another file",
                          printable(path));
      return false;
    }
  // OUT/NAME is mbsc's: a depfile there would be staged inside the folder before its
  // checks, and belongs to no run's list of outputs.
  {
    std::error_code ec;
    const fs::path dir = fs::weakly_canonical(fs::absolute(final_dir, ec), ec);
    const fs::path file = fs::weakly_canonical(fs::absolute(path, ec), ec);
    if (!ec) {
      const auto [d, f] = std::mismatch(dir.begin(), dir.end(), file.begin(), file.end());
      if (d == dir.end() && f != file.end()) {
        error = fmt::format("mbsc: error: --depfile '{}' is inside the output folder '{}', which mbsc "
                            "creates and owns; name a file outside it (e.g. '{}.d')",
                            printable(path), printable(final_dir), printable(final_dir));
        return false;
      }
    }
  }
  std::string text;
  return depfile_text(targets, sources, text, error) && staged.stage(path, text, "--depfile", error);
}

/// The functions `generate --batch` asks for (GenerateArgs::batch), each emitted by the
/// model; "" or the message that names one it does not emit.
std::string batched_functions(const GenerateArgs& a, const emit::GeneratedModel& g, std::vector<std::string>& batched) {
  std::vector<std::string> emitted;
  for (const auto& f : g.functions) emitted.push_back(f.name);
  auto is_emitted = [&](const std::string& name) { return std::find(emitted.begin(), emitted.end(), name) != emitted.end(); };
  batched.clear();
  if (!a.batch) {  // rhs, unless --outputs chose the functions (then only what --batch names)
    if (a.functions.empty() && is_emitted("rhs")) batched.push_back("rhs");
    return "";
  }
  const bool none = std::find(a.batch->begin(), a.batch->end(), "none") != a.batch->end();
  if (none && a.batch->size() > 1) return "--batch: 'none' stands alone (it asks for no batched functions)";
  for (const auto& name : *a.batch) {
    if (name == "none") continue;
    if (!is_emitted(name))
      return fmt::format("--batch: '{}' is not a function this generate emits{} (emitted: {}; add it to --outputs "
                         "where it is one)",
                         name, did_you_mean(name, emitted), fmt::join(emitted, ", "));
    if (std::find(batched.begin(), batched.end(), name) == batched.end()) batched.push_back(name);
  }
  return "";
}

}  // namespace

int run_generate(const GenerateArgs& a, std::ostream& out, std::ostream& err) {
  if (!known_option_values({}, a.functions, err)) return 1;
  if (!a.name.empty()) {
    if (const std::string why = ir::namespace_name_problem(a.name); !why.empty()) {
      err << fmt::format("mbsc: error: --name '{}' {}; it names the generated C++ namespace and files\n",
                         printable(a.name), why);
      return 1;
    }
  }
  std::optional<model::Model> m;
  std::optional<sym::Eom> eom;
  std::optional<emit::GeneratedModel> g;
  emit::GeneratedFiles files;
  std::vector<std::string> sources;  // the model and the files it includes (--depfile)
  std::string python;
  Diagnostics diags;
  bool internal = false;
  std::string batch_error;  // --batch names a function not emitted
  const bool ok = monitored(a.work, diags, err, [&] {
    if (!load_and_derive(a.model, a.frozen, m, eom, diags, nullptr, a.name, &sources)) return false;
    GenerateOptions opt;
    opt.functions = a.functions;
    opt.multipliers = a.multipliers;
    opt.linear_parts = a.linear_parts;
    opt.derivatives = a.derivatives;
    opt.rhs_jacobian = a.rhs_jacobian;
    opt.rhs_jacobian_max_ops = a.rhs_jacobian_max_ops;
    opt.minimal_state = a.minimal_state;
    opt.solver = solver_named(a.solver);
    opt.mass_matrix = mass_matrix_form_named(a.mass_matrix);
    opt.frozen = a.frozen;
    opt.name = a.name;
    g = generate(*m, *eom, opt, diags);
    if (!g) return false;
    if (const std::string why = batched_functions(a, *g, g->batched); !why.empty()) {
      batch_error = why;
      return false;
    }
    if (a.python && emit::is_python_module_name(g->name))
      diags.warning(a.name.empty() ? m->name_pos : SourcePos{m->name_pos.file, 0, 0},
                    fmt::format("'{0}' is also the name of {1}: `import {0}` may load that module instead of {0}.py, "
                                "or {0}.py may hide it from the code that needs it; name the generated files otherwise "
                                "with --name (e.g. --name {0}_model)",
                                g->name, g->name == "numpy" ? "numpy, which the generated module imports"
                                                            : "a module of Python's standard library"));
    checkpoint("emitting", "the C++ files", m->name_pos, 0, 0);
    try {
      files = emit::emit(*g);
      if (a.python) python = emit::emit_python(*g);
    } catch (const std::exception& e) {
      diags.error(m->name_pos, std::string("internal error while emitting: ") + e.what());
      internal = true;
      return false;
    }
    return true;
  });
  if (!batch_error.empty()) err << "mbsc: error: " << printable(batch_error) << "\n";
  if (!ok) return internal ? 2 : 1;
  // The symbolic work is over (and its monitor stopped): write, all or nothing.
  const std::string& name = g->name;
  std::vector<OutputFile> outputs = {{name + ".hpp", files.header}, {name + ".cpp", files.source}};
  if (a.python) outputs.push_back({name + ".py", python});
  if (a.extra_outputs)
    if (const int code = a.extra_outputs({*m, sources, *g, files}, outputs, err); code != 0) return code;
  const std::string final_dir = (fs::path(a.out_dir.empty() ? "." : a.out_dir) / name).string();
  std::string error;
  StagedFile depfile;  // staged once the output folder's checks pass, moved into place once it is written
  if (!a.depfile.empty() && (!check_output_folder(a.out_dir, name, outputs, a.force, error) ||
                             !stage_depfile(a.depfile, final_dir, outputs, sources, depfile, error))) {
    err << error << "\n";
    return 1;
  }
  if (!write_output_folder(a.out_dir, name, outputs, a.force, error) || (!a.depfile.empty() && !depfile.commit(error))) {
    err << error << "\n";
    return 1;
  }
  if (a.work.quiet) return 0;  // --quiet: nothing on success (mbsc_add_model's builds)
  std::string written;  // "a.hpp and a.cpp", "a.hpp, a.cpp and a.py"
  for (std::size_t i = 0; i < outputs.size(); ++i)
    written += (i == 0 ? "" : i + 1 == outputs.size() ? " and " : ", ") + outputs[i].name;
  out << fmt::format("wrote {}/{} ({} dof;", printable(final_dir), written, eom->ndof());
  for (const auto& f : g->functions) out << fmt::format(" {} {} ops", f.name, f.ops.total());
  out << ")\n";
  return 0;
}

}  // namespace mbsc::driver
