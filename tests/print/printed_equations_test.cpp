// SPDX-License-Identifier: GPL-2.0-or-later
// The equations `mbsc print` shows: (a) on every shipped model, the printed M and h
// (through the named intermediates, and --expand; as expressions and as their printed
// text read back) evaluate to the numbers of the pipeline's own unsimplified expressions
// (which the numeric tests tie to the generated code) at random states and parameters;
// (b) for the double pendulum, the 3R arm and the four-bar, the printed M matches the
// textbook form as text and symbolically.
#include "mbsc/print/print_matrix.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <map>
#include <random>
#include <variant>

#include "cli/run_command.hpp"
#include "mbsc/driver/pipeline.hpp"
#include "mbsc/print/canonical_text.hpp"
#include "trig_check.hpp"

using namespace GiNaC;
using mbsc::print::canonical_text;
namespace fs = std::filesystem;

namespace {

struct Loaded {
  std::optional<mbsc::model::Model> m;
  std::optional<mbsc::sym::Eom> eom;
};

Loaded load(const fs::path& path) {
  Loaded l;
  mbsc::Diagnostics diags;
  l.m = mbsc::driver::load_model(path.string(), diags);
  REQUIRE(l.m);
  l.eom = mbsc::sym::derive(*l.m, {}, diags);
  REQUIRE(l.eom);
  return l;
}

/// x = A^-1 b by Gaussian elimination with partial pivoting (A row-major n x n, B n x k).
std::vector<double> solve(int n, int k, std::vector<double> A, std::vector<double> B) {
  for (int c = 0; c < n; ++c) {
    int p = c;
    for (int r = c + 1; r < n; ++r)
      if (std::abs(A[r * n + c]) > std::abs(A[p * n + c])) p = r;
    for (int j = 0; j < n; ++j) std::swap(A[c * n + j], A[p * n + j]);
    for (int j = 0; j < k; ++j) std::swap(B[c * k + j], B[p * k + j]);
    for (int r = c + 1; r < n; ++r) {
      const double f = A[r * n + c] / A[c * n + c];
      for (int j = c; j < n; ++j) A[r * n + j] -= f * A[c * n + j];
      for (int j = 0; j < k; ++j) B[r * k + j] -= f * B[c * k + j];
    }
  }
  for (int c = n - 1; c >= 0; --c)
    for (int j = 0; j < k; ++j) {
      double s = B[c * k + j];
      for (int r = c + 1; r < n; ++r) s -= A[c * n + r] * B[r * k + j];
      B[c * k + j] = s / A[c * n + c];
    }
  return B;
}

/// The dependent speeds (all but the root's independent ones) solved numerically from
/// the order-1 constraints the derivation kept (the rows of every node), at the values
/// in v: --expand writes them through the independent speeds, so the reference must
/// satisfy the velocity constraints.
void consistent_speeds(const mbsc::model::Model& m, const mbsc::sym::Eom& eom, exmap& v) {
  const auto order1 = mbsc::sym::velocity_residuals(m);
  std::vector<int> unknowns, rows;
  for (std::size_t s = 0; s < m.speeds.size(); ++s)
    if (std::find(eom.independent.begin(), eom.independent.end(), static_cast<int>(s)) == eom.independent.end())
      unknowns.push_back(static_cast<int>(s));
  for (const auto& r : eom.nodes) rows.insert(rows.end(), r.rows.begin(), r.rows.end());
  REQUIRE(rows.size() == unknowns.size());
  const int n = static_cast<int>(unknowns.size());
  exmap known = v;
  for (int s : unknowns) known.erase(m.speeds[s].sym);
  // Newton's method (one step for constraints linear in the speeds; a `nonlinear`
  // block takes a few), from 1 for every unknown.
  std::vector<ex> g;
  for (int c : rows) g.push_back(mbsc::driver::finalize(m, eom, order1[c]).subs(known, subs_options::no_pattern));
  std::vector<double> x(n, 1.0);
  for (int iteration = 0; iteration < 20; ++iteration) {
    exmap at;
    for (int i = 0; i < n; ++i) at[m.speeds[unknowns[i]].sym] = x[i];
    std::vector<double> A, B;
    for (const ex& gi : g) {
      for (int s : unknowns) A.push_back(mbsc_test::eval(gi.diff(m.speeds[s].sym), at));
      B.push_back(-mbsc_test::eval(gi, at));
    }
    const auto dx = solve(n, 1, A, B);
    double step = 0.0, size = 1.0;
    for (int i = 0; i < n; ++i) {
      x[i] += dx[i];
      // A speed that converges to 0 would shrink into subnormal numbers, which GiNaC's
      // numbers refuse (CLN's floating-point underflow): flush them.
      if (std::abs(x[i]) < 1e-200) x[i] = 0.0;
      step = std::max(step, std::abs(dx[i]));
      size = std::max(size, std::abs(x[i]));
    }
    if (step <= 1e-15 * size) break;  // converged
  }
  for (int i = 0; i < n; ++i) v[m.speeds[unknowns[i]].sym] = x[i];
}

/// Random values for every input symbol (the dependent speeds consistent with the
/// independent ones), then the pipeline's intermediates (e_, r_ and the numeric solves,
/// done numerically as the generated code does) in order.
exmap reference_values(const mbsc::model::Model& m, const mbsc::sym::Eom& eom, std::mt19937& rng) {
  std::uniform_real_distribution<double> angle(-1.4, 1.4), param(0.5, 1.5);
  exmap v;
  v[m.time] = 0.37;
  for (const auto& q : m.coords) v[q.sym] = angle(rng);
  for (const auto& s : m.speeds) v[s.sym] = angle(rng);
  for (const auto& p : m.params) v[p.sym] = param(rng);
  for (const auto& u : m.inputs) v[u.sym] = angle(rng);
  for (const auto& f : m.frictions) v[f.force] = angle(rng);  // printed as a symbol, like an input
  // Named body rotations (docs/formulation.md) at these coordinates, in definition order:
  // the pipeline's rows read them, the printed equations write them out.
  for (const auto& k : m.kinematic_names) v[k.sym] = mbsc_test::eval(mbsc::driver::finalize(m, eom, k.value), v);
  consistent_speeds(m, eom, v);
  for (const auto& step : eom.pre_steps) {
    if (const auto* d = std::get_if<mbsc::ir::Define>(&step)) {
      v[d->sym] = mbsc_test::eval(mbsc::driver::finalize(m, eom, d->value), v);
      continue;
    }
    const auto& s = std::get<mbsc::ir::Solve>(step);
    if (s.condition) continue;
    std::vector<double> A, B;
    for (const auto& e : s.A) A.push_back(mbsc_test::eval(mbsc::driver::finalize(m, eom, e), v));
    for (const auto& e : s.B) B.push_back(mbsc_test::eval(mbsc::driver::finalize(m, eom, e), v));
    const auto X = solve(s.n, s.k, A, B);
    for (std::size_t i = 0; i < X.size(); ++i) v[s.X[i]] = X[i];
  }
  return v;
}

/// The inputs of `ref` and the printed intermediates evaluated from their printed values
/// (an X without a closed form takes the reference's number).
exmap printed_values(const mbsc::model::Model& m, const mbsc::print::PrintedEquations& p, const exmap& ref) {
  exmap v;
  v[m.time] = ref.at(m.time);
  for (const auto& q : m.coords) v[q.sym] = ref.at(q.sym);
  for (const auto& s : m.speeds) v[s.sym] = ref.at(s.sym);
  for (const auto& q : m.params) v[q.sym] = ref.at(q.sym);
  for (const auto& u : m.inputs) v[u.sym] = ref.at(u.sym);
  for (const auto& f : m.frictions) v[f.force] = ref.at(f.force);
  for (const auto& w : p.where) v[w.sym] = w.solved ? mbsc_test::eval(w.value, v) : ref.at(w.sym);
  return v;
}

void check_close(double got, double want) { CHECK(got == Approx(want).epsilon(1e-9).margin(1e-9)); }

const fs::path kModels = fs::path(MBSC_SOURCE_DIR) / "models";

/// The printed text of e read back with GiNaC's parser (model names such as crank.theta
/// become parser identifiers first), so that what the user reads is what is checked.
ex read_back(const ex& e) {
  std::map<std::string, ex> by_name;
  for (auto it = e.preorder_begin(); it != e.preorder_end(); ++it)
    if (is_a<symbol>(*it)) by_name[ex_to<symbol>(*it).get_name()] = *it;
  const std::string text = canonical_text(e, false);
  std::string plain;
  symtab table;
  table["pi"] = GiNaC::Pi;  // the printer writes the constant as pi (sphere_trough's field)
  for (std::size_t i = 0; i < text.size();) {
    const char c = text[i];
    if (std::isalpha(static_cast<unsigned char>(c)) || c == '_') {
      std::size_t j = i;
      while (j < text.size() && (std::isalnum(static_cast<unsigned char>(text[j])) || text[j] == '_' || text[j] == '.')) ++j;
      std::string word = text.substr(i, j - i);
      auto found = by_name.find(word);
      if (found != by_name.end()) {
        std::string id = word;
        for (char& ch : id)
          if (ch == '.') ch = '_';
        id = "v_" + id;
        table[id] = found->second;
        word = id;
      }
      plain += word;
      i = j;
    } else {
      plain += c;
      ++i;
    }
  }
  parser reader(table, true);
  return reader(plain);
}

const symbol& sym_named(const mbsc::model::Model& m, const std::string& name) {
  for (const auto& q : m.coords)
    if (q.name == name) return q.sym;
  for (const auto& s : m.speeds)
    if (s.name == name) return s.sym;
  for (const auto& p : m.params)
    if (p.name == name) return p.sym;
  throw std::runtime_error("no symbol " + name);
}

std::string print_cli(const std::string& model, const std::string& flags) {
  const auto r = mbsc_test::run(std::string(MBSC_BINARY) + " print -q " + (kModels / model).string() + " " + flags);
  REQUIRE(r.exit_code == 0);
  return r.output;
}

}  // namespace

