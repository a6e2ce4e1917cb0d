// SPDX-License-Identifier: MIT
/**
 * @file hs_run_metrics.h
 * @brief Metrics of run folders read back (issue 22 item 1: what `xrsc metrics` and `xrsc
 *        compare` compute, below the commands): a test frame scored against a reference frame,
 *        the eyes of a run's frame names, and one run's stereo frames (EXR colour + Z per eye
 *        and their cameras from views.csv) with their stereo discrepancy and temporal
 *        difference, computed as `xrsc bench` computes them (xrsc_metrics.h).
 */
#pragma once

#include "hs_run_dir.h"
#include "hs_views_csv.h"
#include "xrsc/xrsc_metrics.h"
#include "xrsc/result.h"

#include <stdbool.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** One frame of a test run and the same frame of a reference run, as read. */
typedef struct hs_frame_pair {
    float *test, *ref; /**< RGBA, w x h each */
    uint32_t w, h;
} hs_frame_pair;

/**
 * Reads both frames (hs_read_frame: PFM, EXR or PNG); they must have the same size. On error
 * fills diag (the unreadable file, or both sizes) and leaves *out empty.
 */
xrsc_result hs_frame_pair_read(const char *ref_path, const char *test_path, hs_frame_pair *out,
                               xrsc_diag *diag);
void hs_frame_pair_free(hs_frame_pair *p);

/** A test frame's scores against its reference. */
typedef struct hs_pair_scores {
    xrsc_error_metrics err; /**< relMSE, RMSE, MSE (xrsc_metrics_error) */
    double psnr_db;         /**< 10 log10(1 / MSE): the peak is linear white; +inf if equal */
    double ssim;            /**< mean SSIM */
    xrsc_cpbd cpbd_test, cpbd_ref; /**< CPBD sharpness of both, when asked for; else zero */
} hs_pair_scores;

/** Scores p->test against p->ref with the options mo; with_cpbd also computes CPBD of both. */
xrsc_result hs_frame_pair_score(const hs_frame_pair *p, const xrsc_metrics_options *mo,
                                bool with_cpbd, hs_pair_scores *out);

/** Whether a file can be opened for reading. */
bool hs_file_exists(const char *path);

/** The sequences of a run to score: one per eye ("left", "right"), or one named "-". */
typedef struct hs_run_eyes {
    uint32_t count;
    hs_frame_pattern pat[2];
    const char *eye[2];
} hs_run_eyes;

/**
 * The eyes of frame names fmt (one %u) in dir from frame first: a name with "left" gets its
 * "right" partner when that eye's frame first exists in dir. False when fmt is not a pattern.
 */
bool hs_run_eyes_of(const char *fmt, const char *dir, uint32_t first, hs_run_eyes *out);

/** The left and right EXR patterns of `--stereo`: fmt (NULL: frame_%05u_left.exr) must name
 *  "left" and end .exr. False otherwise, with why in *out_why. */
bool hs_stereo_patterns(const char *fmt, hs_frame_pattern out[2], const char **out_why);

/** One stereo frame as read: both eyes' colour, depth (metres, 0 = no hit) and cameras. */
typedef struct hs_stereo_frame {
    float *rgba[2], *depth[2];
    xrsc_metrics_camera camera[2];
} hs_stereo_frame;

/**
 * Reads frame f of dir: per eye its EXR's colour and Z (pat[eye]) and its camera from views
 * (read from views_path, named in errors); a views row without a size takes the EXR's. On
 * error fills diag (no Z, no row, sizes that differ). Frees what out held before.
 */
xrsc_result hs_stereo_frame_read(const hs_frame_pattern pat[2], const char *dir,
                                 const hs_views_table *views, const char *views_path, uint32_t f,
                                 hs_stereo_frame *out, xrsc_diag *diag);
void hs_stereo_frame_free(hs_stereo_frame *f);

/** A stereo frame's values: NaN where there is none (no valid pixel, no previous frame). */
typedef struct hs_stereo_values {
    double temporal, stereo;
    uint64_t temporal_valid, stereo_valid;
} hs_stereo_values;

/**
 * stereo = xrsc_metrics_stereo_discrepancy(right, left); temporal = each eye against prev
 * reprojected into it (none without prev), both eyes' means weighted by their valid pixels.
 * The bench's arithmetic (hs_bench.c), so both agree to the last bit on the same input.
 */
xrsc_result hs_stereo_frame_measure(const hs_stereo_frame *cur, const hs_stereo_frame *prev,
                                    const xrsc_metrics_options *mo, hs_stereo_values *out);

#ifdef __cplusplus
}
#endif
