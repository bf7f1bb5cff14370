// SPDX-License-Identifier: GPL-2.0-or-later
// The articulated-body recursion on the sparse system (include/mbsc/sym/tree_recursion.hpp).
//
// The story: find the tree in the rows (which body each row fixes, which joint speeds it
// carries), write each body's rows as an explicit map from its parent's speeds and its
// joint speeds, then run the two sweeps of the articulated-body algorithm over those maps.
// Every quantity is kept twice: as the expression the generated code computes (entries
// named as intermediates) and as its value at the probe point (what checks the pivots).
#include "mbsc/sym/tree_recursion.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <deque>
#include <map>
#include <set>

namespace mbsc::sym {

namespace {

/// An expression and its value at the probe point.
struct Q {
  GiNaC::ex e = 0;
  double v = 0.0;
};

Q operator+(const Q& a, const Q& b) { return {a.e + b.e, a.v + b.v}; }
Q operator-(const Q& a, const Q& b) { return {a.e - b.e, a.v - b.v}; }
Q operator*(const Q& a, const Q& b) {
  if (a.e.is_zero() || b.e.is_zero()) return {};
  return {a.e * b.e, a.v * b.v};
}

/// A dense rows x cols matrix of Q, row-major.
struct Mat {
  int rows = 0, cols = 0;
  std::vector<Q> q;
  Mat() = default;
  Mat(int r, int c) : rows(r), cols(c), q(static_cast<std::size_t>(r * c)) {}
  Q& operator()(int i, int j) { return q[static_cast<std::size_t>(i * cols + j)]; }
  const Q& operator()(int i, int j) const { return q[static_cast<std::size_t>(i * cols + j)]; }
};

/// One step of a body's substitution: `row` gives speed `local` (its position in the
/// body's speeds), whose coefficient there is the number `pivot`.
struct Substitution {
  int row = 0, local = 0;
  GiNaC::ex pivot;
};

/// One body of the tree: its speeds u, the rows that fix them and its joint speeds s.
struct Body {
  std::vector<int> speeds;  // u_c, indices into m.speeds (ascending)
  std::vector<int> rows;    // rows fixing u_c (empty: a free root)
  std::vector<int> joint;   // s_c, indices into m.speeds (ascending)
  int parent = -1;          // body index; -1: the ground (or none, for a free root)
  std::string name;
  Mat T, Phi;               // u_c' = T u_p' + Phi s_c' + k (docs/notation.md)
  std::vector<Q> k;
  Mat IA;                   // articulated inertia (own My block, then children's share)
  std::vector<Substitution> steps;  // its rows in the order they were solved
  std::vector<Q> pA;        // articulated force
};

class Recursion {
 public:
  Recursion(const model::Model& m, const KktSystem& sys, const std::vector<GiNaC::ex>& c,
            const std::function<GiNaC::ex(const GiNaC::ex&)>& fin, const Probe& probe,
            const std::vector<GiNaC::symbol>* lambda)
      : m_(m), sys_(sys), c_(c), fin_(fin), probe_(probe), lambda_(lambda) {}

  std::optional<KktElimination> run(std::string& why) {
    if (!find_bodies(why) || !find_tree(why) || !assign_rows(why) || !check_inertia(why)) return std::nullopt;
    for (int b : order_)
      if (!joint_map(b, why)) return std::nullopt;
    for (auto it = order_.rbegin(); it != order_.rend(); ++it)
      if (!inwards(*it, why)) return std::nullopt;
    for (int b : order_) outwards(b);
    if (lambda_)
      for (auto it = order_.rbegin(); it != order_.rend(); ++it) multipliers(*it);
    KktElimination out;
    out.steps = std::move(steps_);
    out.forest = true;
    out.blocks = static_cast<int>(bodies_.size());
    for (const auto& b : bodies_) out.largest = std::max(out.largest, static_cast<int>(b.speeds.size()));
    return out;
  }

 private:
  // --- the tree in the rows ---------------------------------------------------------------

