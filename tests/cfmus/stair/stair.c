/* Stair: a counter that ends the simulation itself, FMI 2.0 co-simulation in plain C (openEMSS tests).
 *
 *   counter = number of whole seconds since the start; when it reaches stop_count, the step that reached it
 *   returns fmi2Discard with fmi2Terminated true (the FMU asks to end: FMI 2.0, section 4.2.3) and
 *   fmi2LastSuccessfulTime the end of that step.
 *
 * Written for tests/test_fmu_ends_the_run.py (after the behaviour of the Modelica Reference FMUs' Stair,
 * not its code). Build: gcc -shared -fPIC -I<fmpy>/c-code stair.c -o binaries/linux64/Stair.so
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2Functions.h"

#define STAIR_GUID "{3c1d7f52-6a0e-4b8e-9f4e-5b7e2d1c0a91}"

enum { VR_COUNTER = 0, VR_STOP_COUNT = 1, VR_Y = 2 };

typedef struct {
    fmi2Integer counter, stop_count;
    fmi2Real time, start;
    fmi2Boolean terminated;
    fmi2CallbackLogger logger;
    fmi2ComponentEnvironment env;
    char *name;
} Stair;

static fmi2Status say(Stair *s, fmi2Status status, const char *category, const char *message) {
    if (s && s->logger) s->logger(s->env, s->name, status, category, "%s", message);
    return status;
}

static fmi2Status unsupported(fmi2Component c, const char *function) {
    return say((Stair *)c, fmi2Error, "logStatusError", function);
}

const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }
const char *fmi2GetVersion(void) { return fmi2Version; }
fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean on, size_t n, const fmi2String cats[]) {
    (void)c; (void)on; (void)n; (void)cats; return fmi2OK;
}

fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                              fmi2String fmuResourceLocation, const fmi2CallbackFunctions *functions,
                              fmi2Boolean visible, fmi2Boolean loggingOn) {
    (void)fmuResourceLocation; (void)visible; (void)loggingOn;
    if (fmuType != fmi2CoSimulation || !fmuGUID || strcmp(fmuGUID, STAIR_GUID) != 0) return NULL;
    Stair *s = (Stair *)calloc(1, sizeof(Stair));
    if (!s) return NULL;
    const char *name = instanceName ? instanceName : "";
    s->name = (char *)malloc(strlen(name) + 1);
    if (!s->name) { free(s); return NULL; }
    strcpy(s->name, name);
    s->logger = functions ? functions->logger : NULL;
    s->env = functions ? functions->componentEnvironment : NULL;
    s->stop_count = 10;
    return s;
}

void fmi2FreeInstance(fmi2Component c) {
    Stair *s = (Stair *)c;
    if (!s) return;
    free(s->name);
    free(s);
}

fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean tolDefined, fmi2Real tol, fmi2Real startTime,
                               fmi2Boolean stopDefined, fmi2Real stopTime) {
    (void)tolDefined; (void)tol; (void)stopDefined; (void)stopTime;
    ((Stair *)c)->start = ((Stair *)c)->time = startTime;
    return fmi2OK;
}
fmi2Status fmi2EnterInitializationMode(fmi2Component c) { (void)c; return fmi2OK; }
fmi2Status fmi2ExitInitializationMode(fmi2Component c) { (void)c; return fmi2OK; }
fmi2Status fmi2Terminate(fmi2Component c) { (void)c; return fmi2OK; }
fmi2Status fmi2Reset(fmi2Component c) {
    Stair *s = (Stair *)c;
    s->counter = 0; s->time = s->start; s->terminated = fmi2False; s->stop_count = 10;
    return fmi2OK;
}

fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Real v[]) {
    for (size_t i = 0; i < n; i++) {
        if (vr[i] != VR_Y) return unsupported(c, "fmi2GetReal: no such Real");
        v[i] = (fmi2Real)((Stair *)c)->counter;
    }
    return fmi2OK;
}
fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Integer v[]) {
    Stair *s = (Stair *)c;
    for (size_t i = 0; i < n; i++) {
        if (vr[i] == VR_COUNTER) v[i] = s->counter;
        else if (vr[i] == VR_STOP_COUNT) v[i] = s->stop_count;
        else return unsupported(c, "fmi2GetInteger: no such Integer");
    }
    return fmi2OK;
}
fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Boolean v[]) {
    (void)vr; (void)v; return n == 0 ? fmi2OK : unsupported(c, "fmi2GetBoolean: no Boolean");
}
fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2String v[]) {
    (void)vr; (void)v; return n == 0 ? fmi2OK : unsupported(c, "fmi2GetString: no String");
}
fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Real v[]) {
    (void)vr; (void)v; return n == 0 ? fmi2OK : unsupported(c, "fmi2SetReal: no settable Real");
}
fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Integer v[]) {
    for (size_t i = 0; i < n; i++) {
        if (vr[i] != VR_STOP_COUNT) return unsupported(c, "fmi2SetInteger: no such settable Integer");
        ((Stair *)c)->stop_count = v[i];
    }
    return fmi2OK;
}
fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Boolean v[]) {
    (void)vr; (void)v; return n == 0 ? fmi2OK : unsupported(c, "fmi2SetBoolean: no Boolean");
}
fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2String v[]) {
    (void)vr; (void)v; return n == 0 ? fmi2OK : unsupported(c, "fmi2SetString: no String");
}

fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *x) { (void)x; return unsupported(c, "fmi2GetFMUstate"); }
fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate x) { (void)x; return unsupported(c, "fmi2SetFMUstate"); }
fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *x) { (void)x; return unsupported(c, "fmi2FreeFMUstate"); }
fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate x, size_t *n) {
    (void)x; (void)n; return unsupported(c, "fmi2SerializedFMUstateSize");
}
fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate x, fmi2Byte b[], size_t n) {
    (void)x; (void)b; (void)n; return unsupported(c, "fmi2SerializeFMUstate");
}
fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte b[], size_t n, fmi2FMUstate *x) {
    (void)b; (void)n; (void)x; return unsupported(c, "fmi2DeSerializeFMUstate");
}
fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference a[], size_t na,
                                        const fmi2ValueReference b[], size_t nb, const fmi2Real d[], fmi2Real e[]) {
    (void)a; (void)na; (void)b; (void)nb; (void)d; (void)e; return unsupported(c, "fmi2GetDirectionalDerivative");
}
fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                                       const fmi2Integer o[], const fmi2Real v[]) {
    (void)vr; (void)n; (void)o; (void)v; return unsupported(c, "fmi2SetRealInputDerivatives");
}
fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                                        const fmi2Integer o[], fmi2Real v[]) {
    (void)vr; (void)n; (void)o; (void)v; return unsupported(c, "fmi2GetRealOutputDerivatives");
}

fmi2Status fmi2DoStep(fmi2Component c, fmi2Real t, fmi2Real h, fmi2Boolean noSetPrior) {
    Stair *s = (Stair *)c;
    (void)noSetPrior;
    if (s->terminated) return say(s, fmi2Error, "logStatusError", "fmi2DoStep after the FMU ended the simulation");
    s->time = t + h;
    s->counter = (fmi2Integer)floor(s->time - s->start + 1e-9);
    if (s->counter >= s->stop_count) {
        s->terminated = fmi2True;
        say(s, fmi2Discard, "logStatusDiscard", "counter reached stop_count: the simulation is over");
        return fmi2Discard;
    }
    return fmi2OK;
}
fmi2Status fmi2CancelStep(fmi2Component c) { (void)c; return fmi2OK; }

fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind k, fmi2Status *v) {
    (void)k; (void)v; return unsupported(c, "fmi2GetStatus");
}
fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind k, fmi2Real *v) {
    if (k != fmi2LastSuccessfulTime) return unsupported(c, "fmi2GetRealStatus");
    *v = ((Stair *)c)->time;
    return fmi2OK;
}
fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind k, fmi2Integer *v) {
    (void)k; (void)v; return unsupported(c, "fmi2GetIntegerStatus");
}
fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind k, fmi2Boolean *v) {
    if (k != fmi2Terminated) return unsupported(c, "fmi2GetBooleanStatus");
    *v = ((Stair *)c)->terminated;
    return fmi2OK;
}
fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind k, fmi2String *v) {
    (void)k; (void)v; return unsupported(c, "fmi2GetStringStatus");
}

/* model exchange: not supported (co-simulation only) */
fmi2Status fmi2EnterEventMode(fmi2Component c) { return unsupported(c, "fmi2EnterEventMode"); }
fmi2Status fmi2NewDiscreteStates(fmi2Component c, fmi2EventInfo *i) { (void)i; return unsupported(c, "fmi2NewDiscreteStates"); }
fmi2Status fmi2EnterContinuousTimeMode(fmi2Component c) { return unsupported(c, "fmi2EnterContinuousTimeMode"); }
fmi2Status fmi2CompletedIntegratorStep(fmi2Component c, fmi2Boolean a, fmi2Boolean *b, fmi2Boolean *d) {
    (void)a; (void)b; (void)d; return unsupported(c, "fmi2CompletedIntegratorStep");
}
fmi2Status fmi2SetTime(fmi2Component c, fmi2Real t) { (void)t; return unsupported(c, "fmi2SetTime"); }
fmi2Status fmi2SetContinuousStates(fmi2Component c, const fmi2Real x[], size_t n) {
    (void)x; (void)n; return unsupported(c, "fmi2SetContinuousStates");
}
fmi2Status fmi2GetDerivatives(fmi2Component c, fmi2Real d[], size_t n) { (void)d; (void)n; return unsupported(c, "fmi2GetDerivatives"); }
fmi2Status fmi2GetEventIndicators(fmi2Component c, fmi2Real e[], size_t n) {
    (void)e; (void)n; return unsupported(c, "fmi2GetEventIndicators");
}
fmi2Status fmi2GetContinuousStates(fmi2Component c, fmi2Real x[], size_t n) {
    (void)x; (void)n; return unsupported(c, "fmi2GetContinuousStates");
}
fmi2Status fmi2GetNominalsOfContinuousStates(fmi2Component c, fmi2Real x[], size_t n) {
    (void)x; (void)n; return unsupported(c, "fmi2GetNominalsOfContinuousStates");
}
