// SPDX-License-Identifier: GPL-2.0-or-later
// The C++ side of tests/cli/python_module_test.cpp: compiled with a generated model
// (-DMBSC_MODEL=name -DMBSC_MODEL_HEADER='"name.hpp"'), it prints the name tables and
// the result of every function of the common ABI at a random state, for the Python
// module to reproduce. Lines: "names TABLE n name...", "input WHAT n v...",
// "call FUNCTION status n v...".
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

#include MBSC_MODEL_HEADER

namespace m = mbsc_gen::MBSC_MODEL;

namespace {

void names(const char* table, const char* const* list, int n) {
  std::printf("names %s %d", table, n);
  for (int i = 0; i < n; ++i) std::printf(" %s", list[i]);
  std::printf("\n");
}

void indices(const char* table, const int* list, int n) {
  std::printf("index %s %d", table, n);
  for (int i = 0; i < n; ++i) std::printf(" %d", list[i]);
  std::printf("\n");
}

void values(const char* head, const char* what, int status, const double* v, int n) {
  std::printf("%s %s", head, what);
  if (status >= 0) std::printf(" %d", status);
  std::printf(" %d", n);
  for (int i = 0; i < n; ++i) std::printf(" %.17g", v[i]);
  std::printf("\n");
}

using Function = int (*)(double, const double*, const double*, const double*, double*);

}  // namespace

int main(int argc, char** argv) {
  std::mt19937 rng(argc > 1 ? static_cast<unsigned>(std::atoi(argv[1])) : 1u);
  std::uniform_real_distribution<double> d(-0.8, 0.8);
  const double t = 0.37;
  std::vector<double> x(m::kNx), u(m::kNin + 1), p(m::kParamDefaults, m::kParamDefaults + m::kNp);
  for (auto& e : x) e = d(rng);
  for (auto& e : u) e = d(rng);
  names("kStateNames", m::kStateNames, m::kNx);
  names("kFullStateNames", m::kFullStateNames, m::kNxFull);
  names("kDofNames", m::kDofNames, m::kNdof);
  names("kInputNames", m::kInputNames, m::kNin);
  names("kParamNames", m::kParamNames, m::kNp);
  names("kConstraintNames", m::kConstraintNames, m::kNc);
  names("kOutputNames", m::kOutputNames, m::kNy);
  indices("kConstraintJacobianRowPtr", m::kConstraintJacobianRowPtr, m::kNc + 1);
  indices("kConstraintJacobianColIdx", m::kConstraintJacobianColIdx, m::kConstraintJacobianNnz);
  indices("kPositionJacobianRowPtr", m::kPositionJacobianRowPtr, m::kNposc + 1);
  indices("kPositionJacobianColIdx", m::kPositionJacobianColIdx, m::kPositionJacobianNnz);
  values("input", "t", -1, &t, 1);
  values("input", "x", -1, x.data(), m::kNx);
  values("input", "u", -1, u.data(), m::kNin);
  values("input", "p", -1, p.data(), m::kNp);
  const struct {
    const char* name;
    Function f;
    int n;
  } functions[] = {{"rhs", m::rhs, m::kNx},
                   {"mass_matrix", m::mass_matrix, m::kNdof * m::kNdof},
                   {"forcing", m::forcing, m::kNdof},
                   {"position_constraints", m::position_constraints, m::kNposc},
                   {"velocity_constraints", m::velocity_constraints, m::kNc},
                   {"constraint_jacobian", m::constraint_jacobian, m::kNc * m::kNuFull},
                   {"position_jacobian", m::position_jacobian, m::kNposc * m::kNqFull},
                   {"constraint_jacobian_values", m::constraint_jacobian_values, m::kConstraintJacobianNnz},
                   {"position_jacobian_values", m::position_jacobian_values, m::kPositionJacobianNnz},
                   {"energy", m::energy, 3},
                   {"outputs", m::outputs, m::kNy},
                   {"full_state", m::full_state, m::kNxFull},
                   {"conditioning", m::conditioning, m::kNblocks}};
  for (const auto& f : functions) {
    std::vector<double> out(static_cast<std::size_t>(f.n) + 1);
    const int status = f.f(t, x.data(), u.data(), p.data(), out.data());
    values("call", f.name, status, out.data(), f.n);
  }
  // inverse_dynamics: its third argument is kNdof accelerations.
  std::vector<double> zdot(m::kNdof + 1), inv(static_cast<std::size_t>(m::kNin) + 1);
  for (auto& e : zdot) e = d(rng);
  values("input", "zdot", -1, zdot.data(), m::kNdof);
  values("call", "inverse_dynamics", m::inverse_dynamics(t, x.data(), zdot.data(), p.data(), inv.data()), inv.data(), m::kNin);
  std::vector<double> out(static_cast<std::size_t>(m::kNx));
  const int status = m::rhs_partition(0, t, x.data(), u.data(), p.data(), out.data());
  values("call", "rhs_partition", status, out.data(), m::kNx);
  return 0;
}
