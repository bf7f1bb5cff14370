// SPDX-License-Identifier: GPL-2.0-or-later
// Coulomb friction on prismatic and cylindrical joints closed in the generated code
// (docs/formulation.md, "Coulomb friction on a reaction"). Each friction force F is a
// symbol in the forces; every function that reads one gets, before its first use, the
// steps that define them all.
// One joint with friction:
//  1. the system over all speeds [My -A^T; A 0] [q1'; lambda] = [hy; c] solved for two
//     right-hand sides, hy at F = 0 and dhy/dF (the forces are affine in F), so that the
//     joint's normal reaction is N = N0 + F N1;
//  2. the law F = -mu sign(v) |N| squared: (1 - mu^2 |N1|^2) F^2 - 2 mu^2 (N0.N1) F -
//     mu^2 |N0|^2 = 0, whose roots have opposite signs while 1 - mu^2 |N1|^2 > 0; the
//     root of sign -sign(v) is F, and v = 0 gives F = 0;
//  3. 1 - mu^2 |N1|^2 is "solved" as a 1x1 positive definite block: where it is not
//     positive (the Painleve case: friction jams the joint) the function returns 1.
// k > 1 joints (coupled_closure_steps): the same system with 1 + k right-hand sides,
// N_i = N0_i + sum_j F_j N1_ij; the matrix C_ij = sigma_i^2 mu_i |N1_ij| bounds how much
// F_j moves joint i's law, and I - C having positive leading principal minors (checked
// pivot by pivot, status 1 else) makes the law a contraction with one solution; it is
// reached by sweeps of the one-joint closed form over the joints (Gauss-Seidel), and a
// final check of the law's residual returns 1 where the sweeps did not converge.
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cstddef>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "mbsc/driver/pipeline.hpp"
#include "mbsc/sym/multipliers.hpp"
#include "mbsc/sym/tidy.hpp"

