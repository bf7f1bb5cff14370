// SPDX-License-Identifier: GPL-2.0-or-later
// rigid3d kinematics against finite differences: for every Euler / Tait-Bryan sequence
// and the quaternion, with angular speeds in the body or the space frame, the built
// model's coordinate rates must move the attitude so that R' R^T is the skew matrix of
// the angular velocity in space. The rotation matrix is checked against one written
// here, independently.
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <string>

#include "mbsc/model/build.hpp"
#include "mbsc/model/rigid3d.hpp"
#include "mbsc/parse/parse.hpp"

namespace {

using Mat = std::array<double, 9>;

Mat mul(const Mat& a, const Mat& b) {
  Mat c{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) c[3 * i + j] += a[3 * i + k] * b[3 * k + j];
  return c;
}

Mat axis(char ax, double a) {
  const double c = std::cos(a), s = std::sin(a);
  if (ax == 'x') return {1, 0, 0, 0, c, -s, 0, s, c};
  if (ax == 'y') return {c, 0, s, 0, 1, 0, -s, 0, c};
  return {c, -s, 0, s, c, 0, 0, 0, 1};
}

/// The independent rotation: Euler product, or the unit quaternion's matrix.
Mat rotation(const std::string& att, const std::vector<double>& q) {
  if (att != "quaternion") return mul(mul(axis(att[0], q[0]), axis(att[1], q[1])), axis(att[2], q[2]));
  const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  const double w = q[0] / n, x = q[1] / n, y = q[2] / n, z = q[3] / n;
  return {1 - 2 * (y * y + z * z), 2 * (x * y - w * z),     2 * (x * z + w * y),
          2 * (x * y + w * z),     1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
          2 * (x * z - w * y),     2 * (y * z + w * x),     1 - 2 * (x * x + y * y)};
}

double number(const GiNaC::ex& e, const GiNaC::exmap& at) {
  const GiNaC::ex v = e.subs(at).evalf();
  REQUIRE(GiNaC::is_a<GiNaC::numeric>(v));
  return GiNaC::ex_to<GiNaC::numeric>(v).to_double();
}

void check(const std::string& att, const std::string& frame) {
  INFO("attitude " << att << ", angular speeds in the " << frame << " frame");
  const std::string decl = att == "quaternion" ? "quaternion" : "euler " + att;
  mbsc::Diagnostics d;
  auto file = mbsc::parse::parse_text(
      "model m\nbody b : rigid3d {\n mass 1\n inertia (1, 2, 3, 0.1, 0.2, 0.3)\n attitude " + decl + " " + frame + "\n}\n",
      "t.mbs", d);
  REQUIRE(file);
  auto m = mbsc::model::build(*file, d);
  REQUIRE(m);
  const auto& node = m->nodes[0];
  REQUIRE(node.kind == mbsc::model::LeafKind::Rigid3d);
  const bool quat = att == "quaternion";
  std::vector<double> q = quat ? std::vector<double>{0.8, 0.2, -0.4, 0.3} : std::vector<double>{0.4, 0.7, -0.3};
  if (quat) {
    const double n = std::sqrt(0.64 + 0.04 + 0.16 + 0.09);
    for (auto& v : q) v /= n;
  }
  const std::array<double, 3> w{0.3, -1.1, 0.8};
  GiNaC::exmap at;
  for (std::size_t k = 0; k < q.size(); ++k) at[m->coords[static_cast<std::size_t>(node.coords[3 + k])].sym] = q[k];
  for (int k = 0; k < 3; ++k) at[m->speeds[static_cast<std::size_t>(node.speeds[3 + static_cast<std::size_t>(k)])].sym] = w[k];
  // The model's rotation matrix is the independent one.
  const Mat R = rotation(att, q);
  for (int k = 0; k < 9; ++k) CHECK(number(node.rigid3d.rotation[static_cast<std::size_t>(k)], at) == Approx(R[k]).margin(1e-13));
  // Rates, then R' by central differences along them.
  std::vector<double> rate(q.size());
  for (std::size_t k = 0; k < q.size(); ++k) rate[k] = number(m->coord_rates[static_cast<std::size_t>(node.coords[3 + k])], at);
  const double h = 1e-6;
  std::vector<double> qp = q, qm = q;
  for (std::size_t k = 0; k < q.size(); ++k) qp[k] += h * rate[k], qm[k] -= h * rate[k];
  const Mat Rp = rotation(att, qp), Rm = rotation(att, qm);
  Mat Rd{}, Rt{};
  for (int k = 0; k < 9; ++k) Rd[k] = (Rp[k] - Rm[k]) / (2 * h);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) Rt[3 * i + j] = R[3 * j + i];
  const Mat S = mul(Rd, Rt);  // skew matrix of the angular velocity in space
  const std::array<double, 3> got{S[7], S[2], S[3]};
  std::array<double, 3> want = w;
  if (frame == "body")
    for (int i = 0; i < 3; ++i) want[i] = R[3 * i] * w[0] + R[3 * i + 1] * w[1] + R[3 * i + 2] * w[2];
  for (int i = 0; i < 3; ++i) CHECK(got[i] == Approx(want[i]).margin(1e-8));
  if (quat) {  // the rates keep |e| = 1: e.e' = 0
    double dot = 0;
    for (std::size_t k = 0; k < 4; ++k) dot += q[k] * rate[k];
    CHECK(std::abs(dot) < 1e-14);
  }
}

}  // namespace

