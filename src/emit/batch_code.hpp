// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// The batched entry points of a generated model (private to src/emit): for each function
/// named in GeneratedModel::batched, NAME_at (one instance of a struct-of-arrays batch,
/// what a GPU thread calls) and NAME_batch (every instance, in a loop on the calling
/// thread), with the BatchArrays struct that describes the layout (docs/batched.md).
#include <string>

#include "mbsc/emit/generated_model.hpp"

namespace mbsc::emit {

/// Header text: BatchArrays and the declarations; "" when nothing is batched.
std::string batch_declarations(const GeneratedModel& m);
/// Source text: the anonymous-namespace helpers and the definitions; "" when nothing is batched.
std::string batch_definitions(const GeneratedModel& m);
/// The extern "C" `mbsc_NAME_F_batch` entry points (flat arguments, for FFI): declarations
/// and definitions, one per line or block, "" when nothing is batched.
std::string batch_c_declarations(const GeneratedModel& m);
std::string batch_c_definitions(const GeneratedModel& m);

}  // namespace mbsc::emit
