// SPDX-License-Identifier: MIT
/**
 * @file tf_taa.h
 * @brief The TAA post-pass (taa.comp, layouts in shaders/xs_taa.h): temporal antialiasing of
 *        any method's colour, in place on the GPU ([YLS20] as seed 000 §5.1 uses it; seed 004
 *        §4.2 for the PFJ23 weights).
 *
 * Pass "taa": copies the colour (both eyes) into the pass's `src` image, one dispatch reads
 * src, the method's depth and hit ids, the history (last frame's TAA output) and the last
 * frame's depth and instance per pixel, and writes the filtered colour back into the method's
 * colour image (alpha and status per pixel into `aux`) and this frame's depth and instance per
 * pixel into one texel (`next_geo`); then copies the colour, that texel and this frame's
 * instance transforms into the history for the next frame. The pass keeps the last frame's
 * eyes and instance transforms itself (not the scene's prev_object_to_world, which holds the
 * transforms of the last scene-time change: a frame repeated at the same time would reproject
 * a moved instance twice). Recorded by the method into its frame's one command
 * buffer after reconstruction and before the stereo blend (mt_post), so it is timed with the
 * method's passes and precedes every read-back and swapchain copy. The first frame (and the
 * first after tf_taa_reset) has no history: its output is the current frame.
 */
#pragma once

#include "gpu_pipeline.h"
#include "gpu_resource.h"
#include "gpu_scene.h"
#include "gpu_timer.h"
#include "xrsc/xrsc.h"
#include "xrsc_shared.h"
#include "xs_taa.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Pass name in xrsc_renderer_timings. */
#define TF_PASS_TAA "taa"

/** TAA settings: mode XRSC_TAA_ON or XRSC_TAA_PFJ23 (OFF and DEFAULT are resolved by the
 *  caller: no pass); alpha 0 = XS_TF_DEFAULT_ALPHA; debug keeps the reprojected history. */
typedef struct tf_settings {
    xrsc_taa_mode mode;
    float alpha;
    /** History resampling; XRSC_TAA_HISTORY_DEFAULT = bilinear. */
    xrsc_taa_history history;
    /** Mode ON's motion rule (::xrsc_taa_motion): XRSC_TAA_MOTION_ON, XRSC_TAA_MOTION_EDGES
     *  (on the dark side of edges between surfaces only) or not (DEFAULT = off);
     *  motion_px2 / motion_alpha 0 = XS_TF_MOTION_PX2 /
     *  XS_TF_MOTION_ALPHA. */
    xrsc_taa_motion motion;
    float motion_px2, motion_alpha;
    bool debug;
    /** Tests: reproject skinned and morphed surfaces as if rigid (the control of issue 21's
     *  deformation motion; zero = follow them through gpu_scene_prev_positions). */
    bool no_deform_motion;
} tf_settings;

/** The method's images the pass works on, each 2 layers (eyes), GENERAL, width x height:
 *  colour (rgba32f, read and overwritten), depth (r32f), hit ids (rgba32ui). */
typedef struct tf_images {
    const gpu_image *color, *depth, *hitid;
} tf_images;

/** Per-pixel images kept for tests (tf_taa_read). */
typedef enum tf_image_kind {
    TF_IMAGE_SRC,    /**< the method's colour before the pass (rgba32f) */
    TF_IMAGE_AUX,    /**< alpha per channel (rgb), XS_TF_STATUS_* (a) */
    TF_IMAGE_REPROJ, /**< debug only: reprojected history (rgb, 0 if rejected), tap weight (a) */
} tf_image_kind;

typedef struct tf_taa tf_taa;

/** Creates the pass for the scene (its instances are reprojected with their motion) and the
 *  images. Errors: XRSC_ERROR_INVALID_ARGUMENT for a mode other than ON / PFJ23, alpha
 *  outside (0, 1], or images missing or of another size. */
xrsc_result tf_taa_create(gpu_context *ctx, gpu_scene *scene, uint32_t instance_count,
                          uint32_t width, uint32_t height, const tf_settings *settings,
                          const tf_images *imgs, tf_taa **out, xrsc_diag *diag);
void tf_taa_destroy(tf_taa **taa);

/** Forgets the history: the next frame's output is its current frame. */
void tf_taa_reset(tf_taa *taa);

/** Records pass TF_PASS_TAA (timer may be NULL) for the frame xf (its eyes are the current
 *  ones; they become the history's eyes). */
void tf_taa_cmd_record(tf_taa *taa, VkCommandBuffer cmd, gpu_timer *timer, const xs_frame *xf);

/** The history image (2 eyes, rgba32f): after tf_taa_cmd_record, a copy of the frame's TAA
 *  output (st_blend_use_source reads it). */
const gpu_image *tf_taa_history(const tf_taa *taa);

/** For tests: copies one eye of an image of the last frame (rows top to bottom, RGBA floats)
 *  into dst. XRSC_ERROR_INVALID_ARGUMENT for TF_IMAGE_REPROJ without debug. */
xrsc_result tf_taa_read(tf_taa *taa, uint32_t eye, tf_image_kind kind, float *dst, size_t dst_size,
                        xrsc_diag *diag);

#ifdef __cplusplus
}
#endif
