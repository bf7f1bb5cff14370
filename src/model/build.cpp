// SPDX-License-Identifier: GPL-2.0-or-later
#include "mbsc/model/build.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <set>
#include <stdexcept>

#include "mbsc/diag/activity.hpp"
#include "mbsc/diag/limits.hpp"
#include "mbsc/diag/name_suggestions.hpp"
#include "mbsc/model/exact_guard.hpp"
#include "mbsc/model/varying_part.hpp"
#include "mbsc/model/expr_convert.hpp"
#include "mbsc/model/value_bound.hpp"
#include "mbsc/model/rigid3d.hpp"
#include "named_expressions.hpp"
#include "planar_library.hpp"
#include "spatial_library.hpp"

namespace mbsc::model {

const char* to_string(LeafKind kind) {
  switch (kind) {
    case LeafKind::Node: return "node";
    case LeafKind::Particle2d: return "particle2d";
    case LeafKind::Particle3d: return "particle3d";
    case LeafKind::Rigid2d: return "rigid2d";
    case LeafKind::Custom: return "custom";
    case LeafKind::Rigid2dNodal: return "rigid2d_nodal";
    case LeafKind::Rigid3d: return "rigid3d";
  }
  return "?";
}

namespace {

using ast::Statement;
using Kind = ast::Statement::Kind;

/// `global.NAME` names a parameter or input from anywhere (a body's own `u` cannot hide it).
constexpr const char* kGlobalScope = "global";
/// The one named constant of expressions (ExprConverter): no declaration may take it.
constexpr const char* kReservedConstant = "pi";

std::string join(const std::string& prefix, const std::string& name) {
  return prefix.empty() ? name : prefix + "." + name;
}

bool leaf_kind_from_name(const std::string& s, LeafKind& kind) {
  if (s == "particle2d") kind = LeafKind::Particle2d;
  else if (s == "particle3d") kind = LeafKind::Particle3d;
  else if (s == "rigid2d") kind = LeafKind::Rigid2d;
  else if (s == "custom") kind = LeafKind::Custom;
  else if (s == "rigid2d_nodal") kind = LeafKind::Rigid2dNodal;
  else if (s == "rigid3d") kind = LeafKind::Rigid3d;
  else return false;
  return true;
}

/// Per-node bookkeeping used only while building.
struct Pending {
  std::vector<ast::StatementPtr> body;
  const Statement* decl = nullptr;  // the subsystem statement (null for root)
};

class Builder {
  /// What a name in the table stands for, and (for "already declared" messages) what
  /// declared it and where.
  struct Entry {
    enum Kind { Time, Param, Input, Coord, Speed, NodeName, Formal, Let } kind;
    int index;
    GiNaC::symbol sym;
    std::string what = "";  // "a parameter", "a body", "the time variable"...
    SourcePos pos = {};     // where it is declared (line 0 for the time variable)
  };
 public:
  Builder(Diagnostics& diags, const std::map<std::string, double>& frozen) : diags_(diags), frozen_(frozen) {}

  std::optional<Model> run(const ast::File& file) {
    top_ = &file.statements;
    file_path_ = file.path;
    check_reserved_names(file.statements);
    if (diags_.has_errors()) return std::nullopt;  // (a name taken twice would also clash below)
    collect_globals(file.statements);
    if (diags_.has_errors()) return std::nullopt;
    // Pass A: nodes and variables, post-order.
    declare_node(file.statements, "", SourcePos{file.path, 1, 1}, nullptr, 0);
    check_gravity_size();
    check_frozen_names(file.path);
    if (diags_.has_errors()) return std::nullopt;
    // Bodies placed by spatial joints with coordinates: their attitude is the parent's
    // turned by the joint angle; set before pass B, whose joints and forces read it. It
    // needs the bodies' axes, so rigid3d geometry is read first in such models.
    if (!placements_.empty()) {
      for (size_t n = 0; n < m_.nodes.size(); ++n)
        if (m_.nodes[n].kind == LeafKind::Rigid3d) fill_rigid3d_geometry(static_cast<int>(n));
      place_joint_bodies();
    }
    // Pass B: expressions (everything is declared now).
    for (size_t n = 0; n < m_.nodes.size(); ++n) {
      checkpoint("building", fmt::format("subsystem '{}'", m_.label(static_cast<int>(n))), m_.nodes[n].pos, n,
                 m_.nodes.size());
      fill_node(static_cast<int>(n));
    }
    spatial_.finish();  // checks that need every element (a rotational spring's joint)
    if (diags_.has_errors()) return std::nullopt;
    solve_coordinate_rates();
    if (diags_.has_errors()) return std::nullopt;
    substitute_coordinate_rates();
    check_masses();
    if (diags_.has_errors()) return std::nullopt;
    return std::move(m_);
  }

 private:
  // ---- globals: model name, parameters, inputs, gravity, components ----
  void collect_globals(const std::vector<ast::StatementPtr>& stmts) {
    table_["t"] = Entry{Entry::Time, 0, m_.time, "the time variable"};
    for (const auto& s : stmts) {
      switch (s->kind) {
        case Kind::Model:
          if (!m_.name.empty()) diags_.error(s->pos, fmt::format("model name given twice ('{}' and '{}')", m_.name, s->name));
          m_.name = s->name;
          m_.name_pos = s->name_pos;
          break;
        case Kind::Parametrization:
          if (s->name != "absolute" && s->name != "nodal")
            diags_.error(s->name_pos, fmt::format("unknown parametrization '{}' (absolute or nodal)", s->name));
          else if (parametrization_pos_.line != 0)
            diags_.error(s->pos, "parametrization given twice");
          nodal_default_ = s->name == "nodal";
          parametrization_pos_ = s->pos;
          break;
        case Kind::Parameter: {
          if (!declare_global(s->name, s->name_pos, "parameter")) break;
          Variable v{s->name, 0, GiNaC::symbol(s->name), s->name_pos};
          double value = 0;
          if (!s->value) {
            diags_.error(s->name_pos, fmt::format("parameter '{}' needs a default value", s->name));
          } else {
            global_context_ = fmt::format("the default of parameter '{}'", s->name);
            ExprConverter conv = converter(-1);
            auto e = conv.convert(*s->value);
            if (e) {
              try {
                const GiNaC::ex numeric_value = substitute_param_defaults(*e);
                if (!evaluate_number(numeric_value, value))
                  diags_.error(s->value->pos, fmt::format("default value of parameter '{}' is not a number", s->name));
                else if (std::fabs(value) > limits::kMaxValue)  // a = 1e20, b = a*a
                  diags_.error(s->value->pos, fmt::format("default value of parameter '{}': {}", s->name,
                                                          ValueProblem::too_large(value).text()));
              } catch (const std::exception& ex) {
                diags_.error(s->value->pos,
                             fmt::format("default value of parameter '{}' is not a number: {}", s->name, ex.what()));
              }
            }
          }
          table_[s->name] = Entry{Entry::Param, static_cast<int>(m_.params.size()), v.sym, "a parameter", s->name_pos};
          m_.params.push_back(v);
          m_.param_defaults.push_back(value);
          param_values_[v.sym] = value;
          const auto frozen = frozen_.find(s->name);
          param_values_frozen_[v.sym] = frozen != frozen_.end() ? GiNaC::ex(exact_decimal(frozen->second)) : GiNaC::ex(value);
          break;
        }
        case Kind::Input: {
          if (!declare_global(s->name, s->name_pos, "input")) break;
          Variable v{s->name, 0, GiNaC::symbol(s->name), s->name_pos};
          table_[s->name] = Entry{Entry::Input, static_cast<int>(m_.inputs.size()), v.sym, "an input", s->name_pos};
          m_.inputs.push_back(v);
          break;
        }
        case Kind::Component:
          if (components_.count(s->name)) {
            const SourcePos& first = components_[s->name]->name_pos;
            diags_.error(s->name_pos, fmt::format("component '{}' is defined twice (first at {})", s->name,
                                                  position_text(first, s->name_pos)));
          } else {
            components_[s->name] = s.get();
          }
          break;
        case Kind::Gravity:
          if (gravity_stmt_) diags_.error(s->pos, "gravity given twice");
          gravity_stmt_ = s.get();
          break;
        case Kind::Ground:
          declare_ground(*s);
          break;
        default:
          break;
      }
    }
    // At the file's start, named even when it holds no statement (an empty file).
    if (m_.name.empty()) diags_.error(SourcePos{file_path_, 1, 1}, "missing 'model NAME' statement");
    if (gravity_stmt_) {
      m_.gravity_pos = gravity_stmt_->pos;
      global_context_ = "gravity";
      ExprConverter conv = converter(-1);
      for (const auto& g : gravity_stmt_->exprs) {
        auto e = conv.convert(*g);
        if (e) m_.gravity.push_back(*e);
      }
    }
  }

  /// The gravity vector must have the bodies' dimension: (gx, gy) when they are all planar,
  /// (gx, gy, gz) when one is spatial. Planar and spatial bodies may be mixed: then gravity
  /// has three components and the planar ones, moving in the x-y plane, feel (gx, gy).
  void check_gravity_size() {
    if (!gravity_stmt_) return;
    const Node* planar = nullptr;
    const Node* spatial = nullptr;
    for (const auto& n : m_.nodes) {
      if (!is_body(n.kind)) continue;
      const Node*& first = n.kind == LeafKind::Particle3d || n.kind == LeafKind::Rigid3d ? spatial : planar;
      if (!first) first = &n;
    }
    const std::size_t given = gravity_stmt_->exprs.size();
    if (spatial && given == 2)
      diags_.error(gravity_stmt_->pos,
                   fmt::format("gravity has 2 components, but body '{}' is {} (spatial): write gravity (gx, gy, gz)",
                               spatial->name, to_string(spatial->kind)));
    else if (planar && !spatial && given == 3)
      diags_.error(gravity_stmt_->pos,
                   fmt::format("gravity has 3 components, but the bodies are planar ({} '{}' moves in the x-y plane, "
                               "so gz would be ignored): write gravity (gx, gy)",
                               to_string(planar->kind), planar->name));
  }

