/*
 * The FMI 2.0 logger callback is a C variadic function (printf-style), which
 * stable Rust cannot define. This shim implements it: it formats the message
 * with vsnprintf and forwards the finished string to a Rust function whose
 * pointer is the first field of the component environment the master passes
 * to fmi2Instantiate (struct fmi_master_log_env below). No global state.
 *
 * It also provides the memory callbacks (calloc/free) that FMI 2.0 requires
 * the host to supply.
 */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>

typedef void (*fmi_master_sink)(void *env, const char *instance, int status, const char *category,
                                const char *message);

/* Layout shared with `LogEnv` in src/import/ffi.rs (#[repr(C)], sink first). */
struct fmi_master_log_env {
    fmi_master_sink sink;
};

void fmi_master_logger(void *env, const char *instance, int status, const char *category, const char *message,
                       ...) {
    struct fmi_master_log_env *e = (struct fmi_master_log_env *)env;
    char small[1024];
    va_list ap;
    int n;

    if (message == NULL) {
        message = "(null message)";
    }
    va_start(ap, message);
    n = vsnprintf(small, sizeof small, message, ap);
    va_end(ap);
    if (n < 0) {
        /* Bad format: pass the unformatted text on rather than nothing. */
        if (e != NULL && e->sink != NULL) {
            e->sink(env, instance, status, category, message);
        }
        return;
    }
    if ((size_t)n < sizeof small) {
        if (e != NULL && e->sink != NULL) {
            e->sink(env, instance, status, category, small);
        } else {
            fprintf(stderr, "[%s] %s\n", instance ? instance : "?", small);
        }
        return;
    }
    {
        char *big = (char *)malloc((size_t)n + 1);
        const char *text = small; /* truncated fallback if malloc fails */
        if (big != NULL) {
            va_start(ap, message);
            vsnprintf(big, (size_t)n + 1, message, ap);
            va_end(ap);
            text = big;
        }
        if (e != NULL && e->sink != NULL) {
            e->sink(env, instance, status, category, text);
        } else {
            fprintf(stderr, "[%s] %s\n", instance ? instance : "?", text);
        }
        free(big);
    }
}

void *fmi_master_calloc(size_t nobj, size_t size) { return calloc(nobj, size); }

void fmi_master_free(void *obj) { free(obj); }