TEST_CASE("printed M and h of every shipped model evaluate to the pipeline's numbers", "[print][equations]") {
  std::vector<fs::path> models;
  for (const auto& e : fs::directory_iterator(kModels))
    if (e.path().extension() == ".mbs") models.push_back(e.path());
  std::sort(models.begin(), models.end());
  REQUIRE(models.size() >= 14);
  std::mt19937 rng(2024);
  for (const auto& path : models) {
    INFO("model " << path.filename().string());
    Loaded l = load(path);
    const auto& m = *l.m;
    const auto& eom = *l.eom;
    const int root = m.root();
    for (bool expand : {false, true}) {
      INFO("expand " << expand);
      const auto p = mbsc::print::printed_equations(m, eom, root, expand);
      for (int trial = 0; trial < 3; ++trial) {
        const exmap ref = reference_values(m, eom, rng);
        const exmap shown = printed_values(m, p, ref);
        const auto& r = eom.nodes[root];
        const GiNaC::matrix& M = eom.M.get();  // the root's M (formed on first use)
        for (unsigned i = 0; i < M.rows(); ++i) {
          for (unsigned j = 0; j < M.cols(); ++j) {
            const double want = mbsc_test::eval(mbsc::driver::finalize(m, eom, M(i, j)), ref);
            check_close(mbsc_test::eval(p.M[i][j], shown), want);
            if (trial == 0) check_close(mbsc_test::eval(read_back(p.M[i][j]), shown), want);
          }
          const double want = mbsc_test::eval(mbsc::driver::finalize(m, eom, r.h(i, 0)), ref);
          check_close(mbsc_test::eval(p.h[i][0], shown), want);
          if (trial == 0) check_close(mbsc_test::eval(read_back(p.h[i][0]), shown), want);
        }
        // The "where" lines as printed, too.
        if (trial == 0)
          for (const auto& w : p.where)
            if (w.solved) check_close(mbsc_test::eval(read_back(w.value), shown), mbsc_test::eval(w.value, shown));
      }
      // Numeric complements: closed forms everywhere but where a block is too large (the
      // parallelogram chain's 6 x 6 block, the 3-D slider-crank's 7 x 7 one, the Whipple
      // bicycle's 12 x 12 one and 5 x 5 in joint coordinates; the thick disc on the
      // incline, whose tilted normal makes its speed block's closed form too large).
      const std::string name = path.stem().string();
      const bool large_blocks = name == "parallelogram_chain" || name == "slider_crank_3d" ||
                                name == "whipple_bicycle" || name == "whipple_bicycle_joints" ||
                                name == "rolling_disc_incline";
      if (expand) {
        CHECK(p.all_closed == !large_blocks);
        if (name == "slider_crank_3d") {  // its 7 x 7 block stays numeric, the other rows are closed
          bool numeric_block = false, closed = false;
          for (const auto& w : p.where) {
            numeric_block |= w.from_solve && !w.solved;
            closed |= w.solved;
          }
          CHECK(numeric_block);
          CHECK(closed);
        } else {
          for (const auto& w : p.where) CHECK((w.from_solve && !w.solved) == large_blocks);
        }
        // Closed forms read the coordinates and the independent speeds z only, but where
        // the speed cannot be rebuilt (a `nonlinear` velocity block) or its closed form
        // would make h too large to print (the 3-RRR platform: over 60000 nodes; the rolling
        // disc, whose centre velocity in the angular speeds divides by the contact's sine).
        const bool keeps_speeds = name == "spherical_pendulum_extra_speed" || name == "three_rrr" ||
                                  name == "rolling_disc";
        CHECK(p.where.empty() == !large_blocks);
        if (!large_blocks && !keeps_speeds)
          for (std::size_t s = 0; s < m.speeds.size(); ++s) {
            if (std::find(eom.independent.begin(), eom.independent.end(), static_cast<int>(s)) != eom.independent.end())
              continue;
            INFO("dependent speed " << m.speeds[s].name);
            for (const auto& row : p.M)
              for (const auto& e : row) CHECK(!e.has(m.speeds[s].sym));
            for (const auto& row : p.h) CHECK(!row[0].has(m.speeds[s].sym));
          }
      }
    }
  }
}