TEST_CASE("rigid3d: the attitude rates give the angular velocity, every sequence and frame", "[model][rigid3d]") {
  for (const char* seq : {"xyz", "xzy", "yxz", "yzx", "zxy", "zyx", "xyx", "xzx", "yxy", "yzy", "zxz", "zyz", "quaternion"})
    for (const char* frame : {"body", "space"}) check(seq, frame);
}

TEST_CASE("rigid3d: variables, inertia tensor and default attitude", "[model][rigid3d]") {
  mbsc::Diagnostics d;
  auto file = mbsc::parse::parse_text("model m\nbody b : rigid3d { mass 2\n inertia (1, 2, 3, 0.1, 0.2, 0.3) }\n", "t.mbs", d);
  REQUIRE(file);
  auto m = mbsc::model::build(*file, d);
  REQUIRE(m);
  std::vector<std::string> coords, speeds;
  for (const auto& c : m->coords) coords.push_back(c.name);
  for (const auto& s : m->speeds) speeds.push_back(s.name);
  CHECK(coords == std::vector<std::string>{"b.x", "b.y", "b.z", "b.e0", "b.e1", "b.e2", "b.e3"});
  CHECK(speeds == std::vector<std::string>{"b.u", "b.v", "b.w", "b.wx", "b.wy", "b.wz"});
  const auto& r = m->nodes[0].rigid3d;
  CHECK(r.sequence == "quaternion");
  CHECK_FALSE(r.space_frame);
  // Row-major symmetric tensor from (Ixx, Iyy, Izz, Ixy, Ixz, Iyz).
  const double want[9] = {1, 0.1, 0.2, 0.1, 2, 0.3, 0.2, 0.3, 3};
  for (int k = 0; k < 9; ++k) CHECK(number(r.inertia[static_cast<std::size_t>(k)], {}) == Approx(want[k]));
}

TEST_CASE("rigid3d: points and axes in space for joints (x + R p, R d)", "[model][rigid3d]") {
  mbsc::Diagnostics d;
  auto file = mbsc::parse::parse_text(
      "model m\nbody b : rigid3d { mass 1\n inertia (1, 2, 3)\n attitude euler zxz\n point P (0.1, -0.2, 0.3)\n"
      " axis A (0, 0, 0.5) (1, 1, 0) }\n",
      "t.mbs", d);
  REQUIRE(file);
  auto m = mbsc::model::build(*file, d);
  REQUIRE(m);
  const auto& node = m->nodes[0];
  REQUIRE(node.rigid3d.points.count("P") == 1);
  REQUIRE(node.rigid3d.axes.count("A") == 1);
  GiNaC::exmap at;
  const double q[6] = {1.0, -2.0, 0.5, 0.4, 0.7, -0.3};  // x, y, z, phi, theta, psi
  for (int k = 0; k < 6; ++k) at[m->coords[static_cast<std::size_t>(node.coords[static_cast<std::size_t>(k)])].sym] = q[k];
  const Mat R = rotation("zxz", {q[3], q[4], q[5]});
  const auto p = mbsc::model::rigid3d::point_in_space(*m, node, node.rigid3d.points.at("P"));
  const double local[3] = {0.1, -0.2, 0.3};
  for (int i = 0; i < 3; ++i)
    CHECK(number(p[static_cast<std::size_t>(i)], at) ==
          Approx(q[i] + R[3 * i] * local[0] + R[3 * i + 1] * local[1] + R[3 * i + 2] * local[2]).margin(1e-13));
  const auto& axis = node.rigid3d.axes.at("A");
  const auto dir = mbsc::model::rigid3d::direction_in_space(*m, node, {axis[3], axis[4], axis[5]});
  for (int i = 0; i < 3; ++i) CHECK(number(dir[static_cast<std::size_t>(i)], at) == Approx(R[3 * i] + R[3 * i + 1]).margin(1e-13));
}

TEST_CASE("rigid3d: com moves the points' frame origin: x + R (p - com)", "[model][rigid3d]") {
  mbsc::Diagnostics d;
  auto file = mbsc::parse::parse_text(
      "model m\nbody b : rigid3d { mass 1\n inertia (1, 2, 3)\n attitude euler xyz space\n point P (0.1, -0.2, 0.3)\n"
      " com (0.05, 0.1, -0.2) }\n",
      "t.mbs", d);
  REQUIRE(file);
  auto m = mbsc::model::build(*file, d);
  REQUIRE(m);
  const auto& node = m->nodes[0];
  GiNaC::exmap at;
  const double q[6] = {1.0, -2.0, 0.5, 0.4, 0.7, -0.3};
  for (int k = 0; k < 6; ++k) at[m->coords[static_cast<std::size_t>(node.coords[static_cast<std::size_t>(k)])].sym] = q[k];
  const Mat R = rotation("xyz", {q[3], q[4], q[5]});
  const auto p = mbsc::model::rigid3d::point_in_space(*m, node, node.rigid3d.points.at("P"));
  const double rel[3] = {0.1 - 0.05, -0.2 - 0.1, 0.3 + 0.2};
  for (int i = 0; i < 3; ++i)
    CHECK(number(p[static_cast<std::size_t>(i)], at) ==
          Approx(q[i] + R[3 * i] * rel[0] + R[3 * i + 1] * rel[1] + R[3 * i + 2] * rel[2]).margin(1e-13));
}
