// SPDX-License-Identifier: GPL-2.0-or-later
// emit: the batched entry points NAME_at / NAME_batch and their struct-of-arrays layout.
// Instance i's columns are copied into local arrays and the ordinary function is called on
// them, so a batch gives, value for value, what n ordinary calls give.
#include "batch_code.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

#include "text_blocks.hpp"

namespace mbsc::emit {

namespace {

long constant(const GeneratedModel& m, const std::string& name) {
  for (const auto& [n, v] : m.int_constants)
    if (n == name) return v;
  throw std::runtime_error("cannot batch: the model has no constant " + name);
}

const ir::LoweredFunction& function_named(const GeneratedModel& m, const std::string& name) {
  for (const auto& f : m.functions)
    if (f.name == name) return f;
  throw std::runtime_error("cannot batch '" + name + "': the model emits no such function");
}

/// Rows of each argument of a batched function: x, the third argument, p, OUT.
struct Rows {
  long x, third, p, out;
};

bool reads(const ir::LoweredFunction& f, const std::string& arg) {
  return std::find(f.used_args.begin(), f.used_args.end(), arg) != f.used_args.end();
}

// An argument the function does not read has no rows: the batch passes it null and
// does not ask for it.
Rows rows_of(const GeneratedModel& m, const ir::LoweredFunction& f) {
  const long third = f.third_arg == "u"      ? constant(m, "kNin")
                     : f.third_arg == "zdot" ? constant(m, "kNdof")
                     : f.third_arg == "w"    ? constant(m, "kLinearWSize")
                                             : -1;
  if (third < 0) throw std::runtime_error("cannot batch '" + f.name + "': unknown argument '" + f.third_arg + "'");
  return {constant(m, "kNx"), reads(f, f.third_arg) ? third : 0, reads(f, "p") ? constant(m, "kNp") : 0, f.nout};
}

const char* kLayoutDoc =
    "Batched evaluation (docs/batched.md). A batch is n instances of one function, each with its own\n"
    "time, state, inputs and parameters, in struct-of-arrays layout: an array is a matrix with a row\n"
    "per value and a column per instance, value k of instance i at a[k * ld + i], where ld >= n is\n"
    "that array's leading dimension. ld = 0 shares one column among all instances (value k at a[k]):\n"
    "one time or one parameter vector for the whole batch. Outputs are not shared: ldout >= n.\n"
    "NAME_at(i, a) evaluates instance i (0 <= i < n, the layout unchecked): what a GPU thread calls\n"
    "where MBSC_HOST_DEVICE is __host__ __device__. NAME_batch(n, a, status) evaluates instances 0\n"
    "to n-1 in turn on the calling thread, status[i] (status may be null) getting instance i's code;\n"
    "it returns the largest code, or 3, evaluating nothing, when the layout is invalid (n < 0, a\n"
    "leading dimension below n other than 0, or x, u, p or out null where the function reads or writes it).\n"
    "Each instance's values are those of the ordinary function called on its columns, with NaN where\n"
    "a failing instance's function wrote nothing (a singular solve returns before writing).";

const char* kStruct = R"cpp(struct BatchArrays {
  const double* t = nullptr;  // 1 row; null: t = 0 for every instance
  int ldt = 0;
  const double* x = nullptr;  // kNx rows
  int ldx = 0;
  const double* u = nullptr;  // the third argument: u (kNin rows), zdot (kNdof) or w (kLinearWSize); null where unread
  int ldu = 0;
  const double* p = nullptr;  // kNp rows
  int ldp = 0;
  double* out = nullptr;  // the function's output, one row per value
  int ldout = 0;
};)cpp";

