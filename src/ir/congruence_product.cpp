// SPDX-License-Identifier: GPL-2.0-or-later
// The loop that forms a dense symmetric output M = C^T My C from the nonzeros of its
// factors (ir::CongruenceProduct), printed after the values of those nonzeros.
//
// M(a, b) = sum over the nonzeros My(r, s) of My(r, s) C(r, a) C(s, b). The loop visits
// each nonzero of My and, for it, each pair of nonzeros of rows r and s of C, adding
// only to the upper triangle (b >= a); the lower triangle is then copied from it, so
// the result is exactly symmetric (a Cholesky factorisation can rely on it). The rows
// of C are stored by increasing column, so for a diagonal My(r, r) the pairs with
// b >= a start at a itself.
#include <string>

#include "program_ir.hpp"

namespace mbsc::ir {

namespace {

// `static const int NAME[n] = {...};` with 20 values per line (an empty list gets one 0:
// C++ has no zero-length arrays).
std::string int_table(const std::string& name, const std::vector<int>& values) {
  std::string out = "  static const int " + name + "[" + std::to_string(values.empty() ? 1 : values.size()) + "] = {";
  if (values.empty()) return out + "0};\n";
  for (std::size_t i = 0; i < values.size(); ++i) {
    out += i % 20 == 0 ? "\n      " : " ";
    out += std::to_string(values[i]);
    if (i + 1 < values.size()) out += ",";
  }
  return out + "};\n";
}

}  // namespace

std::string congruence_loop(const CongruenceProduct& c, OpCount& ops) {
  const std::string nd = std::to_string(c.nd);
  std::string out;
  out += "  // OUT = C^T My C (" + std::to_string(c.nd) + "x" + nd + ") from the nonzeros of C (" + std::to_string(c.ny) +
         "x" + nd + ", " + std::to_string(c.c_col.size()) + " nonzeros, compressed rows) and My (" +
         std::to_string(c.my_row.size()) + " nonzeros); each nonzero's value is factor_[its *_value_ entry]\n";
  out += int_table("c_row_ptr_", c.c_row_ptr);
  out += int_table("c_col_", c.c_col);
  out += int_table("c_value_", c.c_value);
  out += int_table("my_row_", c.my_row);
  out += int_table("my_col_", c.my_col);
  out += int_table("my_value_", c.my_value);
  out += "  for (int i = 0; i < " + std::to_string(c.nd * c.nd) + "; ++i) OUT[i] = 0.0;\n";
  out += "  for (int k_ = 0; k_ < " + std::to_string(c.my_row.size()) + "; ++k_) {\n";
  out += "    const int r_ = my_row_[k_], s_ = my_col_[k_];\n";
  out += "    const double m_ = factor_[my_value_[k_]];\n";
  out += "    for (int i_ = c_row_ptr_[r_]; i_ < c_row_ptr_[r_ + 1]; ++i_) {\n";
  out += "      const int a_ = c_col_[i_];\n";
  out += "      const double mc_ = m_ * factor_[c_value_[i_]];\n";
  out += "      for (int j_ = r_ == s_ ? i_ : c_row_ptr_[s_]; j_ < c_row_ptr_[s_ + 1]; ++j_)\n";
  out += "        if (c_col_[j_] >= a_) OUT[a_ * " + nd + " + c_col_[j_]] += mc_ * factor_[c_value_[j_]];\n";
  out += "    }\n  }\n";
  out += "  for (int a_ = 0; a_ < " + nd + "; ++a_)\n";
  out += "    for (int b_ = a_ + 1; b_ < " + nd + "; ++b_) OUT[b_ * " + nd + " + a_] = OUT[a_ * " + nd + " + b_];\n";
  out += "  if (!all_finite(OUT, " + std::to_string(c.nd * c.nd) + ")) return 2;\n";
  // What the loop computes, counted like the printed statements: one product per
  // nonzero pair of rows r, s, one multiply-add per pair it keeps.
  for (std::size_t k = 0; k < c.my_row.size(); ++k) {
    const auto r = static_cast<std::size_t>(c.my_row[k]), s = static_cast<std::size_t>(c.my_col[k]);
    for (int i = c.c_row_ptr[r]; i < c.c_row_ptr[r + 1]; ++i) {
      ops.muls += 1;
      for (int j = r == s ? i : c.c_row_ptr[s]; j < c.c_row_ptr[s + 1]; ++j)
        if (c.c_col[static_cast<std::size_t>(j)] >= c.c_col[static_cast<std::size_t>(i)]) {
          ops.muls += 1;
          ops.adds += 1;
        }
    }
  }
  return out;
}

}  // namespace mbsc::ir
