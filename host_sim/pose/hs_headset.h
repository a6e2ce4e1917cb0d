// SPDX-License-Identifier: MIT
/**
 * @file hs_headset.h
 * @brief Headset profiles as data: host_sim/headsets.txt (embedded at build time, or a file
 *        given with `--headsets`) parsed into simulated headsets for `xrsc --headset NAME`.
 *
 * The file's format is documented at its top. A profile gives per-eye resolution, the display
 * refresh rate (and the rates the headset offers), IPD and per-eye asymmetric FOVs in OpenXR's
 * XrFovf convention.
 */
#pragma once

#include "xrsc/result.h"
#include "xrsc/xrsc_math.h"

#include <stdint.h>
#include <stdio.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Most refresh rates one profile lists (refresh_modes_hz). */
#define HS_HEADSET_MAX_MODES 8

typedef struct hs_headset_profile {
    char name[32]; /**< [name]: lower-case letters, digits, '-' */
    char title[96];
    char source[384];     /**< where the numbers come from */
    xrsc_headset headset; /**< ipd_m, fov (radians), width_px/height_px, refresh_hz */
    float refresh_modes_hz[HS_HEADSET_MAX_MODES];
    uint32_t refresh_mode_count; /**< at least 1 (refresh_hz when the file lists none) */
} hs_headset_profile;

typedef struct hs_headset_table {
    hs_headset_profile *items; /**< malloc'ed; hs_headsets_free */
    uint32_t count;
} hs_headset_table;

/**
 * Parses profiles from text (origin names it in errors: a path, or "headsets.txt (built in)").
 * Errors name origin, line and field: XRSC_ERROR_UNKNOWN_COLUMN for an unknown key or a line
 * that is neither a section nor "key = value", XRSC_ERROR_BAD_NUMBER for a value out of its
 * range or not a number, XRSC_ERROR_INVALID_ARGUMENT for a bad or repeated name, a key outside
 * a profile, a repeated key or a missing required key, XRSC_ERROR_EMPTY_FILE when no profile
 * is defined. On error *out is empty.
 */
xrsc_result hs_headsets_parse(const char *text, const char *origin, hs_headset_table *out,
                              xrsc_diag *diag);

/** The built-in profiles' text (host_sim/headsets.txt as of the build), NUL-terminated. */
const char *hs_headsets_builtin_text(void);

/** Loads path (NULL: the built-in text) with hs_headsets_parse. */
xrsc_result hs_headsets_load(const char *path, hs_headset_table *out, xrsc_diag *diag);

/** Frees the table's profiles and leaves it empty; accepts an empty table. */
void hs_headsets_free(hs_headset_table *t);

/** The profile called name, or NULL. */
const hs_headset_profile *hs_headsets_find(const hs_headset_table *t, const char *name);

/**
 * The profile called name; otherwise XRSC_ERROR_INVALID_ARGUMENT (field "--headset") with a
 * message listing the known names.
 */
xrsc_result hs_headsets_select(const hs_headset_table *t, const char *name,
                               const hs_headset_profile **out, xrsc_diag *diag);

/** Prints one line per profile (name, title, resolution, refresh, IPD, FOVs) and its source. */
void hs_headsets_print(const hs_headset_table *t, FILE *f);

#ifdef __cplusplus
}
#endif
