// SPDX-License-Identifier: GPL-2.0-or-later
#include "mbsc/print/print_matrix.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <optional>
#include <stdexcept>
#include <variant>

#include "mbsc/diag/activity.hpp"
#include "mbsc/driver/pipeline.hpp"
#include "mbsc/model/exact_guard.hpp"
#include "mbsc/print/canonical_text.hpp"
#include "mbsc/print/display_simplify.hpp"
#include "mbsc/print/latex_layout.hpp"
#include "mbsc/print/latex_names.hpp"
#include "mbsc/sym/full_complement.hpp"
#include "mbsc/sym/minimal_state.hpp"
#include "mbsc/sym/tidy.hpp"

namespace mbsc::print {
namespace {

/// Closed forms larger than this (nodes) are not substituted: the intermediate stays named.
constexpr std::size_t kMaxClosedNodes = 3000;
/// Numeric solves up to this size get a closed form (Cramer's rule).
constexpr int kMaxClosedSolve = 4;
/// Text matrices whose widest entry is longer than this are listed entry by entry.
constexpr std::size_t kMaxGridEntry = 48;
constexpr std::size_t kMaxGridWidth = 140;

std::string fmt_ex(const GiNaC::ex& e, bool latex) { return canonical_text(display_simplify(e), latex); }

/// An expression as print shows it: finalized, with every kinematic name (a named body
/// rotation entry R_<body>_<ij>, docs/formulation.md) written out in the joint angles, so
/// that the printed equations read only the model's own symbols, and derivatives taken
/// here by coordinates see through the names.
GiNaC::ex shown(const model::Model& m, const sym::Eom& eom, const GiNaC::ex& e) {
  return driver::finalize(m, eom, model::expand_kinematic_names(m, e));
}

std::string pad(const std::string& s, std::size_t w) { return s.size() >= w ? s : s + std::string(w - s.size(), ' '); }

/// A labelled matrix. Text: an aligned grid with row and column labels, or, when an
/// entry is too long for a grid, one line per nonzero entry; LaTeX: a pmatrix.
/// The entries are printed as given (already in display form).
std::string matrix_text(const std::string& title, const std::vector<std::string>& rows, const std::vector<std::string>& cols,
                        const std::vector<std::vector<GiNaC::ex>>& v, bool latex) {
  std::string out;
  if (latex) {
    std::vector<std::vector<std::string>> cells(v.size());
    for (size_t i = 0; i < v.size(); ++i)
      for (const auto& e : v[i]) cells[i].push_back(canonical_text(e, true));
    return latex_matrix(title, rows, cols, cells, LatexSymbolScope::current());
  }
  out += fmt::format("{} ({} x {}), rows: {}; columns: {}\n", title, rows.size(), cols.size(), fmt::join(rows, ", "),
                     fmt::join(cols, ", "));
  std::vector<std::vector<std::string>> cell(v.size());
  std::size_t widest = 0;
  for (size_t i = 0; i < v.size(); ++i)
    for (const auto& e : v[i]) {
      cell[i].push_back(canonical_text(e, false));
      widest = std::max(widest, cell[i].back().size());
    }
  std::size_t label_w = 0;
  for (const auto& r : rows) label_w = std::max(label_w, r.size());
  std::vector<std::size_t> col_w(cols.size());
  std::size_t total = 2 + label_w;
  for (size_t j = 0; j < cols.size(); ++j) {
    col_w[j] = cols[j].size();
    for (size_t i = 0; i < v.size(); ++i) col_w[j] = std::max(col_w[j], cell[i][j].size());
    total += 2 + col_w[j];
  }
  if (widest <= kMaxGridEntry && total <= kMaxGridWidth) {
    std::string head = "  " + std::string(label_w, ' ');
    for (size_t j = 0; j < cols.size(); ++j) head += "  " + pad(cols[j], col_w[j]);
    while (!head.empty() && head.back() == ' ') head.pop_back();
    out += head + "\n";
    for (size_t i = 0; i < v.size(); ++i) {
      std::string line = "  " + pad(rows[i], label_w);
      for (size_t j = 0; j < cols.size(); ++j) line += "  " + pad(cell[i][j], col_w[j]);
      while (!line.empty() && line.back() == ' ') line.pop_back();
      out += line + "\n";
    }
  } else {
    out += widest > kMaxGridEntry ? "  (entries too long for a grid: the nonzero ones, one per line)\n"
                                  : "  (too wide for a grid: the nonzero entries, one per line)\n";
    for (size_t i = 0; i < v.size(); ++i)
      for (size_t j = 0; j < v[i].size(); ++j)
        if (!v[i][j].is_zero()) out += fmt::format("  [{}, {}] = {}\n", rows[i], cols[j], cell[i][j]);
  }
  out += "\n";
  return out;
}

std::vector<std::string> names_of(const model::Model& m, const std::vector<int>& speeds, bool dot) {
  std::vector<std::string> v;
  for (int s : speeds) v.push_back(m.speeds[s].name + (dot ? "'" : ""));
  return v;
}

/// The named variables (e_, r_) and numeric-solve results (X_) of the derivation, in
/// evaluation order, with the closed form of each where it is affordable. A pure alias
/// (a variable equal to one symbol or a number, e_cart_u = e_cable_u) is not listed:
/// what reads it shows its value instead. With `expand`, also the dependent speeds of
/// node n in terms of its independent ones (what `--state minimal` code evaluates), so
/// that closed forms read only coordinates and independent speeds.
class Intermediates {
 public:
  Intermediates(const model::Model& m, const sym::Eom& eom, int n, bool expand) {
    for (const auto& step : eom.pre_steps) {
      if (const auto* d = std::get_if<ir::Define>(&step)) {
        Step s;
        s.define = ir::Define{d->sym, model::subs_present(shown(m, eom, d->value), aliases_), d->named};
        const GiNaC::ex closed = model::subs_present(s.define.value, closed_);
        if (node_count(closed, kMaxClosedNodes) <= kMaxClosedNodes) closed_[d->sym] = closed;
        if (GiNaC::is_a<GiNaC::symbol>(s.define.value) || GiNaC::is_a<GiNaC::numeric>(s.define.value)) {
          aliases_[d->sym] = s.define.value;
          continue;
        }
        steps_.push_back(std::move(s));
        continue;
      }
      const auto& solve = std::get<ir::Solve>(step);
      if (solve.condition) continue;
      Step s;
      s.is_solve = true;
      s.solve = solve;
      for (auto& e : s.solve.A) e = model::subs_present(shown(m, eom, e), aliases_);
      for (auto& e : s.solve.B) e = model::subs_present(shown(m, eom, e), aliases_);
      close_solve(s.solve, closed_);
      steps_.push_back(std::move(s));
    }
    if (expand) close_dependent_speeds(m, eom, n);
  }

