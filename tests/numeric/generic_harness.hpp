// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// One harness for every generated model: MBSC_GENERIC_MODEL(NS) names the common ABI of
// mbsc_gen::NS (README, "The generated ABI") in a struct, so templates can take any
// model. It fails to compile against a model that lacks a function or a size of the
// common set: that is half of what the generic ABI test checks.
#include <cmath>
#include <random>
#include <string>
#include <vector>

#define MBSC_GENERIC_MODEL(NS)                                                                        \
  struct NS##_abi {                                                                                   \
    static constexpr const char* kName = #NS;                                                         \
    static constexpr int kNq = mbsc_gen::NS::kNq, kNu = mbsc_gen::NS::kNu, kNx = mbsc_gen::NS::kNx;   \
    static constexpr int kNdof = mbsc_gen::NS::kNdof, kNin = mbsc_gen::NS::kNin;                      \
    static constexpr int kNp = mbsc_gen::NS::kNp, kNc = mbsc_gen::NS::kNc;                            \
    static constexpr int kNposc = mbsc_gen::NS::kNposc, kNy = mbsc_gen::NS::kNy;                      \
    static constexpr int kNqFull = mbsc_gen::NS::kNqFull, kNuFull = mbsc_gen::NS::kNuFull;            \
    static constexpr int kNxFull = mbsc_gen::NS::kNxFull;                                             \
    static constexpr int kNpartitions = mbsc_gen::NS::kNpartitions;                                   \
    static constexpr int kNblocks = mbsc_gen::NS::kNblocks;                                           \
    static constexpr const char* const* kStateNames = mbsc_gen::NS::kStateNames;                      \
    static constexpr const char* const* kFullStateNames = mbsc_gen::NS::kFullStateNames;              \
    static constexpr const char* const* kDofNames = mbsc_gen::NS::kDofNames;                          \
    static constexpr const char* const* kInputNames = mbsc_gen::NS::kInputNames;                      \
    static constexpr const char* const* kParamNames = mbsc_gen::NS::kParamNames;                      \
    static constexpr const char* const* kConstraintNames = mbsc_gen::NS::kConstraintNames;            \
    static constexpr const char* const* kPositionConstraintNames =                                    \
        mbsc_gen::NS::kPositionConstraintNames;                                                       \
    static constexpr const char* const* kOutputNames = mbsc_gen::NS::kOutputNames;                    \
    static constexpr const char* const* kPartitionNames = mbsc_gen::NS::kPartitionNames;              \
    static constexpr const char* const* kBlockNames = mbsc_gen::NS::kBlockNames;                      \
    static constexpr const double* kParamDefaults = mbsc_gen::NS::kParamDefaults;                     \
    static constexpr mbsc_test::Function rhs = mbsc_gen::NS::rhs;                                     \
    static constexpr mbsc_test::Function mass_matrix = mbsc_gen::NS::mass_matrix;                     \
    static constexpr mbsc_test::Function forcing = mbsc_gen::NS::forcing;                             \
    static constexpr mbsc_test::Function inverse_dynamics = mbsc_gen::NS::inverse_dynamics;           \
    static constexpr mbsc_test::Function position_constraints = mbsc_gen::NS::position_constraints;   \
    static constexpr mbsc_test::Function velocity_constraints = mbsc_gen::NS::velocity_constraints;   \
    static constexpr mbsc_test::Function constraint_jacobian = mbsc_gen::NS::constraint_jacobian;     \
    static constexpr mbsc_test::Function position_jacobian = mbsc_gen::NS::position_jacobian;         \
    static constexpr mbsc_test::Function constraint_jacobian_values =                                 \
        mbsc_gen::NS::constraint_jacobian_values;                                                     \
    static constexpr mbsc_test::Function position_jacobian_values = mbsc_gen::NS::position_jacobian_values; \
    static constexpr int kConstraintJacobianNnz = mbsc_gen::NS::kConstraintJacobianNnz;               \
    static constexpr const int* kConstraintJacobianRowPtr = mbsc_gen::NS::kConstraintJacobianRowPtr;  \
    static constexpr const int* kConstraintJacobianColIdx = mbsc_gen::NS::kConstraintJacobianColIdx;  \
    static constexpr int kPositionJacobianNnz = mbsc_gen::NS::kPositionJacobianNnz;                   \
    static constexpr const int* kPositionJacobianRowPtr = mbsc_gen::NS::kPositionJacobianRowPtr;      \
    static constexpr const int* kPositionJacobianColIdx = mbsc_gen::NS::kPositionJacobianColIdx;      \
    static constexpr mbsc_test::Function energy = mbsc_gen::NS::energy;                               \
    static constexpr mbsc_test::Function outputs = mbsc_gen::NS::outputs;                             \
    static constexpr mbsc_test::Function full_state = mbsc_gen::NS::full_state;                       \
    static constexpr mbsc_test::Function conditioning = mbsc_gen::NS::conditioning;                   \
    static constexpr mbsc_test::PartitionFunction rhs_partition = mbsc_gen::NS::rhs_partition;        \
    static constexpr mbsc_test::PartitionFunction conditioning_partition =                            \
        mbsc_gen::NS::conditioning_partition;                                                         \
    using BatchArrays = mbsc_gen::NS::BatchArrays;                                                    \
    static constexpr auto rhs_at = mbsc_gen::NS::rhs_at;                                              \
    static constexpr auto rhs_batch = mbsc_gen::NS::rhs_batch;                                        \
    static constexpr auto c_rhs_batch = mbsc_##NS##_rhs_batch;                                        \
  }

namespace mbsc_test {

using Function = int (*)(double, const double*, const double*, const double*, double*);
using PartitionFunction = int (*)(int, double, const double*, const double*, const double*, double*);

/// The arguments of one call: a random state and inputs, the default parameters. `u` is
/// null when the model has no input (the ABI allows it; nothing may read it).
template <class M>
struct Arguments {
  double t = 0.3;
  std::vector<double> x, u, p;
  explicit Arguments(std::mt19937& rng) {
    std::uniform_real_distribution<double> d(-0.8, 0.8);
    for (int i = 0; i < M::kNx; ++i) x.push_back(d(rng));
    for (int i = 0; i < M::kNin; ++i) u.push_back(d(rng));
    p.assign(M::kParamDefaults, M::kParamDefaults + M::kNp);
  }
  const double* u_ptr() const { return M::kNin == 0 ? nullptr : u.data(); }
};

/// One call's result: the status and exactly `n` values, with a guard value after them
/// that must survive (the documented size is the size written).
struct Result {
  int status = -1;
  std::vector<double> values;
  bool guard_intact = false;
};

inline Result call(Function f, int n, double t, const std::vector<double>& x, const double* u, const std::vector<double>& p) {
  constexpr double kGuard = 12345.678;
  std::vector<double> out(static_cast<std::size_t>(n) + 1, kGuard);
  Result r;
  r.status = f(t, x.data(), u, p.empty() ? nullptr : p.data(), out.data());
  r.guard_intact = out[static_cast<std::size_t>(n)] == kGuard;
  out.pop_back();
  r.values = out;
  return r;
}

template <class M>
Result call(Function f, int n, const Arguments<M>& a, const std::vector<double>& x) {
  return call(f, n, a.t, x, a.u_ptr(), a.p);
}

inline int find_name(const char* const* names, int n, const std::string& name) {
  for (int i = 0; i < n; ++i)
    if (name == names[i]) return i;
  return -1;
}

}  // namespace mbsc_test
