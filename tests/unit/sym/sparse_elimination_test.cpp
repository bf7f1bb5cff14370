// SPDX-License-Identifier: GPL-2.0-or-later
// The O(N) right-hand side (sparse block elimination in a tree order, --solver sparse)
// against the dense one (reduced M z' = h by Cholesky; multipliers: Schur complement or
// KKT LU), on every shipped model and on random trees of bodies written by the test. Both
// rhs specs are evaluated step by step at pseudo-random states (GiNaC for the
// definitions, Eigen for the solves: independent of the emitted C++), so this checks the
// elimination itself; tests/numeric/sparse_rhs_test.cpp checks the compiled code.
#include <catch2/catch.hpp>
#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <vector>

#include "mbsc/driver/pipeline.hpp"
#include "mbsc/sym/probe.hpp"
#include "../test_scale.hpp"

namespace {

using mbsc::driver::Solver;

struct Loaded {
  std::optional<mbsc::model::Model> m;
  std::optional<mbsc::sym::Eom> eom;
};

Loaded load(const std::string& path) {
  Loaded d;
  mbsc::Diagnostics diags;
  d.m = mbsc::driver::load_model(path, diags);
  INFO(diags.format());
  REQUIRE(d.m);
  d.eom = mbsc::sym::derive(*d.m, {}, diags);
  INFO(diags.format());
  REQUIRE(d.eom);
  return d;
}

// Every step of a spec at the probe point, then its outputs.
std::vector<double> evaluate(const mbsc::ir::FunctionSpec& f, mbsc::sym::Probe& p) {
  for (const auto& step : f.steps) {
    if (const auto* d = std::get_if<mbsc::ir::Define>(&step)) {
      p.bind(d->sym, p.eval(d->value));
      continue;
    }
    const auto& s = std::get<mbsc::ir::Solve>(step);
    Eigen::MatrixXd A(s.n, s.n), B(s.n, s.k);
    for (int i = 0; i < s.n; ++i) {
      for (int j = 0; j < s.n; ++j) A(i, j) = p.eval(s.A[static_cast<std::size_t>(i * s.n + j)]);
      for (int j = 0; j < s.k; ++j) B(i, j) = p.eval(s.B[static_cast<std::size_t>(i * s.k + j)]);
    }
    const Eigen::MatrixXd X = A.fullPivLu().solve(B);
    for (int i = 0; i < s.n; ++i)
      for (int j = 0; j < s.k; ++j) p.bind(s.X[static_cast<std::size_t>(i * s.k + j)], X(i, j));
  }
  std::vector<double> out;
  for (const auto& e : f.outputs) out.push_back(p.eval(e));
  return out;
}

// The same in 32 significant digits (GiNaC floats, solves by GiNaC's Gaussian
// elimination): the reference. The state is the probe's, its doubles taken exactly.
std::vector<double> evaluate_precise(const mbsc::ir::FunctionSpec& f, const mbsc::model::Model& m, const mbsc::sym::Probe& p,
                                     const mbsc::driver::BaumgarteGains& gains) {
  struct Digits {
    long saved = GiNaC::Digits;
    Digits() { GiNaC::Digits = 32; }
    ~Digits() { GiNaC::Digits = saved; }
  } digits;
  auto exact = [](double v) {
    int e = 0;
    const double mant = std::frexp(v, &e);
    const auto i = static_cast<long long>(std::ldexp(mant, 53));
    return GiNaC::ex(GiNaC::numeric(i) * GiNaC::pow(GiNaC::numeric(2), e - 53));
  };
  GiNaC::exmap vals;
  auto put = [&](const GiNaC::ex& s) { vals[s] = exact(p.eval(s)); };
  put(m.time);
  for (const auto& v : m.coords) put(v.sym);
  for (const auto& v : m.speeds) put(v.sym);
  for (const auto& v : m.inputs) put(v.sym);
  for (const auto& v : m.params) put(v.sym);
  put(gains.alpha);
  put(gains.beta);
  for (const auto& fr : m.frictions) put(fr.force);
  auto value = [&](const GiNaC::ex& e) { return e.subs(vals).evalf(); };
  for (const auto& step : f.steps) {
    if (const auto* d = std::get_if<mbsc::ir::Define>(&step)) {
      vals[d->sym] = value(d->value);
      continue;
    }
    const auto& s = std::get<mbsc::ir::Solve>(step);
    GiNaC::matrix A(static_cast<unsigned>(s.n), static_cast<unsigned>(s.n)), B(static_cast<unsigned>(s.n), static_cast<unsigned>(s.k)),
        X(static_cast<unsigned>(s.n), static_cast<unsigned>(s.k));
    for (unsigned i = 0; i < A.rows(); ++i) {
      for (unsigned j = 0; j < A.cols(); ++j) A(i, j) = value(s.A[i * A.cols() + j]);
      for (unsigned j = 0; j < B.cols(); ++j) B(i, j) = value(s.B[i * B.cols() + j]);
    }
    // Gaussian elimination with partial pivoting by magnitude (GiNaC's own picks any
    // nonzero pivot, which loses the digits this reference is for).
    const unsigned n = A.rows(), k = B.cols();
    auto num = [](const GiNaC::ex& e) { return GiNaC::ex_to<GiNaC::numeric>(e); };
    for (unsigned c = 0; c < n; ++c) {
      unsigned piv = c;
      for (unsigned r = c + 1; r < n; ++r)
        if (GiNaC::abs(num(A(r, c))) > GiNaC::abs(num(A(piv, c)))) piv = r;
      for (unsigned j = 0; j < n; ++j) std::swap(A(c, j), A(piv, j));
      for (unsigned j = 0; j < k; ++j) std::swap(B(c, j), B(piv, j));
      for (unsigned r = c + 1; r < n; ++r) {
        const GiNaC::ex factor = (A(r, c) / A(c, c)).evalf();
        for (unsigned j = c; j < n; ++j) A(r, j) = (A(r, j) - factor * A(c, j)).evalf();
        for (unsigned j = 0; j < k; ++j) B(r, j) = (B(r, j) - factor * B(c, j)).evalf();
      }
    }
    for (unsigned j = 0; j < k; ++j)
      for (unsigned i = n; i-- > 0;) {
        GiNaC::ex acc = B(i, j);
        for (unsigned t = i + 1; t < n; ++t) acc -= A(i, t) * X(t, j);
        X(i, j) = (acc / A(i, i)).evalf();
      }
    for (unsigned i = 0; i < X.rows(); ++i)
      for (unsigned j = 0; j < X.cols(); ++j) vals[s.X[i * X.cols() + j]] = X(i, j);
  }
  std::vector<double> out;
  for (const auto& e : f.outputs) out.push_back(GiNaC::ex_to<GiNaC::numeric>(value(e)).to_double());
  return out;
}

struct Variant {
  bool multipliers = false;
  bool minimal = false;
};

// rhs of one variant, or nullopt when it cannot be built (e.g. no sparse order).
std::optional<mbsc::ir::FunctionSpec> rhs_spec(const Loaded& d, Solver solver, Variant v, const mbsc::driver::BaumgarteGains& gains,
                                               std::string& error) {
  mbsc::driver::GenerateOptions opt;
  opt.functions = {"rhs"};
  opt.solver = solver;
  opt.multipliers = v.multipliers;
  mbsc::Diagnostics diags;
  std::optional<mbsc::sym::MinimalState> ms;
  if (v.minimal) {
    ms = mbsc::sym::minimal_state(*d.m, *d.eom, diags);
    if (!ms) return std::nullopt;
  }
  const auto specs = v.multipliers ? mbsc::driver::multiplier_specs(*d.m, *d.eom, opt, gains, diags)
                                   : mbsc::driver::function_specs(*d.m, *d.eom, opt, diags, ms ? &*ms : nullptr);
  error = diags.format();
  for (const auto& f : specs)
    if (f.name == "rhs") return f;
  return std::nullopt;
}

// Errors of the two rhs (double evaluation) over a few probe points against the dense
// rhs in 32 digits, each relative to the largest |xdot|: {dense's, sparse's}. Under
// MBSC_TEST_SCALE=small (the sanitizer job) one probe point: the same evaluations.
std::pair<double, double> errors(const Loaded& d, const mbsc::ir::FunctionSpec& dense, const mbsc::ir::FunctionSpec& sparse,
                                 const mbsc::driver::BaumgarteGains& gains) {
  std::pair<double, double> worst{0.0, 0.0};
  const std::vector<unsigned> seeds = mbsc_test::small_scale() ? std::vector<unsigned>{11u} : std::vector<unsigned>{11u, 12u};
  for (unsigned seed : seeds) {
    mbsc::sym::Probe pa(*d.m, d.eom->param_values, seed), pb(*d.m, d.eom->param_values, seed);
    for (auto* p : {&pa, &pb}) {
      p->bind(gains.alpha, 7.0);
      p->bind(gains.beta, 5.0);
      // A friction force (slider_crank_3d) as a given value, like an input: the rhs
      // specs here are the solves before generate closes the friction law on them.
      for (const auto& fr : d.m->frictions) p->bind(fr.force, 0.3);
    }
    const mbsc::sym::Probe state = pa;
    const auto ref = evaluate_precise(dense, *d.m, state, gains);
    const auto xa = evaluate(dense, pa), xb = evaluate(sparse, pb);
    REQUIRE(xa.size() == xb.size());
    double scale = 1.0, ea = 0.0, eb = 0.0;
    for (std::size_t i = 0; i < xa.size(); ++i) {
      REQUIRE(std::isfinite(xa[i]));
      REQUIRE(std::isfinite(xb[i]));
      scale = std::max(scale, std::fabs(ref[i]));
      ea = std::max(ea, std::fabs(xa[i] - ref[i]));
      eb = std::max(eb, std::fabs(xb[i] - ref[i]));
    }
    worst.first = std::max(worst.first, ea / scale);
    worst.second = std::max(worst.second, eb / scale);
  }
  return worst;
}

// A random planar tree: body k (k = 1..n) hangs from a random earlier body or the ground
// by a revolute, prismatic or pin-in-slot joint at random points; random masses,
// inertias, mass centres; a spring on some joints so that the forces are not only gravity.
std::string random_tree(int n, std::mt19937& rng, bool coordinates = false) {
  std::uniform_real_distribution<double> mass(0.5, 2.0), len(0.2, 1.0), off(-0.2, 0.2);
  auto num = [](double v) { return std::to_string(v); };
  std::string s = "model random_tree\nparameter g = 9.81\ngravity (0, -g)\n";
  for (int k = 1; k <= n; ++k) {
    const double m = mass(rng), l = len(rng);
    s += "body b" + std::to_string(k) + " : rigid2d {\n  mass " + num(m) + "\n  inertia " + num(m * l * l / 12 + 0.01) +
         "\n  point P (" + num(off(rng)) + ", " + num(off(rng)) + ")\n  point D (" + num(l) + ", " + num(off(rng)) +
         ")\n  axis X (0, 0) (" + num(1.0) + ", " + num(off(rng)) + ")\n  com (" + num(l / 2) + ", " + num(off(rng)) +
         ")\n}\n";
  }
  for (int k = 1; k <= n; ++k) {
    const int parent = std::uniform_int_distribution<int>(0, k - 1)(rng);
    const std::string b = "b" + std::to_string(k);
    const std::string pp = parent == 0 ? "ground.origin" : "b" + std::to_string(parent) + ".D";
    const std::string pa = parent == 0 ? "ground.x_axis" : "b" + std::to_string(parent) + ".X";
    // With `coordinates`, revolute and prismatic joints carry a coordinate of their own
    // (joint coordinates: the tree recursion's case); pin-in-slot joints have none.
    const std::string own = coordinates ? " coordinate q" + std::to_string(k) : "";
    switch (std::uniform_int_distribution<int>(0, coordinates ? 2 : 3)(rng)) {
      case 0:
      case 1:
        s += "joint j" + std::to_string(k) + " : revolute " + pp + " " + b + ".P" + own + "\n";
        break;
      case 2:
        s += "joint j" + std::to_string(k) + " : prismatic " + pa + " " + b + ".P" + own + "\n";
        break;
      default:
        s += "joint j" + std::to_string(k) + " : pin_in_slot " + pa + " " + b + ".P\n";
        break;
    }
    if (std::uniform_int_distribution<int>(0, 2)(rng) == 0)
      s += "spring s" + std::to_string(k) + " " + pp + " " + b + ".D stiffness " + num(10 * mass(rng)) + "\n";
  }
  return s;
}

// A random spatial tree in joint coordinates: body k hangs from a random earlier body (or
// from the ground, or from a free base with a quaternion attitude) by a revolute joint with
// a coordinate, about a coordinate axis or a general unit axis (3/5, 0, 4/5); random
// masses, inertia tensors with products, mass centres and joint points; rotational springs
// and dampers on some joints so that the forces are not only gravity and gyroscopic.
// `mixed`: each joint's kind is drawn from revolute, prismatic, cylindrical, universal
// (the second axis perpendicular to the first) and spherical (a quaternion on even-numbered
// bodies, three angles of an Euler sequence on odd-numbered ones).
std::string spherical_coordinates(const std::string& j, const std::string& sequence) {
  if (sequence == "quaternion") return "e0_" + j + ", e1_" + j + ", e2_" + j + ", e3_" + j + " quaternion";
  return "al" + j + ", be" + j + ", ga" + j + " euler " + sequence;
}

std::string random_spatial_tree(int n, bool free_base, std::mt19937& rng, bool mixed = false) {
  std::uniform_real_distribution<double> mass(0.5, 2.0), len(0.2, 0.8), off(-0.15, 0.15), small(-0.004, 0.004);
  auto num = [](double v) { return std::to_string(v); };
  const std::vector<std::string> axes = {"(1, 0, 0)", "(0, 1, 0)", "(0, 0, 1)", "(3/5, 0, 4/5)"};
  const std::vector<std::string> normal_axes = {"(0, 1, 0)", "(0, 0, 1)", "(1, 0, 0)", "(0, 1, 0)"};  // perpendicular
  const std::vector<std::string> kinds = {"revolute", "prismatic", "cylindrical", "universal", "spherical"};
  const std::vector<std::string> sequences = {"zyx", "xyz", "zxz", "yzy"};
  std::vector<int> parent(static_cast<std::size_t>(n + 1), 0);
  std::vector<int> axis(static_cast<std::size_t>(n + 1), 0);
  std::vector<std::string> kind(static_cast<std::size_t>(n + 1), "revolute");
  for (int k = 1; k <= n; ++k) {
    const auto K = static_cast<std::size_t>(k);
    parent[K] = free_base && k == 1 ? -1 : std::uniform_int_distribution<int>(free_base ? 1 : 0, k - 1)(rng);
    axis[K] = std::uniform_int_distribution<int>(0, 3)(rng);
    // Under the ground the joint turns about one of the ground's axes.
    if (parent[K] == 0 && axis[K] == 3) axis[K] = 2;
    if (mixed) kind[K] = kinds[static_cast<std::size_t>(std::uniform_int_distribution<int>(0, 4)(rng))];
  }
  // An end: an axis (with the joint's direction; the child's second axis for universal)
  // or, for spherical, a point.
  auto end = [&](int c, const std::string& name, const std::string& at, bool child) {
    const auto C = static_cast<std::size_t>(c);
    if (kind[C] == "spherical") return "  point " + name + " " + at + "\n";
    const std::string& dir = child && kind[C] == "universal" ? normal_axes[static_cast<std::size_t>(axis[C])] : axes[static_cast<std::size_t>(axis[C])];
    return "  axis " + name + " " + at + " " + dir + "\n";
  };
  std::string s = "model random_spatial_tree\nparameter g = 9.81\ngravity (0, 0, -g)\n";
  for (int k = 1; k <= n; ++k) {
    const double m = mass(rng), l = len(rng);
    s += "body b" + std::to_string(k) + " : rigid3d {\n  mass " + num(m) + "\n  inertia (" + num(0.02 + 0.05 * m * l) + ", " +
         num(0.03 + 0.04 * m * l) + ", " + num(0.025 + 0.03 * m * l) + ", " + num(small(rng)) + ", " + num(small(rng)) + ", " +
         num(small(rng)) + ")\n  com (" + num(off(rng)) + ", " + num(off(rng)) + ", " + num(l / 2) + ")\n";
    if (parent[static_cast<std::size_t>(k)] != -1)
      s += end(k, "top", "(0, 0, 0)", true);
    else
      s += "  attitude quaternion body\n";
    for (int c = k + 1; c <= n; ++c)
      if (parent[static_cast<std::size_t>(c)] == k)
        s += end(c, "c" + std::to_string(c), "(" + num(off(rng)) + ", " + num(off(rng)) + ", " + num(l) + ")", false);
    s += "}\n";
  }
  const char* ground_axes[] = {"ground.x_axis", "ground.y_axis", "ground.z_axis"};
  for (int k = 1; k <= n; ++k) {
    const auto K = static_cast<std::size_t>(k);
    const int p = parent[K];
    if (p < 0) continue;
    const std::string b = "b" + std::to_string(k), j = std::to_string(k);
    const std::string end1 = p == 0 ? (kind[K] == "spherical" ? std::string("ground.origin") : ground_axes[axis[K]])
                                    : "b" + std::to_string(p) + ".c" + j;
    const std::string coordinates = kind[K] == "revolute" || kind[K] == "prismatic" ? "q" + j
                                    : kind[K] == "spherical" ? spherical_coordinates(j, k % 2 == 0 ? "quaternion" : sequences[static_cast<std::size_t>(k / 2) % sequences.size()])
                                                             : "q" + j + ", r" + j;
    s += "joint j" + j + " : " + kind[K] + " " + end1 + " " + b + ".top coordinate " + coordinates + "\n";
    const bool hinged = kind[K] == "revolute" || kind[K] == "cylindrical";
    if (hinged && std::uniform_int_distribution<int>(0, 2)(rng) == 0) {
      s += "spring s" + j + " rotational " + end1 + " " + b + ".top stiffness " + num(5 * mass(rng)) + " angle 0.2\n";
      s += "damper d" + j + " rotational " + end1 + " " + b + ".top coefficient 0.05\n";
    }
  }
  if (free_base) s += "initial b1.e0 = 1\n";
  return s;
}

// Closes `loops` loops on a random spatial tree of n bodies (random_spatial_tree's text):
// each holds a point of a random body on a plane, of the ground or of another body
// (point_on_plane: one row), or on a ground line (point_on_line: two rows, on a body
// deep enough to have the freedom). The joints have no coordinates of their own: their
// rows are the loops the tree recursion closes (docs/formulation.md, "Loops on the tree").
std::string close_loops(std::string text, int n, int loops, std::mt19937& rng) {
  std::uniform_real_distribution<double> off(-0.2, 0.2);
  auto num = [](double v) { return std::to_string(v); };
  auto vec = [&]() { return "(" + num(off(rng)) + ", " + num(off(rng)) + ", " + num(0.3 + off(rng)) + ")"; };
  const std::vector<std::string> normals = {"(1, 0, 0)", "(0, 1, 0)", "(3/5, 0, 4/5)", "(0, 0, 1)"};
  auto add_to_body = [&](int k, const std::string& line) {
    const std::string head = "body b" + std::to_string(k) + " : rigid3d {\n";
    const auto at = text.find(head);
    text.insert(at + head.size(), line);
  };
  std::string ground, joints;
  std::uniform_int_distribution<int> body(std::min(n, 3), n), normal(0, 3), kind(0, 2);
  for (int l = 1; l <= loops; ++l) {
    const std::string L = std::to_string(l);
    const int k = body(rng);
    add_to_body(k, "  point lp" + L + " " + vec() + "\n");
    const std::string point = "b" + std::to_string(k) + ".lp" + L;
    const int which = kind(rng);
    const int other = std::uniform_int_distribution<int>(1, n)(rng);
    if (which == 1 && other != k) {
      add_to_body(other, "  axis la" + L + " " + vec() + " " + normals[static_cast<std::size_t>(normal(rng))] + "\n");
      joints += "joint loop" + L + " : point_on_plane b" + std::to_string(other) + ".la" + L + " " + point + "\n";
    } else {
      ground += "  axis la" + L + " " + vec() + " " + normals[static_cast<std::size_t>(normal(rng))] + "\n";
      joints += "joint loop" + L + " : " + (which == 2 ? "point_on_line" : "point_on_plane") + " ground.la" + L + " " + point + "\n";
    }
  }
  return text + "ground {\n" + ground + "}\n" + joints;
}

// A random spatial tree of n bodies with `loops` loops closed on it whose rows are
// independent: drawn again while mbsc rejects a draw as redundant (a point held on a
// plane along which its body cannot move). The text, also written to `path`.
std::string loop_tree(int n, int loops, bool free_base, bool mixed, std::mt19937& rng, const std::string& path) {
  for (int draw = 0; draw < 20; ++draw) {
    const std::string text = close_loops(random_spatial_tree(n, free_base, rng, mixed), n, loops, rng);
    {
      std::ofstream f(path);
      f << text;
    }
    mbsc::Diagnostics diags;
    const auto m = mbsc::driver::load_model(path, diags);
    if (m && mbsc::sym::derive(*m, {}, diags)) return text;
  }
  FAIL("no draw of " << n << " bodies with " << loops << " independent loops");
  return {};
}

// Whether a spec's steps are the tree recursion's (its joint pivots carry that label).
bool uses_tree_recursion(const mbsc::ir::FunctionSpec& f) {
  for (const auto& step : f.steps)
    if (const auto* s = std::get_if<mbsc::ir::Solve>(&step); s && s->label.rfind("tree recursion", 0) == 0) return true;
  return false;
}

// The model `text` (written to `path`): for each variant, --solver sparse must build (and,
// when `tree`, take the tree recursion) and agree with the dense rhs's 32-digit
// evaluation to 1e-12.
// With `as_accurate_as_dense` (loops, whose conditioning at a random state can be poor),
// the bound is 1e-12 or ten times the dense rhs's own error, whichever is larger.
void check_tree_against_dense(const std::string& text, const std::string& path, const std::vector<Variant>& variants,
                              bool tree, const std::string& label, bool as_accurate_as_dense = false) {
  const mbsc::driver::BaumgarteGains gains;
  {
    std::ofstream f(path);
    f << text;
  }
  INFO(text);
  const Loaded d = load(path);
  for (const Variant& v : variants) {
    std::string err;
    const auto dense = rhs_spec(d, Solver::Dense, v, gains, err);
    REQUIRE(dense);
    const auto sparse = rhs_spec(d, Solver::Sparse, v, gains, err);
    INFO(err);
    REQUIRE(sparse);
    if (tree) CHECK(uses_tree_recursion(*sparse));
    const auto [dense_error, sparse_error] = errors(d, *dense, *sparse, gains);
    INFO(label << (v.multipliers ? " multipliers" : v.minimal ? " minimal" : " full")
               << ", relative errors against 32 digits: dense " << dense_error << ", sparse " << sparse_error);
    CHECK(sparse_error < (as_accurate_as_dense ? std::max(1e-12, 10 * dense_error) : 1e-12));
  }
}

}  // namespace

