// SPDX-License-Identifier: GPL-2.0-or-later
// The rows of `mbsc sweep` (run/sweep_plan.hpp): grids with their end points, the order
// of combinations, sampled values that depend only on the seed and the row and follow
// their laws (moments of 20 000 draws against the closed forms), and the summaries.
#include <catch2/catch.hpp>

#include <cmath>

#include "mbsc/run/sweep_plan.hpp"

using namespace mbsc::run;

TEST_CASE("sweep grids: steps, log spacing and lists, TO included to rounding", "[sweep]") {
  SweepGrid g;
  std::string error;
  REQUIRE(parse_grid("m=1:2:0.1", g, error));
  REQUIRE(g.values.size() == 11);
  CHECK(g.values.front() == 1.0);
  CHECK(g.values.back() == 2.0);  // 10 steps of 0.1 reach 2 only to rounding: snapped
  CHECK(g.values[3] == Approx(1.3).epsilon(1e-15));
  REQUIRE(parse_grid("m=0:1:0.3", g, error));  // 1 is not on the grid
  REQUIRE(g.values.size() == 4);
  CHECK(g.values.back() == Approx(0.9).epsilon(1e-15));
  REQUIRE(parse_grid("g=1:1.00000000035:1e-10", g, error));  // not snapped to TO off the grid
  CHECK(g.values.size() == 4);
  CHECK(g.values.back() == Approx(1.0000000003).epsilon(1e-15));
  REQUIRE(parse_grid("k=1e3:1e5:log3", g, error));
  REQUIRE(g.values.size() == 3);
  CHECK(g.values[0] == 1e3);
  CHECK(g.values[1] == Approx(1e4).epsilon(1e-14));
  CHECK(g.values[2] == 1e5);
  REQUIRE(parse_grid("c=3,1.5,-2", g, error));
  CHECK(g.values == std::vector<double>{3, 1.5, -2});
  for (const char* bad : {"m", "=1:2:0.1", "m=1:2", "m=2:1:0.5", "m=1:2:-1", "m=1:2:0", "m=0:1:log2", "m=1:2:log1",
                          "m=1:2:log2.5", "m=1,,2", "m=nan", "m=1:inf:1", "m=1:2:1e-9", "3m=1,2"}) {
    INFO(bad);
    CHECK(!parse_grid(bad, g, error));
    CHECK(error.rfind("--grid '", 0) == 0);
  }
}

TEST_CASE("sweep rows: combinations in order, samples by seed and row alone", "[sweep]") {
  SweepPlan plan;
  std::string error;
  SweepGrid a, b;
  REQUIRE(parse_grid("a=1,2", a, error));
  REQUIRE(parse_grid("b=10,20,30", b, error));
  plan.grids = {a, b};
  SweepSample s;
  REQUIRE(parse_sample("c~uniform(-1,1)", s, error));
  plan.samples = {s};
  plan.per_point = 2;
  plan.seed = 42;
  REQUIRE(plan.rows() == 12);
  CHECK(plan.names() == std::vector<std::string>{"a", "b", "c"});
  std::uint64_t seed = 0, again = 0;
  // The first grid slowest, then the second, then the samples.
  const double expect_a[] = {1, 1, 1, 1, 1, 1, 2, 2, 2, 2, 2, 2};
  const double expect_b[] = {10, 10, 20, 20, 30, 30, 10, 10, 20, 20, 30, 30};
  std::vector<std::uint64_t> seeds;
  for (long r = 0; r < 12; ++r) {
    const auto v = plan.values(r, seed);
    CHECK(v[0] == expect_a[r]);
    CHECK(v[1] == expect_b[r]);
    CHECK((v[2] >= -1 && v[2] < 1));
    CHECK(plan.values(r, again) == v);  // the same row again: the same values
    CHECK(again == seed);
    seeds.push_back(seed);
  }
  std::sort(seeds.begin(), seeds.end());
  CHECK(std::unique(seeds.begin(), seeds.end()) == seeds.end());
  // Another sweep seed: other draws.
  SweepPlan other = plan;
  other.seed = 43;
  CHECK(other.values(0, seed)[2] != plan.values(0, again)[2]);
}

TEST_CASE("sampled laws have their moments", "[sweep]") {
  auto moments = [](const std::string& law, double& mean, double& sd) {
    SweepPlan plan;
    std::string error;
    SweepSample s;
    REQUIRE(parse_sample(law, s, error));
    plan.samples = {s};
    plan.per_point = 20000;
    double sum = 0, sum2 = 0;
    std::uint64_t seed;
    for (long r = 0; r < plan.per_point; ++r) {
      const double v = plan.values(r, seed)[0];
      sum += v;
      sum2 += v * v;
    }
    mean = sum / plan.per_point;
    sd = std::sqrt(sum2 / plan.per_point - mean * mean);
  };
  double mean, sd;
  // Standard errors of 20 000 draws: sd/141 for the mean, about sd/200 for sd; 5 of them allowed.
  moments("x~normal(40,4)", mean, sd);
  CHECK(std::fabs(mean - 40) < 5 * 4 / 141.0);
  CHECK(std::fabs(sd - 4) < 5 * 4 / 200.0);
  moments("x~uniform(2,5)", mean, sd);
  CHECK(std::fabs(mean - 3.5) < 5 * 0.866 / 141.0);
  CHECK(std::fabs(sd - 3 / std::sqrt(12.0)) < 5 * 0.866 / 200.0);
  // lognormal(0, 0.25): mean exp(sigma^2 / 2).
  moments("x~lognormal(0,0.25)", mean, sd);
  CHECK(std::fabs(mean - std::exp(0.25 * 0.25 / 2)) < 5 * 0.26 / 141.0);
  // loguniform(1, e): mean (e - 1) / ln(e) = e - 1.
  moments("x~loguniform(1,2.718281828459045)", mean, sd);
  CHECK(std::fabs(mean - (std::exp(1.0) - 1)) < 5 * 0.5 / 141.0);
  SweepSample s;
  std::string error;
  for (const char* bad : {"x", "x~normal(1,0)", "x~uniform(2,1)", "x~loguniform(0,1)", "x~cauchy(0,1)", "x~normal(1)",
                          "x~normal(1,2", "~normal(1,2)"}) {
    INFO(bad);
    CHECK(!parse_sample(bad, s, error));
  }
}

TEST_CASE("sweep summaries: kinds, columns, repeats", "[sweep]") {
  std::vector<SummarySpec> specs;
  std::string error;
  REQUIRE(parse_summaries({"final", "max:energy_change", "mean:x", "maxabs:w"}, specs, error));
  REQUIRE(specs.size() == 4);
  CHECK(specs[0].header() == "final");
  CHECK(specs[1].header() == "max:energy_change");
  CHECK(specs[3].kind == SummarySpec::Kind::MaxAbs);
  CHECK(!parse_summaries({"max"}, specs, error));
  CHECK(!parse_summaries({"median:x"}, specs, error));
  CHECK(!parse_summaries({"min:x", "min:x"}, specs, error));
  CHECK(!parse_summaries({"final:"}, specs, error));
}
