// SPDX-License-Identifier: MIT
/**
 * @file hs_run_dir.h
 * @brief Reading the frames of a run folder (what `xrsc replay` writes) for `xrsc metrics` and
 *        `xrsc compare`: file-name patterns with one frame number, the first frame present,
 *        linear PFM or display-referred PNG frames.
 */
#pragma once

#include "xrsc/result.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** A file-name pattern split around its one "%[0][width]u" ("%%" stands for "%"); the text is
 *  never used as a printf format. */
typedef struct hs_frame_pattern {
    char prefix[512], suffix[512];
    bool zero_pad;
    int width;
} hs_frame_pattern;

/** Parses fmt; false unless it has exactly one %u conversion (and fits). */
bool hs_frame_pattern_parse(const char *fmt, hs_frame_pattern *out);
/** dir/prefix NUMBER suffix into out; false if it does not fit. */
bool hs_frame_pattern_path(const char *dir, const hs_frame_pattern *pat, uint32_t frame, char *out,
                           size_t size);
/** The smallest frame number of a file in dir that matches the pattern; false if none does. */
bool hs_frame_pattern_first(const char *dir, const hs_frame_pattern *pat, uint32_t *out_first);

/** What a run folder holds: linear PFM or EXR frames, only display-referred PNGs, or none. */
typedef enum hs_run_kind {
    HS_RUN_NONE,
    HS_RUN_LINEAR, /**< frame_NNNNN_{left,right}.pfm (`--write linear`) */
    HS_RUN_EXR,    /**< frame_NNNNN_{left,right}.exr (`--write exr`), linear */
    HS_RUN_PNG,    /**< frame_NNNNN_{left,right}.png only (tone-mapped, 8 bit) */
} hs_run_kind;

/** The kind of run in dir (PFM, then EXR, then PNG when several are there). */
hs_run_kind hs_run_kind_of(const char *dir);
/**
 * The kind two runs are compared in: LINEAR when both hold PFM frames, else EXR when both hold
 * EXR frames, else PNG when both hold PNG frames (display-referred: the caller warns), else
 * NONE with diag naming the folder that lacks frames.
 */
hs_run_kind hs_run_common_kind(const char *a, const char *b, xrsc_diag *diag);
/** The frame-name pattern of one eye (0 left, 1 right) of a run kind (not NONE). */
const char *hs_run_pattern(hs_run_kind kind, int eye);

/**
 * Reads a frame into w*h RGBA floats (rows top to bottom, alpha 1; *out_rgba malloc'ed): a
 * .pfm or .exr as stored (linear), a .png decoded from sRGB to linear display values (its tone
 * mapping is not undone: *out_tonemapped is set, when given, so callers can warn).
 */
xrsc_result hs_read_frame(const char *path, float **out_rgba, uint32_t *out_w, uint32_t *out_h,
                          bool *out_tonemapped, xrsc_diag *diag);

#ifdef __cplusplus
}
#endif
