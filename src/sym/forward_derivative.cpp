// SPDX-License-Identifier: GPL-2.0-or-later
// Forward-mode differentiation of a FunctionSpec (include/mbsc/sym/forward_derivative.hpp).
#include "mbsc/sym/forward_derivative.hpp"

#include <algorithm>
#include <map>
#include <set>
#include <unordered_map>
#include <utility>

namespace mbsc::sym {

namespace {

/// A tangent: direction -> value, with no zero values.
using Tangent = std::map<int, GiNaC::ex>;

class ForwardMode {
 public:
  ForwardMode(const ir::FunctionSpec& f, const std::vector<std::vector<GiNaC::symbol>>& blocks,
              const std::vector<GiNaC::symbol>& held)
      : f_(f), held_(held.begin(), held.end()) {
    for (const auto& block : blocks) {
      block_sizes_.push_back(static_cast<int>(block.size()));
      for (const auto& y : block) {
        if (id_.count(y)) throw std::logic_error("forward_derivative: a direction listed twice");
        const int d = ndir_++;
        track(y, Tangent{{d, GiNaC::ex(1)}});
      }
    }
  }

  ir::FunctionSpec run() {
    if (f_.congruence) throw NotDifferentiable("a function formed by a congruence product");
    for (const ir::Step& step : f_.steps) {
      if (const auto* d = std::get_if<ir::Define>(&step)) pending_.insert(d->sym);
      else for (const auto& x : std::get<ir::Solve>(step).X) pending_.insert(x);
    }
    const std::vector<char> needed = steps_needed();
    ir::FunctionSpec out;
    out.third_arg = f_.third_arg;
    out.third_bindings = f_.third_bindings;
    for (std::size_t i = 0; i < f_.steps.size(); ++i) {
      const ir::Step& step = f_.steps[i];
      if (!needed[i]) {  // its value only: no output's tangent reads it
        out.steps.push_back(step);
        if (const auto* d = std::get_if<ir::Define>(&step)) pending_.erase(d->sym);
        else for (const auto& x : std::get<ir::Solve>(step).X) pending_.erase(x);
        continue;
      }
      if (const auto* d = std::get_if<ir::Define>(&step)) define(*d, out.steps);
      else solve(std::get<ir::Solve>(step), out.steps);
    }
    // d(output i)/d(direction d), row-major per block (the directions are numbered block
    // after block, so the blocks' row-major layouts follow from one loop per block).
    std::vector<Tangent> rows;
    for (const GiNaC::ex& o : f_.outputs) rows.push_back(tangent_of(o));
    int begin = 0;
    for (const int size : block_sizes_) {
      for (const Tangent& row : rows)
        for (int d = begin; d < begin + size; ++d) {
          const auto it = row.find(d);
          out.outputs.push_back(it == row.end() ? GiNaC::ex(0) : it->second);
        }
      begin += size;
    }
    return out;
  }

 private:
  // The steps whose tangents the outputs read: last step first, a step is needed when an
  // output or a needed step reads what it defines; a held symbol's definition is not
  // followed (its tangent is zero).
  std::vector<char> steps_needed() {
    std::set<GiNaC::ex, GiNaC::ex_is_less> read;
    Seen seen;
    for (const GiNaC::ex& o : f_.outputs) symbols_of(o, read, seen);
    std::vector<char> needed(f_.steps.size(), 0);
    for (std::size_t i = f_.steps.size(); i-- > 0;) {
      if (const auto* d = std::get_if<ir::Define>(&f_.steps[i])) {
        if (!read.count(d->sym) || held_.count(d->sym)) continue;
        needed[i] = 1;
        symbols_of(d->value, read, seen);
        continue;
      }
      const auto& s = std::get<ir::Solve>(f_.steps[i]);
      bool any = false;
      for (const auto& x : s.X) any = any || read.count(x) > 0;
      if (!any) continue;
      for (const auto& x : s.X)
        if (held_.count(x)) throw NotDifferentiable("a held symbol that a solve defines");
      needed[i] = 1;
      for (const auto* entries : {&s.A, &s.B})
        for (const auto& e : *entries) symbols_of(e, read, seen);
    }
    return needed;
  }

  // Nodes visited, each kept alive with its entry: op(i) of a sum or product may build a
  // new node, whose address a later one could reuse.
  using Seen = std::unordered_map<const GiNaC::basic*, GiNaC::ex>;

  static void symbols_of(const GiNaC::ex& e, std::set<GiNaC::ex, GiNaC::ex_is_less>& out, Seen& seen) {
    if (GiNaC::is_a<GiNaC::symbol>(e)) {
      out.insert(e);
      return;
    }
    if (e.nops() == 0 || !seen.emplace(&GiNaC::ex_to<GiNaC::basic>(e), e).second) return;
    for (std::size_t i = 0; i < e.nops(); ++i) symbols_of(e.op(i), out, seen);
  }

  void track(const GiNaC::ex& s, Tangent t) {
    if (t.empty()) return;
    if (!id_.emplace(s, static_cast<int>(tangents_.size())).second)
      throw std::logic_error("forward_derivative: a symbol defined twice");
    tangents_.push_back(std::move(t));
  }

