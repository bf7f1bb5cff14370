// SPDX-License-Identifier: GPL-2.0-or-later
#include "mbsc/sym/multipliers.hpp"

#include "mbsc/sym/kkt_system.hpp"

namespace mbsc::sym {

MultiplierForm multiplier_form(const model::Model& m) { return multiplier_form(m, kkt_system(m)); }

MultiplierForm multiplier_form(const model::Model& m, const KktSystem& k) {
  const unsigned nu = static_cast<unsigned>(m.speeds.size()), nc = static_cast<unsigned>(m.constraints.size());
  MultiplierForm out{GiNaC::matrix(nu, nu), GiNaC::matrix(nu, 1), GiNaC::matrix(nc, nu), GiNaC::matrix(nc, 1),
                     GiNaC::matrix(nc, 1), GiNaC::matrix(nc, 1)};
  // The sparse form, spread out (its zeros are the matrices' own).
  for (unsigned i = 0; i < nu; ++i) {
    for (const auto& e : k.My[i]) out.My(i, static_cast<unsigned>(e.col)) = e.value;
    out.hy(i, 0) = k.hy[i];
  }
  for (unsigned r = 0; r < nc; ++r) {
    for (const auto& e : k.A[r]) out.A(r, static_cast<unsigned>(e.col)) = e.value;
    out.velocity(r, 0) = k.velocity[r];
    out.b(r, 0) = k.b[r];
    out.g(r, 0) = k.g[r];
  }
  return out;
}

}  // namespace mbsc::sym
