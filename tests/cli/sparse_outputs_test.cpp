// SPDX-License-Identifier: GPL-2.0-or-later
// Sparse outputs of a big closed-loop model: the chain of 40 parallelogram four-bars
// (81 bodies, 242 constraints). Its constraint Jacobian is 242 x 243 with 804 entries
// that are not identically zero; the generated functions write those and one zero fill,
// not 58 806 lines, and the header carries the CSR pattern, checked here against the
// chain's structure (each pin ties the coordinates of the one or two bodies it joins).
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "run_command.hpp"

using namespace mbsc_test;

namespace {

const std::string kMbsc = MBSC_BINARY;

std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// The lines of `MBSC_HOST_DEVICE int NAME(` .. the closing brace at column 0.
std::vector<std::string> function_lines(const std::string& source, const std::string& name) {
  const std::size_t begin = source.find("\nMBSC_HOST_DEVICE int " + name + "(");
  REQUIRE(begin != std::string::npos);
  const std::size_t end = source.find("\n}\n", begin + 1);
  REQUIRE(end != std::string::npos);
  std::vector<std::string> lines;
  std::istringstream in(source.substr(begin + 1, end - begin));
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::size_t count_prefix(const std::vector<std::string>& lines, const std::string& prefix) {
  std::size_t n = 0;
  for (const auto& l : lines) n += l.rfind(prefix, 0) == 0 ? 1 : 0;
  return n;
}

// `inline constexpr int NAME = v;`
long int_constant(const std::string& header, const std::string& name) {
  const std::string key = "inline constexpr int " + name + " = ";
  const std::size_t at = header.find(key);
  REQUIRE(at != std::string::npos);
  return std::stol(header.substr(at + key.size()));
}

// `inline constexpr int NAME[] = {a, b, ...};` (over one or more lines).
std::vector<long> int_array(const std::string& header, const std::string& name) {
  const std::string key = "inline constexpr int " + name + "[] = {";
  const std::size_t at = header.find(key);
  REQUIRE(at != std::string::npos);
  const std::size_t end = header.find("};", at);
  std::string body = header.substr(at + key.size(), end - at - key.size());
  for (char& c : body) c = c == ',' ? ' ' : c;
  std::istringstream in(body);
  std::vector<long> out;
  for (long v; in >> v;) out.push_back(v);
  return out;
}

}  // namespace

TEST_CASE("the parallelogram chain of 40 writes its Jacobians' nonzeros only, with their CSR pattern", "[cli][sparse]") {
  const int N = 40;
  const auto dir = fresh_dir("sparse");
  const auto r = run(kMbsc + " generate " + quote(std::string(MBSC_SOURCE_DIR) + "/models/parallelogram_chain.mbs") +
                     " --freeze N=40 --outputs constraint_jacobian,constraint_jacobian_values,position_jacobian --quiet -o " +
                     quote(dir.string()));
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const std::string header = slurp(dir / "parallelogram_chain" / "parallelogram_chain.hpp");
  const std::string source = slurp(dir / "parallelogram_chain" / "parallelogram_chain.cpp");

  // Sizes: 2N + 1 bodies of three coordinates; 3N + 1 pins of two rows.
  const long rows = int_constant(header, "kNc"), cols = int_constant(header, "kNuFull");
  REQUIRE(rows == 2 * (3 * N + 1));
  REQUIRE(cols == 3 * (2 * N + 1));
  // A ground pivot's rows read one body (its x or y and its angle: 2 entries each), a
  // coupler pin's rows two bodies (4 each): 2 * 2 (N + 1) + 2 * 4 * 2N.
  const long nnz = int_constant(header, "kConstraintJacobianNnz");
  REQUIRE(nnz == 4 * (N + 1) + 16 * N);
  const auto row_ptr = int_array(header, "kConstraintJacobianRowPtr");
  const auto col_idx = int_array(header, "kConstraintJacobianColIdx");
  REQUIRE(static_cast<long>(row_ptr.size()) == rows + 1);
  REQUIRE(static_cast<long>(col_idx.size()) == nnz);
  for (long i = 0; i < rows; ++i) {
    const long in_row = row_ptr[static_cast<std::size_t>(i + 1)] - row_ptr[static_cast<std::size_t>(i)];
    REQUIRE((in_row == 2 || in_row == 4));
  }
  // The position Jacobian has the same pattern (every constraint is a position one).
  REQUIRE(int_constant(header, "kPositionJacobianNnz") == nnz);
  REQUIRE(int_array(header, "kPositionJacobianColIdx") == col_idx);

  // The dense function: one fill, then exactly the nnz entries; a few lines per entry
  // (its temporary, the sin/cos of each angle), not rows * cols = 58 806 of them.
  const auto dense = function_lines(source, "constraint_jacobian");
  REQUIRE(count_prefix(dense, "  for (int i = 0; i < " + std::to_string(rows * cols) + "; ++i) OUT[i] = 0.0;") == 1);
  REQUIRE(static_cast<long>(count_prefix(dense, "  OUT[")) == nnz);
  REQUIRE(static_cast<long>(dense.size()) < 2 * nnz);
  // The CSR values: the same entries, no fill.
  const auto values = function_lines(source, "constraint_jacobian_values");
  REQUIRE(count_prefix(values, "  for (int i") == 0);
  REQUIRE(static_cast<long>(count_prefix(values, "  OUT[")) == nnz);
  REQUIRE(static_cast<long>(values.size()) < 2 * nnz);
  // position_jacobian was asked for without its values function: none is written.
  REQUIRE(source.find("int position_jacobian_values(") == std::string::npos);
  REQUIRE(source.find("int position_jacobian(") != std::string::npos);
  std::filesystem::remove_all(dir);
}

TEST_CASE("--outputs with only a values function writes no dense twin", "[cli][sparse]") {
  const auto dir = fresh_dir("sparse_only");
  const auto r = run(kMbsc + " generate " + quote(std::string(MBSC_SOURCE_DIR) + "/models/four_bar.mbs") +
                     " --outputs position_jacobian_values --quiet -o " + quote(dir.string()));
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const std::string source = slurp(dir / "four_bar" / "four_bar.cpp");
  const std::string header = slurp(dir / "four_bar" / "four_bar.hpp");
  REQUIRE(source.find("int position_jacobian_values(") != std::string::npos);
  REQUIRE(source.find("int position_jacobian(") == std::string::npos);
  REQUIRE(source.find("int constraint_jacobian") == std::string::npos);
  // Its pattern, and no other's. Four-bar: 4 pins (8 rows), 2 ground pins with one body.
  REQUIRE(int_constant(header, "kPositionJacobianNnz") == 2 * 2 * 2 + 2 * 2 * 4);
  REQUIRE(header.find("kConstraintJacobianNnz") == std::string::npos);
  std::filesystem::remove_all(dir);
}

TEST_CASE("mass_matrix of a long chain is formed from its factors by a loop; a short one stays symbolic",
          "[cli][sparse][mass_matrix_factors]") {
  // The pendulum chain: at N = 60 the product C^T My C takes about 2 N^3 / 6 = 72 000
  // products (auto: factors); at N = 8 about 350 (auto: symbolic). The factor form's
  // function holds the distinct values (two per link and the mass), not N^2 entries.
  const std::string chain = quote(std::string(MBSC_SOURCE_DIR) + "/tests/data/chain/pendulum_chain.mbs");
  auto mass_matrix_lines = [&](int n, const std::string& extra) {
    const auto dir = fresh_dir("mass_matrix_factors");
    const auto r = run(kMbsc + " generate " + chain + " --freeze N=" + std::to_string(n) +
                       " --state minimal --outputs mass_matrix --quiet -o " + quote(dir.string()) + extra);
    INFO(r.output);
    REQUIRE(r.exit_code == 0);
    return function_lines(slurp(dir / "pendulum_chain" / "pendulum_chain.cpp"), "mass_matrix");
  };
  const auto long_auto = mass_matrix_lines(60, "");
  CHECK(count_prefix(long_auto, "  // OUT = C^T My C (60x60)") == 1);
  CHECK(count_prefix(long_auto, "  OUT[") == 0);  // no entry written one by one
  CHECK(count_prefix(long_auto, "  factor_[") <= 2 * 60 + 2);
  const auto long_symbolic = mass_matrix_lines(60, " --mass-matrix symbolic");
  CHECK(2 * long_auto.size() < long_symbolic.size());  // C's 3 720 nonzeros: tables of 20 a line
  CHECK(count_prefix(long_symbolic, "  // OUT = C^T My C") == 0);
  CHECK(count_prefix(long_symbolic, "  OUT[") >= 60 * 61 / 2);
  const auto short_auto = mass_matrix_lines(8, "");
  CHECK(count_prefix(short_auto, "  // OUT = C^T My C") == 0);
  const auto short_factors = mass_matrix_lines(8, " --mass-matrix factors");
  CHECK(count_prefix(short_factors, "  // OUT = C^T My C (8x8)") == 1);
}
