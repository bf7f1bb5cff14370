// SPDX-License-Identifier: GPL-2.0-or-later
// Generate, compile, cache and load a model for `mbsc run` (include/mbsc/run/compiled_model.hpp).
#include "mbsc/run/compiled_model.hpp"
#include "mbsc/run/run_setup.hpp"

#include <dlfcn.h>
#include <sys/stat.h>
#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <signal.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <ginac/ginac.h>
#include <ostream>
#include <sstream>

#include "mbsc/diag/diagnostics.hpp"
#include "mbsc/driver/pipeline.hpp"
#include "mbsc/model/option_expression.hpp"
#include "mbsc/run/model_cache.hpp"
#include "mbsc/run/process.hpp"
#include "mbsc/run/sha256.hpp"

namespace fs = std::filesystem;

namespace mbsc::run {

namespace {

/// The namespace and file stem of the generated code in the cache: "model_<key>".
/// Unique per entry because GCC gives inline variables (kParamDefaults, the name
/// tables) unique-global linkage: two objects loaded at once (bench loads both
/// formulations) would otherwise share one copy of each table.
std::string stem_of(const std::string& key) { return "model_" + key; }

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// The mbsc binary itself (size and time), so that a rebuilt mbsc does not load objects
/// an older one generated.
std::string self_identity() {
  struct stat st {};
  if (stat("/proc/self/exe", &st) != 0) return "";
  return fmt::format("{} {}.{}", static_cast<long long>(st.st_size), static_cast<long long>(st.st_mtim.tv_sec),
                     static_cast<long long>(st.st_mtim.tv_nsec));
}

/// The shim compiled with the generated code: sizes, names and the inputs, behind
/// extern "C" names that do not depend on the model.
std::string shim_source(const std::string& kStem, const std::string& inputs_body, bool multipliers) {
  std::string s = fmt::format(
      "// Written by mbsc run: the model's sizes and name tables behind fixed names.\n"
      "#include <cmath>\n#include \"{0}.hpp\"\n"
      "namespace m = mbsc_gen::{0};\n"
      "extern \"C\" {{\n"
      "int mbsc_run_sizes(int* s) {{\n"
      "  const int v[] = {{m::kNq, m::kNu, m::kNx, m::kNdof, m::kNin, m::kNp, m::kNc, m::kNposc, m::kNy,\n"
      "                   m::kNpartitions, m::kNqFull, m::kNuFull}};\n"
      "  for (int i = 0; i < 12; ++i) s[i] = v[i];\n  return 12;\n}}\n"
      "const char* const* mbsc_run_names(int k) {{\n"
      "  switch (k) {{\n"
      "    case 0: return m::kStateNames;\n    case 1: return m::kDofNames;\n    case 2: return m::kInputNames;\n"
      "    case 3: return m::kParamNames;\n    case 4: return m::kConstraintNames;\n"
      "    case 5: return m::kPositionConstraintNames;\n    case 6: return m::kOutputNames;\n"
      "    case 7: return m::kPartitionNames;\n    case 8: return m::kFullStateNames;\n"
      "    default: return nullptr;\n  }}\n}}\n"
      "const double* mbsc_run_param_defaults() {{ return m::kParamDefaults; }}\n"
      "int mbsc_run_inputs(double t, const double* p, double* u) {{\n"
      "  (void)t; (void)p; (void)u;\n{1}  return 0;\n}}\n",
      kStem, inputs_body);
  s += fmt::format("int mbsc_run_multipliers() {{ return {}; }}\n}}\n", multipliers ? 1 : 0);
  return s;
}

template <class T>
bool symbol(void* h, const std::string& name, T& out, std::string& missing) {
  void* f = dlsym(h, name.c_str());
  if (!f) {
    missing = name;
    return false;
  }
  out = reinterpret_cast<T>(f);
  return true;
}

/// Fills `t` from the loaded object; false naming the first missing symbol.
bool fill_table(void* h, const std::string& kStem, runtime::ModelTable& t, int (*&inputs)(double, const double*, double*),
                std::string& missing) {
  int (*sizes)(int*) = nullptr;
  const char* const* (*names)(int) = nullptr;
  const double* (*defaults)() = nullptr;
  int (*mult)() = nullptr;
  if (!symbol(h, "mbsc_run_sizes", sizes, missing) || !symbol(h, "mbsc_run_names", names, missing) ||
      !symbol(h, "mbsc_run_param_defaults", defaults, missing) || !symbol(h, "mbsc_run_inputs", inputs, missing) ||
      !symbol(h, "mbsc_run_multipliers", mult, missing))
    return false;
  int s[12];
  sizes(s);
  t.nq = s[0], t.nu = s[1], t.nx = s[2], t.ndof = s[3], t.nin = s[4], t.np = s[5], t.nc = s[6], t.nposc = s[7];
  t.ny = s[8], t.npartitions = s[9], t.nq_full = s[10], t.nu_full = s[11];
  t.multipliers = mult() != 0;
  t.state_names = names(0), t.dof_names = names(1), t.input_names = names(2), t.param_names = names(3);
  t.constraint_names = names(4), t.position_constraint_names = names(5), t.output_names = names(6);
  t.partition_names = names(7);
  t.full_state_names = names(8);
  t.param_defaults = defaults();
  const std::string pre = std::string("mbsc_") + kStem + "_";
  bool ok = symbol(h, pre + "rhs", t.rhs, missing) && symbol(h, pre + "mass_matrix", t.mass_matrix, missing) &&
            symbol(h, pre + "forcing", t.forcing, missing) &&
            symbol(h, pre + "position_constraints", t.position_constraints, missing) &&
            symbol(h, pre + "velocity_constraints", t.velocity_constraints, missing) &&
            symbol(h, pre + "constraint_jacobian", t.constraint_jacobian, missing) &&
            symbol(h, pre + "position_jacobian", t.position_jacobian, missing) &&
            symbol(h, pre + "energy", t.energy, missing) && symbol(h, pre + "outputs", t.outputs, missing) &&
            symbol(h, pre + "full_state", t.full_state, missing) &&
            symbol(h, pre + "conditioning", t.conditioning, missing) &&
            symbol(h, pre + "rhs_partition", t.rhs_partition, missing) &&
            symbol(h, pre + "conditioning_partition", t.conditioning_partition, missing) &&
            symbol(h, pre + "inverse_dynamics", t.inverse_dynamics, missing);
  if (ok && t.multipliers)
    ok = symbol(h, pre + "multipliers", t.multipliers_fn, missing) &&
         symbol(h, pre + "reaction_forces", t.reaction_forces, missing);
  return ok;
}

/// Sets the umask for as long as it lives: what mbsc writes into the cache is private
/// whatever the user's umask.
class UmaskGuard {
 public:
  explicit UmaskGuard(mode_t mask) : old_(::umask(mask)) {}
  ~UmaskGuard() { ::umask(old_); }
  UmaskGuard(const UmaskGuard&) = delete;
  UmaskGuard& operator=(const UmaskGuard&) = delete;