  // ground { point NAME (x, y)  axis NAME (px, py) (dx, dy) }: fixed points and lines.
  void declare_ground(const Statement& g) {
    global_context_ = "the ground block";
    ExprConverter conv = converter(-1);
    for (const auto& sp : g.body) {
      const Statement& s = *sp;
      std::vector<GiNaC::ex> v;
      for (const auto& e : s.exprs) {
        auto c = conv.convert(*e);
        if (!c) break;
        v.push_back(*c);
      }
      if (v.size() != s.exprs.size()) {
        if (s.kind == Kind::Point || s.kind == Kind::Axis) {
          library_.add_failed(PlanarLibrary::kGround, s.name);
          spatial_.add_failed(PlanarLibrary::kGround, s.name);
        }
        continue;
      }
      // Three components (point) or six (axis: point, then direction) make a spatial
      // ground point or axis, which spatial joints name.
      if ((s.kind == Kind::Point && v.size() == 3) || (s.kind == Kind::Axis && v.size() == 6)) {
        if (s.kind == Kind::Point) spatial_.add_ground_point(s.name, v, s.name_pos);
        else spatial_.add_ground_axis(s.name, v, s.name_pos);
        continue;
      }
      if ((s.kind == Kind::Point && v.size() != 2) || (s.kind == Kind::Axis && v.size() != 4)) {
        diags_.error(s.pos, fmt::format("{} '{}' of the ground needs {} components: {}", s.kind == Kind::Point ? "point" : "axis",
                                        s.name, s.kind == Kind::Point ? "2 or 3" : "4 or 6",
                                        s.kind == Kind::Point ? "(x, y) in the plane or (x, y, z) in space"
                                                              : "(px, py) (dx, dy) in the plane or (px, py, pz) (dx, dy, dz) in space"));
        library_.add_failed(PlanarLibrary::kGround, s.name);
        continue;
      }
      if (s.kind == Kind::Point || s.kind == Kind::Axis) spatial_.add_planar_ground_name(s.name);
      if (s.kind == Kind::Point) library_.add_point(PlanarLibrary::kGround, s.name, v[0], v[1], s.name_pos);
      else if (s.kind == Kind::Axis) library_.add_axis(PlanarLibrary::kGround, s.name, v[0], v[1], v[2], v[3], s.name_pos);
      else diags_.error(s.pos, "only 'point' and 'axis' statements belong in 'ground'");
    }
  }

