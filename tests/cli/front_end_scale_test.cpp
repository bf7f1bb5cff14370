// SPDX-License-Identifier: GPL-2.0-or-later
// Big models stay cheap to check and generate (issue 11, generation in O(N log N); the
// figures and their growth are in docs/benchmarks.md, "Front end: scaling"). Each case
// ran for minutes before the front end's quadratic and cubic steps were removed (a has()
// per variable per matrix entry, dense products of mostly-zero matrices, a rank
// factorization per constraint row, pivot searches rescanning the whole matrix) and
// takes a second or two now: the budget leaves ten times that for slow machines and
// sanitizer builds, and stops the old behaviour long before it ends.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

#include "run_command.hpp"

namespace fs = std::filesystem;
using mbsc_test::fresh_dir;
using mbsc_test::quote;
using mbsc_test::run;

namespace {
// The sanitizer build (-O0, ASan) is about ten times slower: its budget is ten times larger.
const std::string kMbsc = std::string("timeout 600 ") + MBSC_BINARY;
const std::string kBudget = std::string(" --budget ") + SCALE_BUDGET;
}  // namespace

TEST_CASE("a chain of 150 parallelogram four-bars is checked well inside the budget", "[cli][scale]") {
  // 301 bodies, 451 pin constraints, 1 degree of freedom.
  const std::string chain = quote(std::string(MBSC_SOURCE_DIR) + "/models/parallelogram_chain.mbs");
  const auto r = run(kMbsc + " check " + chain + " --freeze N=150" + kBudget + " --quiet");
  INFO(r.output.substr(0, 2000));
  CHECK(r.exit_code == 0);
  CHECK(r.output.find("time budget") == std::string::npos);
}

TEST_CASE("400 free particles are generated well inside the budget", "[cli][scale]") {
  const fs::path dir = fresh_dir("scale_particles");
  {
    std::ofstream f(dir / "free.mbs");
    f << "model free_particles\nparameter m = 1, g = 9.81\ngravity (0, -g)\n"
         "for i = 1 to 400 { body b[i] : particle2d { mass m } }\n";
  }
  const auto r = run(kMbsc + " generate " + quote((dir / "free.mbs").string()) + kBudget + " --quiet -o " +
                     quote((dir / "out").string()));
  INFO(r.output.substr(0, 2000));
  CHECK(r.exit_code == 0);
  CHECK(fs::exists(dir / "out" / "free_particles" / "free_particles.cpp"));
  fs::remove_all(dir);
}
