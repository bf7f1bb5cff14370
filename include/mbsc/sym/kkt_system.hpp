// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// The dependent-coordinate equations of a model over all its speeds, kept sparse:
///   My q1' - A^T lambda = hy        (every speed's own effective force, sym/own_force)
///   A q1' + b = 0                   (every constraint at order 2)
/// with A = d(velocity residuals)/d q1 and b the order-2 invariants at q1' = 0. Both the
/// multipliers formulation and the O(N) right-hand side (sym/kkt_elimination.hpp) start
/// from it. Only nonzero entries are stored and every derivative is taken with respect to
/// the symbols an expression contains, so building it costs O(size of the model).
#include <ginac/ginac.h>

#include <vector>

#include "mbsc/model/model.hpp"

namespace mbsc::sym {

/// One structurally nonzero entry of a sparse row.
struct KktEntry {
  int col = 0;
  GiNaC::ex value;
};

struct KktSystem {
  std::vector<std::vector<KktEntry>> My;  // per speed: nonzero My(i, j), by ascending j
  std::vector<GiNaC::ex> hy;              // per speed: own force at q1' = 0
  std::vector<std::vector<KktEntry>> A;   // per constraint: nonzero A(r, j), by ascending j
  std::vector<GiNaC::ex> velocity;        // per constraint: velocity residual A q1 + a
  std::vector<GiNaC::ex> b;               // per constraint: order-2 invariant at q1' = 0
  std::vector<GiNaC::ex> g;               // per constraint: position residual (0 for velocity constraints)
};

KktSystem kkt_system(const model::Model& m);

/// Indices (into `index`'s values) of the symbols `e` contains, ascending, each once.
std::vector<int> symbols_in(const GiNaC::ex& e, const GiNaC::exmap& index);


}  // namespace mbsc::sym
