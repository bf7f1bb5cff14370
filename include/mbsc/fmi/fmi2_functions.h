/* SPDX-License-Identifier: GPL-2.0-or-later WITH mbsc-runtime-exception
 * (see LICENSE: this header may be included in applications under any terms)
 *
 * The C interface of FMI 2.0 (Functional Mock-up Interface for Model Exchange and
 * Co-Simulation, version 2.0, Modelica Association 2014), written for mbsc from the
 * types and function signatures the standard publishes: what an FMU exported by
 * `mbsc generate --fmi 2` defines and what an importer calls. The names, types and
 * argument orders are the standard's; the text is ours. An FMU's shared library
 * exports these functions by their plain names (no model prefix). */
#ifndef MBSC_FMI2_FUNCTIONS_H
#define MBSC_FMI2_FUNCTIONS_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

#if defined(_WIN32)
#define MBSC_FMI2_EXPORT __declspec(dllexport)
#else
#define MBSC_FMI2_EXPORT __attribute__((visibility("default")))
#endif

/* Platform types (the standard's "default" platform). */
typedef void* fmi2Component;
typedef void* fmi2ComponentEnvironment;
typedef void* fmi2FMUstate;
typedef unsigned int fmi2ValueReference;
typedef double fmi2Real;
typedef int fmi2Integer;
typedef int fmi2Boolean;
typedef char fmi2Char;
typedef const fmi2Char* fmi2String;
typedef char fmi2Byte;
#define fmi2True 1
#define fmi2False 0
#define fmi2TypesPlatform "default"
#define fmi2Version "2.0"

typedef enum { fmi2OK, fmi2Warning, fmi2Discard, fmi2Error, fmi2Fatal, fmi2Pending } fmi2Status;
typedef enum { fmi2ModelExchange, fmi2CoSimulation } fmi2Type;
typedef enum { fmi2DoStepStatus, fmi2PendingStatus, fmi2LastSuccessfulTime, fmi2Terminated } fmi2StatusKind;

typedef void (*fmi2CallbackLogger)(fmi2ComponentEnvironment componentEnvironment, fmi2String instanceName,
                                   fmi2Status status, fmi2String category, fmi2String message, ...);
typedef void* (*fmi2CallbackAllocateMemory)(size_t nobj, size_t size);
typedef void (*fmi2CallbackFreeMemory)(void* obj);
typedef void (*fmi2StepFinished)(fmi2ComponentEnvironment componentEnvironment, fmi2Status status);

typedef struct {
  const fmi2CallbackLogger logger;
  const fmi2CallbackAllocateMemory allocateMemory;
  const fmi2CallbackFreeMemory freeMemory;
  const fmi2StepFinished stepFinished;
  const fmi2ComponentEnvironment componentEnvironment;
} fmi2CallbackFunctions;

typedef struct {
  fmi2Boolean newDiscreteStatesNeeded;
  fmi2Boolean terminateSimulation;
  fmi2Boolean nominalsOfContinuousStatesChanged;
  fmi2Boolean valuesOfContinuousStatesChanged;
  fmi2Boolean nextEventTimeDefined;
  fmi2Real nextEventTime;
} fmi2EventInfo;

/* An FMU compiled into its importer from sources names its functions with the prefix
 * FMI2_FUNCTION_PREFIX (the model identifier and '_'), as the standard provides: defined,
 * every function below is declared and defined under the prefixed name. */
