// SPDX-License-Identifier: GPL-2.0-or-later
// NAME.fmu of `mbsc generate --fmi` (include/mbsc/fmu/fmu_export.hpp).
#include "mbsc/fmu/fmu_export.hpp"

#include <fcntl.h>
#include <stdlib.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <ostream>
#include <set>
#include <sstream>

#include <fmt/format.h>

#include "mbsc/diag/diagnostics.hpp"
#include "mbsc/emit/fmu_glue.hpp"
#include "mbsc/emit/generated_model.hpp"
#include "mbsc/fmu/model_description.hpp"
#include "mbsc/fmu/zip_archive.hpp"
#include "mbsc/model/model.hpp"
#include "mbsc/run/compiled_model.hpp"
#include "mbsc/run/process.hpp"
#include "mbsc/run/run_setup.hpp"
#include "mbsc/run/sha256.hpp"

namespace fs = std::filesystem;

namespace mbsc::fmu {

/// Defined in the build folder's embedded_runtime.cpp (cmake/embed_runtime.cmake): the
/// headers under include/mbsc/runtime and include/mbsc/fmi, and the file LICENSE.
const std::vector<std::pair<std::string, std::string>>& runtime_files();
const std::string& licence_text();

namespace {

long int_constant(const emit::GeneratedModel& g, const std::string& name) {
  for (const auto& [n, v] : g.int_constants)
    if (n == name) return v;
  return 0;
}

/// The first `count` names of a generated name list (kInputNames holds a placeholder
/// when the model has no inputs).
std::vector<std::string> names(const emit::GeneratedModel& g, const std::string& list, long count) {
  for (const auto& [n, v] : g.name_lists)
    if (n == list) return std::vector<std::string>(v.begin(), v.begin() + std::min<long>(count, static_cast<long>(v.size())));
  return {};
}

std::vector<double> doubles(const emit::GeneratedModel& g, const std::string& list) {
  for (const auto& [n, v] : g.double_lists)
    if (n == list) return v;
  return {};
}

/// A guid-shaped token from the hash of everything the FMU holds but the token.
std::string token_of(const std::string& text) {
  const std::string h = run::sha256_hex(text);
  return "{" + h.substr(0, 8) + "-" + h.substr(8, 4) + "-" + h.substr(12, 4) + "-" + h.substr(16, 4) + "-" +
         h.substr(20, 12) + "}";
}

/// The state `mbsc run` starts from, at the default parameters (the frozen ones at their
/// frozen values), by name: through run's cached full-state object of the same model.
bool start_state(const driver::GenerateArgs& a, const driver::GenerateArgs::Made& made,
                 std::map<std::string, double>& value, std::set<std::string>& given, std::ostream& err, int& code) {
  run::CompileRequest req;
  req.model_path = a.model;
  req.work = a.work;
  req.work.quiet = true;
  code = 1;
  const auto compiled = run::compile_model(req, made.model, made.sources, err, code);
  if (!compiled) return false;
  const runtime::ModelTable& T = compiled->table();
  std::vector<double> p;
  std::string error;
  if (!run::parameter_values(T, {}, p, error)) {
    err << "mbsc: error: " << error << "\n";
    return false;
  }
  for (const auto& [name, v] : a.frozen)
    if (const int k = runtime::ModelTable::find(T.param_names, T.np, name.c_str()); k >= 0) p[static_cast<std::size_t>(k)] = v;
  std::vector<double> u(static_cast<std::size_t>(std::max(1, T.nin)), 0.0);
  run::InitialState init;
  if (!run::initial_state(made.model, T, p, u, {}, 0.0, init, error)) {
    err << "mbsc: error: the FMU's start values: " << error << "\n";
    return false;
  }
  if (init.assembly.near_singular)
    err << "mbsc: warning: the FMU's initial state is " << init.assembly.message << "\n";
  for (int i = 0; i < T.nx; ++i) value[T.state_names[i]] = init.x[static_cast<std::size_t>(i)];
  given.insert(init.given.begin(), init.given.end());
  code = 0;
  return true;
}

/// Writes `files` (relative paths) under a fresh folder in the system's temporary folder
/// and compiles the shared object there; `so` receives its bytes.
bool compile_fmu(const driver::GenerateArgs& a, const std::string& name,
                 const std::vector<std::pair<std::string, std::string>>& files, std::string& so, std::ostream& err) {
  std::string pattern = (fs::temp_directory_path() / "mbsc-fmu-XXXXXX").string();
  if (!::mkdtemp(pattern.data())) {
    err << "mbsc: error: cannot create a temporary folder to compile the FMU in: " << std::strerror(errno) << "\n";
    return false;
  }
  const fs::path dir = pattern;
  struct Cleanup {
    fs::path dir;
    ~Cleanup() {
      std::error_code ec;
      fs::remove_all(dir, ec);
    }
  } cleanup{dir};
  for (const auto& [path, text] : files) {
    std::error_code ec;
    fs::create_directories((dir / path).parent_path(), ec);
    std::ofstream out(dir / path, std::ios::binary);
    out << text;
    if (!out) {
      err << "mbsc: error: cannot write " << printable((dir / path).string()) << " to compile the FMU\n";
      return false;
    }
  }
  const int folder = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (folder < 0) {
    err << "mbsc: error: cannot open the FMU's temporary folder: " << std::strerror(errno) << "\n";
    return false;
  }
  run::ProcessOptions options;
  options.working_folder = folder;
  options.memory_mib = a.work.budget.memory_mib;
  options.timeout_seconds = std::max(1.0, a.work.budget.seconds_left());
  // The C++ runtime linked in and every symbol but the FMI functions kept local (the
  // version script): the binary loads into hosts that bring a libstdc++ of their own.
  {
    std::ofstream map(dir / "exports.map");
    map << "{\n  global: fmi2*; fmi3*;\n  local: *;\n};\n";
  }
  const std::string cxx = run::cxx_compiler();
  const run::ProcessResult cc =
      run::run_process({cxx, "-std=c++17", "-O2", "-fPIC", "-shared", "-fvisibility=hidden", "-static-libstdc++",
                        "-static-libgcc", "-Wl,--version-script=exports.map", "-I.", "-o", name + ".so", name + ".cpp", name + "_fmu.cpp"},
                       options);
  ::close(folder);
  if (!run::compiler_succeeded(cxx, cc, a.work.budget, err)) return false;
  std::ifstream in(dir / (name + ".so"), std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  so = bytes.str();
  if (so.empty()) {
    err << "mbsc: error: the C++ compiler wrote no shared object for the FMU\n";
    return false;
  }
  return true;
}

}  // namespace

std::string platform_folder(int version) {
#if defined(__linux__) && defined(__x86_64__)
  return version == 3 ? "x86_64-linux" : "linux64";
#elif defined(__linux__) && defined(__aarch64__)
  return version == 3 ? "aarch64-linux" : "";
#elif defined(__linux__) && defined(__i386__)
  return version == 3 ? "x86-linux" : "linux32";
#else
  (void)version;
  return "";
#endif
}

int add_fmu(const FmuOptions& o, const driver::GenerateArgs& a, const driver::GenerateArgs::Made& made,
            std::vector<driver::OutputFile>& outputs, std::ostream& err) {
  const emit::GeneratedModel& g = made.generated;
  const std::string platform = platform_folder(o.version);
  if (platform.empty()) {
    err << fmt::format("mbsc: error: FMI {}.0 names no platform folder for the machine mbsc was built for; export "
                       "with --fmi 3, or build the FMU's sources/ yourself\n",
                       o.version);
    return 1;
  }
  FmuDescription d;
  d.fmi_version = o.version;
  d.model_exchange = o.model_exchange;
  d.co_simulation = o.co_simulation;
  d.model_name = g.name;
  d.generation_tool = "mbsc " + g.tool_version;
  d.description = fmt::format("{} ({} formulation{})", fs::path(a.model).filename().string(),
                              a.multipliers ? "multipliers" : "complement", a.minimal_state ? ", minimal state" : "");
  const long nx = int_constant(g, "kNx");
  d.nq = static_cast<int>(int_constant(g, "kNq"));
  d.assembles = int_constant(g, "kNq") == int_constant(g, "kNqFull") && int_constant(g, "kNu") == int_constant(g, "kNuFull") &&
                (int_constant(g, "kNposc") > 0 || int_constant(g, "kNc") > 0);
  d.states = names(g, "kStateNames", nx);
  d.inputs = names(g, "kInputNames", int_constant(g, "kNin"));
  d.params = names(g, "kParamNames", int_constant(g, "kNp"));
  d.param_defaults = doubles(g, "kParamDefaults");
  d.outputs = names(g, "kOutputNames", int_constant(g, "kNy"));
  for (const auto& name : d.params) {
    std::string text = "parameter";
    for (const auto& v : made.model.params)
      if (v.name == name)
        text = fmt::format("parameter ({}:{})", fs::path(v.pos.file).filename().string(), v.pos.line);
    d.param_descriptions.push_back(text);
  }
  // The start values: run's start, picked by name (a minimal state's entries among them).
  std::map<std::string, double> value;
  std::set<std::string> given;
  int code = 0;
  if (!start_state(a, made, value, given, err, code)) return code;
  for (const auto& s : d.states) {
    const auto it = value.find(s);
    double v = it == value.end() ? 0.0 : it->second;
    // Assembly's round-off (1e-18 where the exact value is 0) and -0 written as 0.
    if (std::fabs(v) < (given.count(s) ? 0.0 : 1e-14) || v == 0.0) v = 0.0;
    d.start.push_back(v);
    d.given.push_back(given.count(s) > 0);
  }
  if (const std::string twice = repeated_name(d); !twice.empty()) {
    err << fmt::format("mbsc: error: the FMU would have two variables named '{}' (a state, input, parameter or output "
                       "of the model, or FMI's 'time'); rename one in the model\n",
                       printable(twice));
    return 1;
  }
  const std::string stem = g.name;
  d.source_files = {stem + ".cpp", stem + "_fmu.cpp"};

  emit::FmuGlue glue;
  glue.fmi_version = o.version;
  glue.model_exchange = o.model_exchange;
  glue.co_simulation = o.co_simulation;
  glue.multipliers = a.multipliers;
  glue.start = d.start;
  glue.given = d.given;
  // The token covers the model's code, the glue and the description (each without it).
  d.token = glue.token = "TOKEN";
  d.token = glue.token = token_of(made.files.header + made.files.source + emit::emit_fmu_glue(g, glue) +
                                  model_description_xml(d));
  std::vector<std::pair<std::string, std::string>> sources = {
      {stem + ".hpp", made.files.header}, {stem + ".cpp", made.files.source}, {stem + "_fmu.cpp", emit::emit_fmu_glue(g, glue)}};
  for (const auto& f : runtime_files()) sources.push_back(f);
  std::string so;
  if (!compile_fmu(a, stem, sources, so, err)) return 1;

  ZipArchive zip;
  zip.add("modelDescription.xml", model_description_xml(d));
  zip.add("binaries/" + platform + "/" + stem + ".so", so, true);
  for (const auto& [path, text] : sources) zip.add("sources/" + path, text);
  if (o.version == 3) zip.add("sources/buildDescription.xml", build_description_xml(d));
  zip.add("documentation/licenses/LICENSE.txt", licence_text());
  std::string bytes, error;
  if (!zip.bytes(bytes, error)) {
    err << "mbsc: error: the FMU: " << error << "\n";
    return 1;
  }
  outputs.push_back({stem + ".fmu", std::move(bytes)});
  return 0;
}

}  // namespace mbsc::fmu
