// SPDX-License-Identifier: GPL-2.0-or-later
#include <catch2/catch.hpp>

#include <algorithm>
#include <string>
#include <vector>

#include "mbsc/emit/generated_model.hpp"
#include "mbsc/ir/program.hpp"

using namespace GiNaC;
using mbsc::ir::Binding;
using mbsc::ir::Define;
using mbsc::ir::FunctionSpec;
using mbsc::ir::Solve;

namespace {

// Builds the same model with symbols created in a given order and sums/products assembled
// in that order, so GiNaC's internal term order differs between calls.
struct Built {
  std::vector<symbol> q;
  std::vector<Binding> bindings;
  FunctionSpec spec;
};

Built build(const std::vector<int>& order) {
  Built b;
  const int n = static_cast<int>(order.size());
  b.q.resize(static_cast<std::size_t>(n));
  for (int i : order) b.q[static_cast<std::size_t>(i)] = symbol("q" + std::to_string(i));
  for (int i : order) b.bindings.push_back({b.q[static_cast<std::size_t>(i)], "x[" + std::to_string(i) + "]"});
  auto q = [&](int i) { return ex(b.q[static_cast<std::size_t>(i)]); };

  symbol w("w"), X0("X0"), X1("X1"), X2("X2"), X3("X3");
  b.spec.name = "f";
  // w := sum over i of q_i * sin(q_{i+1}), summed in `order`.
  ex wsum = 0;
  for (int i : order) wsum += q(i) * sin(q((i + 1) % n));
  b.spec.steps.push_back(Define{w, wsum});
  Solve s;
  s.n = 2;
  s.k = 2;
  s.A = {2 + cos(q(0)), q(1) * q(2), q(2) * q(1), 3 + sin(q(0))};
  s.B = {w, 1, q(3), pow(q(0) + q(1), 2)};
  s.X = {X0, X1, X2, X3};
  b.spec.steps.push_back(s);
  ex prod = 1;
  for (int i : order) prod *= (1 + q(i) * q(i));
  ex mixed = 0;
  for (int i : order) mixed += pow(q(i), i % 4 + 1) * cos(q(i)) - exp(q(i) * w) / (1 + q((i + 2) % n) * q((i + 2) % n));
  b.spec.outputs = {X0 * X3 - X1 * X2, prod, mixed, w * sin(q(0)) + X1, prod * mixed};
  return b;
}

}  // namespace

TEST_CASE("determinism: same text whatever the construction order", "[ir]") {
  const std::vector<int> forward = {0, 1, 2, 3, 4, 5, 6, 7};
  std::vector<int> reversed(forward.rbegin(), forward.rend());
  const std::vector<int> shuffled = {5, 2, 7, 0, 3, 6, 1, 4};
  std::vector<std::string> bodies;
  for (const auto& order : {forward, reversed, shuffled}) {
    const Built b = build(order);
    bodies.push_back(mbsc::ir::lower(b.spec, b.bindings).body);
  }
  CHECK(bodies[0] == bodies[1]);
  CHECK(bodies[0] == bodies[2]);
}

TEST_CASE("determinism: emitted files are byte-identical", "[ir][emit]") {
  std::vector<mbsc::emit::GeneratedFiles> files;
  for (const auto& order : {std::vector<int>{0, 1, 2, 3, 4, 5}, std::vector<int>{3, 5, 1, 0, 4, 2}}) {
    const Built b = build(order);
    mbsc::emit::GeneratedModel m;
    m.name = "det";
    m.source_hash = "0123abcd";
    m.tool_version = "0.1.0";
    m.int_constants = {{"kNx", 6}};
    m.functions = {mbsc::ir::lower(b.spec, b.bindings)};
    files.push_back(mbsc::emit::emit(m));
  }
  CHECK(files[0].header == files[1].header);
  CHECK(files[0].source == files[1].source);
}

TEST_CASE("determinism: signs of sums in products do not follow GiNaC's order", "[ir]") {
  // GiNaC makes a sum factor "unit normal" by the sign of its first term in its own,
  // run-dependent order; symbols created in different orders reproduce that in-process.
  std::vector<int> order = {0, 1, 2, 3};
  std::vector<std::string> bodies;
  do {
    std::vector<symbol> q(4);
    for (int i : order) q[static_cast<std::size_t>(i)] = symbol("q" + std::to_string(i));
    std::vector<Binding> b;
    for (int i = 0; i < 4; ++i) b.push_back({q[static_cast<std::size_t>(i)], "x[" + std::to_string(i) + "]"});
    FunctionSpec f;
    f.name = "f";
    f.outputs = {(q[0] - q[1]) * q[2],
                 (q[1] - 2 * q[3]) * (q[2] - q[0]) * q[3],
                 pow(q[0] - q[3], 3) * q[1],
                 pow(q[2] - q[1], 3),
                 pow(q[3] - q[0] + q[1], -1) * (q[1] - q[2]),
                 (2 * q[0] - 4 * q[1]) * sin(q[2] - q[3]),
                 (q[0] - q[1]) * q[2] + (q[1] - q[0]) * q[3]};
    bodies.push_back(mbsc::ir::lower(f, b).body);
  } while (std::next_permutation(order.begin(), order.end()));
  for (const auto& body : bodies) CHECK(body == bodies.front());
}
