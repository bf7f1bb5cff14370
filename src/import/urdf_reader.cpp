// SPDX-License-Identifier: GPL-2.0-or-later
// URDF text to UrdfDocument with tinyxml2: the elements mbsc reads (<link> with
// <inertial>, <joint> with <origin>, <axis>, <limit>, <dynamics>, <mimic>) and a count of
// those it leaves out. tinyxml2 gives each element's line; the column is found in the
// text, at the element's '<' or at the attribute's name, so every error reads
// file:line:col like a model's.
#include <tinyxml2.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <map>
#include <set>

#include <fmt/format.h>

#include "mbsc/diag/limits.hpp"
#include "mbsc/diag/name_suggestions.hpp"
#include "urdf_document.hpp"

namespace mbsc::import {

namespace {

using tinyxml2::XMLElement;

class Reader {
 public:
  Reader(const std::string& path, const std::string& text, Diagnostics& diags) : path_(path), text_(text), diags_(diags) {
    starts_.push_back(0);
    for (std::size_t i = 0; i < text.size(); ++i)
      if (text[i] == '\n') starts_.push_back(i + 1);
    // Stretches where a '<' starts no element: comments, CDATA, declarations.
    for (std::size_t i = text.find('<'); i != std::string::npos; i = text.find('<', i + 1)) {
      for (const auto& [open, close] : {std::pair<const char*, const char*>{"<!--", "-->"}, {"<![CDATA[", "]]>"}, {"<?", "?>"}})
        if (text.compare(i, std::char_traits<char>::length(open), open) == 0) {
          const std::size_t end = text.find(close, i + 1);
          const std::size_t stop = end == std::string::npos ? text.size() : end + std::char_traits<char>::length(close);
          skipped_.emplace_back(i, stop);
          i = stop - 1;
          break;
        }
    }
  }

  std::optional<UrdfDocument> read() {
    tinyxml2::XMLDocument doc;
    if (doc.Parse(text_.data(), text_.size()) != tinyxml2::XML_SUCCESS) {
      // tinyxml2 names the error (XML_ERROR_MISMATCHED_ELEMENT) and gives a detail after
      // its own prefix ("Error=... Line number=2: XMLElement name=link").
      std::string kind = doc.ErrorName() ? doc.ErrorName() : "XML_ERROR";
      if (kind.rfind("XML_ERROR_", 0) == 0) kind = kind.substr(10);
      for (auto& c : kind) c = c == '_' ? ' ' : static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      std::string detail = doc.ErrorStr() ? doc.ErrorStr() : "";
      const auto colon = detail.find(": ");
      detail = colon == std::string::npos ? "" : ": " + detail.substr(colon + 2);
      // The line tinyxml2 reports, at its first tag (or its start).
      const int line = std::clamp(doc.ErrorLineNum(), 1, static_cast<int>(starts_.size()));
      const std::size_t from = starts_[static_cast<std::size_t>(line - 1)];
      const std::size_t end = line < static_cast<int>(starts_.size()) ? starts_[static_cast<std::size_t>(line)] : text_.size();
      const std::size_t tag = text_.find('<', from);
      const SourcePos pos = position_of(tag != std::string::npos && tag < end ? tag : from);
      diags_.error(pos, fmt::format("the URDF is not well-formed XML ({}{})", kind, printable(detail)));
      return std::nullopt;
    }
    locate(doc.RootElement());
    const XMLElement* robot = doc.RootElement();
    if (!robot || std::string(robot->Name()) != "robot") {
      diags_.error(robot ? at(robot) : SourcePos{path_, 1, 1},
                   fmt::format("a URDF's root element is <robot>, not <{}>", robot ? robot->Name() : ""));
      return std::nullopt;
    }
    UrdfDocument out;
    out.robot_pos = at(robot);
    out.robot_name = required(robot, "name", "<robot>");
    std::set<std::string> others;
    for (const XMLElement* e = robot->FirstChildElement(); e; e = e->NextSiblingElement()) {
      const std::string name = e->Name();
      if (name == "link") out.links.push_back(link(e));
      else if (name == "joint") out.joints.push_back(joint(e));
      else if (name == "transmission") ++out.transmissions;
      else if (name == "gazebo") ++out.gazebo;
      else if (name == "material") ++out.materials;
      else if (others.insert(name).second) out.other_elements.push_back(name);
    }
    if (diags_.has_errors()) return std::nullopt;
    return out;
  }

