// SPDX-License-Identifier: GPL-2.0-or-later
// Joints with coordinates (relative, joint coordinates) against independent formulations:
//  - a 3R arm, a five-rod chain and an R-P arm (revolute and prismatic) written with
//    joint coordinates agree with their twins in absolute coordinates: at random joint
//    states the minimal build rebuilds the bodies' poses and speeds, and the bodies'
//    accelerations of the absolute twin at that state equal the joint model's (full and
//    minimal state), the joint accelerations mapped through theta_k = q_1 + ... + q_k;
//  - a four-bar whose loop is closed by a joint without a coordinate keeps the three joint
//    angles and one rate, and agrees with the four-bar of library joints;
//  - the multipliers form of the joint-coordinate arm agrees with the complement form;
//  - the minimal state is exactly (joint coordinates, joint rates) and the independent
//    speeds are the joint rates;
//  - the textbook two-link arm: mass_matrix and forcing are the closed-form M(q) and
//    h = tau - C(q, q') q' - G(q) of robotics texts.
#include <catch2/catch.hpp>
#include <Eigen/Dense>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "arm_joint_min/arm_joint_min.hpp"
#include "arm_joint_mult/arm_joint_mult.hpp"
#include "chain5_absolute/chain5_absolute.hpp"
#include "chain5_joint/chain5_joint.hpp"
#include "chain5_joint_min/chain5_joint_min.hpp"
#include "four_bar_angles_min/four_bar_angles_min.hpp"
#include "four_bar_joint_angles/four_bar_joint_angles.hpp"
#include "four_bar_joints/four_bar_joints.hpp"
#include "polar_arm_absolute/polar_arm_absolute.hpp"
#include "polar_arm_joint/polar_arm_joint.hpp"
#include "polar_arm_joint_min/polar_arm_joint_min.hpp"
#include "test_support.hpp"
#include "three_r_arm/three_r_arm.hpp"
#include "three_r_arm_joint/three_r_arm_joint.hpp"
#include "two_link_min/two_link_min.hpp"

using mbsc_test::index_of;