TEST_CASE("sparse elimination agrees with the dense rhs on every shipped model", "[sym][sparse]") {
  const mbsc::driver::BaumgarteGains gains;
  std::vector<std::string> files;
  for (const auto& e : std::filesystem::directory_iterator(std::string(MBSC_SOURCE_DIR) + "/models"))
    if (e.path().extension() == ".mbs") files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  REQUIRE(files.size() >= 17);
  int trees = 0;
  for (const auto& file : files) {
    const Loaded d = load(file);
    for (const Variant v : {Variant{false, false}, Variant{true, false}, Variant{false, true}}) {
      std::string err;
      const auto dense = rhs_spec(d, Solver::Dense, v, gains, err);
      if (!dense) continue;  // e.g. no minimal state for this model
      const auto sparse = rhs_spec(d, Solver::Sparse, v, gains, err);
      INFO(file << (v.multipliers ? " multipliers" : " complement") << (v.minimal ? " minimal" : " full") << ": " << err);
      // Every model whose bodies form a tree must have an order; loops may not.
      if (!sparse) {
        CHECK(err.find("cannot be solved in a tree order") != std::string::npos);
        continue;
      }
      const auto [dense_error, sparse_error] = errors(d, *dense, *sparse, gains);
      INFO(file << (v.multipliers ? " multipliers" : " complement") << (v.minimal ? " minimal" : " full")
                << ": relative errors against 32 digits: dense " << dense_error << ", sparse " << sparse_error);
      // In double, as the generated code computes: most models agree to 1e-14; the
      // bicycle's sparse forms reach 4e-13 to 1.1e-12 (its dense complement 8e-12).
      CHECK(sparse_error < 5e-12);
      ++trees;
    }
  }
  CHECK(trees >= 30);
}

