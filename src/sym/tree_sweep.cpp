// SPDX-License-Identifier: GPL-2.0-or-later
// New right-hand sides through a finished tree recursion (include/mbsc/sym/tree_sweep.hpp).
//
// The same two sweeps as the recursion's own column (src/sym/tree_recursion.cpp), with
// the pivots taken as given: leaves to root, beta = pA - IA k, g = D^-1 (f_s + Phi^T beta),
// the parent receives T^T (beta - U g); root to leaves, y = T u_p', s' = g - G y,
// u' = y + Phi s' + k. Only vectors move, one per column.
#include "mbsc/sym/tree_sweep.hpp"

#include <fmt/format.h>

#include <cstddef>

namespace mbsc::sym {

namespace {

using Columns = std::vector<std::vector<GiNaC::ex>>;  // [entry][column]

class Sweep {
 public:
  Sweep(const TreeFactors& tree, int columns, std::vector<ir::Step>& steps) : tree_(tree), k_(columns), steps_(steps) {}

  Columns run(const Columns& forces, const Columns& rows) {
    const std::size_t nb = tree_.bodies.size();
    pA_.assign(nb, {});
    g_.assign(nb, {});
    kc_.assign(nb, {});
    for (std::size_t b = 0; b < nb; ++b)
      for (int s : tree_.bodies[b].speeds) pA_[b].push_back(forces[static_cast<std::size_t>(s)]);
    for (auto it = tree_.order.rbegin(); it != tree_.order.rend(); ++it) inwards(*it, forces, rows);
    Columns rates(forces.size(), std::vector<GiNaC::ex>(static_cast<std::size_t>(k_), GiNaC::ex(0)));
    for (int b : tree_.order) outwards(b, rates);
    return rates;
  }

 private:
  GiNaC::ex named(const GiNaC::ex& e) {
    if (GiNaC::is_a<GiNaC::numeric>(e) || GiNaC::is_a<GiNaC::symbol>(e)) return e;
    const GiNaC::symbol s(fmt::format("ts{}", counter_++));
    steps_.push_back(ir::Define{s, e, false});
    return s;
  }

  static void add_product(GiNaC::ex& sum, const GiNaC::ex& a, const GiNaC::ex& b) {
    if (!a.is_zero() && !b.is_zero()) sum += a * b;
  }

  // D X = R over R's nonzero columns, by the generated code's symmetric solve (the
  // recursion already checked D where it formed it).
  std::vector<std::vector<GiNaC::ex>> solve(const std::vector<GiNaC::ex>& D, const std::vector<std::vector<GiNaC::ex>>& R,
                                            const std::string& label) {
    const int n = static_cast<int>(R.size());
    std::vector<std::vector<GiNaC::ex>> X(static_cast<std::size_t>(n), std::vector<GiNaC::ex>(static_cast<std::size_t>(k_), GiNaC::ex(0)));
    std::vector<int> cols;
    for (int j = 0; j < k_; ++j) {
      bool any = false;
      for (int i = 0; i < n; ++i) any = any || !R[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)].is_zero();
      if (any) cols.push_back(j);
    }
    if (cols.empty()) return X;
    ir::Solve s;
    s.label = label;
    s.n = n;
    s.k = static_cast<int>(cols.size());
    s.spd = true;
    s.reported = false;
    s.A = D;
    for (int i = 0; i < n; ++i)
      for (int j : cols) s.B.push_back(R[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)]);
    for (int i = 0; i < n; ++i)
      for (int j : cols) {
        const GiNaC::symbol x(fmt::format("ts{}", counter_++));
        s.X.push_back(x);
        X[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] = x;
      }
    steps_.push_back(std::move(s));
    return X;
  }

