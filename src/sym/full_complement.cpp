// SPDX-License-Identifier: GPL-2.0-or-later
#include "mbsc/sym/full_complement.hpp"

#include <algorithm>

namespace mbsc::sym {

std::vector<int> subtree_speeds(const model::Model& m, int n) {
  std::vector<int> out;
  for (size_t s = 0; s < m.speeds.size(); ++s)
    for (int k = m.speeds[s].node; k >= 0; k = m.nodes[k].parent)
      if (k == n) {
        out.push_back(static_cast<int>(s));
        break;
      }
  return out;
}

GiNaC::matrix full_complement(const model::Model& m, const Eom& eom, int n, std::vector<int>& rows) {
  const auto& r = eom.nodes[n];
  const auto& node = m.nodes[n];
  rows = subtree_speeds(m, n);
  auto row_of = [&](int s) { return static_cast<unsigned>(std::find(rows.begin(), rows.end(), s) - rows.begin()); };
  // R = blockdiag(1 on own speeds, S_child): maps y to the subtree speeds.
  GiNaC::matrix R(rows.size(), r.y.size());
  unsigned col = 0;
  for (int s : node.speeds) R(row_of(s), col++) = 1;
  for (int c : node.children) {
    std::vector<int> crow;
    GiNaC::matrix Sc = full_complement(m, eom, c, crow);
    for (unsigned j = 0; j < Sc.cols(); ++j, ++col)
      for (unsigned i = 0; i < Sc.rows(); ++i) R(row_of(crow[i]), col) = Sc(i, j);
  }
  return R.mul(r.C.get());
}

}  // namespace mbsc::sym
