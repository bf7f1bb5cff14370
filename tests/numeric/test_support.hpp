// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// Small helpers shared by the numeric tests: state lookup by name and RK4 runs.
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

namespace mbsc_test {

/// Index of `name` in a generated name list (throws when absent, so a renamed
/// variable fails the test loudly).
inline int index_of(const char* const* names, int n, const std::string& name) {
  for (int i = 0; i < n; ++i)
    if (name == names[i]) return i;
  throw std::runtime_error("no state named " + name);
}

}  // namespace mbsc_test

/// The runtime assembly's view of a generated full-state model (namespace NS).
#define MBSC_TEST_ASSEMBLY_MODEL(NS)                                                                                \
  mbsc::runtime::AssemblyModel {                                                                                    \
    NS::kNq, NS::kNu, NS::kNposc, NS::kNc, NS::position_constraints, NS::position_jacobian, NS::velocity_constraints, \
        NS::constraint_jacobian, NS::kPositionConstraintNames, NS::kConstraintNames                                 \
  }
