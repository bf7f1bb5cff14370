// SPDX-License-Identifier: GPL-2.0-or-later WITH mbsc-runtime-exception
// (see LICENSE: this header may be included in applications under any terms)
#pragma once
/// The FMI 3.0 functions of an FMU exported by `mbsc generate --fmi 3`, each a thin
/// translation into FmuInstance (fmu_instance.hpp). Included by exactly one translation
/// unit, the generated NAME_fmu.cpp, after it defined
///   const mbsc::fmi::FmuModel& mbsc_fmu_model();
/// and MBSC_FMU_MODEL_EXCHANGE / MBSC_FMU_CO_SIMULATION (1 for the kinds it exports).
/// Every variable is a Float64; scheduled execution, clocks and the typed accessors of
/// other types answer with an error. No exception leaves a function.
#include <cstring>
#include <new>
#include <string>

#include "mbsc/fmi/fmi3_functions.h"
#include "mbsc/fmi/fmu_instance.hpp"

namespace mbsc::fmi::fmi3 {

struct Component {
  Component(FmuInstance::Kind kind, fmi3LogMessageCallback logger, fmi3InstanceEnvironment env)
      : instance(mbsc_fmu_model(), kind,
                 [this](Status s, const char* category, const std::string& text) {
                   if (this->logger)
                     this->logger(this->environment, static_cast<fmi3Status>(s), category, text.c_str());
                 }),
        logger(logger), environment(env) {}
  FmuInstance instance;
  fmi3LogMessageCallback logger;
  fmi3InstanceEnvironment environment;
};

inline Component* component(fmi3Instance c) { return static_cast<Component*>(c); }

template <class Body>
fmi3Status guarded(fmi3Instance c, Body body) {
  if (!c) return fmi3Error;
  try {
    return static_cast<fmi3Status>(body(component(c)->instance));
  } catch (const std::exception& e) {
    try {
      component(c)->instance.log(kFatal, "logError", std::string("internal error: ") + e.what());
    } catch (...) {
    }
    return fmi3Fatal;
  } catch (...) {
    return fmi3Fatal;
  }
}

inline fmi3Status unsupported(fmi3Instance c, const char* what) {
  return guarded(c, [what](FmuInstance& i) {
    i.log(kError, "logError", std::string(what) + " is not supported by this FMU");
    return kError;
  });
}

inline fmi3Instance instantiate(FmuInstance::Kind kind, fmi3String token, fmi3Boolean loggingOn,
                                fmi3InstanceEnvironment env, fmi3LogMessageCallback logger) {
  auto refuse = [&](const char* why) -> fmi3Instance {
    if (logger) logger(env, fmi3Error, "logError", why);
    return nullptr;
  };
  if (!token || std::strcmp(token, mbsc_fmu_model().token) != 0)
    return refuse("the instantiation token is not this FMU's (modelDescription.xml and the binary are from different "
                  "exports)");
  if (kind == FmuInstance::Kind::ModelExchange && !MBSC_FMU_MODEL_EXCHANGE)
    return refuse("this FMU was exported for co-simulation only (--fmi-kind cs)");
  if (kind == FmuInstance::Kind::CoSimulation && !MBSC_FMU_CO_SIMULATION)
    return refuse("this FMU was exported for model exchange only (--fmi-kind me)");
  try {
    auto* c = new Component(kind, logger, env);
    c->instance.set_logging(loggingOn);
    return c;
  } catch (...) {
    return refuse("out of memory");
  }
}

}  // namespace mbsc::fmi::fmi3