  // Bodies are the leaves with speeds; every other speed is a joint speed.
  bool find_bodies(std::string& why) {
    owner_.assign(m_.speeds.size(), -1);
    for (const auto& node : m_.nodes) {
      if (!node.children.empty() || node.speeds.empty()) continue;
      Body b;
      b.speeds = node.speeds;
      std::sort(b.speeds.begin(), b.speeds.end());
      b.name = node.name;
      for (int s : b.speeds) owner_[static_cast<std::size_t>(s)] = static_cast<int>(bodies_.size());
      bodies_.push_back(std::move(b));
    }
    if (bodies_.empty()) {
      why = "the model has no body";
      return false;
    }
    return true;
  }

  // Rows on one body tie it to the ground, rows on two join a parent and a child; the
  // bodies and their joints must form a forest. A part tied to the ground grows from the
  // body the ground rows fix; a free part (a free base) from the body that no row fixes:
  // the first body from which every joint's rows give its child's speeds one by one.
  bool find_tree(std::string& why) {
    const std::size_t nb = bodies_.size();
    std::vector<std::set<int>> next(nb);
    std::vector<char> grounded(nb, 0);
    row_bodies_.resize(sys_.A.size());
    for (std::size_t r = 0; r < sys_.A.size(); ++r) {
      std::set<int> on;
      for (const auto& e : sys_.A[r])
        if (owner_[static_cast<std::size_t>(e.col)] >= 0) on.insert(owner_[static_cast<std::size_t>(e.col)]);
      if (on.empty() || on.size() > 2) {
        why = fmt::format("constraint '{}' {}", m_.constraints[r].name, on.empty() ? "holds joint speeds alone" : "joins more than two bodies");
        return false;
      }
      row_bodies_[r].assign(on.begin(), on.end());
      if (on.size() == 1) grounded[static_cast<std::size_t>(*on.begin())] = 1;
      else {
        next[static_cast<std::size_t>(row_bodies_[r][0])].insert(row_bodies_[r][1]);
        next[static_cast<std::size_t>(row_bodies_[r][1])].insert(row_bodies_[r][0]);
        edge_rows_[{row_bodies_[r][0], row_bodies_[r][1]}].push_back(static_cast<int>(r));
      }
    }
    std::vector<char> seen(nb, 0);
    for (std::size_t first = 0; first < nb; ++first) {
      if (seen[first]) continue;
      // The part of `first`, in index order.
      std::vector<int> part{static_cast<int>(first)};
      seen[first] = 1;
      for (std::size_t i = 0; i < part.size(); ++i)
        for (int n : next[static_cast<std::size_t>(part[i])])
          if (!seen[static_cast<std::size_t>(n)]) {
            seen[static_cast<std::size_t>(n)] = 1;
            part.push_back(n);
          }
      std::sort(part.begin(), part.end());
      std::vector<int> candidates;
      for (int b : part)
        if (grounded[static_cast<std::size_t>(b)]) candidates.push_back(b);
      if (candidates.size() > 1) {
        why = fmt::format("a closed loop through the ground, '{}' and '{}'", bodies_[static_cast<std::size_t>(candidates[0])].name,
                          bodies_[static_cast<std::size_t>(candidates[1])].name);
        return false;
      }
      const bool free_part = candidates.empty();
      if (free_part) candidates = part;
      bool placed = false;
      for (int root : candidates)
        if (grow(root, next, free_part, why)) {
          placed = true;
          break;
        }
      if (!placed) {
        if (why.empty()) why = fmt::format("no body of the part of '{}' roots it", bodies_[first].name);
        return false;
      }
    }
    return true;
  }