namespace {

using Fn = int (*)(double, const double*, const double*, const double*, double*);

/// One generated model, through its table.
struct View {
  Fn rhs;
  const char* const* names;
  int nx;
  const double* params;
};
#define MBSC_VIEW(NS) \
  View { NS::rhs, NS::kStateNames, NS::kNx, NS::kParamDefaults }

/// The joint model in both states and its absolute twin.
struct Twins {
  View joint_min, joint_full, absolute;
  Fn full_state;                     // of joint_min
  const char* const* full_names;     // joint_min's kFullStateNames
  int nx_full;
};

double inf_norm(const std::vector<double>& v) {
  double m = 0.0;
  for (double e : v) m = std::max(m, std::abs(e));
  return m;
}

struct Rates {
  std::vector<double> joint_min, joint_full, absolute;
};

/// At the joint state x_min: every build's rhs, after checking that they agree.
Rates compare_at(const Twins& t, const std::vector<double>& x_min) {
  std::vector<double> xf(static_cast<std::size_t>(t.nx_full));
  REQUIRE(t.full_state(0.0, x_min.data(), nullptr, t.joint_min.params, xf.data()) == 0);
  REQUIRE(t.nx_full == t.joint_full.nx);
  // The full joint state in the full build's order, and the twin's state by name.
  std::vector<double> x_joint(static_cast<std::size_t>(t.joint_full.nx)), x_abs(static_cast<std::size_t>(t.absolute.nx));
  for (int i = 0; i < t.nx_full; ++i)
    x_joint[static_cast<std::size_t>(index_of(t.joint_full.names, t.joint_full.nx, t.full_names[i]))] =
        xf[static_cast<std::size_t>(i)];
  for (int i = 0; i < t.absolute.nx; ++i)
    x_abs[static_cast<std::size_t>(i)] =
        x_joint[static_cast<std::size_t>(index_of(t.joint_full.names, t.joint_full.nx, t.absolute.names[i]))];
  Rates r{std::vector<double>(x_min.size()), std::vector<double>(x_joint.size()), std::vector<double>(x_abs.size())};
  REQUIRE(t.joint_min.rhs(0.0, x_min.data(), nullptr, t.joint_min.params, r.joint_min.data()) == 0);
  REQUIRE(t.joint_full.rhs(0.0, x_joint.data(), nullptr, t.joint_full.params, r.joint_full.data()) == 0);
  REQUIRE(t.absolute.rhs(0.0, x_abs.data(), nullptr, t.absolute.params, r.absolute.data()) == 0);
  const double scale = std::max(1.0, inf_norm(r.absolute));
  // Minimal and full joint builds: the same joint rates and accelerations.
  for (int i = 0; i < t.joint_min.nx; ++i) {
    INFO(t.joint_min.names[i]);
    CHECK(std::abs(r.joint_min[static_cast<std::size_t>(i)] -
                   r.joint_full[static_cast<std::size_t>(index_of(t.joint_full.names, t.joint_full.nx, t.joint_min.names[i]))]) <
          1e-10 * scale);
  }
  // The bodies: the twin's accelerations equal the joint model's.
  for (int i = 0; i < t.absolute.nx; ++i) {
    INFO(t.absolute.names[i]);
    CHECK(std::abs(r.absolute[static_cast<std::size_t>(i)] -
                   r.joint_full[static_cast<std::size_t>(index_of(t.joint_full.names, t.joint_full.nx, t.absolute.names[i]))]) <
          1e-10 * scale);
  }
  return r;
}

/// Random joint states: angles in (-pi, pi), slides in (0.2, 1.5), rates in (-3, 3).
std::vector<double> random_state(std::mt19937& rng, const char* const* names, int nx, int nq,
                                 const std::vector<std::string>& slides = {}) {
  std::uniform_real_distribution<double> angle(-3.1, 3.1), slide(0.2, 1.5), rate(-3.0, 3.0);
  std::vector<double> x(static_cast<std::size_t>(nx));
  for (int i = 0; i < nx; ++i) {
    const bool is_slide = std::find(slides.begin(), slides.end(), std::string(names[i])) != slides.end();
    x[static_cast<std::size_t>(i)] = i >= nq ? rate(rng) : is_slide ? slide(rng) : angle(rng);
  }
  return x;
}

/// The absolute angle of body `b` is the sum of the joint angles up to it.
void check_angle_sums(const Twins& t, const std::vector<double>& x_min, const Rates& r, const std::vector<std::string>& bodies,
                      const std::vector<std::string>& joints, const std::vector<std::string>& rates) {
  double theta = 0.0, w = 0.0, wdot = 0.0;
  for (std::size_t k = 0; k < bodies.size(); ++k) {
    const std::size_t q = static_cast<std::size_t>(index_of(t.joint_min.names, t.joint_min.nx, joints[k]));
    const std::size_t qd = static_cast<std::size_t>(index_of(t.joint_min.names, t.joint_min.nx, rates[k]));
    theta += x_min[q];
    w += x_min[qd];
    wdot += r.joint_min[qd];
    std::vector<double> xf(static_cast<std::size_t>(t.nx_full));
    REQUIRE(t.full_state(0.0, x_min.data(), nullptr, t.joint_min.params, xf.data()) == 0);
    CHECK(std::abs(xf[static_cast<std::size_t>(index_of(t.full_names, t.nx_full, bodies[k] + ".theta"))] - theta) < 1e-12);
    CHECK(std::abs(xf[static_cast<std::size_t>(index_of(t.full_names, t.nx_full, bodies[k] + ".w"))] - w) < 1e-12);
    const double abs_wdot = r.absolute[static_cast<std::size_t>(index_of(t.absolute.names, t.absolute.nx, bodies[k] + ".w"))];
    CHECK(std::abs(abs_wdot - wdot) < 1e-10 * std::max(1.0, inf_norm(r.absolute)));
  }
}

}  // namespace