  /// The kind of name a statement declares ("parameter", "point"...), or nullptr.
  static const char* declared_kind(const Statement& s) {
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
  void check_reserved_names(const std::vector<ast::StatementPtr>& stmts) {
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

  /// Every --freeze name must be a parameter of the model (a typo would otherwise
  /// freeze nothing, silently).
  void check_frozen_names(const std::string& file) {
    std::vector<std::string> params;
    for (const auto& p : m_.params) params.push_back(p.name);
    for (const auto& [name, value] : frozen_) {
      const auto it = table_.find(name);
      if (it != table_.end() && it->second.kind == Entry::Param) {
        if (std::fabs(value) > limits::kMaxValue)  // the bound of the model's own values
          diags_.error(SourcePos{file, 0, 0}, fmt::format("--freeze {}={}: {}", name, value, ValueProblem::too_large(value).text()));
        continue;
      }
      const std::string is = it != table_.end() && !it->second.what.empty() ? fmt::format(" ('{}' is {})", name, it->second.what)
                                                                             : did_you_mean(name, params);
      diags_.error(SourcePos{file, 0, 0}, fmt::format("--freeze: model '{}' has no parameter '{}'{}", m_.name, name, is));
    }
  }

  /// The statement that declares `path` where the lets are not read yet (parameter
  /// defaults, gravity, the ground): a let (at the top or in a subsystem, by its dotted
  /// path), or a parameter or input declared further down. Nullptr when there is none.
  const Statement* not_yet_declared(const std::string& path, const SourcePos& use) const {
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

  bool declare_global(const std::string& name, const SourcePos& pos, const char* what) {
    if (name == "t") {
      diags_.error(pos, fmt::format("{} 't' clashes with the time variable", what));
      return false;
    }
    auto it = table_.find(name);
    if (it != table_.end()) {
      diags_.error(pos, fmt::format("{} '{}' is already declared{}", what, name, declared_as(it->second, pos)));
      return false;
    }
    return true;
  }

  /// " as a parameter at 3:11" (the file too when it is another one), " as the time variable".
  static std::string declared_as(const Entry& e, const SourcePos& here) {
    if (e.what.empty()) return "";
    return fmt::format(" as {}{}", e.what, e.pos.line > 0 ? " at " + position_text(e.pos, here) : "");
  }

  /// "3:11", or "other.mbs:3:11" when `pos` is in another file than `here`.
  static std::string position_text(const SourcePos& pos, const SourcePos& here) {
    return fmt::format("{}{}:{}", pos.file == here.file ? "" : pos.file + ":", pos.line, pos.col);
  }

  /// e with every parameter replaced by its value: the default, or (with_frozen) the
  /// --freeze value. Guarded (exact_guard.hpp), and only the symbols e holds are looked
  /// up: `parameter a = 3, n = 1e12` with `mass a^n` must not fold 3^(10^12), and 10 000
  /// parameters stay linear. Throws std::runtime_error when the result would be undefined
  /// or too large to fold.
  GiNaC::ex substitute_param_defaults(const GiNaC::ex& e, bool with_frozen = false) const {
    if (GiNaC::is_a<GiNaC::numeric>(e)) return e;
    std::string why;
    auto out = guarded_subs(e, with_frozen ? param_values_frozen_ : param_values_, why);
    if (!out) throw std::runtime_error(why);
    return *out;
  }

  // ---- pass A: declare nodes and their variables (post-order) ----
  int declare_node(const std::vector<ast::StatementPtr>& body, const std::string& prefix, const SourcePos& pos,
                   const Statement* decl, int depth) {
    if (depth > 64) {
      diags_.error(pos, fmt::format("subsystem '{}' nests too deeply (recursive component?)", prefix));
      return -1;
    }
    // Components that each hold two instances of the next one double the tree at every
    // level: bound the count, not only the depth.
    if (++declared_nodes_ > limits::kMaxNodes) {
      if (declared_nodes_ == limits::kMaxNodes + 1)
        diags_.error(pos, fmt::format("the model has more than {} subsystems (components instantiated many times "
                                      "over?); stopped at '{}'",
                                      limits::kMaxNodes, prefix));
      return -1;
    }
    checkpoint("declaring", fmt::format("subsystem '{}'", prefix.empty() ? std::string("<top>") : prefix), pos,
               declared_nodes_, 0);
    Node node;
    node.name = prefix;
    node.pos = pos;
    if (decl && !decl->kind_name.empty()) {
      LeafKind kind;
      if (leaf_kind_from_name(decl->kind_name, kind)) {
        // `parametrization nodal` makes every plain rigid2d body a nodal one.
        node.kind = kind == LeafKind::Rigid2d && nodal_default_ ? LeafKind::Rigid2dNodal : kind;
        if (!decl->exprs.empty())
          diags_.error(decl->kind_pos, fmt::format("leaf kind '{}' of subsystem '{}' takes no arguments", decl->kind_name, prefix));
      } else if (components_.count(decl->kind_name)) {
        node.component = decl->kind_name;
      } else {
        diags_.error(decl->kind_pos, unknown_kind_message(prefix, decl->kind_name));
        return -1;
      }
    }
    // Children first (post-order).
    std::vector<int> children;
    std::vector<ast::StatementPtr> own_body = body;
    if (!node.component.empty()) {
      const Statement* comp = components_.at(node.component);
      if (comp->formals.size() != decl->exprs.size()) {
        diags_.error(decl->kind_pos, fmt::format("component '{}' takes {} argument(s), subsystem '{}' gives {}", node.component,
                                                 comp->formals.size(), prefix, decl->exprs.size()));
        return -1;
      }
      own_body = comp->body;
      own_body.insert(own_body.end(), body.begin(), body.end());
      for (size_t i = 0; i < comp->formals.size(); ++i) {
        std::string full = join(prefix, comp->formals[i]);
        if (!declare_local(full, comp->formal_pos[i], "formal parameter")) continue;
        GiNaC::symbol sym(full);
        table_[full] = Entry{Entry::Formal, 0, sym, "a component parameter", comp->formal_pos[i]};
        formal_args_.push_back({full, decl->exprs[i], prefix});
        m_.formals[full] = Formal{sym, 0};
      }
    }
    scopes_.push_back({prefix, &own_body});
    for (const auto& s : own_body) {
      if (s->kind != Kind::Subsystem) continue;
      std::string child = join(prefix, s->name);
      if (s->name == kGlobalScope) {
        diags_.error(s->name_pos, fmt::format("'{0}' cannot name a subsystem: it names the model's global scope "
                                              "('{0}.g' is the parameter g)",
                                              kGlobalScope));
        continue;
      }
      LeafKind leaf;
      const bool body = leaf_kind_from_name(s->kind_name, leaf) && leaf != LeafKind::Custom;
      if (!declare_local(child, s->name_pos, body ? "body" : "subsystem")) continue;
      table_[child] = Entry{Entry::NodeName, 0, GiNaC::symbol(), body ? "a body" : "a subsystem", s->name_pos};
      int c = declare_node(s->body, child, s->name_pos, s.get(), depth + 1);
      if (c >= 0) children.push_back(c);
    }
    scopes_.pop_back();
    const int id = static_cast<int>(m_.nodes.size());
    node.children = children;
    m_.nodes.push_back(node);
    pending_.push_back(Pending{own_body, decl});
    for (int c : children) m_.nodes[c].parent = id;
    // Leaf kinds bring their variables: coordinates with speeds defined as their rates.
    const char* const planar[] = {"x", "y"};
    const char* const spatial[] = {"x", "y", "z"};
    const char* const rigid[] = {"x", "y", "theta"};
    const char* const speeds2[] = {"u", "v"};
    const char* const speeds3[] = {"u", "v", "w"};
    auto add_kinematic = [&](const char* const* qs, const char* const* us, int n) {
      for (int i = 0; i < n; ++i) {
        int q = add_variable(id, join(prefix, qs[i]), pos, /*coordinate=*/true, /*builtin=*/true);
        int u = add_variable(id, join(prefix, us[i]), pos, /*coordinate=*/false, /*builtin=*/true);
        if (q >= 0 && u >= 0) builtin_rates_[q] = m_.speeds[u].sym;
      }
    };
    switch (m_.nodes[id].kind) {
      case LeafKind::Particle2d: add_kinematic(planar, speeds2, 2); break;
      case LeafKind::Particle3d: add_kinematic(spatial, speeds3, 3); break;
      case LeafKind::Rigid2d: add_kinematic(rigid, speeds3, 3); break;
      case LeafKind::Rigid2dNodal: {
        // Nodal coordinates: each point P brings P_x, P_y with rates P_u, P_v; then the
        // angular speed w (no coordinate of its own).
        int npoints = 0;
        for (const auto& s : own_body) {
          if (s->kind != Kind::Point) continue;
          ++npoints;
          const std::string qx = s->name + "_x", qy = s->name + "_y", ux = s->name + "_u", uy = s->name + "_v";
          const char* const qs[] = {qx.c_str(), qy.c_str()};
          const char* const us[] = {ux.c_str(), uy.c_str()};
          add_kinematic(qs, us, 2);
        }
        add_variable(id, join(prefix, "w"), pos, /*coordinate=*/false, /*builtin=*/true);
        if (npoints < 2)
          diags_.error(pos, fmt::format("rigid2d_nodal body '{}' needs at least two points (its nodes); it has {}", prefix,
                                        npoints));
        break;
      }
      case LeafKind::Rigid3d: declare_rigid3d(id, prefix, pos, own_body); break;
      default: break;
    }
    // Declared coordinates and speeds, and named expressions.
    for (const auto& s : own_body) {
      if (s->kind == Kind::Coordinate) add_variable(id, join(prefix, s->name), s->name_pos, true);
      if (s->kind == Kind::Speed) add_variable(id, join(prefix, s->name), s->name_pos, false);
      if (s->kind == Kind::Let) declare_let(id, join(prefix, s->name), *s);
      if (s->kind == Kind::Joint && !s->joint_coordinate.text.empty()) declare_joint_coordinate(id, prefix, *s);
      if (s->kind == Kind::Joint && s->kind_name == "rolling_sphere") declare_contact_coordinates(id, prefix, *s);
    }
    return id;
  }

  /// A rigid3d leaf's variables (model.hpp Rigid3dData): x, y, z and the attitude
  /// coordinates, u, v, w and wx, wy, wz; the attitude's rates are the kinematic
  /// equations in the angular speeds (model/rigid3d.hpp), its rotation matrix kept for
  /// forces, energy and joints. `attitude` chooses; the default is a unit quaternion with
  /// body-frame angular speeds.
  void declare_rigid3d(int id, const std::string& prefix, const SourcePos& pos, const std::vector<ast::StatementPtr>& body) {
    Rigid3dData data;
    data.sequence = "quaternion";
    const Statement* placing = placing_joint(id, prefix);
    const Statement* given = nullptr;
    for (const auto& s : body) {
      if (s->kind != Kind::Attitude) continue;
      if (placing) {
        diags_.error(s->pos, fmt::format("body '{}' is placed by joint '{}' with coordinate '{}' (at {}): its attitude is "
                                         "its parent's turned by that angle, so it takes no 'attitude' statement",
                                         prefix, placing->name, placing->joint_coordinate.text,
                                         position_text(placing->pos, s->pos)));
        return;
      }
      if (given) {
        diags_.error(s->pos, fmt::format("attitude of body '{}' is given twice (first at {})", prefix,
                                         position_text(given->pos, s->pos)));
        continue;
      }
      given = s.get();
      if (s->name == "euler") {
        if (!rigid3d::valid_sequence(s->path.text)) {
          diags_.error(s->path.pos, fmt::format("'{}' is not an Euler sequence (body '{}'): write three axes of x, y, z "
                                                "with no axis twice in a row, e.g. zyx, zxz, xyz",
                                                s->path.text, prefix));
          return;
        }
        data.sequence = s->path.text;
      } else if (s->name != "quaternion") {
        diags_.error(s->name_pos, fmt::format("unknown attitude '{}' of body '{}' (quaternion or euler SEQUENCE)", s->name,
                                              prefix));
        return;
      }
      data.space_frame = s->option2.text == "space";
    }
    if (placing) {
      data.sequence = "joint";
      data.joint_name = placing->name;
    }
    const bool quaternion = data.sequence == "quaternion";
    const char* const position[] = {"x", "y", "z"};
    const char* const velocity[] = {"u", "v", "w"};
    std::vector<int> q, u;
    for (int i = 0; i < 3; ++i) q.push_back(add_variable(id, join(prefix, position[i]), pos, true, true));
    const std::vector<const char*> attitude = placing      ? std::vector<const char*>{}
                                              : quaternion ? std::vector<const char*>{"e0", "e1", "e2", "e3"}
                                                           : std::vector<const char*>{"phi", "theta", "psi"};
    for (const char* a : attitude) q.push_back(add_variable(id, join(prefix, a), pos, true, true));
    for (int i = 0; i < 3; ++i) u.push_back(add_variable(id, join(prefix, velocity[i]), pos, false, true));
    for (const char* w : {"wx", "wy", "wz"}) u.push_back(add_variable(id, join(prefix, w), pos, false, true));
    for (int i : q)
      if (i < 0) return;  // a name declared twice (reported)
    for (int i : u)
      if (i < 0) return;
    rigid3d::Vec a, w;
    for (std::size_t k = 3; k < q.size(); ++k) a.push_back(m_.coords[static_cast<std::size_t>(q[k])].sym);
    for (int k = 3; k < 6; ++k) w.push_back(m_.speeds[static_cast<std::size_t>(u[k])].sym);
    for (int k = 0; k < 3; ++k) builtin_rates_[q[k]] = m_.speeds[static_cast<std::size_t>(u[k])].sym;
    if (placing) {  // the rotation is set once the parent's is known (place_joint_bodies)
      m_.nodes[id].rigid3d = data;
      return;
    }
    const rigid3d::Vec rates =
        quaternion ? rigid3d::quaternion_rates(a, w, data.space_frame) : rigid3d::euler_rates(data.sequence, a, w, data.space_frame);
    for (std::size_t k = 0; k < rates.size(); ++k) builtin_rates_[q[3 + k]] = rates[k];
    data.rotation = quaternion ? rigid3d::quaternion_rotation(a) : rigid3d::euler_rotation(data.sequence, a);
    m_.nodes[id].rigid3d = data;
  }

  /// The joint with a coordinate that places rigid3d body `prefix`, if any: a revolute
  /// joint written in an enclosing subsystem (or the top level) whose second end is one
  /// of this body's axes, its path resolved as body() resolves it (inner scopes first).
  /// Every such joint is recorded (placements_); the first is returned.
  const Statement* placing_joint(int id, const std::string& prefix) {
    const Statement* first = nullptr;
    for (std::size_t k = scopes_.size(); k-- > 0;) {
      for (const auto& s : *scopes_[k].second) {
        if (s->kind != Kind::Joint || s->joint_coordinate.text.empty() || s->kind_name != "revolute" || s->paths.size() < 2)
          continue;
        const std::string& end = s->paths[1].text;
        const auto dot = end.rfind('.');
        if (dot == std::string::npos) continue;
        const std::string path = end.substr(0, dot);
        for (std::size_t j = k + 1; j-- > 0;) {
          if (join(scopes_[j].first, path) != prefix) continue;
          placements_.push_back({id, s.get(), scopes_[k].first});
          if (!first) first = s.get();
          break;
        }
      }
    }
    return first;
  }

  /// Points, axes and com of a rigid3d body (pass B's statements, read early in models
  /// with placed bodies: the joints' axes give the placed bodies' attitudes).
  void fill_rigid3d_geometry(int id) {
    for (const auto& sp : pending_[static_cast<std::size_t>(id)].body)
      if (sp->kind == Kind::Point || sp->kind == Kind::Com || sp->kind == Kind::Axis) {
        element_ = element_of(*sp, id);
        fill_geometry(id, *sp);
      }
    element_.clear();
    geometry_done_.insert(id);
  }

  /// Every placement, parents before their children; a body placed twice, or placements
  /// in a loop, are errors.
  void place_joint_bodies() {
    std::map<int, const Placement*> by_child;
    for (const auto& p : placements_) {
      const auto [it, fresh] = by_child.emplace(p.child, &p);
      if (fresh) continue;
      const Statement* first = it->second->joint;
      diags_.error(p.joint->pos, fmt::format("joint '{}': body '{}' is already placed by joint '{}' (at {}); a body is the "
                                             "second end of at most one joint with a coordinate (close a loop with a "
                                             "joint without one)",
                                             p.joint->name, m_.nodes[p.child].name, first->name,
                                             position_text(first->pos, p.joint->pos)));
    }
    std::vector<const Placement*> todo;
    for (const auto& [child, p] : by_child) todo.push_back(p);
    bool failed = false;
    while (!todo.empty()) {
      std::vector<const Placement*> later;
      for (const Placement* p : todo) {
        // The node the joint is written in: the one of that name holding the statement
        // (every instance of a component holds the same statements).
        int owner = -1;
        for (std::size_t n = 0; n < pending_.size() && owner < 0; ++n) {
          if (m_.nodes[n].name != p->owner) continue;
          for (const auto& sp : pending_[n].body)
            if (sp.get() == p->joint) owner = static_cast<int>(n);
        }
        const auto jv = joint_variables_.find({owner, p->joint});
        if (owner < 0 || jv == joint_variables_.end()) {  // its coordinate failed (reported)
          failed = true;
          continue;
        }
        const auto r = spatial_.place(owner, placement_element(*p->joint, jv->second), p->child);
        if (r == SpatialLibrary::Placed::Later) later.push_back(p);
        failed = failed || r == SpatialLibrary::Placed::Failed;
      }
      if (later.size() == todo.size()) {
        // Nothing placed in this round: a loop, unless a placement failed (reported),
        // which leaves the bodies below it waiting.
        if (!failed)
          for (const Placement* p : later)
            diags_.error(p->joint->pos, fmt::format("joint '{}': joints with coordinates would form a loop through '{}'; "
                                                    "close the loop with a joint without a coordinate",
                                                    p->joint->name, m_.nodes[p->child].name));
        break;
      }
      todo = later;
    }
  }

  PlanarLibrary::Element placement_element(const Statement& s, std::pair<int, int> variables) const {
    PlanarLibrary::Element e;
    e.name = s.name;
    e.kind = s.kind_name;
    e.pos = s.pos;
    e.kind_pos = s.kind_pos;
    e.end1 = s.paths[0].text;
    e.end1_pos = s.paths[0].pos;
    e.end2 = s.paths[1].text;
    e.end2_pos = s.paths[1].pos;
    e.coordinate = variables.first;
    e.coordinate_speed = variables.second;
    e.coordinate_pos = s.joint_coordinate.pos;
    return e;
  }

  /// `joint ... coordinate q [speed s]`: the joint's relative coordinate q and its rate s
  /// (default q_dot, s = q') become variables of the node the joint is written at.
  void declare_joint_coordinate(int id, const std::string& prefix, const Statement& s) {
    const std::string speed = s.joint_speed.text.empty() ? s.joint_coordinate.text + "_dot" : s.joint_speed.text;
    const SourcePos speed_pos = s.joint_speed.text.empty() ? s.joint_coordinate.pos : s.joint_speed.pos;
    const int q = add_variable(id, join(prefix, s.joint_coordinate.text), s.joint_coordinate.pos, /*coordinate=*/true);
    const int u = add_variable(id, join(prefix, speed), speed_pos, /*coordinate=*/false);
    if (q < 0 || u < 0) return;  // reported: a name declared twice
    const std::string joint = s.name.empty() ? std::string("joint") : fmt::format("joint '{}'", s.name);
    table_[join(prefix, s.joint_coordinate.text)].what = "the coordinate of " + joint;
    table_[join(prefix, speed)].what = "the speed of " + joint;
    builtin_rates_[q] = m_.speeds[static_cast<std::size_t>(u)].sym;
    joint_variables_[{id, &s}] = {q, u};
  }

  /// `joint NAME : rolling_sphere ...`: the contact point's x and y on the surface are two
  /// coordinates NAME.xc, NAME.yc of the node the joint is written at, with their rates
  /// NAME.xc_dot, NAME.yc_dot as speeds (formulation.md, "A sphere rolling on a surface").
  void declare_contact_coordinates(int id, const std::string& prefix, const Statement& s) {
    if (s.name.empty()) {
      // Its contact coordinates are named after it (and `initial` places them by name).
      diags_.error(s.kind_pos, "a rolling_sphere joint needs a name (`joint NAME : rolling_sphere ...`): its contact "
                               "coordinates are NAME.xc and NAME.yc");
      return;
    }
    const std::string& joint = s.name;
    const SourcePos pos = s.name_pos;
    std::vector<int> qs;
    for (const char* c : {"xc", "yc"}) {
      const std::string q_name = join(prefix, joint + "." + c);
      const int q = add_variable(id, q_name, pos, /*coordinate=*/true);
      const int u = add_variable(id, q_name + "_dot", pos, /*coordinate=*/false);
      if (q < 0 || u < 0) return;  // reported: a name declared twice
      table_[q_name].what = fmt::format("a contact coordinate of joint '{}'", joint);
      table_[q_name + "_dot"].what = fmt::format("a contact speed of joint '{}'", joint);
      builtin_rates_[q] = m_.speeds[static_cast<std::size_t>(u)].sym;
      qs.push_back(q);
    }
    contact_coordinates_[{id, &s}] = qs;
  }

  /// A rolling_sphere's surface gamma(x, y): the names x and y are the contact point's
  /// coordinates, any other name is looked up as usual (parameters; the joint checks that
  /// nothing else of the state is read).
  std::optional<GiNaC::ex> convert_surface(int node, const ast::ExprPtr& e, const std::vector<int>& contact) {
    allow_speeds_ = allow_coord_rate_ = allow_speed_rate_ = false;
    ExprConverter conv = converter(node);
    const GiNaC::ex xc = m_.coords[static_cast<std::size_t>(contact[0])].sym;
    const GiNaC::ex yc = m_.coords[static_cast<std::size_t>(contact[1])].sym;
    auto outer = conv.lookup;
    conv.lookup = [outer, xc, yc](const std::string& path, const SourcePos& pos, bool primed) -> std::optional<GiNaC::ex> {
      if (!primed && path == "x") return xc;
      if (!primed && path == "y") return yc;
      return outer(path, pos, primed);
    };
    return conv.convert(*e);
  }

  /// "unknown kind", with the close name if any, the leaf kinds and the components.
  std::string unknown_kind_message(const std::string& subsystem, const std::string& kind) const {
    std::vector<std::string> kinds;
    for (LeafKind k : {LeafKind::Particle2d, LeafKind::Particle3d, LeafKind::Rigid2d, LeafKind::Rigid2dNodal,
                       LeafKind::Rigid3d, LeafKind::Custom})
      kinds.push_back(to_string(k));
    std::vector<std::string> components, all = kinds;
    for (const auto& [name, stmt] : components_) components.push_back(name);
    all.insert(all.end(), components.begin(), components.end());
    // A file of thousands of components lists the first few (alphabetically) and a count.
    constexpr std::size_t kListed = 12;
    const std::size_t more = components.size() > kListed ? components.size() - kListed : 0;
    components.resize(components.size() - more);
    if (more > 0) components.push_back(fmt::format("{} more", more));
    return fmt::format("subsystem '{}' has unknown kind or component '{}'{}; the leaf kinds are {}{}", subsystem, kind,
                       did_you_mean(kind, all), list_names(kinds),
                       components.empty() ? std::string(" (no component is defined)")
                                          : fmt::format(", the components {}", list_names(components)));
  }

  bool declare_local(const std::string& full, const SourcePos& pos, const char* what) {
    auto it = table_.find(full);
    if (it != table_.end()) {
      diags_.error(pos, fmt::format("{} '{}' is already declared{}", what, full, declared_as(it->second, pos)));
      return false;
    }
    return true;
  }

  void declare_let(int node, const std::string& full, const Statement& s) {
    if (!declare_local(full, s.name_pos, "let")) return;
    table_[full] = Entry{Entry::Let, lets_.declare(full, node, s), GiNaC::symbol(), "a let", s.name_pos};
    if (s.value) let_names_[s.value.get()] = full;
  }

  /// A let's value in the scope of `node`, every level allowed (each use checks its own).
  std::optional<GiNaC::ex> convert_let(int node, const ast::Expr& e) {
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

  /// A coordinate or speed; `builtin` for those a leaf kind brings (declared at the body).
  int add_variable(int node, const std::string& full, const SourcePos& pos, bool coordinate, bool builtin = false) {
    if (!declare_local(full, pos, coordinate ? "coordinate" : "speed")) return -1;
    const std::string what = fmt::format("{}{}", coordinate ? "a coordinate" : "a speed",
                                         builtin ? fmt::format(" of the {} body", to_string(m_.nodes[node].kind)) : "");
    Variable v{full, node, GiNaC::symbol(full), pos};
    if (coordinate) {
      int i = static_cast<int>(m_.coords.size());
      m_.coords.push_back(v);
      m_.nodes[node].coords.push_back(i);
      coord_dot_.push_back(GiNaC::symbol(full + "'"));
      table_[full] = Entry{Entry::Coord, i, v.sym, what, pos};
      return i;
    }
    int i = static_cast<int>(m_.speeds.size());
    m_.speeds.push_back(v);
    m_.speed_dots.push_back(GiNaC::symbol(full + "'"));
    m_.nodes[node].speeds.push_back(i);
    table_[full] = Entry{Entry::Speed, i, v.sym, what, pos};
    return i;
  }

  // ---- pass B: expressions of each node ----
  ExprConverter converter(int node) {
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
  std::optional<GiNaC::ex> resolve(const std::string& path, const SourcePos& pos, int node, bool primed) {
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

  static bool is_global(const Entry& e) { return e.kind == Entry::Param || e.kind == Entry::Input || e.kind == Entry::Time; }
  static const char* global_kind_name(const Entry& e) {
    return e.kind == Entry::Param ? "parameter" : e.kind == Entry::Input ? "input" : "time";
  }

  /// Whether the entry may be used here (the allow_ flags of the expression being converted).
  bool allowed(const Entry& e, bool primed) const {
    switch (e.kind) {
      case Entry::NodeName: return false;
      case Entry::Coord: return !primed || allow_coord_rate_;
      case Entry::Speed: return primed ? allow_speed_rate_ : allow_speeds_;
      default: return !primed;
    }
  }

  /// The value of a resolved name, or the error that says why it is not allowed here.
  std::optional<GiNaC::ex> value_of(const Entry& found, const std::string& full, const std::string& path,
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
  std::string suggestion(const std::string& written, int node, bool variables_only) const {
    if (diags_.all().size() >= Diagnostics::kMaxShown) return "";
    return did_you_mean(written, names_in_scope(node, variables_only));
  }

  /// The names that resolve when written at `node`: relative to each enclosing scope,
  /// innermost first (then every full path and global, from the top), `pi` among them;
  /// with `variables_only` just coordinates and speeds. For "did you mean" suggestions.
  std::vector<std::string> names_in_scope(int node, bool variables_only) const {
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

  std::optional<GiNaC::ex> convert(int node, const ast::ExprPtr& e, bool speeds, bool coord_rates, bool speed_rates) {
    allow_speeds_ = speeds;
    allow_coord_rate_ = coord_rates;
    allow_speed_rate_ = speed_rates;
    ExprConverter conv = converter(node);
    return conv.convert(*e);
  }

  void fill_node(int id) {
    const int errors_before = diags_.error_count();
    Node& node = m_.nodes[id];
    const Pending& pend = pending_[id];
    const bool body_kind = is_body(node.kind);
    int nconstraint = 0;
    for (const auto& sp : pend.body) {
      const Statement& s = *sp;
      element_ = element_of(s, id);
      switch (s.kind) {
        case Kind::Speed:
          if (s.value) {
            auto e = convert(id, s.value, false, true, false);
            int u = table_.at(join(node.name, s.name)).index;
            if (e) definitions_.push_back({u, *e, s.value->pos});
          }
          break;
        case Kind::Constraint:
          for (const auto& eq : s.equations) {
            ++nconstraint;
            bool velocity = s.level == "velocity";
            auto lhs = convert(id, eq.lhs, velocity, velocity, false);
            auto rhs = convert(id, eq.rhs, velocity, velocity, false);
            if (!lhs || !rhs) continue;
            Constraint c;
            c.name = eq.label.empty() ? fmt::format("{}{}[{}]", node.name.empty() ? "" : node.name + ".", s.level, nconstraint)
                                      : join(node.name, eq.label);
            c.node = id;
            c.level = velocity ? Constraint::Level::Velocity : Constraint::Level::Position;
            c.nonlinear = s.nonlinear;
            c.residual = *lhs - *rhs;
            c.pos = eq.pos;
            if (!velocity && s.nonlinear)
              diags_.error(s.pos, "'nonlinear' applies to velocity constraints only (position constraints may be nonlinear)");
            node.constraints.push_back(static_cast<int>(m_.constraints.size()));
            m_.constraints.push_back(c);
          }
          break;
        case Kind::Force: {
          auto target = lookup_variable(id, s.path);
          if (!target) break;
          if (target->first) {
            diags_.error(s.path.pos, fmt::format("force target '{}' is a coordinate; forces act along speeds", s.path.text));
            break;
          }
          auto e = convert(id, s.value, true, false, node.kind == LeafKind::Custom);
          if (e) m_.forces.push_back(Force{target->second, *e, s.pos});
          break;
        }
        case Kind::Torque:
          add_rigid3d_torque(id, s);
          break;
        case Kind::Attitude:
          if (node.kind != LeafKind::Rigid3d)
            diags_.error(s.pos, fmt::format("'attitude' is only allowed in rigid3d bodies ('{}' is {})", m_.label(id),
                                            to_string(node.kind)));
          break;
        case Kind::Mass:
        case Kind::Inertia: {
          if (!body_kind) {
            diags_.error(s.pos, fmt::format("'{}' is only allowed in particle2d, particle3d, rigid2d and rigid3d bodies",
                                            s.kind == Kind::Mass ? "mass" : "inertia"));
            break;
          }
          if (s.kind == Kind::Inertia && node.kind == LeafKind::Rigid3d) {
            fill_rigid3d_inertia(id, s);
            break;
          }
          if (s.kind == Kind::Inertia && !s.exprs.empty()) {
            inertia_given_.insert(id);  // (reported here, not as missing)
            diags_.error(s.pos, fmt::format("'inertia' of {} body '{}' is one value (a list of tensor entries is for "
                                            "rigid3d bodies)",
                                            to_string(node.kind), node.name));
            break;
          }
          if (s.kind == Kind::Inertia && !is_rigid2d(node.kind)) {
            diags_.error(s.pos, fmt::format("'inertia' is only allowed in rigid2d bodies ('{}' is {})", node.name, to_string(node.kind)));
            break;
          }
          (s.kind == Kind::Mass ? mass_given_ : inertia_given_).insert(id);  // even if its value fails below
          // Speeds are let through here so that check_masses names them with the rest of
          // what may not vary (a coordinate, an input, t).
          auto e = convert(id, s.value, true, false, false);
          if (!e) break;
          if (s.kind == Kind::Mass) {
            node.mass = *e;
            node.mass_pos = s.value->pos;
            has_mass_.insert(id);
          } else {
            node.inertia = *e;
            node.inertia_pos = s.value->pos;
            inertia_pos_[id] = s.value->pos;
          }
          break;
        }
        case Kind::Kinetic: {
          auto e = convert(id, s.value, true, false, false);
          if (e) {
            node.kinetic = *e;
            node.has_kinetic = true;
          }
          break;
        }
        case Kind::Potential: {
          auto e = convert(id, s.value, false, false, false);
          if (e) node.potential += *e;  // several terms add up (library springs add theirs too)
          break;
        }
        case Kind::Independent:
        case Kind::Alternative: {
          std::vector<int> set;
          for (const auto& p : s.paths) {
            auto v = lookup_variable(id, p);
            if (!v) continue;
            if (v->first) {
              diags_.error(p.pos, fmt::format("{} variable '{}' is a coordinate; name its speed",
                                              s.kind == Kind::Independent ? "independent" : "alternative", p.text));
              continue;
            }
            set.push_back(v->second);
          }
          if (s.kind == Kind::Independent) {
            node.independent_pos = s.pos;
            node.independent.insert(node.independent.end(), set.begin(), set.end());
          } else {
            node.alternatives.push_back(set);
            node.alternative_pos.push_back(s.pos);
          }
          break;
        }
        case Kind::Output:
          if (!s.value) {
            if (id != m_.root()) {
              diags_.error(s.pos, "'output energy' is only allowed at the top level");
            } else {
              m_.output_energy = true;
            }
          } else {
            auto e = convert(id, s.value, true, false, false);
            std::string name = join(node.name, s.name);
            if (const auto [first, fresh] = output_names_.emplace(name, s.name_pos); !fresh) {
              diags_.error(s.name_pos, fmt::format("output '{}' is already declared at {}", name,
                                                   position_text(first->second, s.name_pos)));
            } else if (e) {
              m_.outputs.push_back(NamedExpr{name, *e, s.pos});
            }
          }
          break;
        case Kind::Model:
        case Kind::Parameter:
        case Kind::Input:
        case Kind::Component:
        case Kind::Gravity:
        case Kind::Parametrization:
          if (id != m_.root())
            diags_.error(s.pos, "model, parameter, input, component, gravity and parametrization statements belong at the "
                                "top level");
          break;
        case Kind::Include:
          diags_.error(s.pos, "include is only allowed at the top level of a file");
          break;
        case Kind::Subsystem:
        case Kind::Coordinate:
          break;
        case Kind::Let: {
          // Converted here even when unused, so a mistake in it is reported.
          const auto it = table_.find(join(node.name, s.name));
          if (it != table_.end() && it->second.kind == Entry::Let) lets_.define(it->second.index);
          break;
        }
        case Kind::Ground:
          if (id != m_.root()) diags_.error(s.pos, "'ground' belongs at the top level");
          break;
        case Kind::Latex:
          set_latex_symbol(id, s);
          break;
        case Kind::Initial:
          set_initial_value(id, s);
          break;
        case Kind::Point:
        case Kind::Com:
        case Kind::Axis:
          if (!geometry_done_.count(id)) fill_geometry(id, s);
          break;
        case Kind::Joint:
        case Kind::Spring:
        case Kind::Damper: {
          PlanarLibrary::Element e;
          e.name = s.name;
          e.kind = s.kind == Kind::Joint ? s.kind_name : s.kind == Kind::Spring ? "spring" : "damper";
          if (s.kind != Kind::Joint && s.kind_name == "rotational") e.kind = "rotational_" + e.kind;
          e.pos = s.pos;
          e.kind_pos = s.kind == Kind::Joint ? s.kind_pos : s.pos;
          e.end1 = s.paths[0].text;
          e.end1_pos = s.paths[0].pos;
          e.end2 = s.paths[1].text;
          e.end2_pos = s.paths[1].pos;
          if (s.paths.size() > 2) {  // knife_edge BODY [point P] [axis A]
            e.end3 = s.paths[2].text;
            e.end3_pos = s.paths[2].pos;
          }
          e.option = s.kind == Kind::Joint ? s.level : "";
          e.option_pos = s.path.pos;
          if (!s.joint_coordinate.text.empty()) {
            const auto jv = joint_variables_.find({id, &s});
            if (jv == joint_variables_.end()) break;  // its declaration failed (reported)
            e.coordinate = jv->second.first;
            e.coordinate_speed = jv->second.second;
            e.coordinate_pos = s.joint_coordinate.pos;
          }
          if (s.kind == Kind::Joint && s.kind_name == "rolling_sphere") {
            const auto cc = contact_coordinates_.find({id, &s});
            if (cc == contact_coordinates_.end()) break;  // its declaration failed (reported)
            e.contact = cc->second;
            // The surface expression reads x and y (the contact point); the radius is a constant.
            bool ok = true;
            if (s.value) {
              auto v = s.level == "surface" ? convert_surface(id, s.value, e.contact) : convert(id, s.value, false, false, false);
              if (v) e.value = *v;
              else ok = false;
            }
            if (!s.exprs.empty()) {
              e.option2 = s.option2.text;
              e.option2_pos = s.option2.pos;
              auto v = s.option2.text == "surface" ? convert_surface(id, s.exprs[0], e.contact)
                                                   : convert(id, s.exprs[0], false, false, false);
              if (v) e.value2 = *v;
              else ok = false;
            }
            if (ok) spatial_.add_element(id, e);
            break;
          }
          // Actuator values may read the state and inputs; spring and damper data are constants.
          const bool actuator = s.kind == Kind::Joint && s.level != "angle" && s.level != "ratio" && s.level != "radius" &&
                                s.level != "ring";
          if (s.value) {
            auto v = convert(id, s.value, actuator, false, false);
            if (!v) break;
            e.value = *v;
          }
          if (!s.exprs.empty()) {
            // A second actuator (a cylindrical joint's force and torque) may read the state too.
            const bool actuator2 = s.kind == Kind::Joint && (s.option2.text == "torque" || s.option2.text == "force" ||
                                                                 s.option2.text == "friction");
            auto v = convert(id, s.exprs[0], actuator2, false, false);
            if (!v) break;
            if (s.kind == Kind::Joint) {
              e.option2 = s.option2.text;
              e.option2_pos = s.option2.pos;
              e.value2 = *v;
            } else {
              e.length = *v;
            }
          }
          if (spatial_.claims(id, e)) spatial_.add_element(id, e);
          else library_.add_element(id, e);
          break;
        }
      }
    }
    element_.clear();
    // (A mass or inertia statement whose value failed is reported there, not as missing.)
    if (body_kind && !mass_given_.count(id)) diags_.error(node.pos, fmt::format("body '{}' has no mass", node.name));
    if ((is_rigid2d(node.kind) || node.kind == LeafKind::Rigid3d) && !inertia_given_.count(id))
      diags_.error(node.pos, fmt::format("{} body '{}' has no inertia", to_string(node.kind), node.name));
    // A nodal body is finished from all its points: not when one of them failed.
    if (node.kind == LeafKind::Rigid2dNodal && has_mass_.count(id) && inertia_pos_.count(id) &&
        diags_.error_count() == errors_before)
      library_.finish_nodal(id);
    if (node.kind != LeafKind::Node && !node.children.empty())
      diags_.error(node.pos, fmt::format("leaf '{}' of kind {} cannot contain subsystems", node.name, to_string(node.kind)));
    // Formal parameters of a component instance: bind to the arguments (in the parent's scope).
    for (const auto& f : formal_args_) {
      if (f.instance != node.name) continue;
      element_ = fmt::format("the argument '{}' of '{}'", f.full, node.name);
      auto e = convert(node.parent >= 0 ? node.parent : id, f.arg, false, false, false);
      element_.clear();
      if (e) m_.formals[f.full].value = *e;
    }
    if (id == m_.root()) {
      // Instances of one component share their derivation: remember the first one.
      std::map<std::string, int> first;
      for (size_t n = 0; n < m_.nodes.size(); ++n) {
        auto& nd = m_.nodes[n];
        if (nd.component.empty()) continue;
        if (pending_[n].decl && !pending_[n].decl->body.empty()) continue;  // extended instance: derived on its own
        auto it = first.find(nd.component);
        if (it == first.end()) first[nd.component] = static_cast<int>(n);
        else nd.instance_of = it->second;
      }
    }
  }

  /// A `point`, `com` or `axis` statement of body `id`.
  void fill_geometry(int id, const Statement& s) {
    const Node& node = m_.nodes[static_cast<std::size_t>(id)];
    std::vector<GiNaC::ex> v;
    for (const auto& e : s.exprs) {
      auto c = convert(id, e, false, false, false);
      if (!c) break;
      v.push_back(*c);
    }
    if (v.size() != s.exprs.size()) {
      if (s.kind != Kind::Com) library_.add_failed(id, s.name);  // a joint naming it says no more
      if (s.kind != Kind::Com) spatial_.add_failed(id, s.name);
      return;
    }
    if (!check_point_dimension(id, s)) return;
    if (node.kind == LeafKind::Rigid3d) {
      add_rigid3d_geometry(id, s, v);
      return;
    }
    if (s.kind == Kind::Point) library_.add_point(id, s.name, v[0], v[1], s.name_pos);
    else if (s.kind == Kind::Com) library_.set_com(id, v[0], v[1], s.pos);
    else library_.add_axis(id, s.name, v[0], v[1], v[2], v[3], s.name_pos);
  }

  /// `inertia (Ixx, Iyy, Izz [, Ixy, Ixz, Iyz])` of a rigid3d body: the tensor about the
  /// mass centre in body axes (principal values alone, or with its off-diagonal entries).
  void fill_rigid3d_inertia(int id, const Statement& s) {
    Node& node = m_.nodes[id];
    inertia_given_.insert(id);
    if (s.exprs.size() != 3 && s.exprs.size() != 6) {
      diags_.error(s.pos, fmt::format("inertia of rigid3d body '{}' has {} {}: give (Ixx, Iyy, Izz) or (Ixx, Iyy, Izz, "
                                      "Ixy, Ixz, Iyz) about the mass centre in body axes",
                                      node.name, s.exprs.empty() ? 1 : s.exprs.size(),
                                      s.exprs.size() == 1 || s.exprs.empty() ? "entry" : "entries"));
      return;
    }
    std::vector<GiNaC::ex> e;
    for (const auto& x : s.exprs) {
      auto c = convert(id, x, true, false, false);
      if (!c) return;
      e.push_back(*c);
    }
    while (e.size() < 6) e.push_back(0);
    node.rigid3d.inertia = {e[0], e[3], e[4], e[3], e[1], e[5], e[4], e[5], e[2]};
    node.inertia_pos = s.pos;
    rigid3d_inertia_pos_[id] = s.pos;
  }

  /// `torque [space|body] (Tx, Ty, Tz)` in a rigid3d body: an applied torque given in
  /// space axes (the default) or body axes, turned into generalized forces along the
  /// angular speeds (their frame: R^T tau for body-frame speeds given a space torque, R tau
  /// for space-frame speeds given a body torque). It may read the state, inputs and t.
  void add_rigid3d_torque(int id, const Statement& s) {
    const Node& node = m_.nodes[id];
    if (node.kind != LeafKind::Rigid3d) {
      diags_.error(s.pos, fmt::format("'torque' is only allowed in rigid3d bodies ('{}' is {}); a torque on a "
                                      "planar body is a force on its w",
                                      m_.label(id), to_string(node.kind)));
      return;
    }
    rigid3d::Vec tau;
    for (const auto& e : s.exprs) {
      auto c = convert(id, e, true, false, false);
      if (!c) return;
      tau.push_back(*c);
    }
    if (node.rigid3d.rotation.empty()) return;  // its variables failed (reported)
    const bool given_in_body = s.option2.text == "body";
    rigid3d::Vec along = tau;
    if (given_in_body && node.rigid3d.space_frame) along = rigid3d::mat_vec(node.rigid3d.rotation, tau);
    if (!given_in_body && !node.rigid3d.space_frame) along = rigid3d::mat_t_vec(node.rigid3d.rotation, tau);
    for (int k = 0; k < 3; ++k)
      if (!along[static_cast<std::size_t>(k)].is_zero())
        m_.forces.push_back(Force{node.speeds[3 + static_cast<std::size_t>(k)], along[static_cast<std::size_t>(k)], s.pos});
  }

  /// Points and axes have two components in the plane, three in space.
  bool check_point_dimension(int id, const Statement& s) {
    const Node& node = m_.nodes[id];
    const std::size_t want = node.kind == LeafKind::Rigid3d ? 3 : 2;
    const std::size_t per = s.kind == Kind::Axis ? 2 : 1;
    bool ok = s.exprs.size() == want * per;
    if (s.kind == Kind::Axis && s.exprs.size() == 5) ok = false;  // (a, b) (c, d, e) or the reverse
    if (ok) return true;
    const char* what = s.kind == Kind::Point ? "point" : s.kind == Kind::Com ? "com" : "axis";
    diags_.error(s.pos, fmt::format("{}{} of {} body '{}' needs {} components{} ({})", what,
                                    s.name.empty() ? std::string() : " '" + s.name + "'",
                                    to_string(node.kind), m_.label(id), want, per == 2 ? " for its point and its direction" : "",
                                    want == 3 ? "x, y, z in body axes" : "x, y in body axes"));
    if (s.kind != Kind::Com) library_.add_failed(id, s.name);
    if (s.kind != Kind::Com) spatial_.add_failed(id, s.name);
    return false;
  }

  /// A rigid3d body's points and axes, in body coordinates relative to its mass centre.
  void add_rigid3d_geometry(int id, const Statement& s, const std::vector<GiNaC::ex>& v) {
    Node& node = m_.nodes[id];
    if (s.kind == Kind::Com) {
      if (rigid3d_com_pos_.count(id)) {
        diags_.error(s.pos, fmt::format("com of body '{}' is given twice (first at {})", node.name,
                                        position_text(rigid3d_com_pos_[id], s.pos)));
        return;
      }
      rigid3d_com_pos_[id] = s.pos;
      node.rigid3d.com = v;
      return;
    }
    auto& into = s.kind == Kind::Point ? node.rigid3d.points : node.rigid3d.axes;
    if (node.rigid3d.points.count(s.name) || node.rigid3d.axes.count(s.name)) {
      diags_.error(s.name_pos, fmt::format("point or axis '{}' of body '{}' is already declared", s.name, node.name));
      return;
    }
    if (s.kind == Kind::Axis) {
      double len2 = 0;
      bool known = true;
      for (int k = 3; k < 6; ++k) {
        double d;
        try {
          known = known && evaluate_number(substitute_param_defaults(v[static_cast<std::size_t>(k)], true), d);
        } catch (const std::exception&) {
          known = false;
        }
        if (known) len2 += d * d;
      }
      if (known && !(len2 > 0)) {
        diags_.error(s.name_pos, fmt::format("axis '{}' of body '{}' has a zero direction", s.name, node.name));
        spatial_.add_failed(id, s.name);  // a joint naming it says no more
        return;
      }
    }
    into[s.name] = v;
  }

  /// `latex NAME "text"`: NAME is looked up as an expression would be there (the node's
  /// own names, then outwards, then the globals). A component's statement gives each
  /// instance's variables their symbol; the same statement met again (a global named in
  /// a component used twice) is no duplicate.
  void set_latex_symbol(int node, const Statement& s) {
    std::string full;
    const Entry* found = nullptr;
    // global.NAME: a parameter, input or t, from anywhere (as in an expression).
    const std::string global_prefix = std::string(kGlobalScope) + ".";
    if (s.path.text.rfind(global_prefix, 0) == 0) {
      full = s.path.text.substr(global_prefix.size());
      const auto it = table_.find(full);
      if (it != table_.end() && is_global(it->second)) found = &it->second;
      node = -1;  // no scope search
    }
    for (int n = node; n >= 0 && !found; n = m_.nodes[n].parent) {
      full = join(m_.nodes[n].name, s.path.text);
      const auto it = table_.find(full);
      if (it != table_.end()) found = &it->second;
      if (m_.nodes[n].parent < 0) break;
    }
    if (!found) {
      diags_.error(s.path.pos, fmt::format("unknown name '{}' in latex statement", s.path.text));
      return;
    }
    if (found->kind == Entry::NodeName) {
      diags_.error(s.path.pos, fmt::format("latex: '{}' is a subsystem; give the symbols of its variables", full));
      return;
    }
    if (found->kind == Entry::Let) {
      diags_.error(s.path.pos, fmt::format("latex: '{}' is a let (a named expression substituted where it is used); it "
                                           "has no symbol of its own to name in LaTeX",
                                           full));
      return;
    }
    if (found->kind == Entry::Formal) {
      diags_.error(s.path.pos, fmt::format("latex: '{}' is a component parameter, replaced by its argument in the "
                                           "equations; give the symbol of the names in the argument",
                                           full));
      return;
    }
    const auto [it, fresh] = latex_pos_.emplace(full, s.pos);
    const SourcePos& first = it->second;
    if (!fresh && (first.file != s.pos.file || first.line != s.pos.line || first.col != s.pos.col)) {
      const std::string where = first.file == s.pos.file ? "" : first.file + ":";
      diags_.error(s.path.pos, fmt::format("latex symbol of '{}' is already given at {}{}:{}", full, where, first.line,
                                           first.col));
      return;
    }
    m_.latex_symbols[full] = s.name;
  }

  /// `initial PATH = expr`: PATH a coordinate or speed in scope, expr a constant of the
  /// parameters (it is evaluated before the run, with the run's parameter values).
  void set_initial_value(int node, const Statement& s) {
    const auto var = lookup_variable(node, s.path);
    if (!var) return;
    const Variable& v = var->first ? m_.coords[var->second] : m_.speeds[var->second];
    const auto e = convert(node, s.value, false, false, false);
    if (!e) return;
    if (const std::string varying = varying_part(*e); !varying.empty()) {
      diags_.error(s.value->pos, fmt::format("initial value of '{}' reads {}; it must be a constant of the parameters",
                                             v.name, varying));
      return;
    }
    const bool guess = s.level == "guess";
    if (guess && !var->first) {
      diags_.error(s.path.pos, fmt::format("'initial guess' is for coordinates (where assembly starts); give the speed "
                                           "'{}' with 'initial {} = ...'",
                                           v.name, s.path.text));
      return;
    }
    for (const auto* list : {&m_.initial_values, &m_.initial_guesses})
      for (const auto& given : *list)
        if (given.name == v.name) {
          const std::string where = given.pos.file == s.pos.file ? "" : given.pos.file + ":";
          diags_.error(s.path.pos, fmt::format("initial value of '{}' is already given at {}{}:{}", v.name, where,
                                               given.pos.line, given.pos.col));
          return;
        }
    (guess ? m_.initial_guesses : m_.initial_values).push_back(NamedExpr{v.name, *e, s.path.pos});
  }

  /// Resolves a dotted path to a variable: (is_coordinate, index).
  std::optional<std::pair<bool, int>> lookup_variable(int node, const ast::Path& p) {
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

  // ---- kinematic transformations ----
  /// Each node's speed definitions s = Y q0' + y are solved for the rates of its own
  /// coordinates (a small linear solve per node; leaf kinds give theirs directly).
  void solve_coordinate_rates() {
    m_.coord_rates.assign(m_.coords.size(), GiNaC::ex(0));
    std::vector<bool> done(m_.coords.size(), false);
    GiNaC::exmap known_rates;  // q0' -> its rate, for the coordinates solved so far
    for (auto& [q, rate] : builtin_rates_) {
      m_.coord_rates[q] = rate;
      done[q] = true;
      known_rates[coord_dot_[q]] = rate;
    }
    // Group definitions by the node of their speed.
    std::vector<std::vector<const Definition*>> defs_of(m_.nodes.size());
    for (const auto& d : definitions_) defs_of[static_cast<std::size_t>(m_.speeds[d.speed].node)].push_back(&d);
    for (size_t n = 0; n < m_.nodes.size(); ++n) {
      checkpoint("solving the speed definitions of", fmt::format("subsystem '{}'", m_.label(static_cast<int>(n))),
                 m_.nodes[n].pos, n, m_.nodes.size());
      std::vector<int> unknown;
      for (int q : m_.nodes[n].coords)
        if (!done[q]) unknown.push_back(q);
      const std::vector<const Definition*>& defs = defs_of[n];
      if (unknown.empty() && defs.empty()) continue;
      // Rates of coordinates outside this node may appear in definitions: those are known.
      std::vector<GiNaC::ex> values;
      for (const auto* d : defs) values.push_back(subs_present(d->value, known_rates));
      GiNaC::lst eqs, vars;
      for (int q : unknown) vars.append(coord_dot_[q]);
      for (std::size_t k = 0; k < defs.size(); ++k) eqs.append(GiNaC::ex(m_.speeds[defs[k]->speed].sym) == values[k]);
      if (defs.size() != unknown.size()) {
        if (defs.size() < unknown.size()) {
          for (size_t i = 0; i < unknown.size(); ++i) {
            bool used = false;
            for (const auto* d : defs) used = used || d->value.has(coord_dot_[unknown[i]]);
            if (!used || i >= defs.size()) {
              const auto& c = m_.coords[unknown[i]];
              auto leaf = c.name.substr(c.name.rfind('.') == std::string::npos ? 0 : c.name.rfind('.') + 1);
              diags_.error(c.pos, fmt::format("coordinate '{}' has no speed defining its rate (add `speed d{} = {}'`)", c.name, leaf, leaf));
              break;
            }
          }
        } else {
          const auto* d = defs[unknown.size()];
          diags_.error(d->pos, fmt::format("speed '{}' is defined by coordinate rates, but subsystem '{}' has {} coordinate(s) and {} definitions",
                                           m_.speeds[d->speed].name, m_.nodes[n].name, unknown.size(), defs.size()));
        }
        continue;
      }
      // Each definition must be linear in the unknown rates.
      bool linear = true;
      for (std::size_t k = 0; k < defs.size(); ++k)
        for (int q : unknown)
          if (!values[k].diff(coord_dot_[q], 2).is_zero()) {
            diags_.error(defs[k]->pos, fmt::format("definition of speed '{}' is not linear in the coordinate rates",
                                                   m_.speeds[defs[k]->speed].name));
            linear = false;
          }
      if (!linear) continue;
      GiNaC::ex sol;
      if (unknown.size() == 1) {
        // One rate: s = c q' + r gives q' = (s - r) / c directly (lsolve would normalize,
        // expanding a coefficient such as (a + b + ... + th)^40 term by term).
        const GiNaC::ex qd = coord_dot_[unknown[0]];
        const GiNaC::ex c = values[0].diff(GiNaC::ex_to<GiNaC::symbol>(qd));
        if (!c.is_zero())
          sol = GiNaC::lst{qd == (GiNaC::ex(m_.speeds[defs[0]->speed].sym) - values[0].subs(qd == 0)) / c};
        else
          sol = GiNaC::lst{};
      } else {
        bool small = true;
        for (const auto& v : values) small = small && expanded_terms(v) <= limits::kMaxExpandedTerms;
        if (!small) {
          diags_.error(defs.front()->pos, fmt::format("the speed definitions of subsystem '{}' are too large to solve for "
                                                      "the coordinate rates symbolically",
                                                      m_.label(static_cast<int>(n))));
          continue;
        }
        try {
          sol = GiNaC::lsolve(eqs, vars);
        } catch (const std::exception&) {
          sol = GiNaC::lst{};
        }
      }
      if (sol.nops() != unknown.size()) {
        diags_.error(defs.front()->pos, fmt::format("the speed definitions of subsystem '{}' cannot be solved for the coordinate rates",
                                                    m_.label(static_cast<int>(n))));
        continue;
      }
      for (size_t i = 0; i < unknown.size(); ++i) {
        m_.coord_rates[unknown[i]] = normal_if_small(sol.op(i).rhs());
        done[unknown[i]] = true;
        known_rates[coord_dot_[unknown[i]]] = m_.coord_rates[unknown[i]];
      }
    }
  }

  /// Replace q0' placeholders (velocity constraints, custom forces) by the coordinate rates.
  void substitute_coordinate_rates() {
    GiNaC::exmap rates;
    for (size_t q = 0; q < m_.coords.size(); ++q) rates[coord_dot_[q]] = m_.coord_rates[q];
    // Guarded: a rate with a number in it, put into a power, is folded by GiNaC.
    auto put_rates = [&](GiNaC::ex& e, const SourcePos& pos, const std::string& what) {
      std::string why;
      auto out = guarded_subs(e, rates, why);
      if (!out) {
        diags_.error(pos, fmt::format("{} cannot be written with the coordinate rates: {}", what, why));
        return false;
      }
      e = *out;
      return true;
    };
    for (auto& c : m_.constraints)
      if (put_rates(c.residual, c.pos, fmt::format("constraint '{}'", c.name))) check_constraint(c);
    for (auto& f : m_.forces) put_rates(f.value, f.pos, fmt::format("the force on '{}'", m_.speeds[f.speed].name));
  }

  void check_constraint(const Constraint& c) {
    // Inputs have no known rates, so a constraint cannot be differentiated through them.
    for (const auto& in : m_.inputs)
      if (c.residual.has(in.sym)) {
        diags_.error(c.pos, fmt::format("constraint '{}' depends on input '{}'; constraints may use coordinates, speeds, "
                                        "parameters and t only (prescribe motions as functions of t)",
                                        c.name, in.name));
        return;
      }
    if (c.level == Constraint::Level::Position) {
      return;
    }
    bool has_speed = false;
    for (size_t u = 0; u < m_.speeds.size(); ++u) {
      if (!c.residual.has(m_.speeds[u].sym)) continue;
      has_speed = true;
      if (!c.nonlinear && !c.residual.diff(m_.speeds[u].sym, 2).is_zero()) {
        diags_.error(c.pos, fmt::format("velocity constraint '{}' is not linear in the speed '{}'; write it in a "
                                        "`constraint velocity nonlinear` block",
                                        c.name, m_.speeds[u].name));
        return;
      }
    }
    if (!has_speed)
      diags_.error(c.pos, fmt::format("velocity constraint '{}' contains no speed; write it as a position constraint", c.name));
  }

  /// What makes e vary with the motion: "coordinate 'q'", "speed 'b.u'", "input 'F'",
  /// "the time t"; "" when e holds parameters and numbers only.
  std::string varying_part(const GiNaC::ex& e) const { return model::varying_part(m_, e); }

  /// Masses and inertias are constants: a body's inertia forces are m v' and J w', which
  /// lack the terms of dm/dt when m changes with the motion. So they read parameters
  /// only (directly, through a let or through a component's argument). They may not be
  /// negative, at the parameters' defaults or their --freeze values (which the message
  /// names, since the file alone looks right). Zero is allowed (a massless link); the
  /// derivation then checks that the reduced mass matrix stays positive definite
  /// (sym/massless_check.hpp).
  /// A rigid3d inertia tensor is constant and, at the parameters' defaults (or their
  /// --freeze values), symmetric positive definite: its leading minors are positive.
  /// (A tensor that is not makes the mass matrix singular or indefinite.)
  void check_rigid3d_inertia(const Node& node, const SourcePos& pos, const GiNaC::exmap& formals) {
    std::vector<double> I(9);
    for (std::size_t k = 0; k < 9; ++k) {
      GiNaC::ex e = node.rigid3d.inertia[k];
      try {
        for (int pass = 0; pass < 2 && !formals.empty(); ++pass) {
          std::string why;
          const auto next = guarded_subs(e, formals, why);
          if (!next) throw std::runtime_error(why);
          e = *next;
        }
        if (const std::string varying = varying_part(e); !varying.empty()) {
          diags_.error(pos, fmt::format("inertia of body '{}' must be constant: it reads {} (inertias may use parameters "
                                        "only)",
                                        node.name, varying));
          return;
        }
        const GiNaC::ex v = substitute_param_defaults(e, true);
        if (const auto problem = value_problem(v)) {
          diags_.error(pos, fmt::format("inertia of body '{}' at the parameter values{}: {}", node.name, frozen_note(e),
                                        problem->text()));
          return;
        }
        if (!evaluate_number(v, I[k])) return;  // left symbolic: not checked here
      } catch (const std::exception& ex) {
        diags_.error(pos, fmt::format("inertia of body '{}' is undefined at these parameter values ({})", node.name, ex.what()));
        return;
      }
    }
    const double m1 = I[0], m2 = I[0] * I[4] - I[1] * I[3];
    const double m3 = I[0] * (I[4] * I[8] - I[5] * I[7]) - I[1] * (I[3] * I[8] - I[5] * I[6]) + I[2] * (I[3] * I[7] - I[4] * I[6]);
    GiNaC::ex all = 0;  // every entry, for the note on frozen parameters
    for (const auto& e : node.rigid3d.inertia) all += GiNaC::pow(e, 2);
    if (!(m1 > 0 && m2 > 0 && m3 > 0))
      diags_.error(pos, fmt::format("inertia tensor of body '{}' is not positive definite at the parameter values "
                                    "(leading minors {:g}, {:g}, {:g}; all must be positive){}",
                                    node.name, m1, m2, m3, frozen_note(all)));
  }

  void check_masses() {
    GiNaC::exmap formals;
    for (auto& [name, f] : m_.formals) {
      try {
        formals[f.sym] = substitute_param_defaults(f.value, true);
      } catch (const std::exception&) {
        // Left symbolic: the masses that use it are not checked here (derive reports it).
      }
    }
    for (size_t n = 0; n < m_.nodes.size(); ++n) {
      const Node& node = m_.nodes[n];
      auto check = [&](const GiNaC::ex& e, const SourcePos& pos, const char* what) {
        GiNaC::ex with_formals = e, v;
        try {
          for (int pass = 0; pass < 2 && !formals.empty(); ++pass) {
            std::string why;
            const auto next = guarded_subs(with_formals, formals, why);
            if (!next) throw std::runtime_error(why);
            with_formals = *next;
          }
          if (const std::string varying = varying_part(with_formals); !varying.empty()) {
            diags_.error(pos, fmt::format("{} of body '{}' must be constant: it reads {} (masses and inertias may use "
                                          "parameters only; a body whose {} changes with the motion needs the terms of "
                                          "its rate: write it as a custom leaf with its own forces)",
                                          what, node.name, varying, what));
            return;
          }
          v = substitute_param_defaults(with_formals, true);
        } catch (const std::exception& ex) {
          diags_.error(pos, fmt::format("{} of body '{}' is undefined at these parameter values{} ({})", what, node.name,
                                        frozen_note(with_formals), ex.what()));
          return;
        }
        // At these values the generated code computes with it: a real number within the
        // bound (sqrt(a) with a = -1 is not; neither is a*a with a = 1e20).
        if (const auto problem = value_problem(v)) {
          diags_.error(pos, fmt::format("{} of body '{}' at the parameter values{}: {}", what, node.name,
                                        frozen_note(with_formals), problem->text()));
          return;
        }
        double d;
        if (evaluate_number(v, d) && !(d >= 0))
          diags_.error(pos, fmt::format("{} of body '{}' is negative ({}){}", what, node.name, d,
                                        frozen_note(with_formals)));
      };
      if (has_mass_.count(static_cast<int>(n))) check(node.mass, node.mass_pos, "mass");
      if (inertia_pos_.count(static_cast<int>(n))) check(node.inertia, inertia_pos_[n], "inertia");
      if (rigid3d_inertia_pos_.count(static_cast<int>(n))) check_rigid3d_inertia(node, rigid3d_inertia_pos_[n], formals);
    }
  }

  /// What statement `s` of node `node` gives, naming it in the messages of its values
  /// ("the mass of body 'arm'", "spring 's'"); "" for a statement without values.
  std::string element_of(const Statement& s, int node) const {
    const std::string body = m_.label(node);
    const std::string named = join(m_.nodes[static_cast<std::size_t>(node)].name, s.name);
    switch (s.kind) {
      case Kind::Mass: return fmt::format("the mass of body '{}'", body);
      case Kind::Inertia: return fmt::format("the inertia of body '{}'", body);
      case Kind::Torque: return fmt::format("the torque on body '{}'", body);
      case Kind::Kinetic: return fmt::format("the kinetic energy of '{}'", body);
      case Kind::Potential: return fmt::format("the potential energy of '{}'", body);
      case Kind::Com: return fmt::format("the centre of mass of body '{}'", body);
      case Kind::Force: return fmt::format("the force on '{}'", s.path.text);
      case Kind::Initial: return fmt::format("the initial value of '{}'", s.path.text);
      case Kind::Constraint: return fmt::format("a {} constraint of '{}'", s.level, body);
      case Kind::Joint: return s.name.empty() ? fmt::format("a {} joint", s.kind_name) : fmt::format("joint '{}'", named);
      case Kind::Subsystem: return fmt::format("the arguments of '{}'", named);
      default: {
        const char* what = declared_kind(s);
        return what ? fmt::format("{} '{}'", what, named) : "";
      }
    }
  }

  /// ", with --freeze a=1" naming the frozen parameters e depends on, or "".
  std::string frozen_note(const GiNaC::ex& e) const {
    std::string names;
    for (const auto& p : m_.params) {
      const auto it = frozen_.find(p.name);
      if (it == frozen_.end() || !e.has(p.sym)) continue;
      names += fmt::format("{}{}={}", names.empty() ? "" : " ", p.name, it->second);
    }
    return names.empty() ? "" : ", with --freeze " + names;
  }

  struct Definition {
    int speed;
    GiNaC::ex value;
    SourcePos pos;
  };
  struct FormalArg {
    std::string full;
    ast::ExprPtr arg;
    std::string instance;
  };

  Diagnostics& diags_;
  const std::map<std::string, double>& frozen_;  // --freeze values (parameter name -> value)
  GiNaC::exmap param_values_;         // each parameter's default
  GiNaC::exmap param_values_frozen_;  // its --freeze value, else its default
  Model m_;
  PlanarLibrary library_{m_, diags_};  // points, axes, joints, springs, dampers
  SpatialLibrary spatial_{m_, diags_};  // spatial ground points and axes, spatial joints
  NamedExpressions lets_{diags_, [this](int node, const ast::Expr& e) { return convert_let(node, e); }};
  std::map<std::string, Entry> table_;
  std::map<std::string, const Statement*> components_;
  const Statement* gravity_stmt_ = nullptr;
  bool nodal_default_ = false;      // `parametrization nodal`
  SourcePos parametrization_pos_;
  std::vector<Pending> pending_;
  std::vector<GiNaC::symbol> coord_dot_;
  std::size_t declared_nodes_ = 0;                // subsystems declared so far (limits::kMaxNodes)
  std::map<int, GiNaC::ex> builtin_rates_;
  std::map<int, SourcePos> rigid3d_inertia_pos_;  // rigid3d bodies' inertia statements
  std::map<int, SourcePos> rigid3d_com_pos_;      // rigid3d bodies' com statements
  std::map<std::pair<int, const Statement*>, std::pair<int, int>> joint_variables_;  // (node, joint) -> its coordinate, speed
  std::map<std::pair<int, const Statement*>, std::vector<int>> contact_coordinates_;  // rolling_sphere -> (xc, yc)
  // Pass A: the statements of the subsystems being declared, outermost first, where a
  // rigid3d body finds the joint with a coordinate that places it (placing_joint).
  std::vector<std::pair<std::string, const std::vector<ast::StatementPtr>*>> scopes_;
  struct Placement {
    int child;
    const Statement* joint;
    std::string owner;  // the subsystem the joint is written in (an instance of a component shares its statements)
  };
  std::vector<Placement> placements_;
  std::set<int> geometry_done_;  // rigid3d bodies whose geometry was read before pass B
  std::vector<Definition> definitions_;
  std::vector<FormalArg> formal_args_;
  std::set<int> has_mass_;
  std::set<int> mass_given_, inertia_given_;  // bodies with a mass / inertia statement (valid or not)
  std::map<int, SourcePos> inertia_pos_;
  std::map<std::string, SourcePos> output_names_;  // where each output is declared
  std::map<std::string, SourcePos> latex_pos_;  // where each name's `latex` statement is
  const std::vector<ast::StatementPtr>* top_ = nullptr;  // the file's statements
  std::string file_path_;                                // the model file, for positions of the whole file
  std::string global_context_;  // what converter(-1) is reading: "gravity", "the default of parameter 'm'"...
  std::string element_;         // what the statement being read in pass B gives (element_of)
  std::map<const ast::Expr*, std::string> let_names_;  // a let's expression -> its full name
  bool allow_speeds_ = false, allow_coord_rate_ = false, allow_speed_rate_ = false;
};

}  // namespace

std::optional<Model> build(const ast::File& file, Diagnostics& diags, const std::map<std::string, double>& frozen) {
  Builder b(diags, frozen);
  try {
    auto m = b.run(file);
    if (m) m->structural = file.structural;
    return m;
  } catch (const std::exception& e) {
    diags.error(SourcePos{file.path, 0, 0}, std::string("internal error while building the model: ") + e.what());
    return std::nullopt;
  }
}

}  // namespace mbsc::model