  // The part's tree from `root`: parents, and the order (root first). With `check`, every
  // joint's rows must give its child's speeds one by one (else nothing is kept).
  bool grow(int root, const std::vector<std::set<int>>& next, bool check, std::string& why) {
    std::vector<int> order{root}, parent{-1};
    std::map<int, int> parent_of{{root, -1}};
    for (std::size_t i = 0; i < order.size(); ++i) {
      const int b = order[i];
      for (int n : next[static_cast<std::size_t>(b)]) {
        if (n == parent_of.at(b)) continue;
        if (parent_of.count(n)) {
          why = fmt::format("a closed loop through '{}' and '{}'", bodies_[static_cast<std::size_t>(b)].name,
                            bodies_[static_cast<std::size_t>(n)].name);
          return false;
        }
        if (check && !substitution_order(rows_between(b, n), n)) return false;
        parent_of[n] = b;
        order.push_back(n);
      }
    }
    for (int b : order) {
      bodies_[static_cast<std::size_t>(b)].parent = parent_of.at(b);
      order_.push_back(b);
    }
    return true;
  }

  const std::vector<int>& rows_between(int a, int b) const {
    static const std::vector<int> none;
    const auto it = edge_rows_.find({std::min(a, b), std::max(a, b)});
    return it == edge_rows_.end() ? none : it->second;
  }

  // The order in which `rows` give body b's speeds one by one: each in turn has a single
  // speed of b not given yet, with a number for its coefficient. nullopt when there is
  // none (the rows do not fix b explicitly).
  std::optional<std::vector<Substitution>> substitution_order(const std::vector<int>& rows, int b) const {
    const Body& body = bodies_[static_cast<std::size_t>(b)];
    if (rows.size() != body.speeds.size()) return std::nullopt;
    std::vector<Substitution> order;
    std::vector<char> solved(body.speeds.size(), 0), used(rows.size(), 0);
    for (std::size_t step = 0; step < rows.size(); ++step) {
      bool found = false;
      for (std::size_t t = 0; t < rows.size() && !found; ++t) {
        if (used[t]) continue;
        int open = 0, at = -1;
        GiNaC::ex coefficient;
        for (const auto& e : sys_.A[static_cast<std::size_t>(rows[t])]) {
          const int l = position(body.speeds, e.col);
          if (l < 0 || solved[static_cast<std::size_t>(l)]) continue;
          ++open;
          at = l;
          coefficient = e.value;
        }
        if (open == 1 && GiNaC::is_a<GiNaC::numeric>(coefficient) && !coefficient.is_zero()) {
          used[t] = 1;
          solved[static_cast<std::size_t>(at)] = 1;
          order.push_back({rows[t], at, coefficient});
          found = true;
        }
      }
      if (!found) return std::nullopt;
    }
    return order;
  }

  // Each row fixes the deeper of its bodies; each body needs as many rows as speeds, and
  // each joint speed belongs to one body's rows.
  bool assign_rows(std::string& why) {
    std::vector<int> joint_owner(m_.speeds.size(), -1);
    for (std::size_t r = 0; r < sys_.A.size(); ++r) {
      const auto& on = row_bodies_[r];
      int child = on[0];
      if (on.size() == 2 && bodies_[static_cast<std::size_t>(on[1])].parent == on[0]) child = on[1];
      Body& b = bodies_[static_cast<std::size_t>(child)];
      b.rows.push_back(static_cast<int>(r));
      for (const auto& e : sys_.A[r]) {
        if (owner_[static_cast<std::size_t>(e.col)] >= 0) continue;
        int& j = joint_owner[static_cast<std::size_t>(e.col)];
        if (j >= 0 && j != child) {
          why = fmt::format("joint speed '{}' moves two bodies", m_.speeds[static_cast<std::size_t>(e.col)].name);
          return false;
        }
        j = child;
      }
    }
    for (std::size_t s = 0; s < m_.speeds.size(); ++s) {
      if (owner_[s] >= 0) continue;
      if (joint_owner[s] < 0) {
        why = fmt::format("speed '{}' is in no joint", m_.speeds[s].name);
        return false;
      }
      bodies_[static_cast<std::size_t>(joint_owner[s])].joint.push_back(static_cast<int>(s));
    }
    for (auto& b : bodies_)
      if (!b.rows.empty() && b.rows.size() != b.speeds.size()) {
        why = fmt::format("body '{}' has {} speeds and {} rows", b.name, b.speeds.size(), b.rows.size());
        return false;
      }
    return true;
  }