TEST_CASE("double pendulum: the printed M is the textbook one", "[print][equations]") {
  // Two point masses on massless rods, absolute angles from the downward vertical; by
  // Lagrange's equations (T = m1/2 |v1|^2 + m2/2 |v2|^2), checked with sympy:
  //   M = [[(m1 + m2) l1^2, m2 l1 l2 cos(th1 - th2)], [m2 l1 l2 cos(th1 - th2), m2 l2^2]]
  //   h = [-m2 l1 l2 w2^2 sin(th1 - th2) - (m1 + m2) g l1 sin(th1),
  //         m2 l1 l2 w1^2 sin(th1 - th2) - m2 g l2 sin(th2)]
  Loaded l = load(kModels / "double_pendulum.mbs");
  const auto& m = *l.m;
  auto s = [&](const char* n) { return ex(sym_named(m, n)); };
  const ex th1 = s("th1"), th2 = s("th2"), w1 = s("w1"), w2 = s("w2"), m1 = s("m1"), m2 = s("m2"), l1 = s("l1"),
           l2 = s("l2"), g = s("g");
  const ex M[2][2] = {{(m1 + m2) * pow(l1, 2), m2 * l1 * l2 * cos(th1 - th2)},
                      {m2 * l1 * l2 * cos(th1 - th2), m2 * pow(l2, 2)}};
  const ex h[2] = {-m2 * l1 * l2 * pow(w2, 2) * sin(th1 - th2) - (m1 + m2) * g * l1 * sin(th1),
                   m2 * l1 * l2 * pow(w1, 2) * sin(th1 - th2) - m2 * g * l2 * sin(th2)};
  const char* text[2][2] = {{"(m1 + m2)*l1^2", "l1*l2*m2*cos(th1 - th2)"}, {"l1*l2*m2*cos(th1 - th2)", "l2^2*m2"}};
  for (bool expand : {false, true}) {
    const auto p = mbsc::print::printed_equations(m, *l.eom, m.root(), expand);
    for (int i = 0; i < 2; ++i) {
      for (int j = 0; j < 2; ++j) {
        CHECK(canonical_text(p.M[i][j], false) == text[i][j]);
        CHECK(mbsc_test::trig_equal(p.M[i][j], M[i][j]));
      }
      if (expand) CHECK(mbsc_test::trig_equal(p.h[i][0], h[i]));
    }
  }
  // What the command prints: the grid, and h in closed form with --expand.
  const std::string out = print_cli("double_pendulum.mbs", "--what M");
  CHECK(out.find("  w1'  (m1 + m2)*l1^2           l1*l2*m2*cos(th1 - th2)\n") != std::string::npos);
  CHECK(out.find("  w2'  l1*l2*m2*cos(th1 - th2)  l2^2*m2\n") != std::string::npos);
  const std::string expanded = print_cli("double_pendulum.mbs", "--what h --expand");
  CHECK(expanded.find("e_b1_u") == std::string::npos);
  CHECK(expanded.find("sin(th1 - th2)") != std::string::npos);
}

