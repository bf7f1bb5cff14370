// SPDX-License-Identifier: GPL-2.0-or-later
// Block elimination of the sparse dependent-coordinate system (include/mbsc/sym/kkt_elimination.hpp).
//
// The story: unknowns (every speed's rate, every multiplier) are grouped into blocks; the
// symmetric matrix K = [My -A^T; -A 0] is kept as dense blocks on a sparse block graph,
// each entry both as an expression (what the generated code computes) and as its value at
// the probe point (what decides the order). Eliminating block p with pivot P = K_pp and
// neighbours h solves P X = [K_ph ... | r_p] once (one small dense solve in the generated
// code), updates K_hk -= K_ph^T X_k and r_h -= K_ph^T x_p for every pair of neighbours,
// and drops p. Back substitution, last block first, gives x_p = x_r - sum_h X_h x_h.
#include "mbsc/sym/kkt_elimination.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <set>
#include <tuple>

namespace mbsc::sym {

namespace {

/// A dense rows x cols block, row-major: expressions and their probe values.
struct Block {
  int rows = 0, cols = 0;
  std::vector<GiNaC::ex> e;
  std::vector<double> v;
  Block() = default;
  Block(int r, int c) : rows(r), cols(c), e(static_cast<std::size_t>(r * c), GiNaC::ex(0)), v(static_cast<std::size_t>(r * c), 0.0) {}
  std::size_t at(int i, int j) const { return static_cast<std::size_t>(i * cols + j); }
  bool nonzero(int i, int j) const { return !e[at(i, j)].is_zero(); }
  Block transposed() const {
    Block t(cols, rows);
    for (int i = 0; i < rows; ++i)
      for (int j = 0; j < cols; ++j) {
        t.e[t.at(j, i)] = e[at(i, j)];
        t.v[t.at(j, i)] = v[at(i, j)];
      }
    return t;
  }
};

/// One group of unknowns: speeds (indices into m.speeds) or constraints (into m.constraints).
struct Group {
  bool speed = true;
  std::vector<int> members;
};

/// What back substitution needs from one elimination.
struct Eliminated {
  int p = 0;
  std::vector<int> neighbours;
  std::vector<Block> X;          // per neighbour: |p| x |h|
  std::vector<GiNaC::ex> xr_e;   // |p|
};

class Eliminator {
 public:
  Eliminator(const model::Model& m, const KktSystem& sys, const std::vector<GiNaC::ex>& c,
             const std::vector<GiNaC::symbol>& lambda, const std::function<GiNaC::ex(const GiNaC::ex&)>& fin,
             const Probe& probe, bool speeds_first)
      : m_(m), sys_(sys), lambda_(lambda), fin_(fin), probe_(probe), speeds_first_(speeds_first) {
    group_speeds();
    group_constraints();
    fill_blocks(c);
  }

  std::optional<KktElimination> run(std::string& why) {
    KktElimination out;
    if (!asymmetric_.empty()) {
      why = "the inertia of " + asymmetric_ + " is not symmetric";
      return std::nullopt;
    }
    const bool acyclic = is_forest();
    original_.resize(groups_.size());
    for (std::size_t g = 0; g < groups_.size(); ++g)
      for (const auto& [h, b] : off_[g]) original_[g].push_back(h);
    joined_.assign(groups_.size(), -1);
    for (std::size_t g = 0; g < groups_.size(); ++g) joined_[g] = static_cast<int>(g);
    const int G = static_cast<int>(groups_.size());
    key_.assign(static_cast<std::size_t>(G), {-1, 0, 0});
    eliminated_.assign(static_cast<std::size_t>(G), 0);
    for (int g = 0; g < G; ++g) refresh(g);
    std::vector<Eliminated> order;
    order.reserve(static_cast<std::size_t>(G));
    for (int done = 0; done < G; ++done) {
      if (ready_.empty()) {
        why = stuck_message();
        return std::nullopt;
      }
      const int p = std::get<2>(*ready_.begin());
      order.push_back(eliminate(p, out));
    }
    back_substitute(order);
    // A tree's joints are each reached from one side; a pivot that joins two parts
    // eliminated apart closes a loop (or links two free bodies: counted too, safely).
    out.forest = acyclic && !joins_;
    bool constraint_seen = false;
    out.speeds_first = true;
    for (const auto& rec : order) {
      const bool speed = groups_[static_cast<std::size_t>(rec.p)].speed;
      if (speed && constraint_seen) out.speeds_first = false;
      constraint_seen = constraint_seen || !speed;
    }
    // `conditioning` watches the pivots that may vanish: none in a tree; the constraint
    // pivots when the speeds went first (they vanish with A's rank); else all.
    for (std::size_t i = 0; i < steps_.size(); ++i)
      if (auto* solve = std::get_if<ir::Solve>(&steps_[i]))
        solve->reported = out.forest ? false : out.speeds_first ? constraint_pivots_.count(i) > 0 : true;
    out.steps = std::move(steps_);
    return out;
  }