  // Inertia couples speeds of one body, or joint speeds of one joint; it is symmetric.
  bool check_inertia(std::string& why) {
    std::vector<int> group(m_.speeds.size(), -1);
    for (std::size_t b = 0; b < bodies_.size(); ++b) {
      for (int s : bodies_[b].speeds) group[static_cast<std::size_t>(s)] = static_cast<int>(b);
      for (int s : bodies_[b].joint) group[static_cast<std::size_t>(s)] = static_cast<int>(bodies_.size() + b);
    }
    for (std::size_t i = 0; i < sys_.My.size(); ++i)
      for (const auto& e : sys_.My[i]) {
        if (group[i] != group[static_cast<std::size_t>(e.col)]) {
          why = fmt::format("the inertia couples '{}' and '{}'", m_.speeds[i].name, m_.speeds[static_cast<std::size_t>(e.col)].name);
          return false;
        }
        if (!(e.value - my(e.col, static_cast<int>(i))).expand().is_zero()) {
          why = fmt::format("the inertia of '{}' is not symmetric", m_.speeds[i].name);
          return false;
        }
      }
    return true;
  }

  GiNaC::ex my(int i, int j) const {
    for (const auto& e : sys_.My[static_cast<std::size_t>(i)])
      if (e.col == j) return e.value;
    return 0;
  }

  // --- the joint maps -----------------------------------------------------------------------

  Q read(const GiNaC::ex& e) {
    const GiNaC::ex f = fin_(e);
    return {f, probe_.eval(f)};
  }

  /// A named intermediate for q, unless it is a number or a symbol already.
  Q named(const Q& q) {
    if (GiNaC::is_a<GiNaC::numeric>(q.e) || GiNaC::is_a<GiNaC::symbol>(q.e)) return q;
    const GiNaC::symbol s(fmt::format("ab{}", counter_++));
    steps_.push_back(ir::Define{s, q.e, false});
    return {s, q.v};
  }

  static int position(const std::vector<int>& list, int x) {
    const auto it = std::lower_bound(list.begin(), list.end(), x);
    return it != list.end() && *it == x ? static_cast<int>(it - list.begin()) : -1;
  }

  // The body's rows solved for its speeds by substitution: each step takes a row with one
  // speed of the body not yet solved, whose coefficient is a number.
  bool joint_map(int bi, std::string& why) {
    Body& b = bodies_[static_cast<std::size_t>(bi)];
    if (b.rows.empty()) return true;
    const int nu = static_cast<int>(b.speeds.size()), ns = static_cast<int>(b.joint.size());
    const std::vector<int>* up = b.parent >= 0 ? &bodies_[static_cast<std::size_t>(b.parent)].speeds : nullptr;
    const int np = up ? static_cast<int>(up->size()) : 0;
    b.T = Mat(nu, np);
    b.Phi = Mat(nu, ns);
    b.k.assign(static_cast<std::size_t>(nu), Q{});
    const auto order = substitution_order(b.rows, bi);
    if (!order) {
      why = fmt::format("the rows of body '{}' do not give its speeds one by one", b.name);
      return false;
    }
    for (const auto& [row, a, pivot] : *order) {
      // u_a' = (c_r - sum_j A_rj u_j') / pivot.
      const Q inverse{1 / pivot, 1.0 / GiNaC::ex_to<GiNaC::numeric>(pivot).to_double()};
      Q k = read(c_[static_cast<std::size_t>(row)]) * inverse;
      std::vector<Q> x(static_cast<std::size_t>(np)), s(static_cast<std::size_t>(ns));
      for (const auto& e : sys_.A[static_cast<std::size_t>(row)]) {
        const int l = position(b.speeds, e.col);
        if (l == a) continue;
        const Q w = Q{0, 0.0} - read(e.value) * inverse;
        if (l >= 0) {  // an own speed solved before: its map, scaled
          for (int j = 0; j < np; ++j) x[static_cast<std::size_t>(j)] = x[static_cast<std::size_t>(j)] + w * b.T(l, j);
          for (int j = 0; j < ns; ++j) s[static_cast<std::size_t>(j)] = s[static_cast<std::size_t>(j)] + w * b.Phi(l, j);
          k = k + w * b.k[static_cast<std::size_t>(l)];
        } else if (up && position(*up, e.col) >= 0) {
          x[static_cast<std::size_t>(position(*up, e.col))] = x[static_cast<std::size_t>(position(*up, e.col))] + w;
        } else {
          const int j = position(b.joint, e.col);
          s[static_cast<std::size_t>(j)] = s[static_cast<std::size_t>(j)] + w;
        }
      }
      for (int j = 0; j < np; ++j) b.T(a, j) = named(x[static_cast<std::size_t>(j)]);
      for (int j = 0; j < ns; ++j) b.Phi(a, j) = named(s[static_cast<std::size_t>(j)]);
      b.k[static_cast<std::size_t>(a)] = named(k);
    }
    b.steps = *order;
    return true;
  }

