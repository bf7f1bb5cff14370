// SPDX-License-Identifier: GPL-2.0-or-later
// A component instantiated twice is derived once and renamed for the second instance;
// the result must equal a derivation from scratch (same M and h at random states).
#include <catch2/catch.hpp>
#include <Eigen/Dense>
#include <random>

#include "mbsc/driver/pipeline.hpp"
#include "same_reduced_equations.hpp"
#include "mbsc/sym/probe.hpp"

TEST_CASE("component reuse equals a fresh derivation", "[sym][component]") {
  mbsc::Diagnostics diags;
  auto m = mbsc::driver::load_model(std::string(MBSC_SOURCE_DIR) + "/models/five_bar.mbs", diags);
  REQUIRE(m);
  mbsc::sym::Options reuse, fresh;
  fresh.reuse_components = false;
  auto a = mbsc::sym::derive(*m, reuse, diags);
  auto b = mbsc::sym::derive(*m, fresh, diags);
  REQUIRE(a);
  REQUIRE(b);
  int reused = 0;
  for (const auto& r : a->nodes) reused += r.from_component_cache;
  CHECK(reused == 3);  // linkage.right and its two bodies
  for (const auto& r : b->nodes) CHECK_FALSE(r.from_component_cache);
  REQUIRE(a->solves.size() == b->solves.size());
  // Compare the reduced mass matrix and forcing at random probe points, where every
  // numeric solve of each derivation is evaluated with its own opaque symbols.
  mbsc_test::check_same_reduced_equations(*m, *a, *b);
}