 private:
  // --- grouping ------------------------------------------------------------------------

  int find(std::vector<int>& parent, int a) {
    while (parent[static_cast<std::size_t>(a)] != a) a = parent[static_cast<std::size_t>(a)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(a)])];
    return a;
  }

  // A leaf's speeds move one body together; speeds its inertia couples share a pivot.
  void group_speeds() {
    const int nu = static_cast<int>(m_.speeds.size());
    std::vector<int> parent(static_cast<std::size_t>(nu));
    std::iota(parent.begin(), parent.end(), 0);
    auto join = [&](int a, int b) { parent[static_cast<std::size_t>(find(parent, a))] = find(parent, b); };
    for (const auto& node : m_.nodes)
      if (node.children.empty())
        for (std::size_t k = 1; k < node.speeds.size(); ++k) join(node.speeds[0], node.speeds[k]);
    for (int i = 0; i < nu; ++i)
      for (const auto& e : sys_.My[static_cast<std::size_t>(i)]) join(i, e.col);
    std::map<int, int> group_of_root;
    speed_group_.assign(static_cast<std::size_t>(nu), -1);
    for (int i = 0; i < nu; ++i) {
      const int r = find(parent, i);
      auto it = group_of_root.find(r);
      if (it == group_of_root.end()) {
        it = group_of_root.emplace(r, static_cast<int>(groups_.size())).first;
        groups_.push_back({true, {}});
      }
      speed_group_[static_cast<std::size_t>(i)] = it->second;
      groups_[static_cast<std::size_t>(it->second)].members.push_back(i);
    }
  }

  // Constraint rows that touch the same speed groups form one block (a joint's rows).
  void group_constraints() {
    std::map<std::vector<int>, int> group_of_key;
    const int nc = static_cast<int>(m_.constraints.size());
    constraint_group_.assign(static_cast<std::size_t>(nc), -1);
    std::vector<std::vector<int>> keys(static_cast<std::size_t>(nc));
    for (int r = 0; r < nc; ++r) {
      std::vector<int>& key = keys[static_cast<std::size_t>(r)];
      for (const auto& e : sys_.A[static_cast<std::size_t>(r)]) key.push_back(speed_group_[static_cast<std::size_t>(e.col)]);
      std::sort(key.begin(), key.end());
      key.erase(std::unique(key.begin(), key.end()), key.end());
    }
    if (!m_.kinematic_names.empty()) {
      // Named body rotations (docs/formulation.md): a joint with a coordinate writes rows over (parent, child)
      // (the joint point) and over (parent, child, q') (the angular velocity); as two
      // blocks they close a cycle parent - rows - child - rows, and the block graph is
      // no forest. Rows whose speed groups are a subset of another block's join the
      // smallest such block (one block per joint), which adds no edge.
      std::set<std::vector<int>> distinct(keys.begin(), keys.end());
      std::map<std::vector<int>, std::vector<int>> into;
      for (const auto& k : distinct) {
        const std::vector<int>* best = nullptr;
        for (const auto& other : distinct)
          if (other.size() > k.size() && std::includes(other.begin(), other.end(), k.begin(), k.end()) &&
              (!best || other.size() < best->size()))
            best = &other;
        if (best) into[k] = *best;
      }
      for (auto& key : keys) {
        for (int hops = 0; hops < 8; ++hops) {
          const auto it = into.find(key);
          if (it == into.end()) break;
          key = it->second;
        }
      }
    }
    for (int r = 0; r < nc; ++r) {
      const std::vector<int>& key = keys[static_cast<std::size_t>(r)];
      auto it = group_of_key.find(key);
      if (it == group_of_key.end()) {
        it = group_of_key.emplace(key, static_cast<int>(groups_.size())).first;
        groups_.push_back({false, {}});
      }
      constraint_group_[static_cast<std::size_t>(r)] = it->second;
      groups_[static_cast<std::size_t>(it->second)].members.push_back(r);
    }
  }

