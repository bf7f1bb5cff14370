// SPDX-License-Identifier: GPL-2.0-or-later
// Partition of B's columns into independent (#) and dependent (⋆) speeds.
#include "mbsc/sym/complement.hpp"
#include "mbsc/model/exact_guard.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <set>

namespace mbsc::sym {
namespace {

int numeric_rank(const Eigen::MatrixXd& A) {
  if (A.rows() == 0 || A.cols() == 0) return 0;
  Eigen::FullPivLU<Eigen::MatrixXd> lu(A);
  lu.setThreshold(1e-9);
  return static_cast<int>(lu.rank());
}

/// Rank of A with singular values below 1e-9 times `scale` counted as zero: a block of
/// columns judged against the whole matrix (a 1x1 block cos(pi/2) = 6e-17 is singular,
/// which a threshold relative to the block itself cannot see).
int numeric_rank_against(const Eigen::MatrixXd& A, double scale) {
  if (A.rows() == 0 || A.cols() == 0) return 0;
  // The diagonal of a column-pivoted QR's R, which decreases: cubic with a small constant
  // (an SVD of the 300-row loop block of a long parallelogram chain took seconds).
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(A);
  const Eigen::MatrixXd& R = qr.matrixQR();
  int rank = 0;
  while (rank < std::min(R.rows(), R.cols()) && std::abs(R(rank, rank)) > 1e-9 * scale) ++rank;
  return rank;
}

std::string names(const model::Model& m, const std::vector<int>& speeds) {
  std::string out;
  for (int s : speeds) out += (out.empty() ? "" : ", ") + m.speeds[s].name;
  return out;
}

/// Singleton elimination: repeatedly take a column (among `allowed`) that is nonzero in
/// exactly one remaining row with a state-free, nonzero pivot. Solving the picked rows
/// in reverse pick order is a forward substitution. Returns the (row, column) picks.
std::vector<std::pair<int, int>> singleton_elimination(const ComplementInput& in, const Eigen::MatrixXd& Bn,
                                                      const std::vector<int>& allowed, bool prefer_children) {
  const auto& B = *in.B;
  const int nr = static_cast<int>(B.rows());
  const int ny = static_cast<int>(B.cols());
  std::vector<bool> row_left(nr, true), col_left(ny, false);
  for (int j : allowed) col_left[j] = true;
  // Each column's nonzero rows, and how many of them are left: one pass over B, then
  // every pick updates the columns of its row, instead of rescanning B per pick.
  std::vector<std::vector<int>> col_rows(ny), row_cols(nr);
  for (int i = 0; i < nr; ++i)
    for (int j = 0; j < ny; ++j)
      if (!B(i, j).is_zero()) {
        col_rows[j].push_back(i);
        row_cols[i].push_back(j);
      }
  std::vector<int> left_in_col(ny);
  for (int j = 0; j < ny; ++j) left_in_col[j] = static_cast<int>(col_rows[j].size());
  // Whether B(row, j) can be a pivot, decided once per (column, its last row).
  std::vector<int> judged_row(ny, -1);
  std::vector<char> usable(ny, 0);
  std::vector<std::pair<int, int>> picks;
  for (;;) {
    int best_row = -1, best_col = -1, best_score = -1;
    for (int j = 0; j < ny; ++j) {
      if (!col_left[j] || left_in_col[j] != 1) continue;
      int row = -1;
      for (int i : col_rows[j])
        if (row_left[i]) row = i;
      const GiNaC::ex& pivot = B(row, j);
      if (judged_row[j] != row) {
        judged_row[j] = row;
        usable[j] = is_state_free(pivot, *in.model) && !(std::abs(Bn(row, j)) < 1e-12);
      }
      if (!usable[j]) continue;
      // Prefer numeric pivots, then children's speeds over the node's own extra speeds.
      int score = (GiNaC::is_a<GiNaC::numeric>(pivot) ? 4 : 0) +
                  (prefer_children && in.model->speeds[in.y[j]].node != in.node ? 2 : 0);
      if (score > best_score) {
        best_score = score;
        best_row = row;
        best_col = j;
      }
    }
    if (best_col < 0) break;
    picks.push_back({best_row, best_col});
    row_left[best_row] = false;
    col_left[best_col] = false;
    for (int j : row_cols[best_row]) --left_in_col[j];
  }
  std::reverse(picks.begin(), picks.end());
  return picks;
}

/// Decides how the dependent block is solved and fills p.symbolic / triangular_order.
void classify(const ComplementInput& in, const Eigen::MatrixXd& Bn, const std::vector<int>& dep_cols, Partition& p) {
  const auto& B = *in.B;
  auto picks = singleton_elimination(in, Bn, dep_cols, false);
  if (picks.size() == dep_cols.size() && static_cast<int>(picks.size()) == static_cast<int>(B.rows())) {
    p.symbolic = true;
    for (auto [row, c] : picks) p.triangular_order.push_back({row, in.y[c]});
    return;
  }
  const int nd = static_cast<int>(dep_cols.size());
  if (nd <= 6) {
    GiNaC::matrix Bs(nd, nd);
    for (int i = 0; i < nd; ++i)
      for (int k = 0; k < nd; ++k) Bs(i, k) = B(i, dep_cols[k]);
    GiNaC::ex det = model::normal_if_small(Bs.determinant());
    if (!det.is_zero() && is_state_free(det, *in.model)) p.symbolic = true;
  }
}

/// True when every position constraint of node n and its descendants holds at `at`.
bool subtree_holds(const model::Model& m, int n, const Probe& at) {
  const auto& node = m.nodes[static_cast<std::size_t>(n)];
  for (int c : node.constraints) {
    const auto& con = m.constraints[static_cast<std::size_t>(c)];
    if (con.level == model::Constraint::Level::Position && !(std::abs(at.eval(con.residual)) <= 1e-9)) return false;
  }
  for (int child : node.children)
    if (!subtree_holds(m, child, at)) return false;
  return true;
}

/// B at a configuration of this node: every position constraint of its subtree holds
/// there (B reads the children's dependent rates) and B evaluates to finite numbers (a
/// row that reads a child's numeric solve does not evaluate there). Else nothing.
std::optional<Eigen::MatrixXd> at_point(const ComplementInput& in, const Probe* at) {
  if (!at) return std::nullopt;
  const auto& B = *in.B;
  const auto& m = *in.model;
  if (!subtree_holds(m, in.node, *at)) return std::nullopt;
  Eigen::MatrixXd Br(B.rows(), B.cols());
  for (unsigned i = 0; i < B.rows(); ++i)
    for (unsigned j = 0; j < B.cols(); ++j) {
      Br(i, j) = B(i, j).is_zero() ? 0.0 : at->eval(B(i, j));
      if (!std::isfinite(Br(i, j))) return std::nullopt;
    }
  return Br;
}

std::optional<Eigen::MatrixXd> at_reference(const ComplementInput& in) { return at_point(in, in.reference); }

/// The rows that do not raise the rank of A, in row order.
std::vector<int> dependent_rows(const Eigen::MatrixXd& A) {
  std::vector<int> out;
  int rank = 0;
  for (Eigen::Index i = 0; i < A.rows(); ++i) {
    const int r = numeric_rank(A.topRows(i + 1));
    if (r == rank) out.push_back(static_cast<int>(i));
    rank = r;
  }
  return out;
}

/// The rank of B on the manifold, when B (Bs0, at the start) loses rank there and at every
/// point near it on the manifold (a redundancy of the mechanism, not a singular start):
/// that rank and B at the nearby point that has it. Else nothing (full rank on the
/// manifold, or no point to tell).
std::optional<std::pair<int, Eigen::MatrixXd>> manifold_rank(const ComplementInput& in, const std::optional<Eigen::MatrixXd>& Bs0) {
  const int nr = static_cast<int>(in.B->rows());
  if (!Bs0 || !in.nearby || in.nearby->empty() || numeric_rank(*Bs0) == nr) return std::nullopt;
  std::optional<std::pair<int, Eigen::MatrixXd>> best;
  for (const Probe& p : *in.nearby) {
    auto Bp = at_point(in, &p);
    if (!Bp) return std::nullopt;
    const int r = numeric_rank(*Bp);
    if (r == nr) return std::nullopt;  // regular nearby: the start is a singular pose
    if (!best || r > best->first) best = std::make_pair(r, std::move(*Bp));
  }
  return best;
}

/// Whether the columns dep_cols of Bx lose the rank `rank` (judged against all of Bx).
bool singular_block(const Eigen::MatrixXd& Bx, const std::vector<int>& dep_cols, int rank) {
  Eigen::MatrixXd Bs(Bx.rows(), static_cast<Eigen::Index>(dep_cols.size()));
  for (std::size_t k = 0; k < dep_cols.size(); ++k) Bs.col(static_cast<Eigen::Index>(k)) = Bx.col(dep_cols[k]);
  return numeric_rank_against(Bs, Bx.cwiseAbs().maxCoeff()) < rank;
}

/// Warns when the dependent block of the chosen set is singular at `where` (Br: B there):
/// the generated rhs cannot solve for the dependent speeds there.
void warn_if_singular_at(const ComplementInput& in, const Eigen::MatrixXd& Br, const std::vector<int>& dep_cols,
                                   const Partition& p, const std::string& where, Diagnostics& diags) {
  if (!singular_block(Br, dep_cols, p.rank)) return;
  const auto& m = *in.model;
  const bool given = !in.requested.empty();
  const bool any_works = numeric_rank(Br) == p.rank;
  // The top node's own position is the start of the file: name the model statement instead.
  const SourcePos& node_pos = in.node == m.root() ? m.name_pos : m.nodes[static_cast<std::size_t>(in.node)].pos;
  diags.warning(given ? in.requested_pos : node_pos,
                fmt::format("the {}independent speeds ({}) of subsystem '{}' are singular at {}: the constraints cannot be solved for {} there, "
                            "so the generated rhs fails at that state; {}",
                            given ? "" : "automatic ", names(m, p.independent), m.label(in.node), where, names(m, p.dependent),
                            any_works ? "name a set that works there with `independent` (or add an `alternative`)"
                                      : "no set works there (the constraints themselves are singular there)"));
}

}  // namespace

std::optional<Partition> choose_partition(const ComplementInput& in, Diagnostics& diags) {
  const auto& m = *in.model;
  const auto& B = *in.B;
  const int nr = static_cast<int>(B.rows());
  const int ny = static_cast<int>(B.cols());
  // Numeric B at the probe point.
  Eigen::MatrixXd Bn(nr, ny);
  for (int i = 0; i < nr; ++i)
    for (int j = 0; j < ny; ++j) {
      Bn(i, j) = B(i, j).is_zero() ? 0.0 : in.probe->eval(B(i, j));
      if (!std::isfinite(Bn(i, j))) {
        const auto& c = m.constraints[in.rows[i]];
        diags.error(c.pos, fmt::format("constraint '{}' cannot be evaluated at a generic configuration (its Jacobian is not finite)", c.name));
        return std::nullopt;
      }
    }
  // Rank, row by row: a row that does not raise the rank is redundant. When the whole
  // B has full row rank (the usual case) so has every prefix of it, and only zero rows
  // are looked for: one factorization instead of one per row (quartic in the rows).
  const bool full_rank = numeric_rank(Bn) == nr;
  int rank = 0;
  for (int i = 0; i < nr; ++i) {
    if (full_rank) {
      if (Bn.row(i).norm() != 0.0) continue;
    }
    int r = numeric_rank(Bn.topRows(i + 1));
    const auto& c = m.constraints[in.rows[i]];
    if (Bn.row(i).norm() == 0.0) {
      diags.error(c.pos, fmt::format("constraint '{}' restricts no speed of subsystem '{}' (its rows of B are zero): "
                                     "it is either always satisfied or inconsistent",
                                     c.name, m.label(in.node)));
      return std::nullopt;
    }
    if (r == rank) {
      diags.error(c.pos, fmt::format("constraint '{}' is redundant: it is a combination of the constraints before it in "
                                     "subsystem '{}' (rank {} with {} rows); remove it",
                                     c.name, m.label(in.node), rank, i + 1));
      return std::nullopt;
    }
    rank = r;
  }
  // B at the reference configuration: for a given set (the warning) and for the automatic
  // choice unless its pivots are numbers or parameters (regular everywhere). Where B
  // loses rank there and near it on the manifold, its rank there is the rank of the
  // mechanism (Bm: B at a nearby point with that rank).
  std::optional<Eigen::MatrixXd> Br, Bs0, Bm;  // B at the reference, at the start, near the start
  Partition p;
  p.rank = nr;
  auto measure_on_manifold = [&]() {
    Br = at_reference(in);
    Bs0 = at_point(in, in.start);
    if (auto found = manifold_rank(in, Bs0)) {
      p.rank = found->first;
      Bm = std::move(found->second);
      p.redundant_rows = dependent_rows(*Bm);
    }
  };
  std::vector<int> dep_cols;
  if (!in.requested.empty()) {
    measure_on_manifold();
    const int ndof = ny - p.rank;
    // User's independent set: each must be a column here, the count must be the DOF,
    // and the remaining block must be regular.
    std::set<int> indep_cols;
    for (int s : in.requested) {
      auto it = std::find(in.y.begin(), in.y.end(), s);
      if (it == in.y.end()) {
        diags.error(in.requested_pos, fmt::format("independent speed '{}' is not free at subsystem '{}' (it is not one of its "
                                                  "speeds or was eliminated in a child subsystem); free speeds here: {}",
                                                  m.speeds[s].name, m.label(in.node), names(m, in.y)));
        return std::nullopt;
      }
      if (!indep_cols.insert(static_cast<int>(it - in.y.begin())).second) {
        diags.error(in.requested_pos, fmt::format("independent speed '{}' is listed twice", m.speeds[s].name));
        return std::nullopt;
      }
    }
    if (static_cast<int>(indep_cols.size()) != ndof) {
      diags.error(in.requested_pos, fmt::format("subsystem '{}' has {} degree(s) of freedom but {} independent speed(s) are given",
                                                m.label(in.node), ndof, indep_cols.size()));
      return std::nullopt;
    }
    for (int j = 0; j < ny; ++j)
      if (!indep_cols.count(j)) dep_cols.push_back(j);
    const Eigen::MatrixXd& Bt = Bm ? *Bm : Bn;  // where the block must be regular
    Eigen::MatrixXd Bs(nr, dep_cols.size());
    for (size_t k = 0; k < dep_cols.size(); ++k) Bs.col(k) = Bt.col(dep_cols[k]);
    if (numeric_rank(Bs) < p.rank) {
      std::vector<int> dep;
      for (int j : dep_cols) dep.push_back(in.y[j]);
      diags.error(in.requested_pos, fmt::format("the independent speeds ({}) do not work for subsystem '{}': the constraints "
                                                "cannot be solved for the remaining speeds ({}) at {}",
                                                names(m, in.requested), m.label(in.node), names(m, dep),
                                                Bm ? "a configuration of the mechanism" : "a generic configuration"));
      return std::nullopt;
    }
    for (int s : in.requested) p.independent.push_back(s);
  } else {
    // Automatic: a triangular choice with state-free pivots if one exists (regular
    // everywhere, so never redundant), else the pivot columns of a column-pivoted QR of B.
    std::vector<int> all(ny);
    for (int j = 0; j < ny; ++j) all[j] = j;
    auto picks = singleton_elimination(in, Bn, all, true);
    if (static_cast<int>(picks.size()) == nr) {
      for (auto [row, c] : picks) dep_cols.push_back(c);
    } else {
      measure_on_manifold();
      // The best conditioned columns (greedy, by column-pivoted QR) at the reference
      // configuration when B has full rank there, else at the generic probe point. A
      // skate (-sin th u + cos th v = 0) starts at th = 0 and must not solve for u.
      // With redundant rows, at the nearby point of the mechanism's rank.
      const bool reference_regular = Br && numeric_rank(*Br) == nr;
      Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(Bm ? *Bm : reference_regular ? *Br : Bn);
      for (int k = 0; k < p.rank; ++k) dep_cols.push_back(qr.colsPermutation().indices()(k));
      // Checked where the model starts: a set singular there, where B is not, is chosen
      // there instead (a skate started across, theta = pi/2, must not solve for v).
      if (!Bm && Bs0 && numeric_rank(*Bs0) == nr && singular_block(*Bs0, dep_cols, nr)) {
        Eigen::ColPivHouseholderQR<Eigen::MatrixXd> at_start(*Bs0);
        dep_cols.clear();
        for (int k = 0; k < nr; ++k) dep_cols.push_back(at_start.colsPermutation().indices()(k));
      }
    }
    std::sort(dep_cols.begin(), dep_cols.end());
    for (int j = 0; j < ny; ++j)
      if (!std::binary_search(dep_cols.begin(), dep_cols.end(), j)) p.independent.push_back(in.y[j]);
  }
  std::sort(dep_cols.begin(), dep_cols.end());
  for (int j : dep_cols) p.dependent.push_back(in.y[j]);
  // Warned where the model starts when that is known, else at the reference.
  if (Bs0) warn_if_singular_at(in, *Bs0, dep_cols, p, in.start_name, diags);
  else if (Br) warn_if_singular_at(in, *Br, dep_cols, p, kReferenceName, diags);
  if (p.rank == nr) classify(in, Bn, dep_cols, p);
  return p;
}

}  // namespace mbsc::sym
