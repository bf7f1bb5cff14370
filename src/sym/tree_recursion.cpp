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
#include <memory>
#include <set>
#include <tuple>

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
  bool free_root = false;   // a free part's root: no rows fix it
  std::string name;
  Mat T, Phi;               // u_c' = T u_p' + Phi s_c' + k (docs/notation.md)
  std::vector<Q> k;
  Mat IA;                   // articulated inertia (own My block, then children's share)
  Mat pA;                   // articulated force, a column per right-hand side
  Mat G, g;                 // s_c' = g - G T u_p' (a free root: u_c' = g), g per column
  Mat U, D;                 // U = IA Phi, the joint pivot D = Phi^T U + My_s
  std::vector<Substitution> steps;  // its rows in the order they were solved
  std::vector<TreeFactors::Substitution> k_map;  // how its rows' right-hand sides give k
};

class Recursion {
 public:
  Recursion(const model::Model& m, const KktSystem& sys, const std::vector<GiNaC::ex>& c,
            const std::function<GiNaC::ex(const GiNaC::ex&)>& fin, const Probe& probe,
            const std::vector<GiNaC::symbol>* lambda)
      : m_(m), sys_(sys), c_(c), fin_(fin), probe_(probe), lambda_(lambda) {}

  std::optional<KktElimination> run(std::string& why) {
    if (!find_bodies(why) || !find_tree(why) || !assign_rows(why) || !check_inertia(why)) return std::nullopt;
    // Loops on free bodies alone (no joint coordinates: a sleigh's or a disc's velocity
    // rows) are the block elimination's case: its speeds-first order is the same
    // recursion without the sweeps, and cheaper.
    if (!loop_rows_.empty() && std::all_of(owner_.begin(), owner_.end(), [](int o) { return o >= 0; })) {
      why = "its rows close loops on free bodies alone";
      return std::nullopt;
    }
    for (int b : order_)
      if (!joint_map(b, why)) return std::nullopt;
    for (auto it = order_.rbegin(); it != order_.rend(); ++it)
      if (!inwards(*it, why)) return std::nullopt;
    if (!close_loops(why)) return std::nullopt;
    for (int b : order_) outwards(b);
    if (lambda_)
      for (auto it = order_.rbegin(); it != order_.rend(); ++it) multipliers(*it);
    KktElimination out;
    out.steps = std::move(steps_);
    out.forest = loop_rows_.empty();
    out.speeds_first = !loop_rows_.empty();
    out.blocks = static_cast<int>(bodies_.size());
    for (const auto& b : bodies_) out.largest = std::max(out.largest, static_cast<int>(b.speeds.size()));
    if (out.forest) out.tree = factors();
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

  // Rows on one body tie it to the ground, rows on two join two bodies. A part tied to the
  // ground grows from the ground, a free part (a free base) from the first body from which
  // it grows whole. A body joins the tree through the rows it shares with a body already
  // in it (or with the ground) when they give its speeds one by one; a joint's rows (those
  // that carry joint speeds) are taken first, so that every joint speed lies on the tree.
  // Every row left over closes a loop (docs/formulation.md, "Loops on the tree").
  bool find_tree(std::string& why) {
    const std::size_t nb = bodies_.size();
    next_.assign(nb, {});
    std::vector<char> grounded(nb, 0);
    row_bodies_.resize(sys_.A.size());
    rows_on_.assign(nb, {});
    for (std::size_t r = 0; r < sys_.A.size(); ++r) {
      std::set<int> on;
      for (const auto& e : sys_.A[r])
        if (owner_[static_cast<std::size_t>(e.col)] >= 0) on.insert(owner_[static_cast<std::size_t>(e.col)]);
      row_bodies_[r].assign(on.begin(), on.end());
      for (int b : on) rows_on_[static_cast<std::size_t>(b)].push_back(static_cast<int>(r));
      if (on.size() == 1) {
        grounded[static_cast<std::size_t>(*on.begin())] = 1;
        edge_rows_[{kGround, *on.begin()}].push_back(static_cast<int>(r));
      } else if (on.size() == 2) {
        next_[static_cast<std::size_t>(row_bodies_[r][0])].insert(row_bodies_[r][1]);
        next_[static_cast<std::size_t>(row_bodies_[r][1])].insert(row_bodies_[r][0]);
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
        for (int n : next_[static_cast<std::size_t>(part[i])])
          if (!seen[static_cast<std::size_t>(n)]) {
            seen[static_cast<std::size_t>(n)] = 1;
            part.push_back(n);
          }
      std::sort(part.begin(), part.end());
      std::vector<int> ground_side;
      for (int b : part)
        if (grounded[static_cast<std::size_t>(b)]) ground_side.push_back(b);
      // From the ground alone first; what it leaves unplaced may hang from one free root
      // (a floating base whose feet loop rows hold on the ground).
      if (!ground_side.empty() && grow(part, kNoRoot, ground_side)) continue;
      const std::vector<int> roots = ground_side.empty() ? part : unplaced_;
      bool placed = false;
      for (int root : roots)
        if ((placed = grow(part, root, ground_side))) break;
      if (!placed) {
        why = ground_side.empty()
                  ? fmt::format("no body of the part of '{}' roots it", bodies_[first].name)
                  : fmt::format("body '{}' is not placed by the rows it shares with the ground or another body",
                                bodies_[static_cast<std::size_t>(roots.front())].name);
        return false;
      }
    }
    return true;
  }

  static constexpr int kGround = -1;
  static constexpr int kNoRoot = -2;

  // The part's tree from the ground (when `ground_side`, the bodies with rows on the
  // ground alone, is not empty) and from the free body `root` (kNoRoot: none): parents
  // and the order, roots first. False, keeping nothing but the bodies left out
  // (unplaced_), when a body of the part is left out.
  bool grow(const std::vector<int>& part, int root, const std::vector<int>& ground_side) {
    std::map<int, int> parent_of;
    std::vector<int> sources, placed;
    if (!ground_side.empty()) sources.push_back(kGround);
    if (root != kNoRoot) {
      sources.push_back(root);
      parent_of[root] = kGround;
      placed.push_back(root);
    }
    auto neighbours = [&](int a) -> std::vector<int> {
      if (a == kGround) return ground_side;
      return {next_[static_cast<std::size_t>(a)].begin(), next_[static_cast<std::size_t>(a)].end()};
    };
    std::map<int, std::vector<int>> placing;  // body -> the rows that place it
    auto fits = [&](int a, int n, bool joints_only) {
      for (const auto& rows : row_groups(rows_between(a, n))) {
        if (joints_only && !carries_joint_speed(rows)) continue;
        if (substitution_order(rows, n)) {
          placing[n] = rows;
          return true;
        }
      }
      return false;
    };
    // One sweep over the placed bodies: with `all`, every body a joint's rows place (and
    // those they place in turn); without, the first body any rows place.
    auto sweep = [&](bool joints_only) {
      bool any = false;
      for (std::size_t i = 0; i < sources.size(); ++i)
        for (int n : neighbours(sources[i])) {
          if (parent_of.count(n) || !fits(sources[i], n, joints_only)) continue;
          parent_of[n] = sources[i];
          sources.push_back(n);
          placed.push_back(n);
          any = true;
          if (!joints_only) return true;
        }
      return any;
    };
    while (sweep(true) || sweep(false)) {
    }
    if (placed.size() != part.size()) {
      unplaced_.clear();
      for (int b : part)
        if (!parent_of.count(b)) unplaced_.push_back(b);
      return false;
    }
    for (int b : placed) {
      bodies_[static_cast<std::size_t>(b)].parent = parent_of.at(b);
      bodies_[static_cast<std::size_t>(b)].free_root = b == root;
      if (b != root) bodies_[static_cast<std::size_t>(b)].rows = placing.at(b);
      order_.push_back(b);
    }
    return true;
  }

  // The sets of rows that may place a body, tried in turn: each element's rows (a joint
  // and a loop closed between the same two bodies are two elements, told apart by where
  // they are written), then all of them.
  std::vector<std::vector<int>> row_groups(const std::vector<int>& rows) const {
    std::vector<std::vector<int>> groups;
    std::map<std::tuple<std::string, int, int>, std::size_t> of_element;
    for (int r : rows) {
      const auto& pos = m_.constraints[static_cast<std::size_t>(r)].pos;
      const auto key = std::make_tuple(pos.file, pos.line, pos.col);
      const auto [it, added] = of_element.emplace(key, groups.size());
      if (added) groups.emplace_back();
      groups[it->second].push_back(r);
    }
    if (groups.size() != 1) groups.push_back(rows);
    return groups;
  }

  bool carries_joint_speed(const std::vector<int>& rows) const {
    for (int r : rows)
      for (const auto& e : sys_.A[static_cast<std::size_t>(r)])
        if (owner_[static_cast<std::size_t>(e.col)] < 0) return true;
    return false;
  }

  // The rows on bodies a and b alone (a = kGround: on b alone).
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

  // A placed body's rows are those it shares with its parent (or the ground); each joint
  // speed belongs to one body's rows. Every other row closes a loop.
  bool assign_rows(std::string& why) {
    joint_owner_.assign(m_.speeds.size(), -1);
    std::vector<char> on_tree(sys_.A.size(), 0);
    for (int bi : order_) {
      Body& b = bodies_[static_cast<std::size_t>(bi)];
      if (b.free_root) continue;
      for (int r : b.rows) {
        on_tree[static_cast<std::size_t>(r)] = 1;
        for (const auto& e : sys_.A[static_cast<std::size_t>(r)]) {
          if (owner_[static_cast<std::size_t>(e.col)] >= 0) continue;
          int& j = joint_owner_[static_cast<std::size_t>(e.col)];
          if (j >= 0 && j != bi) {
            why = fmt::format("joint speed '{}' moves two bodies", m_.speeds[static_cast<std::size_t>(e.col)].name);
            return false;
          }
          j = bi;
        }
      }
    }
    for (std::size_t s = 0; s < m_.speeds.size(); ++s) {
      if (owner_[s] >= 0) continue;
      if (joint_owner_[s] < 0) {
        why = fmt::format("speed '{}' is in no joint", m_.speeds[s].name);
        return false;
      }
      bodies_[static_cast<std::size_t>(joint_owner_[s])].joint.push_back(static_cast<int>(s));
    }
    for (std::size_t r = 0; r < sys_.A.size(); ++r)
      if (!on_tree[r]) loop_rows_.push_back(static_cast<int>(r));
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
      TreeFactors::Substitution by_row{a, row, inverse.e, {}};
      for (const auto& e : sys_.A[static_cast<std::size_t>(row)]) {
        const int l = position(b.speeds, e.col);
        if (l == a) continue;
        const Q w = Q{0, 0.0} - read(e.value) * inverse;
        if (l >= 0) {  // an own speed solved before: its map, scaled
          by_row.own.emplace_back(l, w.e);
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
      b.k_map.push_back(std::move(by_row));
    }
    b.steps = *order;
    return true;
  }

  // --- leaves to root -------------------------------------------------------------------------
  //
  // A body's articulated force has a column per right-hand side: column 0 is the model's
  // own (hy, with the rows' c through k), column 1 + j the force of a unit multiplier of
  // loop row j (that row's entries, with no c of its own). Away from the loop rows' bodies
  // and the bodies above them those columns are zeros, which the algebra drops.

  int columns() const { return 1 + static_cast<int>(loop_rows_.size()); }

  // Row r's entry on speed s, read; zero when it has none.
  Q entry(int r, int s) {
    for (const auto& e : sys_.A[static_cast<std::size_t>(r)])
      if (e.col == s) return read(e.value);
    return {};
  }

  // The force on speed s in column col.
  Q force(int s, int col) {
    return col == 0 ? read(sys_.hy[static_cast<std::size_t>(s)]) : entry(loop_rows_[static_cast<std::size_t>(col - 1)], s);
  }

  void start(Body& b) {
    const int nu = static_cast<int>(b.speeds.size());
    b.IA = Mat(nu, nu);
    b.pA = Mat(nu, columns());
    for (int i = 0; i < nu; ++i) {
      for (int col = 0; col < columns(); ++col) b.pA(i, col) = force(b.speeds[static_cast<std::size_t>(i)], col);
      for (int j = 0; j < nu; ++j) b.IA(i, j) = read(my(b.speeds[static_cast<std::size_t>(i)], b.speeds[static_cast<std::size_t>(j)]));
    }
  }

  // One symmetric solve D X = rhs in the generated code (only rhs's columns with an entry;
  // the others give zeros); false when D is not positive definite at the probe point.
  // `reported`: the generated `conditioning` reports it.
  bool pivot_solve(const Mat& D, const Mat& rhs, Mat& out, const std::string& label, bool reported = false) {
    const int n = D.rows, k = rhs.cols;
    Eigen::MatrixXd Dv(n, n), Rv(n, std::max(1, k));
    Rv.setZero();
    ir::Solve solve;
    solve.label = label;
    solve.n = n;
    solve.spd = true;
    solve.reported = reported;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        solve.A.push_back(D(i, j).e);
        Dv(i, j) = D(i, j).v;
      }
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
    const int nu = static_cast<int>(b.speeds.size()), ns = static_cast<int>(b.joint.size()), nc = columns();
    // The children's shares were added as sums: name the totals once.
    for (int i = 0; i < nu; ++i) {
      for (int j = i; j < nu; ++j) b.IA(j, i) = b.IA(i, j) = named(b.IA(i, j));
      for (int col = 0; col < nc; ++col) b.pA(i, col) = named(b.pA(i, col));
    }
    if (b.free_root) {  // IA u' = pA, column by column
      if (!pivot_solve(b.IA, b.pA, b.g, fmt::format("tree recursion: free body {}", b.name))) {
        why = fmt::format("the articulated inertia of free body '{}' is not positive definite", b.name);
        return false;
      }
      return true;
    }
    // beta = pA - IA k (k in the model's column only), U = IA Phi.
    Mat beta(nu, nc);
    for (int i = 0; i < nu; ++i)
      for (int col = 0; col < nc; ++col) {
        Q sum = b.pA(i, col);
        if (col == 0)
          for (int j = 0; j < nu; ++j) sum = sum - b.IA(i, j) * b.k[static_cast<std::size_t>(j)];
        beta(i, col) = named(sum);
      }
    Mat U(nu, ns);
    for (int i = 0; i < nu; ++i)
      for (int j = 0; j < ns; ++j) {
        Q sum;
        for (int t = 0; t < nu; ++t) sum = sum + b.IA(i, t) * b.Phi(t, j);
        U(i, j) = named(sum);
      }
    b.U = U;
    b.G = Mat(ns, nu);
    b.g = Mat(ns, nc);
    if (ns > 0) {
      // D = Phi^T U + My_s, r = h_s + Phi^T beta; [G | g] = D^-1 [U^T | r].
      Mat D(ns, ns), rhs(ns, nu + nc);
      for (int i = 0; i < ns; ++i) {
        const int s = b.joint[static_cast<std::size_t>(i)];
        for (int j = 0; j < ns; ++j) {
          Q sum = read(my(s, b.joint[static_cast<std::size_t>(j)]));
          for (int t = 0; t < nu; ++t) sum = sum + b.Phi(t, i) * U(t, j);
          D(i, j) = sum;
        }
        for (int j = 0; j < nu; ++j) rhs(i, j) = U(j, i);
        for (int col = 0; col < nc; ++col) {
          Q r = force(s, col);
          for (int t = 0; t < nu; ++t) r = r + b.Phi(t, i) * beta(t, col);
          rhs(i, nu + col) = r;
        }
      }
      b.D = D;
      Mat x;
      if (!pivot_solve(D, rhs, x, fmt::format("tree recursion: joint of {}", b.name))) {
        why = fmt::format("the joint pivot of body '{}' is not positive definite", b.name);
        return false;
      }
      for (int i = 0; i < ns; ++i) {
        for (int j = 0; j < nu; ++j) b.G(i, j) = x(i, j);
        for (int col = 0; col < nc; ++col) b.g(i, col) = x(i, nu + col);
      }
    }
    if (b.parent == kGround) return true;
    // What the parent receives: T^T (IA - U G) T and T^T (beta - U g).
    Mat kept(nu, nu);     // IA - U G: what the joint does not take
    Mat passed(nu, nc);   // beta - U g
    for (int i = 0; i < nu; ++i) {
      for (int j = i; j < nu; ++j) {
        Q sum = b.IA(i, j);
        for (int t = 0; t < ns; ++t) sum = sum - U(i, t) * b.G(t, j);
        kept(j, i) = kept(i, j) = named(sum);
      }
      for (int col = 0; col < nc; ++col) {
        Q sum = beta(i, col);
        for (int t = 0; t < ns; ++t) sum = sum - U(i, t) * b.g(t, col);
        passed(i, col) = named(sum);
      }
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
      for (int col = 0; col < nc; ++col) {
        Q sum;
        for (int t = 0; t < nu; ++t) sum = sum + b.T(t, i) * passed(t, col);
        p.pA(i, col) = p.pA(i, col) + sum;
      }
    }
    return true;
  }

  // --- the loops --------------------------------------------------------------------------------
  //
  // The tree's accelerations are linear in the loop rows' multipliers lambda_l:
  // u' = u'_0 + X lambda_l, column 0 giving u'_0 and column 1 + j the column X_j. The loop
  // rows A_l u' = c_l then ask (A_l X) lambda_l = c_l - A_l u'_0, where A_l X = A_l M^-1 A_l^T
  // over the tree's inertia is symmetric and positive definite wherever the rows keep
  // their rank: the one pivot the loops add, a Schur complement as in the speeds-first
  // elimination, and reported as such. Only the bodies the loop rows read, and those above
  // them, are swept for u'_0 and X; then every body's gains take lambda_l in, and the
  // sweep root to leaves runs once, as without loops.
  bool close_loops(std::string& why) {
    if (loop_rows_.empty()) return true;
    const int nc = columns(), nl = nc - 1;
    std::set<int> needed;
    for (int r : loop_rows_)
      for (const auto& e : sys_.A[static_cast<std::size_t>(r)]) {
        int b = owner_[static_cast<std::size_t>(e.col)] >= 0 ? owner_[static_cast<std::size_t>(e.col)]
                                                               : joint_owner_[static_cast<std::size_t>(e.col)];
        while (b != kGround && needed.insert(b).second) b = bodies_[static_cast<std::size_t>(b)].parent;
      }
    std::vector<std::map<int, Q>> acc(static_cast<std::size_t>(nc));  // per column: speed -> its rate
    for (int bi : order_)
      if (needed.count(bi))
        for (int col = 0; col < nc; ++col) sweep_body(bi, col, acc[static_cast<std::size_t>(col)]);
    Mat W(nl, nl), rhs(nl, 1);
    for (int i = 0; i < nl; ++i) {
      const int row = loop_rows_[static_cast<std::size_t>(i)];
      Q r = read(c_[static_cast<std::size_t>(row)]);
      for (const auto& e : sys_.A[static_cast<std::size_t>(row)]) {
        const Q a = read(e.value);
        r = r - a * acc[0].at(e.col);
        for (int j = 0; j < nl; ++j) W(i, j) = W(i, j) + a * acc[static_cast<std::size_t>(1 + j)].at(e.col);
      }
      rhs(i, 0) = r;
    }
    Mat x;
    if (!pivot_solve(W, rhs, x, "tree recursion: loop rows", /*reported=*/true)) {
      why = "the loop rows are redundant at the probe point (A M^-1 A^T is singular)";
      return false;
    }
    loop_lambda_.assign(static_cast<std::size_t>(nl), Q{});
    for (int i = 0; i < nl; ++i) {
      Q l = x(i, 0);
      if (lambda_) {
        const GiNaC::symbol& target = (*lambda_)[static_cast<std::size_t>(loop_rows_[static_cast<std::size_t>(i)])];
        steps_.push_back(ir::Define{target, l.e, true});
        l.e = target;
      }
      loop_lambda_[static_cast<std::size_t>(i)] = l;
    }
    // Column 0 of every body's gains becomes the whole: g_0 + sum_j g_j lambda_j.
    for (auto& b : bodies_)
      for (int i = 0; i < b.g.rows; ++i)
        for (int j = 0; j < nl; ++j) b.g(i, 0) = b.g(i, 0) + b.g(i, 1 + j) * loop_lambda_[static_cast<std::size_t>(j)];
    return true;
  }

  // Body bi's rates in column col from its parent's in `acc` (the sweep root to leaves on
  // one right-hand side: y = T u_p', s' = g - G y, u' = y + Phi s' + k).
  void sweep_body(int bi, int col, std::map<int, Q>& acc) {
    const Body& b = bodies_[static_cast<std::size_t>(bi)];
    const int nu = static_cast<int>(b.speeds.size()), ns = static_cast<int>(b.joint.size());
    if (b.free_root) {
      for (int i = 0; i < nu; ++i) acc[b.speeds[static_cast<std::size_t>(i)]] = b.g(i, col);
      return;
    }
    std::vector<Q> y(static_cast<std::size_t>(nu));
    if (b.parent != kGround) {
      const Body& p = bodies_[static_cast<std::size_t>(b.parent)];
      for (int i = 0; i < nu; ++i) {
        Q sum;
        for (std::size_t j = 0; j < p.speeds.size(); ++j) sum = sum + b.T(i, static_cast<int>(j)) * acc.at(p.speeds[j]);
        y[static_cast<std::size_t>(i)] = named(sum);
      }
    }
    for (int i = 0; i < ns; ++i) {
      Q v = b.g(i, col);
      for (int j = 0; j < nu; ++j) v = v - b.G(i, j) * y[static_cast<std::size_t>(j)];
      acc[b.joint[static_cast<std::size_t>(i)]] = named(v);
    }
    for (int i = 0; i < nu; ++i) {
      Q v = y[static_cast<std::size_t>(i)];
      if (col == 0) v = v + b.k[static_cast<std::size_t>(i)];
      for (int j = 0; j < ns; ++j) v = v + b.Phi(i, j) * acc.at(b.joint[static_cast<std::size_t>(j)]);
      acc[b.speeds[static_cast<std::size_t>(i)]] = named(v);
    }
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
    if (b.free_root) {
      for (int i = 0; i < nu; ++i) define(b.speeds[static_cast<std::size_t>(i)], b.g(i, 0).e);
      return;
    }
    // y = T u_p' (zero under the ground).
    std::vector<GiNaC::ex> y(static_cast<std::size_t>(nu), GiNaC::ex(0));
    if (b.parent != kGround) {
      const Body& p = bodies_[static_cast<std::size_t>(b.parent)];
      for (int i = 0; i < nu; ++i) {
        GiNaC::ex sum = 0;
        for (std::size_t j = 0; j < p.speeds.size(); ++j)
          if (!b.T(i, static_cast<int>(j)).e.is_zero()) sum += b.T(i, static_cast<int>(j)).e * accel_.at(p.speeds[j]);
        y[static_cast<std::size_t>(i)] = named(Q{sum, 0.0}).e;
      }
    }
    for (int i = 0; i < ns; ++i) {
      GiNaC::ex value = b.g(i, 0).e;
      for (int j = 0; j < nu; ++j)
        if (!b.G(i, j).e.is_zero()) value -= b.G(i, j).e * y[static_cast<std::size_t>(j)];
      define(b.joint[static_cast<std::size_t>(i)], value);
    }
    for (int i = 0; i < nu; ++i) {
      GiNaC::ex value = y[static_cast<std::size_t>(i)] + b.k[static_cast<std::size_t>(i)].e;
      for (int j = 0; j < ns; ++j)
        if (!b.Phi(i, j).e.is_zero()) value += b.Phi(i, j).e * accel_.at(b.joint[static_cast<std::size_t>(j)]);
      define(b.speeds[static_cast<std::size_t>(i)], value);
    }
  }

  // --- what later solves keep (sym/tree_sweep.hpp) -----------------------------------------

  std::shared_ptr<const TreeFactors> factors() const {
    auto exprs = [](const Mat& a) {
      std::vector<GiNaC::ex> e;
      for (const Q& q : a.q) e.push_back(q.e);
      return e;
    };
    auto tree = std::make_shared<TreeFactors>();
    for (const Body& b : bodies_) {
      TreeFactors::Body f;
      f.speeds = b.speeds;
      f.joint = b.joint;
      f.parent = b.parent == kGround ? -1 : b.parent;
      f.free_root = b.free_root;
      f.T = exprs(b.T);
      f.Phi = exprs(b.Phi);
      f.IA = exprs(b.IA);
      f.U = exprs(b.U);
      f.D = exprs(b.D);
      f.G = exprs(b.G);
      f.substitutions = b.k_map;
      tree->bodies.push_back(std::move(f));
    }
    tree->order = order_;
    return tree;
  }

  // --- the multipliers, leaves to root -----------------------------------------------------

  // On body b's speeds, A^T lambda = My u' - hy: its own rows' share A_bb^T lambda_b is
  // that minus what the other rows on its speeds put there (its children's rows, known
  // leaves first, and the loop rows, known from the loops' solve). A_bb is triangular in
  // the order the rows were solved, so its transpose is solved last row first.
  void multipliers(int bi) {
    const Body& b = bodies_[static_cast<std::size_t>(bi)];
    if (b.free_root) return;
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
    for (int r : rows_on_[static_cast<std::size_t>(bi)]) {
      if (std::find(b.rows.begin(), b.rows.end(), r) != b.rows.end()) continue;
      for (const auto& e : sys_.A[static_cast<std::size_t>(r)]) {
        const int l = position(b.speeds, e.col);
        if (l >= 0) rest[static_cast<std::size_t>(l)] -= read(e.value).e * (*lambda_)[static_cast<std::size_t>(r)];
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
  std::vector<int> joint_owner_;              // per joint speed: the body whose rows carry it
  std::vector<std::vector<int>> row_bodies_;  // per row: the bodies it touches
  std::vector<std::vector<int>> rows_on_;     // per body: the rows on its speeds
  std::vector<std::set<int>> next_;           // per body: the bodies it shares rows with (two-body rows)
  std::map<std::pair<int, int>, std::vector<int>> edge_rows_;  // (lower, higher body; kGround) -> rows on them alone
  std::vector<int> unplaced_;                 // the bodies a failed grow left out
  std::vector<int> order_;                    // roots first, each body after its parent
  std::vector<int> loop_rows_;                // the rows off the tree, in row order
  std::vector<Q> loop_lambda_;                // their multipliers
  std::set<int> started_;                     // bodies whose IA, pA were initialised
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
