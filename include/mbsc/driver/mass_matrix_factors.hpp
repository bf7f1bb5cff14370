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

/// The mass_matrix function whose outputs are the distinct nonzero values of the root's
/// C and My (finalized by `fin`) and whose CongruenceProduct forms M from them. `steps`
/// are what those values read (the solves, the rebuilt minimal state). nullopt when the
/// root's factors do not have the shapes of M = C^T My C.
std::optional<ir::FunctionSpec> mass_matrix_from_factors(const model::Model& m, const sym::Eom& eom,
                                                         std::vector<ir::Step> steps,
                                                         const std::function<GiNaC::ex(const GiNaC::ex&)>& fin);

}  // namespace mbsc::driver