namespace mbsc::driver {

namespace {

bool reads(const ir::Step& step, const GiNaC::symbol& F) {
  if (const auto* d = std::get_if<ir::Define>(&step)) return d->value.has(F);
  const auto& s = std::get<ir::Solve>(step);
  return std::any_of(s.A.begin(), s.A.end(), [&](const GiNaC::ex& e) { return e.has(F); }) ||
         std::any_of(s.B.begin(), s.B.end(), [&](const GiNaC::ex& e) { return e.has(F); });
}

bool defines(const ir::Step& step, const GiNaC::symbol& F) {
  const auto* d = std::get_if<ir::Define>(&step);
  return d && d->sym.is_equal(F);
}

/// The steps that define the friction force F of `fr`.
std::vector<ir::Step> closure_steps(const model::Model& m, const sym::Eom& eom, const model::Friction& fr,
                                    bool multipliers, const BaumgarteGains& gains) {
  auto fin = [&](const GiNaC::ex& e) { return sym::tidy(finalize(m, eom, e)); };
  const sym::MultiplierForm form = sym::multiplier_form(m);
  const unsigned nu = form.My.rows(), nc = form.A.rows();
  auto row = [&](const std::string& name) {
    for (std::size_t r = 0; r < m.constraints.size(); ++r)
      if (m.constraints[r].name == name) return static_cast<unsigned>(r);
    throw std::logic_error("friction: no row '" + name + "'");
  };
  const unsigned r1 = row(fr.row1), r2 = row(fr.row2);
  const GiNaC::exmap no_friction{{fr.force, 0}};
  ir::Solve s;
  s.label = fmt::format("friction of joint '{}': [My -A^T; A 0] [q1'; lambda] = [hy; c] at F = 0 and d/dF", fr.joint);
  s.n = static_cast<int>(nu + nc);
  s.k = 2;
  s.reported = false;
  for (unsigned i = 0; i < nu + nc; ++i) {
    for (unsigned j = 0; j < nu + nc; ++j) {
      GiNaC::ex e = 0;
      if (i < nu && j < nu) e = form.My(i, j);
      else if (i < nu) e = -form.A(j - nu, i);
      else if (j < nu) e = form.A(i - nu, j);
      s.A.push_back(fin(e));
    }
    if (i < nu) {
      const GiNaC::ex h = form.hy(i, 0);  // affine in F
      s.B.push_back(fin(h.subs(no_friction)));
      s.B.push_back(fin(h.diff(fr.force)));
    } else {
      // The multipliers form's lambda carries its Baumgarte terms (its own rhs uses them).
      const unsigned r = i - nu;
      GiNaC::ex c = -form.b(r, 0);
      if (multipliers) c -= 2 * gains.alpha * form.velocity(r, 0) + gains.beta * gains.beta * form.g(r, 0);
      s.B.push_back(fin(c));
      s.B.push_back(0);
    }
    for (int col = 0; col < 2; ++col) s.X.emplace_back(fmt::format("friction_kkt_{}_{}", i, col));
  }
  auto lambda = [&](unsigned r, int col) { return GiNaC::ex(s.X[(nu + r) * 2 + static_cast<unsigned>(col)]); };
  const GiNaC::ex w1 = fin(fr.weight1), w2 = fin(fr.weight2), mu = fin(fr.mu);
  const GiNaC::ex n00 = w1 * pow(lambda(r1, 0), 2) + w2 * pow(lambda(r2, 0), 2);
  const GiNaC::ex n11 = w1 * pow(lambda(r1, 1), 2) + w2 * pow(lambda(r2, 1), 2);
  const GiNaC::ex n01 = w1 * lambda(r1, 0) * lambda(r1, 1) + w2 * lambda(r2, 0) * lambda(r2, 1);
  // sigma first: at rest (sigma = 0) the law gives F = 0 whatever N, and the lead below
  // is 1, so a joint at rest never reports a jam.
  const GiNaC::symbol sigma("friction_sign"), root("friction_root");
  ir::Solve lead;
  lead.label = fmt::format("friction of joint '{}': 1 - mu^2 |N1|^2 > 0, else the joint jams (status 1)", fr.joint);
  lead.n = 1;
  lead.k = 1;
  lead.spd = true;
  lead.reported = false;
  lead.A.push_back(1 - sigma * sigma * mu * mu * n11);
  lead.B.push_back(1);
  const GiNaC::symbol inverse("friction_inverse_lead");
  lead.X.push_back(inverse);
  const GiNaC::ex b = -2 * mu * mu * n01, c = -mu * mu * n00;
  std::vector<ir::Step> steps{s};
  steps.push_back(ir::Define{sigma, GiNaC::csgn(fin(fr.slide_velocity)), false});
  steps.push_back(lead);
  // b^2 - 4 a c >= b^2 >= 0 since a > 0 and c <= 0.
  steps.push_back(ir::Define{root, GiNaC::sqrt(b * b - 4 * c / inverse), false});
  steps.push_back(ir::Define{fr.force, -(sigma * sigma * b + sigma * root) * inverse / 2, true});
  return steps;
}

/// The sweeps of the coupled closure: enough for a coupling rate of 0.4 per sweep to
/// reach the last bits; slower ones end in the residual check (status 1).
constexpr int kFrictionSweeps = 40;
/// The residual check's relative tolerance on each joint's law.
constexpr double kFrictionTolerance = 1e-9;

/// The steps that define the friction forces of k > 1 joints (the coupled law).
std::vector<ir::Step> coupled_closure_steps(const model::Model& m, const sym::Eom& eom, bool multipliers,
                                            const BaumgarteGains& gains) {
  auto fin = [&](const GiNaC::ex& e) { return sym::tidy(finalize(m, eom, e)); };
  const std::vector<model::Friction>& frs = m.frictions;
  const std::size_t k = frs.size();
  const sym::MultiplierForm form = sym::multiplier_form(m);
  const unsigned nu = form.My.rows(), nc = form.A.rows();
  const unsigned cols = static_cast<unsigned>(k) + 1;
  auto row = [&](const std::string& name) {
    for (std::size_t r = 0; r < m.constraints.size(); ++r)
      if (m.constraints[r].name == name) return static_cast<unsigned>(r);
    throw std::logic_error("friction: no row '" + name + "'");
  };
  GiNaC::exmap no_friction;
  for (const auto& fr : frs) no_friction[fr.force] = 0;
  std::vector<ir::Step> steps;
  // 1. The system over all speeds, columns: at F = 0, then d/dF_j.
  ir::Solve s;
  s.label = fmt::format("friction of {} joints: [My -A^T; A 0] [q1'; lambda] = [hy; c] at F = 0 and d/dF_j", k);
  s.n = static_cast<int>(nu + nc);
  s.k = static_cast<int>(cols);
  s.reported = false;
  for (unsigned i = 0; i < nu + nc; ++i) {
    for (unsigned j = 0; j < nu + nc; ++j) {
      GiNaC::ex e = 0;
      if (i < nu && j < nu) e = form.My(i, j);
      else if (i < nu) e = -form.A(j - nu, i);
      else if (j < nu) e = form.A(i - nu, j);
      s.A.push_back(fin(e));
    }
    if (i < nu) {
      const GiNaC::ex h = form.hy(i, 0);  // affine in every F
      s.B.push_back(fin(h.subs(no_friction)));
      for (const auto& fr : frs) s.B.push_back(fin(h.diff(fr.force)));
    } else {
      const unsigned r = i - nu;
      GiNaC::ex c = -form.b(r, 0);
      if (multipliers) c -= 2 * gains.alpha * form.velocity(r, 0) + gains.beta * gains.beta * form.g(r, 0);
      s.B.push_back(fin(c));
      for (std::size_t j = 0; j < k; ++j) s.B.push_back(0);
    }
    for (unsigned col = 0; col < cols; ++col) s.X.emplace_back(fmt::format("friction_kkt_{}_{}", i, col));
  }
  steps.push_back(s);
  // Joint i's normal reaction in column col: the multipliers of its two rows, with the
  // weights of their gradients' squared lengths in every dot product.
  struct Joint {
    GiNaC::ex w1, w2, mu;
    unsigned r1 = 0, r2 = 0;
    GiNaC::symbol sigma;
  };
  std::vector<Joint> J(k);
  for (std::size_t i = 0; i < k; ++i) {
    J[i].w1 = fin(frs[i].weight1), J[i].w2 = fin(frs[i].weight2), J[i].mu = fin(frs[i].mu);
    J[i].r1 = row(frs[i].row1), J[i].r2 = row(frs[i].row2);
    J[i].sigma = GiNaC::symbol(fmt::format("friction_sign_{}", i));
    steps.push_back(ir::Define{J[i].sigma, GiNaC::csgn(fin(frs[i].slide_velocity)), false});
  }
  using Pair = std::array<GiNaC::ex, 2>;
  auto lambda = [&](unsigned r, unsigned col) { return GiNaC::ex(s.X[(nu + r) * cols + col]); };
  auto N = [&](std::size_t i, unsigned col) { return Pair{lambda(J[i].r1, col), lambda(J[i].r2, col)}; };
  auto dot = [&](std::size_t i, const Pair& a, const Pair& b) { return J[i].w1 * a[0] * b[0] + J[i].w2 * a[1] * b[1]; };
  // A 1x1 positive definite block: status 1 unless a > 0. Its solution for the
  // right-hand sides (1, a) is (1/a, 1): the 1 (exact in floating point) multiplies the
  // forces, so that the check is kept with them.
  std::vector<GiNaC::symbol> ones;
  auto check = [&](const GiNaC::ex& a, const std::string& label, const std::string& stem) {
    ir::Solve c;
    c.label = label;
    c.n = 1;
    c.k = 2;
    c.spd = true;
    c.reported = false;
    c.A.push_back(a);
    c.B.push_back(1);
    c.B.push_back(a);
    c.X.emplace_back(stem + "_inverse");
    c.X.emplace_back(stem + "_one");
    steps.push_back(c);
    ones.push_back(c.X[1]);
    return c.X[0];
  };
  // 2. I - C, C_ij = sigma_i^2 mu_i |N1_ij|: Gaussian elimination without exchanges, each
  // pivot positive (the leading principal minors of a nonsingular M-matrix).
  std::vector<std::vector<GiNaC::ex>> M(k, std::vector<GiNaC::ex>(k));
  for (std::size_t i = 0; i < k; ++i)
    for (std::size_t j = 0; j < k; ++j) {
      const Pair n1 = N(i, static_cast<unsigned>(j) + 1);
      M[i][j] = (i == j ? 1 : 0) - J[i].sigma * J[i].sigma * J[i].mu * GiNaC::sqrt(dot(i, n1, n1));
    }
  for (std::size_t p = 0; p < k; ++p) {
    const GiNaC::symbol inv = check(M[p][p],
                                    fmt::format("friction: pivot {} of I - C > 0, else the joints may jam (status 1)", p),
                                    fmt::format("friction_pivot_{}", p));
    for (std::size_t i = p + 1; i < k; ++i) {
      const GiNaC::ex factor = M[i][p] * inv;
      for (std::size_t j = p + 1; j < k; ++j) {
        const GiNaC::symbol e(fmt::format("friction_minor_{}_{}_{}", p, i, j));
        steps.push_back(ir::Define{e, M[i][j] - factor * M[p][j], true});
        M[i][j] = e;
      }
    }
  }
  // 3. Each joint's own quadratic's lead 1 - sigma^2 mu^2 |N1_ii|^2 (positive when the
  // pivots are: 1 - C_ii > 0), then the sweeps from F = 0.
  std::vector<GiNaC::symbol> inverse_lead(k);
  for (std::size_t i = 0; i < k; ++i) {
    const Pair n1 = N(i, static_cast<unsigned>(i) + 1);
    inverse_lead[i] = check(1 - J[i].sigma * J[i].sigma * J[i].mu * J[i].mu * dot(i, n1, n1),
                            fmt::format("friction of joint '{}': 1 - mu^2 |N1|^2 > 0", frs[i].joint),
                            fmt::format("friction_lead_{}", i));
  }
  auto normal = [&](std::size_t i, const std::vector<GiNaC::ex>& F, bool own) {
    Pair n = N(i, 0);
    for (std::size_t j = 0; j < k; ++j) {
      if (j == i && !own) continue;
      const Pair n1 = N(i, static_cast<unsigned>(j) + 1);
      n[0] += F[j] * n1[0];
      n[1] += F[j] * n1[1];
    }
    return n;
  };
  std::vector<GiNaC::ex> F(k, GiNaC::ex(0));
  for (int sweep = 0; sweep < kFrictionSweeps; ++sweep) {
    for (std::size_t i = 0; i < k; ++i) {
      // F_i = -mu sigma |c + F_i N1_ii|, c the others' share: the one-joint closed form.
      const Pair c = normal(i, F, false), n1 = N(i, static_cast<unsigned>(i) + 1);
      const GiNaC::ex mu2 = J[i].mu * J[i].mu, sg = J[i].sigma;
      const GiNaC::ex b = -2 * mu2 * dot(i, c, n1), cc = -mu2 * dot(i, c, c);
      const GiNaC::symbol root(fmt::format("friction_root_{}_{}", sweep, i)), next(fmt::format("friction_{}_{}", sweep, i));
      steps.push_back(ir::Define{root, GiNaC::sqrt(b * b - 4 * cc / inverse_lead[i]), false});
      steps.push_back(ir::Define{next, -(sg * sg * b + sg * root) * inverse_lead[i] / 2, true});
      F[i] = next;
    }
  }
  // 4. The law's residual r_i = F_i + sigma_i mu_i |N_i(F)| against its scale
  // |F_i| + sigma_i^2 mu_i (|N0_i| + sum_j |N1_ij| |F_j|) (>= |r_i|).
  for (std::size_t i = 0; i < k; ++i) {
    const Pair n = normal(i, F, true), n0 = N(i, 0);
    const GiNaC::ex sg2 = J[i].sigma * J[i].sigma, mu = J[i].mu;
    const GiNaC::ex r = F[i] + J[i].sigma * mu * GiNaC::sqrt(dot(i, n, n));
    GiNaC::ex scale = GiNaC::abs(F[i]) + sg2 * mu * GiNaC::sqrt(dot(i, n0, n0));
    for (std::size_t j = 0; j < k; ++j) {
      const Pair n1 = N(i, static_cast<unsigned>(j) + 1);
      scale += sg2 * mu * GiNaC::sqrt(dot(i, n1, n1)) * GiNaC::abs(F[j]);
    }
    check(GiNaC::numeric(kFrictionTolerance * kFrictionTolerance) * scale * scale - r * r + GiNaC::numeric(1e-300),
          fmt::format("friction of joint '{}': the law's residual within tolerance, else no convergence (status 1)", frs[i].joint),
          fmt::format("friction_residual_{}", i));
  }
  GiNaC::ex one = 1;
  for (const auto& o : ones) one *= o;
  for (std::size_t i = 0; i < k; ++i) steps.push_back(ir::Define{frs[i].force, F[i] * one, true});
  return steps;
}

}  // namespace

void close_friction(const model::Model& m, const sym::Eom& eom, bool multipliers, const BaumgarteGains& gains,
                    std::vector<ir::FunctionSpec>& specs, std::optional<std::vector<ir::Step>>& closure) {
  if (m.frictions.empty()) return;
  auto reads_any = [&](const ir::Step& s) {
    return std::any_of(m.frictions.begin(), m.frictions.end(), [&](const model::Friction& fr) { return reads(s, fr.force); });
  };
  auto has_any = [&](const GiNaC::ex& e) {
    return std::any_of(m.frictions.begin(), m.frictions.end(), [&](const model::Friction& fr) { return e.has(fr.force); });
  };
  const model::Friction& first_friction = m.frictions.front();
  // `closure` is built for the first function that needs it.
  for (auto& f : specs) {
    if (!f.undefined_reason.empty()) continue;
    if (std::any_of(f.steps.begin(), f.steps.end(), [&](const ir::Step& s) { return defines(s, first_friction.force); }))
      continue;
    const auto first = std::find_if(f.steps.begin(), f.steps.end(), reads_any);
    const bool outputs = std::any_of(f.outputs.begin(), f.outputs.end(), has_any);
    if (first == f.steps.end() && !outputs) continue;
    if (f.third_arg == "zdot") {
      // Given accelerations, the friction and the inputs are one coupled problem (the
      // thesis's inverse dynamics of Ex 4.5): not generated.
      f.undefined_reason =
          m.frictions.size() == 1
              ? fmt::format("the friction of joint '{}' and the inputs are coupled; solve them together", first_friction.joint)
              : std::string("the friction of the joints and the inputs are coupled; solve them together");
      continue;
    }
    if (!closure)
      closure = m.frictions.size() == 1 ? closure_steps(m, eom, first_friction, multipliers, gains)
                                        : coupled_closure_steps(m, eom, multipliers, gains);
    f.steps.insert(first, closure->begin(), closure->end());
  }
}

}  // namespace mbsc::driver