TEST_CASE("3R arm: the printed M and h are the textbook ones", "[print][equations]") {
  // Uniform rods (inertia m l^2/12 about the centre) hinged end to end, absolute angles
  // from the x axis, gravity -y; by Lagrange's equations, checked with sympy:
  //   M11 = (m1/3 + m2 + m3) l1^2, M22 = (m2/3 + m3) l2^2, M33 = m3 l3^2/3,
  //   M12 = (m2/2 + m3) l1 l2 cos(th1 - th2), M13 = m3/2 l1 l3 cos(th1 - th3),
  //   M23 = m3/2 l2 l3 cos(th2 - th3);
  //   h1 = -(m1/2 + m2 + m3) g l1 cos th1 - (m2/2 + m3) l1 l2 w2^2 sin(th1 - th2) - m3/2 l1 l3 w3^2 sin(th1 - th3) + tau1 - tau2
  //   h2 = -(m2/2 + m3) g l2 cos th2 + (m2/2 + m3) l1 l2 w1^2 sin(th1 - th2) - m3/2 l2 l3 w3^2 sin(th2 - th3) + tau2 - tau3
  //   h3 = -m3/2 g l3 cos th3 + m3/2 l1 l3 w1^2 sin(th1 - th3) + m3/2 l2 l3 w2^2 sin(th2 - th3) + tau3
  // (the joint torques act on both rods they join).
  Loaded l = load(kModels / "three_r_arm.mbs");
  const auto& m = *l.m;
  auto s = [&](const std::string& n) { return ex(sym_named(m, n)); };
  ex th[3], w[3], ms[3], ls[3], tau[3];
  for (int i = 0; i < 3; ++i) {
    const std::string k = std::to_string(i + 1);
    th[i] = s("link" + k + ".theta");
    w[i] = s("link" + k + ".w");
    ms[i] = s("m" + k);
    ls[i] = s("l" + k);
    tau[i] = s("tau" + k);
  }
  const ex g = s("g");
  const ex half = numeric(1, 2), third = numeric(1, 3);
  const ex M[3][3] = {
      {(ms[0] * third + ms[1] + ms[2]) * pow(ls[0], 2), (ms[1] * half + ms[2]) * ls[0] * ls[1] * cos(th[0] - th[1]),
       ms[2] * half * ls[0] * ls[2] * cos(th[0] - th[2])},
      {(ms[1] * half + ms[2]) * ls[0] * ls[1] * cos(th[0] - th[1]), (ms[1] * third + ms[2]) * pow(ls[1], 2),
       ms[2] * half * ls[1] * ls[2] * cos(th[1] - th[2])},
      {ms[2] * half * ls[0] * ls[2] * cos(th[0] - th[2]), ms[2] * half * ls[1] * ls[2] * cos(th[1] - th[2]),
       ms[2] * third * pow(ls[2], 2)}};
  const ex h[3] = {-(ms[0] * half + ms[1] + ms[2]) * g * ls[0] * cos(th[0]) -
                       (ms[1] * half + ms[2]) * ls[0] * ls[1] * pow(w[1], 2) * sin(th[0] - th[1]) -
                       ms[2] * half * ls[0] * ls[2] * pow(w[2], 2) * sin(th[0] - th[2]) + tau[0] - tau[1],
                   -(ms[1] * half + ms[2]) * g * ls[1] * cos(th[1]) +
                       (ms[1] * half + ms[2]) * ls[0] * ls[1] * pow(w[0], 2) * sin(th[0] - th[1]) -
                       ms[2] * half * ls[1] * ls[2] * pow(w[2], 2) * sin(th[1] - th[2]) + tau[1] - tau[2],
                   -ms[2] * half * g * ls[2] * cos(th[2]) + ms[2] * half * ls[0] * ls[2] * pow(w[0], 2) * sin(th[0] - th[2]) +
                       ms[2] * half * ls[1] * ls[2] * pow(w[1], 2) * sin(th[1] - th[2]) + tau[2]};
  // The textbook entries as written above, in the printer's spelling.
  const char* text[3][3] = {
      {"(1/3*m1 + m2 + m3)*l1^2", "(1/2*m2 + m3)*l1*l2*cos(link1.theta - link2.theta)",
       "1/2*l1*l3*m3*cos(link1.theta - link3.theta)"},
      {"(1/2*m2 + m3)*l1*l2*cos(link1.theta - link2.theta)", "(1/3*m2 + m3)*l2^2", "1/2*l2*l3*m3*cos(link2.theta - link3.theta)"},
      {"1/2*l1*l3*m3*cos(link1.theta - link3.theta)", "1/2*l2*l3*m3*cos(link2.theta - link3.theta)", "1/3*l3^2*m3"}};
  const auto p = mbsc::print::printed_equations(m, *l.eom, m.root(), true);
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      CHECK(canonical_text(p.M[i][j], false) == text[i][j]);
      CHECK(mbsc_test::trig_equal(p.M[i][j], M[i][j]));
    }
    CHECK(mbsc_test::trig_equal(p.h[i][0], h[i]));
  }
  const std::string out = print_cli("three_r_arm.mbs", "--what M");
  CHECK(out.find("[link3.w', link3.w'] = 1/3*l3^2*m3\n") != std::string::npos);
}