  // --- leaves to root -------------------------------------------------------------------------

  void start(Body& b) {
    const int nu = static_cast<int>(b.speeds.size());
    b.IA = Mat(nu, nu);
    b.pA.assign(static_cast<std::size_t>(nu), Q{});
    for (int i = 0; i < nu; ++i) {
      b.pA[static_cast<std::size_t>(i)] = read(sys_.hy[static_cast<std::size_t>(b.speeds[static_cast<std::size_t>(i)])]);
      for (int j = 0; j < nu; ++j) b.IA(i, j) = read(my(b.speeds[static_cast<std::size_t>(i)], b.speeds[static_cast<std::size_t>(j)]));
    }
  }

  // One symmetric solve D [G | g] = [U^T | r] in the generated code; nullopt when D is not
  // positive definite at the probe point.
  bool pivot_solve(const Body& b, const Mat& D, const Mat& rhs, Mat& out, const std::string& label) {
    const int n = D.rows, k = rhs.cols;
    Eigen::MatrixXd Dv(n, n), Rv(n, std::max(1, k));
    Rv.setZero();
    ir::Solve solve;
    solve.label = label;
    solve.n = n;
    solve.spd = true;
    solve.reported = false;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        solve.A.push_back(D(i, j).e);
        Dv(i, j) = D(i, j).v;
      }
    // Only the columns with an entry are solved for; the others give zeros.
    std::vector<int> cols;
    for (int j = 0; j < k; ++j) {
      bool any = false;
      for (int i = 0; i < n; ++i) any = any || !rhs(i, j).e.is_zero();
      if (any) cols.push_back(j);
    }
    for (int i = 0; i < n; ++i)
      for (std::size_t t = 0; t < cols.size(); ++t) {
        solve.B.push_back(rhs(i, cols[t]).e);
        Rv(i, static_cast<int>(t)) = rhs(i, cols[t]).v;
      }
    const Eigen::LLT<Eigen::MatrixXd> llt(Dv);
    if (llt.info() != Eigen::Success || !Dv.allFinite()) return false;
    (void)b;
    const Eigen::MatrixXd Xv = llt.solve(Rv);
    out = Mat(n, k);
    for (int i = 0; i < n; ++i)
      for (std::size_t t = 0; t < cols.size(); ++t) {
        const GiNaC::symbol x(fmt::format("ab{}", counter_++));
        solve.X.push_back(x);
        out(i, cols[t]) = Q{x, Xv(i, static_cast<int>(t))};
      }
    solve.k = static_cast<int>(cols.size());
    if (solve.k > 0) steps_.push_back(solve);
    return true;
  }