TEST_CASE("joint coordinates: the 3R arm in joint angles agrees with the absolute 3R arm", "[numeric][relative]") {
  namespace M = mbsc_gen::arm_joint_min;
  namespace J = mbsc_gen::three_r_arm_joint;
  namespace A = mbsc_gen::three_r_arm;
  // The robot's state: joint angles and joint rates, the joint rates independent.
  REQUIRE(M::kNx == 6);
  const std::vector<std::string> state = {"q1", "q2", "q3", "q1_dot", "q2_dot", "q3_dot"};
  for (int i = 0; i < M::kNx; ++i) CHECK(state[static_cast<std::size_t>(i)] == M::kStateNames[i]);
  REQUIRE(J::kNdof == 3);
  for (int i = 0; i < 3; ++i) CHECK(state[static_cast<std::size_t>(3 + i)] == J::kDofNames[i]);
  const Twins t{MBSC_VIEW(M), MBSC_VIEW(J), MBSC_VIEW(A), M::full_state, M::kFullStateNames, M::kNxFull};
  // Torques on: the same parameter values in all three (same names, same defaults).
  std::vector<double> pm(M::kParamDefaults, M::kParamDefaults + M::kNp), pj(J::kParamDefaults, J::kParamDefaults + J::kNp),
      pa(A::kParamDefaults, A::kParamDefaults + A::kNp);
  const double tau[] = {1.5, -0.7, 0.4};
  for (int k = 0; k < 3; ++k) {
    const std::string name = "tau" + std::to_string(k + 1);
    pm[static_cast<std::size_t>(index_of(M::kParamNames, M::kNp, name))] = tau[k];
    pj[static_cast<std::size_t>(index_of(J::kParamNames, J::kNp, name))] = tau[k];
    pa[static_cast<std::size_t>(index_of(A::kParamNames, A::kNp, name))] = tau[k];
  }
  Twins torqued = t;
  torqued.joint_min.params = pm.data();
  torqued.joint_full.params = pj.data();
  torqued.absolute.params = pa.data();
  std::mt19937 rng(311);
  for (int k = 0; k < 40; ++k) {
    const auto x = random_state(rng, M::kStateNames, M::kNx, M::kNq);
    const Twins& use = k % 2 ? torqued : t;
    const Rates r = compare_at(use, x);
    check_angle_sums(use, x, r, {"link1", "link2", "link3"}, {"q1", "q2", "q3"}, {"q1_dot", "q2_dot", "q3_dot"});
  }
}

TEST_CASE("joint coordinates: a five-rod chain in joint angles agrees with its absolute twin", "[numeric][relative]") {
  namespace M = mbsc_gen::chain5_joint_min;
  namespace J = mbsc_gen::chain5_joint;
  namespace A = mbsc_gen::chain5_absolute;
  REQUIRE(M::kNx == 10);  // written from the free end up, still only the joint angles and rates
  for (int i = 1; i <= 5; ++i) {
    CHECK(index_of(M::kStateNames, M::kNx, "q" + std::to_string(i)) < 5);
    CHECK(index_of(M::kStateNames, M::kNx, "w" + std::to_string(i)) >= 5);
  }
  const Twins t{MBSC_VIEW(M), MBSC_VIEW(J), MBSC_VIEW(A), M::full_state, M::kFullStateNames, M::kNxFull};
  std::mt19937 rng(55);
  for (int k = 0; k < 40; ++k) {
    const auto x = random_state(rng, M::kStateNames, M::kNx, M::kNq);
    const Rates r = compare_at(t, x);
    check_angle_sums(t, x, r, {"r1", "r2", "r3", "r4", "r5"}, {"q1", "q2", "q3", "q4", "q5"}, {"w1", "w2", "w3", "w4", "w5"});
  }
}