  // The tangent of e, node by node (chain rule over GiNaC's expression graph): every node
  // is differentiated once (memo by address, the node kept alive with its entry), so an
  // expression that shares subexpressions costs its graph's size, not its tree's.
  Tangent tangent_of(const GiNaC::ex& e) {
    if (GiNaC::is_a<GiNaC::numeric>(e) || GiNaC::is_a<GiNaC::constant>(e)) return {};
    if (GiNaC::is_a<GiNaC::symbol>(e)) {
      if (pending_.count(e)) throw std::logic_error("forward_derivative: a step reads a symbol a later step defines");
      const auto at = id_.find(e);
      return at == id_.end() ? Tangent{} : tangents_[static_cast<std::size_t>(at->second)];
    }
    const GiNaC::basic* key = &GiNaC::ex_to<GiNaC::basic>(e);
    const auto hit = memo_.find(key);
    if (hit != memo_.end()) return hit->second.second;
    Tangent t = node_tangent(e);
    memo_.emplace(key, std::make_pair(e, t));
    return t;
  }

  static void accumulate(Tangent& sum, const GiNaC::ex& factor, const Tangent& t) {
    if (factor.is_zero()) return;
    for (const auto& [d, v] : t) {
      auto [at, fresh] = sum.emplace(d, factor * v);
      if (!fresh) at->second += factor * v;
    }
  }

  static Tangent nonzero(Tangent t) {
    for (auto it = t.begin(); it != t.end();) it = it->second.is_zero() ? t.erase(it) : std::next(it);
    return t;
  }

  Tangent node_tangent(const GiNaC::ex& e) {
    Tangent sum;
    if (GiNaC::is_a<GiNaC::add>(e)) {
      for (std::size_t i = 0; i < e.nops(); ++i) accumulate(sum, 1, tangent_of(e.op(i)));
      return nonzero(std::move(sum));
    }
    if (GiNaC::is_a<GiNaC::mul>(e)) {
      // d(f_1 ... f_k) = sum_i (prod_{j != i} f_j) df_i, over the factors that move.
      const std::size_t k = e.nops();
      std::vector<Tangent> ts(k);
      for (std::size_t i = 0; i < k; ++i) ts[i] = tangent_of(e.op(i));
      for (std::size_t i = 0; i < k; ++i) {
        if (ts[i].empty()) continue;
        GiNaC::ex others = 1;
        for (std::size_t j = 0; j < k; ++j)
          if (j != i) others *= e.op(j);
        accumulate(sum, others, ts[i]);
      }
      return nonzero(std::move(sum));
    }
    if (GiNaC::is_a<GiNaC::power>(e)) {
      const GiNaC::ex b = e.op(0), x = e.op(1);
      const Tangent tb = tangent_of(b), tx = tangent_of(x);
      if (!tb.empty()) accumulate(sum, x * GiNaC::pow(b, x - 1), tb);
      if (!tx.empty()) accumulate(sum, e * GiNaC::log(b), tx);
      return nonzero(std::move(sum));
    }
    if (GiNaC::is_a<GiNaC::fderivative>(e)) throw NotDifferentiable("a derivative of a function");
    if (GiNaC::is_a<GiNaC::function>(e)) {
      const auto& f = GiNaC::ex_to<GiNaC::function>(e);
      for (std::size_t i = 0; i < e.nops(); ++i) {
        const Tangent ta = tangent_of(e.op(i));
        if (!ta.empty()) accumulate(sum, argument_partial(f, i), ta);
      }
      return nonzero(std::move(sum));
    }
    throw NotDifferentiable("an expression of kind " + std::string(GiNaC::ex_to<GiNaC::basic>(e).class_name()));
  }

  // d f(a_1, .., a_n) / d a_i. abs: csgn(a) (0 at a = 0); csgn: 0 (the functions are
  // piecewise smooth, their derivative is taken where they are smooth); the others
  // GiNaC's own derivative, taken once per function and argument on stand-in symbols.
  GiNaC::ex argument_partial(const GiNaC::function& f, std::size_t i) {
    const std::string name = f.get_name();
    if (name == "abs") return GiNaC::csgn(f.op(0));
    if (name == "csgn") return 0;
    auto& entry = partial_templates_[{f.get_serial(), i}];
    if (entry.args.empty()) {
      GiNaC::exvector stand_ins;
      for (std::size_t j = 0; j < f.nops(); ++j) {
        entry.args.emplace_back("a" + std::to_string(j));
        stand_ins.push_back(entry.args.back());
      }
      entry.partial = GiNaC::function(f.get_serial(), stand_ins).diff(entry.args[i]);
      if (has_derivative_object(entry.partial))
        throw NotDifferentiable("the function " + name);
    }
    GiNaC::exmap at;
    for (std::size_t j = 0; j < f.nops(); ++j) at[entry.args[j]] = f.op(j);
    return entry.partial.subs(at, GiNaC::subs_options::no_pattern);
  }

