// SPDX-License-Identifier: GPL-2.0-or-later
#include "mbsc/model/expr_convert.hpp"

#include <fmt/format.h>

#include <cmath>

namespace mbsc::model {

GiNaC::numeric parse_decimal(const std::string& text_in) {
  if (!text_in.empty() && (text_in[0] == '-' || text_in[0] == '+'))
    return text_in[0] == '-' ? -parse_decimal(text_in.substr(1)) : parse_decimal(text_in.substr(1));
  const std::string& text = text_in;
  // Split mantissa digits, fraction length and exponent; build digits * 10^(exp - frac).
  std::string digits;
  long frac = 0, exponent = 0;
  bool in_frac = false;
  size_t i = 0;
  for (; i < text.size(); ++i) {
    char c = text[i];
    if (c == '.') {
      in_frac = true;
    } else if (c == 'e' || c == 'E') {
      exponent = std::stol(text.substr(i + 1));
      break;
    } else {
      digits += c;
      if (in_frac) ++frac;
    }
  }
  if (digits.empty()) digits = "0";
  GiNaC::numeric value(digits.c_str());
  long shift = exponent - frac;
  if (shift >= 0) return value * GiNaC::pow(GiNaC::numeric(10), GiNaC::numeric(shift));
  return value / GiNaC::pow(GiNaC::numeric(10), GiNaC::numeric(-shift));
}

GiNaC::numeric exact_decimal(double v) { return parse_decimal(fmt::format("{}", v)); }

bool evaluate_number(const GiNaC::ex& e, double& value) {
  try {
    GiNaC::ex v = GiNaC::evalf(e);
    if (!GiNaC::is_a<GiNaC::numeric>(v)) return false;
    const auto& n = GiNaC::ex_to<GiNaC::numeric>(v);
    if (!n.is_real()) return false;
    value = n.to_double();
    return std::isfinite(value);
  } catch (const std::exception&) {
    return false;
  }
}

namespace {

struct FunctionInfo {
  const char* name;
  int arity;
};
const FunctionInfo kFunctions[] = {{"sin", 1},  {"cos", 1},  {"tan", 1},  {"exp", 1},   {"log", 1},
                                   {"sqrt", 1}, {"abs", 1},  {"asin", 1}, {"acos", 1},  {"atan", 1},
                                   {"sinh", 1}, {"cosh", 1}, {"tanh", 1}, {"atan2", 2}, {"pow", 2}};

GiNaC::ex apply_function(const std::string& f, const std::vector<GiNaC::ex>& a) {
  if (f == "sin") return GiNaC::sin(a[0]);
  if (f == "cos") return GiNaC::cos(a[0]);
  if (f == "tan") return GiNaC::tan(a[0]);
  if (f == "exp") return GiNaC::exp(a[0]);
  if (f == "log") return GiNaC::log(a[0]);
  if (f == "sqrt") return GiNaC::sqrt(a[0]);
  if (f == "abs") return GiNaC::abs(a[0]);
  if (f == "asin") return GiNaC::asin(a[0]);
  if (f == "acos") return GiNaC::acos(a[0]);
  if (f == "atan") return GiNaC::atan(a[0]);
  if (f == "sinh") return GiNaC::sinh(a[0]);
  if (f == "cosh") return GiNaC::cosh(a[0]);
  if (f == "tanh") return GiNaC::tanh(a[0]);
  if (f == "atan2") return GiNaC::atan2(a[0], a[1]);
  return GiNaC::pow(a[0], a[1]);
}

}  // namespace

std::optional<GiNaC::ex> ExprConverter::convert(const ast::Expr& e) {
  using K = ast::Expr::Kind;
  switch (e.kind) {
    case K::Number:
      try {
        return GiNaC::ex(parse_decimal(e.text));
      } catch (const std::exception&) {
        diags.error(e.pos, fmt::format("malformed number '{}'", e.text));
        return std::nullopt;
      }
    case K::Name:
      if (e.text == "pi") return GiNaC::ex(GiNaC::Pi);
      return lookup(e.text, e.pos, false);
    case K::Prime: {
      const ast::Expr& inner = *e.args.at(0);
      if (inner.kind != K::Name) {
        diags.error(e.pos, "the derivative ' applies to a variable name only (x', not (x+y)' or x'')");
        return std::nullopt;
      }
      return lookup(inner.text, inner.pos, true);
    }
    case K::Call: {
      const FunctionInfo* info = nullptr;
      for (const auto& f : kFunctions)
        if (e.text == f.name) info = &f;
      if (!info) {
        diags.error(e.pos, fmt::format("unknown function '{}'", e.text));
        return std::nullopt;
      }
      if (static_cast<int>(e.args.size()) != info->arity) {
        diags.error(e.pos, fmt::format("function '{}' takes {} argument(s), {} given", e.text, info->arity, e.args.size()));
        return std::nullopt;
      }
      std::vector<GiNaC::ex> args;
      bool ok = true;
      for (const auto& a : e.args) {
        auto v = convert(*a);
        if (!v) ok = false;
        else args.push_back(*v);
      }
      if (!ok) return std::nullopt;
      return apply_function(e.text, args);
    }
    case K::Unary: {
      auto v = convert(*e.args.at(0));
      if (!v) return std::nullopt;
      return e.text == "-" ? -*v : *v;
    }
    case K::Binary: {
      auto l = convert(*e.args.at(0));
      auto r = convert(*e.args.at(1));
      if (!l || !r) return std::nullopt;
      if (e.text == "+") return *l + *r;
      if (e.text == "-") return *l - *r;
      if (e.text == "*") return *l * *r;
      if (e.text == "/") {
        if (r->is_zero()) {
          diags.error(e.pos, "division by zero");
          return std::nullopt;
        }
        return *l / *r;
      }
      return GiNaC::pow(*l, *r);
    }
  }
  return std::nullopt;
}

}  // namespace mbsc::model
