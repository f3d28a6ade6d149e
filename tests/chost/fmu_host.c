/* A minimal FMI 2.0 co-simulation host in C (issue 16 point 4): no Python of its own.
 *
 *   fmu_host FMU_DIR MODEL_IDENTIFIER GUID STEP_S N_STEPS VR [VR ...]
 *
 * loads FMU_DIR/binaries/linux64/MODEL_IDENTIFIER.so with dlopen, instantiates it (resources at
 * FMU_DIR/resources), initializes it at its start values, makes N_STEPS steps of STEP_S and prints,
 * after initialization and after every step, the time and the Real variables VR... (one line each,
 * %.17g), then terminates and frees the instance. Exit code 0 on success, 1 with one line on stderr
 * otherwise. Built against the FMI 2.0 headers that fmpy ships (fmpy/c-code).
 */
#include <dlfcn.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>
#include "fmi2Functions.h"

static void logger(fmi2ComponentEnvironment env, fmi2String name, fmi2Status status, fmi2String category,
                   fmi2String message, ...) {
    (void)env;
    fprintf(stderr, "[%s %d %s] %s\n", name ? name : "", (int)status, category ? category : "", message);
}

#define LOAD(type, name)                                                               \
    type name = (type)dlsym(lib, #name);                                               \
    if (!name) { fprintf(stderr, "fmu_host: %s not found: %s\n", #name, dlerror()); return 1; }

int main(int argc, char **argv) {
    if (argc < 7) {
        fprintf(stderr, "usage: fmu_host FMU_DIR MODEL_IDENTIFIER GUID STEP_S N_STEPS VR [VR ...]\n");
        return 1;
    }
    const char *dir = argv[1], *id = argv[2], *guid = argv[3];
    double h = atof(argv[4]);
    int n = atoi(argv[5]), nvr = argc - 6;
    fmi2ValueReference *vrs = calloc((size_t)nvr, sizeof *vrs);
    fmi2Real *vals = calloc((size_t)nvr, sizeof *vals);
    for (int i = 0; i < nvr; i++) vrs[i] = (fmi2ValueReference)strtoul(argv[6 + i], NULL, 10);
    char path[4096], resources[4096];
    snprintf(path, sizeof path, "%s/binaries/linux64/%s.so", dir, id);
    snprintf(resources, sizeof resources, "file://%s/resources", dir);
    void *lib = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (!lib) { fprintf(stderr, "fmu_host: cannot load %s: %s\n", path, dlerror()); return 1; }
    LOAD(fmi2InstantiateTYPE *, fmi2Instantiate)
    LOAD(fmi2SetupExperimentTYPE *, fmi2SetupExperiment)
    LOAD(fmi2EnterInitializationModeTYPE *, fmi2EnterInitializationMode)
    LOAD(fmi2ExitInitializationModeTYPE *, fmi2ExitInitializationMode)
    LOAD(fmi2GetRealTYPE *, fmi2GetReal)
    LOAD(fmi2DoStepTYPE *, fmi2DoStep)
    LOAD(fmi2TerminateTYPE *, fmi2Terminate)
    LOAD(fmi2FreeInstanceTYPE *, fmi2FreeInstance)
    fmi2CallbackFunctions cb = {logger, calloc, free, NULL, NULL};
    fmi2Component c = fmi2Instantiate(id, fmi2CoSimulation, guid, resources, &cb, fmi2False, fmi2True);  /* logging on: pythonfmu forwards nothing otherwise */
    if (!c) { fprintf(stderr, "fmu_host: fmi2Instantiate failed\n"); return 1; }
    if (fmi2SetupExperiment(c, fmi2False, 0.0, 0.0, fmi2False, 0.0) > fmi2Warning ||
        fmi2EnterInitializationMode(c) > fmi2Warning || fmi2ExitInitializationMode(c) > fmi2Warning) {
        fprintf(stderr, "fmu_host: initialization failed\n");
        return 1;
    }
    for (int k = 0; k <= n; k++) {
        if (k > 0 && fmi2DoStep(c, (k - 1) * h, h, fmi2True) > fmi2Warning) {
            fprintf(stderr, "fmu_host: fmi2DoStep failed at t = %g s\n", (k - 1) * h);
            return 1;
        }
        if (fmi2GetReal(c, vrs, (size_t)nvr, vals) > fmi2Warning) { fprintf(stderr, "fmu_host: fmi2GetReal failed\n"); return 1; }
        printf("%.17g", k * h);
        for (int i = 0; i < nvr; i++) printf(" %.17g", vals[i]);
        printf("\n");
    }
    if (fmi2Terminate(c) > fmi2Warning) { fprintf(stderr, "fmu_host: fmi2Terminate failed\n"); return 1; }
    fmi2FreeInstance(c);
    free(vrs);
    free(vals);
    fflush(stdout);
    fflush(stderr);
    /* Neither dlclose nor a normal exit: pythonfmu finalizes the interpreter it started from a static
     * destructor at exit, in its worker thread, where JSBSim's exit handler (the airframe) corrupts the
     * heap (glibc aborts in _dl_update_slotinfo). _exit ends the process after everything is freed. */
    _exit(0);
}
