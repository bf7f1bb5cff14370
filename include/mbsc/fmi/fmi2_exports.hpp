// SPDX-License-Identifier: GPL-2.0-or-later WITH mbsc-runtime-exception
// (see LICENSE: this header may be included in applications under any terms)
#pragma once
/// The FMI 2.0 functions of an FMU exported by `mbsc generate --fmi 2`, each a thin
/// translation into FmuInstance (fmu_instance.hpp). Included by exactly one translation
/// unit, the generated NAME_fmu.cpp, after it defined
///   const mbsc::fmi::FmuModel& mbsc_fmu_model();
/// and MBSC_FMU_MODEL_EXCHANGE / MBSC_FMU_CO_SIMULATION (1 for the kinds it exports).
/// No exception leaves a function: each one's body is guarded and a throw is fmi2Fatal.
#include <cstring>
#include <new>
#include <string>

#include "mbsc/fmi/fmi2_functions.h"
#include "mbsc/fmi/fmu_instance.hpp"

namespace mbsc::fmi::fmi2 {

/// One fmi2Component: the instance and the importer's logger.
struct Component {
  Component(FmuInstance::Kind kind, const std::string& name, fmi2CallbackLogger logger, fmi2ComponentEnvironment env)
      : instance(mbsc_fmu_model(), kind,
                 [this](Status s, const char* category, const std::string& text) {
                   if (this->logger)
                     this->logger(this->environment, this->name.c_str(), static_cast<fmi2Status>(s), category, "%s",
                                  text.c_str());
                 }),
        name(name), logger(logger), environment(env) {}
  FmuInstance instance;
  std::string name;
  fmi2CallbackLogger logger;
  fmi2ComponentEnvironment environment;
};

inline Component* component(fmi2Component c) { return static_cast<Component*>(c); }

/// Runs `body` on the component, turning a null component and any exception into errors.
template <class Body>
fmi2Status guarded(fmi2Component c, Body body) {
  if (!c) return fmi2Error;
  try {
    return static_cast<fmi2Status>(body(component(c)->instance));
  } catch (const std::exception& e) {
    try {
      component(c)->instance.log(kFatal, "logError", std::string("internal error: ") + e.what());
    } catch (...) {
    }
    return fmi2Fatal;
  } catch (...) {
    return fmi2Fatal;
  }
}

inline fmi2Status unsupported(fmi2Component c, const char* what) {
  return guarded(c, [what](FmuInstance& i) {
    i.log(kError, "logError", std::string(what) + " is not supported by this FMU");
    return kError;
  });
}

}  // namespace mbsc::fmi::fmi2

extern "C" {

using mbsc::fmi::FmuInstance;
using mbsc::fmi::fmi2::guarded;
using mbsc::fmi::fmi2::unsupported;

const char* fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }
const char* fmi2GetVersion(void) { return fmi2Version; }

fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean loggingOn, size_t, const fmi2String[]) {
  return guarded(c, [&](FmuInstance& i) {
    i.set_logging(loggingOn != fmi2False);
    return mbsc::fmi::kOK;
  });
}

fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID, fmi2String,
                              const fmi2CallbackFunctions* functions, fmi2Boolean, fmi2Boolean loggingOn) {
  const fmi2CallbackLogger logger = functions ? functions->logger : nullptr;
  const fmi2ComponentEnvironment env = functions ? functions->componentEnvironment : nullptr;
  const char* name = instanceName ? instanceName : "";
  auto refuse = [&](const char* why) -> fmi2Component {
    if (logger) logger(env, name, fmi2Error, "logError", "%s", why);
    return nullptr;
  };
  if (!fmuGUID || std::strcmp(fmuGUID, mbsc_fmu_model().token) != 0)
    return refuse("the guid given is not this FMU's (modelDescription.xml and the binary are from different exports)");
  if ((fmuType == fmi2ModelExchange && !MBSC_FMU_MODEL_EXCHANGE) || (fmuType == fmi2CoSimulation && !MBSC_FMU_CO_SIMULATION))
    return refuse(fmuType == fmi2ModelExchange ? "this FMU was exported for co-simulation only (--fmi-kind cs)"
                                               : "this FMU was exported for model exchange only (--fmi-kind me)");
  if (fmuType != fmi2ModelExchange && fmuType != fmi2CoSimulation) return refuse("unknown fmuType");
  try {
    auto* c = new mbsc::fmi::fmi2::Component(
        fmuType == fmi2ModelExchange ? FmuInstance::Kind::ModelExchange : FmuInstance::Kind::CoSimulation, name, logger,
        env);
    c->instance.set_logging(loggingOn != fmi2False);
    return c;
  } catch (...) {
    return refuse("out of memory");
  }
}