TEST_CASE("four-bar: the printed M is the textbook one, through the velocity ratios", "[print][equations]") {
  // Crank (a, angle t1) about O, coupler (b, t2), rocker (c, t3) about Q = (d, 0); uniform
  // bars. With the velocity ratios k2 = w2/w1 = -a sin(t1 - t3)/(b sin(t2 - t3)) and
  // k3 = w3/w1 = -a sin(t1 - t2)/(c sin(t2 - t3)) (loop closure differentiated, solved
  // with sympy), T = M w1^2/2 gives
  //   M = m1 a^2/3 + m2 a^2 + m2 a b k2 cos(t1 - t2) + m2 b^2 k2^2/3 + m3 c^2 k3^2/3.
  // The complement is numeric: print shows M through X_top_0_0 = -k2, X_top_1_0 = -k3
  // and lists their closed forms.
  Loaded l = load(kModels / "four_bar.mbs");
  const auto& m = *l.m;
  auto s = [&](const std::string& n) { return ex(sym_named(m, n)); };
  const ex t1 = s("crank.theta"), t2 = s("coupler.theta"), t3 = s("rocker.theta");
  const ex a = s("a"), b = s("b"), c = s("c"), m1 = s("m1"), m2 = s("m2"), m3 = s("m3");
  const ex k2 = -a * sin(t1 - t3) / (b * sin(t2 - t3)), k3 = -a * sin(t1 - t2) / (c * sin(t2 - t3));
  auto textbook = [&](const ex& r2, const ex& r3) {
    return m1 * pow(a, 2) / 3 + m2 * pow(a, 2) + m2 * a * b * r2 * cos(t1 - t2) + m2 * pow(b, 2) * pow(r2, 2) / 3 +
           m3 * pow(c, 2) * pow(r3, 2) / 3;
  };
  const auto p = mbsc::print::printed_equations(m, *l.eom, m.root(), false);
  REQUIRE(p.numeric_solves);
  symbol x00, x10;
  for (const auto& w : p.where) {
    if (w.sym.get_name() == "X_top_0_0") {
      x00 = w.sym;
      CHECK(canonical_text(w.value, false) == "a*sin(crank.theta - rocker.theta)/(b*sin(coupler.theta - rocker.theta))");
      CHECK(mbsc_test::trig_equal(w.value, -k2));
    }
    if (w.sym.get_name() == "X_top_1_0") {
      x10 = w.sym;
      CHECK(canonical_text(w.value, false) == "-a*sin(coupler.theta - crank.theta)/(c*sin(coupler.theta - rocker.theta))");
      CHECK(mbsc_test::trig_equal(w.value, -k3));
    }
  }
  CHECK(canonical_text(p.M[0][0], false) ==
        "1/3*X_top_0_0^2*b^2*m2 + 1/3*X_top_1_0^2*c^2*m3 + 1/3*a^2*m1 - X_top_0_0*a*b*m2*cos(coupler.theta - crank.theta) + "
        "a^2*m2");
  CHECK(mbsc_test::trig_equal(p.M[0][0], textbook(-x00, -x10)));
  // --expand: the closed form, equal to the textbook M with the ratios put in.
  const auto e = mbsc::print::printed_equations(m, *l.eom, m.root(), true);
  CHECK(e.where.empty());
  CHECK(mbsc_test::trig_equal(e.M[0][0], textbook(k2, k3)));
  const std::string out = print_cli("four_bar.mbs", "--what M");
  CHECK(out.find("note: the complement here is numeric") != std::string::npos);
  CHECK(out.find("  X_top_0_0 = a*sin(crank.theta - rocker.theta)/(b*sin(coupler.theta - rocker.theta))") != std::string::npos);
}
