// SPDX-License-Identifier: GPL-2.0-or-later
// Massless bodies at the reference configuration (docs/language.md "Massless links"):
// for each model, `mbsc check` (with the same --freeze as the generated code) warns
// that massless bodies leave the reduced mass matrix singular at the reference
// configuration exactly when the generated rhs, called at that state (every coordinate,
// speed, input and t at 0), returns status 1. A singularity there that moves no massless
// body (a custom leaf's inertia, the spherical angles' pole) makes the rhs fail too but
// is not blamed on massless bodies.
#include <catch2/catch.hpp>
#include <string>
#include <vector>

#include "../cli/run_command.hpp"
#include "test_support.hpp"
#include "gantry_cable/gantry_cable.hpp"
#include "gantry_massless_cart/gantry_massless_cart.hpp"
#include "gantry_massless_cart_mult/gantry_massless_cart_mult.hpp"
#include "massless_rod_and_flywheel/massless_rod_and_flywheel.hpp"
#include "massless_rod_pendulum/massless_rod_pendulum.hpp"
#include "spherical_pendulum_angles/spherical_pendulum_angles.hpp"

using namespace mbsc_test;

namespace {

/// The generated rhs's status at the reference state, with the generated parameter defaults.
template <int Nx, int Nin, typename Rhs>
int status_at_reference(Rhs rhs, const double* p) {
  std::vector<double> x(Nx, 0.0), u(Nin + 1, 0.0), xd(Nx, 0.0);
  return rhs(0.0, x.data(), Nin > 0 ? u.data() : nullptr, p, xd.data());
}

struct Checked {
  bool massless_warning = false;
  std::string line;  // check's "massless bodies: ..." line
  std::string output;
};

Checked check(const std::string& model, const std::string& flags) {
  const auto r = run(std::string(MBSC_BINARY) + " check " + quote(std::string(MBSC_SOURCE_DIR) + "/" + model) + " " + flags);
  Checked c;
  c.output = r.output;
  REQUIRE(r.exit_code == 0);
  c.massless_warning = r.output.find("singular at the reference configuration (parameter defaults") != std::string::npos &&
                       r.output.find(": warning: ") != std::string::npos;
  const auto at = r.output.find("massless bodies: ");
  if (at != std::string::npos) c.line = r.output.substr(at, r.output.find('\n', at) - at);
  return c;
}

}  // namespace

TEST_CASE("massless warning at the reference configuration exactly when the rhs fails there", "[numeric][massless]") {
  namespace G = mbsc_gen::gantry_cable;
  namespace GC = mbsc_gen::gantry_massless_cart;
  namespace MR = mbsc_gen::massless_rod_pendulum;
  struct Case {
    const char* model;
    const char* flags;
    int status;
  };
  const Case cases[] = {
      {"tests/data/planar/gantry_crane.mbs", "", status_at_reference<G::kNx, G::kNin>(G::rhs, G::kParamDefaults)},
      {"tests/data/planar/gantry_crane.mbs", "--freeze M=0",
       status_at_reference<GC::kNx, GC::kNin>(GC::rhs, GC::kParamDefaults)},
      {"models/massless_rod_pendulum.mbs", "", status_at_reference<MR::kNx, MR::kNin>(MR::rhs, MR::kParamDefaults)},
  };
  for (const auto& c : cases) {
    INFO(c.model << " " << c.flags << ": rhs status " << c.status);
    const Checked k = check(c.model, c.flags);
    INFO(k.output);
    CHECK(c.status != 2);
    CHECK(k.massless_warning == (c.status == 1));
    // check's line says where M was found positive definite.
    CHECK(k.line.find(c.status == 1 ? "positive definite at a generic configuration but singular at the reference "
                                      "configuration, where massless bodies carry a motion"
                                    : "positive definite at a generic configuration and at the reference configuration") !=
          std::string::npos);
  }
  // The reviewer's case: the massless cart fails there, the massive one does not; the
  // multipliers form's [M -A^T; A 0] is singular at the same state.
  namespace GM = mbsc_gen::gantry_massless_cart_mult;
  CHECK(status_at_reference<GC::kNx, GC::kNin>(GC::rhs, GC::kParamDefaults) == 1);
  CHECK(status_at_reference<GM::kNx, GM::kNin>(GM::rhs, GM::kParamDefaults) == 1);
  CHECK(status_at_reference<G::kNx, G::kNin>(G::rhs, G::kParamDefaults) == 0);
}

TEST_CASE("massless warning: the tolerance follows M's scale", "[numeric][massless]") {
  // The same crane in micro units (masses in the nanogram range, a 1 mm cable): M's
  // entries are ~1e-15, far below any absolute tolerance. A massive cart is still
  // regular (no warning, rhs status 0) and a massless one still singular (warning, 1).
  namespace G = mbsc_gen::gantry_cable;
  for (const double cart : {1e-8, 0.0}) {
    std::vector<double> p(G::kParamDefaults, G::kParamDefaults + G::kNp);
    p[static_cast<std::size_t>(index_of(G::kParamNames, G::kNp, "M"))] = cart;
    p[static_cast<std::size_t>(index_of(G::kParamNames, G::kNp, "m"))] = 2e-9;
    p[static_cast<std::size_t>(index_of(G::kParamNames, G::kNp, "L"))] = 1e-3;
    const int status = status_at_reference<G::kNx, G::kNin>(G::rhs, p.data());
    INFO("cart mass " << cart << ": rhs status " << status);
    CHECK(status == (cart == 0.0 ? 1 : 0));
    const Checked k = check("tests/data/planar/gantry_crane.mbs", cart == 0.0 ? "--freeze M=0 m=2e-9 L=1e-3"
                                                                              : "--freeze M=1e-8 m=2e-9 L=1e-3");
    INFO(k.output);
    CHECK(k.massless_warning == (status == 1));
  }
}

TEST_CASE("massless bodies are not blamed for a singularity they do not move in", "[numeric][massless]") {
  namespace F = mbsc_gen::massless_rod_and_flywheel;
  namespace S = mbsc_gen::spherical_pendulum_angles;
  // The flywheel's inertia J sin(q)^2 vanishes at q = 0: the rhs fails there.
  CHECK(status_at_reference<F::kNx, F::kNin>(F::rhs, F::kParamDefaults) == 1);
  const Checked f = check("tests/data/planar/massless_rod_and_flywheel.mbs", "");
  INFO(f.output);
  CHECK_FALSE(f.massless_warning);
  CHECK(f.output.find(": warning: ") == std::string::npos);
  CHECK(f.line.find("singular at the reference configuration, in a motion that moves no massless body") != std::string::npos);
  // A massive model singular at its reference configuration (the pole of spherical angles).
  CHECK(status_at_reference<S::kNx, S::kNin>(S::rhs, S::kParamDefaults) == 1);
  const Checked s = check("models/spherical_pendulum_angles.mbs", "");
  INFO(s.output);
  CHECK(s.output.find(": warning: ") == std::string::npos);
  CHECK(s.line.empty());
}
