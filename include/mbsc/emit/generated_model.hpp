// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// Everything the emitter prints for one model, and the printed files.
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "mbsc/ir/program.hpp"

namespace mbsc::emit {

/// Run-time re-selection of the independent set: the rhs and conditioning function of
/// each partition, dispatched by rhs_partition(k, ...) / conditioning_partition(k, ...).
struct PartitionTable {
  std::vector<std::string> rhs;           // function name per partition ("rhs", "rhs_alt1", ...)
  std::vector<std::string> conditioning;  // "" when that partition solves no block by LU
};

struct GeneratedModel {
  std::string name;          // model name: C++ namespace and file stem
  std::string source_hash;   // hex digest of the model text (banner)
  std::string tool_version;  // banner
  std::vector<std::string> banner_notes;  // extra banner lines ("frozen: g = 0")
  std::vector<std::pair<std::string, long>> int_constants;                        // {"kNq", 3}
  std::vector<std::pair<std::string, std::vector<std::string>>> name_lists;       // {"kStateNames", {...}}
  std::vector<std::pair<std::string, std::vector<double>>> double_lists;          // {"kParamDefaults", {...}}
  std::vector<std::pair<std::string, std::vector<long>>> int_lists;              // {"kConstraintJacobianRowPtr", {...}}
  std::vector<ir::LoweredFunction> functions;
  std::optional<PartitionTable> partitions;  // emitted with rhs and conditioning
  /// Functions that also get batched entry points NAME_at and NAME_batch over a
  /// struct-of-arrays batch (generate --batch; docs/batched.md).
  std::vector<std::string> batched;
};

struct GeneratedFiles {
  std::string header;  // <name>.hpp
  std::string source;  // <name>.cpp
};

/// Renders templates/model.hpp.in and templates/model.cpp.in.
GeneratedFiles emit(const GeneratedModel& model);

/// Renders templates/model.py.in: NAME.py of `generate --python`, a ctypes module over
/// the extern "C" functions of NAME.cpp with the sizes and name tables of NAME.hpp.
std::string emit_python(const GeneratedModel& model);

/// Shortest decimal text that reads back as the same double ("0.1", "1e-12", "3").
std::string format_double(double v);

}  // namespace mbsc::emit
