// SPDX-License-Identifier: GPL-2.0-or-later
// Named body rotations (docs/formulation.md, "Named body rotations"): which bodies placed
// by joints with coordinates get names R_<body>_<ij>, that a component holding such
// bodies is derived for each instance (its names are its own), and that the names are
// the written-out rotations at the probe point.
#include <catch2/catch.hpp>

#include <set>
#include <string>

#include "mbsc/driver/pipeline.hpp"
#include "same_reduced_equations.hpp"
#include "mbsc/sym/probe.hpp"

namespace {

std::optional<mbsc::model::Model> load(const std::string& file) {
  mbsc::Diagnostics diags;
  auto m = mbsc::driver::load_model(std::string(MBSC_SOURCE_DIR) + "/tests/data/spatial_joints/" + file, diags);
  INFO(diags.format());
  REQUIRE(m);
  return m;
}

std::set<std::string> named_bodies(const mbsc::model::Model& m) {
  std::set<std::string> out;
  for (const auto& n : m.nodes)
    if (n.rigid3d.named_rotation) out.insert(n.name);
  return out;
}

}  // namespace

TEST_CASE("named rotations: deep in a chain on the ground and under a free base", "[sym][spatial][names]") {
  // Two joints from the ground: written out, no names.
  const auto arm = load("arm_joint.mbs");
  CHECK(arm->kinematic_names.empty());
  CHECK(named_bodies(*arm).empty());
  // Six placed bodies (more than four): every one is named, so that each body's rows read
  // its parent's speeds alone (the tree recursion).
  const auto chain = load("chain6_joint.mbs");
  CHECK(named_bodies(*chain) == std::set<std::string>{"link1", "link2", "link3", "link4", "link5", "link6"});
  // Under a free base every placed body is named, in each instance.
  const auto pair = load("arm_pair_component.mbs");
  CHECK(named_bodies(*pair) == std::set<std::string>{"left.upper", "left.fore", "right.upper", "right.fore"});
  // Every name is its written-out value at the probe point (the Probe binds them in
  // definition order), and nothing in a written-out value is a name.
  for (const auto* m : {&*chain, &*pair}) {
    REQUIRE_FALSE(m->kinematic_names.empty());
    const GiNaC::exmap values = mbsc::model::kinematic_name_values(*m);
    mbsc::sym::Probe p(*m, {}, 7);
    for (const auto& k : m->kinematic_names) {
      const GiNaC::ex full = values.at(k.sym);
      for (const auto& other : m->kinematic_names) CHECK_FALSE(full.has(other.sym));
      CHECK(p.eval(k.sym) == Approx(p.eval(full)).margin(1e-13));
    }
  }
}

TEST_CASE("named rotations: a component is derived for each of its instances", "[sym][spatial][names][component]") {
  // A later instance derived by renaming the first instance's symbols would read the
  // first instance's rotation names; the derivation must equal one from scratch.
  const auto m = load("arm_pair_component.mbs");
  mbsc::Diagnostics diags;
  mbsc::sym::Options reuse, fresh;
  fresh.reuse_components = false;
  auto a = mbsc::sym::derive(*m, reuse, diags);
  auto b = mbsc::sym::derive(*m, fresh, diags);
  REQUIRE(a);
  REQUIRE(b);
  for (const auto& r : a->nodes) {
    INFO(m->nodes[static_cast<std::size_t>(r.node)].name);
    if (m->nodes[static_cast<std::size_t>(r.node)].rigid3d.named_rotation) CHECK_FALSE(r.from_component_cache);
  }
  const int nd = a->ndof();
  REQUIRE(nd == b->ndof());
  REQUIRE(nd == 16);
  mbsc_test::check_same_reduced_equations(*m, *a, *b);
}
