// SPDX-License-Identifier: GPL-2.0-or-later
// `mbsc generate --fmi 2|3`: the FMU loaded as an importer would load it (the zip read by
// a reader of this file, its binary dlopen'ed, the FMI calling sequences of model exchange
// and co-simulation driven by this file's own integrator), its trajectories compared with
// `mbsc run`'s, and modelDescription.xml checked against the standard's rules (unique
// value references and names, causality/variability/initial combinations, every
// derivative's state declared, ModelStructure listing exactly the outputs, derivatives
// and initial unknowns). Also: the kinds exported, a wrong token, a parameter set after
// initialization, FMU states saved and restored, the bytes equal from run to run.
#include <catch2/catch.hpp>
#include <dlfcn.h>
#include <tinyxml2.h>

#include <cmath>
#include <cstdarg>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "mbsc/fmi/fmi2_functions.h"
#include "mbsc/fmi/fmi3_functions.h"
#include "run_command.hpp"

using mbsc_test::quote;
using mbsc_test::run;

namespace fs = std::filesystem;

namespace {

const std::string kSource = MBSC_SOURCE_DIR;
const std::string kMbsc = MBSC_BINARY;

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// ---- the zip container, read independently of mbsc's writer ----

std::uint32_t le(const std::string& s, std::size_t at, int bytes) {
  std::uint32_t v = 0;
  for (int i = bytes - 1; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(s.at(at + static_cast<std::size_t>(i)));
  return v;
}

/// CRC-32 bit by bit (mbsc's writer uses a table).
std::uint32_t crc_bitwise(const std::string& data) {
  std::uint32_t c = 0xffffffffu;
  for (unsigned char b : data) {
    c ^= b;
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
  }
  return ~c;
}

/// Every entry of a zip through its central directory; stored entries only (what mbsc
/// writes). CHECKs the signatures, sizes and CRCs.
std::map<std::string, std::string> unzip(const std::string& zip) {
  std::map<std::string, std::string> files;
  const std::size_t end = zip.rfind(std::string("PK\x05\x06", 4));
  REQUIRE(end != std::string::npos);
  const std::uint32_t count = le(zip, end + 10, 2), dir_offset = le(zip, end + 16, 4);
  std::size_t at = dir_offset;
  for (std::uint32_t k = 0; k < count; ++k) {
    REQUIRE(le(zip, at, 4) == 0x02014b50u);
    const std::uint32_t method = le(zip, at + 10, 2), crc = le(zip, at + 16, 4), size = le(zip, at + 20, 4);
    const std::uint32_t name_len = le(zip, at + 28, 2), extra = le(zip, at + 30, 2), comment = le(zip, at + 32, 2);
    const std::uint32_t local = le(zip, at + 42, 4);
    const std::string name = zip.substr(at + 46, name_len);
    REQUIRE(method == 0);
    REQUIRE(le(zip, local, 4) == 0x04034b50u);
    const std::size_t data = local + 30 + le(zip, local + 26, 2) + le(zip, local + 28, 2);
    files[name] = zip.substr(data, size);
    CHECK(crc_bitwise(files[name]) == crc);
    at += 46 + name_len + extra + comment;
  }
  return files;
}

// ---- modelDescription.xml ----

struct Variable {
  std::string name, causality, variability, initial;
  unsigned vr = 0;
  bool has_start = false;
  double start = 0;
  long derivative = -1;  // FMI 2.0: 1-based index; FMI 3.0: a value reference
};

struct Description {
  std::string token, identifier;
  bool me = false, cs = false;
  std::vector<Variable> vars;
  std::vector<long> outputs, derivatives, initial_unknowns;  // FMI 2.0: indices; 3.0: value references
  double tolerance = 0;
};

std::string attr(const tinyxml2::XMLElement* e, const char* name) {
  const char* v = e->Attribute(name);
  return v ? v : "";
}

Description read_description(const std::string& xml, int version) {
  tinyxml2::XMLDocument doc;
  REQUIRE(doc.Parse(xml.c_str(), xml.size()) == tinyxml2::XML_SUCCESS);
  const auto* root = doc.FirstChildElement("fmiModelDescription");
  REQUIRE(root);
  Description d;
  CHECK(attr(root, "fmiVersion") == (version == 3 ? "3.0" : "2.0"));
  d.token = attr(root, version == 3 ? "instantiationToken" : "guid");
  for (const char* kind : {"ModelExchange", "CoSimulation"})
    if (const auto* e = root->FirstChildElement(kind)) {
      (std::string(kind) == "ModelExchange" ? d.me : d.cs) = true;
      d.identifier = attr(e, "modelIdentifier");
    }
  if (const auto* e = root->FirstChildElement("DefaultExperiment")) d.tolerance = e->DoubleAttribute("tolerance");
  const auto* vars = root->FirstChildElement("ModelVariables");
  REQUIRE(vars);
  for (const auto* e = vars->FirstChildElement(); e; e = e->NextSiblingElement()) {
    Variable v;
    v.name = attr(e, "name");
    v.vr = e->UnsignedAttribute("valueReference");
    v.causality = attr(e, "causality");
    v.variability = attr(e, "variability");
    v.initial = attr(e, "initial");
    const tinyxml2::XMLElement* typed = e;
    if (version == 2) {
      CHECK(std::string(e->Name()) == "ScalarVariable");
      typed = e->FirstChildElement("Real");
      REQUIRE(typed);
    } else {
      CHECK(std::string(e->Name()) == "Float64");
    }
    v.has_start = typed->Attribute("start") != nullptr;
    v.start = typed->DoubleAttribute("start");
    if (typed->Attribute("derivative")) v.derivative = typed->Int64Attribute("derivative");
    if (v.causality.empty()) v.causality = "local";
    if (v.variability.empty()) v.variability = "continuous";
    d.vars.push_back(v);
  }
  const auto* ms = root->FirstChildElement("ModelStructure");
  REQUIRE(ms);
  if (version == 2) {
    auto list = [&](const char* name, std::vector<long>& out) {
      if (const auto* e = ms->FirstChildElement(name))
        for (const auto* u = e->FirstChildElement("Unknown"); u; u = u->NextSiblingElement("Unknown"))
          out.push_back(u->Int64Attribute("index"));
    };
    list("Outputs", d.outputs);
    list("Derivatives", d.derivatives);
    list("InitialUnknowns", d.initial_unknowns);
  } else {
    for (const auto* e = ms->FirstChildElement(); e; e = e->NextSiblingElement()) {
      const std::string n = e->Name();
      const long vr = e->Int64Attribute("valueReference");
      if (n == "Output") d.outputs.push_back(vr);
      else if (n == "ContinuousStateDerivative") d.derivatives.push_back(vr);
      else if (n == "InitialUnknown") d.initial_unknowns.push_back(vr);
    }
  }
  return d;
}

/// The rules of the standards' variable tables that an mbsc export can meet.
void check_rules(const Description& d, int version) {
  std::set<std::string> names;
  std::set<unsigned> vrs;
  int independents = 0;
  for (const auto& v : d.vars) {
    INFO(v.name);
    CHECK(names.insert(v.name).second);
    CHECK(vrs.insert(v.vr).second);
    const std::string& c = v.causality;
    const std::string& var = v.variability;
    // causality x variability (FMI 2.0 table 2.2.7; 3.0 the same for these kinds)
    if (c == "parameter" || c == "calculatedParameter") CHECK((var == "fixed" || var == "tunable"));
    else if (c == "input") CHECK((var == "discrete" || var == "continuous"));
    else if (c == "independent") {
      CHECK(var == "continuous");
      CHECK(!v.has_start);
      CHECK(v.initial.empty());
      ++independents;
    } else CHECK((c == "output" || c == "local"));
    // initial
    if (c == "parameter") {
      CHECK((v.initial.empty() || v.initial == "exact"));
      CHECK(v.has_start);
    } else if (c == "input") {
      CHECK(v.initial.empty());
      CHECK(v.has_start);
    } else if (c == "output" && var == "continuous") {
      CHECK((v.initial.empty() || v.initial == "calculated" || v.initial == "exact"));
    } else if (c == "local" && var == "continuous") {
      CHECK((v.initial.empty() || v.initial == "calculated" || v.initial == "exact" || v.initial == "approx"));
    }
    if (v.initial == "exact" || v.initial == "approx") CHECK(v.has_start);
    if (v.initial == "calculated" || v.initial.empty()) {
      if (c == "local" || c == "output") CHECK(!v.has_start);
    }
  }
  CHECK(independents == (version == 3 ? 1 : 0));
  // Each derivative names a declared continuous real state.
  auto state_of = [&](const Variable& der) -> const Variable* {
    if (version == 2) return der.derivative >= 1 && der.derivative <= static_cast<long>(d.vars.size())
                                 ? &d.vars[static_cast<std::size_t>(der.derivative - 1)]
                                 : nullptr;
    for (const auto& v : d.vars)
      if (static_cast<long>(v.vr) == der.derivative) return &v;
    return nullptr;
  };
  std::vector<long> outputs, derivatives, initial;
  for (std::size_t i = 0; i < d.vars.size(); ++i) {
    const Variable& v = d.vars[i];
    const long key = version == 2 ? static_cast<long>(i + 1) : static_cast<long>(v.vr);
    if (v.causality == "output") outputs.push_back(key);
    if (v.derivative >= 0) {
      const Variable* s = state_of(v);
      REQUIRE(s);
      CHECK(s->variability == "continuous");
      CHECK(s->derivative < 0);
      CHECK(v.name == "der(" + s->name + ")");
      derivatives.push_back(key);
    }
    if ((v.causality == "output" && (v.initial.empty() || v.initial == "calculated")) || v.derivative >= 0 ||
        (v.initial == "approx" || (v.causality == "local" && v.initial == "calculated")))
      initial.push_back(key);
  }
  // The states: every variable a derivative names, in the order of their derivatives.
  CHECK(d.outputs == outputs);
  CHECK(d.derivatives == derivatives);
  CHECK(d.initial_unknowns == initial);
}

// ---- mbsc run's trajectory ----

struct Table {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
  double at(std::size_t row, const std::string& column) const {
    for (std::size_t c = 0; c < columns.size(); ++c)
      if (columns[c] == column) return rows.at(row).at(c);
    FAIL("no column " << column);
    return 0;
  }
};

Table read_csv(const fs::path& p) {
  Table t;
  std::istringstream in(slurp(p));
  std::string line;
  std::getline(in, line);
  std::stringstream header(line);
  for (std::string c; std::getline(header, c, ',');) t.columns.push_back(c);
  while (std::getline(in, line)) {
    std::stringstream row(line);
    std::vector<double> r;
    for (std::string c; std::getline(row, c, ',');) r.push_back(std::stod(c));
    t.rows.push_back(r);
  }
  return t;
}

// ---- the importer ----

std::vector<std::string> g_log;  // the FMU's messages

void log2(fmi2ComponentEnvironment, fmi2String, fmi2Status, fmi2String, fmi2String message, ...) {
  // mbsc passes "%s" and the text.
  va_list args;
  va_start(args, message);
  char buf[2048];
  std::vsnprintf(buf, sizeof buf, message, args);
  va_end(args);
  g_log.push_back(buf);
}
void log3(fmi3InstanceEnvironment, fmi3Status, fmi3String, fmi3String message) { g_log.push_back(message); }

class Library {
 public:
  explicit Library(const fs::path& so) : h_(dlopen(so.c_str(), RTLD_NOW | RTLD_LOCAL)) {
    INFO(dlerror_text());
    REQUIRE(h_);
  }
  // Never closed: each FMU links its own libstdc++, whose emergency exception pool is
  // allocated when it loads; once unloaded, LeakSanitizer counts that pool as leaked.
  ~Library() = default;
  Library(const Library&) = delete;
  Library& operator=(const Library&) = delete;
  template <class F>
  F fn(const char* name) {
    void* p = dlsym(h_, name);
    INFO(name);
    REQUIRE(p);
    return reinterpret_cast<F>(p);
  }
  bool has(const char* name) const { return dlsym(h_, name) != nullptr; }

 private:
  static std::string dlerror_text() {
    const char* e = dlerror();
    return e ? e : "";
  }
  void* h_;
};

/// What a run of the importer sets and reads.
struct Scenario {
  std::map<std::string, double> params, inputs;
  double t_end = 2.0, dt_out = 0.1;
  double me_step = 1e-3;     // the importer's RK4 step
  double cs_step = 0.05;     // the communication step
  double tolerance = 1e-10;  // passed to setup
};

using Sample = std::map<std::string, double>;  // one row: name -> value (states and outputs)

unsigned vr_of(const Description& d, const std::string& name) {
  for (const auto& v : d.vars)
    if (v.name == name) return v.vr;
  FAIL("no variable " << name);
  return 0;
}

/// The names sampled: the states and outputs.
std::vector<const Variable*> sampled(const Description& d) {
  std::vector<const Variable*> out;
  for (const auto& v : d.vars)
    if ((v.causality == "local" && v.derivative < 0 && v.name.rfind("der(", 0) != 0) || v.causality == "output")
      out.push_back(&v);
  return out;
}

/// The continuous states in the order of the derivatives (FMI's state vector order).
std::size_t state_count(const Description& d) { return d.derivatives.size(); }

struct Fmi2 {
  explicit Fmi2(Library& l)
      : instantiate(l.fn<decltype(&fmi2Instantiate)>("fmi2Instantiate")),
        free_instance(l.fn<decltype(&fmi2FreeInstance)>("fmi2FreeInstance")),
        setup(l.fn<decltype(&fmi2SetupExperiment)>("fmi2SetupExperiment")),
        enter_init(l.fn<decltype(&fmi2EnterInitializationMode)>("fmi2EnterInitializationMode")),
        exit_init(l.fn<decltype(&fmi2ExitInitializationMode)>("fmi2ExitInitializationMode")),
        get_real(l.fn<decltype(&fmi2GetReal)>("fmi2GetReal")),
        set_real(l.fn<decltype(&fmi2SetReal)>("fmi2SetReal")),
        new_discrete(l.fn<decltype(&fmi2NewDiscreteStates)>("fmi2NewDiscreteStates")),
        enter_event(l.fn<decltype(&fmi2EnterEventMode)>("fmi2EnterEventMode")),
        enter_ct(l.fn<decltype(&fmi2EnterContinuousTimeMode)>("fmi2EnterContinuousTimeMode")),
        completed(l.fn<decltype(&fmi2CompletedIntegratorStep)>("fmi2CompletedIntegratorStep")),
        set_time(l.fn<decltype(&fmi2SetTime)>("fmi2SetTime")),
        set_states(l.fn<decltype(&fmi2SetContinuousStates)>("fmi2SetContinuousStates")),
        get_states(l.fn<decltype(&fmi2GetContinuousStates)>("fmi2GetContinuousStates")),
        get_derivatives(l.fn<decltype(&fmi2GetDerivatives)>("fmi2GetDerivatives")),
        do_step(l.fn<decltype(&fmi2DoStep)>("fmi2DoStep")),
        terminate(l.fn<decltype(&fmi2Terminate)>("fmi2Terminate")),
        get_state(l.fn<decltype(&fmi2GetFMUstate)>("fmi2GetFMUstate")),
        set_state(l.fn<decltype(&fmi2SetFMUstate)>("fmi2SetFMUstate")),
        free_state(l.fn<decltype(&fmi2FreeFMUstate)>("fmi2FreeFMUstate")),
        serialized_size(l.fn<decltype(&fmi2SerializedFMUstateSize)>("fmi2SerializedFMUstateSize")),
        serialize(l.fn<decltype(&fmi2SerializeFMUstate)>("fmi2SerializeFMUstate")),
        deserialize(l.fn<decltype(&fmi2DeSerializeFMUstate)>("fmi2DeSerializeFMUstate")) {}
  decltype(&fmi2Instantiate) instantiate;
  decltype(&fmi2FreeInstance) free_instance;
  decltype(&fmi2SetupExperiment) setup;
  decltype(&fmi2EnterInitializationMode) enter_init;
  decltype(&fmi2ExitInitializationMode) exit_init;
  decltype(&fmi2GetReal) get_real;
  decltype(&fmi2SetReal) set_real;
  decltype(&fmi2NewDiscreteStates) new_discrete;
  decltype(&fmi2EnterEventMode) enter_event;
  decltype(&fmi2EnterContinuousTimeMode) enter_ct;
  decltype(&fmi2CompletedIntegratorStep) completed;
  decltype(&fmi2SetTime) set_time;
  decltype(&fmi2SetContinuousStates) set_states;
  decltype(&fmi2GetContinuousStates) get_states;
  decltype(&fmi2GetDerivatives) get_derivatives;
  decltype(&fmi2DoStep) do_step;
  decltype(&fmi2Terminate) terminate;
  decltype(&fmi2GetFMUstate) get_state;
  decltype(&fmi2SetFMUstate) set_state;
  decltype(&fmi2FreeFMUstate) free_state;
  decltype(&fmi2SerializedFMUstateSize) serialized_size;
  decltype(&fmi2SerializeFMUstate) serialize;
  decltype(&fmi2DeSerializeFMUstate) deserialize;
};

struct Fmi3 {
  explicit Fmi3(Library& l)
      : instantiate_me(l.fn<decltype(&fmi3InstantiateModelExchange)>("fmi3InstantiateModelExchange")),
        instantiate_cs(l.fn<decltype(&fmi3InstantiateCoSimulation)>("fmi3InstantiateCoSimulation")),
        free_instance(l.fn<decltype(&fmi3FreeInstance)>("fmi3FreeInstance")),
        enter_init(l.fn<decltype(&fmi3EnterInitializationMode)>("fmi3EnterInitializationMode")),
        exit_init(l.fn<decltype(&fmi3ExitInitializationMode)>("fmi3ExitInitializationMode")),
        get_float64(l.fn<decltype(&fmi3GetFloat64)>("fmi3GetFloat64")),
        set_float64(l.fn<decltype(&fmi3SetFloat64)>("fmi3SetFloat64")),
        update_discrete(l.fn<decltype(&fmi3UpdateDiscreteStates)>("fmi3UpdateDiscreteStates")),
        enter_event(l.fn<decltype(&fmi3EnterEventMode)>("fmi3EnterEventMode")),
        enter_ct(l.fn<decltype(&fmi3EnterContinuousTimeMode)>("fmi3EnterContinuousTimeMode")),
        completed(l.fn<decltype(&fmi3CompletedIntegratorStep)>("fmi3CompletedIntegratorStep")),
        set_time(l.fn<decltype(&fmi3SetTime)>("fmi3SetTime")),
        set_states(l.fn<decltype(&fmi3SetContinuousStates)>("fmi3SetContinuousStates")),
        get_states(l.fn<decltype(&fmi3GetContinuousStates)>("fmi3GetContinuousStates")),
        get_derivatives(l.fn<decltype(&fmi3GetContinuousStateDerivatives)>("fmi3GetContinuousStateDerivatives")),
        number_of_states(l.fn<decltype(&fmi3GetNumberOfContinuousStates)>("fmi3GetNumberOfContinuousStates")),
        enter_step(l.fn<decltype(&fmi3EnterStepMode)>("fmi3EnterStepMode")),
        do_step(l.fn<decltype(&fmi3DoStep)>("fmi3DoStep")),
        terminate(l.fn<decltype(&fmi3Terminate)>("fmi3Terminate")) {}
  decltype(&fmi3InstantiateModelExchange) instantiate_me;
  decltype(&fmi3InstantiateCoSimulation) instantiate_cs;
  decltype(&fmi3FreeInstance) free_instance;
  decltype(&fmi3EnterInitializationMode) enter_init;
  decltype(&fmi3ExitInitializationMode) exit_init;
  decltype(&fmi3GetFloat64) get_float64;
  decltype(&fmi3SetFloat64) set_float64;
  decltype(&fmi3UpdateDiscreteStates) update_discrete;
  decltype(&fmi3EnterEventMode) enter_event;
  decltype(&fmi3EnterContinuousTimeMode) enter_ct;
  decltype(&fmi3CompletedIntegratorStep) completed;
  decltype(&fmi3SetTime) set_time;
  decltype(&fmi3SetContinuousStates) set_states;
  decltype(&fmi3GetContinuousStates) get_states;
  decltype(&fmi3GetContinuousStateDerivatives) get_derivatives;
  decltype(&fmi3GetNumberOfContinuousStates) number_of_states;
  decltype(&fmi3EnterStepMode) enter_step;
  decltype(&fmi3DoStep) do_step;
  decltype(&fmi3Terminate) terminate;
};

/// One classical Runge-Kutta step of x' = f(t, x) through set_time/set_states/get_derivatives.
void rk4_step(double t, double h, std::vector<double>& x, const std::function<void(double, const std::vector<double>&,
                                                                                     std::vector<double>&)>& f) {
  const std::size_t n = x.size();
  std::vector<double> k1(n), k2(n), k3(n), k4(n), y(n);
  f(t, x, k1);
  for (std::size_t i = 0; i < n; ++i) y[i] = x[i] + 0.5 * h * k1[i];
  f(t + 0.5 * h, y, k2);
  for (std::size_t i = 0; i < n; ++i) y[i] = x[i] + 0.5 * h * k2[i];
  f(t + 0.5 * h, y, k3);
  for (std::size_t i = 0; i < n; ++i) y[i] = x[i] + h * k3[i];
  f(t + h, y, k4);
  for (std::size_t i = 0; i < n; ++i) x[i] += h / 6.0 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
}

struct Trajectory {
  std::vector<Sample> samples;  // at 0, dt_out, 2 dt_out, ...
  long events = 0;              // step events (projections) of model exchange
};

/// The output grid's number of intervals.
int grid(const Scenario& s) { return static_cast<int>(std::lround(s.t_end / s.dt_out)); }

Trajectory run_fmi2(const fs::path& so, const Description& d, bool model_exchange, const Scenario& s) {
  Library lib(so);
  Fmi2 f(lib);
  const fmi2CallbackFunctions callbacks = {log2, nullptr, nullptr, nullptr, nullptr};
  fmi2Component c = f.instantiate("test", model_exchange ? fmi2ModelExchange : fmi2CoSimulation, d.token.c_str(), "",
                                  &callbacks, fmi2False, fmi2False);
  REQUIRE(c);
  REQUIRE(f.setup(c, fmi2True, s.tolerance, 0.0, fmi2False, 0.0) == fmi2OK);
  REQUIRE(f.enter_init(c) == fmi2OK);
  for (const auto& [name, v] : s.params) {
    const unsigned vr = vr_of(d, name);
    REQUIRE(f.set_real(c, &vr, 1, &v) == fmi2OK);
  }
  for (const auto& [name, v] : s.inputs) {
    const unsigned vr = vr_of(d, name);
    REQUIRE(f.set_real(c, &vr, 1, &v) == fmi2OK);
  }
  INFO((g_log.empty() ? "" : g_log.back()));
  REQUIRE(f.exit_init(c) == fmi2OK);
  Trajectory out;
  auto sample = [&] {
    Sample row;
    for (const Variable* v : sampled(d)) {
      double value = 0;
      REQUIRE(f.get_real(c, &v->vr, 1, &value) == fmi2OK);
      row[v->name] = value;
    }
    out.samples.push_back(row);
  };
  const std::size_t n = state_count(d);
  if (model_exchange) {
    fmi2EventInfo info{};
    do REQUIRE(f.new_discrete(c, &info) == fmi2OK);
    while (info.newDiscreteStatesNeeded);
    REQUIRE(f.enter_ct(c) == fmi2OK);
    std::vector<double> x(n);
    REQUIRE(f.get_states(c, x.data(), n) == fmi2OK);
    auto rhs = [&](double t, const std::vector<double>& y, std::vector<double>& dy) {
      REQUIRE(f.set_time(c, t) == fmi2OK);
      REQUIRE(f.set_states(c, y.data(), n) == fmi2OK);
      REQUIRE(f.get_derivatives(c, dy.data(), n) == fmi2OK);
    };
    const int steps_per_sample = static_cast<int>(std::lround(s.dt_out / s.me_step));
    sample();
    for (int k = 1; k <= grid(s); ++k) {
      for (int j = 0; j < steps_per_sample; ++j) {
        const double t = ((k - 1) * steps_per_sample + j) * s.me_step;
        rk4_step(t, s.me_step, x, rhs);
        REQUIRE(f.set_time(c, t + s.me_step) == fmi2OK);
        REQUIRE(f.set_states(c, x.data(), n) == fmi2OK);
        fmi2Boolean enter = fmi2False, terminate = fmi2False;
        REQUIRE(f.completed(c, fmi2True, &enter, &terminate) == fmi2OK);
        if (enter) {
          ++out.events;
          REQUIRE(f.enter_event(c) == fmi2OK);
          do REQUIRE(f.new_discrete(c, &info) == fmi2OK);
          while (info.newDiscreteStatesNeeded);
          REQUIRE(f.enter_ct(c) == fmi2OK);
          if (info.valuesOfContinuousStatesChanged) REQUIRE(f.get_states(c, x.data(), n) == fmi2OK);
        }
      }
      sample();
    }
  } else {
    sample();
    const int steps_per_sample = static_cast<int>(std::lround(s.dt_out / s.cs_step));
    for (int k = 1; k <= grid(s); ++k) {
      for (int j = 0; j < steps_per_sample; ++j) {
        const double t = ((k - 1) * steps_per_sample + j) * s.cs_step;
        INFO((g_log.empty() ? "" : g_log.back()));
        REQUIRE(f.do_step(c, t, s.cs_step, fmi2True) == fmi2OK);
      }
      sample();
    }
  }
  REQUIRE(f.terminate(c) == fmi2OK);
  f.free_instance(c);
  return out;
}

Trajectory run_fmi3(const fs::path& so, const Description& d, bool model_exchange, const Scenario& s) {
  Library lib(so);
  Fmi3 f(lib);
  fmi3Instance c = model_exchange
                       ? f.instantiate_me("test", d.token.c_str(), "", false, false, nullptr, log3)
                       : f.instantiate_cs("test", d.token.c_str(), "", false, false, false, false, nullptr, 0, nullptr,
                                          log3, nullptr);
  REQUIRE(c);
  REQUIRE(f.enter_init(c, true, s.tolerance, 0.0, false, 0.0) == fmi3OK);
  for (const auto* list : {&s.params, &s.inputs})
    for (const auto& [name, v] : *list) {
      const fmi3ValueReference vr = vr_of(d, name);
      REQUIRE(f.set_float64(c, &vr, 1, &v, 1) == fmi3OK);
    }
  INFO((g_log.empty() ? "" : g_log.back()));
  REQUIRE(f.exit_init(c) == fmi3OK);
  Trajectory out;
  auto sample = [&] {
    Sample row;
    for (const Variable* v : sampled(d)) {
      double value = 0;
      REQUIRE(f.get_float64(c, &v->vr, 1, &value, 1) == fmi3OK);
      row[v->name] = value;
    }
    out.samples.push_back(row);
  };
  const std::size_t n = state_count(d);
  bool need = false, terminate = false, nominals = false, changed = false, next_defined = false;
  double next = 0;
  if (model_exchange) {
    size_t count = 0;
    REQUIRE(f.number_of_states(c, &count) == fmi3OK);
    REQUIRE(count == n);
    do REQUIRE(f.update_discrete(c, &need, &terminate, &nominals, &changed, &next_defined, &next) == fmi3OK);
    while (need);
    REQUIRE(f.enter_ct(c) == fmi3OK);
    std::vector<double> x(n);
    REQUIRE(f.get_states(c, x.data(), n) == fmi3OK);
    auto rhs = [&](double t, const std::vector<double>& y, std::vector<double>& dy) {
      REQUIRE(f.set_time(c, t) == fmi3OK);
      REQUIRE(f.set_states(c, y.data(), n) == fmi3OK);
      REQUIRE(f.get_derivatives(c, dy.data(), n) == fmi3OK);
    };
    const int steps_per_sample = static_cast<int>(std::lround(s.dt_out / s.me_step));
    sample();
    for (int k = 1; k <= grid(s); ++k) {
      for (int j = 0; j < steps_per_sample; ++j) {
        const double t = ((k - 1) * steps_per_sample + j) * s.me_step;
        rk4_step(t, s.me_step, x, rhs);
        REQUIRE(f.set_time(c, t + s.me_step) == fmi3OK);
        REQUIRE(f.set_states(c, x.data(), n) == fmi3OK);
        bool enter = false;
        REQUIRE(f.completed(c, true, &enter, &terminate) == fmi3OK);
        if (enter) {
          ++out.events;
          REQUIRE(f.enter_event(c) == fmi3OK);
          do REQUIRE(f.update_discrete(c, &need, &terminate, &nominals, &changed, &next_defined, &next) == fmi3OK);
          while (need);
          REQUIRE(f.enter_ct(c) == fmi3OK);
          if (changed) REQUIRE(f.get_states(c, x.data(), n) == fmi3OK);
        }
      }
      sample();
    }
  } else {
    sample();
    const int steps_per_sample = static_cast<int>(std::lround(s.dt_out / s.cs_step));
    for (int k = 1; k <= grid(s); ++k) {
      for (int j = 0; j < steps_per_sample; ++j) {
        const double t = ((k - 1) * steps_per_sample + j) * s.cs_step;
        bool event = false, early = false;
        double last = 0;
        INFO((g_log.empty() ? "" : g_log.back()));
        REQUIRE(f.do_step(c, t, s.cs_step, true, &event, &terminate, &early, &last) == fmi3OK);
        CHECK(last == Approx(t + s.cs_step));
      }
      sample();
    }
  }
  REQUIRE(f.terminate(c) == fmi3OK);
  f.free_instance(c);
  return out;
}

/// The FMU's samples against `mbsc run`'s rows at the same times: the largest difference.
double worst_difference(const Trajectory& fmu, const Table& reference) {
  REQUIRE(fmu.samples.size() == reference.rows.size());
  double worst = 0;
  for (std::size_t r = 0; r < reference.rows.size(); ++r)
    for (const auto& [name, v] : fmu.samples[r]) {
      INFO(name << " at row " << r);
      REQUIRE(std::isfinite(v));
      worst = std::max(worst, std::fabs(v - reference.at(r, name)));
    }
  return worst;
}

struct Exported {
  fs::path folder;  // where the FMU was unpacked
  fs::path so;
  Description description;
  std::map<std::string, std::string> files;
  std::string bytes;
};

Exported export_fmu(const fs::path& dir, const std::string& model, int version, const std::string& extra = "") {
  const fs::path out = dir / ("out" + std::to_string(version));
  const auto r = run(kMbsc + " generate " + quote(kSource + "/" + model) + " --fmi " + std::to_string(version) + " -o " +
                     quote(out.string()) + " " + extra);
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const std::string name = fs::path(model).stem().string();
  Exported e;
  e.bytes = slurp(out / name / (name + ".fmu"));
  REQUIRE(!e.bytes.empty());
  e.files = unzip(e.bytes);
  e.folder = dir / ("unpacked" + std::to_string(version));
  for (const auto& [path, data] : e.files) mbsc_test::write(e.folder / path, data);
  const std::string platform = version == 3 ? "x86_64-linux" : "linux64";
  e.so = e.folder / "binaries" / platform / (name + ".so");
  REQUIRE(fs::exists(e.so));
  REQUIRE(e.files.count("modelDescription.xml"));
  e.description = read_description(e.files["modelDescription.xml"], version);
  CHECK(e.description.identifier == name);
  return e;
}

Table reference_run(const fs::path& dir, const std::string& model, const Scenario& s, const std::string& tag) {
  std::string cmd = kMbsc + " run " + quote(kSource + "/" + model) + " --t-end " + std::to_string(s.t_end) +
                    " --dt-out " + std::to_string(s.dt_out) + " --rtol 1e-11 --atol 1e-13 -o " +
                    quote((dir / (tag + ".csv")).string());
  for (const auto& [n, v] : s.params) cmd += " --set " + n + "=" + std::to_string(v);
  for (const auto& [n, v] : s.inputs) cmd += " --input " + n + "=" + std::to_string(v);
  const auto r = run(cmd);
  INFO(cmd << "\n" << r.output);
  REQUIRE(r.exit_code == 0);
  return read_csv(dir / (tag + ".csv"));
}

}  // namespace

TEST_CASE("generate --fmi 2: the crane's FMU runs as mbsc run does, model exchange and co-simulation", "[fmi]") {
  if (!fs::exists("/usr/bin/c++") && std::getenv("CXX") == nullptr) WARN("no C++ compiler named c++; the test may fail");
  const fs::path dir = mbsc_test::fresh_dir("fmi2");
  const Exported e = export_fmu(dir, "models/gantry_crane.mbs", 2);
  check_rules(e.description, 2);
  CHECK(e.description.me);
  CHECK(e.description.cs);
  // The sources build the same binary's functions elsewhere: every file SourceFiles names is there.
  CHECK(e.files.count("sources/gantry_crane.cpp"));
  CHECK(e.files.count("sources/gantry_crane_fmu.cpp"));
  CHECK(e.files.count("sources/mbsc/fmi/fmu_instance.hpp"));

  // A changed rope length (the start is assembled again) and a constant force.
  Scenario s;
  s.params = {{"l", 1.5}};
  s.inputs = {{"F", 2.0}};
  const Table reference = reference_run(dir, "models/gantry_crane.mbs", s, "crane");
  const Trajectory me = run_fmi2(e.so, e.description, true, s);
  const Trajectory cs = run_fmi2(e.so, e.description, false, s);
  const double me_error = worst_difference(me, reference), cs_error = worst_difference(cs, reference);
  INFO("model exchange " << me_error << ", co-simulation " << cs_error << ", step events " << me.events);
  CHECK(me_error < 1e-9);
  CHECK(cs_error < 1e-9);
  // The rope length reached the dynamics: the load hangs 1.5 below the cart at the start.
  CHECK(reference.at(0, "load.y") == Approx(-1.5 * std::cos(0.3)).margin(1e-9));
  CHECK(me.samples.front().at("load.y") == Approx(-1.5 * std::cos(0.3)).margin(1e-9));

  SECTION("the bytes are the same from run to run") {
    const fs::path again = mbsc_test::fresh_dir("fmi2_again");
    const auto r = run(kMbsc + " generate " + quote(kSource + "/models/gantry_crane.mbs") + " --fmi 2 -o " +
                       quote(again.string()));
    REQUIRE(r.exit_code == 0);
    CHECK(slurp(again / "gantry_crane" / "gantry_crane.fmu") == e.bytes);
    fs::remove_all(again);
  }
  SECTION("initialization: the initial unknowns are those of the assembled state; an approx start is a guess") {
    Library lib(e.so);
    Fmi2 f(lib);
    const fmi2CallbackFunctions callbacks = {log2, nullptr, nullptr, nullptr, nullptr};
    fmi2Component c = f.instantiate("x", fmi2ModelExchange, e.description.token.c_str(), "", &callbacks, fmi2False,
                                    fmi2False);
    REQUIRE(c);
    REQUIRE(f.setup(c, fmi2False, 0, 0, fmi2False, 0) == fmi2OK);
    REQUIRE(f.enter_init(c) == fmi2OK);
    const unsigned l = vr_of(e.description, "l"), load_y = vr_of(e.description, "load.y"),
                   theta = vr_of(e.description, "theta");
    const double length = 1.5, wrong = 7.0, angle = 0.5;
    REQUIRE(f.set_real(c, &l, 1, &length) == fmi2OK);
    REQUIRE(f.set_real(c, &load_y, 1, &wrong) == fmi2OK);  // approx: a first guess only
    REQUIRE(f.set_real(c, &theta, 1, &angle) == fmi2OK);   // exact: kept
    double y = 0;
    REQUIRE(f.get_real(c, &load_y, 1, &y) == fmi2OK);
    CHECK(y == Approx(-1.5 * std::cos(0.5)).margin(1e-10));
    REQUIRE(f.exit_init(c) == fmi2OK);
    REQUIRE(f.get_real(c, &load_y, 1, &y) == fmi2OK);
    CHECK(y == Approx(-1.5 * std::cos(0.5)).margin(1e-10));
    // Calls out of order are errors that leave the instance usable.
    double dx[16];
    CHECK(f.do_step(c, 0.0, 0.1, fmi2True) == fmi2Error);
    fmi2EventInfo info{};
    REQUIRE(f.new_discrete(c, &info) == fmi2OK);
    REQUIRE(f.enter_ct(c) == fmi2OK);
    REQUIRE(f.get_derivatives(c, dx, 16) == fmi2OK);
    CHECK(f.get_derivatives(c, dx, 3) == fmi2Error);
    REQUIRE(f.get_derivatives(c, dx, 16) == fmi2OK);
    f.free_instance(c);
  }
  SECTION("a wrong guid, a kind not exported, a parameter after initialization, saved states") {
    Library lib(e.so);
    Fmi2 f(lib);
    const fmi2CallbackFunctions callbacks = {log2, nullptr, nullptr, nullptr, nullptr};
    g_log.clear();
    CHECK(f.instantiate("x", fmi2CoSimulation, "{not-this-one}", "", &callbacks, fmi2False, fmi2False) == nullptr);
    REQUIRE(!g_log.empty());
    CHECK(g_log.back().find("guid") != std::string::npos);
    fmi2Component c = f.instantiate("x", fmi2CoSimulation, e.description.token.c_str(), "", &callbacks, fmi2False,
                                    fmi2False);
    REQUIRE(c);
    REQUIRE(f.setup(c, fmi2False, 0, 0, fmi2False, 0) == fmi2OK);
    REQUIRE(f.enter_init(c) == fmi2OK);
    REQUIRE(f.exit_init(c) == fmi2OK);
    const unsigned l = vr_of(e.description, "l");
    const double v = 2.0;
    CHECK(f.set_real(c, &l, 1, &v) == fmi2Error);
    CHECK(g_log.back().find("'l'") != std::string::npos);
    // Save, step, restore (also through bytes): the same step gives the same state.
    fmi2FMUstate saved = nullptr;
    REQUIRE(f.get_state(c, &saved) == fmi2OK);
    size_t size = 0;
    REQUIRE(f.serialized_size(c, saved, &size) == fmi2OK);
    std::vector<fmi2Byte> bytes(size);
    REQUIRE(f.serialize(c, saved, bytes.data(), size) == fmi2OK);
    const unsigned x = vr_of(e.description, "x");
    double x1 = 0, x2 = 0, x3 = 0;
    REQUIRE(f.do_step(c, 0.0, 0.5, fmi2False) == fmi2OK);
    REQUIRE(f.get_real(c, &x, 1, &x1) == fmi2OK);
    REQUIRE(f.set_state(c, saved) == fmi2OK);
    REQUIRE(f.do_step(c, 0.0, 0.5, fmi2False) == fmi2OK);
    REQUIRE(f.get_real(c, &x, 1, &x2) == fmi2OK);
    fmi2FMUstate restored = nullptr;
    REQUIRE(f.deserialize(c, bytes.data(), size, &restored) == fmi2OK);
    REQUIRE(f.set_state(c, restored) == fmi2OK);
    REQUIRE(f.do_step(c, 0.0, 0.5, fmi2False) == fmi2OK);
    REQUIRE(f.get_real(c, &x, 1, &x3) == fmi2OK);
    CHECK(x1 == x2);
    CHECK(x1 == x3);
    CHECK(x1 != 0.0);
    bytes[0] ^= 1;
    fmi2FMUstate bad = nullptr;
    CHECK(f.deserialize(c, bytes.data(), size, &bad) == fmi2Error);
    f.free_state(c, &saved);
    f.free_state(c, &restored);
    f.free_instance(c);
  }
  fs::remove_all(dir);
}

TEST_CASE("generate --fmi 3: the four-bar's FMU runs as mbsc run does and projects in step events", "[fmi]") {
  const fs::path dir = mbsc_test::fresh_dir("fmi3");
  const Exported e = export_fmu(dir, "models/four_bar.mbs", 3);
  check_rules(e.description, 3);
  CHECK(e.files.count("sources/buildDescription.xml"));
  Scenario s;
  s.params = {{"tau0", 0.5}};
  s.me_step = 1e-3;  // the constraints drift past the tolerance now and then and get projected
  s.tolerance = 1e-9;
  const Table reference = reference_run(dir, "models/four_bar.mbs", s, "four_bar");
  const Trajectory me = run_fmi3(e.so, e.description, true, s);
  s.tolerance = 1e-10;
  const Trajectory cs = run_fmi3(e.so, e.description, false, s);
  const double me_error = worst_difference(me, reference), cs_error = worst_difference(cs, reference);
  INFO("model exchange " << me_error << " (" << me.events << " step events), co-simulation " << cs_error);
  CHECK(me.events > 0);
  CHECK(me_error < 3e-6);
  CHECK(cs_error < 1e-7);
  fs::remove_all(dir);
}

TEST_CASE("generate --fmi: the kinds, the minimal state, and what is refused", "[fmi]") {
  const fs::path dir = mbsc_test::fresh_dir("fmi_kinds");
  SECTION("--fmi-kind cs exports co-simulation only, and the binary refuses model exchange") {
    const Exported e = export_fmu(dir, "models/slider_crank.mbs", 2, "--fmi-kind cs --state minimal");
    check_rules(e.description, 2);
    CHECK(!e.description.me);
    CHECK(e.description.cs);
    Library lib(e.so);
    Fmi2 f(lib);
    const fmi2CallbackFunctions callbacks = {log2, nullptr, nullptr, nullptr, nullptr};
    g_log.clear();
    CHECK(f.instantiate("x", fmi2ModelExchange, e.description.token.c_str(), "", &callbacks, fmi2False, fmi2False) ==
          nullptr);
    CHECK(g_log.back().find("co-simulation only") != std::string::npos);
    // The minimal state co-simulated against mbsc run --state minimal's full columns.
    Scenario s;
    s.inputs = {{"tau", 0.3}};
    s.t_end = 1.0;
    const Table reference = reference_run(dir, "models/slider_crank.mbs", s, "slider");
    const Trajectory cs = run_fmi2(e.so, e.description, false, s);
    const double error = worst_difference(cs, reference);
    INFO("co-simulation of the minimal state " << error);
    CHECK(error < 1e-7);
  }
  SECTION("model exchange keeps a free body's quaternion unit in step events") {
    const Exported e = export_fmu(dir, "models/free_body_quaternion.mbs", 2, "--fmi-kind me");
    check_rules(e.description, 2);
    Scenario s;
    s.t_end = 1.0;
    s.me_step = 1e-2;     // a coarse step: RK4's drift of |e| passes the tolerance, normalized in events
    s.tolerance = 1e-12;
    const Table reference = reference_run(dir, "models/free_body_quaternion.mbs", s, "free_body");
    const Trajectory me = run_fmi2(e.so, e.description, true, s);
    const double error = worst_difference(me, reference);
    INFO("model exchange " << error << ", " << me.events << " step events");
    CHECK(me.events > 0);
    CHECK(error < 1e-6);
    for (const Sample& row : me.samples) {
      double n2 = 0;
      for (const char* q : {"b.e0", "b.e1", "b.e2", "b.e3"}) n2 += row.at(q) * row.at(q);
      CHECK(std::sqrt(n2) == Approx(1.0).margin(1e-11));
    }
  }
  SECTION("model exchange switches the independent set where the first one is singular") {
    // Released with the rod horizontal: the set u is singular at the start and v near
    // the bottom; without re-selection the FMU fails at the start.
    const Exported e = export_fmu(dir, "tests/data/fmi/released_particle.mbs", 3, "--fmi-kind me");
    Scenario s;
    s.tolerance = 1e-9;
    const Table reference = reference_run(dir, "tests/data/fmi/released_particle.mbs", s, "released");
    const Trajectory me = run_fmi3(e.so, e.description, true, s);
    const double error = worst_difference(me, reference);
    INFO("model exchange " << error << ", " << me.events << " step events");
    CHECK(error < 1e-6);
  }
  SECTION("refused: --fmi 4, --fmi-kind alone, --fmi with --outputs") {
    for (const std::string args : {"--fmi 4", "--fmi-kind me", "--fmi 2 --outputs rhs"}) {
      const auto r = run(kMbsc + " generate " + quote(kSource + "/models/four_bar.mbs") + " -o " +
                         quote((dir / "refused").string()) + " " + args);
      INFO(args << "\n" << r.output);
      CHECK(r.exit_code != 0);
      CHECK(r.output.find("--fmi") != std::string::npos);
      CHECK(!fs::exists(dir / "refused"));
    }
  }
  fs::remove_all(dir);
}
