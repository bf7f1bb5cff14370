// SPDX-License-Identifier: GPL-2.0-or-later
// Ranks on the mechanism (docs/formulation.md, "Redundant constraints"; issue 26): what
// `check` says where rows are redundant wherever the constraints hold, where the start is
// a singular pose, and where the automatic independent set must come from the start.
#include <catch2/catch.hpp>
#include <filesystem>
#include <string>

#include "run_command.hpp"

using namespace mbsc_test;

namespace {
std::string data(const char* path) { return quote(std::string(MBSC_SOURCE_DIR) + "/tests/data/" + path); }
const std::string kMbsc = MBSC_BINARY;
bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }
}  // namespace

TEST_CASE("check: Bricard's linkage has one degree of freedom and one row redundant on the mechanism", "[cli]") {
  const auto r = run(kMbsc + " check " + data("redundant/bricard.mbs"));
  INFO(r.output);
  CHECK(r.exit_code == 0);
  CHECK(has(r.output, "model bricard: 1 degree(s) of freedom"));
  CHECK(has(r.output, "redundant on the mechanism: r5.align2 (independent at a generic configuration"));
  CHECK(has(r.output, "30 constraint(s), rank 29, 1 dof"));
  CHECK(has(r.output, "by least squares in generated code"));
  CHECK(has(r.output, "ranks: at a generic configuration and at the initial state"));
  CHECK(!has(r.output, "warning"));
}

TEST_CASE("check: the parallelogram's third crank is redundant on the mechanism", "[cli]") {
  const auto r = run(kMbsc + " check " + data("linear/parallelogram_redundant.mbs"));
  INFO(r.output);
  CHECK(r.exit_code == 0);
  CHECK(has(r.output, "1 degree(s) of freedom"));
  CHECK(has(r.output, "redundant on the mechanism: tip3.y"));
}

TEST_CASE("check: a singular start is not a redundancy", "[cli]") {
  const auto r = run(kMbsc + " check " + data("start/parallelogram_flat.mbs"));
  INFO(r.output);
  CHECK(r.exit_code == 0);
  CHECK(has(r.output, "1 degree(s) of freedom"));
  CHECK(!has(r.output, "redundant on the mechanism"));
  CHECK(has(r.output, "are singular at the initial state"));
  CHECK(has(r.output, "no set works there (the constraints themselves are singular there)"));
}

TEST_CASE("check: the automatic independent set is chosen where the model starts", "[cli]") {
  const auto r = run(kMbsc + " check " + data("start/skate_across.mbs"));
  INFO(r.output);
  CHECK(r.exit_code == 0);
  CHECK(has(r.output, "independent speeds: b.v, b.w"));
  CHECK(!has(r.output, "warning"));
}

TEST_CASE("generate: redundant rows refuse the tree-order solver", "[cli]") {
  const auto dir = fresh_dir("redundant_sparse");
  const auto r = run(kMbsc + " generate " + data("redundant/bricard.mbs") + " --solver sparse -o " + quote(dir.string()));
  std::filesystem::remove_all(dir);
  INFO(r.output);
  CHECK(r.exit_code == 1);
  CHECK(has(r.output, "--solver sparse: model 'bricard' has constraint rows that are redundant on the mechanism ('r5.align2' first)"));
}