  /// With expand: the dependent speeds that entries still read (no affordable closed
  /// form, or one the rebuild cannot give), by name.
  std::vector<std::string> dependent_read(const std::vector<std::vector<GiNaC::ex>>& entries) const {
    std::vector<std::string> out;
    for (const auto& [name, sym] : dependent_) {
      bool read = false;
      for (const auto& row : entries)
        for (const auto& e : row) read = read || e.has(sym);
      if (read) out.push_back(name);
    }
    return out;
  }

  /// x with the pure aliases replaced by their values (the form shown without --expand).
  GiNaC::ex resolve(const GiNaC::ex& x) const { return model::subs_present(x, aliases_); }

  /// x with every closed form substituted (the intermediates, then the dependent speeds),
  /// each stage kept only when its result is not too large.
  GiNaC::ex expand(const GiNaC::ex& x) const {
    GiNaC::ex e = model::subs_present(x, closed_);
    if (node_count(e, 20 * kMaxClosedNodes) > 20 * kMaxClosedNodes) return resolve(x);
    const GiNaC::ex f = model::subs_present(e, speeds_);
    return node_count(f, 20 * kMaxClosedNodes) <= 20 * kMaxClosedNodes ? f : e;
  }

  /// The intermediates `shown` reads, directly or through each other, in evaluation order.
  std::vector<Intermediate> needed(const std::vector<std::vector<GiNaC::ex>>& shown, bool& numeric, bool& all_closed) const {
    std::vector<bool> need(steps_.size(), false);
    auto read_by = [&](const GiNaC::symbol& x, size_t after) {
      for (const auto& row : shown)
        for (const auto& e : row)
          if (e.has(x)) return true;
      for (size_t j = after + 1; j < steps_.size(); ++j) {
        if (!need[j]) continue;
        if (steps_[j].is_solve) {
          for (const auto& e : steps_[j].solve.A)
            if (e.has(x)) return true;
          for (const auto& e : steps_[j].solve.B)
            if (e.has(x)) return true;
        } else if (steps_[j].define.value.has(x)) {
          return true;
        }
      }
      return false;
    };
    for (size_t i = steps_.size(); i-- > 0;) {
      if (steps_[i].is_solve) {
        for (const auto& x : steps_[i].solve.X) need[i] = need[i] || read_by(x, i);
      } else {
        need[i] = read_by(steps_[i].define.sym, i);
      }
    }
    std::vector<Intermediate> out;
    for (size_t i = 0; i < steps_.size(); ++i) {
      if (!need[i]) continue;
      if (!steps_[i].is_solve) {
        out.push_back({steps_[i].define.sym, display_simplify(steps_[i].define.value), false, true});
        continue;
      }
      numeric = true;
      for (const auto& x : steps_[i].solve.X) {
        auto it = closed_.find(x);
        const bool solved = it != closed_.end();
        all_closed = all_closed && solved;
        out.push_back({x, solved ? display_simplify(it->second) : GiNaC::ex(x), true, solved});
      }
    }
    return out;
  }

