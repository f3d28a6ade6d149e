/* CGain: the benchmark's Gain FMU (tests/fmus/gain.py) in plain C, FMI 2.0 co-simulation.
 *
 *   y_real = k * u_real    y_int = u_int + 1    y_bool = !u_bool
 *
 * Same variables, value references and start values as the pythonfmu Gain FMU
 * (see modelDescription.xml next to this file). As in Gain, the outputs follow the
 * inputs directly: they are recomputed after every fmi2Set* (so they are right in
 * initialization mode too) and in fmi2DoStep.
 *
 * Build (benchmarks/bench_orchestration.py does this at run time):
 *   gcc -shared -fPIC -O2 -I<fmpy>/c-code gain.c -o binaries/linux64/CGain.so
 * where <fmpy>/c-code holds the FMI 2.0 headers that fmpy ships.
 */
#include <stdlib.h>
#include <string.h>

#include "fmi2Functions.h"

#define CGAIN_GUID "{8c4e810f-3df3-4a00-8a85-d5a1c1d0a8b7}"

/* value references: the same as in the pythonfmu Gain FMU */
enum { VR_K = 0, VR_U_REAL = 1, VR_U_INT = 2, VR_U_BOOL = 3, VR_Y_REAL = 4, VR_Y_INT = 5, VR_Y_BOOL = 6 };

typedef struct {
    fmi2Real k, u_real, y_real;
    fmi2Integer u_int, y_int;
    fmi2Boolean u_bool, y_bool;
    fmi2CallbackLogger logger;
    fmi2ComponentEnvironment env;
    fmi2Boolean logging_on;
    char *name;
} Gain;

static void start_values(Gain *g) {
    g->k = 1.0;
    g->u_real = 0.0;
    g->u_int = 0;
    g->u_bool = fmi2False;
}

static void update(Gain *g) {
    g->y_real = g->k * g->u_real;
    g->y_int = g->u_int + 1;
    g->y_bool = g->u_bool ? fmi2False : fmi2True;
}

static fmi2Status fail(fmi2Component c, const char *message) {
    Gain *g = (Gain *)c;
    if (g && g->logger) g->logger(g->env, g->name, fmi2Error, "logStatusError", "%s", message);
    return fmi2Error;
}

static fmi2Status unsupported(fmi2Component c, const char *function) {
    Gain *g = (Gain *)c;
    if (g && g->logger) g->logger(g->env, g->name, fmi2Error, "logStatusError", "%s is not supported", function);
    return fmi2Error;
}

/* -- common functions -------------------------------------------------------------------------- */
const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }
const char *fmi2GetVersion(void) { return fmi2Version; }

fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean loggingOn, size_t nCategories,
                               const fmi2String categories[]) {
    (void)nCategories; (void)categories;
    ((Gain *)c)->logging_on = loggingOn;
    return fmi2OK;
}

fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                              fmi2String fmuResourceLocation, const fmi2CallbackFunctions *functions,
                              fmi2Boolean visible, fmi2Boolean loggingOn) {
    (void)fmuResourceLocation; (void)visible;
    fmi2CallbackLogger logger = functions ? functions->logger : NULL;
    fmi2ComponentEnvironment env = functions ? functions->componentEnvironment : NULL;
    if (fmuType != fmi2CoSimulation) {
        if (logger) logger(env, instanceName, fmi2Error, "logStatusError", "CGain supports co-simulation only");
        return NULL;
    }
    if (!fmuGUID || strcmp(fmuGUID, CGAIN_GUID) != 0) {
        if (logger) logger(env, instanceName, fmi2Error, "logStatusError", "wrong GUID %s, expected %s",
                           fmuGUID ? fmuGUID : "(null)", CGAIN_GUID);
        return NULL;
    }
    Gain *g = (Gain *)calloc(1, sizeof(Gain));
    if (!g) return NULL;
    const char *name = instanceName ? instanceName : "";
    g->name = (char *)malloc(strlen(name) + 1);
    if (!g->name) { free(g); return NULL; }
    strcpy(g->name, name);
    g->logger = logger;
    g->env = env;
    g->logging_on = loggingOn;
    start_values(g);
    update(g);
    return g;
}

void fmi2FreeInstance(fmi2Component c) {
    Gain *g = (Gain *)c;
    if (!g) return;
    free(g->name);
    free(g);
}

fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean toleranceDefined, fmi2Real tolerance,
                               fmi2Real startTime, fmi2Boolean stopTimeDefined, fmi2Real stopTime) {
    (void)c; (void)toleranceDefined; (void)tolerance; (void)startTime; (void)stopTimeDefined; (void)stopTime;
    return fmi2OK;
}

fmi2Status fmi2EnterInitializationMode(fmi2Component c) { (void)c; return fmi2OK; }
fmi2Status fmi2ExitInitializationMode(fmi2Component c) { update((Gain *)c); return fmi2OK; }
fmi2Status fmi2Terminate(fmi2Component c) { (void)c; return fmi2OK; }

fmi2Status fmi2Reset(fmi2Component c) {
    start_values((Gain *)c);
    update((Gain *)c);
    return fmi2OK;
}

/* -- getting and setting by value reference ---------------------------------------------------- */
fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Real value[]) {
    Gain *g = (Gain *)c;
    for (size_t i = 0; i < nvr; i++) {
        switch (vr[i]) {
            case VR_K: value[i] = g->k; break;
            case VR_U_REAL: value[i] = g->u_real; break;
            case VR_Y_REAL: value[i] = g->y_real; break;
            default: return fail(c, "fmi2GetReal: no Real variable with this value reference");
        }
    }
    return fmi2OK;
}

fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Integer value[]) {
    Gain *g = (Gain *)c;
    for (size_t i = 0; i < nvr; i++) {
        switch (vr[i]) {
            case VR_U_INT: value[i] = g->u_int; break;
            case VR_Y_INT: value[i] = g->y_int; break;
            default: return fail(c, "fmi2GetInteger: no Integer variable with this value reference");
        }
    }
    return fmi2OK;
}

fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Boolean value[]) {
    Gain *g = (Gain *)c;
    for (size_t i = 0; i < nvr; i++) {
        switch (vr[i]) {
            case VR_U_BOOL: value[i] = g->u_bool; break;
            case VR_Y_BOOL: value[i] = g->y_bool; break;
            default: return fail(c, "fmi2GetBoolean: no Boolean variable with this value reference");
        }
    }
    return fmi2OK;
}

fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2String value[]) {
    (void)vr; (void)value;
    return nvr == 0 ? fmi2OK : fail(c, "fmi2GetString: CGain has no String variables");
}

fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Real value[]) {
    Gain *g = (Gain *)c;
    for (size_t i = 0; i < nvr; i++) {
        switch (vr[i]) {
            case VR_K: g->k = value[i]; break;
            case VR_U_REAL: g->u_real = value[i]; break;
            default: return fail(c, "fmi2SetReal: no settable Real variable with this value reference");
        }
    }
    update(g);
    return fmi2OK;
}

fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Integer value[]) {
    Gain *g = (Gain *)c;
    for (size_t i = 0; i < nvr; i++) {
        if (vr[i] != VR_U_INT) return fail(c, "fmi2SetInteger: no settable Integer variable with this value reference");
        g->u_int = value[i];
    }
    update(g);
    return fmi2OK;
}

fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Boolean value[]) {
    Gain *g = (Gain *)c;
    for (size_t i = 0; i < nvr; i++) {
        if (vr[i] != VR_U_BOOL) return fail(c, "fmi2SetBoolean: no settable Boolean variable with this value reference");
        g->u_bool = value[i] ? fmi2True : fmi2False;
    }
    update(g);
    return fmi2OK;
}

fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2String value[]) {
    (void)vr; (void)value;
    return nvr == 0 ? fmi2OK : fail(c, "fmi2SetString: CGain has no String variables");
}

/* -- FMU state and directional derivatives: not supported (canGetAndSetFMUstate="false") ------- */
fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *s) { (void)s; return unsupported(c, "fmi2GetFMUstate"); }
fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate s) { (void)s; return unsupported(c, "fmi2SetFMUstate"); }
fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *s) { (void)s; return unsupported(c, "fmi2FreeFMUstate"); }

fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate s, size_t *size) {
    (void)s; (void)size;
    return unsupported(c, "fmi2SerializedFMUstateSize");
}

fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate s, fmi2Byte bytes[], size_t size) {
    (void)s; (void)bytes; (void)size;
    return unsupported(c, "fmi2SerializeFMUstate");
}

fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte bytes[], size_t size, fmi2FMUstate *s) {
    (void)bytes; (void)size; (void)s;
    return unsupported(c, "fmi2DeSerializeFMUstate");
}

fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference vUnknown[], size_t nUnknown,
                                        const fmi2ValueReference vKnown[], size_t nKnown,
                                        const fmi2Real dvKnown[], fmi2Real dvUnknown[]) {
    (void)vUnknown; (void)nUnknown; (void)vKnown; (void)nKnown; (void)dvKnown; (void)dvUnknown;
    return unsupported(c, "fmi2GetDirectionalDerivative");
}

/* -- model exchange: not supported (the FMU declares co-simulation only) ---------------------- */
fmi2Status fmi2EnterEventMode(fmi2Component c) { return unsupported(c, "fmi2EnterEventMode"); }

fmi2Status fmi2NewDiscreteStates(fmi2Component c, fmi2EventInfo *info) {
    (void)info;
    return unsupported(c, "fmi2NewDiscreteStates");
}

fmi2Status fmi2EnterContinuousTimeMode(fmi2Component c) { return unsupported(c, "fmi2EnterContinuousTimeMode"); }

fmi2Status fmi2CompletedIntegratorStep(fmi2Component c, fmi2Boolean noSetFMUStatePriorToCurrentPoint,
                                       fmi2Boolean *enterEventMode, fmi2Boolean *terminateSimulation) {
    (void)noSetFMUStatePriorToCurrentPoint; (void)enterEventMode; (void)terminateSimulation;
    return unsupported(c, "fmi2CompletedIntegratorStep");
}

fmi2Status fmi2SetTime(fmi2Component c, fmi2Real time) { (void)time; return unsupported(c, "fmi2SetTime"); }

fmi2Status fmi2SetContinuousStates(fmi2Component c, const fmi2Real x[], size_t nx) {
    (void)x; (void)nx;
    return unsupported(c, "fmi2SetContinuousStates");
}

fmi2Status fmi2GetDerivatives(fmi2Component c, fmi2Real derivatives[], size_t nx) {
    (void)derivatives; (void)nx;
    return unsupported(c, "fmi2GetDerivatives");
}

fmi2Status fmi2GetEventIndicators(fmi2Component c, fmi2Real eventIndicators[], size_t ni) {
    (void)eventIndicators; (void)ni;
    return unsupported(c, "fmi2GetEventIndicators");
}

fmi2Status fmi2GetContinuousStates(fmi2Component c, fmi2Real x[], size_t nx) {
    (void)x; (void)nx;
    return unsupported(c, "fmi2GetContinuousStates");
}

fmi2Status fmi2GetNominalsOfContinuousStates(fmi2Component c, fmi2Real x_nominal[], size_t nx) {
    (void)x_nominal; (void)nx;
    return unsupported(c, "fmi2GetNominalsOfContinuousStates");
}

/* -- co-simulation ----------------------------------------------------------------------------- */
fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                       const fmi2Integer order[], const fmi2Real value[]) {
    (void)vr; (void)nvr; (void)order; (void)value;
    return unsupported(c, "fmi2SetRealInputDerivatives");  /* canInterpolateInputs="false" */
}

fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                        const fmi2Integer order[], fmi2Real value[]) {
    (void)vr; (void)nvr; (void)order; (void)value;
    return unsupported(c, "fmi2GetRealOutputDerivatives");  /* maxOutputDerivativeOrder = 0 */
}

fmi2Status fmi2DoStep(fmi2Component c, fmi2Real currentCommunicationPoint, fmi2Real communicationStepSize,
                      fmi2Boolean noSetFMUStatePriorToCurrentPoint) {
    (void)currentCommunicationPoint; (void)communicationStepSize; (void)noSetFMUStatePriorToCurrentPoint;
    update((Gain *)c);
    return fmi2OK;
}

fmi2Status fmi2CancelStep(fmi2Component c) { (void)c; return fmi2OK; }  /* fmi2DoStep never runs asynchronously */

fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind s, fmi2Status *value) {
    (void)s; (void)value;
    return unsupported(c, "fmi2GetStatus");
}

fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind s, fmi2Real *value) {
    (void)s; (void)value;
    return unsupported(c, "fmi2GetRealStatus");
}

fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind s, fmi2Integer *value) {
    (void)s; (void)value;
    return unsupported(c, "fmi2GetIntegerStatus");
}

fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind s, fmi2Boolean *value) {
    (void)s; (void)value;
    return unsupported(c, "fmi2GetBooleanStatus");
}

fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind s, fmi2String *value) {
    (void)s; (void)value;
    return unsupported(c, "fmi2GetStringStatus");
}
