// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// The model builder that the build*.cpp files share (private to src/model): one Builder
/// turns one parsed file into a Model (include/mbsc/model/build.hpp). Pass A declares the
/// subsystem tree and its variables (build_tree.cpp, build_rigid3d.cpp), pass B turns each
/// subsystem's statements into expressions (build_statements.cpp), every name read through
/// the table (build_names.cpp); then the coordinate rates are solved (build_rates.cpp) and
/// the masses checked (build_masses.cpp). build.cpp runs the passes in this order.
#include <ginac/ginac.h>

#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "mbsc/model/build.hpp"
#include "mbsc/model/expr_convert.hpp"
#include "named_expressions.hpp"
#include "planar_library.hpp"
#include "spatial_library.hpp"

namespace mbsc::model::build_detail {

using ast::Statement;
using Kind = ast::Statement::Kind;

/// `global.NAME` names a parameter or input from anywhere (a body's own `u` cannot hide it).
inline constexpr const char* kGlobalScope = "global";

inline std::string join(const std::string& prefix, const std::string& name) {
  return prefix.empty() ? name : prefix + "." + name;
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
  std::optional<Model> run(const ast::File& file);

 private:
  // build_globals.cpp: the model name, parameters, inputs, components, gravity, the ground
  void collect_globals(const std::vector<ast::StatementPtr>& stmts);
  void check_gravity_size();
  void declare_ground(const Statement& g);
  void check_frozen_names(const std::string& file);
  bool declare_global(const std::string& name, const SourcePos& pos, const char* what);
  GiNaC::ex substitute_param_defaults(const GiNaC::ex& e, bool with_frozen = false) const;

  // build_names.cpp: the name table: declaring names and reading them in expressions
  static const char* declared_kind(const Statement& s);
  void check_reserved_names(const std::vector<ast::StatementPtr>& stmts);
  const Statement* not_yet_declared(const std::string& path, const SourcePos& use) const;
  static std::string declared_as(const Entry& e, const SourcePos& here);
  static std::string position_text(const SourcePos& pos, const SourcePos& here);
  bool declare_local(const std::string& full, const SourcePos& pos, const char* what);
  void declare_let(int node, const std::string& full, const Statement& s);
  std::optional<GiNaC::ex> convert_let(int node, const ast::Expr& e);
  ExprConverter converter(int node);
  std::optional<GiNaC::ex> resolve(const std::string& path, const SourcePos& pos, int node, bool primed);
  static bool is_global(const Entry& e);
  static const char* global_kind_name(const Entry& e);
  bool allowed(const Entry& e, bool primed) const;
  std::optional<GiNaC::ex> value_of(const Entry& found, const std::string& full, const std::string& path,
                                    const SourcePos& pos, bool primed);
  std::string suggestion(const std::string& written, int node, bool variables_only) const;
  std::vector<std::string> names_in_scope(int node, bool variables_only) const;
  std::optional<GiNaC::ex> convert(int node, const ast::ExprPtr& e, bool speeds, bool coord_rates, bool speed_rates);
  std::optional<std::pair<bool, int>> lookup_variable(int node, const ast::Path& p);

  // build_tree.cpp: pass A: the subsystem tree and the variables each node declares
  int declare_node(const std::vector<ast::StatementPtr>& body, const std::string& prefix, const SourcePos& pos,
                   const Statement* decl, int depth);
  void declare_joint_coordinate(int id, const std::string& prefix, const Statement& s);
  void declare_joint_quaternion(int id, const std::string& prefix, const Statement& s, const std::string& joint);
  void declare_contact_coordinates(int id, const std::string& prefix, const Statement& s);
  std::string unknown_kind_message(const std::string& subsystem, const std::string& kind) const;
  int add_variable(int node, const std::string& full, const SourcePos& pos, bool coordinate, bool builtin = false);

  // build_rigid3d.cpp: rigid3d bodies: variables, attitude, placement, geometry, inertia, torques
  void declare_rigid3d(int id, const std::string& prefix, const SourcePos& pos, const std::vector<ast::StatementPtr>& body);
  const Statement* placing_joint(int id, const std::string& prefix);
  void fill_rigid3d_geometry(int id);
  void place_joint_bodies();
  struct JointVariables {  // a joint's own coordinates and their speeds (indices), in order
    std::vector<int> coordinates, speeds;
  };
  PlanarLibrary::Element placement_element(const Statement& s, const JointVariables& variables) const;
  static void fill_joint_coordinates(PlanarLibrary::Element& e, const Statement& s, const JointVariables& variables);
  void fill_rigid3d_inertia(int id, const Statement& s);
  void add_rigid3d_torque(int id, const Statement& s);
  void add_rigid3d_geometry(int id, const Statement& s, const std::vector<GiNaC::ex>& v);

  // build_statements.cpp: pass B: each subsystem's statements
  std::optional<GiNaC::ex> convert_surface(int node, const ast::ExprPtr& e, const std::vector<int>& contact);
  void fill_node(int id);
  void fill_geometry(int id, const Statement& s);
  bool check_point_dimension(int id, const Statement& s);
  void set_latex_symbol(int node, const Statement& s);
  void set_initial_value(int node, const Statement& s);
  std::string element_of(const Statement& s, int node) const;

  // build_rates.cpp: the coordinate rates from the speed definitions
  void solve_coordinate_rates();
  void substitute_coordinate_rates();
  void check_constraint(const Constraint& c);

  // build_masses.cpp: masses and inertias: constant, not negative, tensors positive definite
  std::string varying_part(const GiNaC::ex& e) const;
  void check_rigid3d_inertia(const Node& node, const SourcePos& pos, const GiNaC::exmap& formals);
  void check_masses();
  std::string frozen_note(const GiNaC::ex& e) const;

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
  std::map<std::pair<int, const Statement*>, JointVariables> joint_variables_;  // (node, joint) -> its variables
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

}  // namespace mbsc::model::build_detail
