// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// The absolute-coordinate mixed chain (tests/data/spatial_joints/mixed_absolute.mbs) that
// the spatial joint tests map their joint states onto: does a mapped state satisfy every
// one of its position and velocity rows?
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "mixed_absolute/mixed_absolute.hpp"

namespace mbsc_test {

inline void check_on_mixed_absolute_rows(const std::vector<double>& xa, const double* inputs, int trial) {
  namespace A = mbsc_gen::mixed_absolute;
  std::vector<double> g(static_cast<std::size_t>(A::kNposc)), c(static_cast<std::size_t>(A::kNc));
  REQUIRE(A::position_constraints(0.0, xa.data(), inputs, A::kParamDefaults, g.data()) == 0);
  REQUIRE(A::velocity_constraints(0.0, xa.data(), inputs, A::kParamDefaults, c.data()) == 0);
  for (std::size_t r = 0; r < g.size(); ++r) {
    INFO("position row " << r << " at trial " << trial);
    CHECK(std::fabs(g[r]) < 1e-12);
  }
  for (std::size_t r = 0; r < c.size(); ++r) {
    INFO("velocity row " << r << " at trial " << trial);
    CHECK(std::fabs(c[r]) < 1e-12);
  }
}

}  // namespace mbsc_test
