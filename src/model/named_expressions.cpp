// SPDX-License-Identifier: GPL-2.0-or-later
#include "named_expressions.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "mbsc/diag/limits.hpp"

namespace mbsc::model {

namespace {

/// Lets used before their definitions (across includes) that one conversion may pass
/// through, one inside another, and the levels of their expressions together: the
/// converter recurses through each, so both stay well inside the stack, also in a
/// sanitizer build, whose frames are several times larger (200 shallow lets overflowed
/// there). docs/language.md, "Limits".
constexpr int kMaxLetChain = 32;
constexpr int kMaxConvertingLevels = limits::kMaxNesting;

/// a + b, at most the limit's next value (the sizes of a chain of lets grow geometrically).
std::size_t saturating_add(std::size_t a, std::size_t b) {
  constexpr std::size_t cap = limits::kMaxLetNodes + 1;
  return a >= cap || b >= cap || a + b >= cap ? cap : a + b;
}

/// Nodes of an expression as written (a use of a let counts one here, its value on use).
/// The parser bounds the nesting, so the recursion is shallow.
std::size_t written_nodes(const ast::Expr& e) {
  std::size_t n = 1;
  for (const auto& a : e.args) n = saturating_add(n, written_nodes(*a));
  return n;
}

/// Levels of an expression as written (a name or a number is one).
int written_depth(const ast::Expr& e) {
  int d = 0;
  for (const auto& a : e.args) d = std::max(d, written_depth(*a));
  return d + 1;
}

/// The first name of each kind: `into`'s own, else `from`'s.
void merge(NamedExpressions::Reads& into, const NamedExpressions::Reads& from) {
  if (into.speed.empty()) into.speed = from.speed;
  if (into.coord_rate.empty()) into.coord_rate = from.coord_rate;
  if (into.speed_rate.empty()) into.speed_rate = from.speed_rate;
}

/// a is before b in the same file (positions of different files are not ordered).
bool before(const SourcePos& a, const SourcePos& b) {
  return a.file == b.file && (a.line < b.line || (a.line == b.line && a.col < b.col));
}
}  // namespace

int NamedExpressions::declare(const std::string& full, int node, const ast::Statement& s) {
  Let let;
  let.name = full;
  let.node = node;
  let.stmt = &s;
  let.size = written_nodes(*s.value);
  let.depth = written_depth(*s.value);
  lets_.push_back(std::move(let));
  return static_cast<int>(lets_.size()) - 1;
}

std::optional<GiNaC::ex> NamedExpressions::value(int index) {
  Let& let = lets_[static_cast<std::size_t>(index)];
  switch (let.state) {
    case State::Done: return let.value;
    case State::Failed: return std::nullopt;
    case State::Converting: return std::nullopt;  // a cycle: reported by use()
    case State::Pending: break;
  }
  // Only a let used before its definition converts another on the way (across files, or
  // from an element built before the let's statement is reached); a chain of them is
  // bounded here, before it exhausts the stack.
  // The converter recurses through each let's expression on the way: the levels of all
  // of them are bounded as well (each may nest kMaxNesting deep).
  if (converting_.size() >= static_cast<std::size_t>(kMaxLetChain) ||
      converting_levels_ + let.depth > kMaxConvertingLevels) {
    // Once: a long chain reached again from its next let says nothing new.
    if (!chain_reported_)
      diags_.error(let.stmt->name_pos,
                   fmt::format("let '{}' is reached through more than {} lets used before their definitions (or "
                               "{} levels of their expressions); define each let before the lets and elements that "
                               "use it",
                               let.name, kMaxLetChain, kMaxConvertingLevels));
    chain_reported_ = true;
    let.state = State::Failed;
    return std::nullopt;
  }
  let.state = State::Converting;
  converting_.push_back(index);
  converting_levels_ += let.depth;
  const auto v = convert_(let.node, *let.stmt->value);
  converting_levels_ -= lets_[static_cast<std::size_t>(index)].depth;
  converting_.pop_back();
  Let& done = lets_[static_cast<std::size_t>(index)];
  if (!v) {
    done.state = State::Failed;
    return std::nullopt;
  }
  if (done.size > limits::kMaxLetNodes) {
    diags_.error(done.stmt->name_pos, fmt::format("let '{}' expands to more than {} nodes (each let it uses is "
                                                  "written out in full at each use)",
                                                  done.name, limits::kMaxLetNodes));
    done.state = State::Failed;
    return std::nullopt;
  }
  done.value = *v;
  done.state = State::Done;
  return done.value;
}

std::optional<GiNaC::ex> NamedExpressions::use(int index, const SourcePos& pos, Allowed allowed) {
  const Let& let = lets_[static_cast<std::size_t>(index)];
  if (before(pos, let.stmt->name_pos)) {
    diags_.error(pos, fmt::format("let '{}' is used before its definition (at {}:{})", let.name, let.stmt->name_pos.line,
                                  let.stmt->name_pos.col));
    return std::nullopt;
  }
  if (let.state == State::Converting) {
    std::string chain;
    bool on = false;
    for (int k : converting_) {
      on = on || k == index;
      if (on) chain += lets_[static_cast<std::size_t>(k)].name + " -> ";
    }
    diags_.error(pos, fmt::format("let '{}' refers to itself ({}{})", let.name, chain, let.name));
    lets_[static_cast<std::size_t>(index)].state = State::Failed;  // one message per cycle
    return std::nullopt;
  }
  const auto v = value(index);
  if (!v) return std::nullopt;
  if (!converting_.empty()) {  // a let used in another's value: its size and reads add up there
    Let& user = lets_[static_cast<std::size_t>(converting_.back())];
    const Let& used = lets_[static_cast<std::size_t>(index)];
    user.size = saturating_add(user.size, used.size - 1);  // the name is replaced by its value
    merge(user.reads, used.reads);
  }
  const Reads& r = lets_[static_cast<std::size_t>(index)].reads;
  if (!allowed.speeds && !r.speed.empty()) {
    diags_.error(pos, fmt::format("let '{}' reads the speed '{}', which is not allowed here (a position-level expression)",
                                  let.name, r.speed));
    return std::nullopt;
  }
  if (!allowed.coord_rates && !r.coord_rate.empty()) {
    diags_.error(pos, fmt::format("let '{}' reads the rate {}' of a coordinate, which is not allowed here (only in speed "
                                  "definitions and velocity constraints)",
                                  let.name, r.coord_rate));
    return std::nullopt;
  }
  if (!allowed.speed_rates && !r.speed_rate.empty()) {
    diags_.error(pos, fmt::format("let '{}' reads the acceleration {}' of a speed, which is only allowed in a custom leaf's "
                                  "forces",
                                  let.name, r.speed_rate));
    return std::nullopt;
  }
  return v;
}

void NamedExpressions::note_read(const Reads& r) {
  if (!converting_.empty()) merge(lets_[static_cast<std::size_t>(converting_.back())].reads, r);
}

}  // namespace mbsc::model
