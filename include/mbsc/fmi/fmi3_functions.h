/* SPDX-License-Identifier: GPL-2.0-or-later WITH mbsc-runtime-exception
 * (see LICENSE: this header may be included in applications under any terms)
 *
 * The C interface of FMI 3.0 (Functional Mock-up Interface, version 3.0, Modelica
 * Association 2022), written for mbsc from the types and function signatures the
 * standard publishes: what an FMU exported by `mbsc generate --fmi 3` defines and what
 * an importer calls. The names, types and argument orders are the standard's; the text
 * is ours. An FMU's shared library exports these functions by their plain names. */
#ifndef MBSC_FMI3_FUNCTIONS_H
#define MBSC_FMI3_FUNCTIONS_H

#include <stddef.h>
#include <stdint.h>
#ifndef __cplusplus
#include <stdbool.h>
#endif

#ifdef __cplusplus
extern "C" {
#endif

#if defined(_WIN32)
#define MBSC_FMI3_EXPORT __declspec(dllexport)
#else
#define MBSC_FMI3_EXPORT __attribute__((visibility("default")))
#endif

typedef void* fmi3Instance;
typedef void* fmi3InstanceEnvironment;
typedef void* fmi3FMUState;
typedef uint32_t fmi3ValueReference;
typedef float fmi3Float32;
typedef double fmi3Float64;
typedef int8_t fmi3Int8;
typedef uint8_t fmi3UInt8;
typedef int16_t fmi3Int16;
typedef uint16_t fmi3UInt16;
typedef int32_t fmi3Int32;
typedef uint32_t fmi3UInt32;
typedef int64_t fmi3Int64;
typedef uint64_t fmi3UInt64;
typedef bool fmi3Boolean;
typedef char fmi3Char;
typedef const fmi3Char* fmi3String;
typedef uint8_t fmi3Byte;
typedef const fmi3Byte* fmi3Binary;
typedef bool fmi3Clock;
#define fmi3True true
#define fmi3False false
#define fmi3Version "3.0"

typedef enum { fmi3OK, fmi3Warning, fmi3Discard, fmi3Error, fmi3Fatal } fmi3Status;
typedef enum { fmi3ModelExchange, fmi3CoSimulation, fmi3ScheduledExecution } fmi3Type;
typedef enum { fmi3Independent, fmi3Constant, fmi3Fixed, fmi3Tunable, fmi3Discrete, fmi3Dependent } fmi3DependencyKind;
typedef enum { fmi3IntervalNotYetKnown, fmi3IntervalUnchanged, fmi3IntervalChanged } fmi3IntervalQualifier;

typedef void (*fmi3LogMessageCallback)(fmi3InstanceEnvironment instanceEnvironment, fmi3Status status,
                                       fmi3String category, fmi3String message);
typedef void (*fmi3ClockUpdateCallback)(fmi3InstanceEnvironment instanceEnvironment);
typedef void (*fmi3IntermediateUpdateCallback)(fmi3InstanceEnvironment instanceEnvironment,
                                               fmi3Float64 intermediateUpdateTime,
                                               fmi3Boolean intermediateVariableSetRequested,
                                               fmi3Boolean intermediateVariableGetAllowed,
                                               fmi3Boolean intermediateStepFinished, fmi3Boolean canReturnEarly,
                                               fmi3Boolean* earlyReturnRequested, fmi3Float64* earlyReturnTime);
typedef void (*fmi3LockPreemptionCallback)(void);
typedef void (*fmi3UnlockPreemptionCallback)(void);

/* An FMU compiled into its importer from sources names its functions with the prefix
 * FMI3_FUNCTION_PREFIX (the model identifier and '_'), as the standard provides: defined,
 * every function below is declared and defined under the prefixed name. */
#ifdef FMI3_FUNCTION_PREFIX
#define MBSC_FMI3_PASTE(a, b) a##b
#define MBSC_FMI3_NAME(a, b) MBSC_FMI3_PASTE(a, b)
#define fmi3GetVersion MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3GetVersion)
#define fmi3SetDebugLogging MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3SetDebugLogging)
#define fmi3InstantiateModelExchange MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3InstantiateModelExchange)
#define fmi3InstantiateCoSimulation MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3InstantiateCoSimulation)
#define fmi3InstantiateScheduledExecution MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3InstantiateScheduledExecution)
#define fmi3FreeInstance MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3FreeInstance)
#define fmi3EnterInitializationMode MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3EnterInitializationMode)
#define fmi3ExitInitializationMode MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3ExitInitializationMode)
#define fmi3EnterEventMode MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3EnterEventMode)
#define fmi3Terminate MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3Terminate)
#define fmi3Reset MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3Reset)
#define fmi3GetBinary MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3GetBinary)
#define fmi3SetBinary MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3SetBinary)
#define fmi3GetClock MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3GetClock)
#define fmi3SetClock MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3SetClock)
#define fmi3GetNumberOfVariableDependencies MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3GetNumberOfVariableDependencies)
#define fmi3GetVariableDependencies MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3GetVariableDependencies)
#define fmi3GetFMUState MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3GetFMUState)
#define fmi3SetFMUState MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3SetFMUState)
#define fmi3FreeFMUState MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3FreeFMUState)
#define fmi3SerializedFMUStateSize MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3SerializedFMUStateSize)
#define fmi3SerializeFMUState MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3SerializeFMUState)
#define fmi3DeserializeFMUState MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3DeserializeFMUState)
#define fmi3GetDirectionalDerivative MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3GetDirectionalDerivative)
#define fmi3GetAdjointDerivative MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3GetAdjointDerivative)
#define fmi3EnterConfigurationMode MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3EnterConfigurationMode)
#define fmi3ExitConfigurationMode MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3ExitConfigurationMode)
#define fmi3GetIntervalDecimal MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3GetIntervalDecimal)
#define fmi3GetIntervalFraction MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3GetIntervalFraction)
#define fmi3GetShiftDecimal MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3GetShiftDecimal)
#define fmi3GetShiftFraction MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3GetShiftFraction)
#define fmi3SetIntervalDecimal MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3SetIntervalDecimal)
#define fmi3SetIntervalFraction MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3SetIntervalFraction)
#define fmi3SetShiftDecimal MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3SetShiftDecimal)
#define fmi3SetShiftFraction MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3SetShiftFraction)
#define fmi3EvaluateDiscreteStates MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3EvaluateDiscreteStates)
#define fmi3UpdateDiscreteStates MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3UpdateDiscreteStates)
#define fmi3EnterContinuousTimeMode MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3EnterContinuousTimeMode)
#define fmi3CompletedIntegratorStep MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3CompletedIntegratorStep)
#define fmi3SetTime MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3SetTime)
#define fmi3SetContinuousStates MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3SetContinuousStates)
#define fmi3GetContinuousStateDerivatives MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3GetContinuousStateDerivatives)
#define fmi3GetEventIndicators MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3GetEventIndicators)
#define fmi3GetContinuousStates MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3GetContinuousStates)
#define fmi3GetNominalsOfContinuousStates MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3GetNominalsOfContinuousStates)
#define fmi3GetNumberOfEventIndicators MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3GetNumberOfEventIndicators)
#define fmi3GetNumberOfContinuousStates MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3GetNumberOfContinuousStates)
#define fmi3EnterStepMode MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3EnterStepMode)
#define fmi3GetOutputDerivatives MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3GetOutputDerivatives)
#define fmi3DoStep MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3DoStep)
#define fmi3ActivateModelPartition MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3ActivateModelPartition)
#define fmi3GetUInt64 MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3GetUInt64)
#define fmi3SetUInt8 MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3SetUInt8)
#define fmi3SetUInt16 MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3SetUInt16)
#define fmi3GetInt8 MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3GetInt8)
#define fmi3SetUInt64 MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3SetUInt64)
#define fmi3GetFloat64 MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3GetFloat64)
#define fmi3SetBoolean MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3SetBoolean)
#define fmi3SetInt8 MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3SetInt8)
#define fmi3GetString MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3GetString)
#define fmi3GetUInt8 MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3GetUInt8)
#define fmi3SetInt32 MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3SetInt32)
#define fmi3SetString MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3SetString)
#define fmi3SetFloat32 MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3SetFloat32)
#define fmi3GetBoolean MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3GetBoolean)
#define fmi3GetUInt32 MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3GetUInt32)
#define fmi3GetInt32 MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3GetInt32)
#define fmi3SetInt16 MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3SetInt16)
#define fmi3GetUInt16 MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3GetUInt16)
#define fmi3SetUInt32 MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3SetUInt32)
#define fmi3GetInt64 MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3GetInt64)
#define fmi3GetFloat32 MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3GetFloat32)
#define fmi3SetInt64 MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3SetInt64)
#define fmi3SetFloat64 MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3SetFloat64)
#define fmi3GetInt16 MBSC_FMI3_NAME(FMI3_FUNCTION_PREFIX, fmi3GetInt16)
#endif

/* Common to every kind. */
MBSC_FMI3_EXPORT const char* fmi3GetVersion(void);
MBSC_FMI3_EXPORT fmi3Status fmi3SetDebugLogging(fmi3Instance instance, fmi3Boolean loggingOn, size_t nCategories,
                                                const fmi3String categories[]);
MBSC_FMI3_EXPORT fmi3Instance fmi3InstantiateModelExchange(fmi3String instanceName, fmi3String instantiationToken,
                                                           fmi3String resourcePath, fmi3Boolean visible,
                                                           fmi3Boolean loggingOn,
                                                           fmi3InstanceEnvironment instanceEnvironment,
                                                           fmi3LogMessageCallback logMessage);
MBSC_FMI3_EXPORT fmi3Instance fmi3InstantiateCoSimulation(
    fmi3String instanceName, fmi3String instantiationToken, fmi3String resourcePath, fmi3Boolean visible,
    fmi3Boolean loggingOn, fmi3Boolean eventModeUsed, fmi3Boolean earlyReturnAllowed,
    const fmi3ValueReference requiredIntermediateVariables[], size_t nRequiredIntermediateVariables,
    fmi3InstanceEnvironment instanceEnvironment, fmi3LogMessageCallback logMessage,
    fmi3IntermediateUpdateCallback intermediateUpdate);
MBSC_FMI3_EXPORT fmi3Instance fmi3InstantiateScheduledExecution(
    fmi3String instanceName, fmi3String instantiationToken, fmi3String resourcePath, fmi3Boolean visible,
    fmi3Boolean loggingOn, fmi3InstanceEnvironment instanceEnvironment, fmi3LogMessageCallback logMessage,
    fmi3ClockUpdateCallback clockUpdate, fmi3LockPreemptionCallback lockPreemption,
    fmi3UnlockPreemptionCallback unlockPreemption);
MBSC_FMI3_EXPORT void fmi3FreeInstance(fmi3Instance instance);
MBSC_FMI3_EXPORT fmi3Status fmi3EnterInitializationMode(fmi3Instance instance, fmi3Boolean toleranceDefined,
                                                        fmi3Float64 tolerance, fmi3Float64 startTime,
                                                        fmi3Boolean stopTimeDefined, fmi3Float64 stopTime);
MBSC_FMI3_EXPORT fmi3Status fmi3ExitInitializationMode(fmi3Instance instance);
MBSC_FMI3_EXPORT fmi3Status fmi3EnterEventMode(fmi3Instance instance);
MBSC_FMI3_EXPORT fmi3Status fmi3Terminate(fmi3Instance instance);
MBSC_FMI3_EXPORT fmi3Status fmi3Reset(fmi3Instance instance);

/* Getting and setting values: one pair per type. */
#define MBSC_FMI3_GET_SET(Type)                                                                                   \
  MBSC_FMI3_EXPORT fmi3Status fmi3Get##Type(fmi3Instance instance, const fmi3ValueReference valueReferences[],   \
                                            size_t nValueReferences, fmi3##Type values[], size_t nValues);       \
  MBSC_FMI3_EXPORT fmi3Status fmi3Set##Type(fmi3Instance instance, const fmi3ValueReference valueReferences[],   \
                                            size_t nValueReferences, const fmi3##Type values[], size_t nValues);
MBSC_FMI3_GET_SET(Float32)
MBSC_FMI3_GET_SET(Float64)
MBSC_FMI3_GET_SET(Int8)
MBSC_FMI3_GET_SET(UInt8)
MBSC_FMI3_GET_SET(Int16)
MBSC_FMI3_GET_SET(UInt16)
MBSC_FMI3_GET_SET(Int32)
MBSC_FMI3_GET_SET(UInt32)
MBSC_FMI3_GET_SET(Int64)
MBSC_FMI3_GET_SET(UInt64)
MBSC_FMI3_GET_SET(Boolean)
MBSC_FMI3_GET_SET(String)
#undef MBSC_FMI3_GET_SET
MBSC_FMI3_EXPORT fmi3Status fmi3GetBinary(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                          size_t nValueReferences, size_t valueSizes[], fmi3Binary values[],
                                          size_t nValues);
MBSC_FMI3_EXPORT fmi3Status fmi3SetBinary(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                          size_t nValueReferences, const size_t valueSizes[],
                                          const fmi3Binary values[], size_t nValues);
MBSC_FMI3_EXPORT fmi3Status fmi3GetClock(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                         size_t nValueReferences, fmi3Clock values[]);
MBSC_FMI3_EXPORT fmi3Status fmi3SetClock(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                         size_t nValueReferences, const fmi3Clock values[]);

MBSC_FMI3_EXPORT fmi3Status fmi3GetNumberOfVariableDependencies(fmi3Instance instance,
                                                                fmi3ValueReference valueReference,
                                                                size_t* nDependencies);
MBSC_FMI3_EXPORT fmi3Status fmi3GetVariableDependencies(fmi3Instance instance, fmi3ValueReference dependent,
                                                        size_t elementIndicesOfDependent[],
                                                        fmi3ValueReference independents[],
                                                        size_t elementIndicesOfIndependents[],
                                                        fmi3DependencyKind dependencyKinds[], size_t nDependencies);

MBSC_FMI3_EXPORT fmi3Status fmi3GetFMUState(fmi3Instance instance, fmi3FMUState* FMUState);
MBSC_FMI3_EXPORT fmi3Status fmi3SetFMUState(fmi3Instance instance, fmi3FMUState FMUState);
MBSC_FMI3_EXPORT fmi3Status fmi3FreeFMUState(fmi3Instance instance, fmi3FMUState* FMUState);
MBSC_FMI3_EXPORT fmi3Status fmi3SerializedFMUStateSize(fmi3Instance instance, fmi3FMUState FMUState, size_t* size);
MBSC_FMI3_EXPORT fmi3Status fmi3SerializeFMUState(fmi3Instance instance, fmi3FMUState FMUState,
                                                  fmi3Byte serializedState[], size_t size);
MBSC_FMI3_EXPORT fmi3Status fmi3DeserializeFMUState(fmi3Instance instance, const fmi3Byte serializedState[],
                                                    size_t size, fmi3FMUState* FMUState);

MBSC_FMI3_EXPORT fmi3Status fmi3GetDirectionalDerivative(fmi3Instance instance, const fmi3ValueReference unknowns[],
                                                         size_t nUnknowns, const fmi3ValueReference knowns[],
                                                         size_t nKnowns, const fmi3Float64 seed[], size_t nSeed,
                                                         fmi3Float64 sensitivity[], size_t nSensitivity);
MBSC_FMI3_EXPORT fmi3Status fmi3GetAdjointDerivative(fmi3Instance instance, const fmi3ValueReference unknowns[],
                                                     size_t nUnknowns, const fmi3ValueReference knowns[],
                                                     size_t nKnowns, const fmi3Float64 seed[], size_t nSeed,
                                                     fmi3Float64 sensitivity[], size_t nSensitivity);

MBSC_FMI3_EXPORT fmi3Status fmi3EnterConfigurationMode(fmi3Instance instance);
MBSC_FMI3_EXPORT fmi3Status fmi3ExitConfigurationMode(fmi3Instance instance);

/* Clocks. */
MBSC_FMI3_EXPORT fmi3Status fmi3GetIntervalDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                                   size_t nValueReferences, fmi3Float64 intervals[],
                                                   fmi3IntervalQualifier qualifiers[]);
