// SPDX-License-Identifier: GPL-2.0-or-later
// The name table: declaring a name (each once, `pi` reserved) and reading one in an
// expression: from the innermost subsystem outwards, then the globals (`global.NAME`
// from anywhere); lets converted where first read; each kind of name allowed or refused
// where it is read (a speed in a position-level expression); "did you mean" for the rest.
#include "build_internal.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <set>

#include "mbsc/diag/name_suggestions.hpp"

namespace mbsc::model::build_detail {

namespace {

/// The one named constant of expressions (ExprConverter): no declaration may take it.
constexpr const char* kReservedConstant = "pi";

}  // namespace

/// The kind of name a statement declares ("parameter", "point"...), or nullptr.
const char* Builder::declared_kind(const Statement& s) {
  switch (s.kind) {
    case Kind::Parameter: return "parameter";
    case Kind::Input: return "input";
    case Kind::Component: return "component";
    case Kind::Subsystem: return "subsystem";
    case Kind::Coordinate: return "coordinate";
    case Kind::Speed: return "speed";
    case Kind::Let: return "let";
    case Kind::Output: return s.value ? "output" : nullptr;
    case Kind::Point: return "point";
    case Kind::Axis: return "axis";
    case Kind::Joint: return "joint";
    case Kind::Spring: return "spring";
    case Kind::Damper: return "damper";
    default: return nullptr;
  }
}

/// `pi` always means the constant π in an expression, so no declaration may take that
/// name (it would take a p[] slot, or a variable, that no expression could read).
/// Checked over the whole file, component bodies included, once per statement.
void Builder::check_reserved_names(const std::vector<ast::StatementPtr>& stmts) {
  for (const auto& s : stmts) {
    const char* what = declared_kind(*s);
    auto refuse = [&](const SourcePos& pos, const char* kind) {
      diags_.error(pos, fmt::format("{} '{}' clashes with the constant pi (every 'pi' in an expression means "
                                    "3.14159...); choose another name",
                                    kind, kReservedConstant));
    };
    if (what && s->name == kReservedConstant) refuse(s->name_pos, what);
    for (std::size_t i = 0; i < s->formals.size(); ++i)
      if (s->formals[i] == kReservedConstant) refuse(s->formal_pos[i], "component parameter");
    check_reserved_names(s->body);
  }
}

/// The statement that declares `path` where the lets are not read yet (parameter
/// defaults, gravity, the ground): a let (at the top or in a subsystem, by its dotted
/// path), or a parameter or input declared further down. Nullptr when there is none.
const Statement* Builder::not_yet_declared(const std::string& path, const SourcePos& use) const {
  const std::vector<ast::StatementPtr>* stmts = top_;
  std::string rest = path;
  for (std::size_t dot = rest.find('.'); stmts && dot != std::string::npos; dot = rest.find('.')) {
    const std::string head = rest.substr(0, dot);
    const std::vector<ast::StatementPtr>* inner = nullptr;
    for (const auto& s : *stmts)
      if (s->kind == Kind::Subsystem && s->name == head) inner = &s->body;
    stmts = inner;
    rest = rest.substr(dot + 1);
  }
  if (!stmts) return nullptr;
  const bool top = stmts == top_;
  const auto after_use = [&](const SourcePos& p) {
    return p.file == use.file && (p.line > use.line || (p.line == use.line && p.col > use.col));
  };
  for (const auto& s : *stmts) {
    if (s->name != rest) continue;
    if (s->kind == Kind::Let) return s.get();
    if (top && (s->kind == Kind::Parameter || s->kind == Kind::Input) && after_use(s->name_pos)) return s.get();
  }
  return nullptr;
}

/// " as a parameter at 3:11" (the file too when it is another one), " as the time variable".
std::string Builder::declared_as(const Entry& e, const SourcePos& here) {
  if (e.what.empty()) return "";
  return fmt::format(" as {}{}", e.what, e.pos.line > 0 ? " at " + position_text(e.pos, here) : "");
}

/// "3:11", or "other.mbs:3:11" when `pos` is in another file than `here`.
std::string Builder::position_text(const SourcePos& pos, const SourcePos& here) {
  return fmt::format("{}{}:{}", pos.file == here.file ? "" : pos.file + ":", pos.line, pos.col);
}

bool Builder::declare_local(const std::string& full, const SourcePos& pos, const char* what) {
  auto it = table_.find(full);
  if (it != table_.end()) {
    diags_.error(pos, fmt::format("{} '{}' is already declared{}", what, full, declared_as(it->second, pos)));
    return false;
  }
  return true;
}

void Builder::declare_let(int node, const std::string& full, const Statement& s) {
  if (!declare_local(full, s.name_pos, "let")) return;
  table_[full] = Entry{Entry::Let, lets_.declare(full, node, s), GiNaC::symbol(), "a let", s.name_pos};
  if (s.value) let_names_[s.value.get()] = full;
}

/// A let's value in the scope of `node`, every level allowed (each use checks its own).
std::optional<GiNaC::ex> Builder::convert_let(int node, const ast::Expr& e) {
  const bool speeds = allow_speeds_, coord_rates = allow_coord_rate_, speed_rates = allow_speed_rate_;
  allow_speeds_ = allow_coord_rate_ = allow_speed_rate_ = true;
  ExprConverter conv = converter(node);
  const auto name = let_names_.find(&e);  // converted where it is first read: named by itself
  conv.element = name != let_names_.end() ? fmt::format("let '{}'", name->second) : "";
  auto out = conv.convert(e);
  allow_speeds_ = speeds;
  allow_coord_rate_ = coord_rates;
  allow_speed_rate_ = speed_rates;
  return out;
}

ExprConverter Builder::converter(int node) {
  ExprConverter conv(diags_);
  conv.element = node < 0 ? global_context_ : element_;
  conv.lookup = [this, node](const std::string& path, const SourcePos& pos, bool primed) -> std::optional<GiNaC::ex> {
    return resolve(path, pos, node, primed);
  };
  return conv;
}

/// Finds `path` from the innermost scope (the node) outwards, then globals. `global.NAME`
/// names a parameter, input or t whatever the scope. A body's own variable does not
/// capture a parameter or input of the same name where it is not allowed (a speed in a
/// point's position: the parameter is meant); where both are allowed the name is
/// ambiguous and both spellings are offered.
std::optional<GiNaC::ex> Builder::resolve(const std::string& path, const SourcePos& pos, int node, bool primed) {
  const std::string global_prefix = std::string(kGlobalScope) + ".";
  if (path.rfind(global_prefix, 0) == 0) {
    const std::string name = path.substr(global_prefix.size());
    const auto it = table_.find(name);
    if (it == table_.end() || !is_global(it->second)) {
      std::vector<std::string> globals;
      for (const auto& [key, entry] : table_)
        if (is_global(entry)) globals.push_back(key);
      const auto close = closest_name(name, globals);
      diags_.error(pos, fmt::format("no parameter or input '{}' for '{}'{}", name, path,
                                    close ? fmt::format(" (did you mean '{}{}'?)", global_prefix, *close) : ""));
      return std::nullopt;
    }
    return value_of(it->second, name, path, pos, primed);
  }
  // Every match, innermost first (the root's is the global or full-path one).
  std::vector<std::pair<std::string, const Entry*>> matches;
  for (int n = node; n >= 0; n = m_.nodes[n].parent) {
    const std::string full = join(m_.nodes[n].name, path);
    auto it = table_.find(full);
    if (it != table_.end() && (matches.empty() || matches.back().first != full)) matches.emplace_back(full, &it->second);
    if (m_.nodes[n].parent < 0) break;
  }
  if (matches.empty()) {
    auto it = table_.find(path);
    if (it != table_.end()) matches.emplace_back(path, &it->second);
  }
  if (matches.empty()) {
    if (const Statement* later = node < 0 ? not_yet_declared(path, pos) : nullptr) {
      if (later->kind == Kind::Let)
        diags_.error(pos, fmt::format("let '{}' cannot be used in {}: lets are read after the parameters, gravity and "
                                      "the ground (write its expression here instead)",
                                      path, global_context_));
      else
        diags_.error(pos, fmt::format("{} '{}' is declared after {} (at {}); declare it first",
                                      declared_kind(*later), path, global_context_,
                                      position_text(later->name_pos, pos)));
      return std::nullopt;
    }
    diags_.error(pos, fmt::format("unknown name '{}'{}", path, suggestion(path, node, false)));
    return std::nullopt;
  }
  const auto& [full, found] = matches.front();
  const bool local_variable = found->kind == Entry::Coord || found->kind == Entry::Speed;
  const auto global = std::find_if(matches.begin() + 1, matches.end(), [](const auto& m) { return is_global(*m.second); });
  if (local_variable && global != matches.end()) {
    const bool local_ok = allowed(*found, primed), global_ok = allowed(*global->second, primed);
    if (!local_ok && global_ok) return value_of(*global->second, global->first, path, pos, primed);
    if (local_ok && global_ok) {
      diags_.error(pos, fmt::format("'{0}' is ambiguous here: the {1} '{2}' or the {3} '{0}'; write '{2}' for the {1} "
                                    "or '{4}.{0}' for the {3}",
                                    path, found->kind == Entry::Coord ? "coordinate" : "speed", full,
                                    global_kind_name(*global->second), kGlobalScope));
      return std::nullopt;
    }
  }
  return value_of(*found, full, path, pos, primed);
}

bool Builder::is_global(const Entry& e) { return e.kind == Entry::Param || e.kind == Entry::Input || e.kind == Entry::Time; }

const char* Builder::global_kind_name(const Entry& e) {
  return e.kind == Entry::Param ? "parameter" : e.kind == Entry::Input ? "input" : "time";
}

/// Whether the entry may be used here (the allow_ flags of the expression being converted).
bool Builder::allowed(const Entry& e, bool primed) const {
  switch (e.kind) {
    case Entry::NodeName: return false;
    case Entry::Coord: return !primed || allow_coord_rate_;
    case Entry::Speed: return primed ? allow_speed_rate_ : allow_speeds_;
    default: return !primed;
  }
}

/// The value of a resolved name, or the error that says why it is not allowed here.
std::optional<GiNaC::ex> Builder::value_of(const Entry& found, const std::string& full, const std::string& path,
                                           const SourcePos& pos, bool primed) {
  switch (found.kind) {
    case Entry::NodeName:
      diags_.error(pos, fmt::format("'{}' is a subsystem, not a value", full));
      return std::nullopt;
    case Entry::Let:
      if (primed) {
        diags_.error(pos, fmt::format("the derivative ' is only allowed on coordinates and speeds, not on let '{}'", full));
        return std::nullopt;
      }
      return lets_.use(found.index, pos, {allow_speeds_, allow_coord_rate_, allow_speed_rate_});
    case Entry::Coord:
      if (primed) {
        if (!allow_coord_rate_) {
          diags_.error(pos, fmt::format("the rate {}' of coordinate '{}' is not allowed here", path, full));
          return std::nullopt;
        }
        lets_.note_read({"", full, ""});  // a let being converted reads it
        return GiNaC::ex(coord_dot_[found.index]);
      }
      return GiNaC::ex(found.sym);
    case Entry::Speed:
      if (primed) {
        if (!allow_speed_rate_) {
          diags_.error(pos, fmt::format("the acceleration {}' of speed '{}' is only allowed in forces", path, full));
          return std::nullopt;
        }
        lets_.note_read({"", "", full});
        return GiNaC::ex(m_.speed_dots[found.index]);
      }
      if (!allow_speeds_) {
        diags_.error(pos, fmt::format("speed '{}' is not allowed here (a position-level expression)", full));
        return std::nullopt;
      }
      lets_.note_read({full, "", ""});
      return GiNaC::ex(found.sym);
    default:
      if (primed) {
        diags_.error(pos, fmt::format("the derivative ' is only allowed on coordinates and speeds, not on '{}'", full));
        return std::nullopt;
      }
      return GiNaC::ex(found.sym);
  }
}

/// " (did you mean ...?)" for an unknown name at `node`, or "". Only while diagnostics
/// are still shown: a file of 100 000 unknown names must not compare each with every name.
std::string Builder::suggestion(const std::string& written, int node, bool variables_only) const {
  if (diags_.all().size() >= Diagnostics::kMaxShown) return "";
  return did_you_mean(written, names_in_scope(node, variables_only));
}

/// The names that resolve when written at `node`: relative to each enclosing scope,
/// innermost first (then every full path and global, from the top), `pi` among them;
/// with `variables_only` just coordinates and speeds. For "did you mean" suggestions.
std::vector<std::string> Builder::names_in_scope(int node, bool variables_only) const {
  std::vector<std::string> out;
  std::set<std::string> seen;
  auto add = [&](const std::string& name, const Entry& e) {
    if (e.kind == Entry::NodeName) return;
    if (variables_only && e.kind != Entry::Coord && e.kind != Entry::Speed) return;
    if (seen.insert(name).second) out.push_back(name);
  };
  for (int n = node; n >= 0; n = m_.nodes[n].parent) {
    const std::string& scope = m_.nodes[n].name;
    if (scope.empty()) break;  // the root: below
    const std::string prefix = scope + ".";
    for (auto it = table_.lower_bound(prefix); it != table_.end() && it->first.rfind(prefix, 0) == 0; ++it)
      add(it->first.substr(prefix.size()), it->second);
  }
  for (const auto& [name, e] : table_) add(name, e);
  if (!variables_only && seen.insert("pi").second) out.push_back("pi");
  return out;
}

std::optional<GiNaC::ex> Builder::convert(int node, const ast::ExprPtr& e, bool speeds, bool coord_rates, bool speed_rates) {
  allow_speeds_ = speeds;
  allow_coord_rate_ = coord_rates;
  allow_speed_rate_ = speed_rates;
  ExprConverter conv = converter(node);
  return conv.convert(*e);
}

/// Resolves a dotted path to a variable: (is_coordinate, index).
std::optional<std::pair<bool, int>> Builder::lookup_variable(int node, const ast::Path& p) {
  for (int n = node; n >= 0; n = m_.nodes[n].parent) {
    auto it = table_.find(join(m_.nodes[n].name, p.text));
    if (it != table_.end()) {
      if (it->second.kind == Entry::Coord) return std::make_pair(true, it->second.index);
      if (it->second.kind == Entry::Speed) return std::make_pair(false, it->second.index);
      diags_.error(p.pos, fmt::format("'{}' is not a variable", p.text));
      return std::nullopt;
    }
    if (m_.nodes[n].parent < 0) break;
  }
  diags_.error(p.pos, fmt::format("unknown variable '{}'{}", p.text, suggestion(p.text, node, true)));
  return std::nullopt;
}

}  // namespace mbsc::model::build_detail