  /// The solve that yields x (for the note of an unsolved X).
  const ir::Solve* solve_of(const GiNaC::symbol& x) const {
    for (const auto& s : steps_)
      if (s.is_solve)
        for (const auto& y : s.solve.X)
          if (y.is_equal(x)) return &s.solve;
    return nullptr;
  }

 private:
  struct Step {
    bool is_solve = false;
    ir::Define define;
    ir::Solve solve;
  };

  /// X = A^-1 B by Cramer's rule for a small block (numerator and determinant each in
  /// display form, the closed forms in `known` put in); nothing when the block is large,
  /// singular or the result too big.
  static void close_solve(const ir::Solve& s, GiNaC::exmap& known) {
    if (s.n > kMaxClosedSolve) return;
    GiNaC::matrix A(s.n, s.n);
    for (int i = 0; i < s.n; ++i)
      for (int j = 0; j < s.n; ++j) {
        // Expanded first: the complement keeps eliminated entries factored (a - f b,
        // nested), and a determinant of those expands every product of them afresh.
        A(i, j) = model::expand_if_small(model::subs_present(s.A[i * s.n + j], known));
        if (node_count(A(i, j), kMaxClosedNodes) > kMaxClosedNodes) return;
      }
    const GiNaC::ex det = display_simplify(A.determinant(GiNaC::determinant_algo::laplace));
    if (det.is_zero()) return;
    for (int l = 0; l < s.k; ++l) {
      for (int i = 0; i < s.n; ++i) {
        GiNaC::matrix Ai = A;
        for (int r = 0; r < s.n; ++r) Ai(r, i) = model::expand_if_small(model::subs_present(s.B[r * s.k + l], known));
        const GiNaC::ex num = display_simplify(Ai.determinant(GiNaC::determinant_algo::laplace));
        const GiNaC::ex x = num / det;
        if (node_count(x, kMaxClosedNodes) > kMaxClosedNodes) continue;
        known[s.X[i * s.k + l]] = x;
      }
    }
  }