#ifdef FMI2_FUNCTION_PREFIX
#define MBSC_FMI2_PASTE(a, b) a##b
#define MBSC_FMI2_NAME(a, b) MBSC_FMI2_PASTE(a, b)
#define fmi2GetTypesPlatform MBSC_FMI2_NAME(FMI2_FUNCTION_PREFIX, fmi2GetTypesPlatform)
#define fmi2GetVersion MBSC_FMI2_NAME(FMI2_FUNCTION_PREFIX, fmi2GetVersion)
#define fmi2SetDebugLogging MBSC_FMI2_NAME(FMI2_FUNCTION_PREFIX, fmi2SetDebugLogging)
#define fmi2Instantiate MBSC_FMI2_NAME(FMI2_FUNCTION_PREFIX, fmi2Instantiate)
#define fmi2FreeInstance MBSC_FMI2_NAME(FMI2_FUNCTION_PREFIX, fmi2FreeInstance)
#define fmi2SetupExperiment MBSC_FMI2_NAME(FMI2_FUNCTION_PREFIX, fmi2SetupExperiment)
#define fmi2EnterInitializationMode MBSC_FMI2_NAME(FMI2_FUNCTION_PREFIX, fmi2EnterInitializationMode)
#define fmi2ExitInitializationMode MBSC_FMI2_NAME(FMI2_FUNCTION_PREFIX, fmi2ExitInitializationMode)
#define fmi2Terminate MBSC_FMI2_NAME(FMI2_FUNCTION_PREFIX, fmi2Terminate)
#define fmi2Reset MBSC_FMI2_NAME(FMI2_FUNCTION_PREFIX, fmi2Reset)
#define fmi2GetReal MBSC_FMI2_NAME(FMI2_FUNCTION_PREFIX, fmi2GetReal)
#define fmi2GetInteger MBSC_FMI2_NAME(FMI2_FUNCTION_PREFIX, fmi2GetInteger)
#define fmi2GetBoolean MBSC_FMI2_NAME(FMI2_FUNCTION_PREFIX, fmi2GetBoolean)
#define fmi2GetString MBSC_FMI2_NAME(FMI2_FUNCTION_PREFIX, fmi2GetString)
#define fmi2SetReal MBSC_FMI2_NAME(FMI2_FUNCTION_PREFIX, fmi2SetReal)
#define fmi2SetInteger MBSC_FMI2_NAME(FMI2_FUNCTION_PREFIX, fmi2SetInteger)
#define fmi2SetBoolean MBSC_FMI2_NAME(FMI2_FUNCTION_PREFIX, fmi2SetBoolean)
#define fmi2SetString MBSC_FMI2_NAME(FMI2_FUNCTION_PREFIX, fmi2SetString)
#define fmi2GetFMUstate MBSC_FMI2_NAME(FMI2_FUNCTION_PREFIX, fmi2GetFMUstate)
#define fmi2SetFMUstate MBSC_FMI2_NAME(FMI2_FUNCTION_PREFIX, fmi2SetFMUstate)
#define fmi2FreeFMUstate MBSC_FMI2_NAME(FMI2_FUNCTION_PREFIX, fmi2FreeFMUstate)
#define fmi2SerializedFMUstateSize MBSC_FMI2_NAME(FMI2_FUNCTION_PREFIX, fmi2SerializedFMUstateSize)
#define fmi2SerializeFMUstate MBSC_FMI2_NAME(FMI2_FUNCTION_PREFIX, fmi2SerializeFMUstate)
#define fmi2DeSerializeFMUstate MBSC_FMI2_NAME(FMI2_FUNCTION_PREFIX, fmi2DeSerializeFMUstate)
#define fmi2GetDirectionalDerivative MBSC_FMI2_NAME(FMI2_FUNCTION_PREFIX, fmi2GetDirectionalDerivative)
#define fmi2EnterEventMode MBSC_FMI2_NAME(FMI2_FUNCTION_PREFIX, fmi2EnterEventMode)
#define fmi2NewDiscreteStates MBSC_FMI2_NAME(FMI2_FUNCTION_PREFIX, fmi2NewDiscreteStates)
#define fmi2EnterContinuousTimeMode MBSC_FMI2_NAME(FMI2_FUNCTION_PREFIX, fmi2EnterContinuousTimeMode)
#define fmi2CompletedIntegratorStep MBSC_FMI2_NAME(FMI2_FUNCTION_PREFIX, fmi2CompletedIntegratorStep)
#define fmi2SetTime MBSC_FMI2_NAME(FMI2_FUNCTION_PREFIX, fmi2SetTime)
#define fmi2SetContinuousStates MBSC_FMI2_NAME(FMI2_FUNCTION_PREFIX, fmi2SetContinuousStates)
#define fmi2GetDerivatives MBSC_FMI2_NAME(FMI2_FUNCTION_PREFIX, fmi2GetDerivatives)
#define fmi2GetEventIndicators MBSC_FMI2_NAME(FMI2_FUNCTION_PREFIX, fmi2GetEventIndicators)
#define fmi2GetContinuousStates MBSC_FMI2_NAME(FMI2_FUNCTION_PREFIX, fmi2GetContinuousStates)
#define fmi2GetNominalsOfContinuousStates MBSC_FMI2_NAME(FMI2_FUNCTION_PREFIX, fmi2GetNominalsOfContinuousStates)
#define fmi2SetRealInputDerivatives MBSC_FMI2_NAME(FMI2_FUNCTION_PREFIX, fmi2SetRealInputDerivatives)
#define fmi2GetRealOutputDerivatives MBSC_FMI2_NAME(FMI2_FUNCTION_PREFIX, fmi2GetRealOutputDerivatives)
#define fmi2DoStep MBSC_FMI2_NAME(FMI2_FUNCTION_PREFIX, fmi2DoStep)
#define fmi2CancelStep MBSC_FMI2_NAME(FMI2_FUNCTION_PREFIX, fmi2CancelStep)
#define fmi2GetStatus MBSC_FMI2_NAME(FMI2_FUNCTION_PREFIX, fmi2GetStatus)
#define fmi2GetRealStatus MBSC_FMI2_NAME(FMI2_FUNCTION_PREFIX, fmi2GetRealStatus)
#define fmi2GetIntegerStatus MBSC_FMI2_NAME(FMI2_FUNCTION_PREFIX, fmi2GetIntegerStatus)
#define fmi2GetBooleanStatus MBSC_FMI2_NAME(FMI2_FUNCTION_PREFIX, fmi2GetBooleanStatus)
#define fmi2GetStringStatus MBSC_FMI2_NAME(FMI2_FUNCTION_PREFIX, fmi2GetStringStatus)
#endif

/* Common to both kinds. */
MBSC_FMI2_EXPORT const char* fmi2GetTypesPlatform(void);
MBSC_FMI2_EXPORT const char* fmi2GetVersion(void);
MBSC_FMI2_EXPORT fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean loggingOn, size_t nCategories,
                                                const fmi2String categories[]);
