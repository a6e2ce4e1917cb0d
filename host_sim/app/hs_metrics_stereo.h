// SPDX-License-Identifier: MIT
/**
 * @file hs_metrics_stereo.h
 * @brief `xrsc metrics --stereo DIR`: the stereo discrepancy and the temporal difference of a
 *        folder of stereo frames (EXR colour + Z per eye, and views.csv), computed as
 *        `xrsc bench` computes them (xrsc_metrics.h, me_reproject.c).
 *
 * Per frame f: stereo = xrsc_metrics_stereo_discrepancy(right, left) (the left eye reprojected
 * into the right by depth, seed 000 Fig. 15), NaN when no pixel is valid; temporal = frame f
 * against frame f-1 reprojected into it (xrsc_metrics_temporal_diff), per eye, both eyes'
 * means weighted by their valid pixels (none for the first frame read). The means are over the
 * frames from first + warmup on whose value is finite: the bench's temporal_msd and stereo_msd
 * columns and the summary's "temporal" and "stereo".
 */
#pragma once

#include "xrsc/xrsc_metrics.h"

#include <stdbool.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct hs_stereo_args {
    const char *dir;        /**< the frames */
    const char *views_path; /**< NULL: DIR/views.csv */
    const char *pattern;    /**< the left eye's EXR names; NULL: frame_%05u_left.exr */
    const char *csv_path;   /**< per-frame values as CSV, or NULL */
    uint32_t first, max_frames, warmup;
    bool first_given, quiet;
    xrsc_metrics_options mo; /**< depth_tolerance is used */
} hs_stereo_args;

/** Runs it; returns the exit code (0, 1 for unreadable or inconsistent input, 2 bad pattern). */
int hs_metrics_stereo_run(const hs_stereo_args *a);

#ifdef __cplusplus
}
#endif
