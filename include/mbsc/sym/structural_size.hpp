// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// The size of an expression by its structure, the same in every run: the nodes counted
/// with repetition, numbers free, and a product counted only when it joins two or more
/// factors. GiNaC holds a sum as s or as -(-s) by its run-dependent term order (it moves
/// the sign between the sum's terms and the coefficient of the product that holds it), and
/// a plain count of nodes sees the difference; sizes decide whether and how an expression
/// is simplified, so they must not (docs/backend.md "Determinism").
#include <ginac/ginac.h>

#include <cstddef>

namespace mbsc::sym {

/// The size of e, or limit + 1 as soon as it exceeds `limit`.
std::size_t structural_size(const GiNaC::ex& e, std::size_t limit);

}  // namespace mbsc::sym
