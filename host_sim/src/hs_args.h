// SPDX-License-Identifier: MIT
/**
 * @file hs_args.h
 * @brief Command-line helpers shared by `xrsc`, `xrsc metrics` and `xrsc bench`: whole-string
 *        number parsing, option-list lookup, the one format of a bad-argument error, and the
 *        creation of output folders.
 */
#pragma once

#include "xrsc/result.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** The exit code of a bad command line. */
#define HS_EXIT_BAD_ARGS 2

/**
 * Prints "CMD: error: FLAG[ VALUE]: WHY (see CMD --help)" to stderr (value may be NULL) and
 * returns HS_EXIT_BAD_ARGS. cmd is the command as typed, e.g. "xrsc" or "xrsc bench".
 */
int hs_bad_arg(const char *cmd, const char *flag, const char *value, const char *why);

/** A decimal unsigned 32-bit integer, the whole of s (no sign); *out is set only on success. */
bool hs_parse_u32(const char *s, uint32_t *out);

/** A number (strtod), the whole of s, not NaN; infinities pass (callers bound the value). *out
 *  is set only on success. */
bool hs_parse_f(const char *s, double *out);

/** Whether flag is one of the count options in list. */
bool hs_arg_in(const char *flag, const char *const *list, size_t count);

/**
 * mkdir -p path (folders that exist already are fine). Errors name `field` (the option that gave
 * the path, e.g. "--out") in diag: XRSC_ERROR_INVALID_ARGUMENT for an empty path or one of 1024
 * bytes or more, XRSC_ERROR_IO (diag.file: the folder) for a folder that cannot be created.
 */
xrsc_result hs_make_dirs(const char *path, const char *field, xrsc_diag *diag);

#ifdef __cplusplus
}
#endif