  /// The dependent speeds of node n's subtree (every speed there but n's independent
  /// ones) in terms of n's independent speeds and the coordinates: the top-down rebuild
  /// of the minimal state, each step with the ones before it put in, small numeric
  /// blocks by Cramer's rule. A speed without an affordable closed form stays a symbol.
  void close_dependent_speeds(const model::Model& m, const sym::Eom& eom, int n) {
    std::vector<int> dependent = sym::subtree_speeds(m, n);
    const auto& z = eom.nodes[n].independent;
    dependent.erase(std::remove_if(dependent.begin(), dependent.end(),
                                   [&](int s) { return std::find(z.begin(), z.end(), s) != z.end(); }),
                    dependent.end());
    if (dependent.empty()) return;
    for (int s : dependent) dependent_.push_back({m.speeds[s].name, m.speeds[s].sym});
    auto is_dependent = [&](const GiNaC::ex& x) {
      for (int s : dependent)
        if (x.is_equal(m.speeds[s].sym)) return true;
      return false;
    };
    Diagnostics quiet;  // a model the rebuild cannot handle keeps its dependent speeds
    std::optional<sym::MinimalState> rebuild;
    try {
      rebuild = sym::minimal_state(m, eom, quiet);
    } catch (const std::exception&) {
      return;
    }
    if (!rebuild) return;
    for (const auto& step : rebuild->speeds) {
      if (const auto* d = std::get_if<ir::Define>(&step)) {
        if (!is_dependent(d->sym)) continue;
        const GiNaC::ex value = model::subs_present(shown(m, eom, d->value), speeds_);
        if (node_count(value, kMaxClosedNodes) <= kMaxClosedNodes) speeds_[d->sym] = value;
        continue;
      }
      ir::Solve s = std::get<ir::Solve>(step);
      if (s.condition || !std::all_of(s.X.begin(), s.X.end(), is_dependent)) continue;
      for (auto& e : s.A) e = shown(m, eom, e);
      for (auto& e : s.B) e = shown(m, eom, e);
      close_solve(s, speeds_);
    }
  }

