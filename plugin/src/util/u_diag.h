// SPDX-License-Identifier: MIT
/**
 * @file u_diag.h
 * @brief Internal helpers to fill an ::xrsc_diag and to log, shared by every module.
 */
#pragma once

#include "xrsc/result.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Fills diag (if not NULL) and returns code, so callers can `return u_diag_set(...)`. */
xrsc_result u_diag_set(xrsc_diag *diag, xrsc_result code, const char *file, int line,
                       const char *field, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 6, 7)))
#endif
    ;

typedef enum u_log_level { U_LOG_DEBUG, U_LOG_INFO, U_LOG_WARN, U_LOG_ERROR } u_log_level;

/** Logs to stderr with a level prefix. XRSC_LOG=debug|info|warn|error sets the threshold
 *  (default info); XRSC_LOG=quiet shows only errors. */
void u_log(u_log_level level, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

#define U_LOG_D(...) u_log(U_LOG_DEBUG, __VA_ARGS__)
#define U_LOG_I(...) u_log(U_LOG_INFO, __VA_ARGS__)
#define U_LOG_W(...) u_log(U_LOG_WARN, __VA_ARGS__)
#define U_LOG_E(...) u_log(U_LOG_ERROR, __VA_ARGS__)

#ifdef __cplusplus
}
#endif
