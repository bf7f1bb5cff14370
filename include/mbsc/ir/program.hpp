// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// The straight-line IR of one emitted function: canonical, hash-consed expression
/// nodes (independent of GiNaC's run-dependent term order), statements in emission
/// order, and operation counts.
#include <cstdint>
#include <string>
#include <vector>

#include "mbsc/ir/function_spec.hpp"

namespace mbsc::ir {

/// Operation counts of a Program (what `mbsc print --stats` and the banner report).
struct OpCount {
  long adds = 0;    // + and - (binary)
  long muls = 0;    // * (including squares)
  long divs = 0;    // /
  long calls = 0;   // sin, cos, sqrt, pow, exp, ...
  long solve_flops = 0;  // multiply-adds inside numeric LU solves (n^3/3 + n^2 k)
  long total() const { return adds + muls + divs + calls + solve_flops; }
};

struct Program;  // defined in src/ir (opaque to users of the back end)

/// Lowers a FunctionSpec: converts every expression to canonical DAG nodes, drops steps
/// no output needs, hoists sin/cos pairs, numbers temporaries by first use.
/// `bindings` maps input symbols to C++ text. Throws std::runtime_error on an
/// expression it cannot print (an unbound symbol, an unsupported function).
struct LoweredFunction {
  std::string name;
  std::string doc;
  std::string out_name;
  std::string out_shape;
  int nout = 0;
  std::string body;        // C++ statements of the function body (indented 2 spaces), ends with `return 0;`
  std::vector<std::string> used_args;  // which of "t","x","u","zdot","p" the body reads
  std::string third_arg = "u";         // FunctionSpec::third_arg
  std::string returns;     // when set, replaces the usual "Returns 0 on success, ..." of its declaration
  OpCount ops;
};

LoweredFunction lower(const FunctionSpec& spec, const std::vector<Binding>& bindings);

}  // namespace mbsc::ir