  int size(int g) const { return static_cast<int>(groups_[static_cast<std::size_t>(g)].members.size()); }
  // Position of a speed / constraint inside its group.
  int local(int g, int member) const {
    const auto& mem = groups_[static_cast<std::size_t>(g)].members;
    return static_cast<int>(std::lower_bound(mem.begin(), mem.end(), member) - mem.begin());
  }

  GiNaC::ex prepared(const GiNaC::ex& e) { return fin_(e); }

  void fill_blocks(const std::vector<GiNaC::ex>& c) {
    const int G = static_cast<int>(groups_.size());
    diag_.resize(static_cast<std::size_t>(G));
    off_.resize(static_cast<std::size_t>(G));
    rhs_.resize(static_cast<std::size_t>(G));
    for (int g = 0; g < G; ++g) {
      diag_[static_cast<std::size_t>(g)] = Block(size(g), size(g));
      rhs_[static_cast<std::size_t>(g)].assign(static_cast<std::size_t>(size(g)), GiNaC::ex(0));
    }
    for (std::size_t i = 0; i < sys_.My.size(); ++i) {
      const int g = speed_group_[i], a = local(g, static_cast<int>(i));
      for (const auto& e : sys_.My[i]) set(diag_[static_cast<std::size_t>(g)], a, local(g, e.col), prepared(e.value));
      rhs_[static_cast<std::size_t>(g)][static_cast<std::size_t>(a)] = prepared(sys_.hy[i]);
    }
    // The elimination is symmetric: an inertia must be (bodies' are; a custom leaf's
    // force may say otherwise).
    for (int g = 0; g < G && asymmetric_.empty(); ++g) {
      const Block& d = diag_[static_cast<std::size_t>(g)];
      for (int i = 0; i < d.rows && asymmetric_.empty(); ++i)
        for (int j = i + 1; j < d.cols && asymmetric_.empty(); ++j)
          if (!(d.e[d.at(i, j)] - d.e[d.at(j, i)]).expand().is_zero())
            asymmetric_ = m_.speeds[static_cast<std::size_t>(groups_[static_cast<std::size_t>(g)].members[static_cast<std::size_t>(i)])].name;
    }
    for (std::size_t r = 0; r < sys_.A.size(); ++r) {
      const int cg = constraint_group_[r], a = local(cg, static_cast<int>(r));
      for (const auto& e : sys_.A[r]) {
        const int sg = speed_group_[static_cast<std::size_t>(e.col)];
        Block& b = block(cg, sg);
        set(b, a, local(sg, e.col), prepared(-e.value));
      }
      rhs_[static_cast<std::size_t>(cg)][static_cast<std::size_t>(a)] = prepared(-c[r]);
    }
    // The speed -> constraint blocks are the transposes.
    for (int g = 0; g < G; ++g) {
      if (groups_[static_cast<std::size_t>(g)].speed) continue;
      for (const auto& [h, b] : off_[static_cast<std::size_t>(g)]) off_[static_cast<std::size_t>(h)][g] = b.transposed();
    }
  }

  Block& block(int g, int h) {
    auto& row = off_[static_cast<std::size_t>(g)];
    auto it = row.find(h);
    if (it == row.end()) it = row.emplace(h, Block(size(g), size(h))).first;
    return it->second;
  }

  void set(Block& b, int i, int j, const GiNaC::ex& e) {
    b.e[b.at(i, j)] = e;
    b.v[b.at(i, j)] = probe_.eval(e);
  }

  // The block graph has no cycle (union-find: no edge inside a component). Loops that
  // close through the ground (two ground pivots, or rows tying a body to a fixed point
  // through an angle coordinate) are not cycles of this graph: the elimination finds them
  // (a constraint pivot that joins parts eliminated apart, `joins_`).
  bool is_forest() {
    const int G = static_cast<int>(groups_.size());
    std::vector<int> parent(static_cast<std::size_t>(G));
    std::iota(parent.begin(), parent.end(), 0);
    for (int g = 0; g < G; ++g)
      for (const auto& [h, b] : off_[static_cast<std::size_t>(g)]) {
        if (h < g) continue;
        const int a = find(parent, g), z = find(parent, h);
        if (a == z) return false;
        parent[static_cast<std::size_t>(a)] = z;
      }
    return true;
  }

