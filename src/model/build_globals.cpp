// SPDX-License-Identifier: GPL-2.0-or-later
// The model's globals, collected before any subsystem: its name, the parametrization, the
// parameters with their defaults (numbers within the bound) and --freeze values, the
// inputs, the components, gravity (its size checked against the bodies) and the ground's
// points and axes.
#include "build_internal.hpp"

#include <fmt/format.h>

#include <cmath>
#include <exception>
#include <stdexcept>

#include "mbsc/diag/limits.hpp"
#include "mbsc/diag/name_suggestions.hpp"
#include "mbsc/model/exact_guard.hpp"
#include "mbsc/model/value_bound.hpp"

namespace mbsc::model::build_detail {

void Builder::collect_globals(const std::vector<ast::StatementPtr>& stmts) {
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
void Builder::check_gravity_size() {
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
void Builder::declare_ground(const Statement& g) {
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

/// Every --freeze name must be a parameter of the model (a typo would otherwise
/// freeze nothing, silently).
void Builder::check_frozen_names(const std::string& file) {
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

bool Builder::declare_global(const std::string& name, const SourcePos& pos, const char* what) {
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

/// e with every parameter replaced by its value: the default, or (with_frozen) the
/// --freeze value. Guarded (exact_guard.hpp), and only the symbols e holds are looked
/// up: `parameter a = 3, n = 1e12` with `mass a^n` must not fold 3^(10^12), and 10 000
/// parameters stay linear. Throws std::runtime_error when the result would be undefined
/// or too large to fold.
GiNaC::ex Builder::substitute_param_defaults(const GiNaC::ex& e, bool with_frozen) const {
  if (GiNaC::is_a<GiNaC::numeric>(e)) return e;
  std::string why;
  auto out = guarded_subs(e, with_frozen ? param_values_frozen_ : param_values_, why);
  if (!out) throw std::runtime_error(why);
  return *out;
}

}  // namespace mbsc::model::build_detail