MBSC_FMI2_EXPORT fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                                               fmi2String fmuResourceLocation, const fmi2CallbackFunctions* functions,
                                               fmi2Boolean visible, fmi2Boolean loggingOn);
MBSC_FMI2_EXPORT void fmi2FreeInstance(fmi2Component c);
MBSC_FMI2_EXPORT fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean toleranceDefined, fmi2Real tolerance,
                                                fmi2Real startTime, fmi2Boolean stopTimeDefined, fmi2Real stopTime);
MBSC_FMI2_EXPORT fmi2Status fmi2EnterInitializationMode(fmi2Component c);
MBSC_FMI2_EXPORT fmi2Status fmi2ExitInitializationMode(fmi2Component c);
MBSC_FMI2_EXPORT fmi2Status fmi2Terminate(fmi2Component c);
MBSC_FMI2_EXPORT fmi2Status fmi2Reset(fmi2Component c);
MBSC_FMI2_EXPORT fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Real value[]);
MBSC_FMI2_EXPORT fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                           fmi2Integer value[]);
MBSC_FMI2_EXPORT fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                           fmi2Boolean value[]);
MBSC_FMI2_EXPORT fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                          fmi2String value[]);
MBSC_FMI2_EXPORT fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                        const fmi2Real value[]);
MBSC_FMI2_EXPORT fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                           const fmi2Integer value[]);
MBSC_FMI2_EXPORT fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                           const fmi2Boolean value[]);
MBSC_FMI2_EXPORT fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                          const fmi2String value[]);
MBSC_FMI2_EXPORT fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate* FMUstate);
MBSC_FMI2_EXPORT fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate FMUstate);
MBSC_FMI2_EXPORT fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate* FMUstate);
MBSC_FMI2_EXPORT fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate FMUstate, size_t* size);
MBSC_FMI2_EXPORT fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate FMUstate, fmi2Byte serializedState[],
                                                  size_t size);
MBSC_FMI2_EXPORT fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte serializedState[], size_t size,
                                                    fmi2FMUstate* FMUstate);
MBSC_FMI2_EXPORT fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference vUnknown_ref[],
                                                         size_t nUnknown, const fmi2ValueReference vKnown_ref[],
                                                         size_t nKnown, const fmi2Real dvKnown[],
                                                         fmi2Real dvUnknown[]);

/* Model exchange. */
MBSC_FMI2_EXPORT fmi2Status fmi2EnterEventMode(fmi2Component c);
MBSC_FMI2_EXPORT fmi2Status fmi2NewDiscreteStates(fmi2Component c, fmi2EventInfo* eventInfo);
MBSC_FMI2_EXPORT fmi2Status fmi2EnterContinuousTimeMode(fmi2Component c);
MBSC_FMI2_EXPORT fmi2Status fmi2CompletedIntegratorStep(fmi2Component c, fmi2Boolean noSetFMUStatePriorToCurrentPoint,
                                                        fmi2Boolean* enterEventMode, fmi2Boolean* terminateSimulation);
MBSC_FMI2_EXPORT fmi2Status fmi2SetTime(fmi2Component c, fmi2Real time);
MBSC_FMI2_EXPORT fmi2Status fmi2SetContinuousStates(fmi2Component c, const fmi2Real x[], size_t nx);
MBSC_FMI2_EXPORT fmi2Status fmi2GetDerivatives(fmi2Component c, fmi2Real derivatives[], size_t nx);
MBSC_FMI2_EXPORT fmi2Status fmi2GetEventIndicators(fmi2Component c, fmi2Real eventIndicators[], size_t ni);
MBSC_FMI2_EXPORT fmi2Status fmi2GetContinuousStates(fmi2Component c, fmi2Real x[], size_t nx);
MBSC_FMI2_EXPORT fmi2Status fmi2GetNominalsOfContinuousStates(fmi2Component c, fmi2Real x_nominal[], size_t nx);

/* Co-simulation. */
MBSC_FMI2_EXPORT fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                                        const fmi2Integer order[], const fmi2Real value[]);
MBSC_FMI2_EXPORT fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                                         const fmi2Integer order[], fmi2Real value[]);
MBSC_FMI2_EXPORT fmi2Status fmi2DoStep(fmi2Component c, fmi2Real currentCommunicationPoint,
                                       fmi2Real communicationStepSize, fmi2Boolean noSetFMUStatePriorToCurrentPoint);
MBSC_FMI2_EXPORT fmi2Status fmi2CancelStep(fmi2Component c);
MBSC_FMI2_EXPORT fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind s, fmi2Status* value);
MBSC_FMI2_EXPORT fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind s, fmi2Real* value);
MBSC_FMI2_EXPORT fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind s, fmi2Integer* value);
MBSC_FMI2_EXPORT fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind s, fmi2Boolean* value);
MBSC_FMI2_EXPORT fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind s, fmi2String* value);

#ifdef __cplusplus
}
#endif

#endif /* MBSC_FMI2_FUNCTIONS_H */
