// SPDX-License-Identifier: GPL-2.0-or-later
#include "mbsc/sym/massless_check.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <tuple>

namespace mbsc::sym {

namespace {

/// Relative tolerance on M's eigenvalues: below this fraction of the largest one, a
/// motion carries no inertia.
constexpr double kNullRatio = 1e-10;

bool is_zero_at(const Probe& probe, const GiNaC::ex& e) { return probe.eval(e) == 0.0; }

/// The motion of every speed (index-aligned with m.speeds) when the independent speeds
/// move as z: the dependent rates of eom.top_down are affine in the independent ones,
/// so their value at z minus their value at 0 is the linear part C z.
std::vector<double> motion_of(const model::Model& m, const Eom& eom, const Probe& probe, const Eigen::VectorXd& z) {
  auto rates = [&](bool with_z) {
    Probe p = probe;
    std::vector<double> out(m.speeds.size(), 0.0);
    for (std::size_t j = 0; j < eom.independent.size(); ++j) {
      const double v = with_z ? z(static_cast<Eigen::Index>(j)) : 0.0;
      p.bind(m.speed_dots[static_cast<std::size_t>(eom.independent[j])], v);
      out[static_cast<std::size_t>(eom.independent[j])] = v;
    }
    for (const auto& d : eom.top_down) {
      const double v = p.eval(d.value);
      p.bind(d.sym, v);
      for (std::size_t s = 0; s < m.speeds.size(); ++s)
        if (m.speed_dots[s].is_equal(d.sym)) out[s] = v;
    }
    return out;
  };
  const auto a = rates(true), b = rates(false);
  std::vector<double> out(a.size());
  for (std::size_t s = 0; s < a.size(); ++s) out[s] = a[s] - b[s];
  return out;
}

/// ", with --freeze m2=0" for the frozen parameters e holds (the file alone looks right), or "".
std::string frozen_note(const model::Model& m, const Eom& eom, const GiNaC::ex& e) {
  std::string names;
  for (const auto& p : m.params) {
    const auto it = eom.options.frozen.find(p.name);
    if (it == eom.options.frozen.end() || m.structural.count(p.name) || !e.has(p.sym)) continue;
    names += fmt::format("{}{}={}", names.empty() ? "" : " ", p.name, it->second);
  }
  return names.empty() ? "" : ", with --freeze " + names;
}

/// A basis of the motions without inertia (the eigenvectors of the symmetric Mn whose
/// eigenvalues are at most kNullRatio times the largest), brought to reduced row
/// echelon form: the same basis on every run whatever the eigensolver returns, and
/// motions of decoupled parts of the model stay apart. Each column's largest entry is 1.
Eigen::MatrixXd null_motions(const Eigen::MatrixXd& Mn) {
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(0.5 * (Mn + Mn.transpose()));
  if (eig.info() != Eigen::Success) return {};
  const double scale = eig.eigenvalues().cwiseAbs().maxCoeff();
  Eigen::Index k = 0;
  while (k < eig.eigenvalues().size() && eig.eigenvalues()(k) <= kNullRatio * scale) ++k;  // ascending
  Eigen::MatrixXd R = eig.eigenvectors().leftCols(k).transpose();  // k x n, rows span the null space
  Eigen::Index row = 0;
  for (Eigen::Index col = 0; col < R.cols() && row < R.rows(); ++col) {
    Eigen::Index pivot = row;
    R.col(col).segment(row, R.rows() - row).cwiseAbs().maxCoeff(&pivot);
    pivot += row;
    if (std::abs(R(pivot, col)) <= 1e-9) continue;
    R.row(row).swap(R.row(pivot));
    R.row(row) /= R(row, col);
    for (Eigen::Index i = 0; i < R.rows(); ++i)
      if (i != row) R.row(i) -= R(i, col) * R.row(row);
    ++row;
  }
  for (Eigen::Index i = 0; i < R.rows(); ++i) {
    const double big = R.row(i).cwiseAbs().maxCoeff();
    if (big > 0) R.row(i) /= big;
    for (Eigen::Index j = 0; j < R.cols(); ++j)
      if (std::abs(R(i, j)) <= 1e-9) R(i, j) = 0.0;
  }
  return R.transpose();
}

/// A body's share of a motion without inertia: its speeds that move against its zero
/// mass (translation) and its angular speed against its zero inertia (rotation).
struct Share {
  std::vector<std::string> translation, rotation;  // speed names, in model order
};

/// Massless bodies that move together in motions without inertia: the motions, along
/// the independent speeds `direction`, move these bodies and nothing with inertia.
/// Bodies that share a motion are one group: one cause, one message.
struct Group {
  std::vector<std::string> direction;
  std::map<int, Share> bodies;  // node -> its share
  int motions = 0;
};

void add(std::vector<std::string>& v, const std::string& s) {
  if (std::find(v.begin(), v.end(), s) == v.end()) v.push_back(s);
}

std::string list(const std::vector<std::string>& v, const char* last = ", ") {
  std::string out;
  for (std::size_t i = 0; i < v.size(); ++i) out += (i == 0 ? "" : i + 1 == v.size() ? last : ", ") + v[i];
  return out;
}

/// Speed names of one node, sorted as the node declares them.
void in_model_order(const model::Model& m, const model::Node& node, std::vector<std::string>& names) {
  auto rank = [&](const std::string& name) {
    for (std::size_t k = 0; k < node.speeds.size(); ++k)
      if (m.speeds[static_cast<std::size_t>(node.speeds[k])].name == name) return k;
    return node.speeds.size();
  };
  std::stable_sort(names.begin(), names.end(), [&](const auto& a, const auto& b) { return rank(a) < rank(b); });
}

/// The groups of massless bodies that move in the null motions of Mn (the value of M
/// at `probe`). A null motion that moves no massless body has another cause (a
/// coordinate singularity, a custom leaf) and is not blamed on them.
std::vector<Group> inertia_free_groups(const model::Model& m, const Eom& eom, const Probe& probe, const Eigen::MatrixXd& Mn) {
  const Eigen::MatrixXd N = null_motions(Mn);
  std::vector<Group> groups;
  for (Eigen::Index k = 0; k < N.cols(); ++k) {
    const Eigen::VectorXd z = N.col(k);
    const auto motion = motion_of(m, eom, probe, z);
    double largest = 0.0;
    for (double v : motion) largest = std::max(largest, std::abs(v));
    Group g;
    g.motions = 1;
    for (std::size_t n = 0; n < m.nodes.size(); ++n) {
      const auto& node = m.nodes[n];
      if (!model::is_body(node.kind)) continue;
      const bool no_mass = is_zero_at(probe, node.mass);
      const bool no_inertia = model::is_rigid2d(node.kind) && is_zero_at(probe, node.inertia);
      if (!no_mass && !no_inertia) continue;
      Share share;
      for (std::size_t k2 = 0; k2 < node.speeds.size(); ++k2) {
        const auto s = static_cast<std::size_t>(node.speeds[k2]);
        if (!(std::abs(motion[s]) > 1e-9 * largest)) continue;
        const bool angular = model::is_rigid2d(node.kind) && k2 + 1 == node.speeds.size();
        if (angular && no_inertia) share.rotation.push_back(m.speeds[s].name);
        if (!angular && no_mass) share.translation.push_back(m.speeds[s].name);
      }
      if (!share.translation.empty() || !share.rotation.empty()) g.bodies[static_cast<int>(n)] = share;
    }
    if (g.bodies.empty()) continue;
    for (Eigen::Index j = 0; j < z.size(); ++j)
      if (z(j) != 0.0) add(g.direction, m.speeds[static_cast<std::size_t>(eom.independent[static_cast<std::size_t>(j)])].name);
    // Merge with every group that shares a body.
    for (auto it = groups.begin(); it != groups.end();) {
      bool shared = false;
      for (const auto& [n, share] : it->bodies) shared = shared || g.bodies.count(n);
      if (!shared) {
        ++it;
        continue;
      }
      for (const auto& [n, share] : it->bodies) {
        Share& into = g.bodies[n];
        const auto& node = m.nodes[static_cast<std::size_t>(n)];
        for (const auto& s : share.translation) add(into.translation, s);
        for (const auto& s : share.rotation) add(into.rotation, s);
        in_model_order(m, node, into.translation);
      }
      std::vector<std::string> direction = it->direction;
      for (const auto& s : g.direction) add(direction, s);
      g.direction = direction;
      g.motions += it->motions;
      it = groups.erase(it);
    }
    groups.push_back(g);
  }
  return groups;
}

/// Where a group's message goes: at the zero mass or inertia statement the user most
/// likely just changed, i.e. one that a --freeze made zero, else the one written last.
struct Site {
  int node = -1;
  SourcePos pos;
};

SourcePos inertia_pos(const model::Node& node) { return node.inertia_pos.line != 0 ? node.inertia_pos : node.pos; }

Site site_of(const model::Model& m, const Eom& eom, const Group& g) {
  Site best;
  std::tuple<bool, int, int> best_key{false, -1, -1};
  for (const auto& body : g.bodies) {
    const int n = body.first;  // (a lambda cannot capture a structured binding in C++17)
    const auto& share = body.second;
    const auto& node = m.nodes[static_cast<std::size_t>(n)];
    auto consider = [&](const GiNaC::ex& value, const SourcePos& pos) {
      const std::tuple<bool, int, int> key{!frozen_note(m, eom, value).empty(), pos.line, pos.col};
      if (best.node < 0 || key >= best_key) {
        best = Site{n, pos};
        best_key = key;
      }
    };
    if (!share.translation.empty()) consider(node.mass, node.mass_pos);
    if (!share.rotation.empty()) consider(node.inertia, inertia_pos(node));
  }
  return best;
}

/// The bodies of a group, the site's first, then in model order.
std::vector<int> bodies_in_order(const Group& g, const Site& site) {
  std::vector<int> out{site.node};
  for (const auto& [n, share] : g.bodies)
    if (n != site.node) out.push_back(n);
  return out;
}

/// "rod (inertia 0)" or "bob (mass 0, with --freeze m=0)".
std::string zero_note(const model::Model& m, const Eom& eom, int n, const Share& share) {
  const auto& node = m.nodes[static_cast<std::size_t>(n)];
  std::vector<std::string> parts;
  if (!share.translation.empty()) parts.push_back("mass 0" + frozen_note(m, eom, node.mass));
  if (!share.rotation.empty()) parts.push_back("inertia 0" + frozen_note(m, eom, node.inertia));
  return list(parts);
}

/// "moves bob (bob.u, bob.v)", "turns rod (rod.w)", "moves and turns cable (...)";
/// "move", "turn" after several motions.
std::string what_moves(const model::Model& m, int n, const Share& share, bool one) {
  const std::string& name = m.nodes[static_cast<std::size_t>(n)].name;
  std::vector<std::string> speeds = share.translation;
  for (const auto& s : share.rotation) add(speeds, s);
  const std::string verb = share.rotation.empty()      ? (one ? "moves" : "move")
                           : share.translation.empty() ? (one ? "turns" : "turn")
                                                       : (one ? "moves and turns" : "move and turn");
  return fmt::format("{} {} ({})", verb, name, list(speeds));
}

/// "give 'bob' a mass or 'rod' an inertia": one motion needs inertia from any one of
/// them; several motions may need all of it.
std::string advice(const model::Model& m, const Group& g, const std::vector<int>& order) {
  std::vector<std::string> items;
  const bool one = g.motions == 1;
  for (int n : order) {
    const Share& share = g.bodies.at(n);
    const char* what = share.rotation.empty()      ? "a mass"
                       : share.translation.empty() ? "an inertia"
                       : one                       ? "a mass or an inertia"
                                                   : "a mass and an inertia";
    items.push_back(fmt::format("'{}' {}", m.nodes[static_cast<std::size_t>(n)].name, what));
  }
  return "give " + list(items, one ? " or " : " and ");
}

void report_group(const model::Model& m, const Eom& eom, const Group& g, Diagnostics& diags) {
  const Site site = site_of(m, eom, g);
  const auto order = bodies_in_order(g, site);
  const bool one = g.motions == 1;
  const std::string along = fmt::format("{} along {}", one ? "the motion" : "the motions", list(g.direction));
  const char* that = one ? "that motion" : "those motions";
  const char* s = one ? "s" : "";
  if (order.size() == 1) {
    // One body: its own words.
    const auto& node = m.nodes[static_cast<std::size_t>(site.node)];
    const Share& share = g.bodies.at(site.node);
    const std::string zero = zero_note(m, eom, site.node, share);
    if (share.rotation.empty()) {
      diags.error(site.pos, fmt::format("body '{}' is massless ({}) and the reduced mass matrix is singular: {} move{} it "
                                        "({}) and nothing with inertia; give it a mass or constrain {}",
                                        node.name, zero, along, s, list(share.translation), that));
    } else if (share.translation.empty()) {
      diags.error(site.pos, fmt::format("body '{}' has no rotational inertia ({}) and the reduced mass matrix is singular: "
                                        "{} turn{} it ({}) and move{} nothing with inertia; give it an inertia or constrain {}",
                                        node.name, zero, along, s, list(share.rotation), s,
                                        one ? "that rotation" : "those rotations"));
    } else {
      diags.error(site.pos, fmt::format("body '{}' has neither mass nor rotational inertia ({}) and the reduced mass matrix "
                                        "is singular: {} {} and nothing with inertia; {}, or constrain {}",
                                        node.name, zero, along, what_moves(m, site.node, share, one),
                                        advice(m, g, order), that));
    }
    return;
  }
  std::vector<std::string> named, moved;
  for (int n : order) {
    named.push_back(fmt::format("'{}' ({})", m.nodes[static_cast<std::size_t>(n)].name, zero_note(m, eom, n, g.bodies.at(n))));
    moved.push_back(what_moves(m, n, g.bodies.at(n), one));
  }
  diags.error(site.pos, fmt::format("bodies {} carry no inertia and the reduced mass matrix is singular: {} {} and nothing "
                                    "with inertia; {}, or constrain {}",
                                    list(named, " and "), along, list(moved, " and "), advice(m, g, order), that));
}

/// The values of the opaque symbols (numeric solves, named e_/r_ variables) at `at`, as
/// the generated code computes them there; false where a solve is singular.
bool bind_pre_steps(const Eom& eom, Probe& at) {
  for (const auto& step : eom.pre_steps) {
    if (const auto* d = std::get_if<ir::Define>(&step)) {
      at.bind(d->sym, at.eval(d->value));
      continue;
    }
    const auto& s = std::get<ir::Solve>(step);
    Eigen::MatrixXd A(s.n, s.n), B(s.n, s.k);
    for (int i = 0; i < s.n; ++i) {
      for (int j = 0; j < s.n; ++j) A(i, j) = at.eval(s.A[static_cast<std::size_t>(i * s.n + j)]);
      for (int j = 0; j < s.k; ++j) B(i, j) = at.eval(s.B[static_cast<std::size_t>(i * s.k + j)]);
    }
    if (!A.allFinite() || !B.allFinite()) return false;
    Eigen::FullPivLU<Eigen::MatrixXd> lu(A);
    if (!lu.isInvertible()) return false;
    const Eigen::MatrixXd X = lu.solve(B);
    for (int i = 0; i < s.n; ++i)
      for (int j = 0; j < s.k; ++j) at.bind(s.X[static_cast<std::size_t>(i * s.k + j)], X(i, j));
  }
  return true;
}

}  // namespace

std::vector<std::string> massless_bodies(const model::Model& m, const Probe& probe) {
  std::vector<std::string> out;
  for (const auto& node : m.nodes) {
    if (!model::is_body(node.kind)) continue;
    const bool no_mass = is_zero_at(probe, node.mass);
    const bool no_inertia = model::is_rigid2d(node.kind) && is_zero_at(probe, node.inertia);
    if (!no_mass && !no_inertia) continue;
    out.push_back(fmt::format("{} ({}{}{})", node.name, no_mass ? "mass 0" : "", no_mass && no_inertia ? ", " : "",
                              no_inertia ? "inertia 0" : ""));
  }
  return out;
}

bool report_massless_directions(const model::Model& m, const Eom& eom, const Probe& probe, const Eigen::MatrixXd& Mn,
                                Diagnostics& diags) {
  if (massless_bodies(m, probe).empty() || !Mn.allFinite()) return false;
  const auto groups = inertia_free_groups(m, eom, probe, Mn);
  for (const auto& g : groups) report_group(m, eom, g, diags);
  return !groups.empty();
}

MassAtReference check_massless_at_reference(const model::Model& m, const Eom& eom, const Probe& reference,
                                            Diagnostics& diags) {
  if (massless_bodies(m, reference).empty()) return MassAtReference::NotChecked;
  Probe at = reference;
  const int nd = eom.ndof();
  if (nd == 0 || !bind_pre_steps(eom, at)) return MassAtReference::NotEvaluated;
  Eigen::MatrixXd Mr(nd, nd);
  for (int i = 0; i < nd; ++i)
    for (int j = 0; j < nd; ++j) Mr(i, j) = at.eval(eom.M(static_cast<unsigned>(i), static_cast<unsigned>(j)));
  if (!Mr.allFinite()) return MassAtReference::NotEvaluated;
  if (null_motions(Mr).cols() == 0) return MassAtReference::PositiveDefinite;
  const auto groups = inertia_free_groups(m, eom, at, Mr);
  if (groups.empty()) return MassAtReference::SingularOtherwise;
  bool frozen = false;
  for (const auto& p : m.params) frozen = frozen || (eom.options.frozen.count(p.name) && !m.structural.count(p.name));
  for (const auto& g : groups) {
    const Site site = site_of(m, eom, g);
    const auto order = bodies_in_order(g, site);
    std::vector<std::string> named;
    for (int n : order) {
      const Share& share = g.bodies.at(n);
      std::vector<std::string> speeds = share.translation;
      for (const auto& s : share.rotation) add(speeds, s);
      named.push_back(fmt::format("'{}' ({}: {})", m.nodes[static_cast<std::size_t>(n)].name, zero_note(m, eom, n, share),
                                  list(speeds)));
    }
    diags.warning(site.pos, fmt::format("the reduced mass matrix is positive definite at a generic configuration but singular "
                                        "at the reference configuration (parameter defaults{}, coordinates, speeds and t at "
                                        "0): there {} along {} move{} only {} without inertia, {}, so the generated "
                                        "rhs fails at that state; {}, or start the model elsewhere",
                                        frozen ? " and --freeze values" : "", g.motions == 1 ? "the motion" : "the motions",
                                        list(g.direction), g.motions == 1 ? "s" : "",
                                        order.size() == 1 ? "a body" : "bodies", list(named, " and "), advice(m, g, order)));
  }
  return MassAtReference::SingularMassless;
}

}  // namespace mbsc::sym
