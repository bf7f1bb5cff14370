// SPDX-License-Identifier: GPL-2.0-or-later
#include "prescribed_motion.hpp"

#include <fmt/format.h>

#include <cmath>
#include <vector>

#include "mbsc/diag/diagnostics.hpp"
#include "mbsc/model/exact_guard.hpp"
#include "mbsc/model/expr_convert.hpp"
#include "mbsc/model/option_expression.hpp"
#include "mbsc/model/value_bound.hpp"

namespace mbsc::run {

namespace {

/// GiNaC's reason without its function's name: "log_eval(): log(0)" -> "log(0)".
std::string short_reason(const std::string& why) {
  const auto at = why.find("(): ");
  return at == std::string::npos ? why : why.substr(at + 4);
}

}  // namespace

std::optional<PrescribedMotion> read_prescribed_motion(const std::string& coord, const std::string& text,
                                                       const std::map<std::string, double>& params, std::string& error) {
  PrescribedMotion m;
  model::OptionNames names = {{"t", m.t}};
  for (const auto& [name, value] : params) names[name] = model::exact_decimal(value);
  std::string why;
  const auto q = model::read_option_expression(text, names, "t and the model's parameters", why);
  if (!q) {
    error = "--prescribe " + printable(coord) + ": error: " + why;
    return std::nullopt;
  }
  try {
    m.q = *q;
    m.qd = m.q.diff(m.t);
    m.qdd = m.qd.diff(m.t);
  } catch (const std::exception& e) {
    error = "--prescribe " + printable(coord) + ": error: cannot differentiate '" + printable(text) + "': " + e.what();
    return std::nullopt;
  }
  return m;
}

bool motion_at(const PrescribedMotion& m, double t, std::array<double, 3>& out, std::string& why) {
  static const char* const kWhat[] = {"it", "its first derivative", "its second derivative"};
  const GiNaC::exmap at = {{m.t, model::exact_decimal(t)}};
  const GiNaC::ex* parts[] = {&m.q, &m.qd, &m.qdd};
  for (std::size_t k = 0; k < 3; ++k) {
    std::string reason;
    const std::optional<GiNaC::ex> v = model::guarded_subs(*parts[k], at, reason);
    std::optional<double> value;
    if (v) {
      value = model::constant_value(*v);
      double d = 0.0;  // a function the double walk does not know: GiNaC's evaluation
      if (!value && model::evaluate_number(*v, d)) value = d;
      if (!value || !std::isfinite(*value)) {
        why = fmt::format("{} is not a finite real number at t = {:g}", kWhat[k], t);
        return false;
      }
    }
    if (!reason.empty()) {  // GiNaC's exception (log(0)), or the guard of exact powers
      const bool huge = reason.find("exact value") != std::string::npos;
      why = fmt::format("{} is {} at t = {:g} ({})", kWhat[k], huge ? "too large for a double" : "undefined", t,
                        short_reason(reason));
      return false;
    }
    out[k] = *value;
  }
  return true;
}

}  // namespace mbsc::run