  void inwards(int bi, const Columns& forces, const Columns& rows) {
    const TreeFactors::Body& b = tree_.bodies[static_cast<std::size_t>(bi)];
    const std::size_t nu = b.speeds.size(), ns = b.joint.size(), K = static_cast<std::size_t>(k_);
    auto& pA = pA_[static_cast<std::size_t>(bi)];
    for (auto& row : pA)
      for (auto& e : row) e = named(e);
    if (b.free_root) {
      g_[static_cast<std::size_t>(bi)] = solve(b.IA, pA, "tree sweep: free body");
      return;
    }
    // k per column: the body's rows solved by the same substitution as its own k.
    auto& kc = kc_[static_cast<std::size_t>(bi)];
    kc.assign(nu, std::vector<GiNaC::ex>(K, GiNaC::ex(0)));
    for (const auto& sub : b.substitutions)
      for (std::size_t j = 0; j < K; ++j) {
        GiNaC::ex v = 0;
        add_product(v, rows[static_cast<std::size_t>(sub.row)][j], sub.inverse);
        for (const auto& [l, w] : sub.own) add_product(v, w, kc[static_cast<std::size_t>(l)][j]);
        kc[static_cast<std::size_t>(sub.a)][j] = named(v);
      }
    // beta = pA - IA k.
    std::vector<std::vector<GiNaC::ex>> beta(nu, std::vector<GiNaC::ex>(K));
    for (std::size_t i = 0; i < nu; ++i)
      for (std::size_t j = 0; j < K; ++j) {
        GiNaC::ex v = pA[i][j];
        for (std::size_t t = 0; t < nu; ++t) add_product(v, -b.IA[i * nu + t], kc[t][j]);
        beta[i][j] = named(v);
      }
    auto& g = g_[static_cast<std::size_t>(bi)];
    if (ns > 0) {
      std::vector<std::vector<GiNaC::ex>> r(ns, std::vector<GiNaC::ex>(K));
      for (std::size_t i = 0; i < ns; ++i)
        for (std::size_t j = 0; j < K; ++j) {
          GiNaC::ex v = forces[static_cast<std::size_t>(b.joint[i])][j];
          for (std::size_t t = 0; t < nu; ++t) add_product(v, b.Phi[t * ns + i], beta[t][j]);
          r[i][j] = v;
        }
      g = solve(b.D, r, "tree sweep: joint pivot");
    }
    if (b.parent < 0) return;
    const TreeFactors::Body& p = tree_.bodies[static_cast<std::size_t>(b.parent)];
    const std::size_t np = p.speeds.size();
    std::vector<std::vector<GiNaC::ex>> passed(nu, std::vector<GiNaC::ex>(K));
    for (std::size_t i = 0; i < nu; ++i)
      for (std::size_t j = 0; j < K; ++j) {
        GiNaC::ex v = beta[i][j];
        for (std::size_t t = 0; t < ns; ++t) add_product(v, -b.U[i * ns + t], g[t][j]);
        passed[i][j] = named(v);
      }
    auto& into = pA_[static_cast<std::size_t>(b.parent)];
    for (std::size_t i = 0; i < np; ++i)
      for (std::size_t j = 0; j < K; ++j)
        for (std::size_t t = 0; t < nu; ++t) add_product(into[i][j], b.T[t * np + i], passed[t][j]);
  }

  void outwards(int bi, Columns& rates) {
    const TreeFactors::Body& b = tree_.bodies[static_cast<std::size_t>(bi)];
    const std::size_t nu = b.speeds.size(), ns = b.joint.size(), K = static_cast<std::size_t>(k_);
    const auto& g = g_[static_cast<std::size_t>(bi)];
    if (b.free_root) {
      for (std::size_t i = 0; i < nu; ++i) rates[static_cast<std::size_t>(b.speeds[i])] = g[i];
      return;
    }
    std::vector<std::vector<GiNaC::ex>> y(nu, std::vector<GiNaC::ex>(K, GiNaC::ex(0)));
    if (b.parent >= 0) {
      const TreeFactors::Body& p = tree_.bodies[static_cast<std::size_t>(b.parent)];
      const std::size_t np = p.speeds.size();
      for (std::size_t i = 0; i < nu; ++i)
        for (std::size_t j = 0; j < K; ++j) {
          GiNaC::ex v = 0;
          for (std::size_t t = 0; t < np; ++t) add_product(v, b.T[i * np + t], rates[static_cast<std::size_t>(p.speeds[t])][j]);
          y[i][j] = named(v);
        }
    }
    for (std::size_t i = 0; i < ns; ++i)
      for (std::size_t j = 0; j < K; ++j) {
        GiNaC::ex v = g[i][j];
        for (std::size_t t = 0; t < nu; ++t) add_product(v, -b.G[i * nu + t], y[t][j]);
        rates[static_cast<std::size_t>(b.joint[i])][j] = named(v);
      }
    const auto& kc = kc_[static_cast<std::size_t>(bi)];
    for (std::size_t i = 0; i < nu; ++i)
      for (std::size_t j = 0; j < K; ++j) {
        GiNaC::ex v = y[i][j] + kc[i][j];
        for (std::size_t t = 0; t < ns; ++t) add_product(v, b.Phi[i * ns + t], rates[static_cast<std::size_t>(b.joint[t])][j]);
        rates[static_cast<std::size_t>(b.speeds[i])][j] = named(v);
      }
  }

  const TreeFactors& tree_;
  const int k_;
  std::vector<ir::Step>& steps_;
  std::vector<std::vector<std::vector<GiNaC::ex>>> pA_, g_, kc_;  // per body: [entry][column]
  long counter_ = 0;
};

}  // namespace

std::vector<std::vector<GiNaC::ex>> solve_columns(const TreeFactors& tree, const std::vector<std::vector<GiNaC::ex>>& forces,
                                                  const std::vector<std::vector<GiNaC::ex>>& rows, int columns,
                                                  std::vector<ir::Step>& steps) {
  return Sweep(tree, columns, steps).run(forces, rows);
}

}  // namespace mbsc::sym
