// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// One `--prescribe NAME="expr of t"` of `mbsc inverse`: the expression read with the
/// model language's syntax and functions, its first and second time derivatives taken
/// symbolically, and the three evaluated at a time. The motion must be defined and twice
/// differentiable wherever it is evaluated (every output time): log(t) at t = 0, abs(t-1)'
/// at t = 1 or t^t^t at t = 0 are not, and are the user's errors, not NaN in the solve.
#include <ginac/ginac.h>

#include <array>
#include <map>
#include <optional>
#include <string>

namespace mbsc::run {

struct PrescribedMotion {
  GiNaC::realsymbol t{"t"};  // real: abs(t-1)' is (t-1)/abs(t-1), not one with conjugate(t)
  GiNaC::ex q, qd, qdd;
};

/// Reads `text` as an expression of t and the parameters (`params`: name -> value); the
/// error is "--prescribe NAME:COL: error: ..." (columns of the expression as given).
std::optional<PrescribedMotion> read_prescribed_motion(const std::string& coord, const std::string& text,
                                                       const std::map<std::string, double>& params, std::string& error);

/// q(t), q'(t), q''(t), evaluated in double arithmetic as compiled code would (t put in
/// exactly, exact powers guarded: t^t^t at t = 10 is refused, not computed digit by
/// digit). False, with `why` ("its first derivative is undefined at t = 1 (division by
/// zero)"), when one of them is not a finite real number there.
bool motion_at(const PrescribedMotion& m, double t, std::array<double, 3>& out, std::string& why);

}  // namespace mbsc::run
