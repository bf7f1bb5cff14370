// SPDX-License-Identifier: GPL-2.0-or-later
// M q'' + C q' + K q = T from the linear model: a change of coordinates on its tangent
// space to (q, q', the rest), then the q'' rows read off (include/mbsc/run/second_order_form.hpp).
#include "mbsc/run/second_order_form.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace mbsc::run {

bool second_order_form(const runtime::LinearModel& lin, int nq, const std::vector<int>& coords, SecondOrderForm& out,
                       std::string& why) {
  const int n = lin.n, m = lin.m, k = static_cast<int>(coords.size());
  using Mat = Eigen::MatrixXd;
  Mat A(n, n), V(n, m), Bq(n, nq);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) A(i, j) = lin.A[static_cast<std::size_t>(i * n + j)];
    for (int j = 0; j < m; ++j) V(i, j) = lin.tangent[static_cast<std::size_t>(i * m + j)];
    for (int j = 0; j < nq; ++j) Bq(i, j) = lin.Bq[static_cast<std::size_t>(i * nq + j)];
  }
  // The functionals of xi: q (unit rows), q' (A's rows of q), then unit rows that complete
  // a basis of the tangent space's dual, taken in layout order.
  std::vector<Eigen::RowVectorXd> rows;
  for (int c : coords) rows.push_back(Eigen::RowVectorXd::Unit(n, c));
  for (int c : coords) rows.push_back(A.row(c));
  auto rank_of = [&](const std::vector<Eigen::RowVectorXd>& r) {
    Mat L(static_cast<int>(r.size()), n);
    for (int i = 0; i < L.rows(); ++i) L.row(i) = r[static_cast<std::size_t>(i)];
    Eigen::ColPivHouseholderQR<Mat> qr(L * V);
    qr.setThreshold(1e-9);
    return static_cast<int>(qr.rank());
  };
  if (rank_of(rows) < 2 * k) {
    why = "the coordinates and their rates are not independent on the motions the linearized constraints allow (a "
          "coordinate or a rate fixed by the constraints, or a coordinate named twice)";
    return false;
  }
  for (int i = 0; i < n && static_cast<int>(rows.size()) < m; ++i) {
    rows.push_back(Eigen::RowVectorXd::Unit(n, i));
    if (rank_of(rows) < static_cast<int>(rows.size())) rows.pop_back();
  }
  if (static_cast<int>(rows.size()) != m) {
    why = "cannot complete the coordinates to a state of the linear model";
    return false;
  }
  Mat L(m, n);
  for (int i = 0; i < m; ++i) L.row(i) = rows[static_cast<std::size_t>(i)];
  const Mat LV = L * V;
  const Mat Axi = L * A * V * LV.inverse();  // xi' = Axi xi
  Mat Bxi(m, k);
  for (int j = 0; j < k; ++j) Bxi.col(j) = L * Bq.col(coords[static_cast<std::size_t>(j)]);
  const Mat Minv = Bxi.block(k, 0, k, k);
  Eigen::FullPivLU<Mat> lu(Minv);
  if (!lu.isInvertible()) {
    why = "generalized forces on these coordinates do not determine their accelerations (M is singular)";
    return false;
  }
  const Mat M = lu.inverse();
  const Mat K = -M * Axi.block(k, 0, k, k), C = -M * Axi.block(k, k, k, k);
  const double rest = m > 2 * k ? (M * Axi.block(k, 2 * k, k, m - 2 * k)).cwiseAbs().maxCoeff() : 0.0;
  out.k = k;
  out.coupling = rest / std::max({K.cwiseAbs().maxCoeff(), C.cwiseAbs().maxCoeff(), 1e-300});
  out.M.resize(static_cast<std::size_t>(k * k)), out.C.resize(out.M.size()), out.K.resize(out.M.size());
  for (int i = 0; i < k; ++i)
    for (int j = 0; j < k; ++j) {
      out.M[static_cast<std::size_t>(i * k + j)] = M(i, j);
      out.C[static_cast<std::size_t>(i * k + j)] = C(i, j);
      out.K[static_cast<std::size_t>(i * k + j)] = K(i, j);
    }
  return true;
}

}  // namespace mbsc::run