// The helpers every batch uses, and those only batches with outputs use (an unused one
// would be a warning in the user's build).
const char* kGatherHelpers = R"cpp(// Column i of a batch array of `rows` values with leading dimension ld (0: one column
// shared by every instance) into v[0..rows).
MBSC_HOST_DEVICE void batch_gather(const double* a, int ld, int i, int rows, double* v) {
  const long long stride = ld > 0 ? ld : 1;
  const long long column = ld > 0 ? i : 0;
  for (int k = 0; k < rows; ++k) v[k] = a[k * stride + column];
}

// An input array of `rows` values can be read for n instances.
MBSC_HOST_DEVICE bool batch_input_ok(const double* a, int ld, int rows, int n) {
  return rows == 0 || n == 0 || (a != nullptr && (ld == 0 || ld >= n));
}

// A batch of n instances can be read and written as `a` describes.
MBSC_HOST_DEVICE bool batch_layout_ok(int n, const BatchArrays& a, int x_rows, int u_rows, int p_rows, int out_rows) {
  return n >= 0 && (a.t == nullptr || batch_input_ok(a.t, a.ldt, 1, n)) && batch_input_ok(a.x, a.ldx, x_rows, n) &&
         batch_input_ok(a.u, a.ldu, u_rows, n) && batch_input_ok(a.p, a.ldp, p_rows, n) &&
         (out_rows == 0 || n == 0 || (a.out != nullptr && a.ldout >= n));
})cpp";

const char* kOutputHelpers = R"cpp(// v[0..rows) = quiet NaN: what a failed instance shows where its function wrote nothing.
MBSC_HOST_DEVICE void batch_fill_nan(int rows, double* v) {
  const std::uint64_t bits = 0x7ff8000000000000u;
  double nan;
  std::memcpy(&nan, &bits, sizeof nan);
  for (int k = 0; k < rows; ++k) v[k] = nan;
}

// v[0..rows) into column i of a batch array with leading dimension ld.
MBSC_HOST_DEVICE void batch_scatter(const double* v, int rows, int i, int ld, double* a) {
  for (int k = 0; k < rows; ++k) a[static_cast<long long>(k) * ld + i] = v[k];
})cpp";

std::string n(long v) { return std::to_string(v); }

std::string at_definition(const GeneratedModel& m, const ir::LoweredFunction& f) {
  const Rows r = rows_of(m, f);
  const std::string& u = f.third_arg;
  std::string s = "MBSC_HOST_DEVICE int " + f.name + "_at(int i, const BatchArrays& a) {\n";
  std::vector<std::string> locals;
  if (r.x > 0) locals.push_back("x[" + n(r.x) + "]");
  if (r.out > 0) locals.push_back("out[" + n(r.out) + "]");
  if (!locals.empty()) s += "  double " + join(locals, ", ") + ";\n";
  if (r.x > 0) s += "  batch_gather(a.x, a.ldx, i, " + n(r.x) + ", x);\n";
  // Shared arguments (ld = 0) are read in place; an instance's own column is copied.
  auto own_or_shared = [&](const std::string& name, const std::string& member, const std::string& ld, long rows) {
    s += "  const double* " + name + " = a." + member + ";\n";
    s += "  double " + name + "_i[" + n(rows) + "];\n";
    s += "  if (a." + ld + " > 0) {\n    batch_gather(a." + member + ", a." + ld + ", i, " + n(rows) + ", " + name +
         "_i);\n    " + name + " = " + name + "_i;\n  }\n";
  };
  if (r.third > 0) own_or_shared(u, "u", "ldu", r.third);
  if (r.p > 0) own_or_shared("p", "p", "ldp", r.p);
  if (r.out > 0) s += "  batch_fill_nan(" + n(r.out) + ", out);\n";
  s += "  const double t = a.t == nullptr ? 0.0 : a.t[a.ldt > 0 ? i : 0];\n";
  s += "  const int status = " + f.name + "(t, " + (r.x > 0 ? "x" : "nullptr") + ", " + (r.third > 0 ? u : "nullptr") +
       ", " + (r.p > 0 ? "p" : "nullptr") + ", " + (r.out > 0 ? "out" : "nullptr") + ");\n";
  if (r.out > 0) s += "  batch_scatter(out, " + n(r.out) + ", i, a.ldout, a.out);\n";
  return s + "  return status;\n}";
}