TEST_CASE("sparse elimination agrees with the dense rhs on random trees of 1 to 40 bodies", "[sym][sparse][trees]") {
  std::mt19937 rng(20261202);
  const std::string path = (std::filesystem::temp_directory_path() / "mbsc_random_tree.mbs").string();
  // Under MBSC_TEST_SCALE=small (the sanitizer job) up to 20 bodies: every joint kind,
  // branching and depth appear already (the Release run takes 40 too).
  const std::vector<int> sizes = mbsc_test::small_scale() ? std::vector<int>{1, 2, 4, 9, 20} : std::vector<int>{1, 2, 4, 9, 20, 40};
  for (int n : sizes)
    check_tree_against_dense(random_tree(n, rng), path, {Variant{false, false}, Variant{true, false}}, false,
                             "n = " + std::to_string(n));
  std::remove(path.c_str());
}

TEST_CASE("a loop through the ground that the block graph does not show is not taken for a tree", "[sym][sparse]") {
  // The four-bar in angle coordinates: the closure's pivot would join the crank's and the
  // rocker's sides, singular where crank and rocker are parallel although the mechanism
  // is regular there. The pendulum chain in the same style is a tree.
  auto forest = [](const std::string& file, const std::map<std::string, double>& frozen) {
    mbsc::Diagnostics diags;
    const auto m = mbsc::driver::load_model(std::string(MBSC_SOURCE_DIR) + "/tests/data/chain/" + file, diags, frozen);
    INFO(diags.format());
    REQUIRE(m);
    const auto eom = mbsc::sym::derive(*m, {}, diags);
    REQUIRE(eom);
    const auto sys = mbsc::sym::kkt_system(*m);
    std::vector<GiNaC::ex> c;
    std::vector<GiNaC::symbol> lambda;
    for (const auto& b : sys.b) {
      c.push_back(-b);
      lambda.emplace_back();
    }
    std::string why;
    const auto e = mbsc::driver::sparse_solve_steps(*m, *eom, sys, c, lambda, why);
    INFO(why);
    REQUIRE(e);
    bool reported = false;
    for (const auto& step : e->steps)
      if (const auto* s = std::get_if<mbsc::ir::Solve>(&step)) reported = reported || s->reported;
    CHECK(reported == !e->forest);  // a loop's pivots are watched by `conditioning`
    return e->forest;
  };
  CHECK_FALSE(forest("angle_four_bar.mbs", {}));
  CHECK(forest("pendulum_chain.mbs", {{"N", 6}}));
}

