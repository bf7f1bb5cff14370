// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// The values a model may give (docs/language.md, "Limits"): real numbers of magnitude
/// at most limits::kMaxValue. The generated code computes in doubles, and M and h
/// multiply a handful of the model's values in each entry; bounding each value keeps
/// those products finite, so that `check` can refuse at the element what the lowering
/// (ir/from_ginac.cpp) would otherwise meet as a constant beyond a double, or a NaN.
#include <ginac/ginac.h>

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace mbsc::model {

/// A number, or a constant part of an expression, the generated code cannot compute with.
struct ValueProblem {
  std::string part;       // the offending number or constant part, as printed (cut when long)
  bool not_real = false;  // not a finite real number (a complex constant, a NaN, an overflow)
  double value = 0.0;     // its value when real (beyond the bound)
  bool number = false;    // `part` is the number itself, not an expression of numbers
  /// "sqrt(-2) is not a finite real number", "2e+307 is larger in magnitude than 1e+30 ...".
  std::string text() const;
  /// A value (a parameter's default, a --freeze value) beyond the bound.
  static ValueProblem too_large(double value);
};

/// The first number or constant part of `e` (a function of numbers, evaluated in double
/// arithmetic as the generated code evaluates it) that is not a finite real number or
/// whose magnitude exceeds limits::kMaxValue; nullopt when there is none.
std::optional<ValueProblem> value_problem(const GiNaC::ex& e);

/// The value of a constant expression (numbers, pi, functions of them) in double
/// arithmetic, as the generated code computes it (NaN or infinite when undefined there);
/// nullopt when e holds a symbol or something the generated code has no function for.
std::optional<double> constant_value(const GiNaC::ex& e);

/// The same with symbols given double values (no exact arithmetic, so nothing GiNaC
/// could throw or fold for hours: t^t^t at t = 10 is simply infinite); nullopt when e
/// holds another symbol or a function the walk does not know.
std::optional<double> value_at(const GiNaC::ex& e, const std::vector<std::pair<GiNaC::ex, double>>& values);

/// f(a) or f(a, b) in double arithmetic, by the name of the GiNaC function (the model
/// language's functions and csgn, what the lowering knows, as the generated code calls
/// them); false for another function or another number of arguments.
bool function_value(const std::string& f, const std::vector<double>& args, double& out);

}  // namespace mbsc::model
