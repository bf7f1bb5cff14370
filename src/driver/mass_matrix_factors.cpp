// SPDX-License-Identifier: GPL-2.0-or-later
// The mass_matrix output of a long chain formed from its factors: the root's reduced
// mass matrix is M = C^T My C (docs/formulation.md), with C (y over the independent
// speeds) and My (block diagonal) sparse and their entries short, while M itself is
// dense with entries of O(N) terms. Forming M symbolically costs O(N^3) terms to build,
// simplify, lower and compile; its factors hold O(N^2) nonzeros with few distinct
// values (a chain's C repeats -l sin(th_j) down a column). So the generated code gets
// the distinct values, the pattern as integer tables and a loop (ir::CongruenceProduct).
#include "mbsc/driver/mass_matrix_factors.hpp"

#include <map>

namespace mbsc::driver {

MassMatrixForm mass_matrix_form_named(const std::string& name) {
  return name == "symbolic" ? MassMatrixForm::Symbolic : name == "factors" ? MassMatrixForm::Factors : MassMatrixForm::Auto;
}

namespace {

/// C is ny x nd and My is ny x ny: the shapes of M = C^T My C.
bool congruent_shapes(const GiNaC::matrix& C, const GiNaC::matrix& My) {
  return C.rows() == My.rows() && My.rows() == My.cols();
}

}  // namespace

long congruence_products(const GiNaC::matrix& C, const GiNaC::matrix& My) {
  if (!congruent_shapes(C, My)) return 0;
  const unsigned ny = C.rows(), nd = C.cols();
  std::vector<std::vector<unsigned>> row_cols(ny);  // the nonzero columns of each row of C
  for (unsigned i = 0; i < ny; ++i)
    for (unsigned j = 0; j < nd; ++j)
      if (!C(i, j).is_zero()) row_cols[i].push_back(j);
  long products = 0;
  for (unsigned r = 0; r < ny; ++r)
    for (unsigned s = 0; s < ny; ++s) {
      if (My(r, s).is_zero()) continue;
      for (unsigned a : row_cols[r])
        for (unsigned b : row_cols[s]) products += b >= a ? 1 : 0;
    }
  return products;
}

bool form_mass_matrix_from_factors(ir::FunctionSpec& f, const model::Model& m, const sym::Eom& eom,
                                   const std::function<GiNaC::ex(const GiNaC::ex&)>& fin) {
  const sym::NodeResult& root = eom.nodes[static_cast<std::size_t>(m.root())];
  const GiNaC::matrix &C = root.C.get(), &My = root.My;
  const int nd = eom.ndof();
  if (nd == 0 || static_cast<int>(C.cols()) != nd || !congruent_shapes(C, My)) return false;
  const unsigned ny = C.rows();

  ir::CongruenceProduct product;
  product.ny = static_cast<int>(ny);
  product.nd = nd;
  // Each distinct value once, numbered in order of first appearance (C by rows, then My),
  // so that the generated code does not depend on how GiNaC orders expressions.
  std::map<GiNaC::ex, int, GiNaC::ex_is_less> index;
  std::vector<GiNaC::ex> values;
  auto value_index = [&](const GiNaC::ex& e) {
    const auto [it, added] = index.emplace(e, static_cast<int>(values.size()));
    if (added) values.push_back(e);
    return it->second;
  };
  product.c_row_ptr.push_back(0);
  for (unsigned i = 0; i < ny; ++i) {
    for (unsigned j = 0; j < static_cast<unsigned>(nd); ++j) {
      if (C(i, j).is_zero()) continue;
      product.c_col.push_back(static_cast<int>(j));
      product.c_value.push_back(value_index(C(i, j)));
    }
    product.c_row_ptr.push_back(static_cast<int>(product.c_col.size()));
  }
  for (unsigned r = 0; r < ny; ++r)
    for (unsigned s = 0; s < ny; ++s) {
      if (My(r, s).is_zero()) continue;
      product.my_row.push_back(static_cast<int>(r));
      product.my_col.push_back(static_cast<int>(s));
      product.my_value.push_back(value_index(My(r, s)));
    }

  f.outputs.clear();
  f.outputs.reserve(values.size());
  for (const auto& v : values) f.outputs.push_back(fin(v));
  f.congruence = std::move(product);
  return true;
}

}  // namespace mbsc::driver
