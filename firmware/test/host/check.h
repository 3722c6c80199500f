/* Minimal test harness: CHECK(cond, fmt, ...) counts; tests end with the line "N passed, N failed". */
#ifndef CHECK_H
#define CHECK_H
#include <stdio.h>

static int check_pass, check_fail; /* per test program */

#define CHECK(cond, ...)                                                    \
    do {                                                                    \
        if (cond) {                                                         \
            check_pass++;                                                   \
        } else {                                                            \
            check_fail++;                                                   \
            fprintf(stderr, "FAIL %s:%d: %s: ", __FILE__, __LINE__, #cond); \
            fprintf(stderr, __VA_ARGS__);                                   \
            fprintf(stderr, "\n");                                          \
        }                                                                   \
    } while (0)

static inline int check_summary(const char *name)
{
    printf("%s: %d passed, %d failed\n", name, check_pass, check_fail);
    return check_fail ? 1 : 0;
}
#endif