  bool inwards(int bi, std::string& why) {
    Body& b = bodies_[static_cast<std::size_t>(bi)];
    if (started_.insert(bi).second) start(b);
    const int nu = static_cast<int>(b.speeds.size()), ns = static_cast<int>(b.joint.size());
    // The children's shares were added as sums: name the totals once.
    for (int i = 0; i < nu; ++i) {
      for (int j = i; j < nu; ++j) b.IA(j, i) = b.IA(i, j) = named(b.IA(i, j));
      b.pA[static_cast<std::size_t>(i)] = named(b.pA[static_cast<std::size_t>(i)]);
    }
    if (b.rows.empty()) {  // a free root: IA u' = pA
      Mat rhs(nu, 1);
      for (int i = 0; i < nu; ++i) rhs(i, 0) = b.pA[static_cast<std::size_t>(i)];
      Mat x;
      if (!pivot_solve(b, b.IA, rhs, x, fmt::format("tree recursion: free body {}", b.name))) {
        why = fmt::format("the articulated inertia of free body '{}' is not positive definite", b.name);
        return false;
      }
      for (int i = 0; i < nu; ++i) accel_[b.speeds[static_cast<std::size_t>(i)]] = x(i, 0).e;
      return true;
    }
    // beta = pA - IA k, U = IA Phi.
    std::vector<Q> beta(static_cast<std::size_t>(nu));
    for (int i = 0; i < nu; ++i) {
      Q sum = b.pA[static_cast<std::size_t>(i)];
      for (int j = 0; j < nu; ++j) sum = sum - b.IA(i, j) * b.k[static_cast<std::size_t>(j)];
      beta[static_cast<std::size_t>(i)] = named(sum);
    }
    Mat U(nu, ns);
    for (int i = 0; i < nu; ++i)
      for (int j = 0; j < ns; ++j) {
        Q sum;
        for (int t = 0; t < nu; ++t) sum = sum + b.IA(i, t) * b.Phi(t, j);
        U(i, j) = named(sum);
      }
    Mat G(ns, nu);
    std::vector<Q> g(static_cast<std::size_t>(ns));
    if (ns > 0) {
      // D = Phi^T U + My_s, r = h_s + Phi^T beta; [G | g] = D^-1 [U^T | r].
      Mat D(ns, ns), rhs(ns, nu + 1);
      for (int i = 0; i < ns; ++i) {
        for (int j = 0; j < ns; ++j) {
          Q sum = read(my(b.joint[static_cast<std::size_t>(i)], b.joint[static_cast<std::size_t>(j)]));
          for (int t = 0; t < nu; ++t) sum = sum + b.Phi(t, i) * U(t, j);
          D(i, j) = sum;
        }
        Q r = read(sys_.hy[static_cast<std::size_t>(b.joint[static_cast<std::size_t>(i)])]);
        for (int t = 0; t < nu; ++t) r = r + b.Phi(t, i) * beta[static_cast<std::size_t>(t)];
        for (int j = 0; j < nu; ++j) rhs(i, j) = U(j, i);
        rhs(i, nu) = r;
      }
      Mat x;
      if (!pivot_solve(b, D, rhs, x, fmt::format("tree recursion: joint of {}", b.name))) {
        why = fmt::format("the joint pivot of body '{}' is not positive definite", b.name);
        return false;
      }
      for (int i = 0; i < ns; ++i) {
        for (int j = 0; j < nu; ++j) G(i, j) = x(i, j);
        g[static_cast<std::size_t>(i)] = x(i, nu);
      }
    }
    b_G_[bi] = G;
    b_g_[bi] = g;
    if (b.parent < 0) return true;
    // What the parent receives: T^T (IA - U G) T and T^T (beta - U g).
    Mat kept(nu, nu);  // IA - U G: what the joint does not take
    std::vector<Q> passed(static_cast<std::size_t>(nu));  // beta - U g
    for (int i = 0; i < nu; ++i) {
      for (int j = i; j < nu; ++j) {
        Q sum = b.IA(i, j);
        for (int t = 0; t < ns; ++t) sum = sum - U(i, t) * G(t, j);
        kept(j, i) = kept(i, j) = named(sum);
      }
      Q sum = beta[static_cast<std::size_t>(i)];
      for (int t = 0; t < ns; ++t) sum = sum - U(i, t) * g[static_cast<std::size_t>(t)];
      passed[static_cast<std::size_t>(i)] = named(sum);
    }
    Body& p = bodies_[static_cast<std::size_t>(b.parent)];
    if (started_.insert(b.parent).second) start(p);
    const int np = static_cast<int>(p.speeds.size());
    Mat IaT(nu, np);  // (IA - U G) T
    for (int i = 0; i < nu; ++i)
      for (int j = 0; j < np; ++j) {
        Q sum;
        for (int t = 0; t < nu; ++t) sum = sum + kept(i, t) * b.T(t, j);
        IaT(i, j) = named(sum);
      }
    for (int i = 0; i < np; ++i) {
      for (int j = i; j < np; ++j) {
        Q sum;
        for (int t = 0; t < nu; ++t) sum = sum + b.T(t, i) * IaT(t, j);
        p.IA(i, j) = p.IA(i, j) + sum;
        if (j != i) p.IA(j, i) = p.IA(i, j);
      }
      Q sum;
      for (int t = 0; t < nu; ++t) sum = sum + b.T(t, i) * passed[static_cast<std::size_t>(t)];
      p.pA[static_cast<std::size_t>(i)] = p.pA[static_cast<std::size_t>(i)] + sum;
    }
    return true;
  }

