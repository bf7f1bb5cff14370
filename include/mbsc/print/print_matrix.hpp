// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// `mbsc print`: the labelled matrices of one subsystem, as text or LaTeX, in the form
/// a person writes them (print/display_simplify.hpp).
#include <ginac/ginac.h>

#include <string>
#include <vector>

#include "mbsc/model/model.hpp"
#include "mbsc/sym/eom.hpp"

namespace mbsc::print {

/// what: any of "eom" (M z' = h row by row), "M", "h", "invariants" (the constraints),
/// "rates", "A", "B", "C", "S", "f", "fbar". With `expand`, the named intermediates
/// (e_, r_), the numeric solves small enough for a closed form and the node's dependent
/// speeds (through its independent ones) are substituted. A "where" list after a run of
/// M, h, eom (and after B, C, S, f, fbar) holds what those entries read.
/// Throws std::invalid_argument for an unknown item.
std::string print_node(const model::Model& m, const sym::Eom& eom, int node, const std::vector<std::string>& what, bool latex,
                       bool expand = false);

/// One named intermediate that printed equations read, in evaluation order: an e_/r_
/// variable (value: its display form, through earlier intermediates) or one result of
/// a numeric solve X = A^-1 B (value: its closed form when affordable, else `solved`
/// is false and the value is the symbol itself).
struct Intermediate {
  GiNaC::symbol sym;
  GiNaC::ex value;
  bool from_solve = false;
  bool solved = true;
};

/// What `print` shows for M and h of a node: the display forms of the entries and the
/// intermediates they read (empty after a full expansion).
struct PrintedEquations {
  std::vector<std::vector<GiNaC::ex>> M, h;
  std::vector<Intermediate> where;
  bool numeric_solves = false;  // the node's equations go through numeric solves (X_ symbols)
  bool all_closed = true;       // every solve had an affordable closed form
};
PrintedEquations printed_equations(const model::Model& m, const sym::Eom& eom, int node, bool expand);

}  // namespace mbsc::print
