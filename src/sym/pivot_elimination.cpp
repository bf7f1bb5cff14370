// SPDX-License-Identifier: GPL-2.0-or-later
// Symbolic elimination on state-free pivots (see pivot_elimination.hpp).
#include "mbsc/sym/pivot_elimination.hpp"
#include "mbsc/model/exact_guard.hpp"

#include <cmath>
#include <vector>

namespace mbsc::sym {

Elimination eliminate_state_free_pivots(std::vector<LinearRow> rows, const model::Model& model, const Probe& probe) {
  const std::size_t n_rows = rows.size();
  const std::size_t n_vars = n_rows == 0 ? 0 : rows.front().c.size();
  std::vector<bool> row_done(n_rows, false), var_done(n_vars, false);
  // Sparse bookkeeping: each live row's nonzero live columns (ascending) and each
  // column's count of live nonzero rows, updated only for the rows a pivot touches; and
  // whether an entry can be a pivot, decided once per value of the entry. Rescanning
  // the whole matrix per pivot made this quartic in the size of a big loop-closing node.
  std::vector<std::vector<std::size_t>> cols_of(n_rows);
  std::vector<long> col_count(n_vars, 0);
  std::vector<std::vector<signed char>> usable(n_rows);
  auto scan_row = [&](std::size_t i) {
    for (std::size_t j : cols_of[i]) --col_count[j];
    cols_of[i].clear();
    for (std::size_t j = 0; j < n_vars; ++j)
      if (!var_done[j] && !rows[i].c[j].is_zero()) {
        cols_of[i].push_back(j);
        ++col_count[j];
      }
    usable[i].assign(n_vars, -1);
  };
  for (std::size_t i = 0; i < n_rows; ++i) scan_row(i);
  Elimination out;
  for (;;) {
    // Markowitz: (row count - 1) (column count - 1) among the live entries, numbers first.
    std::size_t best_i = n_rows, best_j = n_vars;
    long best_score = 0;
    for (std::size_t i = 0; i < n_rows; ++i) {
      if (row_done[i]) continue;
      const long row_count = static_cast<long>(cols_of[i].size());
      for (std::size_t j : cols_of[i]) {
        const GiNaC::ex& p = rows[i].c[j];
        signed char& ok = usable[i][j];
        if (ok < 0) ok = is_state_free(p, model) && std::abs(probe.eval(p)) > 1e-12;
        if (!ok) continue;
        const long score = (row_count - 1) * (col_count[j] - 1) * 2 + (GiNaC::is_a<GiNaC::numeric>(p) ? 0 : 1);
        if (best_i == n_rows || score < best_score) {
          best_i = i;
          best_j = j;
          best_score = score;
        }
      }
    }
    if (best_i == n_rows) break;
    const LinearRow pivot_row = rows[best_i];
    const std::vector<std::size_t> pivot_cols = cols_of[best_i];
    const GiNaC::ex& p = pivot_row.c[best_j];
    row_done[best_i] = true;
    for (std::size_t j : cols_of[best_i]) --col_count[j];
    cols_of[best_i].clear();
    var_done[best_j] = true;
    for (std::size_t k = 0; k < n_rows; ++k) {
      LinearRow& row = rows[k];
      if (k == best_i || row_done[k] || row.c[best_j].is_zero()) continue;
      const GiNaC::ex f = row.c[best_j] / p;
      for (std::size_t l : pivot_cols)
        if (l != best_j) {
          // The update stays factored (a - f b) unless its expansion is a number or is
          // free of the state where the factored form is not: expanding multiplies out
          // products of sines and cosines that the factored form shares (a spatial joint
          // chain: 19 553 -> 5 973 rhs operations for the joint-coordinate bicycle). Zeros,
          // numbers and state-free entries are judged on the expansion, so the sparsity,
          // the pivots and the Markowitz scores are those of full expansion.
          const GiNaC::ex x = row.c[l] - f * pivot_row.c[l];
          const GiNaC::ex xe = model::expand_if_small(x);
          const bool use_expansion = GiNaC::is_a<GiNaC::numeric>(xe) || (is_state_free(xe, model) && !is_state_free(x, model));
          row.c[l] = use_expansion ? xe : x;
        }
      row.c[best_j] = 0;
      row.rest = row.rest - f * pivot_row.rest;
      scan_row(k);
    }
    out.pivots.push_back({static_cast<int>(best_j), pivot_row});
  }
  for (std::size_t i = 0; i < n_rows; ++i)
    if (!row_done[i]) out.core_rows.push_back(static_cast<int>(i));
  for (std::size_t j = 0; j < n_vars; ++j)
    if (!var_done[j]) out.core_vars.push_back(static_cast<int>(j));
  out.rows = std::move(rows);
  return out;
}

std::vector<CoreBlock> core_blocks(const Elimination& e) {
  // Union-find over core rows (0 .. R-1) and unknowns (R .. R+V-1), joined by nonzeros.
  const std::size_t nr = e.core_rows.size(), nv = e.core_vars.size();
  std::vector<std::size_t> parent(nr + nv);
  for (std::size_t i = 0; i < parent.size(); ++i) parent[i] = i;
  auto find = [&](std::size_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (std::size_t i = 0; i < nr; ++i)
    for (std::size_t j = 0; j < nv; ++j)
      if (!e.rows[static_cast<std::size_t>(e.core_rows[i])].c[static_cast<std::size_t>(e.core_vars[j])].is_zero())
        parent[find(i)] = find(nr + j);
  std::vector<CoreBlock> blocks;
  std::map<std::size_t, std::size_t> block_of;  // root -> index in blocks (first row first)
  for (std::size_t i = 0; i < nr; ++i) {
    auto [it, fresh] = block_of.emplace(find(i), blocks.size());
    if (fresh) blocks.emplace_back();
    blocks[it->second].rows.push_back(e.core_rows[i]);
  }
  for (std::size_t j = 0; j < nv; ++j) {
    auto it = block_of.find(find(nr + j));
    if (it == block_of.end()) {  // an unknown in no row: the core is singular; keep it whole
      return {CoreBlock{e.core_rows, e.core_vars}};
    }
    blocks[it->second].vars.push_back(e.core_vars[j]);
  }
  for (const auto& b : blocks)
    if (b.rows.size() != b.vars.size()) return {CoreBlock{e.core_rows, e.core_vars}};
  return blocks;
}

void to_normal_equations(std::vector<GiNaC::ex>& A, std::vector<GiNaC::ex>& B, int rows, int n, int k) {
  auto at = [](const std::vector<GiNaC::ex>& M, int cols, int i, int j) -> const GiNaC::ex& {
    return M[static_cast<std::size_t>(i * cols + j)];
  };
  std::vector<GiNaC::ex> N(static_cast<std::size_t>(n * n)), R(static_cast<std::size_t>(n * k));
  for (int a = 0; a < n; ++a) {
    for (int b = 0; b < n; ++b) {
      GiNaC::ex acc = 0;
      for (int i = 0; i < rows; ++i)
        if (!at(A, n, i, a).is_zero() && !at(A, n, i, b).is_zero()) acc += at(A, n, i, a) * at(A, n, i, b);
      N[static_cast<std::size_t>(a * n + b)] = acc;
    }
    for (int l = 0; l < k; ++l) {
      GiNaC::ex acc = 0;
      for (int i = 0; i < rows; ++i)
        if (!at(A, n, i, a).is_zero() && !at(B, k, i, l).is_zero()) acc += at(A, n, i, a) * at(B, k, i, l);
      R[static_cast<std::size_t>(a * k + l)] = acc;
    }
  }
  A = std::move(N);
  B = std::move(R);
}

GiNaC::ex pivot_value(const Elimination::Pivot& p, const std::map<int, GiNaC::ex>& value) {
  GiNaC::ex acc = p.row.rest;
  for (std::size_t l = 0; l < p.row.c.size(); ++l)
    if (static_cast<int>(l) != p.var && !p.row.c[l].is_zero()) acc += p.row.c[l] * value.at(static_cast<int>(l));
  return -acc / p.row.c[static_cast<std::size_t>(p.var)];
}

void back_substitute(const Elimination& e, std::map<int, GiNaC::ex>& value) {
  for (auto it = e.pivots.rbegin(); it != e.pivots.rend(); ++it) value[it->var] = pivot_value(*it, value);
}

}  // namespace mbsc::sym
