// SPDX-License-Identifier: GPL-2.0-or-later
#include "mbsc/driver/print_matrix.hpp"

#include <fmt/format.h>

#include <stdexcept>

#include "mbsc/driver/canonical_text.hpp"
#include "mbsc/driver/latex_layout.hpp"
#include "mbsc/driver/pipeline.hpp"
#include "mbsc/sym/full_complement.hpp"
#include "mbsc/sym/tidy.hpp"

namespace mbsc::driver {
namespace {

std::string fmt_ex(const GiNaC::ex& e, bool latex) { return canonical_text(sym::tidy(e), latex); }


/// A labelled matrix: one line per nonzero entry in text, a pmatrix in LaTeX.
std::string matrix_text(const std::string& title, const std::vector<std::string>& rows, const std::vector<std::string>& cols,
                        const std::vector<std::vector<GiNaC::ex>>& v, bool latex) {
  std::string out;
  if (latex) {
    std::vector<std::vector<std::string>> cells(v.size());
    for (size_t i = 0; i < v.size(); ++i)
      for (const auto& e : v[i]) cells[i].push_back(fmt_ex(e, true));
    return latex_matrix(title, rows, cols, cells, LatexSymbolScope::current());
  }
  out += fmt::format("{} ({} x {}), rows: {}; columns: {}\n", title, rows.size(), cols.size(), fmt::join(rows, ", "),
                     fmt::join(cols, ", "));
  for (size_t i = 0; i < v.size(); ++i)
    for (size_t j = 0; j < v[i].size(); ++j)
      if (!v[i][j].is_zero()) out += fmt::format("  [{}, {}] = {}\n", rows[i], cols[j], fmt_ex(v[i][j], false));
  out += "\n";
  return out;
}

std::vector<std::string> names_of(const model::Model& m, const std::vector<int>& speeds, bool dot) {
  std::vector<std::string> v;
  for (int s : speeds) v.push_back(m.speeds[s].name + (dot ? "'" : ""));
  return v;
}

std::vector<std::vector<GiNaC::ex>> to_rows(const GiNaC::matrix& M, const model::Model& m, const sym::Eom& eom) {
  std::vector<std::vector<GiNaC::ex>> v(M.rows(), std::vector<GiNaC::ex>(M.cols()));
  for (unsigned i = 0; i < M.rows(); ++i)
    for (unsigned j = 0; j < M.cols(); ++j) v[i][j] = finalize(m, eom, M(i, j));
  return v;
}

/// The named variables (e_, r_) that `shown` reads, directly or through each other, from
/// the subtree of node n, in evaluation order: printed under the matrices that use them.
std::string where_text(const model::Model& m, const sym::Eom& eom, int n, const std::vector<std::vector<GiNaC::ex>>& shown,
                       bool latex) {
  std::vector<const ir::Define*> defs;
  int first = n;  // post-order: the subtree is first..n, first its leftmost leaf
  while (!m.nodes[first].children.empty()) first = m.nodes[first].children.front();
  for (int k = first; k <= n; ++k)
    for (const auto& d : eom.nodes[k].named_defines) defs.push_back(&d);
  std::vector<bool> needed(defs.size(), false);
  for (size_t i = defs.size(); i-- > 0;) {
    bool read = false;
    for (const auto& row : shown)
      for (const auto& e : row) read = read || e.has(defs[i]->sym);
    for (size_t j = i + 1; j < defs.size() && !read; ++j) read = needed[j] && defs[j]->value.has(defs[i]->sym);
    needed[i] = read;
  }
  std::string out;
  std::vector<LatexEquation> equations;
  for (size_t i = 0; i < defs.size(); ++i) {
    if (!needed[i]) continue;
    const std::string value = fmt_ex(finalize(m, eom, defs[i]->value), latex);
    if (latex) equations.push_back({canonical_text(defs[i]->sym, true), value, ""});
    else out += fmt::format("  {} = {}\n", defs[i]->sym.get_name(), value);
  }
  if (latex) return latex_equations("where (evaluated in this order)", equations);
  if (out.empty()) return out;
  return (latex ? std::string("% where (evaluated in this order)\n") : std::string("  where (evaluated in this order)\n")) + out +
         "\n";
}

}  // namespace

std::string print_node(const model::Model& m, const sym::Eom& eom, int n, const std::vector<std::string>& what, bool latex) {
  const LatexSymbolScope symbols(m.latex_symbols);  // the model's `latex` statements
  const auto& r = eom.nodes[n];
  const std::string who = m.nodes[n].name.empty() ? m.name : m.nodes[n].name;
  std::string out = latex ? fmt::format("% subsystem {}\n", who) : fmt::format("subsystem {}\n\n", who);
  std::vector<std::string> cons;
  for (int c : r.rows) cons.push_back(m.constraints[c].name);
  const auto ynames = names_of(m, r.y, true);
  const auto inames = names_of(m, r.independent, true);
  for (const auto& w : what) {
    if (w == "rates") {
      std::vector<std::vector<GiNaC::ex>> v;
      std::vector<std::string> rows;
      for (size_t q = 0; q < m.coords.size(); ++q) {
        rows.push_back(m.coords[q].name + "'");
        v.push_back({finalize(m, eom, m.coord_rates[q])});
      }
      out += matrix_text("kinematic transformations q0'", rows, {"value"}, v, latex);
    } else if (w == "A") {
      auto speeds = sym::subtree_speeds(m, n);
      std::vector<std::vector<GiNaC::ex>> v;
      for (int c : r.rows) {
        GiNaC::ex g = m.constraints[c].residual;
        if (m.constraints[c].level == model::Constraint::Level::Position) g = sym::time_derivative(m, g);
        std::vector<GiNaC::ex> row;
        for (int s : speeds) row.push_back(finalize(m, eom, g.diff(m.speeds[s].sym)));
        v.push_back(row);
      }
      out += matrix_text("A", cons, names_of(m, speeds, false), v, latex);
    } else if (w == "B") {
      if (r.rows.empty()) out += latex ? "% B is empty (no constraints here)\n" : "B is empty (no constraints here)\n\n";
      else out += matrix_text("B", cons, ynames, to_rows(r.B, m, eom), latex);
    } else if (w == "C") {
      out += matrix_text("C", ynames, inames, to_rows(r.C, m, eom), latex);
    } else if (w == "S") {
      std::vector<int> rows;
      GiNaC::matrix S = sym::full_complement(m, eom, n, rows);
      out += matrix_text("S", names_of(m, rows, false), inames, to_rows(S, m, eom), latex);
    } else if (w == "f" || w == "fbar") {
      // f = -My y' + hy over y; fbar = -M z' + h over the independent speeds.
      const bool full = w == "f";
      const auto& vars = full ? r.y : r.independent;
      const GiNaC::matrix& Mx = full ? r.My : r.M;
      const GiNaC::matrix& hx = full ? r.hy : r.h;
      std::vector<std::vector<GiNaC::ex>> v;
      for (size_t i = 0; i < vars.size(); ++i) {
        GiNaC::ex e = hx(i, 0);
        for (size_t j = 0; j < vars.size(); ++j) e -= Mx(i, j) * m.speed_dots[vars[j]];
        v.push_back({finalize(m, eom, e)});
      }
      out += matrix_text(full ? "f" : "fbar", full ? ynames : inames, {"value"}, v, latex);
      out += where_text(m, eom, n, v, latex);
    } else if (w == "M" || w == "h") {
      const auto rows = to_rows(w == "M" ? r.M : r.h, m, eom);
      out += w == "M" ? matrix_text("M", inames, inames, rows, latex) : matrix_text("h", inames, {"value"}, rows, latex);
      out += where_text(m, eom, n, rows, latex);
    } else if (w == "invariants") {
      // The node's constraints as written or as joints expand them: residual = 0.
      if (!latex) out += fmt::format("invariants of {} (residual = 0)\n", who);
      std::vector<LatexEquation> equations;
      for (int ci : m.nodes[n].constraints) {
        const auto& c = m.constraints[ci];
        const char* level = c.level == model::Constraint::Level::Position ? "position" : "velocity";
        const std::string text = fmt_ex(finalize(m, eom, c.residual), latex);
        if (latex) equations.push_back({"0", text, fmt::format("{} ({})", c.name, level)});
        else out += fmt::format("  {} ({}): {} = 0\n", c.name, level, text);
      }
      out += latex ? latex_equations(fmt::format("invariants of {}", who), equations) : "\n";
    } else {
      throw std::invalid_argument(fmt::format("--what: unknown item '{}' (known: rates A B C S f fbar M h invariants)", w));
    }
  }
  return out;
}

}  // namespace mbsc::driver
