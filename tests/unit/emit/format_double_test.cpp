// SPDX-License-Identifier: GPL-2.0-or-later
#include <catch2/catch.hpp>

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "../../../src/emit/number_literal.hpp"
#include "mbsc/emit/generated_model.hpp"

using mbsc::emit::cpp_double_literal;
using mbsc::emit::format_double;

namespace {

double read_back(const std::string& s) {
  double v = 0.0;
  const auto res = std::from_chars(s.data(), s.data() + s.size(), v);
  REQUIRE(res.ec == std::errc());
  REQUIRE(res.ptr == s.data() + s.size());
  return v;
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

}  // namespace

TEST_CASE("format_double: shortest text of common values", "[emit]") {
  CHECK(format_double(1.0) == "1");
  CHECK(format_double(3.0) == "3");
  CHECK(format_double(0.1) == "0.1");
  CHECK(format_double(-2.5) == "-2.5");
  CHECK(format_double(0.5) == "0.5");
  CHECK(format_double(1e-12) == "1e-12");
  CHECK(format_double(1e-300) == "1e-300");
  CHECK(format_double(6.02e23) == "6.02e23");
  CHECK(format_double(9.81) == "9.81");
  CHECK(format_double(1.0 / 3.0) == "0.3333333333333333");
  CHECK(format_double(2.0 / 3.0) == "0.6666666666666666");
  CHECK(format_double(100000.0) == "1e5");
  CHECK(format_double(123456.0) == "123456");
  CHECK(format_double(0.0) == "0");
  CHECK(format_double(-0.0) == "-0");
  CHECK(format_double(std::numeric_limits<double>::infinity()) == "inf");
  CHECK(format_double(std::nan("")) == "nan");
}

TEST_CASE("format_double: round trip over many values", "[emit]") {
  std::vector<double> values = {1.0,  0.1,   1.0 / 3.0, 1e-300, -2.5, 6.02e23, 9.80665, 3.141592653589793, 2.718281828459045, 1e308,
                                -1e-5, 0.3,  0.7,       1.1,    2.2,  4.35,    1e15,    1e16, 1e17, 123456789.0,
                                std::numeric_limits<double>::min(), std::numeric_limits<double>::denorm_min(),
                                std::numeric_limits<double>::max(), std::numeric_limits<double>::epsilon()};
  // A deterministic spread of bit patterns over the whole finite range.
  std::uint64_t state = 0x9e3779b97f4a7c15ULL;
  for (int i = 0; i < 20000; ++i) {
    state ^= state << 13;
    state ^= state >> 7;
    state ^= state << 17;
    double v;
    std::memcpy(&v, &state, sizeof v);
    if (std::isfinite(v)) values.push_back(v);
  }
  for (double v : values) {
    const std::string s = format_double(v);
    INFO(s);
    CHECK(same_bits(read_back(s), v));
    CHECK(same_bits(read_back(format_double(-v)), -v));
  }
}

TEST_CASE("format_double: no fewer significant digits suffice", "[emit]") {
  for (double v : {0.1, 1.0 / 3.0, 9.81, 6.02e23, 1e-300, 2.0 / 7.0}) {
    const std::string s = format_double(v);
    std::string mant = s.substr(0, s.find('e'));
    int sig = 0;
    bool leading = true;
    for (char c : mant) {
      if (c < '0' || c > '9') continue;
      if (leading && c == '0') continue;
      leading = false;
      ++sig;
    }
    char buf[64];
    const auto res = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, sig - 1 > 0 ? sig - 1 : 1);
    if (sig > 1) CHECK_FALSE(read_back(std::string(buf, res.ptr)) == v);
  }
}

TEST_CASE("cpp_double_literal: always a double literal", "[emit]") {
  CHECK(cpp_double_literal(3.0) == "3.0");
  CHECK(cpp_double_literal(1.0) == "1.0");
  CHECK(cpp_double_literal(-2.0) == "-2.0");
  CHECK(cpp_double_literal(0.0) == "0.0");
  CHECK(cpp_double_literal(-0.0) == "-0.0");
  CHECK(cpp_double_literal(0.5) == "0.5");
  CHECK(cpp_double_literal(1e-300) == "1e-300");
  CHECK(cpp_double_literal(6.02e23) == "6.02e23");
  CHECK(cpp_double_literal(1e5) == "1e5");
  CHECK_THROWS_AS(cpp_double_literal(std::numeric_limits<double>::infinity()), std::runtime_error);
  CHECK_THROWS_AS(cpp_double_literal(std::nan("")), std::runtime_error);
}
