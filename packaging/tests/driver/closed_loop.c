/* A minimal FMI 2.0 co-simulation master in C, built for Linux (gcc, dlopen) and for
 * Windows (mingw-w64, LoadLibrary) by packaging/tests/platforms.rs: it runs the closed loop
 * plant.x -> controller.y, controller.u -> plant.u (Gauss-Seidel, controller first, as
 * ClosedLoop.ssd) for STEPS steps of H seconds and prints the bits of x and u every 1000 steps,
 * then an FMU state round trip (get + serialize at STEPS/2, deserialize + set, run again) and a
 * hash of the serialized states. The test compares the output of the two builds byte for byte.
 *
 * usage: closed_loop PLANT_LIB PLANT_GUID CTRL_LIB CTRL_GUID VR_X VR_U_PLANT VR_Y VR_U_CTRL STEPS H
 */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "fmi2Functions.h"

#ifdef _WIN32
#include <windows.h>
typedef HMODULE lib_t;
static lib_t open_lib(const char *p) { return LoadLibraryA(p); }
static void *sym(lib_t l, const char *n) { return (void *)GetProcAddress(l, n); }
#else
#include <dlfcn.h>
typedef void *lib_t;
static lib_t open_lib(const char *p) { return dlopen(p, RTLD_NOW | RTLD_LOCAL); }
static void *sym(lib_t l, const char *n) { return dlsym(l, n); }
#endif

typedef struct {
    fmi2InstantiateTYPE *instantiate;
    fmi2SetupExperimentTYPE *setup;
    fmi2EnterInitializationModeTYPE *enter_init;
    fmi2ExitInitializationModeTYPE *exit_init;
    fmi2GetRealTYPE *get_real;
    fmi2SetRealTYPE *set_real;
    fmi2DoStepTYPE *do_step;
    fmi2GetFMUstateTYPE *get_state;
    fmi2SetFMUstateTYPE *set_state;
    fmi2FreeFMUstateTYPE *free_state;
    fmi2SerializedFMUstateSizeTYPE *state_size;
    fmi2SerializeFMUstateTYPE *serialize;
    fmi2DeSerializeFMUstateTYPE *deserialize;
    fmi2TerminateTYPE *terminate;
    fmi2FreeInstanceTYPE *free_instance;
    fmi2Component c;
} fmu_t;

static void fail(const char *what) {
    fprintf(stderr, "closed_loop: %s\n", what);
    exit(1);
}

static void logger(fmi2ComponentEnvironment env, fmi2String name, fmi2Status status, fmi2String category,
                   fmi2String message, ...) {
    va_list ap;
    (void)env;
    fprintf(stderr, "[%s %d %s] ", name, (int)status, category);
    va_start(ap, message);
    vfprintf(stderr, message, ap);
    va_end(ap);
    fprintf(stderr, "\n");
}

static const fmi2CallbackFunctions callbacks = {logger, calloc, free, NULL, NULL};

#define LOAD(f, field, name)                                                  \
    do {                                                                      \
        (f)->field = sym(lib, name);                                          \
        if (!(f)->field) fail("missing symbol " name);                        \
    } while (0)

static void load(fmu_t *f, const char *path, const char *name, const char *guid) {
    lib_t lib = open_lib(path);
    if (!lib) fail("cannot load the library");
    LOAD(f, instantiate, "fmi2Instantiate");
    LOAD(f, setup, "fmi2SetupExperiment");
    LOAD(f, enter_init, "fmi2EnterInitializationMode");
    LOAD(f, exit_init, "fmi2ExitInitializationMode");
    LOAD(f, get_real, "fmi2GetReal");
    LOAD(f, set_real, "fmi2SetReal");
    LOAD(f, do_step, "fmi2DoStep");
    LOAD(f, get_state, "fmi2GetFMUstate");
    LOAD(f, set_state, "fmi2SetFMUstate");
    LOAD(f, free_state, "fmi2FreeFMUstate");
    LOAD(f, state_size, "fmi2SerializedFMUstateSize");
    LOAD(f, serialize, "fmi2SerializeFMUstate");
    LOAD(f, deserialize, "fmi2DeSerializeFMUstate");
    LOAD(f, terminate, "fmi2Terminate");
    LOAD(f, free_instance, "fmi2FreeInstance");
    f->c = f->instantiate(name, fmi2CoSimulation, guid, "file:///nonexistent/resources", &callbacks, fmi2False,
                          fmi2False);
    if (!f->c) fail("fmi2Instantiate returned NULL");
    if (f->setup(f->c, fmi2False, 0.0, 0.0, fmi2False, 0.0) != fmi2OK) fail("fmi2SetupExperiment");
    if (f->enter_init(f->c) != fmi2OK) fail("fmi2EnterInitializationMode");
    if (f->exit_init(f->c) != fmi2OK) fail("fmi2ExitInitializationMode");
}

