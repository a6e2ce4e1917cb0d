// SPDX-License-Identifier: MIT
/**
 * @file hs_views.h
 * @brief What a replay writes so its frames can be scored from files (`xrsc metrics --stereo`):
 *        views.csv (each frame's eye poses, FOVs and sizes, hs_views_csv.h) and, with
 *        `--write exr`, the depth at pixel centres that the EXRs carry as Z.
 *
 * Both replay paths call it with the views each frame was rendered with (the direct path's
 * xrsc_frame, the OpenXR path's located views) and the frame's file number. The depth is that
 * of a `primary` renderer (one ray through each pixel centre), the depth `xrsc bench`
 * reprojects by, rather than the method's own first hit, which is jittered within the pixel
 * for most methods: so the temporal difference and stereo discrepancy computed from the files
 * equal the bench's for the same frames.
 */
#pragma once

#include "hs_replay.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct hs_views hs_views;

/**
 * Opens OUT/views.csv (under a temporary name, hs_file.h) when opt->out_dir is set and, with
 * opt->write_exr, a `primary` renderer of w x h per eye on ctx and scene. *out is NULL when
 * there is nothing to write.
 */
xrsc_result hs_views_open(const hs_replay_options *opt, xrsc_context *ctx, xrsc_scene *scene,
                          uint32_t w, uint32_t h, hs_views **out, xrsc_diag *diag);

/** Writes frame `number`'s two rows and renders its depth (accepts v == NULL). */
xrsc_result hs_views_frame(hs_views *v, const xrsc_frame *frame, uint32_t number, xrsc_diag *diag);

/** The renderer whose XRSC_OUTPUT_DEPTH the EXRs carry (after hs_views_frame), or NULL. */
xrsc_renderer *hs_views_depth(hs_views *v);

/**
 * Closes views.csv (renamed into place with keep and when every write succeeded; its rows so
 * far are whole, so a failed run keeps them too when keep is true), frees everything and sets
 * *v to NULL. Accepts NULL.
 */
xrsc_result hs_views_close(hs_views **v, bool keep, xrsc_diag *diag);

#ifdef __cplusplus
}
#endif