void fmi2FreeInstance(fmi2Component c) { delete mbsc::fmi::fmi2::component(c); }

fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean toleranceDefined, fmi2Real tolerance, fmi2Real startTime,
                               fmi2Boolean, fmi2Real) {
  return guarded(c, [&](FmuInstance& i) { return i.setup(toleranceDefined != fmi2False, tolerance, startTime); });
}
fmi2Status fmi2EnterInitializationMode(fmi2Component c) {
  return guarded(c, [](FmuInstance& i) { return i.enter_initialization(); });
}
fmi2Status fmi2ExitInitializationMode(fmi2Component c) {
  return guarded(c, [](FmuInstance& i) { return i.exit_initialization(); });
}
fmi2Status fmi2Terminate(fmi2Component c) {
  return guarded(c, [](FmuInstance& i) { return i.terminate(); });
}
fmi2Status fmi2Reset(fmi2Component c) {
  return guarded(c, [](FmuInstance& i) {
    i.reset();
    return mbsc::fmi::kOK;
  });
}

fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Real value[]) {
  return guarded(c, [&](FmuInstance& i) { return i.get_real(vr, nvr, value); });
}
fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Real value[]) {
  return guarded(c, [&](FmuInstance& i) { return i.set_real(vr, nvr, value); });
}
// Every variable is a Real: asking for other types is an error unless nothing is asked.
fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference[], size_t nvr, fmi2Integer[]) {
  return nvr == 0 ? fmi2OK : unsupported(c, "an Integer variable");
}
fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference[], size_t nvr, fmi2Boolean[]) {
  return nvr == 0 ? fmi2OK : unsupported(c, "a Boolean variable");
}
fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference[], size_t nvr, fmi2String[]) {
  return nvr == 0 ? fmi2OK : unsupported(c, "a String variable");
}
fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference[], size_t nvr, const fmi2Integer[]) {
  return nvr == 0 ? fmi2OK : unsupported(c, "an Integer variable");
}
fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference[], size_t nvr, const fmi2Boolean[]) {
  return nvr == 0 ? fmi2OK : unsupported(c, "a Boolean variable");
}
fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference[], size_t nvr, const fmi2String[]) {
  return nvr == 0 ? fmi2OK : unsupported(c, "a String variable");
}

fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate* state) {
  return guarded(c, [&](FmuInstance& i) { return i.get_fmu_state(state); });
}
fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate state) {
  return guarded(c, [&](FmuInstance& i) { return i.set_fmu_state(state); });
}
fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate* state) {
  return guarded(c, [&](FmuInstance&) { return FmuInstance::free_fmu_state(state); });
}
fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate state, size_t* size) {
  return guarded(c, [&](FmuInstance& i) { return i.serialized_size(state, size); });
}
fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate state, fmi2Byte bytes[], size_t size) {
  return guarded(c, [&](FmuInstance& i) { return i.serialize_into(state, reinterpret_cast<unsigned char*>(bytes), size); });
}
fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte bytes[], size_t size, fmi2FMUstate* state) {
  return guarded(c, [&](FmuInstance& i) {
    return i.deserialize_into(reinterpret_cast<const unsigned char*>(bytes), size, state);
  });
}
fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference[], size_t, const fmi2ValueReference[],
                                        size_t, const fmi2Real[], fmi2Real[]) {
  return unsupported(c, "fmi2GetDirectionalDerivative");
}

