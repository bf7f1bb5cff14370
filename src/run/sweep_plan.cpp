// SPDX-License-Identifier: GPL-2.0-or-later
// The rows of `mbsc sweep` (include/mbsc/run/sweep_plan.hpp). The sampled values come
// from std::mt19937_64 (fully specified by the standard) through our own transforms, so
// a seed gives the same values with any standard library.
#include "mbsc/run/sweep_plan.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fmt/format.h>
#include <random>

#include "mbsc/diag/diagnostics.hpp"

namespace mbsc::run {

namespace {

/// A finite number, the whole of `text`.
bool number(const std::string& text, double& v) {
  if (text.empty() || std::isspace(static_cast<unsigned char>(text[0]))) return false;
  char* end = nullptr;
  errno = 0;
  v = std::strtod(text.c_str(), &end);
  return end == text.c_str() + text.size() && errno != ERANGE && std::isfinite(v) &&
         text.find_first_of("xXnN") == std::string::npos;  // no hex, nan or inf
}

std::vector<std::string> split(const std::string& text, char sep) {
  std::vector<std::string> parts;
  std::size_t b = 0;
  for (std::size_t e; (e = text.find(sep, b)) != std::string::npos; b = e + 1) parts.push_back(text.substr(b, e - b));
  parts.push_back(text.substr(b));
  return parts;
}

bool valid_name(const std::string& name) {
  if (name.empty() || !(std::isalpha(static_cast<unsigned char>(name[0])) || name[0] == '_')) return false;
  for (char c : name)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.')) return false;
  return true;
}

constexpr long kMaxGridPoints = 1000000;

/// A seed per row: splitmix64 of the sweep's seed and the row (well spread even for
/// neighbouring rows).
std::uint64_t row_seed_of(std::uint64_t seed, long r) {
  std::uint64_t z = seed + 0x9e3779b97f4a7c15ULL * (static_cast<std::uint64_t>(r) + 1);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

/// Uniform in [0, 1) from 53 bits.
double uniform01(std::mt19937_64& g) { return static_cast<double>(g() >> 11) * 0x1.0p-53; }

/// Standard normal by Box-Muller (two uniforms per value).
double standard_normal(std::mt19937_64& g) {
  const double u1 = 1.0 - uniform01(g);  // (0, 1]
  const double u2 = uniform01(g);
  constexpr double kTwoPi = 6.283185307179586;
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(kTwoPi * u2);
}

}  // namespace

bool parse_grid(const std::string& text, SweepGrid& out, std::string& error) {
  auto fail = [&](const std::string& why) {
    error = fmt::format("--grid '{}': {}", printable(text), why);
    return false;
  };
  const std::size_t eq = text.find('=');
  if (eq == std::string::npos) return fail("expected NAME=FROM:TO:STEP, NAME=FROM:TO:logN or NAME=V1,V2,...");
  out.name = text.substr(0, eq);
  out.values.clear();
  if (!valid_name(out.name)) return fail(fmt::format("'{}' is not a name", printable(out.name)));
  const std::string rest = text.substr(eq + 1);
  if (rest.find(':') == std::string::npos) {
    for (const auto& item : split(rest, ',')) {
      double v = 0;
      if (!number(item, v)) return fail(fmt::format("'{}' is not a finite number", printable(item)));
      out.values.push_back(v);
    }
    return true;
  }
  const auto parts = split(rest, ':');
  double from = 0, to = 0;
  if (parts.size() != 3 || !number(parts[0], from) || !number(parts[1], to))
    return fail("expected NAME=FROM:TO:STEP or NAME=FROM:TO:logN with finite numbers");
  if (parts[2].rfind("log", 0) == 0) {
    double count = 0;
    if (!number(parts[2].substr(3), count) || count != std::floor(count) || count < 2 || count > kMaxGridPoints)
      return fail(fmt::format("logN takes a whole number of points from 2 to {}", kMaxGridPoints));
    if (!(from > 0 && to > 0)) return fail("a log grid needs FROM and TO above 0");
    const long n = static_cast<long>(count);
    for (long k = 0; k < n; ++k)
      out.values.push_back(k == n - 1 ? to : from * std::pow(to / from, static_cast<double>(k) / static_cast<double>(n - 1)));
    return true;
  }
  double step = 0;
  if (!number(parts[2], step) || !(step > 0)) return fail("STEP must be a positive number");
  if (to < from) return fail("TO must not lie below FROM");
  const double span = (to - from) / step;
  if (!(span < kMaxGridPoints)) return fail(fmt::format("more than {} points; choose a larger STEP", kMaxGridPoints));
  // TO is included when it lies within rounding of a whole number of steps (then exactly).
  const double whole = std::round(span);
  const bool to_on_grid = std::fabs(span - whole) <= 1e-9 * std::max(1.0, whole);
  const long n = (to_on_grid ? static_cast<long>(whole) : static_cast<long>(std::floor(span))) + 1;
  for (long k = 0; k < n; ++k) out.values.push_back(from + static_cast<double>(k) * step);
  if (to_on_grid) out.values.back() = to;
  return true;
}

bool parse_sample(const std::string& text, SweepSample& out, std::string& error) {
  auto fail = [&](const std::string& why) {
    error = fmt::format("--sample '{}': {}", printable(text), why);
    return false;
  };
  const std::size_t tilde = text.find('~');
  const std::size_t open = text.find('(', tilde == std::string::npos ? 0 : tilde);
  if (tilde == std::string::npos || open == std::string::npos || text.back() != ')')
    return fail("expected NAME~uniform(LO,HI), NAME~normal(MEAN,SD), NAME~loguniform(LO,HI) or NAME~lognormal(MU,SIGMA)");
  out.name = text.substr(0, tilde);
  if (!valid_name(out.name)) return fail(fmt::format("'{}' is not a name", printable(out.name)));
  const std::string law = text.substr(tilde + 1, open - tilde - 1);
  const auto args = split(text.substr(open + 1, text.size() - open - 2), ',');
  if (args.size() != 2 || !number(args[0], out.a) || !number(args[1], out.b))
    return fail("a law takes two finite numbers");
  if (law == "uniform" || law == "loguniform") {
    out.law = law == "uniform" ? SweepSample::Law::Uniform : SweepSample::Law::LogUniform;
    if (!(out.a < out.b)) return fail("LO must lie below HI");
    if (out.law == SweepSample::Law::LogUniform && !(out.a > 0)) return fail("loguniform needs LO above 0");
  } else if (law == "normal" || law == "lognormal") {
    out.law = law == "normal" ? SweepSample::Law::Normal : SweepSample::Law::LogNormal;
    if (!(out.b > 0)) return fail("the standard deviation must be above 0");
  } else {
    return fail(fmt::format("unknown law '{}' (known: uniform, normal, loguniform, lognormal)", printable(law)));
  }
  return true;
}

long SweepPlan::rows() const {
  long n = per_point;
  for (const auto& g : grids) {
    if (g.values.empty() || n > kMaxSweepRows / static_cast<long>(g.values.size())) return kMaxSweepRows + 1;
    n *= static_cast<long>(g.values.size());
  }
  return n;
}

std::vector<std::string> SweepPlan::names() const {
  std::vector<std::string> out;
  for (const auto& g : grids) out.push_back(g.name);
  for (const auto& s : samples) out.push_back(s.name);
  return out;
}

std::vector<double> SweepPlan::values(long r, std::uint64_t& row_seed) const {
  std::vector<double> out(grids.size() + samples.size());
  // The grid point: r / per_point in mixed radix, the last grid fastest.
  long point = r / per_point;
  for (std::size_t k = grids.size(); k-- > 0;) {
    const long size = static_cast<long>(grids[k].values.size());
    out[k] = grids[k].values[static_cast<std::size_t>(point % size)];
    point /= size;
  }
  row_seed = row_seed_of(seed, r);
  std::mt19937_64 g(row_seed);
  for (std::size_t k = 0; k < samples.size(); ++k) {
    const SweepSample& s = samples[k];
    double& v = out[grids.size() + k];
    switch (s.law) {
      case SweepSample::Law::Uniform: v = s.a + (s.b - s.a) * uniform01(g); break;
      case SweepSample::Law::LogUniform: v = std::exp(std::log(s.a) + (std::log(s.b) - std::log(s.a)) * uniform01(g)); break;
      case SweepSample::Law::Normal: v = s.a + s.b * standard_normal(g); break;
      case SweepSample::Law::LogNormal: v = std::exp(s.a + s.b * standard_normal(g)); break;
    }
  }
  return out;
}

std::string SummarySpec::header() const {
  const char* kind_name = kind == Kind::Final ? "final" : kind == Kind::Max ? "max" : kind == Kind::Min ? "min"
                          : kind == Kind::Mean ? "mean" : "maxabs";
  return column.empty() ? kind_name : std::string(kind_name) + ":" + column;
}

bool parse_summaries(const std::vector<std::string>& items, std::vector<SummarySpec>& out, std::string& error) {
  out.clear();
  for (const auto& item : items) {
    const std::size_t colon = item.find(':');
    const std::string kind = item.substr(0, colon);
    SummarySpec s;
    if (kind == "final") s.kind = SummarySpec::Kind::Final;
    else if (kind == "max") s.kind = SummarySpec::Kind::Max;
    else if (kind == "min") s.kind = SummarySpec::Kind::Min;
    else if (kind == "mean") s.kind = SummarySpec::Kind::Mean;
    else if (kind == "maxabs") s.kind = SummarySpec::Kind::MaxAbs;
    else {
      error = fmt::format("--summary: unknown item '{}' (known: final, final:NAME, max:NAME, min:NAME, mean:NAME, "
                          "maxabs:NAME)", printable(item));
      return false;
    }
    if (colon != std::string::npos) s.column = item.substr(colon + 1);
    if (s.column.empty() && (colon != std::string::npos || s.kind != SummarySpec::Kind::Final)) {
      error = fmt::format("--summary: '{}' needs a column: {}:NAME", printable(item), kind);
      return false;
    }
    for (const auto& o : out)
      if (o.header() == s.header()) {
        error = fmt::format("--summary: '{}' is given twice", printable(item));
        return false;
      }
    out.push_back(s);
  }
  return true;
}

}  // namespace mbsc::run
