// SPDX-License-Identifier: MIT
/**
 * @file hsrt_preview_view.h
 * @brief The preview window's picture (internal to the runtime): the views (side by side, one
 *        eye, the depth-compensated stereo difference, the error against a reference) and the
 *        text overlay, composed on the CPU into the buffer that is copied to the swapchain.
 */
#pragma once

#include "hsrt.h"

/** The views, in the order V cycles through them. */
typedef enum hsrt_view {
    HSRT_VIEW_SBS,         /**< both eyes side by side (S swaps them) */
    HSRT_VIEW_LEFT,        /**< the left eye alone */
    HSRT_VIEW_RIGHT,       /**< the right eye alone */
    HSRT_VIEW_STEREO_DIFF, /**< left vs the right eye reprojected into it by depth */
    HSRT_VIEW_REF_ERROR,   /**< each eye's per-pixel error against the reference folder */
    HSRT_VIEW_COUNT
} hsrt_view;

/** Full scale of the stereo-difference heat map: RMS over R, G, B of linear radiance. */
#define HSRT_PREVIEW_STEREO_SCALE 0.25
/** Full scale of the reference-error heat map: sqrt of the per-pixel relMSE term. */
#define HSRT_PREVIEW_REF_SCALE 1.0
/** The difference view's gain without depth: |left - right| of the display values, times this. */
#define HSRT_PREVIEW_DIFF_GAIN 4
/** Passes the overlay lists at most. */
#define HSRT_PREVIEW_MAX_PASSES 16

/** The run's settings, from the information channel's "run" line. */
typedef struct hsrt_preview_run_info {
    bool has;
    char method[32], blend[32];
    double r;
} hsrt_preview_run_info;

/** One frame's timings, from a "frame" line. */
typedef struct hsrt_preview_frame_info {
    bool has;
    double ms;
    uint32_t pass_count;
    char pass_name[HSRT_PREVIEW_MAX_PASSES][24];
    double pass_ms[HSRT_PREVIEW_MAX_PASSES];
} hsrt_preview_frame_info;

/** The last stereo difference computed, so that redraws of a frame (a key, its timings
 *  arriving) do not recompute it; owned by the window, freed with hsrt_view_cache_free. */
typedef struct hsrt_view_cache {
    bool valid;
    uint64_t frame;
    uint32_t w, h;
    bool depth; /**< the frame had depth (else nothing is cached but that) */
    float *rms; /**< w*h, hsrt_view_stereo_diff's */
    double mean, compared;
} hsrt_view_cache;
void hsrt_view_cache_free(hsrt_view_cache *c);

/** What to draw besides the frame itself. */
typedef struct hsrt_view_state {
    hsrt_view view;
    bool swapped, overlay;
    const char *state; /**< "running", "paused", "exiting", "ended" */
    uint32_t back;     /**< frames behind the latest (stepping back) */
    const hsrt_preview_run_info *run;
    const hsrt_preview_frame_info *info; /**< this frame's; has = false until it arrives */
    bool has_reference;                  /**< a reference folder is configured */
    const hsrt_eye_image *reference;     /**< this frame's reference eyes (rgba), NULL if none */
    hsrt_view_cache *cache;              /**< NULL: compute every time */
} hsrt_view_state;

/**
 * Composes frame f (NULL: none yet) as the state says into a w x h 4-byte image (`bgra`
 * orders the bytes B,G,R,A, else R,G,B,A). False when out of memory.
 */
bool hsrt_view_compose(const hsrt_preview_frame *f, const hsrt_view_state *vs, uint8_t *out,
                       uint32_t w, uint32_t h, bool bgra);

/** The view's name for the window title ("left|right", "difference x4", ...). */
const char *hsrt_view_name(const hsrt_preview_frame *f, const hsrt_view_state *vs);

/**
 * The stereo difference of a frame with depth: per left-eye pixel the RMS over R, G, B of
 * left - right reprojected into it (xrsc_metrics_stereo_discrepancy; background pixels at
 * infinity, i.e. by direction), or a negative value where the right eye has no comparable
 * pixel (outside its view, occluded there). out_rms holds w*h floats of the left eye; returns
 * false without depth or memory. out_mean/out_valid: mean RMS and fraction of pixels compared.
 */
bool hsrt_view_stereo_diff(const hsrt_preview_frame *f, float *out_rms, double *out_mean,
                           double *out_valid);