  static bool has_derivative_object(const GiNaC::ex& e) {
    if (GiNaC::is_a<GiNaC::fderivative>(e)) return true;
    for (std::size_t i = 0; i < e.nops(); ++i)
      if (has_derivative_object(e.op(i))) return true;
    return false;
  }

  struct PartialTemplate {
    std::vector<GiNaC::symbol> args;
    GiNaC::ex partial;
  };

  void define(const ir::Define& d, std::vector<ir::Step>& steps) {
    steps.push_back(d);
    pending_.erase(d.sym);
    if (held_.count(d.sym)) return;
    Tangent t = tangent_of(d.value);
    Tangent named;
    for (auto& [dir, v] : t) {
      if (GiNaC::is_a<GiNaC::numeric>(v) || GiNaC::is_a<GiNaC::symbol>(v)) {
        named.emplace(dir, v);
        continue;
      }
      GiNaC::symbol s("d" + std::to_string(dir) + "_" + d.sym.get_name());
      steps.push_back(ir::Define{s, v, d.named});
      named.emplace(dir, s);
    }
    track(d.sym, std::move(named));
  }

  // X = A^-1 B, so A dX = dB - dA X: one more solve with the same A, every nonzero
  // direction's k columns side by side.
  void solve(const ir::Solve& s, std::vector<ir::Step>& steps) {
    if (s.condition) throw NotDifferentiable("a conditioning estimate");
    for (const auto& x : s.X) pending_.erase(x);
    steps.push_back(s);
    const int n = s.n, k = s.k;
    std::vector<Tangent> rhs(static_cast<std::size_t>(n * k));
    for (int i = 0; i < n; ++i) {
      for (int c = 0; c < k; ++c) accumulate(rhs[static_cast<std::size_t>(i * k + c)], 1, tangent_of(s.B[static_cast<std::size_t>(i * k + c)]));
      for (int j = 0; j < n; ++j) {
        const Tangent ta = tangent_of(s.A[static_cast<std::size_t>(i * n + j)]);
        if (ta.empty()) continue;
        for (int c = 0; c < k; ++c) accumulate(rhs[static_cast<std::size_t>(i * k + c)], -s.X[static_cast<std::size_t>(j * k + c)], ta);
      }
    }
    std::set<int> dirs;
    for (auto& entry : rhs) {
      entry = nonzero(std::move(entry));
      for (const auto& [d, v] : entry) dirs.insert(d);
    }
    if (!dirs.empty() && s.spd && s.rank > 0)
      throw NotDifferentiable("a minimum-norm solve of a semidefinite matrix (redundant constraints)");
    if (dirs.empty()) return;
    const std::vector<int> dir_list(dirs.begin(), dirs.end());
    const int nd = static_cast<int>(dir_list.size());
    ir::Solve t;
    t.label = "derivative of " + s.label;
    t.n = n;
    t.k = k * nd;
    t.A = s.A;
    t.spd = s.spd;
    t.reported = false;
    for (int i = 0; i < n; ++i)
      for (int a = 0; a < nd; ++a)
        for (int c = 0; c < k; ++c) {
          const auto& entry = rhs[static_cast<std::size_t>(i * k + c)];
          const auto it = entry.find(dir_list[static_cast<std::size_t>(a)]);
          t.B.push_back(it == entry.end() ? GiNaC::ex(0) : it->second);
        }
    for (int j = 0; j < n; ++j)
      for (int a = 0; a < nd; ++a)
        for (int c = 0; c < k; ++c)
          t.X.push_back(GiNaC::symbol("d" + std::to_string(dir_list[static_cast<std::size_t>(a)]) + "_" +
                                      s.X[static_cast<std::size_t>(j * k + c)].get_name()));
    for (int j = 0; j < n; ++j)
      for (int c = 0; c < k; ++c) {
        Tangent tx;
        for (int a = 0; a < nd; ++a) tx.emplace(dir_list[static_cast<std::size_t>(a)], t.X[static_cast<std::size_t>((j * nd + a) * k + c)]);
        track(s.X[static_cast<std::size_t>(j * k + c)], std::move(tx));
      }
    steps.push_back(std::move(t));
  }

  const ir::FunctionSpec& f_;
  const std::set<GiNaC::ex, GiNaC::ex_is_less> held_;  // symbols whose tangent is taken as zero
  int ndir_ = 0;
  std::vector<int> block_sizes_;  // the directions, block after block
  std::map<GiNaC::ex, int, GiNaC::ex_is_less> id_;
  std::vector<Tangent> tangents_;
  std::unordered_map<const GiNaC::basic*, std::pair<GiNaC::ex, Tangent>> memo_;  // the ex keeps its address unique
  std::map<std::pair<unsigned, std::size_t>, PartialTemplate> partial_templates_;
  std::set<GiNaC::ex, GiNaC::ex_is_less> pending_;
};

}  // namespace

ir::FunctionSpec forward_derivative(const ir::FunctionSpec& f, const std::vector<std::vector<GiNaC::symbol>>& blocks,
                                    const std::vector<GiNaC::symbol>& held) {
  return ForwardMode(f, blocks, held).run();
}

}  // namespace mbsc::sym
