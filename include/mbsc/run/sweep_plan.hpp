// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// What `mbsc sweep` runs (docs/sweep.md): the rows of a sweep from its grids and its
/// sampled names, and the summary columns each row gets. Pure data and parsing: no model.
#include <cstdint>
#include <string>
#include <vector>

namespace mbsc::run {

/// `--grid NAME=FROM:TO:STEP` (FROM, FROM + STEP, ... up to TO, TO included to rounding),
/// `NAME=FROM:TO:logN` (N points spaced evenly in log, both ends included; FROM, TO > 0)
/// or `NAME=V1,V2,...` (those values).
struct SweepGrid {
  std::string name;
  std::vector<double> values;
};

/// `--sample 'NAME~LAW(A,B)'`: uniform(lo,hi), normal(mean,sd), loguniform(lo,hi) (lo > 0),
/// lognormal(mu,sigma) (exp of a normal with those).
struct SweepSample {
  enum class Law { Uniform, Normal, LogUniform, LogNormal };
  std::string name;
  Law law = Law::Uniform;
  double a = 0.0, b = 1.0;
};

bool parse_grid(const std::string& text, SweepGrid& out, std::string& error);
bool parse_sample(const std::string& text, SweepSample& out, std::string& error);

/// The rows: every combination of the grids' values (the first grid varies slowest), and
/// at each `per_point` rows whose sampled names are drawn from the generator seeded with
/// the row's seed. Row r's seed depends only on `seed` and r, so a row's values are the
/// same whatever ran before it (threads, ranks, a resumed sweep).
struct SweepPlan {
  std::vector<SweepGrid> grids;
  std::vector<SweepSample> samples;
  long per_point = 1;
  std::uint64_t seed = 1;

  long rows() const;
  /// The swept names: the grids', then the samples'.
  std::vector<std::string> names() const;
  /// Row r's values, in the order of names(); its seed in `row_seed`.
  std::vector<double> values(long r, std::uint64_t& row_seed) const;
};

/// Most rows a sweep may have.
constexpr long kMaxSweepRows = 100000000;

/// `--summary` items: `final` (every coordinate and speed at the end), `final:NAME`,
/// `max:NAME`, `min:NAME`, `mean:NAME`, `maxabs:NAME`, where NAME is a column of `mbsc
/// run`'s CSV (a coordinate, speed, output, input, kinetic, potential, energy) or
/// `energy_change` (|E - E0|). The statistics are over the output rows (every --dt-out).
struct SummarySpec {
  enum class Kind { Final, Max, Min, Mean, MaxAbs };
  Kind kind = Kind::Final;
  std::string column;  // "" with Final: every coordinate and speed
  std::string header() const;  // "final:x", "max:energy_change"
};

bool parse_summaries(const std::vector<std::string>& items, std::vector<SummarySpec>& out, std::string& error);

}  // namespace mbsc::run