TEST_CASE("a loop of massive bodies is eliminated speeds first: only constraint pivots, banded fill", "[sym][sparse]") {
  // The parallelogram chain of 40 windows (every body has mass and inertia): the fewest-
  // neighbours order meets the loops; speeds first makes every constraint pivot a Schur
  // complement of -A My^-1 A^T (regular wherever A has full rank), and only those are
  // watched by `conditioning`. The fill stays that of a banded A My^-1 A^T: far fewer
  // operations than the dense forms.
  mbsc::Diagnostics diags;
  const auto m = mbsc::driver::load_model(std::string(MBSC_SOURCE_DIR) + "/models/parallelogram_chain.mbs", diags, {{"N", 40}});
  INFO(diags.format());
  REQUIRE(m);
  const auto eom = mbsc::sym::derive(*m, {}, diags);
  REQUIRE(eom);
  const auto sys = mbsc::sym::kkt_system(*m);
  std::vector<GiNaC::ex> c;
  std::vector<GiNaC::symbol> lambda;
  for (const auto& b : sys.b) {
    c.push_back(-b);
    lambda.emplace_back();
  }
  std::string why;
  const auto e = mbsc::driver::sparse_solve_steps(*m, *eom, sys, c, lambda, why);
  INFO(why);
  REQUIRE(e);
  CHECK_FALSE(e->forest);
  CHECK(e->speeds_first);
  int constraint_pivots = 0, speed_pivots = 0;
  for (const auto& step : e->steps)
    if (const auto* s = std::get_if<mbsc::ir::Solve>(&step)) {
      const bool constraint = s->label.rfind("sparse elimination: constraints", 0) == 0;
      (constraint ? constraint_pivots : speed_pivots) += 1;
      CHECK(s->reported == constraint);
    }
  CHECK(constraint_pivots > 0);
  CHECK(speed_pivots > 0);
  // Forced sparse against dense, both formulations: same accelerations (32-digit dense
  // reference), and a fraction of the operations.
  Loaded d;
  d.m = m;
  d.eom = eom;
  const mbsc::driver::BaumgarteGains gains;
  for (const Variant v : {Variant{false, false}, Variant{true, false}}) {
    INFO("multipliers " << v.multipliers);
    std::string err;
    const auto dense = rhs_spec(d, Solver::Dense, v, gains, err);
    REQUIRE(dense);
    const auto sparse = rhs_spec(d, Solver::Sparse, v, gains, err);
    INFO(err);
    REQUIRE(sparse);
    const auto [dense_error, sparse_error] = errors(d, *dense, *sparse, gains);
    INFO("relative errors against 32 digits: dense " << dense_error << ", sparse " << sparse_error);
    // Evaluated in double, as the generated code is: 1.8-2.0e-12 for the sparse form and
    // up to 1e-12 for the dense multipliers form on this 40-window loop (the summation
    // order of a term follows GiNaC's, which changes from run to run).
    CHECK(sparse_error < 5e-12);
    auto binds = mbsc::driver::bindings(*d.m, *d.eom);
    binds.push_back({gains.alpha, "p[100]", true});  // the multipliers' gains (any free slot)
    binds.push_back({gains.beta, "p[101]", true});
    const long dense_ops = mbsc::ir::lower(*dense, binds).ops.total();
    const long sparse_ops = mbsc::ir::lower(*sparse, binds).ops.total();
    INFO("operations: dense " << dense_ops << ", sparse " << sparse_ops);
    CHECK(3 * sparse_ops < dense_ops);
  }
}