  std::vector<Step> steps_;
  GiNaC::exmap closed_;
  GiNaC::exmap aliases_;  // pure aliases: symbol -> the symbol or number it equals
  GiNaC::exmap speeds_;   // with expand: dependent speed -> closed form in z and q0
  std::vector<std::pair<std::string, GiNaC::symbol>> dependent_;  // with expand: node n's dependent speeds
};

/// The "where" list under printed equations.
std::string where_text(const std::vector<Intermediate>& where, const Intermediates& all, bool latex) {
  if (where.empty()) return "";
  std::string out = latex ? "" : "  where (evaluated in this order; --expand writes the closed form instead)\n";
  std::vector<LatexEquation> equations;  // LaTeX: the closed forms, in one align*
  for (size_t i = 0; i < where.size(); ++i) {
    const auto& w = where[i];
    if (w.from_solve && !w.solved) {
      // The results of one solve without a closed form, on one line.
      const ir::Solve* s = all.solve_of(w.sym);
      std::vector<std::string> names{w.sym.get_name()};
      while (i + 1 < where.size() && where[i + 1].from_solve && !where[i + 1].solved && all.solve_of(where[i + 1].sym) == s)
        names.push_back(where[++i].sym.get_name());
      const std::string why = fmt::format("the {} x {} linear solve of {} (LU in the generated code; too large for a closed "
                                          "form here)",
                                          s ? s->n : 0, s ? s->n : 0, s ? s->label : std::string("?"));
      out += latex ? fmt::format("% {}: {}\n", fmt::join(names, ", "), why)
                   : fmt::format("  {}: {}\n", fmt::join(names, ", "), why);
      continue;
    }
    const std::string value = canonical_text(w.value, latex);
    const char* tag = w.from_solve ? "   (numeric solve in the generated code; closed form)" : "";
    if (latex) equations.push_back({canonical_text(w.sym, true), value, w.from_solve ? "closed form of a numeric solve" : ""});
    else out += fmt::format("  {} = {}{}\n", w.sym.get_name(), value, tag);
  }
  if (latex) return out + latex_equations("where (evaluated in this order)", equations);
  return out + "\n";
}

/// M z' = h written out row by row.
std::string eom_text(const model::Model& m, const std::vector<int>& z, const PrintedEquations& p, bool latex) {
  std::vector<LatexEquation> equations;  // LaTeX: one align*
  std::string out = latex ? ""
                          : fmt::format("equations of motion M z' = h, z = ({})\n", fmt::join(names_of(m, z, false), ", "));
  for (size_t i = 0; i < z.size(); ++i) {
    std::string lhs;
    for (size_t j = 0; j < z.size(); ++j) {
      const GiNaC::ex& e = p.M[i][j];
      if (e.is_zero()) continue;
      std::string t = canonical_text(e, latex);
      const std::string dot = latex ? latex_symbol(m.speeds[z[j]].name + "'", LatexSymbolScope::current()) : m.speeds[z[j]].name + "'";
      bool neg = false;
      if (GiNaC::is_a<GiNaC::add>(e)) {
        t = (latex ? "\\left(" + t + "\\right)" : "(" + t + ")");
      } else if (!t.empty() && t[0] == '-') {
        neg = true;
        t = t.substr(1);
      }
      std::string factor = t == "1" ? dot : t + (latex ? " " : "*") + dot;
      if (lhs.empty()) lhs = (neg ? "-" : "") + factor;
      else lhs += (neg ? " - " : " + ") + factor;
    }
    if (lhs.empty()) lhs = "0";
    const std::string rhs = canonical_text(p.h[i][0], latex);
    if (latex) equations.push_back({lhs, rhs, ""});
    else out += fmt::format("  {}:  {} = {}\n", m.speeds[z[i]].name, lhs, rhs);
  }
  if (latex) return latex_equations("equations of motion M z' = h", equations);
  return out + "\n";
}

}  // namespace

namespace {

/// A matrix's entries in display form: simplified, in closed form with --expand, else
/// with the intermediates' aliases resolved.
std::vector<std::vector<GiNaC::ex>> display_rows(const model::Model& m, const sym::Eom& eom, const GiNaC::matrix& X,
                                                 bool expand, const Intermediates& inter) {
  std::vector<std::vector<GiNaC::ex>> v(X.rows(), std::vector<GiNaC::ex>(X.cols()));
  for (unsigned i = 0; i < X.rows(); ++i)
    for (unsigned j = 0; j < X.cols(); ++j) {
      const GiNaC::ex e = shown(m, eom, X(i, j));
      v[i][j] = display_simplify(expand ? inter.expand(e) : inter.resolve(e));
    }
  return v;
}

PrintedEquations equations_of(const model::Model& m, const sym::Eom& eom, int n, bool expand, const Intermediates& inter) {
  const auto& r = eom.nodes[n];
  PrintedEquations p;
  p.M = display_rows(m, eom, n == m.root() ? eom.M.get() : r.M, expand, inter);  // the root's is formed on demand
  p.h = display_rows(m, eom, r.h, expand, inter);
  std::vector<std::vector<GiNaC::ex>> both = p.M;
  both.insert(both.end(), p.h.begin(), p.h.end());
  p.where = inter.needed(both, p.numeric_solves, p.all_closed);
  return p;
}

/// The note above M and h when they read results of numeric solves.
std::string numeric_note(const PrintedEquations& p, bool expand, bool latex) {
  if (!p.numeric_solves) return "";
  std::string note =
      expand ? "note: the complement here is numeric (LU in the generated code) and some of its blocks are too large for a "
               "closed form: M and h read their results X_..., listed under 'where'"
      : p.all_closed
          ? "note: the complement here is numeric (LU in the generated code): M and h read its results X_..., whose closed "
            "forms are listed under 'where'; --expand substitutes them"
          : "note: the complement here is numeric (LU in the generated code): M and h read its results X_..., listed under "
            "'where' (closed forms where affordable; --expand substitutes those)";
  return latex ? "% " + note + "\n" : note + "\n\n";
}

}  // namespace

PrintedEquations printed_equations(const model::Model& m, const sym::Eom& eom, int node, bool expand) {
  const Intermediates inter(m, eom, node, expand);
  return equations_of(m, eom, node, expand, inter);
}

std::string print_node(const model::Model& m, const sym::Eom& eom, int n, const std::vector<std::string>& what, bool latex,
                       bool expand) {
  const LatexSymbolScope symbols(m.latex_symbols);  // the model's `latex` statements
  const auto& r = eom.nodes[n];
  const std::string who = m.nodes[n].name.empty() ? m.name : m.nodes[n].name;
  std::string out = latex ? fmt::format("% subsystem {}\n", who) : fmt::format("subsystem {}\n\n", who);
  std::vector<std::string> cons;
  for (int c : r.rows) cons.push_back(m.constraints[c].name);
  const auto ynames = names_of(m, r.y, true);
  const auto inames = names_of(m, r.independent, true);
  checkpoint("printing", "the closed forms of the named intermediates", m.nodes[n].pos, 0, what.size());
  const Intermediates inter(m, eom, n, expand);
  std::optional<PrintedEquations> eq;
  auto equations = [&]() -> const PrintedEquations& {
    if (!eq) eq = equations_of(m, eom, n, expand, inter);
    return *eq;
  };
  // A matrix's entries in display form (closed form with --expand), and what they read.
  auto rows_of = [&](const GiNaC::matrix& X) { return display_rows(m, eom, X, expand, inter); };
  auto where_of = [&](const std::vector<std::vector<GiNaC::ex>>& v) {
    bool numeric = false, closed = true;
    return where_text(inter.needed(v, numeric, closed), inter, latex);
  };
  bool noted = false;
  std::vector<std::vector<GiNaC::ex>> run_reads;  // the entries of the current run of M, h, eom
  for (size_t k = 0; k < what.size(); ++k) {
    const std::string& w = what[k];
    // The budget (--budget) and the progress line see the printing too.
    checkpoint("printing", fmt::format("{} of subsystem '{}'", w, who), m.nodes[n].pos, k, what.size());
    if (w == "eom" || w == "M" || w == "h") {
      const PrintedEquations& p = equations();
      if (!noted) {
        out += numeric_note(p, expand, latex);
        std::vector<std::vector<GiNaC::ex>> both = p.M;
        both.insert(both.end(), p.h.begin(), p.h.end());
        const auto left = expand ? inter.dependent_read(both) : std::vector<std::string>{};
        if (!left.empty()) {
          const std::string note = fmt::format(
              "note: h reads the dependent speed{} {} as the state holds {}: {} closed form in the independent speeds "
              "would be too large to print, or the velocity constraints do not give {} linearly",
              left.size() > 1 ? "s" : "", fmt::join(left, ", "), left.size() > 1 ? "them" : "it",
              left.size() > 1 ? "their" : "its", left.size() > 1 ? "them" : "it");
          out += latex ? "% " + note + "\n" : note + "\n\n";
        }
      }
      noted = true;
      if (w == "M") out += matrix_text("M", inames, inames, p.M, latex);
      else if (w == "h") out += matrix_text("h", inames, {"value"}, p.h, latex);
      else out += eom_text(m, r.independent, p, latex);
      if (w != "h") run_reads.insert(run_reads.end(), p.M.begin(), p.M.end());
      if (w != "M") run_reads.insert(run_reads.end(), p.h.begin(), p.h.end());
      // One "where" list after the last of a run of M, h and eom: what that run reads.
      const bool run_goes_on = k + 1 < what.size() && (what[k + 1] == "eom" || what[k + 1] == "M" || what[k + 1] == "h");
      if (!run_goes_on) {
        out += where_of(run_reads);
        run_reads.clear();
      }
    } else if (w == "rates") {
      std::vector<std::vector<GiNaC::ex>> v;
      std::vector<std::string> rows;
      for (size_t q = 0; q < m.coords.size(); ++q) {
        rows.push_back(m.coords[q].name + "'");
        v.push_back({display_simplify(shown(m, eom, m.coord_rates[q]))});
      }
      out += matrix_text("kinematic transformations q0'", rows, {"value"}, v, latex);
    } else if (w == "A") {
      auto speeds = sym::subtree_speeds(m, n);
      std::vector<std::vector<GiNaC::ex>> v;
      for (int c : r.rows) {
        GiNaC::ex g = m.constraints[c].residual;
        if (m.constraints[c].level == model::Constraint::Level::Position) g = sym::time_derivative(m, g);
        std::vector<GiNaC::ex> row;
        for (int s : speeds) row.push_back(display_simplify(shown(m, eom, g.diff(m.speeds[s].sym))));
        v.push_back(row);
      }
      out += matrix_text("A", cons, names_of(m, speeds, false), v, latex);
    } else if (w == "B") {
      if (r.rows.empty()) out += latex ? "% B is empty (no constraints here)\n" : "B is empty (no constraints here)\n\n";
      else {
        const auto v = rows_of(r.B);
        out += matrix_text("B", cons, ynames, v, latex) + where_of(v);
      }
    } else if (w == "C") {
      const auto v = rows_of(r.C.get());
      out += matrix_text("C", ynames, inames, v, latex) + where_of(v);
    } else if (w == "S") {
      std::vector<int> rows;
      GiNaC::matrix S = sym::full_complement(m, eom, n, rows);
      const auto v = rows_of(S);
      out += matrix_text("S", names_of(m, rows, false), inames, v, latex) + where_of(v);
    } else if (w == "f" || w == "fbar") {
      // f = -My y' + hy over y; fbar = -M z' + h over the independent speeds.
      const bool full = w == "f";
      const auto& vars = full ? r.y : r.independent;
      const GiNaC::matrix& Mx = full ? r.My : (n == m.root() ? eom.M.get() : r.M);
      const GiNaC::matrix& hx = full ? r.hy : r.h;
      std::vector<std::vector<GiNaC::ex>> v;
      for (size_t i = 0; i < vars.size(); ++i) {
        GiNaC::ex e = hx(i, 0);
        for (size_t j = 0; j < vars.size(); ++j) e -= Mx(i, j) * m.speed_dots[vars[j]];
        e = shown(m, eom, e);
        v.push_back({display_simplify(expand ? inter.expand(e) : inter.resolve(e))});
      }
      out += matrix_text(full ? "f" : "fbar", full ? ynames : inames, {"value"}, v, latex) + where_of(v);
    } else if (w == "invariants") {
      // The node's constraints as written or as joints expand them: residual = 0.
      if (!latex) out += fmt::format("constraints of {} (residual = 0)\n", who);
      if (!latex && m.nodes[n].constraints.empty()) out += "  none\n";
      std::vector<LatexEquation> equations;
      for (int ci : m.nodes[n].constraints) {
        const auto& c = m.constraints[ci];
        const char* level = c.level == model::Constraint::Level::Position ? "position" : "velocity";
        const std::string text = fmt_ex(shown(m, eom, c.residual), latex);
        if (latex) equations.push_back({"0", text, fmt::format("{} ({})", c.name, level)});
        else out += fmt::format("  {} ({}): {} = 0\n", c.name, level, text);
      }
      out += latex ? latex_equations(fmt::format("invariants of {}", who), equations) : "\n";
    } else {
      throw std::invalid_argument(
          fmt::format("--what: unknown item '{}' (known: eom M h invariants rates A B C S f fbar)", w));
    }
  }
  return out;
}

}  // namespace mbsc::print
