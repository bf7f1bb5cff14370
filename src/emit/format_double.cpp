// SPDX-License-Identifier: GPL-2.0-or-later
// Shortest round-trip formatting of doubles, and their C++ literal spelling.
#include <charconv>
#include <cmath>
#include <stdexcept>
#include <string>

#include "mbsc/emit/generated_model.hpp"
#include "number_literal.hpp"

namespace mbsc::emit {

namespace {

// "1e-05" -> "1e-5", "6.02e+23" -> "6.02e23": no '+', no leading zeros in the exponent.
std::string tidy_exponent(const std::string& s) {
  const std::size_t e = s.find('e');
  if (e == std::string::npos) return s;
  std::string mant = s.substr(0, e);
  std::string sign;
  std::size_t i = e + 1;
  if (i < s.size() && (s[i] == '+' || s[i] == '-')) {
    if (s[i] == '-') sign = "-";
    ++i;
  }
  while (i + 1 < s.size() && s[i] == '0') ++i;
  return mant + "e" + sign + s.substr(i);
}

}  // namespace

// Try 1..17 significant digits in %g style until the text reads back as the same value.
// to_chars/from_chars are locale-independent (printf/strtod would follow LC_NUMERIC).
std::string format_double(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v < 0 ? "-inf" : "inf";
  char buf[64];
  std::string text;
  for (int precision = 1; precision <= 17; ++precision) {
    const auto res = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, precision);
    text.assign(buf, res.ptr);
    double back = 0.0;
    std::from_chars(text.data(), text.data() + text.size(), back);
    if (back == v) break;
  }
  return tidy_exponent(text);
}

// A literal of type double: integral-looking texts get ".0" so 1/2 never divides ints.
std::string cpp_double_literal(double v) {
  if (!std::isfinite(v)) throw std::runtime_error("cannot print non-finite constant " + format_double(v));
  std::string s = format_double(v);
  if (s.find_first_of(".e") == std::string::npos) s += ".0";
  return s;
}

}  // namespace mbsc::emit
