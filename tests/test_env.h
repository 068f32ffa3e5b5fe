/* What the test programs read from the environment: GRANULE_TEST_QUICK=1 (the ASan pass: smaller
 * systems, shorter runs) and GRANULE_TEST_VERBOSE=1 (print the measured numbers). */
#ifndef GR_TEST_ENV_H
#define GR_TEST_ENV_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* set, non-empty and not "0" */
static inline int env_flag(const char *name)
{
    const char *v = getenv(name);
    return v && *v && strcmp(v, "0") != 0;
}

static inline int quick(void) { return env_flag("GRANULE_TEST_QUICK"); }
static inline int verbose(void) { return env_flag("GRANULE_TEST_VERBOSE"); }

#define VERBOSE(...)                                                                               \
    do {                                                                                           \
        if (verbose()) {                                                                           \
            fprintf(stderr, __VA_ARGS__);                                                          \
        }                                                                                          \
    } while (0)

#endif