extern "C" {

using mbsc::fmi::FmuInstance;
using mbsc::fmi::fmi3::guarded;
using mbsc::fmi::fmi3::unsupported;

const char* fmi3GetVersion(void) { return fmi3Version; }

fmi3Status fmi3SetDebugLogging(fmi3Instance c, fmi3Boolean loggingOn, size_t, const fmi3String[]) {
  return guarded(c, [&](FmuInstance& i) {
    i.set_logging(loggingOn);
    return mbsc::fmi::kOK;
  });
}

fmi3Instance fmi3InstantiateModelExchange(fmi3String, fmi3String instantiationToken, fmi3String, fmi3Boolean,
                                          fmi3Boolean loggingOn, fmi3InstanceEnvironment env,
                                          fmi3LogMessageCallback logMessage) {
  return mbsc::fmi::fmi3::instantiate(FmuInstance::Kind::ModelExchange, instantiationToken, loggingOn, env, logMessage);
}
fmi3Instance fmi3InstantiateCoSimulation(fmi3String, fmi3String instantiationToken, fmi3String, fmi3Boolean,
                                         fmi3Boolean loggingOn, fmi3Boolean eventModeUsed, fmi3Boolean,
                                         const fmi3ValueReference[], size_t, fmi3InstanceEnvironment env,
                                         fmi3LogMessageCallback logMessage, fmi3IntermediateUpdateCallback) {
  if (eventModeUsed) {
    if (logMessage) logMessage(env, fmi3Error, "logError", "this FMU has no event mode in co-simulation (hasEventMode is false)");
    return nullptr;
  }
  return mbsc::fmi::fmi3::instantiate(FmuInstance::Kind::CoSimulation, instantiationToken, loggingOn, env, logMessage);
}
fmi3Instance fmi3InstantiateScheduledExecution(fmi3String, fmi3String, fmi3String, fmi3Boolean, fmi3Boolean,
                                               fmi3InstanceEnvironment env, fmi3LogMessageCallback logMessage,
                                               fmi3ClockUpdateCallback, fmi3LockPreemptionCallback,
                                               fmi3UnlockPreemptionCallback) {
  if (logMessage) logMessage(env, fmi3Error, "logError", "this FMU offers no scheduled execution");
  return nullptr;
}
void fmi3FreeInstance(fmi3Instance c) { delete mbsc::fmi::fmi3::component(c); }

fmi3Status fmi3EnterInitializationMode(fmi3Instance c, fmi3Boolean toleranceDefined, fmi3Float64 tolerance,
                                       fmi3Float64 startTime, fmi3Boolean, fmi3Float64) {
  return guarded(c, [&](FmuInstance& i) {
    if (const auto s = i.setup(toleranceDefined, tolerance, startTime); s != mbsc::fmi::kOK) return s;
    return i.enter_initialization();
  });
}
fmi3Status fmi3ExitInitializationMode(fmi3Instance c) {
  return guarded(c, [](FmuInstance& i) { return i.exit_initialization(); });
}
fmi3Status fmi3EnterEventMode(fmi3Instance c) {
  return guarded(c, [](FmuInstance& i) { return i.enter_event_mode(); });
}
fmi3Status fmi3Terminate(fmi3Instance c) {
  return guarded(c, [](FmuInstance& i) { return i.terminate(); });
}
fmi3Status fmi3Reset(fmi3Instance c) {
  return guarded(c, [](FmuInstance& i) {
    i.reset();
    return mbsc::fmi::kOK;
  });
}

fmi3Status fmi3GetFloat64(fmi3Instance c, const fmi3ValueReference vr[], size_t nvr, fmi3Float64 values[],
                          size_t nValues) {
  return guarded(c, [&](FmuInstance& i) {
    if (nValues != nvr) return i.refuse("get values", "one per value reference (every variable is a scalar)");
    return i.get_real(vr, nvr, values);
  });
}
fmi3Status fmi3SetFloat64(fmi3Instance c, const fmi3ValueReference vr[], size_t nvr, const fmi3Float64 values[],
                          size_t nValues) {
  return guarded(c, [&](FmuInstance& i) {
    if (nValues != nvr) return i.refuse("set values", "one per value reference (every variable is a scalar)");
    return i.set_real(vr, nvr, values);
  });
}

// The other types: no variable has them.
#define MBSC_FMI3_NO_TYPE(Type)                                                                                   \
  fmi3Status fmi3Get##Type(fmi3Instance c, const fmi3ValueReference[], size_t nvr, fmi3##Type[], size_t) {      \
    return nvr == 0 ? fmi3OK : unsupported(c, "a variable of type " #Type);                                     \
  }                                                                                                             \
  fmi3Status fmi3Set##Type(fmi3Instance c, const fmi3ValueReference[], size_t nvr, const fmi3##Type[], size_t) { \
    return nvr == 0 ? fmi3OK : unsupported(c, "a variable of type " #Type);                                     \
  }
MBSC_FMI3_NO_TYPE(Float32)
MBSC_FMI3_NO_TYPE(Int8)
MBSC_FMI3_NO_TYPE(UInt8)
MBSC_FMI3_NO_TYPE(Int16)
MBSC_FMI3_NO_TYPE(UInt16)
MBSC_FMI3_NO_TYPE(Int32)
MBSC_FMI3_NO_TYPE(UInt32)
MBSC_FMI3_NO_TYPE(Int64)
MBSC_FMI3_NO_TYPE(UInt64)
MBSC_FMI3_NO_TYPE(Boolean)
MBSC_FMI3_NO_TYPE(String)
#undef MBSC_FMI3_NO_TYPE
fmi3Status fmi3GetBinary(fmi3Instance c, const fmi3ValueReference[], size_t nvr, size_t[], fmi3Binary[], size_t) {
  return nvr == 0 ? fmi3OK : unsupported(c, "a Binary variable");
}
fmi3Status fmi3SetBinary(fmi3Instance c, const fmi3ValueReference[], size_t nvr, const size_t[], const fmi3Binary[],
                         size_t) {
  return nvr == 0 ? fmi3OK : unsupported(c, "a Binary variable");
}
fmi3Status fmi3GetClock(fmi3Instance c, const fmi3ValueReference[], size_t nvr, fmi3Clock[]) {
  return nvr == 0 ? fmi3OK : unsupported(c, "a Clock variable");
}
fmi3Status fmi3SetClock(fmi3Instance c, const fmi3ValueReference[], size_t nvr, const fmi3Clock[]) {
  return nvr == 0 ? fmi3OK : unsupported(c, "a Clock variable");
}

fmi3Status fmi3GetNumberOfVariableDependencies(fmi3Instance c, fmi3ValueReference, size_t*) {
  return unsupported(c, "fmi3GetNumberOfVariableDependencies");
}
fmi3Status fmi3GetVariableDependencies(fmi3Instance c, fmi3ValueReference, size_t[], fmi3ValueReference[], size_t[],
                                       fmi3DependencyKind[], size_t) {
  return unsupported(c, "fmi3GetVariableDependencies");
}

fmi3Status fmi3GetFMUState(fmi3Instance c, fmi3FMUState* state) {
  return guarded(c, [&](FmuInstance& i) { return i.get_fmu_state(state); });
}
fmi3Status fmi3SetFMUState(fmi3Instance c, fmi3FMUState state) {
  return guarded(c, [&](FmuInstance& i) { return i.set_fmu_state(state); });
}
fmi3Status fmi3FreeFMUState(fmi3Instance c, fmi3FMUState* state) {
  return guarded(c, [&](FmuInstance&) { return FmuInstance::free_fmu_state(state); });
}
fmi3Status fmi3SerializedFMUStateSize(fmi3Instance c, fmi3FMUState state, size_t* size) {
  return guarded(c, [&](FmuInstance& i) { return i.serialized_size(state, size); });
}
fmi3Status fmi3SerializeFMUState(fmi3Instance c, fmi3FMUState state, fmi3Byte bytes[], size_t size) {
  return guarded(c, [&](FmuInstance& i) { return i.serialize_into(state, reinterpret_cast<unsigned char*>(bytes), size); });
}
fmi3Status fmi3DeserializeFMUState(fmi3Instance c, const fmi3Byte bytes[], size_t size, fmi3FMUState* state) {
  return guarded(c, [&](FmuInstance& i) {
    return i.deserialize_into(reinterpret_cast<const unsigned char*>(bytes), size, state);
  });
}
fmi3Status fmi3GetDirectionalDerivative(fmi3Instance c, const fmi3ValueReference[], size_t, const fmi3ValueReference[],
                                        size_t, const fmi3Float64[], size_t, fmi3Float64[], size_t) {
  return unsupported(c, "fmi3GetDirectionalDerivative");
}
fmi3Status fmi3GetAdjointDerivative(fmi3Instance c, const fmi3ValueReference[], size_t, const fmi3ValueReference[],
                                    size_t, const fmi3Float64[], size_t, fmi3Float64[], size_t) {
  return unsupported(c, "fmi3GetAdjointDerivative");
}
fmi3Status fmi3EnterConfigurationMode(fmi3Instance c) {
  return unsupported(c, "configuration mode (no structural parameters)");
}
fmi3Status fmi3ExitConfigurationMode(fmi3Instance c) {
  return unsupported(c, "configuration mode (no structural parameters)");
}

fmi3Status fmi3GetIntervalDecimal(fmi3Instance c, const fmi3ValueReference[], size_t, fmi3Float64[],
                                  fmi3IntervalQualifier[]) {
  return unsupported(c, "a clock");
}
fmi3Status fmi3GetIntervalFraction(fmi3Instance c, const fmi3ValueReference[], size_t, fmi3UInt64[], fmi3UInt64[],
                                   fmi3IntervalQualifier[]) {
  return unsupported(c, "a clock");
}
fmi3Status fmi3GetShiftDecimal(fmi3Instance c, const fmi3ValueReference[], size_t, fmi3Float64[]) {
  return unsupported(c, "a clock");
}
fmi3Status fmi3GetShiftFraction(fmi3Instance c, const fmi3ValueReference[], size_t, fmi3UInt64[], fmi3UInt64[]) {
  return unsupported(c, "a clock");
}
fmi3Status fmi3SetIntervalDecimal(fmi3Instance c, const fmi3ValueReference[], size_t, const fmi3Float64[]) {
  return unsupported(c, "a clock");
}
fmi3Status fmi3SetIntervalFraction(fmi3Instance c, const fmi3ValueReference[], size_t, const fmi3UInt64[],
                                   const fmi3UInt64[]) {
  return unsupported(c, "a clock");
}
fmi3Status fmi3SetShiftDecimal(fmi3Instance c, const fmi3ValueReference[], size_t, const fmi3Float64[]) {
  return unsupported(c, "a clock");
}
fmi3Status fmi3SetShiftFraction(fmi3Instance c, const fmi3ValueReference[], size_t, const fmi3UInt64[],
                                const fmi3UInt64[]) {
  return unsupported(c, "a clock");
}
fmi3Status fmi3EvaluateDiscreteStates(fmi3Instance c) {
  return guarded(c, [](FmuInstance&) { return mbsc::fmi::kOK; });
}
fmi3Status fmi3UpdateDiscreteStates(fmi3Instance c, fmi3Boolean* discreteStatesNeedUpdate,
                                    fmi3Boolean* terminateSimulation, fmi3Boolean* nominalsOfContinuousStatesChanged,
                                    fmi3Boolean* valuesOfContinuousStatesChanged, fmi3Boolean* nextEventTimeDefined,
                                    fmi3Float64* nextEventTime) {
  return guarded(c, [&](FmuInstance& i) {
    bool changed = false;
    const auto s = i.update_discrete_states(changed);
    if (discreteStatesNeedUpdate) *discreteStatesNeedUpdate = false;
    if (terminateSimulation) *terminateSimulation = false;
    if (nominalsOfContinuousStatesChanged) *nominalsOfContinuousStatesChanged = false;
    if (valuesOfContinuousStatesChanged) *valuesOfContinuousStatesChanged = changed;
    if (nextEventTimeDefined) *nextEventTimeDefined = false;
    if (nextEventTime) *nextEventTime = 0.0;
    return s;
  });
}

// ---- model exchange ----
fmi3Status fmi3EnterContinuousTimeMode(fmi3Instance c) {
  return guarded(c, [](FmuInstance& i) { return i.enter_continuous_time_mode(); });
}
fmi3Status fmi3CompletedIntegratorStep(fmi3Instance c, fmi3Boolean, fmi3Boolean* enterEventMode,
                                       fmi3Boolean* terminateSimulation) {
  return guarded(c, [&](FmuInstance& i) {
    bool event = false;
    const auto s = i.completed_integrator_step(event);
    if (enterEventMode) *enterEventMode = event;
    if (terminateSimulation) *terminateSimulation = false;
    return s;
  });
}
fmi3Status fmi3SetTime(fmi3Instance c, fmi3Float64 time) {
  return guarded(c, [&](FmuInstance& i) { return i.set_time(time); });
}
fmi3Status fmi3SetContinuousStates(fmi3Instance c, const fmi3Float64 x[], size_t n) {
  return guarded(c, [&](FmuInstance& i) { return i.set_states(x, n); });
}
fmi3Status fmi3GetContinuousStateDerivatives(fmi3Instance c, fmi3Float64 derivatives[], size_t n) {
  return guarded(c, [&](FmuInstance& i) { return i.get_derivatives(derivatives, n); });
}
fmi3Status fmi3GetEventIndicators(fmi3Instance c, fmi3Float64[], size_t n) {
  return n == 0 ? fmi3OK : unsupported(c, "an event indicator");
}
fmi3Status fmi3GetContinuousStates(fmi3Instance c, fmi3Float64 x[], size_t n) {
  return guarded(c, [&](FmuInstance& i) { return i.get_states(x, n); });
}
fmi3Status fmi3GetNominalsOfContinuousStates(fmi3Instance c, fmi3Float64 nominals[], size_t n) {
  return guarded(c, [&](FmuInstance& i) { return i.get_nominals(nominals, n); });
}
fmi3Status fmi3GetNumberOfEventIndicators(fmi3Instance c, size_t* n) {
  return guarded(c, [&](FmuInstance&) {
    if (n) *n = 0;
    return mbsc::fmi::kOK;
  });
}
fmi3Status fmi3GetNumberOfContinuousStates(fmi3Instance c, size_t* n) {
  return guarded(c, [&](FmuInstance& i) {
    if (n) *n = static_cast<size_t>(i.model().table.nx);
    return mbsc::fmi::kOK;
  });
}

// ---- co-simulation ----
fmi3Status fmi3EnterStepMode(fmi3Instance c) {
  return guarded(c, [](FmuInstance&) { return mbsc::fmi::kOK; });
}
fmi3Status fmi3GetOutputDerivatives(fmi3Instance c, const fmi3ValueReference[], size_t nvr, const fmi3Int32[],
                                    fmi3Float64[], size_t) {
  return nvr == 0 ? fmi3OK : unsupported(c, "fmi3GetOutputDerivatives");
}
fmi3Status fmi3DoStep(fmi3Instance c, fmi3Float64 currentCommunicationPoint, fmi3Float64 communicationStepSize,
                      fmi3Boolean, fmi3Boolean* eventHandlingNeeded, fmi3Boolean* terminateSimulation,
                      fmi3Boolean* earlyReturn, fmi3Float64* lastSuccessfulTime) {
  return guarded(c, [&](FmuInstance& i) {
    const auto s = i.do_step(currentCommunicationPoint, communicationStepSize);
    if (eventHandlingNeeded) *eventHandlingNeeded = false;
    if (terminateSimulation) *terminateSimulation = false;
    if (earlyReturn) *earlyReturn = false;
    if (lastSuccessfulTime) *lastSuccessfulTime = i.time();
    return s;
  });
}

fmi3Status fmi3ActivateModelPartition(fmi3Instance c, fmi3ValueReference, fmi3Float64) {
  return unsupported(c, "scheduled execution");
}

}  // extern "C"
