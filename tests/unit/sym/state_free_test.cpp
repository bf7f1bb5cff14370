// SPDX-License-Identifier: GPL-2.0-or-later
// is_state_free keeps an index of the parameters of the model it was last asked about
// (sym/probe.cpp): asking about two models in turn must not mix them up.
#include <catch2/catch.hpp>

#include "mbsc/driver/pipeline.hpp"
#include "mbsc/sym/probe.hpp"

namespace {

mbsc::model::Model load(const std::string& file) {
  mbsc::Diagnostics diags;
  auto m = mbsc::driver::load_model(std::string(MBSC_SOURCE_DIR) + "/models/" + file, diags);
  INFO(diags.format());
  REQUIRE(m);
  return *m;
}

}  // namespace

TEST_CASE("is_state_free against two models in turn", "[sym][scale]") {
  const auto a = load("double_pendulum.mbs");
  const auto b = load("four_bar.mbs");
  REQUIRE(!a.params.empty());
  REQUIRE(!b.params.empty());
  const GiNaC::ex pa = a.params.front().sym, pb = b.params.front().sym;
  for (int round = 0; round < 2; ++round) {
    CHECK(mbsc::sym::is_state_free(pa * pa + 2, a));
    CHECK_FALSE(mbsc::sym::is_state_free(pa, b));  // a's parameter is an unknown symbol in b
    CHECK(mbsc::sym::is_state_free(GiNaC::sin(pb) / 3, b));
    CHECK_FALSE(mbsc::sym::is_state_free(pb, a));
    CHECK_FALSE(mbsc::sym::is_state_free(pa * a.coords.front().sym, a));
    CHECK_FALSE(mbsc::sym::is_state_free(pb + b.speeds.front().sym, b));
    CHECK_FALSE(mbsc::sym::is_state_free(pa + a.time, a));
    CHECK(mbsc::sym::is_state_free(GiNaC::ex(7), b));
  }
}