MBSC_FMI3_EXPORT fmi3Status fmi3GetIntervalFraction(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                                    size_t nValueReferences, fmi3UInt64 counters[],
                                                    fmi3UInt64 resolutions[], fmi3IntervalQualifier qualifiers[]);
MBSC_FMI3_EXPORT fmi3Status fmi3GetShiftDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                                size_t nValueReferences, fmi3Float64 shifts[]);
MBSC_FMI3_EXPORT fmi3Status fmi3GetShiftFraction(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                                 size_t nValueReferences, fmi3UInt64 counters[],
                                                 fmi3UInt64 resolutions[]);
MBSC_FMI3_EXPORT fmi3Status fmi3SetIntervalDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                                   size_t nValueReferences, const fmi3Float64 intervals[]);
MBSC_FMI3_EXPORT fmi3Status fmi3SetIntervalFraction(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                                    size_t nValueReferences, const fmi3UInt64 counters[],
                                                    const fmi3UInt64 resolutions[]);
MBSC_FMI3_EXPORT fmi3Status fmi3SetShiftDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                                size_t nValueReferences, const fmi3Float64 shifts[]);
MBSC_FMI3_EXPORT fmi3Status fmi3SetShiftFraction(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                                 size_t nValueReferences, const fmi3UInt64 counters[],
                                                 const fmi3UInt64 resolutions[]);
