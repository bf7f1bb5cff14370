// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// The LaTeX symbol of a model name, for `mbsc print --latex`: what a person would write
/// for it in a paper. Pure functions of the name (and of the `latex NAME "..."` overrides
/// a model gives); docs/language.md "Printing" lists the rules.
///
///   th1 -> \theta_{1}       l2 -> l_{2}         m_3 -> m_{3}        Omega -> \Omega
///   m_crank -> m_{\mathrm{crank}}   mUL -> m_{\mathrm{UL}}    Im -> I_{m}
///   crank.theta -> \theta_{\mathrm{crank}}    b.x -> x_{b}    crank_2.w -> w_{\mathrm{crank}_{2}}
///   motor_left.w -> w_{\mathrm{motor\_left}}  (bodies and subsystems are labels: words stay whole)
///   w1' -> \dot{w}_{1}      (a rate: one dot per prime, up to three)
///   anything else -> \mathrm{...} of the name as written
#include <map>
#include <string>

namespace mbsc::print {

/// The symbol of `name`: a dotted path of identifiers, possibly followed by primes.
std::string latex_symbol(const std::string& name);

/// As above, but a name (without its primes) found in `overrides` (full dotted name ->
/// LaTeX, from `latex` statements) prints as that text, braced so that a power or a
/// subscript after it stays valid; its rate as \dot{that text}.
std::string latex_symbol(const std::string& name, const std::map<std::string, std::string>& overrides);

/// A call of one of GiNaC's functions in LaTeX: sin(x) -> \sin\left(x\right),
/// asin -> \arcsin, log -> \ln, abs(x) -> \left|x\right|, atan2 -> \operatorname{atan2};
/// `args` is the LaTeX of the arguments, comma-separated.
std::string latex_call(const std::string& function, const std::string& args);

}  // namespace mbsc::print