  // --- root to leaves -------------------------------------------------------------------------

  void define(int speed, const GiNaC::ex& value) {
    const GiNaC::symbol& target = m_.speed_dots[static_cast<std::size_t>(speed)];
    steps_.push_back(ir::Define{target, value, true});
    accel_[speed] = target;
  }

  void outwards(int bi) {
    Body& b = bodies_[static_cast<std::size_t>(bi)];
    const int nu = static_cast<int>(b.speeds.size()), ns = static_cast<int>(b.joint.size());
    if (b.rows.empty()) {
      for (int s : b.speeds) define(s, accel_.at(s));
      return;
    }
    // y = T u_p' (zero under the ground).
    std::vector<GiNaC::ex> y(static_cast<std::size_t>(nu), GiNaC::ex(0));
    if (b.parent >= 0) {
      const Body& p = bodies_[static_cast<std::size_t>(b.parent)];
      for (int i = 0; i < nu; ++i) {
        GiNaC::ex sum = 0;
        for (std::size_t j = 0; j < p.speeds.size(); ++j)
          if (!b.T(i, static_cast<int>(j)).e.is_zero()) sum += b.T(i, static_cast<int>(j)).e * accel_.at(p.speeds[j]);
        y[static_cast<std::size_t>(i)] = named(Q{sum, 0.0}).e;
      }
    }
    const Mat& G = b_G_.at(bi);
    const std::vector<Q>& g = b_g_.at(bi);
    for (int i = 0; i < ns; ++i) {
      GiNaC::ex value = g[static_cast<std::size_t>(i)].e;
      for (int j = 0; j < nu; ++j)
        if (!G(i, j).e.is_zero()) value -= G(i, j).e * y[static_cast<std::size_t>(j)];
      define(b.joint[static_cast<std::size_t>(i)], value);
    }
    for (int i = 0; i < nu; ++i) {
      GiNaC::ex value = y[static_cast<std::size_t>(i)] + b.k[static_cast<std::size_t>(i)].e;
      for (int j = 0; j < ns; ++j)
        if (!b.Phi(i, j).e.is_zero()) value += b.Phi(i, j).e * accel_.at(b.joint[static_cast<std::size_t>(j)]);
      define(b.speeds[static_cast<std::size_t>(i)], value);
    }
  }


  // --- the multipliers, leaves to root -----------------------------------------------------

