// SPDX-License-Identifier: GPL-2.0-or-later
// AST -> Model (include/mbsc/model/build.hpp): the Builder's passes in order. The globals
// are read first; pass A declares every subsystem and variable; bodies placed by joints
// with a coordinate get their attitude; pass B builds each subsystem's expressions; the
// coordinate rates and the checks of masses close the model. What each pass builds is in
// the build_*.cpp files (build_internal.hpp declares the Builder they share).
#include "mbsc/model/build.hpp"

#include <fmt/format.h>

#include <exception>
#include <string>

#include "build_internal.hpp"
#include "mbsc/diag/activity.hpp"

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

namespace build_detail {

std::optional<Model> Builder::run(const ast::File& file) {
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

}  // namespace build_detail

std::optional<Model> build(const ast::File& file, Diagnostics& diags, const std::map<std::string, double>& frozen) {
  build_detail::Builder b(diags, frozen);
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
