// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// Named expressions (`let NAME = expr`, docs/language.md "Named expressions"), private
/// to src/model. A let is a name for an expression of parameters, t, coordinates, speeds
/// and coordinate rates, looked up like any other name of its scope. Its value is
/// converted once, in the scope where it is written, the first time it is used (or
/// when its statement is reached), and put in place at every use. A use is checked
/// where it stands: a let read before its definition, a let that reads itself through
/// other lets, and a let whose value holds a speed (or a rate) where the use allows none
/// are errors at the use, naming the let.
///
/// A value is a shared graph: `let b = a*a + a` holds `a` twice, so a chain of such lets
/// grows a tree that triples at each line while its graph grows by a node. Nothing here
/// walks a value: its size as a tree (saturating) and the speeds and rates it reads are
/// kept per let, from its own nodes and symbols and those of the lets it uses, and a let
/// whose tree is larger than limits::kMaxLetNodes is an error at its name, so everything
/// downstream (derivatives, code generation) sees trees of bounded size.
#include <ginac/ginac.h>

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "mbsc/diag/diagnostics.hpp"
#include "mbsc/parse/ast.hpp"

namespace mbsc::model {

class NamedExpressions {
 public:
  /// What a use allows, as the builder's conversion flags say.
  struct Allowed {
    bool speeds = false, coord_rates = false, speed_rates = false;
  };
  /// The first speed, coordinate rate and speed rate a value holds ("" for none).
  struct Reads {
    std::string speed, coord_rate, speed_rate;
  };
  /// Converts a let's expression in the scope of `node` with every level allowed.
  using Convert = std::function<std::optional<GiNaC::ex>(int node, const ast::Expr& e)>;

  NamedExpressions(Diagnostics& diags, Convert convert) : diags_(diags), convert_(std::move(convert)) {}

  /// Declares `let NAME = expr` (full dotted name) at `node`; returns its index.
  int declare(const std::string& full, int node, const ast::Statement& s);
  /// The value at a use at `pos`, or nullopt (reported at the use, or once in the let's
  /// own expression when that is wrong).
  std::optional<GiNaC::ex> use(int index, const SourcePos& pos, Allowed allowed);
  /// Converts a let whether or not it is used, so mistakes in an unused one are reported.
  void define(int index) { value(index); }
  /// The builder met a speed or a rate while converting a let: the innermost let being
  /// converted reads it (a no-op outside a let).
  void note_read(const Reads& r);

 private:
  enum class State { Pending, Converting, Done, Failed };
  struct Let {
    std::string name;
    int node = 0;
    const ast::Statement* stmt = nullptr;
    State state = State::Pending;
    GiNaC::ex value;
    Reads reads;             // own symbols and those of the lets it uses
    std::size_t size = 0;    // nodes of the value as a tree (saturating)
    int depth = 0;           // levels of its own expression as written
  };
  /// The converted value, or nullopt when its expression failed or a cycle was found.
  std::optional<GiNaC::ex> value(int index);

  Diagnostics& diags_;
  Convert convert_;
  std::vector<Let> lets_;
  std::vector<int> converting_;  // lets being converted, outermost first (for cycle messages)
  int converting_levels_ = 0;    // the written levels of the lets in converting_, together
  bool chain_reported_ = false;  // a chain of lets used before their definitions went too deep
};

}  // namespace mbsc::model