MBSC_FMI3_EXPORT fmi3Status fmi3EvaluateDiscreteStates(fmi3Instance instance);
MBSC_FMI3_EXPORT fmi3Status fmi3UpdateDiscreteStates(fmi3Instance instance, fmi3Boolean* discreteStatesNeedUpdate,
                                                     fmi3Boolean* terminateSimulation,
                                                     fmi3Boolean* nominalsOfContinuousStatesChanged,
                                                     fmi3Boolean* valuesOfContinuousStatesChanged,
                                                     fmi3Boolean* nextEventTimeDefined, fmi3Float64* nextEventTime);

/* Model exchange. */
MBSC_FMI3_EXPORT fmi3Status fmi3EnterContinuousTimeMode(fmi3Instance instance);
MBSC_FMI3_EXPORT fmi3Status fmi3CompletedIntegratorStep(fmi3Instance instance,
                                                        fmi3Boolean noSetFMUStatePriorToCurrentPoint,
                                                        fmi3Boolean* enterEventMode, fmi3Boolean* terminateSimulation);
MBSC_FMI3_EXPORT fmi3Status fmi3SetTime(fmi3Instance instance, fmi3Float64 time);
MBSC_FMI3_EXPORT fmi3Status fmi3SetContinuousStates(fmi3Instance instance, const fmi3Float64 continuousStates[],
                                                    size_t nContinuousStates);