  // --- order -----------------------------------------------------------------------------

  // Speeds pivot on a positive definite block, constraints on a negative definite one,
  // checked by a Cholesky factorisation of sign * P at the probe point.
  bool definite(int g) const {
    const Block& P = diag_[static_cast<std::size_t>(g)];
    const double sign = groups_[static_cast<std::size_t>(g)].speed ? 1.0 : -1.0;
    const int s = P.rows;
    Eigen::MatrixXd L = Eigen::MatrixXd::Zero(s, s);
    double scale = 0.0;
    for (int i = 0; i < s; ++i) {
      if (!P.nonzero(i, i)) return false;
      scale = std::max(scale, std::fabs(P.v[P.at(i, i)]));
    }
    if (!(scale > 0.0) || !std::isfinite(scale)) return false;
    for (int j = 0; j < s; ++j) {
      double d = sign * P.v[P.at(j, j)];
      for (int k = 0; k < j; ++k) d -= L(j, k) * L(j, k);
      if (!(d > 1e-9 * scale)) return false;
      L(j, j) = std::sqrt(d);
      for (int i = j + 1; i < s; ++i) {
        double t = sign * P.v[P.at(i, j)];
        for (int k = 0; k < j; ++k) t -= L(i, k) * L(j, k);
        L(i, j) = t / L(j, j);
      }
    }
    return true;
  }

  // The scalar unknowns an elimination of g couples: the fewer, the cheaper (and the less fill).
  long cost(int g) const {
    long n = 0;
    for (const auto& [h, b] : off_[static_cast<std::size_t>(g)]) n += size(h);
    return n;
  }

  void refresh(int g) {
    auto& k = key_[static_cast<std::size_t>(g)];
    if (std::get<0>(k) >= 0) ready_.erase(k);
    std::get<0>(k) = -1;
    if (eliminated_[static_cast<std::size_t>(g)] || !definite(g)) return;
    // Speeds first (the loop order): a constraint block waits while any speed block is ready.
    const long later = speeds_first_ && !groups_[static_cast<std::size_t>(g)].speed ? (1L << 40) : 0L;
    k = {cost(g) + later, size(g), g};
    ready_.insert(k);
  }

  std::string name_of(int g) const {
    const auto& grp = groups_[static_cast<std::size_t>(g)];
    std::string s;
    for (std::size_t i = 0; i < grp.members.size() && i < 3; ++i) {
      const int k = grp.members[i];
      s += (i ? ", " : "") + (grp.speed ? m_.speeds[static_cast<std::size_t>(k)].name : m_.constraints[static_cast<std::size_t>(k)].name);
    }
    if (grp.members.size() > 3) s += ", ...";
    return s;
  }

  std::string stuck_message() const {
    for (std::size_t g = 0; g < groups_.size(); ++g)
      if (!eliminated_[g])
        return fmt::format("no definite pivot left (first remaining block: {} {})",
                           groups_[g].speed ? "speeds" : "constraints", name_of(static_cast<int>(g)));
    return "no definite pivot left";
  }

  GiNaC::symbol fresh(const char* stem) { return GiNaC::symbol(fmt::format("{}{}", stem, counter_++)); }

  // --- one elimination ---------------------------------------------------------------------