 private:
  /// file:line:col of a byte offset; the column counts characters (UTF-8), as the model
  /// language's lexer does.
  SourcePos position_of(std::size_t offset) const {
    const auto it = std::upper_bound(starts_.begin(), starts_.end(), offset);
    const std::size_t line = static_cast<std::size_t>(it - starts_.begin());
    int col = 1;
    for (std::size_t i = starts_[line - 1]; i < offset && i < text_.size(); ++i)
      col += (static_cast<unsigned char>(text_[i]) & 0xC0) != 0x80;
    return SourcePos{path_, static_cast<int>(line), col};
  }

  bool skipped(std::size_t offset) const {
    for (const auto& [from, to] : skipped_)
      if (offset >= from && offset < to) return true;
    return false;
  }

  /// Every element's start tag, found in document order with a cursor that only moves on:
  /// the first "<Name" followed by a space, '/' or '>' at or after the line tinyxml2
  /// reports, outside comments, after the element before it.
  void locate(const XMLElement* root) {
    std::size_t cursor = 0;
    std::vector<const XMLElement*> stack;
    if (root) stack.push_back(root);
    while (!stack.empty()) {
      const XMLElement* e = stack.back();
      stack.pop_back();
      const int line = e->GetLineNum();
      std::size_t from = cursor;
      if (line >= 1 && static_cast<std::size_t>(line) <= starts_.size())
        from = std::max(from, starts_[static_cast<std::size_t>(line - 1)]);
      const std::string tag = std::string("<") + e->Name();
      std::size_t found = text_.find(tag, from);
      while (found != std::string::npos) {
        const std::size_t after = found + tag.size();
        const char next = after < text_.size() ? text_[after] : '>';
        if (!skipped(found) && (std::isspace(static_cast<unsigned char>(next)) || next == '/' || next == '>')) break;
        found = text_.find(tag, found + 1);
      }
      if (found == std::string::npos) found = from < text_.size() ? from : 0;
      offsets_[e] = found;
      cursor = found + 1;
      // Children in document order: pushed last to first.
      std::vector<const XMLElement*> children;
      for (const XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) children.push_back(c);
      for (auto it = children.rbegin(); it != children.rend(); ++it) stack.push_back(*it);
    }
  }

  /// Where the element's start tag begins (its '<').
  std::size_t offset_of(const XMLElement* e) const {
    const auto it = offsets_.find(e);
    return it == offsets_.end() ? 0 : it->second;
  }

  SourcePos at(const XMLElement* e) const { return position_of(offset_of(e)); }

  /// The position of attribute `name` in e's start tag (the element's when not found).
  SourcePos at(const XMLElement* e, const char* name) const {
    const std::size_t start = offset_of(e);
    const std::size_t end = text_.find('>', start);
    std::size_t i = start;
    const std::string key = name;
    while ((i = text_.find(key, i + 1)) != std::string::npos && i < end) {
      const char before = text_[i - 1];
      std::size_t j = i + key.size();
      while (j < text_.size() && std::isspace(static_cast<unsigned char>(text_[j]))) ++j;
      if (std::isspace(static_cast<unsigned char>(before)) && j < text_.size() && text_[j] == '=') return position_of(i);
    }
    return position_of(start);
  }

  std::string required(const XMLElement* e, const char* attribute, const std::string& what) {
    const char* v = e->Attribute(attribute);
    if (!v || !*v) {
      diags_.error(at(e), fmt::format("{} needs the attribute {}", what, attribute));
      return "";
    }
    return v;
  }

