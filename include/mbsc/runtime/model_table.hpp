// SPDX-License-Identifier: GPL-2.0-or-later WITH mbsc-runtime-exception
// (see LICENSE: this header may be included in applications under any terms)
#pragma once
/// One generated model seen through plain data and function pointers, so that the
/// runtime's simulation, assembly, projection and inverse-dynamics code is written once
/// for every model (and `mbsc run` can load a compiled model from a shared object).
///
///   #include "four_bar/four_bar.hpp"
///   #include "mbsc/runtime/model_table.hpp"
///   const mbsc::runtime::ModelTable m = MBSC_MODEL_TABLE(mbsc_gen::four_bar);
///
/// The macro needs the model generated with every function (the default of
/// `mbsc generate`). `multipliers` tells the Lagrange-multiplier form (whose last two
/// parameters are the Baumgarte gains alpha, beta) from the complement form; models of
/// the complement form have null `multipliers_fn` / `reaction_forces`.
#include <cstring>
#include <string>
#include <vector>

namespace mbsc::runtime {

struct ModelTable {
  using Fn = int (*)(double, const double*, const double*, const double*, double*);
  using PartitionFn = int (*)(int, double, const double*, const double*, const double*, double*);

  int nq, nu, nx, ndof, nin, np, nc, nposc, ny, npartitions;
  int nq_full, nu_full;  // equal to nq, nu for the full state; larger for --state minimal
  bool multipliers;      // --formulation multipliers

  const char* const* state_names;                // nx
  const char* const* dof_names;                  // ndof
  const char* const* input_names;                // nin (one empty name when nin == 0)
  const char* const* param_names;                // np
  const char* const* constraint_names;           // nc
  const char* const* position_constraint_names;  // nposc
  const char* const* output_names;               // ny
  const char* const* partition_names;            // npartitions
  const char* const* full_state_names;           // nq_full + nu_full (= state_names for the full state)
  const double* param_defaults;                  // np

  Fn rhs, mass_matrix, forcing, position_constraints, velocity_constraints, constraint_jacobian, position_jacobian,
      energy, outputs, full_state, conditioning;
  PartitionFn rhs_partition, conditioning_partition;
  Fn multipliers_fn, reaction_forces;  // multipliers form only, else nullptr
  /// inverse_dynamics(t, x, zdot, p, u): the inputs giving the independent accelerations
  /// zdot (kNdof); both forms. Its third argument is zdot, not the inputs.
  Fn inverse_dynamics;
  /// rhs_jacobian(t, x, u, p, OUT): OUT = (dxdot/dx, nx x nx, then dxdot/du, nx x nin),
  /// row-major; inverse_dynamics_jacobian(t, x, zdot, p, OUT): (du/dx, nin x nx, then
  /// du/dzdot, nin x ndof). Null where the code was generated without them (the
  /// MBSC_MODEL_TABLE macros set them null: assign them for a model generated with
  /// --derivatives).
  Fn rhs_jacobian = nullptr;
  Fn inverse_dynamics_jacobian = nullptr;

  bool full_state_layout() const { return nq == nq_full && nu == nu_full; }
  /// names[0..n) as strings (for messages and column lists).
  static std::vector<std::string> names_of(const char* const* names, int n) {
    return std::vector<std::string>(names, names + n);
  }
  /// Index of `name` in names[0..n), or -1.
  static int find(const char* const* names, int n, const char* name) {
    for (int i = 0; i < n; ++i)
      if (std::strcmp(names[i], name) == 0) return i;
    return -1;
  }
};

}  // namespace mbsc::runtime

/// A ModelTable for the generated namespace NS (e.g. mbsc_gen::four_bar), complement form.
#define MBSC_MODEL_TABLE(NS)                                                                                          \
  ::mbsc::runtime::ModelTable {                                                                                      \
    NS::kNq, NS::kNu, NS::kNx, NS::kNdof, NS::kNin, NS::kNp, NS::kNc, NS::kNposc, NS::kNy, NS::kNpartitions,         \
        NS::kNqFull, NS::kNuFull, false, NS::kStateNames, NS::kDofNames, NS::kInputNames, NS::kParamNames,           \
        NS::kConstraintNames, NS::kPositionConstraintNames, NS::kOutputNames, NS::kPartitionNames, NS::kFullStateNames, \
        NS::kParamDefaults, &NS::rhs, &NS::mass_matrix, &NS::forcing, &NS::position_constraints,                     \
        &NS::velocity_constraints, &NS::constraint_jacobian, &NS::position_jacobian, &NS::energy, &NS::outputs,      \
        &NS::full_state, &NS::conditioning, &NS::rhs_partition, &NS::conditioning_partition, nullptr, nullptr,       \
        &NS::inverse_dynamics, nullptr, nullptr                                                                      \
  }

/// The same for a model generated with --formulation multipliers.
#define MBSC_MODEL_TABLE_MULTIPLIERS(NS)                                                                              \
  ::mbsc::runtime::ModelTable {                                                                                      \
    NS::kNq, NS::kNu, NS::kNx, NS::kNdof, NS::kNin, NS::kNp, NS::kNc, NS::kNposc, NS::kNy, NS::kNpartitions,         \
        NS::kNqFull, NS::kNuFull, true, NS::kStateNames, NS::kDofNames, NS::kInputNames, NS::kParamNames,            \
        NS::kConstraintNames, NS::kPositionConstraintNames, NS::kOutputNames, NS::kPartitionNames, NS::kFullStateNames, \
        NS::kParamDefaults, &NS::rhs, &NS::mass_matrix, &NS::forcing, &NS::position_constraints,                     \
        &NS::velocity_constraints, &NS::constraint_jacobian, &NS::position_jacobian, &NS::energy, &NS::outputs,      \
        &NS::full_state, &NS::conditioning, &NS::rhs_partition, &NS::conditioning_partition, &NS::multipliers,       \
        &NS::reaction_forces, &NS::inverse_dynamics, nullptr, nullptr                                                \
  }