  Eliminated eliminate(int p, KktElimination& out) {
    const Block& P = diag_[static_cast<std::size_t>(p)];
    const int s = P.rows;
    const bool speed = groups_[static_cast<std::size_t>(p)].speed;
    const double sign = speed ? 1.0 : -1.0;
    Eliminated rec;
    rec.p = p;
    // The parts already eliminated that p touches in the original graph: a constraint
    // block that meets two of them closes a loop; p then joins them into one.
    {
      std::vector<int> parts;
      for (int h : original_[static_cast<std::size_t>(p)])
        if (eliminated_[static_cast<std::size_t>(h)]) parts.push_back(find(joined_, h));
      std::sort(parts.begin(), parts.end());
      parts.erase(std::unique(parts.begin(), parts.end()), parts.end());
      if (!speed && parts.size() > 1) joins_ = true;
      for (int part : parts) joined_[static_cast<std::size_t>(part)] = p;
    }
    for (const auto& [h, b] : off_[static_cast<std::size_t>(p)]) rec.neighbours.push_back(h);
    ++out.blocks;
    out.largest = std::max(out.largest, s);

    // The right-hand-side columns: every neighbour column with a nonzero entry, then r_p.
    struct Column {
      int nb;  // index into rec.neighbours, or -1 for r_p
      int j;
    };
    std::vector<Column> cols;
    for (std::size_t n = 0; n < rec.neighbours.size(); ++n) {
      const Block& b = off_[static_cast<std::size_t>(p)].at(rec.neighbours[n]);
      for (int j = 0; j < b.cols; ++j) {
        bool any = false;
        for (int i = 0; i < s && !any; ++i) any = b.nonzero(i, j);
        if (any) cols.push_back({static_cast<int>(n), j});
      }
    }
    {
      bool any = false;
      for (const auto& e : rhs_[static_cast<std::size_t>(p)]) any = any || !e.is_zero();
      if (any) cols.push_back({-1, 0});
    }
    auto entry = [&](int i, const Column& c) -> const GiNaC::ex& {
      if (c.nb < 0) return rhs_[static_cast<std::size_t>(p)][static_cast<std::size_t>(i)];
      const Block& b = off_[static_cast<std::size_t>(p)].at(rec.neighbours[static_cast<std::size_t>(c.nb)]);
      return b.e[b.at(i, c.j)];
    };
    // A constraint pivot (of the speeds-first order above all) is reported with its neighbour columns
    // as `gains`: its conditioning divides by max(1, |P^-1 K_ph|), which grows without
    // bound as the pivot vanishes with A's rank, while P and K_ph share their units (both
    // blocks of A My^-1 A^T), so the measure is scale-free. Row i of a split diagonal
    // pivot, or the whole block (i < 0): the neighbour columns come first in B.
    auto neighbour_columns = [&](int i) {
      int n = 0;
      for (const auto& c : cols)
        if (c.nb >= 0 && (i < 0 || !entry(i, c).is_zero())) ++n;
      return n;
    };
    auto entry_value = [&](int i, const Column& c) -> double {
      if (c.nb < 0) return 0.0;  // right-hand sides are not needed at the probe
      const Block& b = off_[static_cast<std::size_t>(p)].at(rec.neighbours[static_cast<std::size_t>(c.nb)]);
      return b.v[b.at(i, c.j)];
    };

    // X = P^-1 [columns], as symbols (what the generated solve returns) and probe values.
    for (int h : rec.neighbours) rec.X.emplace_back(s, size(h));
    rec.xr_e.assign(static_cast<std::size_t>(s), GiNaC::ex(0));
    auto store = [&](int i, const Column& c, const GiNaC::ex& e, double v) {
      if (c.nb < 0) {
        rec.xr_e[static_cast<std::size_t>(i)] = e;
        return;
      }
      Block& X = rec.X[static_cast<std::size_t>(c.nb)];
      X.e[X.at(i, c.j)] = e;
      X.v[X.at(i, c.j)] = v;
    };
    bool diagonal = true;
    for (int i = 0; i < s && diagonal; ++i)
      for (int j = 0; j < s && diagonal; ++j) diagonal = i == j || !P.nonzero(i, j);
    const std::string label = fmt::format("sparse elimination: {} {}", speed ? "speeds" : "constraints", name_of(p));
    if (diagonal) {
      // Uncoupled unknowns: one 1x1 pivot each, with only the columns its row has.
      for (int i = 0; i < s; ++i) {
        ir::Solve solve;
        solve.label = label;
        solve.n = 1;
        solve.spd = true;
        solve.reported = false;
        solve.A = {sign * P.e[P.at(i, i)]};
        const double pv = P.v[P.at(i, i)];
        for (const auto& c : cols) {
          if (entry(i, c).is_zero()) continue;
          solve.B.push_back(sign * entry(i, c));
          const GiNaC::symbol x = fresh("kx");
          solve.X.push_back(x);
          store(i, c, x, entry_value(i, c) / pv);
        }
        solve.k = static_cast<int>(solve.B.size());
        if (!speed) solve.gains = neighbour_columns(i);
        if (solve.k > 0) {
          if (!speed) constraint_pivots_.insert(steps_.size());
          steps_.push_back(solve);
        }
      }
    } else {
      ir::Solve solve;
      solve.label = label;
      solve.n = s;
      solve.k = static_cast<int>(cols.size());
      solve.spd = true;
      solve.reported = false;
      Eigen::MatrixXd Pv(s, s), Bv(s, std::max<int>(1, solve.k));
      Bv.setZero();
      for (int i = 0; i < s; ++i)
        for (int j = 0; j < s; ++j) {
          solve.A.push_back(sign * P.e[P.at(i, j)]);
          Pv(i, j) = sign * P.v[P.at(i, j)];
        }
      for (int i = 0; i < s; ++i)
        for (std::size_t k = 0; k < cols.size(); ++k) {
          solve.B.push_back(sign * entry(i, cols[k]));
          Bv(i, static_cast<int>(k)) = sign * entry_value(i, cols[k]);
        }
      const Eigen::MatrixXd Xv = Pv.llt().solve(Bv);
      for (int i = 0; i < s; ++i)
        for (std::size_t k = 0; k < cols.size(); ++k) {
          const GiNaC::symbol x = fresh("kx");
          solve.X.push_back(x);
          store(i, cols[k], x, Xv(i, static_cast<int>(k)));
        }
      if (!speed) solve.gains = neighbour_columns(-1);
      if (solve.k > 0) {
        if (!speed) constraint_pivots_.insert(steps_.size());
        steps_.push_back(solve);
      }
    }

    // Schur complement on the neighbours: K_hk -= K_ph^T X_k, r_h -= K_ph^T x_r.
    const std::size_t nn = rec.neighbours.size();
    for (std::size_t a = 0; a < nn; ++a) {
      const int h = rec.neighbours[a];
      const Block& Kph = off_[static_cast<std::size_t>(p)].at(h);
      for (std::size_t bidx = a; bidx < nn; ++bidx) {
        const int k = rec.neighbours[bidx];
        const Block& Xk = rec.X[bidx];
        const bool self = h == k;
        if (!self && !off_[static_cast<std::size_t>(h)].count(k)) ++out.fill;
        Block& target = self ? diag_[static_cast<std::size_t>(h)] : block(h, k);
        bool changed = false;
        for (int i = 0; i < Kph.cols; ++i)
          for (int j = self ? i : 0; j < Xk.cols; ++j) {
            GiNaC::ex sum = 0;
            double value = 0.0;
            bool any = false;
            for (int t = 0; t < s; ++t) {
              if (!Kph.nonzero(t, i) || Xk.e[Xk.at(t, j)].is_zero()) continue;
              sum += Kph.e[Kph.at(t, i)] * Xk.e[Xk.at(t, j)];
              value += Kph.v[Kph.at(t, i)] * Xk.v[Xk.at(t, j)];
              any = true;
            }
            if (!any) continue;
            changed = true;
            const GiNaC::symbol u = fresh("ks");
            steps_.push_back(ir::Define{u, target.e[target.at(i, j)] - sum, false});
            target.e[target.at(i, j)] = u;
            target.v[target.at(i, j)] -= value;
            if (self && j != i) {
              target.e[target.at(j, i)] = u;
              target.v[target.at(j, i)] = target.v[target.at(i, j)];
            }
          }
        if (!self && changed) off_[static_cast<std::size_t>(k)][h] = target.transposed();
        if (!self && !changed && !off_[static_cast<std::size_t>(k)].count(h)) {
          // Nothing was coupled after all: no block.
          off_[static_cast<std::size_t>(h)].erase(k);
          --out.fill;
        }
      }
      for (int i = 0; i < Kph.cols; ++i) {
        GiNaC::ex sum = 0;
        bool any = false;
        for (int t = 0; t < s; ++t) {
          if (!Kph.nonzero(t, i) || rec.xr_e[static_cast<std::size_t>(t)].is_zero()) continue;
          sum += Kph.e[Kph.at(t, i)] * rec.xr_e[static_cast<std::size_t>(t)];
          any = true;
        }
        if (!any) continue;
        auto& r = rhs_[static_cast<std::size_t>(h)][static_cast<std::size_t>(i)];
        const GiNaC::symbol u = fresh("kr");
        steps_.push_back(ir::Define{u, r - sum, false});
        r = u;
      }
    }
    // p leaves the graph; its neighbours' pivots and degrees changed.
    eliminated_[static_cast<std::size_t>(p)] = 1;
    const auto& ready_key = key_[static_cast<std::size_t>(p)];
    if (std::get<0>(ready_key) >= 0) ready_.erase(ready_key);
    std::get<0>(key_[static_cast<std::size_t>(p)]) = -1;
    for (int h : rec.neighbours) off_[static_cast<std::size_t>(h)].erase(p);
    off_[static_cast<std::size_t>(p)].clear();
    for (int h : rec.neighbours) refresh(h);
    return rec;
  }

