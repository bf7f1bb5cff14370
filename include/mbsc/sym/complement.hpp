// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// Choice of the independent set # for the orthogonal complement C of B (thesis
/// (2.26)-(2.29), partition method), with rank and redundancy checks.
#include <ginac/ginac.h>

#include <optional>
#include <utility>
#include <vector>

#include "mbsc/diag/diagnostics.hpp"
#include "mbsc/model/model.hpp"
#include "mbsc/sym/probe.hpp"

namespace mbsc::sym {

struct ComplementInput {
  const model::Model* model;
  const Probe* probe;
  int node;
  std::vector<int> y;          // speeds of the columns of B
  std::vector<int> rows;       // constraint index of each row of B
  const GiNaC::matrix* B;      // rows x y
  std::vector<int> requested;  // user's independent speeds (empty: automatic)
  SourcePos requested_pos;
  /// The model's reference configuration (Probe::reference), or null: where it is a
  /// configuration of this node (its position constraints hold there), the automatic
  /// set is the best conditioned one there, and a set singular there is warned about.
  const Probe* reference = nullptr;
};

/// The partition: # (independent) and ⋆ (dependent) speeds. `symbolic` when the
/// dependent block can be solved exactly at generation time: it is triangular with
/// state-free pivots (`triangular_order` lists (row, speed) in substitution order), or
/// small with a state-free determinant. Otherwise the block is solved numerically.
struct Partition {
  std::vector<int> independent;
  std::vector<int> dependent;
  bool symbolic = false;
  std::vector<std::pair<int, int>> triangular_order;
};

/// Checks that the rows of B are independent (else names the redundant constraint)
/// and picks the partition. Errors go to the constraint or `independent` statement; a
/// warning to the `independent` statement (or the node) when the set is singular at the
/// reference configuration.
std::optional<Partition> choose_partition(const ComplementInput& in, Diagnostics& diags);

}  // namespace mbsc::sym