MBSC_FMI3_EXPORT fmi3Status fmi3GetContinuousStateDerivatives(fmi3Instance instance, fmi3Float64 derivatives[],
                                                              size_t nContinuousStates);
MBSC_FMI3_EXPORT fmi3Status fmi3GetEventIndicators(fmi3Instance instance, fmi3Float64 eventIndicators[],
                                                   size_t nEventIndicators);
MBSC_FMI3_EXPORT fmi3Status fmi3GetContinuousStates(fmi3Instance instance, fmi3Float64 continuousStates[],
                                                    size_t nContinuousStates);
MBSC_FMI3_EXPORT fmi3Status fmi3GetNominalsOfContinuousStates(fmi3Instance instance, fmi3Float64 nominals[],
                                                              size_t nContinuousStates);
MBSC_FMI3_EXPORT fmi3Status fmi3GetNumberOfEventIndicators(fmi3Instance instance, size_t* nEventIndicators);
MBSC_FMI3_EXPORT fmi3Status fmi3GetNumberOfContinuousStates(fmi3Instance instance, size_t* nContinuousStates);

/* Co-simulation. */
MBSC_FMI3_EXPORT fmi3Status fmi3EnterStepMode(fmi3Instance instance);
MBSC_FMI3_EXPORT fmi3Status fmi3GetOutputDerivatives(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                                     size_t nValueReferences, const fmi3Int32 orders[],
                                                     fmi3Float64 values[], size_t nValues);
MBSC_FMI3_EXPORT fmi3Status fmi3DoStep(fmi3Instance instance, fmi3Float64 currentCommunicationPoint,
                                       fmi3Float64 communicationStepSize, fmi3Boolean noSetFMUStatePriorToCurrentPoint,
                                       fmi3Boolean* eventHandlingNeeded, fmi3Boolean* terminateSimulation,
                                       fmi3Boolean* earlyReturn, fmi3Float64* lastSuccessfulTime);

/* Scheduled execution. */
MBSC_FMI3_EXPORT fmi3Status fmi3ActivateModelPartition(fmi3Instance instance, fmi3ValueReference clockReference,
                                                       fmi3Float64 activationTime);

#ifdef __cplusplus
}
#endif

#endif /* MBSC_FMI3_FUNCTIONS_H */