  // x_p = x_r - sum_h X_h x_h, the last block first: every x_h is known by then.
  void back_substitute(const std::vector<Eliminated>& order) {
    std::vector<std::vector<GiNaC::ex>> x(groups_.size());
    for (auto it = order.rbegin(); it != order.rend(); ++it) {
      const auto& grp = groups_[static_cast<std::size_t>(it->p)];
      const int s = size(it->p);
      auto& xp = x[static_cast<std::size_t>(it->p)];
      xp.resize(static_cast<std::size_t>(s));
      for (int i = 0; i < s; ++i) {
        GiNaC::ex value = it->xr_e[static_cast<std::size_t>(i)];
        for (std::size_t n = 0; n < it->neighbours.size(); ++n) {
          const Block& X = it->X[n];
          const auto& xh = x[static_cast<std::size_t>(it->neighbours[n])];
          for (int j = 0; j < X.cols; ++j)
            if (!X.e[X.at(i, j)].is_zero()) value -= X.e[X.at(i, j)] * xh[static_cast<std::size_t>(j)];
        }
        const int k = grp.members[static_cast<std::size_t>(i)];
        const GiNaC::symbol target = grp.speed ? m_.speed_dots[static_cast<std::size_t>(k)] : lambda_[static_cast<std::size_t>(k)];
        steps_.push_back(ir::Define{target, value, true});
        xp[static_cast<std::size_t>(i)] = target;
      }
    }
  }