static unsigned long long bits(double x) {
    unsigned long long b;
    memcpy(&b, &x, sizeof b);
    return b;
}

/* FNV-1a over bytes. */
static unsigned long long fnv(const char *p, size_t n, unsigned long long h) {
    size_t i;
    for (i = 0; i < n; i++) {
        h ^= (unsigned char)p[i];
        h *= 1099511628211ULL;
    }
    return h;
}

static fmu_t plant, ctrl;
static fmi2ValueReference vr_x, vr_up, vr_y, vr_uc;

/* One communication step at t: controller then plant (Gauss-Seidel). Returns x and u. */
static void step(double t, double h, double *x, double *u) {
    if (plant.get_real(plant.c, &vr_x, 1, x) != fmi2OK) fail("get x");
    if (ctrl.set_real(ctrl.c, &vr_y, 1, x) != fmi2OK) fail("set y");
    if (ctrl.do_step(ctrl.c, t, h, fmi2True) != fmi2OK) fail("controller step");
    if (ctrl.get_real(ctrl.c, &vr_uc, 1, u) != fmi2OK) fail("get u");
    if (plant.set_real(plant.c, &vr_up, 1, u) != fmi2OK) fail("set u");
    if (plant.do_step(plant.c, t, h, fmi2True) != fmi2OK) fail("plant step");
}

static unsigned long long serialized_hash(fmu_t *f, fmi2FMUstate s, char **bytes, size_t *n) {
    if (f->state_size(f->c, s, n) != fmi2OK) fail("state size");
    *bytes = malloc(*n);
    if (f->serialize(f->c, s, *bytes, *n) != fmi2OK) fail("serialize");
    return fnv(*bytes, *n, 1469598103934665603ULL);
}

int main(int argc, char **argv) {
    long steps, k;
    double h, x = 0, u = 0, x_end, u_end;
    fmi2FMUstate sp = NULL, sc = NULL, rp = NULL, rc = NULL;
    char *bp, *bc;
    size_t np, nc;
    unsigned long long hp, hc;
    if (argc != 11) fail("usage: PLANT_LIB PLANT_GUID CTRL_LIB CTRL_GUID VR_X VR_U_PLANT VR_Y VR_U_CTRL STEPS H");
    vr_x = (fmi2ValueReference)strtoul(argv[5], NULL, 10);
    vr_up = (fmi2ValueReference)strtoul(argv[6], NULL, 10);
    vr_y = (fmi2ValueReference)strtoul(argv[7], NULL, 10);
    vr_uc = (fmi2ValueReference)strtoul(argv[8], NULL, 10);
    steps = strtol(argv[9], NULL, 10);
    h = strtod(argv[10], NULL);
    load(&plant, argv[1], "plant", argv[2]);
    load(&ctrl, argv[3], "controller", argv[4]);
    for (k = 0; k < steps; k++) {
        if (k == steps / 2) {
            if (plant.get_state(plant.c, &sp) != fmi2OK || ctrl.get_state(ctrl.c, &sc) != fmi2OK) fail("get state");
        }
        step(k * h, h, &x, &u);
        if (k % 1000 == 999) printf("%ld %016llx %016llx\n", k + 1, bits(x), bits(u));
    }
    x_end = x;
    u_end = u;
    hp = serialized_hash(&plant, sp, &bp, &np);
    hc = serialized_hash(&ctrl, sc, &bc, &nc);
    printf("state bytes %lu %lu hash %016llx %016llx\n", (unsigned long)np, (unsigned long)nc, hp, hc);
    if (plant.deserialize(plant.c, bp, np, &rp) != fmi2OK) fail("deserialize plant");
    if (ctrl.deserialize(ctrl.c, bc, nc, &rc) != fmi2OK) fail("deserialize controller");
    if (plant.set_state(plant.c, rp) != fmi2OK || ctrl.set_state(ctrl.c, rc) != fmi2OK) fail("set state");
    for (k = steps / 2; k < steps; k++) step(k * h, h, &x, &u);
    printf("round trip %s %016llx %016llx\n", (bits(x) == bits(x_end) && bits(u) == bits(u_end)) ? "identical" : "DIFFERENT",
           bits(x), bits(u));
    plant.free_state(plant.c, &sp);
    plant.free_state(plant.c, &rp);
    ctrl.free_state(ctrl.c, &sc);
    ctrl.free_state(ctrl.c, &rc);
    free(bp);
    free(bc);
    plant.terminate(plant.c);
    ctrl.terminate(ctrl.c);
    plant.free_instance(plant.c);
    ctrl.free_instance(ctrl.c);
    return 0;
}
