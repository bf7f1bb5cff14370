// SPDX-License-Identifier: GPL-2.0-or-later
// The compressed-row (CSR) twins of the dense Jacobians: constraint_jacobian_values and
// position_jacobian_values write only the entries that are not identically zero, row by
// row, and the header gets their pattern (k<Name>Nnz, k<Name>RowPtr, k<Name>ColIdx) so a
// sparse solver can take the values without scanning a mostly-zero dense matrix.
#include <algorithm>
#include <stdexcept>

#include "mbsc/driver/pipeline.hpp"

namespace mbsc::driver {

SparseJacobian sparse_jacobian(const ir::FunctionSpec& dense, long rows, long cols, const std::string& prefix) {
  if (static_cast<long>(dense.outputs.size()) != rows * cols)
    throw std::logic_error("sparse_jacobian: " + dense.name + " does not have rows x cols outputs");
  SparseJacobian s;
  s.prefix = prefix;
  // Every field of the dense spec but its rows x cols outputs (copying those first would
  // hold a second dense matrix of expressions at the peak of a big model's generation).
  s.values.name = dense.name + "_values";
  s.values.steps = dense.steps;
  s.values.third_arg = dense.third_arg;
  s.values.undefined_reason = dense.undefined_reason;
  s.values.doc = "the entries of " + dense.name + " that are not identically zero, row by row (CSR order: row i holds\n" +
                 prefix + "ColIdx[" + prefix + "RowPtr[i] .. " + prefix + "RowPtr[i+1]))";
  s.values.out_name = "values";
  s.values.out_shape = prefix + "Nnz";
  s.row_ptr.push_back(0);
  for (long r = 0; r < rows; ++r) {
    for (long c = 0; c < cols; ++c) {
      const GiNaC::ex& e = dense.outputs[static_cast<std::size_t>(r * cols + c)];
      if (e.is_zero()) continue;  // a structural zero: no symbolic dependence at all
      s.values.outputs.push_back(e);
      s.col_idx.push_back(c);
    }
    s.row_ptr.push_back(static_cast<long>(s.col_idx.size()));
  }
  return s;
}

std::vector<SparseJacobian> add_sparse_jacobians(const model::Model& m, const GenerateOptions& opt,
                                                 std::vector<ir::FunctionSpec>& specs) {
  long nposc = 0;
  for (const auto& c : m.constraints) nposc += c.level == model::Constraint::Level::Position;
  struct Kind {
    const char* dense;
    const char* prefix;
    long rows, cols;
  };
  const Kind kinds[] = {
      {"constraint_jacobian", "kConstraintJacobian", static_cast<long>(m.constraints.size()), static_cast<long>(m.speeds.size())},
      {"position_jacobian", "kPositionJacobian", nposc, static_cast<long>(m.coords.size())}};
  auto wanted = [&](const std::string& n) { return opt.functions.empty() || opt.functions.count(n) > 0; };
  std::vector<SparseJacobian> out;
  for (const Kind& k : kinds) {
    auto dense = std::find_if(specs.begin(), specs.end(), [&](const ir::FunctionSpec& f) { return f.name == k.dense; });
    if (dense == specs.end()) continue;
    out.push_back(sparse_jacobian(*dense, k.rows, k.cols, k.prefix));
    // The values function comes right after its dense twin; the dense one only when asked for.
    if (!wanted(std::string(k.dense) + "_values")) continue;
    if (wanted(k.dense)) specs.insert(dense + 1, out.back().values);
    else *dense = out.back().values;
  }
  return out;
}

}  // namespace mbsc::driver