namespace {

// Binds a coordinate or speed of the model by name in a probe.
void bind_named(const mbsc::model::Model& m, mbsc::sym::Probe& p, const std::string& name, double v) {
  for (const auto& c : m.coords)
    if (c.name == name) return p.bind(c.sym, v);
  for (const auto& s : m.speeds)
    if (s.name == name) return p.bind(s.sym, v);
  FAIL("no coordinate or speed " << name);
}

}  // namespace

TEST_CASE("auto takes a loop's elimination only where it is as regular as the dense forms: the angle four-bar",
          "[sym][sparse][auto]") {
  // tests/data/chain/angle_four_bar.mbs: the angles are massless, so no speeds-first order
  // exists, and the fewest-neighbours order's closure pivot vanishes where the crank is
  // parallel to the rocker (th1 = th3), a pose where A has full rank. auto must keep the
  // dense forms there: its rhs equals the dense rhs at that pose and 1e-6 rad from it.
  const Loaded d = load(std::string(MBSC_SOURCE_DIR) + "/tests/data/chain/angle_four_bar.mbs");
  const auto& m = *d.m;
  const double l1 = 0.3, l2 = 1.0, l3 = 0.8, dd = 1.0;
  // Parallel: th1 = th3 = t with (l3 - l1)(cos t, sin t) + (d, 0) of length l2, cos t = -1/4.
  const double t_par = std::acos(-0.25);
  // The closed loop at crank angle th1: Newton on (th2, th3) from the parallel pose's.
  auto assemble = [&](double th1, double& th2, double& th3) {
    th3 = t_par;
    th2 = std::atan2(0.5 * std::sin(t_par), 0.875);
    for (int it = 0; it < 50; ++it) {
      const double f0 = l1 * std::cos(th1) + l2 * std::cos(th2) - dd - l3 * std::cos(th3);
      const double f1 = l1 * std::sin(th1) + l2 * std::sin(th2) - l3 * std::sin(th3);
      Eigen::Matrix2d J;
      J << -l2 * std::sin(th2), l3 * std::sin(th3), l2 * std::cos(th2), -l3 * std::cos(th3);
      const Eigen::Vector2d step = J.fullPivLu().solve(Eigen::Vector2d(-f0, -f1));
      th2 += step(0);
      th3 += step(1);
    }
  };
  const mbsc::driver::BaumgarteGains gains;
  int parallel_pivot_seen = 0;
  for (const Variant v : {Variant{false, false}, Variant{true, false}, Variant{false, true}}) {
    std::string err;
    const auto dense = rhs_spec(d, Solver::Dense, v, gains, err);
    const auto autos = rhs_spec(d, Solver::Auto, v, gains, err);
    const auto forced = rhs_spec(d, Solver::Sparse, v, gains, err);
    INFO((v.multipliers ? "multipliers" : "complement") << (v.minimal ? " minimal" : " full") << ": " << err);
    REQUIRE(dense);
    REQUIRE(autos);
    for (double offset : {0.0, 1e-6, -1e-6}) {
      const double th1 = t_par + offset;
      double th2 = 0.0, th3 = 0.0;
      assemble(th1, th2, th3);
      INFO("th1 - th3 = " << th1 - th3);
      REQUIRE(std::abs(th1 - th3) <= 1e-5);
      REQUIRE(std::abs(l1 * std::sin(th1) + l2 * std::sin(th2) - l3 * std::sin(th3)) < 1e-14);
      // Consistent speeds: w1 = 2, w2 and w3 from the closure's rates.
      const double w1 = 2.0;
      Eigen::Matrix2d J;
      J << -l2 * std::sin(th2), l3 * std::sin(th3), l2 * std::cos(th2), -l3 * std::cos(th3);
      const Eigen::Vector2d w = J.fullPivLu().solve(Eigen::Vector2d(l1 * std::sin(th1) * w1, -l1 * std::cos(th1) * w1));
      auto state = [&](mbsc::sym::Probe& p) {
        p.bind(gains.alpha, 7.0);
        p.bind(gains.beta, 5.0);
        bind_named(m, p, "th1", th1);
        bind_named(m, p, "th2", th2);
        bind_named(m, p, "th3", th3);
        bind_named(m, p, "w1", w1);
        bind_named(m, p, "w2", w(0));
        bind_named(m, p, "w3", w(1));
        bind_named(m, p, "b1.x", l1 * std::cos(th1));
        bind_named(m, p, "b1.y", l1 * std::sin(th1));
        bind_named(m, p, "b3.x", dd + l3 * std::cos(th3));
        bind_named(m, p, "b3.y", l3 * std::sin(th3));
        bind_named(m, p, "b1.u", -l1 * std::sin(th1) * w1);
        bind_named(m, p, "b1.v", l1 * std::cos(th1) * w1);
        bind_named(m, p, "b3.u", -l3 * std::sin(th3) * w(1));
        bind_named(m, p, "b3.v", l3 * std::cos(th3) * w(1));
      };
      mbsc::sym::Probe pd(m, d.eom->param_values), pa(m, d.eom->param_values);
      state(pd);
      state(pa);
      const auto xd = evaluate(*dense, pd), xa = evaluate(*autos, pa);
      REQUIRE(xd.size() == xa.size());
      double scale = 1.0, diff = 0.0;
      for (std::size_t i = 0; i < xd.size(); ++i) {
        REQUIRE(std::isfinite(xd[i]));
        REQUIRE(std::isfinite(xa[i]));
        scale = std::max(scale, std::fabs(xd[i]));
        diff = std::max(diff, std::fabs(xa[i] - xd[i]));
      }
      CHECK(diff < 1e-9 * scale);
      // What auto refuses: the forced tree order solves a pivot that vanishes at th1 = th3.
      if (forced && offset == 0.0) {
        mbsc::sym::Probe pf(m, d.eom->param_values);
        state(pf);
        for (const auto& step : forced->steps) {
          if (const auto* dfn = std::get_if<mbsc::ir::Define>(&step)) {
            pf.bind(dfn->sym, pf.eval(dfn->value));
            continue;
          }
          const auto& s = std::get<mbsc::ir::Solve>(step);
          Eigen::MatrixXd A(s.n, s.n);
          for (int i = 0; i < s.n; ++i)
            for (int j = 0; j < s.n; ++j) A(i, j) = pf.eval(s.A[static_cast<std::size_t>(i * s.n + j)]);
          double big = 1.0;
          for (int i = 0; i < s.n; ++i) big = std::max(big, std::fabs(pf.eval(s.A[static_cast<std::size_t>(i * s.n + i)])));
          if (A.fullPivLu().rank() < s.n || std::fabs(A.determinant()) < 1e-12 * std::pow(big, s.n)) ++parallel_pivot_seen;
          Eigen::MatrixXd B(s.n, s.k);
          for (int i = 0; i < s.n; ++i)
            for (int j = 0; j < s.k; ++j) B(i, j) = pf.eval(s.B[static_cast<std::size_t>(i * s.k + j)]);
          const Eigen::MatrixXd X = A.fullPivLu().solve(B);
          for (int i = 0; i < s.n; ++i)
            for (int j = 0; j < s.k; ++j) pf.bind(s.X[static_cast<std::size_t>(i * s.k + j)], X(i, j));
        }
      }
    }
  }
  // The hazard is real: the forced order met a singular pivot at the parallel pose.
  CHECK(parallel_pivot_seen > 0);
}