  // On body b's speeds, A^T lambda = My u' - hy: its own rows' share A_bb^T lambda_b is
  // that minus what its children's rows put on its speeds (their lambdas are known,
  // leaves first). A_bb is triangular in the order the rows were solved, so its transpose
  // is solved last row first.
  void multipliers(int bi) {
    const Body& b = bodies_[static_cast<std::size_t>(bi)];
    if (b.rows.empty()) return;
    const int nu = static_cast<int>(b.speeds.size());
    std::vector<GiNaC::ex> rest(static_cast<std::size_t>(nu));
    for (int i = 0; i < nu; ++i) {
      const int s = b.speeds[static_cast<std::size_t>(i)];
      GiNaC::ex sum = -read(sys_.hy[static_cast<std::size_t>(s)]).e;
      for (int j = 0; j < nu; ++j) {
        const GiNaC::ex mij = read(my(s, b.speeds[static_cast<std::size_t>(j)])).e;
        if (!mij.is_zero()) sum += mij * accel_.at(b.speeds[static_cast<std::size_t>(j)]);
      }
      rest[static_cast<std::size_t>(i)] = sum;
    }
    for (std::size_t r = 0; r < sys_.A.size(); ++r) {
      const auto& on = row_bodies_[r];
      if (on.size() != 2 || (on[0] != bi && on[1] != bi)) continue;
      const int other = on[0] == bi ? on[1] : on[0];
      if (bodies_[static_cast<std::size_t>(other)].parent != bi) continue;  // a child's row
      for (const auto& e : sys_.A[r]) {
        const int l = position(b.speeds, e.col);
        if (l >= 0) rest[static_cast<std::size_t>(l)] -= read(e.value).e * (*lambda_)[r];
      }
    }
    for (auto step = b.steps.rbegin(); step != b.steps.rend(); ++step) {
      const auto& [row, a, pivot] = *step;
      GiNaC::ex value = rest[static_cast<std::size_t>(a)];
      for (auto later = b.steps.rbegin(); later != step; ++later) {
        const int r = later->row;
        for (const auto& e : sys_.A[static_cast<std::size_t>(r)])
          if (position(b.speeds, e.col) == a) value -= read(e.value).e * (*lambda_)[static_cast<std::size_t>(r)];
      }
      steps_.push_back(ir::Define{(*lambda_)[static_cast<std::size_t>(row)], value / pivot, true});
    }
  }

  const model::Model& m_;
  const KktSystem& sys_;
  const std::vector<GiNaC::ex>& c_;
  const std::function<GiNaC::ex(const GiNaC::ex&)>& fin_;
  const Probe& probe_;
  const std::vector<GiNaC::symbol>* lambda_;  // the rows' multipliers to define, or null
  std::vector<Body> bodies_;
  std::vector<int> owner_;                    // per speed: its body, -1 for a joint speed
  std::vector<std::vector<int>> row_bodies_;  // per row: the bodies it touches (1 or 2)
  std::map<std::pair<int, int>, std::vector<int>> edge_rows_;  // (lower, higher body) -> rows on both
  std::vector<int> order_;                    // roots first, each body after its parent
  std::set<int> started_;                     // bodies whose IA, pA were initialised
  std::map<int, Mat> b_G_;
  std::map<int, std::vector<Q>> b_g_;
  std::map<int, GiNaC::ex> accel_;            // speed -> its rate's symbol once defined
  std::vector<ir::Step> steps_;
  long counter_ = 0;
};

}  // namespace

std::optional<KktElimination> tree_recursion(const model::Model& m, const KktSystem& sys, const std::vector<GiNaC::ex>& c,
                                             const std::function<GiNaC::ex(const GiNaC::ex&)>& fin, const Probe& probe,
                                             const std::vector<GiNaC::symbol>* lambda, std::string& why) {
  return Recursion(m, sys, c, fin, probe, lambda).run(why);
}

}  // namespace mbsc::sym
