// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// Gaussian elimination on the state-free pivots of a linear system (docs/formulation.md,
/// "Dependent rates"). The rows sum_j c_j x_j + rest = 0 of a dependent block often have
/// pivots that are numbers or parameters (the unit entries of joint rows in absolute
/// coordinates); eliminating those symbolically divides by nothing that can vanish at
/// run time and leaves a small core whose pivots all depend on the state, which the
/// generated code solves numerically (a four-bar's 8x8 block leaves its 2x2 loop).
#include <ginac/ginac.h>

#include <map>
#include <vector>

#include "mbsc/model/model.hpp"
#include "mbsc/sym/probe.hpp"

namespace mbsc::sym {

/// sum_j c[j] x_j + rest = 0.
struct LinearRow {
  std::vector<GiNaC::ex> c;
  GiNaC::ex rest;
};

struct Elimination {
  struct Pivot {
    int var;        // the unknown this row was solved for
    LinearRow row;  // the row then: it reads only later pivots' unknowns and the core's
  };
  std::vector<Pivot> pivots;         // in elimination order
  std::vector<int> core_rows;        // rows left (indices into `rows`)
  std::vector<int> core_vars;        // unknowns left
  std::vector<LinearRow> rows;       // every row after elimination (the core rows are reduced)
};

/// Eliminates, one at a time, the state-free pivot with the smallest Markowitz count
/// (numbers before parameter expressions) until none is left.
Elimination eliminate_state_free_pivots(std::vector<LinearRow> rows, const model::Model& model, const Probe& probe);

/// The core split into independent square blocks (connected components of its rows and
/// unknowns; a regular matrix splits into square ones), in the order of their first row.
/// Three legs of a parallel mechanism closing on a platform whose speeds are
/// independent give three 2x2 blocks instead of one 6x6.
struct CoreBlock {
  std::vector<int> rows, vars;
};
std::vector<CoreBlock> core_blocks(const Elimination& e);

/// A block A X = B (A: rows x n, B: rows x k, row-major) with more rows than unknowns,
/// as rows redundant on the mechanism leave it: replaced by its normal equations
/// A^T A X = A^T B (n x n, n x k), whose solution is exact where the rows are consistent,
/// on the manifold (thesis Section 4.5: the least-squares complement). Products of zero
/// entries are not formed.
void to_normal_equations(std::vector<GiNaC::ex>& A, std::vector<GiNaC::ex>& B, int rows, int n, int k);

/// A pivot's unknown from the values of the unknowns its row reads:
/// x_var = -(rest + sum_{l != var} c_l x_l) / c_var.
GiNaC::ex pivot_value(const Elimination::Pivot& p, const std::map<int, GiNaC::ex>& value);

/// Fills value[var] for every pivot, last pivot first, given value[] of the core's unknowns.
void back_substitute(const Elimination& e, std::map<int, GiNaC::ex>& value);

}  // namespace mbsc::sym
