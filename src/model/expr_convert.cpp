// SPDX-License-Identifier: GPL-2.0-or-later
#include "mbsc/model/expr_convert.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "mbsc/diag/limits.hpp"
#include "mbsc/diag/name_suggestions.hpp"
#include "mbsc/model/exact_guard.hpp"
#include "mbsc/model/value_bound.hpp"

namespace mbsc::model {

GiNaC::numeric parse_decimal(const std::string& text_in) {
  if (!text_in.empty() && (text_in[0] == '-' || text_in[0] == '+'))
    return text_in[0] == '-' ? -parse_decimal(text_in.substr(1)) : parse_decimal(text_in.substr(1));
  const std::string& text = text_in;
  // Split mantissa digits, fraction length and exponent; build digits * 10^(exp - frac).
  std::string digits;
  long frac = 0;
  std::string exponent_text;
  bool in_frac = false;
  for (size_t i = 0; i < text.size(); ++i) {
    char c = text[i];
    if (c == '.') {
      in_frac = true;
    } else if (c == 'e' || c == 'E') {
      exponent_text = text.substr(i + 1);
      break;
    } else if (c >= '0' && c <= '9') {
      digits += c;
      if (in_frac) ++frac;
    } else {
      throw std::invalid_argument("malformed number");
    }
  }
  // Zero whatever its exponent (0e999999999999999999999 is a valid way to write 0).
  if (digits.find_first_not_of('0') == std::string::npos) return 0;
  // The lexer only lets through literals within double range and 100 characters, so the
  // exponent fits a long unless it is malformed (std::stol throws then).
  const long exponent = exponent_text.empty() ? 0 : std::stol(exponent_text);
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

namespace {

/// Why an exact real constant is out of what a double holds, or nullptr.
const char* out_of_double_range(const GiNaC::numeric& n) {
  if (!n.is_real() || n.is_zero()) return nullptr;
  if (binary_exponent(n) > 1025) return "too large for a double";
  if (binary_exponent(n) < -1023) return "too small for a double";
  try {
    const double d = n.to_double();
    if (!std::isfinite(d)) return "too large for a double";
    if (std::fabs(d) < DBL_MIN) return "too small for a double";
  } catch (const std::exception&) {
    return "out of the range of a double";
  }
  return nullptr;
}

/// The overall numeric coefficient of a sum, product or number (what constant folding
/// grows), if any.
std::optional<GiNaC::numeric> folded_coefficient(const GiNaC::ex& e) {
  if (GiNaC::is_a<GiNaC::numeric>(e)) return GiNaC::ex_to<GiNaC::numeric>(e);
  if ((GiNaC::is_a<GiNaC::add>(e) || GiNaC::is_a<GiNaC::mul>(e)) && e.nops() > 0) {
    const GiNaC::ex last = e.op(e.nops() - 1);
    if (GiNaC::is_a<GiNaC::numeric>(last)) return GiNaC::ex_to<GiNaC::numeric>(last);
  }
  return std::nullopt;
}

/// "f(a, b)" for messages, the arguments as GiNaC prints them (cut when long).
std::string call_text(const std::string& f, const std::vector<GiNaC::ex>& args) {
  std::ostringstream out;
  out << f << "(";
  for (std::size_t i = 0; i < args.size(); ++i) out << (i ? ", " : "") << args[i];
  out << ")";
  std::string text = out.str();
  if (text.size() > 60) text = text.substr(0, 56) + "...)";
  return text;
}

/// "about 1e+600" for a message about a constant a double cannot hold.
std::string magnitude_text(const GiNaC::numeric& n) {
  if (!n.is_rational()) return "";
  return fmt::format(" (about 1e{:+d})", std::lround(static_cast<double>(binary_exponent(n)) * 0.30103));
}

/// True when e holds no symbol (only numbers, pi and functions of them).
bool is_constant(const GiNaC::ex& e) {
  for (GiNaC::const_preorder_iterator it = e.preorder_begin(); it != e.preorder_end(); ++it)
    if (GiNaC::is_a<GiNaC::symbol>(*it)) return false;
  return true;
}

}  // namespace

bool ExprConverter::check_folded(const GiNaC::ex& e, const SourcePos& pos) {
  const auto c = folded_coefficient(e);
  if (!c) return true;
  if (exact_bits(*c) > limits::kMaxExactBits) {
    diags.error(pos, fmt::format("this expression folds to an exact constant of more than {} bits", limits::kMaxExactBits));
    return false;
  }
  if (const char* why = out_of_double_range(*c)) {
    diags.error(pos, fmt::format("this expression folds to a constant {}{}", why, magnitude_text(*c)));
    return false;
  }
  return true;
}

std::optional<GiNaC::ex> ExprConverter::power(const GiNaC::ex& base, const GiNaC::ex& exponent, const SourcePos& pos) {
  // Exact numbers to an exact power are evaluated at once by GiNaC: 2^(2^40) or
  // 10^1000000000 would be computed digit by digit. Refuse what would be too large.
  if (GiNaC::is_a<GiNaC::numeric>(base) && GiNaC::is_a<GiNaC::numeric>(exponent)) {
    const auto& b = GiNaC::ex_to<GiNaC::numeric>(base);
    const auto& x = GiNaC::ex_to<GiNaC::numeric>(exponent);
    if (b.is_zero() && !(x.is_real() && x.is_positive())) {
      diags.error(pos, fmt::format("0^{} is undefined", x.is_real() ? fmt::format("{}", approx_double(x)) : "z"));
      return std::nullopt;
    }
  }
  if (!is_constant(base) && GiNaC::is_a<GiNaC::numeric>(exponent) &&
      !(std::fabs(approx_double(GiNaC::ex_to<GiNaC::numeric>(exponent))) <= limits::kMaxExponent)) {
    diags.error(pos, fmt::format("the exponent of this power is larger than {:g} in magnitude", limits::kMaxExponent));
    return std::nullopt;
  }
  // (3*x)^n is 3^n x^n for GiNaC, and (a^r)^n is a^(r n): any numbers in the base count.
  if (const std::string why = power_problem(base, exponent); !why.empty()) {
    diags.error(pos, fmt::format("this power cannot be folded exactly: {}; write it with exp and log, e.g. "
                                 "exp(x*log(b)), to have it evaluated in floating point",
                                 why));
    return std::nullopt;
  }
  auto r = apply(pos, "^", [&] { return GiNaC::pow(base, exponent); });
  // A power of constants must be real, as in the generated code's std::pow: (-1)^(1/2)
  // is I for GiNaC, (-8)^(1/3) a complex root.
  if (r && is_constant(base) && is_constant(exponent)) {
    if (const auto problem = value_problem(*r); problem && problem->not_real) {
      std::ostringstream text;
      text << "(" << base << ")^(" << exponent << ")";
      diags.error(pos, fmt::format("{}{} is not a finite real number", element.empty() ? "" : element + ": ", text.str()));
      return std::nullopt;
    }
  }
  return r;
}

std::optional<GiNaC::ex> ExprConverter::apply(const SourcePos& pos, const std::string& what,
                                              const std::function<GiNaC::ex()>& op) {
  GiNaC::ex result;
  try {
    result = op();
  } catch (const std::exception& e) {
    // GiNaC evaluates functions of exact numbers at once: log(0), tan(pi/2), 0^(-1).
    const std::string why = e.what();
    diags.error(pos, fmt::format("{} is undefined{}", what,
                                 why.find("pole") != std::string::npos || why.find("log(0)") != std::string::npos ? " (a pole)"
                                 : why.find("division") != std::string::npos ? " (division by zero)"
                                                                             : " (" + why + ")"));
    return std::nullopt;
  }
  if (!check_folded(result, pos)) return std::nullopt;
  return result;
}

std::optional<GiNaC::ex> ExprConverter::chain(const ast::Expr& e) {
  // One GiNaC sum or product built from all the operands at once (n log n, not n^2),
  // after an estimate of the exact constant it folds to.
  const bool product = e.kind == ast::Expr::Kind::Product;
  GiNaC::exvector operands;
  operands.reserve(e.args.size());
  bool ok = true;
  for (std::size_t i = 0; i < e.args.size(); ++i) {
    auto v = convert(*e.args[i]);
    if (!v) {
      ok = false;
      continue;
    }
    const char op = i > 0 ? e.text.at(i - 1) : '+';
    if (op == '/' && v->is_zero()) {
      diags.error(e.args[i]->pos, "division by zero");
      ok = false;
      continue;
    }
    operands.push_back(op == '-' ? -*v : op == '/' ? GiNaC::pow(*v, -1) : *v);
  }
  if (!ok) return std::nullopt;
  const char* what = product ? "product" : "sum";
  if (const std::string why = product ? product_problem(operands) : sum_problem(operands); !why.empty()) {
    diags.error(e.pos, fmt::format("this {} cannot be folded exactly: {}", what, why));
    return std::nullopt;
  }
  return apply(e.pos, what,
               [&] { return product ? GiNaC::ex(GiNaC::mul(operands)) : GiNaC::ex(GiNaC::add(operands)); });
}

std::optional<GiNaC::ex> ExprConverter::convert(const ast::Expr& e) {
  struct Depth {
    int& d;
    explicit Depth(int& depth) : d(++depth) {}
    ~Depth() { --d; }
  };
  std::optional<GiNaC::ex> r;
  {
    Depth inner(depth_);
    r = convert_node(e);
  }
  if (depth_ == 0 && r) {
    if (const auto problem = value_problem(*r)) {
      diags.error(e.pos, element.empty() ? problem->text() : element + ": " + problem->text());
      return std::nullopt;
    }
  }
  return r;
}

std::optional<GiNaC::ex> ExprConverter::convert_node(const ast::Expr& e) {
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
        std::vector<std::string> known;
        for (const auto& f : kFunctions) known.push_back(f.name);
        diags.error(e.pos, fmt::format("unknown function '{}'{}", e.text, did_you_mean(e.text, known)));
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
      if (e.text == "pow") return power(args[0], args[1], e.pos);
      auto r = apply(e.pos, call_text(e.text, args), [&] { return apply_function(e.text, args); });
      if (!r) return std::nullopt;
      // A function of constants must be a finite real number: acos(2), log(-1) are not.
      bool constant = true;
      for (const auto& a : args) constant = constant && is_constant(a);
      if (constant) {
        double value = 0;
        if (!evaluate_number(*r, value)) {
          diags.error(e.pos, fmt::format("{} is not a finite real number", call_text(e.text, args)));
          return std::nullopt;
        }
        if (value != 0 && std::fabs(value) < DBL_MIN) {
          diags.error(e.pos, fmt::format("{} is too small for a double", call_text(e.text, args)));
          return std::nullopt;
        }
      }
      return r;
    }
    case K::Unary: {
      auto v = convert(*e.args.at(0));
      if (!v) return std::nullopt;
      return e.text == "-" ? -*v : *v;
    }
    case K::Sum:
    case K::Product:
      return chain(e);
    case K::Binary: {
      auto l = convert(*e.args.at(0));
      auto r = convert(*e.args.at(1));
      if (!l || !r) return std::nullopt;
      return power(*l, *r, e.pos);
    }
  }
  return std::nullopt;
}

}  // namespace mbsc::model
