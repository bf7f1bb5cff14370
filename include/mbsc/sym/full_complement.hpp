// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// S = R C (thesis Thm 2.10): the complement of a subtree's whole constraint Jacobian,
/// over all the subtree's speeds. Not needed by the generated code (it only uses the
/// per-node C); used by `mbsc print` and by the tests (A S == 0).
#include <ginac/ginac.h>

#include <vector>

#include "mbsc/model/model.hpp"
#include "mbsc/sym/eom.hpp"

namespace mbsc::sym {

/// Speeds of the subtree rooted at node n, in model order.
std::vector<int> subtree_speeds(const model::Model& m, int n);

/// S: rows = subtree_speeds(n) (returned in `rows`), columns = the node's independent speeds.
GiNaC::matrix full_complement(const model::Model& m, const Eom& eom, int n, std::vector<int>& rows);

}  // namespace mbsc::sym
