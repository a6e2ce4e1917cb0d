// SPDX-License-Identifier: MIT
/**
 * @file st_blend.h
 * @brief The stereo blend pass (stereo_blend.comp, formulas in shaders/xs_stereo.h): each eye
 *        of a rendered stereo pair improved from the other, in place on the GPU.
 *
 * Pass "blend": copies the colour (both eyes) into the blend's own `src` image, then one
 * dispatch reads src, depth and (moments) mu_1/mu_2 of both eyes and writes the blended colour
 * back into the colour image, plus beta and a status per pixel into the `aux` image. It is
 * recorded by the method into its frame's one command buffer after reconstruction (mt_post),
 * so it is timed with the method's passes and precedes every read-back and swapchain copy.
 */
#pragma once

#include "gpu_resource.h"
#include "gpu_pipeline.h"
#include "gpu_timer.h"
#include "xrsc/xrsc.h"
#include "xrsc_shared.h"
#include "xs_stereo.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Pass name in xrsc_renderer_timings. */
#define ST_PASS_BLEND "blend"

/** Blend settings (defaults filled in by st_blend_create). */
typedef struct st_settings {
    xrsc_blend blend;
    float r;               /**< R in [0, 1] */
    float depth_tolerance; /**< 0: XS_ST_DEPTH_TOLERANCE */
    bool pixel_mean; /**< Eq. 8 of the pixel values' moments (xs_st_beta_eq8_mean) instead of
                          the per-sample moments as printed (the default) */
    /** Taps (of the other eye, and this eye's moment neighbours) must also show the pixel's
     *  instance (st_images.hitid): the depth test alone (5 %) takes the Cornell light panel,
     *  1 cm below the ceiling, for the ceiling, and the bilinear tap mixed the panel's
     *  radiance into the ceiling beside it (issue 19, bench/results/issue19-cornell/). */
    bool instance_test;
} st_settings;

/** The images a blend works on, each 2 layers (eyes), GENERAL, width x height. mu1/mu2 may be
 *  NULL except for XRSC_BLEND_MOMENTS. color is read (copied to src) and overwritten. */
typedef struct st_images {
    const gpu_image *color, *depth, *mu1, *mu2;
    const gpu_image *hitid; /**< hit ids (instance in .x); NULL: no instance test */
} st_images;

typedef struct st_blend {
    gpu_context *ctx;
    uint32_t width, height;
    st_settings set;
    gpu_compute_program prog;
    gpu_buffer params; /**< xs_st_params, host-visible */
    gpu_image src, aux; /**< src: none (freed) once st_blend_use_source gave one */
    gpu_image stub; /**< 1 x 1 x 2 rgba32f bound for absent moments */
    gpu_image stub_hitid; /**< 1 x 1 x 2 rgba32ui bound for absent hit ids */
    bool hitid_given;     /**< st_images.hitid was given: instance_test can apply */
    const gpu_image *color; /**< borrowed: read (copied to src) and overwritten */
} st_blend;

/** Creates the pass for images of width x height, bound to imgs. Errors:
 *  XRSC_ERROR_INVALID_ARGUMENT for an unknown blend, R outside [0, 1], moments without
 *  mu1/mu2, or images of another size. */
xrsc_result st_blend_create(gpu_context *ctx, uint32_t width, uint32_t height,
                            const st_settings *settings, const st_images *imgs, st_blend **out,
                            xrsc_diag *diag);
void st_blend_destroy(st_blend **st);

/** Eye matrices of xs_st_params from two views (as mt_trace_frame_constants makes them). */
void st_eyes_from_views(const xrsc_view views[2], xs_eye out_eyes[2]);

/** Reads src (borrowed, the colour's size and format) instead of a copy of the colour: the
 *  temporal filter's history, which it copies from the colour it has just written
 *  (tf_taa_history), so the blend's own copy is saved (on an H200 it took 1.3 ms at
 *  2 x 1440 x 1600 after TAA, 0.04 ms without). src must hold the colour when the pass runs. */
void st_blend_use_source(st_blend *st, const gpu_image *src);

/** Records pass ST_PASS_BLEND (timer may be NULL) for the eyes in eyes[2] (xs_frame.eyes):
 *  barrier, copy colour -> src (unless st_blend_use_source), dispatch, barrier. Nothing for
 *  XRSC_BLEND_NONE. */
void st_blend_cmd_record(st_blend *st, VkCommandBuffer cmd, gpu_timer *timer,
                         const xs_eye eyes[2]);

/**
 * For tests: blends host images (each 2 eyes, eye 0 first, rows top to bottom; colour, mu1, mu2
 * RGBA floats, depth floats; mu1/mu2 may be NULL except for moments) for views[2] with
 * settings, in one submission; out_rgba (2 eyes) gets the result, out_aux (optional, 2 eyes
 * RGBA) beta (rgb) and XS_ST_STATUS_* (a).
 */
xrsc_result st_blend_run_host(gpu_context *ctx, uint32_t width, uint32_t height,
                              const st_settings *settings, const xrsc_view views[2],
                              const float *color, const float *depth, const float *mu1,
                              const float *mu2, float *out_rgba, float *out_aux,
                              xrsc_diag *diag);

#ifdef __cplusplus
}
#endif