TEST_CASE("auto takes the speeds-first elimination of the 40-window parallelogram chain", "[sym][sparse][auto]") {
  // Every body has mass: the loop is eliminated speeds first, regular wherever A has full
  // rank, and far cheaper than the dense forms (an 80x80 LU, a 242x242 Cholesky): auto
  // takes it, in both formulations and with --state minimal.
  Loaded d;
  {
    mbsc::Diagnostics diags;
    d.m = mbsc::driver::load_model(std::string(MBSC_SOURCE_DIR) + "/models/parallelogram_chain.mbs", diags, {{"N", 40}});
    INFO(diags.format());
    REQUIRE(d.m);
    d.eom = mbsc::sym::derive(*d.m, {}, diags);
    REQUIRE(d.eom);
  }
  const mbsc::driver::BaumgarteGains gains;
  auto binds = mbsc::driver::bindings(*d.m, *d.eom);
  binds.push_back({gains.alpha, "p[100]", true});
  binds.push_back({gains.beta, "p[101]", true});
  for (const Variant v : {Variant{false, false}, Variant{true, false}}) {
    INFO("multipliers " << v.multipliers);
    std::string err;
    const auto dense = rhs_spec(d, Solver::Dense, v, gains, err);
    const auto autos = rhs_spec(d, Solver::Auto, v, gains, err);
    const auto forced = rhs_spec(d, Solver::Sparse, v, gains, err);
    INFO(err);
    REQUIRE(dense);
    REQUIRE(autos);
    REQUIRE(forced);
    const long dense_ops = mbsc::ir::lower(*dense, binds).ops.total();
    const long auto_ops = mbsc::ir::lower(*autos, binds).ops.total();
    const long forced_ops = mbsc::ir::lower(*forced, binds).ops.total();
    INFO("operations: dense " << dense_ops << ", auto " << auto_ops << ", sparse " << forced_ops);
    CHECK(auto_ops == forced_ops);
    CHECK(5 * auto_ops < dense_ops);
    int constraint_pivots = 0;
    for (const auto& step : autos->steps)
      if (const auto* s = std::get_if<mbsc::ir::Solve>(&step); s && s->label.rfind("sparse elimination: constraints", 0) == 0)
        ++constraint_pivots;
    CHECK(constraint_pivots > 0);
    const auto [dense_error, auto_error] = errors(d, *dense, *autos, gains);
    INFO("relative errors against 32 digits: dense " << dense_error << ", auto " << auto_error);
    CHECK(auto_error < 5e-12);
  }
}