TEST_CASE("joint coordinates: an R-P arm (revolute and prismatic) agrees with its absolute twin", "[numeric][relative]") {
  namespace M = mbsc_gen::polar_arm_joint_min;
  namespace J = mbsc_gen::polar_arm_joint;
  namespace A = mbsc_gen::polar_arm_absolute;
  REQUIRE(M::kNx == 4);
  CHECK(std::string("q") == M::kStateNames[0]);
  CHECK(std::string("s") == M::kStateNames[1]);
  const Twins t{MBSC_VIEW(M), MBSC_VIEW(J), MBSC_VIEW(A), M::full_state, M::kFullStateNames, M::kNxFull};
  std::mt19937 rng(7);
  const double n = std::sqrt(5.0);  // the rail's direction (2, 1) in the boom's frame, made a unit vector
  for (int k = 0; k < 40; ++k) {
    const auto x = random_state(rng, M::kStateNames, M::kNx, M::kNq, {"s"});
    const Rates r = compare_at(t, x);
    // The slide is the distance of the slider's point C from the rail's point along the rail.
    std::vector<double> xf(static_cast<std::size_t>(M::kNxFull));
    REQUIRE(M::full_state(0.0, x.data(), nullptr, M::kParamDefaults, xf.data()) == 0);
    const auto at = [&](const char* name) { return xf[static_cast<std::size_t>(index_of(M::kFullStateNames, M::kNxFull, name))]; };
    const double q = x[0], s = x[1], lb = 1.2, th = at("slider.theta");
    CHECK(std::abs(th - q) < 1e-12);  // no angle option: the slider keeps the boom's angle
    const double rail_x = at("boom.x") + std::cos(q) * (-lb / 2) - std::sin(q) * 0.1;
    const double rail_y = at("boom.y") + std::sin(q) * (-lb / 2) + std::cos(q) * 0.1;
    const double cx = at("slider.x") + std::cos(th) * 0.05 - std::sin(th) * (-0.02);
    const double cy = at("slider.y") + std::sin(th) * 0.05 + std::cos(th) * (-0.02);
    CHECK(std::abs(cx - rail_x - s * (2 * std::cos(q) - std::sin(q)) / n) < 1e-12);
    CHECK(std::abs(cy - rail_y - s * (2 * std::sin(q) + std::cos(q)) / n) < 1e-12);
    (void)r;
  }
}

TEST_CASE("joint coordinates: the multipliers form of the joint-angle arm agrees with the complement form",
          "[numeric][relative]") {
  namespace M = mbsc_gen::arm_joint_min;
  namespace J = mbsc_gen::three_r_arm_joint;
  namespace L = mbsc_gen::arm_joint_mult;
  REQUIRE(L::kNx == J::kNx);
  std::mt19937 rng(99);
  for (int k = 0; k < 20; ++k) {
    const auto x = random_state(rng, M::kStateNames, M::kNx, M::kNq);
    std::vector<double> xf(M::kNxFull), xj(J::kNx), dj(J::kNx), dl(L::kNx);
    REQUIRE(M::full_state(0.0, x.data(), nullptr, M::kParamDefaults, xf.data()) == 0);
    for (int i = 0; i < M::kNxFull; ++i)
      xj[static_cast<std::size_t>(index_of(J::kStateNames, J::kNx, M::kFullStateNames[i]))] = xf[static_cast<std::size_t>(i)];
    REQUIRE(J::rhs(0.0, xj.data(), nullptr, J::kParamDefaults, dj.data()) == 0);
    REQUIRE(L::rhs(0.0, xj.data(), nullptr, L::kParamDefaults, dl.data()) == 0);  // same layout, same names
    for (int i = 0; i < J::kNx; ++i) {
      INFO(J::kStateNames[i]);
      CHECK(std::string(J::kStateNames[i]) == L::kStateNames[i]);
      CHECK(std::abs(dj[static_cast<std::size_t>(i)] - dl[static_cast<std::size_t>(i)]) < 1e-9 * std::max(1.0, inf_norm(dj)));
    }
  }
}