// ---- model exchange ----
fmi2Status fmi2EnterEventMode(fmi2Component c) {
  return guarded(c, [](FmuInstance& i) { return i.enter_event_mode(); });
}
fmi2Status fmi2NewDiscreteStates(fmi2Component c, fmi2EventInfo* info) {
  return guarded(c, [&](FmuInstance& i) {
    bool changed = false;
    const auto s = i.update_discrete_states(changed);
    if (info) {
      info->newDiscreteStatesNeeded = fmi2False;
      info->terminateSimulation = fmi2False;
      info->nominalsOfContinuousStatesChanged = fmi2False;
      info->valuesOfContinuousStatesChanged = changed ? fmi2True : fmi2False;
      info->nextEventTimeDefined = fmi2False;
      info->nextEventTime = 0.0;
    }
    return s;
  });
}
fmi2Status fmi2EnterContinuousTimeMode(fmi2Component c) {
  return guarded(c, [](FmuInstance& i) { return i.enter_continuous_time_mode(); });
}
fmi2Status fmi2CompletedIntegratorStep(fmi2Component c, fmi2Boolean, fmi2Boolean* enterEventMode,
                                       fmi2Boolean* terminateSimulation) {
  return guarded(c, [&](FmuInstance& i) {
    bool event = false;
    const auto s = i.completed_integrator_step(event);
    if (enterEventMode) *enterEventMode = event ? fmi2True : fmi2False;
    if (terminateSimulation) *terminateSimulation = fmi2False;
    return s;
  });
}
fmi2Status fmi2SetTime(fmi2Component c, fmi2Real time) {
  return guarded(c, [&](FmuInstance& i) { return i.set_time(time); });
}
fmi2Status fmi2SetContinuousStates(fmi2Component c, const fmi2Real x[], size_t nx) {
  return guarded(c, [&](FmuInstance& i) { return i.set_states(x, nx); });
}
fmi2Status fmi2GetDerivatives(fmi2Component c, fmi2Real derivatives[], size_t nx) {
  return guarded(c, [&](FmuInstance& i) { return i.get_derivatives(derivatives, nx); });
}
fmi2Status fmi2GetEventIndicators(fmi2Component c, fmi2Real[], size_t ni) {
  return ni == 0 ? fmi2OK : unsupported(c, "an event indicator");
}
fmi2Status fmi2GetContinuousStates(fmi2Component c, fmi2Real x[], size_t nx) {
  return guarded(c, [&](FmuInstance& i) { return i.get_states(x, nx); });
}
fmi2Status fmi2GetNominalsOfContinuousStates(fmi2Component c, fmi2Real x_nominal[], size_t nx) {
  return guarded(c, [&](FmuInstance& i) { return i.get_nominals(x_nominal, nx); });
}

// ---- co-simulation ----
fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference[], size_t nvr, const fmi2Integer[],
                                       const fmi2Real[]) {
  return nvr == 0 ? fmi2OK : unsupported(c, "fmi2SetRealInputDerivatives (inputs are held constant over a step)");
}
fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference[], size_t nvr, const fmi2Integer[],
                                        fmi2Real[]) {
  return nvr == 0 ? fmi2OK : unsupported(c, "fmi2GetRealOutputDerivatives");
}
fmi2Status fmi2DoStep(fmi2Component c, fmi2Real currentCommunicationPoint, fmi2Real communicationStepSize, fmi2Boolean) {
  return guarded(c, [&](FmuInstance& i) { return i.do_step(currentCommunicationPoint, communicationStepSize); });
}
fmi2Status fmi2CancelStep(fmi2Component c) { return unsupported(c, "fmi2CancelStep (doStep never returns pending)"); }
fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind, fmi2Status*) {
  return unsupported(c, "fmi2GetStatus (doStep never returns pending)");
}
fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind s, fmi2Real* value) {
  if (s != fmi2LastSuccessfulTime || !value) return unsupported(c, "this fmi2GetRealStatus query");
  return guarded(c, [&](FmuInstance& i) {
    *value = i.time();
    return mbsc::fmi::kOK;
  });
}
fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind, fmi2Integer*) {
  return unsupported(c, "fmi2GetIntegerStatus");
}
fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind s, fmi2Boolean* value) {
  if (s != fmi2Terminated || !value) return unsupported(c, "this fmi2GetBooleanStatus query");
  *value = fmi2False;
  return fmi2OK;
}
fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind, fmi2String*) {
  return unsupported(c, "fmi2GetStringStatus");
}

}  // extern "C"