TEST_CASE("the tree recursion agrees with the dense rhs on random spatial trees of 1 to 40 bodies", "[sym][sparse][trees]") {
  // Above four placed bodies every body's rotation is named and each body's rows read its
  // parent's speeds alone: --solver sparse takes the articulated-body recursion
  // (sym/tree_recursion.hpp). Its rhs, in double, against the dense rhs in 32 digits.
  std::mt19937 rng(20261205);
  const std::string path = (std::filesystem::temp_directory_path() / "mbsc_random_spatial_tree.mbs").string();
  struct Case {
    int n;
    bool free_base;
  };
  const std::vector<Case> cases = mbsc_test::small_scale()
                                      ? std::vector<Case>{{1, false}, {6, false}, {7, true}, {12, false}}
                                      : std::vector<Case>{{1, false}, {3, true}, {6, false}, {7, true}, {12, false}, {20, true}, {40, false}};
  // The big trees in the full state only: the dense reference's 32-digit evaluation is
  // what costs (the minimal state's rows are the same, checked on the smaller trees).
  for (const auto& c : cases)
    check_tree_against_dense(random_spatial_tree(c.n, c.free_base, rng), path,
                             c.n >= 20 ? std::vector<Variant>{Variant{false, false}}
                                       : std::vector<Variant>{Variant{false, false}, Variant{false, true}},
                             c.n > 4 || c.free_base, "n = " + std::to_string(c.n) + (c.free_base ? " (free base)" : ""));
  std::remove(path.c_str());
}

TEST_CASE("the tree recursion agrees with the dense rhs on random spatial trees of mixed joint kinds",
          "[sym][sparse][trees]") {
  // Revolute, prismatic, cylindrical, universal and spherical joints with coordinates: every
  // kind places its child by a slide and turns (docs/formulation.md, "Joint coordinates in
  // space"), and the tree recursion reads them all alike.
  std::mt19937 rng(20261209);
  const std::string path = (std::filesystem::temp_directory_path() / "mbsc_random_mixed_tree.mbs").string();
  struct Case {
    int n;
    bool free_base;
  };
  const std::vector<Case> cases = mbsc_test::small_scale() ? std::vector<Case>{{2, false}, {6, true}, {10, false}}
                                                           : std::vector<Case>{{1, false}, {2, false}, {3, true}, {6, true},
                                                                               {9, false}, {12, true}};
  int quaternion_joints = 0;
  for (const auto& c : cases) {
    const std::string text = random_spatial_tree(c.n, c.free_base, rng, /*mixed=*/true);
    for (auto at = text.find(" quaternion\n"); at != std::string::npos; at = text.find(" quaternion\n", at + 1)) ++quaternion_joints;
    check_tree_against_dense(text, path,
                             c.n >= 9 ? std::vector<Variant>{Variant{false, false}}
                                      : std::vector<Variant>{Variant{false, false}, Variant{false, true}},
                             c.n > 4 || c.free_base, "n = " + std::to_string(c.n) + (c.free_base ? " (free base)" : ""));
  }
  CHECK(quaternion_joints > 0);  // spherical joints with a quaternion were drawn
  std::remove(path.c_str());
}

TEST_CASE("the tree recursion agrees with the dense rhs on random planar trees in joint coordinates", "[sym][sparse][trees]") {
  // Revolute and prismatic joints with coordinates place each body from its parent: the
  // rows give the child's x, y, theta one by one, and --solver sparse takes the recursion.
  std::mt19937 rng(20261207);
  const std::string path = (std::filesystem::temp_directory_path() / "mbsc_random_joint_tree.mbs").string();
  for (int n : {1, 4, 12, 30})
    check_tree_against_dense(random_tree(n, rng, /*coordinates=*/true), path,
                             {Variant{false, false}, Variant{false, true}, Variant{true, false}}, true, "n = " + std::to_string(n));
  std::remove(path.c_str());
}

