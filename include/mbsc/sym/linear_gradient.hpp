// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// The derivatives of one expression by many symbols in one pass, for expressions that
/// are linear in them (the dependent rates of a chain: q1dot_k is a sum of a_kj q1dot_j
/// over every joint j before it). Differentiating such a sum by each of its n symbols
/// costs n traversals of n terms; here each term is visited once. Terms that nest the
/// symbols (a loop's rates from back substitution: products of sums that share their
/// subexpressions) are differentiated once per distinct subexpression, where GiNaC's
/// diff revisits a shared one on every path to it; a shape that is not linear (a symbol
/// in a power or a function) goes to diff.
#include <ginac/ginac.h>

#include <vector>

namespace mbsc::sym {

std::vector<GiNaC::ex> linear_gradient(const GiNaC::ex& e, const std::vector<GiNaC::symbol>& by);

}  // namespace mbsc::sym
