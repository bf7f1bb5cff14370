// SPDX-License-Identifier: GPL-2.0-or-later
#include "mbsc/model/value_bound.hpp"

#include <fmt/format.h>

#include <cmath>
#include <sstream>
#include <unordered_map>
#include <vector>

#include "mbsc/diag/limits.hpp"
#include "mbsc/model/exact_guard.hpp"

namespace mbsc::model {

namespace {

std::string printed(const GiNaC::ex& e) {
  if (GiNaC::is_a<GiNaC::numeric>(e) && GiNaC::ex_to<GiNaC::numeric>(e).is_real())
    return fmt::format("{:g}", approx_double(GiNaC::ex_to<GiNaC::numeric>(e)));
  std::ostringstream out;
  out << e;
  std::string text = out.str();
  if (text.size() > 60) text = text.substr(0, 57) + "...";
  return text;
}

/// One walk over an expression, bottom-up: the double value of every constant part, the
/// first problem met. A DAG (shared subexpressions) is walked once per node: values are
/// remembered by address, and the nodes kept alive while remembered (op(i) of a sum or
/// product may build a temporary whose address a later one reuses).
class Walk {
 public:
  explicit Walk(bool check, std::vector<std::pair<GiNaC::ex, double>> values = {})
      : check_(check), values_(std::move(values)) {}
  std::optional<ValueProblem> problem;

  std::optional<double> value(const GiNaC::ex& e) {
    if (GiNaC::is_a<GiNaC::numeric>(e)) return number(e);
    const GiNaC::basic* key = &GiNaC::ex_to<GiNaC::basic>(e);
    if (const auto it = seen_.find(key); it != seen_.end()) return it->second;
    const std::optional<double> v = inner(e);
    if (v) judge(e, *v);
    seen_.emplace(key, v);
    pinned_.push_back(e);
    return v;
  }

 private:
  std::optional<double> number(const GiNaC::ex& e) {
    const auto& n = GiNaC::ex_to<GiNaC::numeric>(e);
    if (!n.is_real()) {
      if (check_ && !problem) problem = ValueProblem{"the complex number " + printed(e), true, 0.0, false};
      return std::nullopt;
    }
    const double v = approx_double(n);
    if (check_ && !problem && !(std::fabs(v) <= limits::kMaxValue)) {
      // Beyond a double too (a product of frozen values): its magnitude, not "inf".
      const std::string text = std::isfinite(v) ? fmt::format("{:g}", v)
                                                : fmt::format("about 1e{:+d}", std::lround(static_cast<double>(binary_exponent(n)) * 0.30103));
      problem = ValueProblem{text, false, v, true};
    }
    return v;
  }

  std::optional<double> inner(const GiNaC::ex& e) {
    if (GiNaC::is_a<GiNaC::symbol>(e)) {
      for (const auto& [symbol, v] : values_)
        if (symbol.is_equal(e)) return v;
      return std::nullopt;
    }
    if (GiNaC::is_a<GiNaC::constant>(e)) {
      double v = NAN;
      try {
        const GiNaC::ex f = e.evalf();
        if (GiNaC::is_a<GiNaC::numeric>(f)) v = GiNaC::ex_to<GiNaC::numeric>(f).to_double();
      } catch (const std::exception&) {
      }
      return v;
    }
    // Every operand is walked (each may hold a problem of its own); the part is constant
    // when all of them are.
    std::vector<double> args;
    bool constant = true;
    for (std::size_t i = 0; i < e.nops(); ++i) {
      const std::optional<double> v = value(e.op(i));
      if (v) args.push_back(*v);
      else constant = false;
    }
    if (!constant) return std::nullopt;
    if (GiNaC::is_a<GiNaC::add>(e) || GiNaC::is_a<GiNaC::mul>(e)) {
      const bool sum = GiNaC::is_a<GiNaC::add>(e);
      double acc = sum ? 0.0 : 1.0;
      for (double a : args) acc = sum ? acc + a : acc * a;
      return acc;
    }
    if (GiNaC::is_a<GiNaC::power>(e)) return std::pow(args[0], args[1]);
    double out = 0.0;
    if (GiNaC::is_a<GiNaC::function>(e) && function_value(GiNaC::ex_to<GiNaC::function>(e).get_name(), args, out)) return out;
    return std::nullopt;
  }

  void judge(const GiNaC::ex& e, double v) {
    if (!std::isfinite(v)) note(e, true, 0.0);
    else if (std::fabs(v) > limits::kMaxValue) note(e, false, v);
  }

  void note(const GiNaC::ex& e, bool not_real, double v) {
    if (check_ && !problem) problem = ValueProblem{printed(e), not_real, v, false};
  }

  bool check_;
  std::vector<std::pair<GiNaC::ex, double>> values_;  // symbols with a value
  std::unordered_map<const GiNaC::basic*, std::optional<double>> seen_;
  std::vector<GiNaC::ex> pinned_;
};

}  // namespace

ValueProblem ValueProblem::too_large(double value) { return ValueProblem{fmt::format("{:g}", value), false, value, true}; }

std::string ValueProblem::text() const {
  if (not_real) return fmt::format("{} is not a finite real number", part);
  return fmt::format("{}{} is larger in magnitude than {:g}, the largest value a model may hold", part,
                     number ? "" : fmt::format(" = {:g}", value), limits::kMaxValue);
}

std::optional<ValueProblem> value_problem(const GiNaC::ex& e) {
  Walk walk(true);
  walk.value(e);
  return walk.problem;
}

std::optional<double> constant_value(const GiNaC::ex& e) {
  Walk walk(false);
  return walk.value(e);
}

std::optional<double> value_at(const GiNaC::ex& e, const std::vector<std::pair<GiNaC::ex, double>>& values) {
  Walk walk(false, values);
  return walk.value(e);
}

bool function_value(const std::string& f, const std::vector<double>& a, double& out) {
  if (a.size() == 2) {
    if (f != "atan2") return false;
    out = std::atan2(a[0], a[1]);
    return true;
  }
  if (a.size() != 1) return false;
  const double x = a[0];
  if (f == "sin") out = std::sin(x);
  else if (f == "cos") out = std::cos(x);
  else if (f == "tan") out = std::tan(x);
  else if (f == "exp") out = std::exp(x);
  else if (f == "log") out = std::log(x);
  else if (f == "abs") out = std::fabs(x);
  else if (f == "asin") out = std::asin(x);
  else if (f == "acos") out = std::acos(x);
  else if (f == "atan") out = std::atan(x);
  else if (f == "sinh") out = std::sinh(x);
  else if (f == "cosh") out = std::cosh(x);
  else if (f == "tanh") out = std::tanh(x);
  else if (f == "csgn") out = x > 0.0 ? 1.0 : x < 0.0 ? -1.0 : 0.0;
  else return false;
  return true;
}

}  // namespace mbsc::model