TEST_CASE("the tree recursion closes loops on random spatial trees", "[sym][sparse][trees]") {
  // Rows that no joint's coordinates make explicit (a point held on a plane or a line)
  // close loops: the recursion carries a unit force per loop row, solves the small
  // A M^-1 A^T system for their multipliers and sweeps out once (sym/tree_recursion.hpp).
  // Its rhs, in double, against the dense rhs in 32 digits; full and minimal state.
  std::mt19937 rng(20261210);
  const std::string path = (std::filesystem::temp_directory_path() / "mbsc_random_loop_tree.mbs").string();
  struct Case {
    int n, loops;
    bool free_base, mixed;
  };
  const std::vector<Case> cases = mbsc_test::small_scale()
                                      ? std::vector<Case>{{6, 1, false, false}, {12, 1, false, false}}
                                      : std::vector<Case>{{6, 1, false, false}, {8, 2, true, false}, {10, 2, false, true}, {12, 1, false, false}};
  for (const auto& c : cases) {
    const std::string text = loop_tree(c.n, c.loops, c.free_base, c.mixed, rng, path);
    check_tree_against_dense(text, path,
                             c.n > 6 ? std::vector<Variant>{Variant{false, false}}
                                     : std::vector<Variant>{Variant{false, false}, Variant{false, true}},
                             true, "n = " + std::to_string(c.n) + ", " + std::to_string(c.loops) + " loops",
                             /*as_accurate_as_dense=*/true);
    // The loops' pivot is there, and it is reported (conditioning), unlike the joints'.
    const Loaded d = load(path);
    std::string err;
    const auto sparse = rhs_spec(d, Solver::Sparse, Variant{false, false}, mbsc::driver::BaumgarteGains{}, err);
    REQUIRE(sparse);
    int loop_solves = 0;
    for (const auto& step : sparse->steps)
      if (const auto* s = std::get_if<mbsc::ir::Solve>(&step); s && s->label == "tree recursion: loop rows") {
        ++loop_solves;
        CHECK(s->reported);
        CHECK(s->n >= c.loops);
      }
    CHECK(loop_solves == 1);
  }
  std::remove(path.c_str());
}

TEST_CASE("the tree recursion's multipliers equal the dense multipliers formulation's", "[sym][sparse]") {
  // --formulation multipliers: the recursion defines every row's lambda leaves to root
  // from each body's own equations; the rows are independent, so lambda is unique and
  // must equal the dense KKT solve's (rhs with Baumgarte terms, multipliers, reactions).
  const mbsc::driver::BaumgarteGains gains;
  std::mt19937 rng(20261206);
  const std::string path = (std::filesystem::temp_directory_path() / "mbsc_random_spatial_tree_mult.mbs").string();
  // Revolute trees, trees of mixed kinds (whose joints fix their children by one to
  // three rates each), and mixed trees with loops closed on them (the loop rows'
  // multipliers come from the loops' solve, the tree rows' from the bodies' equations).
  struct Case {
    bool free_base, mixed;
    int loops;
  };
  for (const auto& [free_base, mixed, loops] : {Case{false, false, 0}, Case{true, false, 0}, Case{false, true, 0},
                                                Case{true, true, 0}, Case{false, true, 2}}) {
    const std::string text = loops > 0 ? loop_tree(7, loops, free_base, mixed, rng, path) : random_spatial_tree(7, free_base, rng, mixed);
    {
      std::ofstream f(path);
      f << text;
    }
    INFO(text);
    const Loaded d = load(path);
    auto specs = [&](Solver solver) {
      mbsc::driver::GenerateOptions opt;
      opt.functions = {"rhs", "multipliers", "reaction_forces"};
      opt.solver = solver;
      opt.multipliers = true;
      mbsc::Diagnostics diags;
      auto out = mbsc::driver::multiplier_specs(*d.m, *d.eom, opt, gains, diags);
      INFO(diags.format());
      REQUIRE(out.size() == 3);
      return out;
    };
    const auto dense = specs(Solver::Dense), tree = specs(Solver::Sparse);
    CHECK(uses_tree_recursion(tree[0]));
    for (std::size_t f = 0; f < 3; ++f) {
      mbsc::sym::Probe pa(*d.m, d.eom->param_values, 21), pb(*d.m, d.eom->param_values, 21);
      for (auto* p : {&pa, &pb}) {
        p->bind(gains.alpha, 7.0);
        p->bind(gains.beta, 5.0);
      }
      const auto xa = evaluate(dense[f], pa), xb = evaluate(tree[f], pb);
      REQUIRE(xa.size() == xb.size());
      REQUIRE_FALSE(xa.empty());
      double scale = 1.0, diff = 0.0;
      for (std::size_t i = 0; i < xa.size(); ++i) {
        REQUIRE(std::isfinite(xb[i]));
        scale = std::max(scale, std::fabs(xa[i]));
        diff = std::max(diff, std::fabs(xa[i] - xb[i]));
      }
      INFO(dense[f].name << (free_base ? " (free base)" : "") << (mixed ? " (mixed kinds)" : "") << " loops " << loops << ": relative difference "
                         << diff / scale);
      CHECK(diff < 1e-10 * scale);
    }
  }
  std::remove(path.c_str());
}

TEST_CASE("auto takes the tree recursion for a long spatial chain and the dense rhs for a short one", "[sym][sparse][auto]") {
  // A chain of n links, axes z, y, x, ...: at 3 links the written-out rotations' dense rhs
  // is cheaper; at 10 the recursion (linear in n) is, and auto must take it.
  auto chain = [](int n) {
    const char* axes[] = {"(0, 0, 1)", "(0, 1, 0)", "(1, 0, 0)"};
    std::string s = "model spatial_chain\nparameter g = 9.81\ngravity (0, 0, -g)\n";
    for (int k = 1; k <= n; ++k) {
      s += "body l" + std::to_string(k) + " : rigid3d {\n  mass 1.1\n  inertia (0.05, 0.06, 0.04, 0.001, -0.002, 0.003)\n"
           "  com (0.1, 0.02, 0.2)\n  axis top (0, 0, 0) " + std::string(axes[(k - 1) % 3]) + "\n";
      if (k < n) s += "  axis tip (0, 0, 0.5) " + std::string(axes[k % 3]) + "\n";
      s += "}\n";
    }
    s += "joint j1 : revolute ground.z_axis l1.top coordinate q1\n";
    for (int k = 2; k <= n; ++k)
      s += "joint j" + std::to_string(k) + " : revolute l" + std::to_string(k - 1) + ".tip l" + std::to_string(k) + ".top coordinate q" +
           std::to_string(k) + "\n";
    return s;
  };
  const mbsc::driver::BaumgarteGains gains;
  const std::string path = (std::filesystem::temp_directory_path() / "mbsc_spatial_chain.mbs").string();
  for (int n : {3, 10}) {
    {
      std::ofstream f(path);
      f << chain(n);
    }
    const Loaded d = load(path);
    std::string err;
    const auto autos = rhs_spec(d, Solver::Auto, Variant{false, true}, gains, err);
    INFO("n = " << n << ": " << err);
    REQUIRE(autos);
    CHECK(uses_tree_recursion(*autos) == (n == 10));
  }
  std::remove(path.c_str());
}