TEST_CASE("joint coordinates: a four-bar in joint angles closed by a plain joint agrees with the four-bar of joints",
          "[numeric][relative]") {
  namespace M = mbsc_gen::four_bar_angles_min;
  namespace J = mbsc_gen::four_bar_joint_angles;
  namespace A = mbsc_gen::four_bar_joints;
  // The loop closure is no explicit row: the three joint angles stay, with one rate.
  REQUIRE(M::kNx == 4);
  CHECK(std::string("q1") == M::kStateNames[0]);
  CHECK(std::string("q2") == M::kStateNames[1]);
  CHECK(std::string("q3") == M::kStateNames[2]);
  CHECK(std::string("q1_dot") == M::kStateNames[3]);
  const Twins t{MBSC_VIEW(M), MBSC_VIEW(J), MBSC_VIEW(A), M::full_state, M::kFullStateNames, M::kNxFull};
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> crank(0.0, 6.28), rate(-3.0, 3.0);
  // Off the loop's closure, the joints' own rows hold exactly (they are what places the
  // bodies) and only the closing joint's rows do not, though it is written first.
  for (int k = 0; k < 10; ++k) {
    const std::vector<double> x = {crank(rng), crank(rng), crank(rng), rate(rng)};
    std::vector<double> xf(M::kNxFull), xj(J::kNx), g(J::kNposc);
    REQUIRE(M::full_state(0.0, x.data(), nullptr, M::kParamDefaults, xf.data()) == 0);
    for (int i = 0; i < M::kNxFull; ++i)
      xj[static_cast<std::size_t>(index_of(J::kStateNames, J::kNx, M::kFullStateNames[i]))] = xf[static_cast<std::size_t>(i)];
    REQUIRE(J::position_constraints(0.0, xj.data(), nullptr, J::kParamDefaults, g.data()) == 0);
    double closure = 0.0;
    for (int i = 0; i < J::kNposc; ++i) {
      const std::string row = J::kPositionConstraintNames[i];
      INFO(row);
      if (row.rfind("rockerpin.", 0) == 0) closure = std::max(closure, std::abs(g[static_cast<std::size_t>(i)]));
      else CHECK(std::abs(g[static_cast<std::size_t>(i)]) < 1e-14);
    }
    CHECK(closure > 1e-6);
  }
  std::vector<double> x = {1.2, 0.4 - 1.2, 1.9, 0.0}, r(M::kNposc), rp(M::kNposc), rm(M::kNposc);
  for (int k = 0; k < 20; ++k) {
    // Close the loop over q2, q3 for a crank angle near the last one (Newton, differences).
    x[0] += 0.3 * (crank(rng) - 3.14) / 3.14;
    for (int it = 0; it < 50; ++it) {
      REQUIRE(M::position_constraints(0.0, x.data(), nullptr, M::kParamDefaults, r.data()) == 0);
      if (inf_norm(r) < 1e-14) break;
      Eigen::MatrixXd Jq(M::kNposc, 2);
      for (int c = 0; c < 2; ++c) {
        std::vector<double> xp = x, xm = x;
        xp[static_cast<std::size_t>(c + 1)] += 1e-7;
        xm[static_cast<std::size_t>(c + 1)] -= 1e-7;
        M::position_constraints(0.0, xp.data(), nullptr, M::kParamDefaults, rp.data());
        M::position_constraints(0.0, xm.data(), nullptr, M::kParamDefaults, rm.data());
        for (int i = 0; i < M::kNposc; ++i)
          Jq(i, c) = (rp[static_cast<std::size_t>(i)] - rm[static_cast<std::size_t>(i)]) / 2e-7;
      }
      const Eigen::VectorXd dx = Jq.colPivHouseholderQr().solve(-Eigen::Map<Eigen::VectorXd>(r.data(), M::kNposc));
      x[1] += dx(0);
      x[2] += dx(1);
    }
    REQUIRE(inf_norm(r) < 1e-13);
    x[3] = rate(rng);
    compare_at(t, x);
  }
}