 private:
  mode_t old_;
};

/// The compiler's output, each of its first lines made safe to print.
std::string compiler_lines(const std::string& output) {
  std::string shown;
  std::istringstream lines(output.substr(0, 4000));
  for (std::string line; std::getline(lines, line);) shown += "  " + printable(line) + "\n";
  return shown;
}

/// Generates the model into a work folder of the cache, compiles it there and publishes
/// it as `entry`. False with the messages on `err` and `exit_code` set.
bool build_entry(const CompileRequest& req, const CacheFolder& cache, const std::string& entry, const std::string& key,
                 const std::string& stem, const std::string& cxx, const std::vector<std::string>& flags,
                 const std::string& shim, std::ostream& err, int& exit_code) {
  std::string error;
  cache.tidy(entry);
  const auto work = cache.start_work(error);
  if (!work) {
    err << "mbsc: error: " << error << "\n";
    return false;
  }
  driver::GenerateArgs gen;
  gen.model = req.model_path;
  gen.out_dir = work->folder_path();
  gen.name = stem;
  gen.multipliers = req.multipliers;
  gen.minimal_state = req.minimal_state;
  gen.solver = req.solver;
  gen.linear_parts = req.linear_parts;
  gen.rhs_jacobian = req.rhs_jacobian;
  gen.rhs_jacobian_max_ops = kRunJacobianMaxOps;
  gen.work = req.work;
  gen.work.quiet = true;
  std::ostringstream sink;
  if (const int g = driver::run_generate(gen, sink, err); g != 0) {
    exit_code = g;
    return false;
  }
  const int folder = work->open_subfolder(stem);
  if (folder < 0 || !work->write_file(folder, "shim.cpp", shim, error)) {
    if (folder >= 0) ::close(folder);
    err << "mbsc: error: " << (error.empty() ? "the generated code is missing from the cache folder" : error) << "\n";
    return false;
  }
  ProcessOptions options;
  options.working_folder = folder;
  options.private_files = true;
  options.memory_mib = req.work.budget.memory_mib;
  options.timeout_seconds = std::max(1.0, req.work.budget.seconds_left());
  std::vector<std::string> cmd = {cxx};
  cmd.insert(cmd.end(), flags.begin(), flags.end());
  cmd.insert(cmd.end(), {"-o", "lib.so", stem + ".cpp", "shim.cpp"});
  const ProcessResult cc = run_process(cmd, options);
  ::close(folder);
  if (!compiler_succeeded(cxx, cc, req.work.budget, err)) return false;
  if (!work->publish(stem, entry, key, error)) {
    err << "mbsc: error: " << error << "\n";
    return false;
  }
  return true;
}

}  // namespace

CompiledModel::~CompiledModel() {
  if (handle_) dlclose(handle_);
}

std::string cache_folder(const std::string& requested) {
  if (!requested.empty()) return requested;
  if (const char* v = std::getenv("MBSC_CACHE_DIR"); v && *v) return v;
  if (const char* v = std::getenv("XDG_CACHE_HOME"); v && *v) return (fs::path(v) / "mbsc").string();
  if (const char* v = std::getenv("HOME"); v && *v) return (fs::path(v) / ".cache" / "mbsc").string();
  // No home: a folder of this user's own under the temporary folder (checked below).
  return (fs::temp_directory_path() / fmt::format("mbsc-cache-{}", static_cast<long>(getuid()))).string();
}

std::string input_expression_cpp(const model::Model& m, const std::string& text, std::string& error) {
  model::OptionNames names;
  std::map<std::string, std::string> cpp_names;
  names["t"] = m.time, cpp_names["t"] = "t";
  // Frozen (structural) parameters keep their p[] slot; every name is known here.
  for (std::size_t i = 0; i < m.params.size(); ++i) {
    names[m.params[i].name] = m.params[i].sym;
    cpp_names[m.params[i].name] = fmt::format("p[{}]", i);
  }
  if (!model::read_option_expression(text, names, "t and the model's parameters", error)) return "";
  return model::option_expression_cpp(text, cpp_names);
}

// An input is a function of t: when the expression read a coordinate or a speed, say how
// state feedback is written instead (docs/running.md, "Inputs").
static std::string state_feedback_hint(const model::Model& m, const std::string& error) {
  auto named = [&](const std::string& n) { return error.find("unknown name '" + n + "'") != std::string::npos; };
  std::string state;
  for (const auto& c : m.coords)
    if (state.empty() && named(c.name)) state = c.name;
  for (const auto& v : m.speeds)
    if (state.empty() && named(v.name)) state = v.name;
  if (state.empty()) return "";
  return fmt::format("; '{}' is part of the state, and an input is a function of t only: feed the state back in the "
                     "model, where forces may read it (a joint's `force -k*{}`, or a `force` statement), with the gain "
                     "a parameter",
                     state, state);
}

bool compiler_succeeded(const std::string& cxx, const ProcessResult& cc, const driver::WorkBudget& budget,
                        std::ostream& err) {
  if (cc.timed_out) {
    err << fmt::format("mbsc: error: the C++ compiler '{}' was stopped when the time budget of {:g} s ran out (it "
                       "covers the whole command; raise it with --budget SECONDS)\n",
                       printable(cxx), budget.seconds);
    return false;
  }
  if (cc.exit_code != 0) {
    const bool memory = cc.output.find("memory exhausted") != std::string::npos ||
                        cc.output.find("Cannot allocate memory") != std::string::npos ||
                        cc.output.find("out of memory") != std::string::npos || cc.output.find("bad_alloc") != std::string::npos;
    if (memory)
      err << fmt::format("mbsc: error: the C++ compiler '{}' ran out of the memory budget of {} MiB on the generated "
                         "code (raise it with --max-memory MIB):\n{}",
                         printable(cxx), budget.memory_mib, compiler_lines(cc.output));
    else
      err << fmt::format("mbsc: error: the C++ compiler failed on the generated code ({}, exit code {}{}):\n{}",
                         printable(cxx), cc.exit_code, cc.spawn_error.empty() ? "" : ", " + cc.spawn_error,
                         compiler_lines(cc.output));
    return false;
  }
  return true;
}

std::string cxx_compiler() {
  for (const char* var : {"MBSC_CXX", "CXX"})
    if (const char* v = std::getenv(var); v && *v) return v;
  return "c++";
}

std::unique_ptr<CompiledModel> compile_model(const CompileRequest& req, const model::Model& m,
                                             const std::vector<std::string>& sources, std::ostream& err, int& exit_code) {
  exit_code = 1;
  // ---- the inputs, as C++ ----
  std::string inputs_body;
  for (const auto& [name, text] : req.input_expressions) {
    int index = -1;
    for (std::size_t i = 0; i < m.inputs.size(); ++i)
      if (m.inputs[i].name == name) index = static_cast<int>(i);
    if (index < 0) {
      err << "mbsc: error: " << unknown_input_message(m, name) << "\n";
      return nullptr;
    }
    std::string error;
    const std::string cpp = input_expression_cpp(m, text, error);
    if (cpp.empty()) {
      err << "mbsc: error: --input " << printable(name) << ": " << error << state_feedback_hint(m, error) << "\n";
      return nullptr;
    }
    inputs_body += fmt::format("  u[{}] = {};\n", index, cpp);
  }
  // ---- the key ----
  const std::string cxx = cxx_compiler();
  const std::vector<std::string> flags = {"-std=c++17", "-O2", "-fPIC", "-shared"};
  ProcessResult version = run_process({cxx, "--version"}, "", 30);
  if (version.timed_out) {
    err << fmt::format("mbsc: error: the C++ compiler '{}' did not answer --version within 30 s\n", printable(cxx));
    return nullptr;
  }
  if (version.exit_code != 0) {
    err << fmt::format("mbsc: error: no working C++ compiler: '{}' {} (install g++, or name one with the CXX or "
                       "MBSC_CXX environment variable)\n",
                       printable(cxx), version.spawn_error.empty() ? "--version failed" : version.spawn_error);
    return nullptr;
  }
  std::string key_text = std::string("mbsc ") + MBSC_VERSION + " " + self_identity() + "\n" + cxx + "\n" + version.output + "\n";
  for (const auto& f : flags) key_text += f + " ";
  key_text += req.multipliers ? "\nmultipliers\n" : "\ncomplement\n";
  key_text += req.minimal_state ? "minimal\n" : "full\n";
  key_text += "solver " + req.solver + "\n";
  if (req.linear_parts) key_text += "linear_parts\n";
  if (req.rhs_jacobian) key_text += "rhs_jacobian " + std::to_string(kRunJacobianMaxOps) + "\n";
  key_text += inputs_body;
  for (const auto& s : sources) key_text += "\n--- " + s + "\n" + read_text(s);
  // The entry's name: the model's and 16 hex digits of the key's hash; its record holds
  // the whole hash, checked on loading.
  const std::string key = sha256_hex(key_text);
  const std::string kStem = stem_of(key.substr(0, 16));
  const std::string entry = m.name.substr(0, 64) + "-" + key.substr(0, 16);

  auto result = std::unique_ptr<CompiledModel>(new CompiledModel());
  const UmaskGuard private_files(077);
  std::string error;
  const auto cache = CacheFolder::open(cache_folder(req.cache_dir), error);
  if (!cache) {
    err << "mbsc: error: " << error << "\n";
    return nullptr;
  }
  const std::string entry_path = (fs::path(cache->path()) / entry).string();
  std::string why;
  int object = cache->open_object(entry, key, why);
  if (object < 0 && !why.empty()) {
    err << fmt::format("mbsc: warning: the cached model '{}' cannot be used: {}; compiling it again\n",
                       printable(entry_path), why);
    cache->remove_entry(entry);
  }
  result->from_cache_ = object >= 0;
  if (object < 0) {
    if (!build_entry(req, *cache, entry, key, kStem, cxx, flags, shim_source(kStem, inputs_body, req.multipliers), err,
                     exit_code))
      return nullptr;
    object = cache->open_object(entry, key, why);
    if (object < 0) {
      err << fmt::format("mbsc: error: the compiled model '{}' cannot be loaded: {}\n", printable(entry_path),
                         why.empty() ? "it is not in the cache folder" : why);
      return nullptr;
    }
    if (!req.work.quiet)
      err << fmt::format("mbsc: compiled {} ({}) into {}\n", m.name, req.multipliers ? "multipliers" : "complement",
                         printable(entry_path));
  }
  // Loaded through the descriptor that was checked: the file verified is the file loaded.
  // The descriptor stays open for the rest of the process: the dynamic loader knows an
  // object by the name it was loaded under, and GCC's unique symbols (the generated
  // inline tables) keep an object loaded after dlclose, so a later object loaded under
  // a reused /proc/self/fd/N would be taken for this one.
  result->folder_ = entry_path;
  result->handle_ = dlopen(fmt::format("/proc/self/fd/{}", object).c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!result->handle_) ::close(object);
  if (!result->handle_) {
    const char* dl = dlerror();
    err << fmt::format("mbsc: error: cannot load the compiled model '{}': {} (remove that folder to rebuild it)\n",
                       printable(entry_path), printable(dl ? dl : "unknown reason"));
    return nullptr;
  }
  std::string missing;
  if (!fill_table(result->handle_, kStem, result->table_, result->inputs_, missing)) {
    err << fmt::format("mbsc: error: the compiled model '{}' lacks '{}' (remove that folder to rebuild it)\n",
                       printable(entry_path), missing);
    return nullptr;
  }
  if (req.rhs_jacobian && !symbol(result->handle_, "mbsc_" + kStem + "_rhs_jacobian", result->table_.rhs_jacobian, missing)) {
    err << fmt::format("mbsc: error: the compiled model '{}' lacks '{}' (remove that folder to rebuild it)\n",
                       printable(entry_path), missing);
    return nullptr;
  }
  if (req.linear_parts && !symbol(result->handle_, "mbsc_" + kStem + "_linear_parts", result->linear_parts_, missing)) {
    err << fmt::format("mbsc: error: the compiled model '{}' lacks '{}' (remove that folder to rebuild it)\n",
                       printable(entry_path), missing);
    return nullptr;
  }
  exit_code = 0;
  return result;
}

}  // namespace mbsc::run
