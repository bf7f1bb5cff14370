// SPDX-License-Identifier: GPL-2.0-or-later
#include "named_expressions.hpp"

#include <fmt/format.h>

namespace mbsc::model {

namespace {
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
  let.state = State::Converting;
  converting_.push_back(index);
  const auto v = convert_(let.node, *let.stmt->value);
  converting_.pop_back();
  Let& done = lets_[static_cast<std::size_t>(index)];
  if (!v) {
    done.state = State::Failed;
    return std::nullopt;
  }
  done.value = *v;
  done.reads = classify_(*v);
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

}  // namespace mbsc::model