  /// An attribute of n numbers separated by spaces, or `fallback` when absent.
  template <std::size_t N>
  std::array<double, N> numbers(const XMLElement* e, const char* attribute, const std::array<double, N>& fallback,
                                const std::string& what) {
    const char* v = e->Attribute(attribute);
    if (!v) return fallback;
    std::array<double, N> out{};
    const char* p = v;
    std::size_t k = 0;
    for (; k <= N; ++k) {
      while (*p && std::isspace(static_cast<unsigned char>(*p))) ++p;
      if (!*p) break;
      char* end = nullptr;
      const double x = std::strtod(p, &end);
      if (end == p || k == N || !std::isfinite(x) ||
          (*end && !std::isspace(static_cast<unsigned char>(*end)))) {
        k = N + 1;
        break;
      }
      out[k] = x;
      p = end;
    }
    if (k != N) {
      diags_.error(at(e, attribute), fmt::format("{}: {}=\"{}\" should be {} finite number{} separated by spaces", what,
                                                 attribute, printable(v), N, N == 1 ? "" : "s"));
      return fallback;
    }
    // The range of the model language's numbers (docs/language.md, "Limits").
    for (const double x : out)
      if (std::abs(x) > limits::kMaxValue || (x != 0 && std::abs(x) < std::numeric_limits<double>::min())) {
        diags_.error(at(e, attribute), fmt::format("{}: {}=\"{}\": {} is outside the range of mbsc's numbers (1e-308 to "
                                                   "1e30 in magnitude, or 0)",
                                                   what, attribute, printable(v), x));
        return fallback;
      }
    return out;
  }

  double number(const XMLElement* e, const char* attribute, double fallback, const std::string& what,
                bool needed = false) {
    if (needed && !e->Attribute(attribute)) {
      diags_.error(at(e), fmt::format("{} needs the attribute {}", what, attribute));
      return fallback;
    }
    return numbers<1>(e, attribute, {fallback}, what)[0];
  }

  /// <origin xyz=".." rpy=".."/> under e, or the identity.
  Pose origin(const XMLElement* e, const std::string& what, Vec3* rpy_out = nullptr) {
    Pose pose;
    const XMLElement* o = e->FirstChildElement("origin");
    if (!o) return pose;
    pose.position = numbers<3>(o, "xyz", {0, 0, 0}, what + " <origin>");
    Vec3 rpy = numbers<3>(o, "rpy", {0, 0, 0}, what + " <origin>");
    if (std::abs(rpy[0]) > kMaxAngle || std::abs(rpy[1]) > kMaxAngle || std::abs(rpy[2]) > kMaxAngle) {
      diags_.error(at(o, "rpy"), fmt::format("{} <origin>: rpy angles beyond {:g} rad (thousands of turns) are not meant; "
                                             "write the angle within a turn",
                                             what, kMaxAngle));
      rpy = {0, 0, 0};
    }
    pose.rotation = rpy_rotation(rpy);
    if (rpy_out) *rpy_out = rpy;
    return pose;
  }

  UrdfLink link(const XMLElement* e) {
    UrdfLink l;
    l.pos = at(e);
    l.name = required(e, "name", "<link>");
    const std::string what = fmt::format("link '{}'", l.name);
    for (const XMLElement* c = e->FirstChildElement("visual"); c; c = c->NextSiblingElement("visual")) ++l.visuals;
    for (const XMLElement* c = e->FirstChildElement("collision"); c; c = c->NextSiblingElement("collision")) ++l.collisions;
    const XMLElement* in = e->FirstChildElement("inertial");
    if (!in) return l;
    UrdfInertial i;
    i.pos = at(in);
    i.origin = origin(in, what + ": <inertial>");
    const XMLElement* mass = in->FirstChildElement("mass");
    const XMLElement* inertia = in->FirstChildElement("inertia");
    if (!mass || !inertia) {
      diags_.error(i.pos, fmt::format("{}: <inertial> needs <mass> and <inertia>", what));
      return l;
    }
    i.mass = number(mass, "value", 0, what + ": <mass>", true);
    if (i.mass < 0) diags_.error(at(mass, "value"), fmt::format("{}: the mass must not be negative (it is {})", what, i.mass));
    const std::string it = what + ": <inertia>";
    i.ixx = number(inertia, "ixx", 0, it, true);
    i.ixy = number(inertia, "ixy", 0, it, true);
    i.ixz = number(inertia, "ixz", 0, it, true);
    i.iyy = number(inertia, "iyy", 0, it, true);
    i.iyz = number(inertia, "iyz", 0, it, true);
    i.izz = number(inertia, "izz", 0, it, true);
    l.inertial = i;
    return l;
  }

