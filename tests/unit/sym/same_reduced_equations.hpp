// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// Test helper: two derivations of one model (e.g. with and without component reuse) give
// the same reduced mass matrix M and forcing h at random probe points, each evaluated
// with its own numeric solves bound (bind_solves).
#include <catch2/catch.hpp>

#include "bind_solves.hpp"
#include "mbsc/driver/pipeline.hpp"
#include "mbsc/sym/probe.hpp"

namespace mbsc_test {

inline void check_same_reduced_equations(const mbsc::model::Model& m, const mbsc::sym::Eom& a, const mbsc::sym::Eom& b) {
  const int nd = a.ndof();
  REQUIRE(nd == b.ndof());
  for (unsigned seed : {1u, 2u, 3u}) {
    mbsc::sym::Probe pa(m, {}, seed), pb(m, {}, seed);
    bind_solves(pa, m, a);
    bind_solves(pb, m, b);
    for (int i = 0; i < nd; ++i) {
      const double ha = pa.eval(mbsc::driver::finalize(m, a, a.h(i, 0)));
      const double hb = pb.eval(mbsc::driver::finalize(m, b, b.h(i, 0)));
      CHECK(ha == Approx(hb).epsilon(1e-10).margin(1e-12));
      for (int j = 0; j < nd; ++j) {
        const double Ma = pa.eval(mbsc::driver::finalize(m, a, a.M(i, j)));
        const double Mb = pb.eval(mbsc::driver::finalize(m, b, b.M(i, j)));
        CHECK(Ma == Approx(Mb).epsilon(1e-10).margin(1e-12));
      }
    }
  }
}

}  // namespace mbsc_test
