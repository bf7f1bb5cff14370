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
  // In double arithmetic, as the runtime uses the values: no exact substitution, so
  // nothing for GiNaC to throw (log(0)) or to fold for hours (t^t^t at t = 10).
  const GiNaC::ex* parts[] = {&m.q, &m.qd, &m.qdd};
  for (std::size_t k = 0; k < 3; ++k) {
    const std::optional<double> value = model::value_at(*parts[k], {{m.t, t}});
    if (!value || !std::isfinite(*value)) {
      why = value ? fmt::format("{} is not finite at t = {:g} ({})", kWhat[k], t, std::isnan(*value) ? "nan" : *value > 0 ? "inf" : "-inf")
                  : fmt::format("{} cannot be evaluated at t = {:g}", kWhat[k], t);
      return false;
    }
    out[k] = *value;
  }
  return true;
}

}  // namespace mbsc::run
