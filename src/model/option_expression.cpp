// SPDX-License-Identifier: GPL-2.0-or-later
// Command-line expressions (include/mbsc/model/option_expression.hpp).
#include "mbsc/model/option_expression.hpp"

#include <fmt/format.h>

#include <cfloat>
#include <cmath>
#include <vector>

#include "mbsc/diag/diagnostics.hpp"
#include "mbsc/diag/name_suggestions.hpp"
#include "mbsc/model/expr_convert.hpp"
#include "mbsc/model/value_bound.hpp"
#include "mbsc/parse/parse.hpp"

namespace mbsc::model {

namespace {

/// The text for a message: printable, and cut when long (an option may hold megabytes).
std::string shown(const std::string& text) {
  if (text.size() <= 80) return printable(text);
  return fmt::format("{}...' ({} characters", printable(text.substr(0, 60)), text.size());
}

/// The first error of `diags` as "'TEXT': column C: MESSAGE".
std::string first_error(const Diagnostics& diags, const std::string& text) {
  const std::string quoted = "'" + shown(text) + (text.size() > 80 ? ")" : "'");
  for (const auto& d : diags.all())
    if (d.severity == Severity::Error)
      return fmt::format("{}: {}{}", quoted, d.pos.col > 0 ? fmt::format("column {}: ", d.pos.col) : "",
                         printable(d.message));
  return quoted + " is not an expression";
}

}  // namespace

std::optional<GiNaC::ex> read_option_expression(const std::string& text, const OptionNames& names,
                                                const std::string& what_names, std::string& error) {
  Diagnostics diags;
  const ast::ExprPtr tree = parse::parse_expression(text, "<option>", diags);
  if (!tree) {
    error = first_error(diags, text);
    return std::nullopt;
  }
  std::vector<std::string> known = {"pi"};
  for (const auto& [name, value] : names) known.push_back(name);
  ExprConverter convert(diags);
  convert.lookup = [&](const std::string& path, const SourcePos& pos, bool primed) -> std::optional<GiNaC::ex> {
    if (primed) {
      diags.error(pos, fmt::format("{}': no rates here, only {}", path, what_names));
      return std::nullopt;
    }
    const auto it = names.find(path);
    if (it != names.end()) return it->second;
    diags.error(pos, fmt::format("unknown name '{}' (this option takes {}){}", path, what_names, did_you_mean(path, known)));
    return std::nullopt;
  };
  const std::optional<GiNaC::ex> e = convert.convert(*tree);
  if (!e || diags.has_errors()) {
    error = first_error(diags, text);
    return std::nullopt;
  }
  return e;
}

bool option_value(const std::string& text, const OptionNames& names, const std::string& what_names, double& value,
                  std::string& error) {
  const auto e = read_option_expression(text, names, what_names, error);
  if (!e) return false;
  // In double arithmetic, as the generated code computes (GiNaC's evalf loses exp of
  // a huge argument); GiNaC's only for what that walk has no function for.
  const std::optional<double> in_doubles = constant_value(*e);
  if (in_doubles) value = *in_doubles;
  if (in_doubles ? !std::isfinite(value) : !evaluate_number(*e, value)) {
    error = fmt::format("'{}' is not a finite real number", shown(text));
    return false;
  }
  if (value != 0 && std::fabs(value) < DBL_MIN) {
    error = fmt::format("'{}' is too small for a double (nonzero, but below about 2.2e-308)", shown(text));
    return false;
  }
  return true;
}

namespace {

std::string cpp_of(const ast::Expr& e, const std::map<std::string, std::string>& cpp_names) {
  using K = ast::Expr::Kind;
  switch (e.kind) {
    case K::Number: {
      const std::string d = fmt::format("{}", parse_decimal(e.text).to_double());
      return d.find_first_of(".en") == std::string::npos ? d + ".0" : d;
    }
    case K::Name: {
      if (e.text == "pi") return "3.141592653589793";
      const auto it = cpp_names.find(e.text);
      return it != cpp_names.end() ? it->second : "0.0";
    }
    case K::Call: {
      std::string args;
      for (const auto& a : e.args) args += (args.empty() ? "" : ", ") + cpp_of(*a, cpp_names);
      return "std::" + (e.text == "abs" ? std::string("fabs") : e.text) + "(" + args + ")";
    }
    case K::Unary: return "(" + e.text + cpp_of(*e.args.at(0), cpp_names) + ")";
    case K::Sum:
    case K::Product: {
      std::string out = "(" + cpp_of(*e.args.at(0), cpp_names);
      for (std::size_t i = 1; i < e.args.size(); ++i)
        out += fmt::format(" {} {}", e.text.at(i - 1), cpp_of(*e.args[i], cpp_names));
      return out + ")";
    }
    case K::Binary: return "std::pow(" + cpp_of(*e.args.at(0), cpp_names) + ", " + cpp_of(*e.args.at(1), cpp_names) + ")";
    case K::Prime: break;
  }
  return "0.0";
}

}  // namespace

std::string option_expression_cpp(const std::string& text, const std::map<std::string, std::string>& cpp_names) {
  Diagnostics diags;
  const ast::ExprPtr tree = parse::parse_expression(text, "<option>", diags);
  return tree ? cpp_of(*tree, cpp_names) : "0.0";
}

}  // namespace mbsc::model
