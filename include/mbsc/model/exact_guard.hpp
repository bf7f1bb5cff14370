// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// Guards for GiNaC's eager work. GiNaC folds numbers exactly as soon as an expression
/// is built: 3^(10^12), (3*x)^(10^12) (= 3^(10^12) x^(10^12)) or a product of 100 000
/// large constants would be computed digit by digit, for hours; and expand() or normal()
/// of (a + b + ... + h)^40 writes out hundreds of millions of terms. These functions
/// estimate the size first, cheaply, so that such an expression is refused
/// (limits::kMaxExactBits) or left unexpanded (limits::kMaxExpandedTerms).
#include <ginac/ginac.h>

#include <optional>
#include <string>

namespace mbsc::model {

/// Bits of the larger of numerator and denominator of an exact number (0 for a float),
/// over its real and imaginary parts.
std::size_t exact_bits(const GiNaC::numeric& n);

/// log2 |n| within a bit for an exact rational (bits of the numerator minus bits of the
/// denominator), without converting it to a double; 0 for anything else.
long binary_exponent(const GiNaC::numeric& n);

/// The real part of n as a double, saturating: +-HUGE_VAL past about 2^1100 (and when
/// CLN cannot convert), 0 below about 2^-1100. For estimates and messages.
double approx_double(const GiNaC::numeric& n);

/// e with the values of the symbols it holds, and only those, put in. GiNaC's own subs
/// tries every key of the map at every node of e, so with a map of all a model's
/// parameters or variables each call would cost the model's size.
GiNaC::ex subs_present(const GiNaC::ex& e, const GiNaC::exmap& values);

/// How many bits the exact numbers in e grow by per unit of an exponent, were e raised
/// to a power: a number's bits, a number's power's bits times its exponent, the sum over
/// a product's factors; 0 for anything else (a sum to a power stays unexpanded).
double growth_bits(const GiNaC::ex& e);

/// Why base^exponent would fold to an exact constant beyond the limit, or "".
std::string power_problem(const GiNaC::ex& base, const GiNaC::ex& exponent);

/// Why the product of `factors` would fold to an exact constant beyond the limit, or "".
std::string product_problem(const GiNaC::exvector& factors);

/// Why the sum of `terms` would fold to an exact constant beyond the limit (many
/// different denominators), or "".
std::string sum_problem(const GiNaC::exvector& terms);

/// e with `values` put in for symbols, rebuilt bottom-up so that every power, product
/// and sum is checked before GiNaC folds it. nullopt with `why` set when one would be too
/// large, or when GiNaC throws (a division by zero, a pole).
std::optional<GiNaC::ex> guarded_subs(const GiNaC::ex& e, const GiNaC::exmap& values, std::string& why);

/// An upper bound of the number of terms e.expand() writes out (saturating at 1e18).
double expanded_terms(const GiNaC::ex& e);

/// e.expand(), or e itself when the expansion would exceed limits::kMaxExpandedTerms
/// (the callers expand to simplify: without it they are still right, only less tidy).
GiNaC::ex expand_if_small(const GiNaC::ex& e);

/// e.normal(), or e itself when its numerator or denominator would expand beyond
/// limits::kMaxExpandedTerms.
GiNaC::ex normal_if_small(const GiNaC::ex& e);

}  // namespace mbsc::model