  UrdfJoint joint(const XMLElement* e) {
    UrdfJoint j;
    j.pos = at(e);
    j.name = required(e, "name", "<joint>");
    const std::string what = fmt::format("joint '{}'", j.name);
    j.type = required(e, "type", what);
    j.type_pos = at(e, "type");
    static const std::vector<std::string> kinds = {"revolute", "continuous", "prismatic", "fixed", "floating", "planar"};
    if (!j.type.empty() && std::find(kinds.begin(), kinds.end(), j.type) == kinds.end())
      diags_.error(j.type_pos, fmt::format("{}: unknown joint type '{}'{} (URDF's types: {})", what, printable(j.type),
                                           did_you_mean(j.type, kinds), list_names(kinds)));
    const XMLElement* parent = e->FirstChildElement("parent");
    const XMLElement* child = e->FirstChildElement("child");
    if (!parent || !child) {
      diags_.error(j.pos, fmt::format("{} needs a <parent link=\"...\"/> and a <child link=\"...\"/>", what));
      return j;
    }
    j.parent = required(parent, "link", what + ": <parent>");
    j.parent_pos = at(parent, "link");
    j.child = required(child, "link", what + ": <child>");
    j.child_pos = at(child, "link");
    j.origin = origin(e, what, &j.rpy);
    if (const XMLElement* axis = e->FirstChildElement("axis")) {
      j.axis_pos = at(axis, "xyz");
      j.axis = numbers<3>(axis, "xyz", {1, 0, 0}, what + ": <axis>");
    } else {
      j.axis_pos = j.pos;
    }
    if (const XMLElement* limit = e->FirstChildElement("limit")) {
      for (const tinyxml2::XMLAttribute* a = limit->FirstAttribute(); a; a = a->Next())
        j.limit += fmt::format("{}{} {}", j.limit.empty() ? "" : ", ", a->Name(), printable(a->Value()));
    }
    if (const XMLElement* dynamics = e->FirstChildElement("dynamics")) {
      j.dynamics_pos = at(dynamics);
      j.damping = number(dynamics, "damping", 0, what + ": <dynamics>");
      j.friction = number(dynamics, "friction", 0, what + ": <dynamics>");
      if (j.damping < 0 || j.friction < 0)
        diags_.error(j.dynamics_pos, fmt::format("{}: damping and friction must not be negative", what));
    }
    if (const XMLElement* mimic = e->FirstChildElement("mimic")) {
      UrdfMimic m;
      m.pos = at(mimic);
      m.joint = required(mimic, "joint", what + ": <mimic>");
      m.joint_pos = at(mimic, "joint");
      m.multiplier = number(mimic, "multiplier", 1, what + ": <mimic>");
      m.offset = number(mimic, "offset", 0, what + ": <mimic>");
      j.mimic = m;
    }
    j.safety = e->FirstChildElement("safety_controller") != nullptr;
    j.calibration = e->FirstChildElement("calibration") != nullptr;
    return j;
  }

  const std::string& path_;
  const std::string& text_;
  Diagnostics& diags_;
  std::vector<std::size_t> starts_;  // offset of each line's first character
  std::vector<std::pair<std::size_t, std::size_t>> skipped_;  // comments, CDATA, declarations
  std::map<const XMLElement*, std::size_t> offsets_;          // each element's '<' (locate)
  static constexpr double kMaxAngle = 1e4;
};

}  // namespace

std::optional<UrdfDocument> read_urdf(const std::string& path, const std::string& text, Diagnostics& diags) {
  return Reader(path, text, diags).read();
}

}  // namespace mbsc::import
