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
/// Operands of one sum or product written in a model (a + b + ... or a * b * ...).
constexpr std::size_t kMaxOperands = 100000;
/// Bits of the numerator or denominator of an exact constant while folding constants
/// (2^65536 is about 10^19728; a double reaches 10^308).
constexpr std::size_t kMaxExactBits = 65536;

}  // namespace mbsc::limits
