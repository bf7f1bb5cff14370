// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// Choice of the independent set # for the orthogonal complement C of B (thesis
/// (2.26)-(2.29), partition method), with rank and redundancy checks.
#include <ginac/ginac.h>

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "mbsc/diag/diagnostics.hpp"
#include "mbsc/model/model.hpp"
#include "mbsc/sym/probe.hpp"

namespace mbsc::sym {

/// What messages call the reference configuration.
inline const char* const kReferenceName = "the reference configuration (parameter defaults, coordinates and t at 0)";

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
  /// The model's start, assembled at generation time (sym/manifold_points.hpp), or null.
  /// The automatic set is checked there (and chosen there when the reference's choice is
  /// singular there), warnings speak of it, and a rank deficit of B there that the
  /// `nearby` points share is a redundancy of the mechanism.
  const Probe* start = nullptr;
  const std::vector<Probe>* nearby = nullptr;
  /// What the start is, for messages.
  std::string start_name = kReferenceName;
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
  /// Rank of B on the constraint manifold: the number of rows unless some are redundant
  /// where the constraints hold (independent at a generic point, dependent at every
  /// assembled one). Then the dependent block has more rows than speeds and is solved in
  /// the least-squares sense (exact on the manifold, thesis Section 4.5).
  int rank = 0;
  std::vector<int> redundant_rows;  // rows of B (indices) that do not raise that rank
};

/// Checks that the rows of B are independent (else names the redundant constraint)
/// and picks the partition. Errors go to the constraint or `independent` statement; a
/// warning to the `independent` statement (or the node) when the set is singular at the
/// reference configuration.
std::optional<Partition> choose_partition(const ComplementInput& in, Diagnostics& diags);

}  // namespace mbsc::sym