std::string batch_definition(const GeneratedModel& m, const ir::LoweredFunction& f) {
  const Rows r = rows_of(m, f);
  return "MBSC_HOST_DEVICE int " + f.name + "_batch(int n, const BatchArrays& a, int* status) {\n" +
         "  if (!batch_layout_ok(n, a, " + std::to_string(r.x) + ", " + std::to_string(r.third) + ", " +
         std::to_string(r.p) + ", " + std::to_string(r.out) + ")) return 3;\n" +
         "  int worst = 0;\n"
         "  for (int i = 0; i < n; ++i) {\n"
         "    const int code = " + f.name + "_at(i, a);\n"
         "    if (status != nullptr) status[i] = code;\n"
         "    worst = code > worst ? code : worst;\n"
         "  }\n"
         "  return worst;\n}";
}

std::string c_signature(const GeneratedModel& m, const ir::LoweredFunction& f) {
  return "int mbsc_" + m.name + "_" + f.name + "_batch(int n, const double* t, int ldt, const double* x, int ldx, const double* " +
         f.third_arg + ", int ld" + f.third_arg + ", const double* p, int ldp, double* OUT, int ldout, int* status)";
}

}  // namespace

std::string batch_declarations(const GeneratedModel& m) {
  if (m.batched.empty()) return "";
  std::vector<std::string> blocks = {comment_block(kLayoutDoc, "///") + "\n" + kStruct};
  for (const auto& name : m.batched) {
    const auto& f = function_named(m, name);
    blocks.push_back("/// " + name + " of instance i of a batch; " + name + " of instances 0 .. n-1 (BatchArrays).\n" +
                     "MBSC_HOST_DEVICE int " + name + "_at(int i, const BatchArrays& a);\n" + "MBSC_HOST_DEVICE int " +
                     f.name + "_batch(int n, const BatchArrays& a, int* status);");
  }
  return join(blocks, "\n\n");
}

std::string batch_definitions(const GeneratedModel& m) {
  if (m.batched.empty()) return "";
  bool any_outputs = false;
  for (const auto& name : m.batched) any_outputs = any_outputs || function_named(m, name).nout > 0;
  std::vector<std::string> blocks = {std::string("namespace {\n\n") + kGatherHelpers +
                                     (any_outputs ? std::string("\n\n") + kOutputHelpers : std::string()) +
                                     "\n\n}  // namespace"};
  for (const auto& name : m.batched) {
    const auto& f = function_named(m, name);
    blocks.push_back(at_definition(m, f));
    blocks.push_back(batch_definition(m, f));
  }
  return join(blocks, "\n\n");
}

std::string batch_c_declarations(const GeneratedModel& m) {
  std::vector<std::string> lines;
  for (const auto& name : m.batched) lines.push_back(c_signature(m, function_named(m, name)) + ";");
  return join(lines, "\n");
}

std::string batch_c_definitions(const GeneratedModel& m) {
  std::vector<std::string> blocks;
  for (const auto& name : m.batched) {
    const auto& f = function_named(m, name);
    const std::string ns = "mbsc_gen::" + m.name + "::";
    blocks.push_back("extern \"C\" " + c_signature(m, f) + " {\n  " + ns + "BatchArrays a;\n" +
                     "  a.t = t;\n  a.ldt = ldt;\n  a.x = x;\n  a.ldx = ldx;\n  a.u = " + f.third_arg + ";\n  a.ldu = ld" +
                     f.third_arg + ";\n  a.p = p;\n  a.ldp = ldp;\n  a.out = OUT;\n  a.ldout = ldout;\n  return " + ns +
                     f.name + "_batch(n, a, status);\n}");
  }
  return join(blocks, "\n\n");
}

}  // namespace mbsc::emit