TEST_CASE("joint coordinates: the two-link arm's M(q) and h(q, q') are the textbook closed forms", "[numeric][relative]") {
  namespace M = mbsc_gen::two_link_min;
  REQUIRE(M::kNx == 4);
  REQUIRE(M::kNdof == 2);
  std::vector<double> p(M::kParamDefaults, M::kParamDefaults + M::kNp);
  const auto param = [&](const char* name) -> double& { return p[static_cast<std::size_t>(index_of(M::kParamNames, M::kNp, name))]; };
  std::mt19937 rng(2024);
  std::uniform_real_distribution<double> angle(-3.1, 3.1), rate(-4.0, 4.0), torque(-2.0, 2.0), positive(0.2, 2.0);
  for (int k = 0; k < 50; ++k) {
    // Random links too: every parameter enters the closed forms.
    for (const char* name : {"m1", "m2", "l1", "c1", "c2", "I1", "I2"}) param(name) = positive(rng);
    param("tau1") = torque(rng);
    param("tau2") = torque(rng);
    const double m1 = param("m1"), m2 = param("m2"), l1 = param("l1"), c1 = param("c1"), c2 = param("c2"), I1 = param("I1"),
                 I2 = param("I2"), g = param("g"), tau1 = param("tau1"), tau2 = param("tau2");
    const double q1 = angle(rng), q2 = angle(rng), qd1 = rate(rng), qd2 = rate(rng);
    const std::vector<double> x = {q1, q2, qd1, qd2};
    double Mq[4], h[2];
    REQUIRE(M::mass_matrix(0.0, x.data(), nullptr, p.data(), Mq) == 0);
    REQUIRE(M::forcing(0.0, x.data(), nullptr, p.data(), h) == 0);
    const double M11 = I1 + I2 + m1 * c1 * c1 + m2 * (l1 * l1 + c2 * c2 + 2 * l1 * c2 * std::cos(q2));
    const double M12 = I2 + m2 * (c2 * c2 + l1 * c2 * std::cos(q2));
    const double M22 = I2 + m2 * c2 * c2;
    const double hh = m2 * l1 * c2 * std::sin(q2);
    const double C1 = -hh * (2 * qd1 * qd2 + qd2 * qd2), C2 = hh * qd1 * qd1;  // C(q, q') q'
    const double G1 = (m1 * c1 + m2 * l1) * g * std::cos(q1) + m2 * c2 * g * std::cos(q1 + q2);
    const double G2 = m2 * c2 * g * std::cos(q1 + q2);
    const double scale = std::max({1.0, std::abs(M11), std::abs(G1), std::abs(C1)});
    CHECK(std::abs(Mq[0] - M11) < 1e-12 * scale);
    CHECK(std::abs(Mq[1] - M12) < 1e-12 * scale);
    CHECK(std::abs(Mq[2] - M12) < 1e-12 * scale);
    CHECK(std::abs(Mq[3] - M22) < 1e-12 * scale);
    CHECK(std::abs(h[0] - (tau1 - C1 - G1)) < 1e-12 * scale);
    CHECK(std::abs(h[1] - (tau2 - C2 - G2)) < 1e-12 * scale);
    // rhs is (q', M^-1 h).
    double xd[4];
    REQUIRE(M::rhs(0.0, x.data(), nullptr, p.data(), xd) == 0);
    const double det = M11 * M22 - M12 * M12;
    CHECK(std::abs(xd[0] - qd1) < 1e-14);
    CHECK(std::abs(xd[1] - qd2) < 1e-14);
    CHECK(std::abs(xd[2] - (M22 * h[0] - M12 * h[1]) / det) < 1e-10 * std::max(1.0, std::abs(xd[2])));
    CHECK(std::abs(xd[3] - (M11 * h[1] - M12 * h[0]) / det) < 1e-10 * std::max(1.0, std::abs(xd[3])));
  }
}
