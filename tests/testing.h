// SPDX-License-Identifier: MIT
/**
 * @file testing.h
 * @brief A tiny test harness: CHECK macros that count failures, and paths to fixtures.
 *
 * Each test program runs its cases, prints "N passed, N failed" and exits non-zero on any
 * failure. XRSC_SOURCE_DIR and XRSC_SHARED_DIR are compile definitions.
 */
#pragma once

#include <math.h>
#include <stddef.h>
#include <stdio.h>

typedef struct t_state {
    int checks, failures;
    int cases_passed, cases_failed;
    int case_failures_at_start;
} t_state;

extern t_state t_g;

#define CHECK(cond)                                                                                \
    do {                                                                                           \
        t_g.checks++;                                                                              \
        if (!(cond)) {                                                                             \
            t_g.failures++;                                                                        \
            fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #cond);               \
        }                                                                                          \
    } while (0)

#define CHECK_MSG(cond, ...)                                                                       \
    do {                                                                                           \
        t_g.checks++;                                                                              \
        if (!(cond)) {                                                                             \
            t_g.failures++;                                                                        \
            fprintf(stderr, "%s:%d: CHECK failed: %s: ", __FILE__, __LINE__, #cond);               \
            fprintf(stderr, __VA_ARGS__);                                                          \
            fputc('\n', stderr);                                                                   \
        }                                                                                          \
    } while (0)

#define CHECK_NEAR(a, b, tol)                                                                      \
    CHECK_MSG(fabs((double)(a) - (double)(b)) <= (double)(tol), "%s = %.9g, %s = %.9g, tol %.3g",  \
              #a, (double)(a), #b, (double)(b), (double)(tol))

#define CHECK_EQ_INT(a, b)                                                                         \
    CHECK_MSG((long long)(a) == (long long)(b), "%s = %lld, %s = %lld", #a, (long long)(a), #b,    \
              (long long)(b))

/** Runs one case: RUN(fn) calls fn() and records whether it added failures. The environment
 *  can pick cases by name: T_CASES=a,b runs only those, T_SKIP_CASES=a,b all others. */
#define RUN(fn) t_run(#fn, fn)
void t_run(const char *name, void (*fn)(void));
/** Prints the summary line and returns the process exit code. */
int t_finish(void);

/** Joins XRSC_SOURCE_DIR or XRSC_SHARED_DIR with a relative path into a static buffer. */
const char *t_source_path(const char *rel);
const char *t_shared_path(const char *rel);
/** "data:application/octet-stream;base64,..." (RFC 4648 base64) of n bytes, for glTF buffers
 *  written by tests; malloc'ed, caller frees; NULL when out of memory. */
char *t_data_uri(const void *data, size_t n);
/** Writes text to a fresh temporary file and returns its path (static buffer, per call). */
const char *t_temp_file(const char *name, const char *contents);
/** Reads a whole file into a malloc'd buffer (free it); NULL and *out_size 0 unless all of it
 *  was read. */
void *t_read_file(const char *path, size_t *out_size);
