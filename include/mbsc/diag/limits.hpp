// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// The fixed limits on what a model may ask of the compiler, in one place. Each keeps
/// a hostile or mistaken input from crashing, hanging or exhausting the machine; each
/// is far above what a real model needs (docs/language.md, "Limits"). Going over one
/// is an error at the element that did it. The symbolic-work budget (time and memory),
/// which real big models may need to raise, is a command-line option instead
/// (driver/work_monitor.hpp).
#include <cstddef>

namespace mbsc::limits {

/// Bytes of one source file (the model or an included file).
constexpr std::size_t kMaxFileBytes = std::size_t{16} << 20;
/// Bytes of all the text read for one model, includes counted each time they are spliced.
constexpr std::size_t kMaxTotalBytes = std::size_t{64} << 20;
/// Include chains deeper than this are rejected (cycles are caught before).
constexpr std::size_t kMaxIncludeDepth = 64;
/// Include statements expanded for one model, in all (a file included twice counts twice).
constexpr std::size_t kMaxSplices = 10000;
/// Characters of one number literal.
constexpr std::size_t kMaxNumberChars = 100;
/// Nesting of parentheses, unary signs, powers and blocks in the parser.
constexpr int kMaxNesting = 200;
/// Nesting of `for` loops.
constexpr int kMaxLoopNesting = 32;
/// Tokens of one file after its `for` loops are expanded.
constexpr std::size_t kMaxExpandedTokens = std::size_t{4} << 20;
/// Tokens of the model and all its includes after expansion (includes counted each time).
constexpr std::size_t kMaxTotalTokens = std::size_t{16} << 20;
/// Subsystems (nodes and leaves, component instances included) of one model.
constexpr std::size_t kMaxNodes = 100000;
/// Operands of one sum or product written in a model (a + b + ... or a * b * ...).
constexpr std::size_t kMaxOperands = 100000;
/// Bits of the numerator or denominator of an exact constant while folding constants
/// (2^65536 is about 10^19728; a double reaches 10^308).
constexpr std::size_t kMaxExactBits = 65536;
/// Magnitude of a numeric exponent of a non-constant base (x^1000). Substitutions may
/// later put numbers into the base, (w/3)^n = 3^-n w^n, which GiNaC folds exactly.
constexpr double kMaxExponent = 1000;
/// Magnitude of a value a model gives: a number, a folded constant, a parameter's default
/// or --freeze value, a constant part of an expression (exp(80)). M and h multiply a
/// handful of values in doubles (a mass, lengths, gravity, a stiffness): ten of 1e30
/// stay below 1e300, inside a double's 1.8e308 (model/value_bound.hpp).
constexpr double kMaxValue = 1e30;
/// Nodes of a let's value written out as a tree, each let it uses put in place (a
/// chain `let b = a*a + a` triples at each line). A real named expression has hundreds.
constexpr std::size_t kMaxLetNodes = 10000;
/// Terms an expansion may write out where the compiler expands to simplify (more: the
/// expression is kept as it is).
constexpr double kMaxExpandedTerms = 20000;

}  // namespace mbsc::limits