  const model::Model& m_;
  const KktSystem& sys_;
  const std::vector<GiNaC::symbol>& lambda_;
  const std::function<GiNaC::ex(const GiNaC::ex&)>& fin_;
  const Probe& probe_;
  std::vector<Group> groups_;
  std::vector<int> speed_group_, constraint_group_;
  std::vector<Block> diag_;
  std::vector<std::map<int, Block>> off_;
  std::vector<std::vector<GiNaC::ex>> rhs_;
  std::vector<char> eliminated_;            // per group
  std::vector<std::vector<int>> original_;  // per group: its neighbours before any elimination
  std::vector<int> joined_;                 // union-find over eliminated groups (parts eliminated together)
  bool joins_ = false;                      // a constraint pivot joined two such parts
  std::vector<std::tuple<long, int, int>> key_;
  std::set<std::tuple<long, int, int>> ready_;
  std::vector<ir::Step> steps_;
  long counter_ = 0;
  std::string asymmetric_;      // a speed whose My row is not its column (a custom leaf's force)
  bool speeds_first_ = false;   // order: every ready speed block before any constraint block
  std::set<std::size_t> constraint_pivots_;  // indices into steps_ of the constraint blocks' pivot solves
};

}  // namespace

std::optional<KktElimination> eliminate_kkt(const model::Model& m, const KktSystem& sys, const std::vector<GiNaC::ex>& c,
                                            const std::vector<GiNaC::symbol>& lambda,
                                            const std::function<GiNaC::ex(const GiNaC::ex&)>& fin, const Probe& probe,
                                            bool loops_speeds_first, std::string& why) {
  auto fewest = Eliminator(m, sys, c, lambda, fin, probe, false).run(why);
  if ((fewest && fewest->forest) || !loops_speeds_first) return fewest;
  // A loop (or no order at all): speeds first keeps every pivot regular where A has full
  // rank, at the price of the fill of A My^-1 A^T (banded for a chain of loops).
  std::string why_speeds;
  auto speeds = Eliminator(m, sys, c, lambda, fin, probe, true).run(why_speeds);
  if (speeds && (speeds->speeds_first || !fewest)) {
    why.clear();
    return speeds;
  }
  return fewest;
}

}  // namespace mbsc::sym
