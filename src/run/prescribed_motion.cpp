// SPDX-License-Identifier: GPL-2.0-or-later
#include "prescribed_motion.hpp"

#include <fmt/format.h>

#include <cmath>
#include <vector>

#include "mbsc/diag/diagnostics.hpp"
#include "mbsc/diag/name_suggestions.hpp"
#include "mbsc/model/exact_guard.hpp"
#include "mbsc/model/expr_convert.hpp"
#include "mbsc/model/value_bound.hpp"
#include "mbsc/parse/parse.hpp"

namespace mbsc::run {

namespace {

// The statement the expression is wrapped in, so the model language's own parser and
// converter read it (same syntax, functions and messages); its columns are shifted back.
constexpr const char* kWrapHead = "model prescribed\noutput value = ";

/// GiNaC's reason without its function's name: "log_eval(): log(0)" -> "log(0)".
std::string short_reason(const std::string& why) {
  const auto at = why.find("(): ");
  return at == std::string::npos ? why : why.substr(at + 4);
}

}  // namespace

std::optional<PrescribedMotion> read_prescribed_motion(const std::string& coord, const std::string& text,
                                                       const std::map<std::string, double>& params, std::string& error) {
  const std::string where = "--prescribe " + coord;
  if (text.find_first_of("\n\r;") != std::string::npos) {
    error = where + ": error: the expression must be one line (no newline or ';')";
    return std::nullopt;
  }
  const std::size_t shift = std::string(kWrapHead).size() - std::string("model prescribed\n").size();
  auto report = [&](const Diagnostics& diags) {
    for (const auto& d : diags.all())
      if (d.severity == Severity::Error) {
        const int col = d.pos.line == 2 ? d.pos.col - static_cast<int>(shift) : 0;
        error = where + (col > 0 ? ":" + std::to_string(col) : std::string()) + ": error: " + printable(d.message) + " in '" +
                printable(text) + "'";
        return;
      }
    error = where + ": error: cannot read the expression '" + printable(text) + "'";
  };
  Diagnostics diags;
  const auto file = parse::parse_text(kWrapHead + text + "\n", where, diags);
  if (!file || diags.has_errors() || file->statements.size() != 2 ||
      file->statements[1]->kind != ast::Statement::Kind::Output || !file->statements[1]->value) {
    report(diags);
    return std::nullopt;
  }
  PrescribedMotion m;
  std::vector<std::string> known = {"t", "pi"};
  for (const auto& [name, value] : params) known.push_back(name);
  model::ExprConverter conv(diags);
  conv.lookup = [&](const std::string& path, const SourcePos& pos, bool primed) -> std::optional<GiNaC::ex> {
    if (primed) {
      diags.error(pos, fmt::format("{}': a prescribed motion is written as a function of t, without derivatives", path));
      return std::nullopt;
    }
    if (path == "t") return GiNaC::ex(m.t);
    const auto it = params.find(path);
    if (it != params.end()) return GiNaC::ex(model::exact_decimal(it->second));
    diags.error(pos, fmt::format("unknown name '{}' (a prescribed motion is a function of t and the model's parameters){}", path,
                                 did_you_mean(path, known)));
    return std::nullopt;
  };
  const auto q = conv.convert(*file->statements[1]->value);
  if (!q || diags.has_errors()) {
    report(diags);
    return std::nullopt;
  }
  try {
    m.q = *q;
    m.qd = m.q.diff(m.t);
    m.qdd = m.qd.diff(m.t);
  } catch (const std::exception& e) {
    error = where + ": error: cannot differentiate '" + printable(text) + "': " + e.what();
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
