// SPDX-License-Identifier: GPL-2.0-or-later
#include "mbsc/driver/commands.hpp"

#include <fmt/format.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "mbsc/driver/pipeline.hpp"
#include "mbsc/driver/print_matrix.hpp"

namespace mbsc::driver {
namespace fs = std::filesystem;

bool parse_assignment(const std::string& text, std::string& name, double& value) {
  auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0) return false;
  name = text.substr(0, eq);
  const std::string v = text.substr(eq + 1);
  char* end = nullptr;
  value = std::strtod(v.c_str(), &end);
  return !v.empty() && end && *end == '\0';
}

namespace {

std::string speed_names(const model::Model& m, const std::vector<int>& speeds) {
  std::vector<std::string> v;
  for (int s : speeds) v.push_back(m.speeds[s].name);
  return fmt::format("{}", fmt::join(v, ", "));
}

/// Loads and derives; prints diagnostics. Returns false (exit 1) on user errors. The
/// `alternative` independent sets are derived too, so their mistakes are reported here;
/// `partitions` (when given) receives each partition's independent speeds.
bool load_and_derive(const std::string& path, const std::map<std::string, double>& frozen, std::optional<model::Model>& m,
                     std::optional<sym::Eom>& eom, std::ostream& err, std::vector<std::string>* partitions = nullptr) {
  Diagnostics diags;
  m = load_model(path, diags, frozen);
  if (m) {
    sym::Options opt;
    opt.frozen = frozen;
    eom = sym::derive(*m, opt, diags);
    if (eom && partitions) partitions->push_back(speed_names(*m, eom->independent));
    for (int k = 1; eom && k < m->partition_count(); ++k) {
      opt.partition = k;
      auto alt = sym::derive(*m, opt, diags);
      if (alt && partitions) partitions->push_back(speed_names(*m, alt->independent));
    }
  }
  err << diags.format();
  return m && eom && !diags.has_errors();
}

}  // namespace

int run_check(const CheckArgs& a, std::ostream& out, std::ostream& err) {
  std::optional<model::Model> m;
  std::optional<sym::Eom> eom;
  std::vector<std::string> partitions;
  if (!load_and_derive(a.model, {}, m, eom, err, &partitions)) return 1;
  out << fmt::format("model {}: {} degree(s) of freedom\n", m->name, eom->ndof());
  out << fmt::format("  coordinates q0 ({}):", m->coords.size());
  for (const auto& q : m->coords) out << " " << q.name;
  out << fmt::format("\n  speeds q1 ({}):", m->speeds.size());
  for (const auto& u : m->speeds) out << " " << u.name;
  out << fmt::format("\n  parameters ({}), inputs ({}), constraints ({}), outputs ({})\n", m->params.size(), m->inputs.size(),
                     m->constraints.size(), m->outputs.size() + (m->output_energy ? 1 : 0));
  out << fmt::format("  independent speeds: {}\n", speed_names(*m, eom->independent));
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
                             ? fmt::format("{} rates by state-free pivots, the other {} by LU in generated code",
                                           r.dependent.size() - static_cast<std::size_t>(r.numeric_core), r.numeric_core)
                             : std::string("numeric (LU in generated code)"));
    if (r.from_component_cache) out << "; reused from the first instance of its component";
    out << "\n";
  }
  return 0;
}

int run_print(const PrintArgs& a, std::ostream& out, std::ostream& err) {
  std::optional<model::Model> m;
  std::optional<sym::Eom> eom;
  if (!load_and_derive(a.model, a.frozen, m, eom, err)) return 1;
  int node = m->root();
  if (!a.node.empty()) {
    node = -1;
    for (size_t n = 0; n < m->nodes.size(); ++n)
      if (m->nodes[n].name == a.node) node = static_cast<int>(n);
    if (node < 0) {
      err << fmt::format("mbsc: error: model '{}' has no subsystem '{}'\n", m->name, a.node);
      return 1;
    }
  }
  if (a.stats) {
    GenerateOptions opt;
    opt.frozen = a.frozen;
    opt.functions = a.functions;
    opt.minimal_state = a.minimal_state;
    Diagnostics diags;
    auto g = generate(*m, *eom, opt, diags);
    err << diags.format();
    if (!g) return 1;
    out << fmt::format("{:<22} {:>8} {:>8} {:>8} {:>8} {:>11} {:>9}\n", "function", "adds", "muls", "divs", "calls", "solve_flops",
                       "total");
    for (const auto& f : g->functions)
      out << fmt::format("{:<22} {:>8} {:>8} {:>8} {:>8} {:>11} {:>9}\n", f.name, f.ops.adds, f.ops.muls, f.ops.divs,
                         f.ops.calls, f.ops.solve_flops, f.ops.total());
    return 0;
  }
  std::vector<std::string> what = a.what;
  if (what.empty()) what = node == m->root() ? std::vector<std::string>{"rates", "B", "C", "fbar", "M", "h"}
                                             : std::vector<std::string>{"B", "C", "fbar"};
  try {
    out << print_node(*m, *eom, node, what, a.latex);
  } catch (const std::invalid_argument& e) {
    err << "mbsc: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}

int run_generate(const GenerateArgs& a, std::ostream& out, std::ostream& err) {
  std::optional<model::Model> m;
  std::optional<sym::Eom> eom;
  if (!load_and_derive(a.model, a.frozen, m, eom, err)) return 1;
  Diagnostics diags;
  GenerateOptions opt;
  opt.functions = a.functions;
  opt.multipliers = a.multipliers;
  opt.minimal_state = a.minimal_state;
  opt.frozen = a.frozen;
  opt.name = a.name;
  auto g = generate(*m, *eom, opt, diags);
  err << diags.format();
  if (!g) return 1;
  emit::GeneratedFiles files;
  try {
    files = emit::emit(*g);
  } catch (const std::exception& e) {
    err << "mbsc: internal error while emitting: " << e.what() << "\n";
    return 2;
  }
  // Write into a fresh temporary folder, then move it into place: nothing half-written.
  const fs::path dir = fs::path(a.out_dir.empty() ? "." : a.out_dir);
  const std::string& name = g->name;
  const fs::path final_dir = dir / name;
  const fs::path tmp_dir = dir / ("." + name + ".tmp");
  std::error_code ec;
  fs::create_directories(dir, ec);
  fs::remove_all(tmp_dir, ec);
  fs::create_directories(tmp_dir, ec);
  if (ec) {
    err << fmt::format("mbsc: error: cannot create folder '{}': {}\n", tmp_dir.string(), ec.message());
    return 1;
  }
  auto write = [&](const fs::path& p, const std::string& text) {
    std::ofstream f(p, std::ios::binary);
    f << text;
    return static_cast<bool>(f);
  };
  if (!write(tmp_dir / (name + ".hpp"), files.header) || !write(tmp_dir / (name + ".cpp"), files.source)) {
    fs::remove_all(tmp_dir, ec);
    err << fmt::format("mbsc: error: cannot write into '{}'\n", tmp_dir.string());
    return 1;
  }
  fs::remove_all(final_dir, ec);
  fs::rename(tmp_dir, final_dir, ec);
  if (ec) {
    fs::remove_all(tmp_dir, ec);
    err << fmt::format("mbsc: error: cannot create '{}'\n", final_dir.string());
    return 1;
  }
  out << fmt::format("wrote {}/{}.hpp and {}.cpp ({} dof;", final_dir.string(), name, name, eom->ndof());
  for (const auto& f : g->functions) out << fmt::format(" {} {} ops", f.name, f.ops.total());
  out << ")\n";
  return 0;
}

}  // namespace mbsc::driver
