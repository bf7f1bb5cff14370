// SPDX-License-Identifier: GPL-2.0-or-later
// emit::emit_python: NAME.py of `generate --python`, a ctypes module over the extern "C"
// twins with the sizes and name tables of the header (templates/model.py.in).
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "mbsc/emit/generated_model.hpp"
#include "number_literal.hpp"
#include "renderer.hpp"
#include "text_blocks.hpp"

namespace mbsc::emit {

namespace {

// A Python tuple literal: "()", "(a,)", "(a, b)".
std::string tuple(const std::vector<std::string>& items) {
  if (items.size() == 1) return "(" + items[0] + ",)";
  return "(" + join(items, ", ") + ")";
}

std::string python_float(double v) {
  if (std::isnan(v)) return "float(\"nan\")";
  if (std::isinf(v)) return v < 0 ? "float(\"-inf\")" : "float(\"inf\")";
  return cpp_double_literal(v);  // "3.0", "0.1", "1e-5": Python reads them alike
}

long constant(const GeneratedModel& m, const std::string& name) {
  for (const auto& [n, v] : m.int_constants)
    if (n == name) return v;
  throw std::runtime_error("emit_python: no constant " + name);
}

// The output shape of a function as a tuple of numbers: "kNdof*kNdof" -> (2, 2); a
// shape that is not a product of the model's sizes is taken flat, (nout,).
std::string shape_tuple(const GeneratedModel& m, const ir::LoweredFunction& f) {
  std::vector<std::string> dims;
  long product = 1;
  std::string rest = f.out_shape.empty() ? std::to_string(f.nout) : f.out_shape;
  while (!rest.empty()) {
    const std::size_t star = rest.find('*');
    const std::string token = rest.substr(0, star);
    rest = star == std::string::npos ? "" : rest.substr(star + 1);
    long value = -1;
    if (!token.empty() && token.find_first_not_of("0123456789") == std::string::npos) {
      value = std::stol(token);
    } else {
      for (const auto& [n, v] : m.int_constants)
        if (n == token) value = v;
    }
    if (value < 0) return tuple({std::to_string(f.nout)});
    dims.push_back(std::to_string(value));
    product *= value;
  }
  if (product != f.nout) return tuple({std::to_string(f.nout)});
  return tuple(dims);
}

// The blocks of an output made of several matrices one after the other (a derivative:
// "kNx*kNx + kNx*kNin"), each as its two sizes; empty for an output of one block.
std::vector<std::pair<long, long>> output_blocks(const GeneratedModel& m, const ir::LoweredFunction& f) {
  std::vector<std::pair<long, long>> blocks;
  std::string rest = f.out_shape;
  if (rest.find(" + ") == std::string::npos) return {};
  while (!rest.empty()) {
    const std::size_t plus = rest.find(" + ");
    const std::string term = rest.substr(0, plus);
    rest = plus == std::string::npos ? "" : rest.substr(plus + 3);
    const std::size_t star = term.find('*');
    if (star == std::string::npos) return {};
    blocks.emplace_back(constant(m, term.substr(0, star)), constant(m, term.substr(star + 1)));
  }
  return blocks;
}

std::string constants(const GeneratedModel& m) {
  std::vector<std::string> lines;
  for (const auto& [name, value] : m.int_constants) lines.push_back(name + " = " + std::to_string(value));
  lines.push_back("");
  for (const auto& [name, values] : m.name_lists) {
    std::vector<std::string> items;
    for (const auto& v : values) items.push_back(c_string_literal(v));
    lines.push_back(name + " = " + tuple(items));
  }
  for (const auto& [name, values] : m.double_lists) {
    std::vector<std::string> items;
    for (double v : values) items.push_back(python_float(v));
    lines.push_back(name + " = " + tuple(items));
  }
  for (const auto& [name, values] : m.int_lists) {
    std::vector<std::string> items;
    for (long v : values) items.push_back(std::to_string(v));
    lines.push_back(name + " = " + tuple(items));
  }
  return join(lines, "\n");
}

// First line of a function's documentation, for its docstring.
std::string summary(const ir::LoweredFunction& f) {
  const std::string doc = f.doc.empty() ? f.name : f.doc;
  std::string line = doc.substr(0, doc.find('\n'));
  std::string clean;
  for (char c : line) clean += (c == '"' || c == '\\' || static_cast<unsigned char>(c) < 0x20) ? ' ' : c;
  return clean;
}

}  // namespace

std::string emit_python(const GeneratedModel& m) {
  std::vector<std::string> shapes, partition_shapes, methods;
  for (const auto& f : m.functions) {
    shapes.push_back(c_string_literal(f.name) + ": " + shape_tuple(m, f) + ",");
    if (const auto blocks = output_blocks(m, f); !blocks.empty()) {
      // A derivative: its blocks as matrices, (d/dx, d/du) or (d/dx, d/dzdot).
      const bool zdot = f.third_arg == "zdot";
      const std::string third = zdot ? "zdot" : "u";
      std::string body = "def " + f.name + "(self, t, x, " + third + "=None, p=None):\n    \"\"\"" + summary(f) +
                         ": a tuple of matrices.\"\"\"\n    out = self.call(\"" + f.name + "\", t, x, " + third + ", p" +
                         (zdot ? ", third=(\"zdot\", kNdof)" : "") + ")\n    return (";
      long at = 0;
      for (const auto& [rows, cols] : blocks) {
        body += "out[" + std::to_string(at) + ":" + std::to_string(at + rows * cols) + "].reshape((" + std::to_string(rows) +
                ", " + std::to_string(cols) + ")), ";
        at += rows * cols;
      }
      methods.push_back(body + ")");
    } else if (f.third_arg == "w")  // linear_parts: inputs, rates of every speed, multipliers
      methods.push_back("def " + f.name + "(self, t, x, w, p=None):\n    \"\"\"" + summary(f) + ".\"\"\"\n    return self.call(\"" +
                        f.name + "\", t, x, w, p, third=(\"w\", kLinearWSize))");
    else if (f.third_arg == "zdot")  // inverse_dynamics: the third argument is kNdof accelerations
      methods.push_back("def " + f.name + "(self, t, x, zdot, p=None):\n    \"\"\"" + summary(f) + ".\"\"\"\n    return self.call(\"" +
                        f.name + "\", t, x, zdot, p, third=(\"zdot\", kNdof))");
    else
      methods.push_back("def " + f.name + "(self, t, x, u=None, p=None):\n    \"\"\"" + summary(f) + ".\"\"\"\n    return self.call(\"" +
                        f.name + "\", t, x, u, p)");
  }
  if (m.partitions) {
    partition_shapes.push_back("\"rhs_partition\": (" + std::to_string(constant(m, "kNx")) + ",),");
    partition_shapes.push_back("\"conditioning_partition\": (1,),");
    methods.push_back("def rhs_partition(self, k, t, x, u=None, p=None):\n    \"\"\"State derivative computed with partition k "
                      "(kPartitionNames[k]).\"\"\"\n    return self.call_partition(\"rhs_partition\", k, t, x, u, p)");
    methods.push_back("def conditioning_partition(self, k, t, x, u=None, p=None):\n    \"\"\"Smallest reciprocal condition number of "
                      "the blocks partition k solves.\"\"\"\n    return self.call_partition(\"conditioning_partition\", k, t, x, u, p)");
  }
  Fragments py;
  py["banner"] = comment_block(banner_text(m), "#");
  py["name"] = m.name;
  py["constants"] = constants(m);
  py["function_shapes"] = join(shapes, "\n");
  py["partition_shapes"] = join(partition_shapes, "\n");
  py["methods"] = join(methods, "\n\n");
  return render("model.py.in", template_text("model.py.in"), py);
}

}  // namespace mbsc::emit
