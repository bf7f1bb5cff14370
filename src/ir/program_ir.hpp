// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// The straight-line Program (private to src/ir; opaque in include/mbsc/ir/program.hpp):
/// a canonical DAG plus statements in emission order. Built by schedule(), printed by
/// print_program().
#include <string>
#include <vector>

#include "canonical_dag.hpp"
#include "mbsc/ir/program.hpp"

namespace mbsc::ir {

/// A numeric linear solve kept by dead-code removal.
struct SolveBlock {
  int step = 0;    // index in FunctionSpec::steps
  int number = 0;  // emitted as A_<number>, B_<number>
  int n = 0;
  int k = 0;
  std::string label;
  bool spd = false;       // Cholesky instead of LU
  int rank = 0;           // with spd: semidefinite of this rank, minimum-norm solve (0: definite)
  bool condition = false;  // rcond of A into B_<number>[0] instead of a solve
  std::vector<NodeId> A;  // n x n, row-major
  std::vector<NodeId> B;  // n x k, row-major
};

struct Statement {
  enum class Kind {
    Temp,    // const double <name of node> = <node>;
    Solve,   // double A_i[..] = {..}; double B_i[..] = {..}; if (lu_solve(..) != 0) return 1;
    Output,  // OUT[index] = <node>;
  };
  Kind kind = Kind::Temp;
  NodeId node = -1;
  int index = 0;  // Solve: index in Program::solves; Output: output index
};

/// What the root walk visits, in order: live steps, then outputs.
struct Root {
  enum class Kind { Define, Solve, Output };
  Kind kind = Kind::Output;
  int index = 0;   // Define: step; Solve: index in Program::solves; Output: output index
  NodeId node = -1;  // Define / Output
};

struct Program {
  Dag dag;
  std::vector<std::string> names;  // per node: temporary's name, empty when printed inline
  std::vector<SolveBlock> solves;  // live solves, in step order
  std::vector<Root> roots;
  /// Per step: the value node of a named Define that something refers to (its readers
  /// hold the leaf Sym(step, -1), printed as this node), else -1.
  std::vector<NodeId> define_ref_value;
  std::vector<Statement> statements;
  int nout = 0;
  std::string out_array = "OUT";  // where the outputs go (a local array when OUT is formed from them)
  std::vector<std::string> used_args;  // subset of t, x, u, p, in that order
  std::vector<std::string> live_inputs;  // texts of the inputs the function reads ("x[3]", "p[0]"), sorted
};

/// Marks temporaries (shared nodes, Define values, sin/cos, repeated-multiplication bases,
/// over-deep inline expressions), names them and orders the statements. `define_names`
/// maps a Define step to its symbol's name (empty for other steps).
void schedule(Program& prog, const std::vector<std::string>& define_names, const std::vector<std::string>& reserved);

/// Prints the statements as the function body (2-space indent, ends with `return 0;`)
/// and counts the operations it prints.
std::string print_program(const Program& prog, OpCount& ops);

/// The static pattern tables and the loop forming OUT = C^T My C from the local array
/// factor_ (the function's outputs), then OUT's finiteness check; counts what it adds.
std::string congruence_loop(const CongruenceProduct& product, OpCount& ops);

/// Largest integer exponent printed as repeated multiplication (x*x*x*x).
inline constexpr int kMaxRepeatedPower = 4;
/// Deepest expression printed inline before a temporary is forced.
inline constexpr int kMaxInlineDepth = 32;

/// Exponent of a Pow node printed by repeated multiplication: n with 2 <= |n| <= 4, else 0.
int repeated_power(const Dag& dag, NodeId pow);

}  // namespace mbsc::ir
