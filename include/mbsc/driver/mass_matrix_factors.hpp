// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// mass_matrix formed in the generated code from the factors of M = C^T My C (the root's
/// complement C and block-diagonal My), for models where the symbolic M is too big.
#include <functional>
#include <optional>
#include <vector>

#include "mbsc/driver/pipeline.hpp"
#include "mbsc/ir/function_spec.hpp"

namespace mbsc::driver {

/// Makes `f` (the mass_matrix function, its steps already those the values read: the
/// solves, the rebuilt minimal state) compute M from its factors: its outputs become the
/// distinct nonzero values of the root's C and My (finalized by `fin`) and its
/// CongruenceProduct forms M from them. false, `f` untouched, when the root's factors do
/// not have the shapes of M = C^T My C.
bool form_mass_matrix_from_factors(ir::FunctionSpec& f, const model::Model& m, const sym::Eom& eom,
                                   const std::function<GiNaC::ex(const GiNaC::ex&)>& fin);

}  // namespace mbsc::driver
