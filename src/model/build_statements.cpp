// SPDX-License-Identifier: GPL-2.0-or-later
// Pass B: each subsystem's statements become the model's expressions: speed definitions,
// constraints, forces, masses and inertias, energies, independent sets, outputs, initial
// values, LaTeX symbols, points and axes, and the joints, springs and dampers handed to the
// planar and spatial libraries; then what needs the whole subsystem (a body without a
// mass) and the binding of a component instance's arguments.
#include "build_internal.hpp"

#include <fmt/format.h>

namespace mbsc::model::build_detail {

/// A rolling_sphere's surface gamma(x, y): the names x and y are the contact point's
/// coordinates, any other name is looked up as usual (parameters; the joint checks that
/// nothing else of the state is read).
std::optional<GiNaC::ex> Builder::convert_surface(int node, const ast::ExprPtr& e, const std::vector<int>& contact) {
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

void Builder::fill_node(int id) {
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
        if (!s.joint_coordinates.empty()) {
          const auto jv = joint_variables_.find({id, &s});
          if (jv == joint_variables_.end()) break;  // its declaration failed (reported)
          fill_joint_coordinates(e, s, jv->second);
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
void Builder::fill_geometry(int id, const Statement& s) {
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

/// Points and axes have two components in the plane, three in space.
bool Builder::check_point_dimension(int id, const Statement& s) {
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

/// `latex NAME "text"`: NAME is looked up as an expression would be there (the node's
/// own names, then outwards, then the globals). A component's statement gives each
/// instance's variables their symbol; the same statement met again (a global named in
/// a component used twice) is no duplicate.
void Builder::set_latex_symbol(int node, const Statement& s) {
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
void Builder::set_initial_value(int node, const Statement& s) {
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

/// What statement `s` of node `node` gives, naming it in the messages of its values
/// ("the mass of body 'arm'", "spring 's'"); "" for a statement without values.
std::string Builder::element_of(const Statement& s, int node) const {
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

}  // namespace mbsc::model::build_detail
