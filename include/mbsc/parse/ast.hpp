// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// The syntax tree of a model file. It mirrors the text: user names and nesting are kept,
/// and every node carries the SourcePos of its first token. No name is resolved here.
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "mbsc/diag/diagnostics.hpp"

namespace mbsc::ast {

struct Expr;
using ExprPtr = std::shared_ptr<const Expr>;

/// An expression of the model language.
///   Number  text = literal as written ("0.15", "2", "1e-3")
///   Name    text = dotted path as written ("m1", "R.u", "left.upper.theta", "t")
///   Call    text = function name ("sin"), args = arguments
///   Unary   text = "-" or "+", args = {operand}
///   Sum     args = the operands (two or more), text = the sign before each operand after
///           the first: a + b - c is {a, b, c} with text "+-"
///   Product args likewise, text of '*' and '/': a * b / c is {a, b, c} with text "*/"
///   Binary  text = "^", args = {base, exponent}
///   Prime   args = {operand}: time derivative written postfix, x' (only of a Name)
/// Sums and products are flat (not a chain of binary nodes), so a long one written in a
/// model costs no depth: only parentheses, signs and powers nest, and the parser bounds
/// those (limits::kMaxNesting).
struct Expr {
  enum class Kind { Number, Name, Call, Unary, Sum, Product, Binary, Prime };
  Kind kind = Kind::Number;
  std::string text;
  std::vector<ExprPtr> args;
  SourcePos pos;
};

/// One row of a constraint block: [label ':'] lhs '=' rhs.
struct Equation {
  std::string label;  // empty when not given
  ExprPtr lhs, rhs;
  SourcePos pos;
};

/// A dotted reference to a variable or element ("R.u", "crank.angle").
struct Path {
  std::string text;
  SourcePos pos;
};

struct Statement;
using StatementPtr = std::shared_ptr<const Statement>;

/// One statement. Which fields are used depends on kind (see the comments).
struct Statement {
  enum class Kind {
    Model,        // model NAME                         name
    Parametrization,  // parametrization absolute|nodal name (how `rigid2d` bodies are parametrized)
    Parameter,    // parameter NAME [= expr]            name, value (may be null)
    Input,        // input NAME                         name
    Gravity,      // gravity (gx, gy [, gz])            exprs
    Include,      // include "file"                     name = file text as written (unquoted)
    Component,    // component NAME(formals) { body }   name, formals, body
    Subsystem,    // subsystem NAME [: KIND[(args)]] [{ body }]
                  //                                    name, kind_name (may be empty), exprs = args, body
    Coordinate,   // coordinate NAME                    name
    Speed,        // speed NAME [= expr]                name, value (may be null)
    Constraint,   // constraint position|velocity [nonlinear] { equations }
                  //                                    level, nonlinear, equations
    Force,        // force PATH : expr                  path, value
    Mass,         // mass expr                          value
    Inertia,      // inertia expr                       value
                  // inertia (Ixx, Iyy, Izz [, Ixy, Ixz, Iyz])  exprs (a rigid3d body's tensor)
    Attitude,     // attitude quaternion [body|space]   name = "quaternion" or "euler", name_pos;
                  // attitude euler SEQ [body|space]    path = SEQ (e.g. zyx), option2 = the frame word
    Torque,       // torque [body|space] (Tx, Ty, Tz)   exprs, option2 = the frame word (a rigid3d body's
                  //                                    applied torque; 'torque' is a keyword only here)
    Kinetic,      // kinetic expr                       value
    Potential,    // potential expr                     value
    Independent,  // independent PATH, PATH ...         paths
    Alternative,  // alternative PATH, PATH ...         paths (another independent set, for run-time re-selection)
    Output,       // output NAME = expr | output energy name, value (null for "output energy")
    Let,          // let NAME = expr                    name, value (a named expression, docs/language.md "Named expressions")
    // Planar library level (docs/language.md "Bodies, points and joints"):
    Point,        // point NAME (ex, ey [, ez])          name, exprs = {ex, ey[, ez]} (body coordinates)
    Com,          // com (ex, ey [, ez])                exprs = {ex, ey[, ez]}
    Axis,         // axis NAME (px, py) (dx, dy)        name, exprs = {px, py, dx, dy} (or three of each)
    Ground,       // ground { point/axis ... }          body
    Joint,        // joint [NAME :] KIND PATH PATH [coordinate Q, ... [speed S, ...] [euler SEQ]] [OPTION expr [OPTION2 expr2]]
                  //                                    name (may be empty), kind_name, paths, level = OPTION,
                  //                                    path.pos = OPTION's position, value; option2, exprs = {expr2};
                  //                                    joint_coordinates / joint_speeds (empty when absent),
                  //                                    joint_sequence (spherical: the angles' Euler sequence)
                  // joint [NAME :] knife_edge BODY [point P] [axis A]
                  //                                    paths = {BODY, P, A} (text empty when not given)
    Spring,       // spring NAME [rotational] PATH PATH stiffness expr [length|angle expr]
                  //                                    name, kind_name = "rotational" or "", paths, value = stiffness,
                  //                                    exprs = {rest length or angle} (may be empty)
    Damper,       // damper NAME [rotational] PATH PATH coefficient expr
                  //                                    name, kind_name, paths, value = coefficient
    Initial,      // initial [guess] PATH = expr        path, value (the variable's starting value, for `mbsc run`);
                  //                                    level = "guess" for a starting guess of assembly
    Latex,        // latex PATH "text"                  path = the name it gives a symbol to, name = the text
                  //                                    (unquoted), name_pos = the string's position
  };
  Kind kind = Kind::Model;
  SourcePos pos;       // position of the keyword
  std::string name;    // declared name (or file for Include)
  SourcePos name_pos;  // position of the name token
  std::string kind_name;  // Subsystem: leaf kind or component name ("rigid2d", "Arm"); empty for a plain node
  SourcePos kind_pos;
  ExprPtr value;
  std::vector<ExprPtr> exprs;      // Gravity components, Subsystem component arguments
  std::vector<std::string> formals;  // Component formal parameter names
  std::vector<SourcePos> formal_pos;
  std::string level;               // Constraint: "position" or "velocity"
  bool nonlinear = false;          // Constraint: "nonlinear" given
  std::vector<Equation> equations; // Constraint rows
  Path path;                       // Force target
  Path option2;                    // Joint: the second option word (text empty when absent)
  std::vector<Path> joint_coordinates;  // Joint: 'coordinate Q, ...', the joint's own (relative) coordinates, or none
  std::vector<Path> joint_speeds;       // Joint: 'speed S, ...', the names of their rates (none: Q_dot, ...)
  Path joint_sequence;                  // Joint: 'euler SEQ' after the coordinates (spherical), 'quaternion', or empty
  std::vector<Path> paths;         // Independent list; Joint / Spring / Damper ends
  std::vector<StatementPtr> body;  // Component / Subsystem body (has_body tells whether braces were given)
  bool has_body = false;
};

/// A parsed file: its statements in order. Includes are kept as statements; the
/// parser entry point resolves them (see parse.hpp).
struct File {
  std::string path;
  std::vector<StatementPtr> statements;
  /// Parameters that loop bounds or indices used, with the value used (structural:
  /// the model freezes them, since other values need another expansion).
  std::map<std::string, double> structural;
  /// The text of the model file itself (parse_file), for the banner hash.
  std::string main_source;
  /// Every file parse_file read: the model first, then each included file once, in the
  /// order first read, each path as it was opened (relative to the including file's
  /// folder). What the generated code depends on (generate --depfile).
  std::vector<std::string> sources;
  /// Tokens after loop expansion, over every file read (the include budget counts them).
  std::size_t token_count = 0;
};

}  // namespace mbsc::ast
