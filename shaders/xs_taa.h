// SPDX-License-Identifier: MIT
/**
 * @file xs_taa.h
 * @brief The TAA post-pass's layouts, bindings and constants (taa.comp and plugin/src/temporal/),
 *        and the Halton(2,3) sub-pixel jitter of method `taa`, one source for C and GLSL.
 *
 * TAA as [YLS20] describes it and seed 000 §5/§5.1 puts it on top of every method: the
 * history (last frame's TAA output) is reprojected into the current frame, validated
 * (disocclusion), rectified (variance clipping in YCoCg, [Sal16]) and blended with the current
 * frame with weight alpha: out = lerp(history, current, alpha). Mode PFJ23 replaces the fixed
 * alpha by seed 004 Eq. 4 estimated per pixel and channel with Eq. 10-11 (seed 004 §4.2).
 *
 * Set 0 of taa.comp is the ray-tracing programs' set 0 (xrsc_shared.h, XS_BIND_*: the scene's
 * vertices and instances, and XS_BIND_FRAME = the current frame's xs_frame) followed by the
 * XS_TF_BIND_* bindings below.
 */
#ifndef XS_TAA_H
#define XS_TAA_H

#include "xrsc_shared.h"

/* ---- taa.comp: set 0 after XS_BIND_RAY_COUNTER ---- */
#define XS_TF_BIND_PARAMS 16     /* uniform xs_tf_params */
#define XS_TF_BIND_SRC 17        /* rgba32f: the method's colour of this frame (copy, input) */
#define XS_TF_BIND_DEPTH 18      /* r32f: this frame's view depth, 0 = background */
#define XS_TF_BIND_HITID 19      /* rgba32ui: this frame's hit ids (instance in .x) */
#define XS_TF_BIND_HISTORY 20    /* rgba32f: last frame's TAA output */
#define XS_TF_BIND_PREV_GEO 21   /* rg32ui: last frame's depth bits (x), instance (y) */
#define XS_TF_BIND_NEXT_GEO 22   /* rg32ui: this frame's, copied to PREV_GEO after the dispatch */
#define XS_TF_BIND_OUT 23        /* rgba32f: the method's colour image (output) */
#define XS_TF_BIND_AUX 24        /* rgba32f: alpha used per channel (rgb), XS_TF_STATUS_* (a) */
#define XS_TF_BIND_REPROJ 25     /* rgba32f, debug only: reprojected history (rgb), tap weight (a) */
#define XS_TF_BIND_PREV_XFORM 26 /* readonly buffer mat4[]: object_to_world of the last frame */
#define XS_TF_BIND_NEXT_XFORM 27 /* buffer mat4[]: this frame's, copied to PREV_XFORM after */
#define XS_TF_BIND_PREV_POS 28   /* readonly buffer vec4[]: last frame's posed object-space
                                  * position per scene vertex (gpu_deform.h), when deform = 1 */

#define XS_TF_GROUP 8u /* local size x and y of taa.comp */

/* Modes: the public xrsc_taa_mode values (XRSC_TAA_ON, XRSC_TAA_PFJ23). */
#define XS_TF_MODE_ON 2u
#define XS_TF_MODE_PFJ23 3u

/* Per-pixel outcome in the aux image's alpha. */
#define XS_TF_STATUS_NO_HISTORY 0.0f /* first frame (or after a reset): output = current */
#define XS_TF_STATUS_BLENDED 1.0f    /* history reprojected, validated and blended */
#define XS_TF_STATUS_REJECTED 2.0f   /* disoccluded or off-screen: output = current */

/** The current frame's weight with mode ON ([YLS20]; seed 004 §1: usually 0.1). */
#define XS_TF_DEFAULT_ALPHA 0.1f
/** Variance clipping box: mean +- gamma sigma in YCoCg ([Sal16], as [YLS20] surveys it). */
#define XS_TF_GAMMA 1.0f
/** A previous-frame pixel stands for the reprojected point when it shows the same instance and
 *  |d_tap - d_expected| <= tol * d_expected + XS_TF_SLOPE_PX * slope, tol the stereo blend's
 *  (XS_ST_DEPTH_TOLERANCE), slope the surface's largest depth step to a neighbouring pixel:
 *  the pixels compared lie up to 2 pixels from the point (tap + neighbour), and a relative
 *  tolerance alone rejected the jittered history at grazing silhouettes of a still view. */
#define XS_TF_DEPTH_TOLERANCE 0.05f
#define XS_TF_SLOPE_PX 2.0f
/** Mode ON's weight of the current frame for the share of the history that is not trusted
 *  (taa.comp history_at: taps that did not show the pixel's surface themselves, read through
 *  a neighbour, off the image or rejected; in motion also those read at the tap as an edge's
 *  mix): alpha_used = alpha + (max(XS_TF_UNTRUSTED_ALPHA, alpha) - alpha) x (1 - trusted
 *  weight). At an edge the 3 x 3 box spans both surfaces and cannot clip such a history, so
 *  at alpha 0.1 a thin feature's rim and an early frame's error stayed for ~10 frames under
 *  a pan or a sideways move (issue 19: `edges` 0.181 -> 0.155 relMSE, `disocclusion`
 *  0.063 -> 0.054 at 2 x 96^2; bench/results/issue19-taasharp/). */
#define XS_TF_UNTRUSTED_ALPHA 0.5f
/** A reprojected point within this many pixels of its pixel's centre (each axis) is a still
 *  view: its edge taps read at the tap are the pixel's own antialiased mix (trusted). */
#define XS_TF_STILL_PX 0.01f
/** Below this share of the bilinear kernel's weight on accepted taps the history is rejected
 *  (disocclusion), as the stereo blend does (XS_ST_MIN_WEIGHT). */
#define XS_TF_MIN_WEIGHT 0.5f
/** The resolve (history resampling, neighbourhood, clipping, PFJ23 weights, blend) works on
 *  t = c / (1 + Y), Y = c's YCoCg luma, and returns c = t / max(1 - Y_t, XS_TF_TONEMAP_FLOOR)
 *  (taa.comp): an emitter's radiance next to a dark surface no longer leaks into it through
 *  the bilinear history or escapes the clipping box (issue 19). The floor keeps the inverse
 *  finite; it caps the output luma at about 1 / XS_TF_TONEMAP_FLOOR. */
#define XS_TF_TONEMAP_FLOOR 1e-6f

/** Motion rule of mode ON (xs_tf_params.motion_px2, motion_alpha; issue 19; off unless
 *  asked for, ::xrsc_taa_motion): resampling the history between pixels (the reprojected
 *  point at fraction f = (fx, fy) between the 2 x 2 taps) adds the bilinear kernel's variance
 *  fx (1 - fx) + fy (1 - fy) px^2 of blur to it each frame, and at weight alpha the history
 *  keeps about (1 - alpha) / alpha frames of it: at alpha 0.1 under a sub-pixel pan ~1.5 px
 *  (sigma), which on an already converged input (the sample cache) costs more than the noise
 *  TAA removes (issue 19's `edges`, `disocclusion`). The current frame's weight rises linearly
 *  from alpha at no blur (a still view) to XS_TF_MOTION_ALPHA at XS_TF_MOTION_PX2 or more.
 *  It lowers relMSE under motion but raises the temporal and stereo differences of orbits
 *  (bench/results/issue19-taaedge/), hence not the default. */
#define XS_TF_MOTION_PX2 0.25f
#define XS_TF_MOTION_ALPHA 0.5f

/* History resampling (xs_tf_params.history_filter; the public xrsc_taa_history values). */
#define XS_TF_HISTORY_BILINEAR 1u    /* the 2 x 2 bilinear taps */
#define XS_TF_HISTORY_CATMULL_ROM 2u /* 4 x 4 Catmull-Rom taps where the surface allows (taa.comp) */

/** Method `taa`'s jitter: the Halton(2,3) points 1..XS_TF_HALTON_PERIOD, repeating ([YLS20]
 *  §3.1: a short low-discrepancy sequence; index 0 = (0, 0) is skipped). */
#define XS_TF_HALTON_PERIOD 16u

XS_STRUCT(xs_tf_params)
{
    xs_eye prev_eyes[2];   /* the last frame's eyes (view, view_inv, proj, tan_fov) */
    xs_uint width, height; /* per eye, pixels */
    xs_uint mode;          /* XS_TF_MODE_* */
    xs_uint history_valid; /* 0: no history (first frame, reset): output = current */
    xs_float alpha;        /* mode ON: the current frame's weight */
    xs_float gamma;        /* XS_TF_GAMMA */
    xs_float depth_tolerance;
    xs_float min_weight;
    xs_uint instance_count; /* entries of the transform buffers */
    xs_uint debug;          /* 1: write XS_TF_BIND_REPROJ */
    xs_uint deform;         /* 1: PREV_POS follows skinned/morphed surfaces (issue 21) */
    xs_uint history_filter; /* XS_TF_HISTORY_*: how the reprojected history is resampled */
    xs_float motion_px2;    /* mode ON, > 0: the blur (px^2) at which alpha reaches
                             * motion_alpha (XS_TF_MOTION_*); 0: no motion rule */
    xs_float motion_alpha;  /* the current frame's weight at that blur or more */
    xs_uint motion_edges;   /* 1: the motion rule only where the current 3 x 3 neighbourhood
                             * shows another surface (XRSC_TAA_MOTION_EDGES) */
    xs_uint pad1;
} XS_END(xs_tf_params);

#ifndef XRSC_GLSL
_Static_assert(sizeof(xs_tf_params) == 2 * 208 + 64, "xs_tf_params layout");

/** The radical inverse of index in base b (Halton's sequence, one coordinate). */
static inline float xs_tf_halton(uint32_t index, uint32_t b)
{
    float f = 1.0f, r = 0.0f;
    while (index > 0u) {
        f /= (float)b;
        r += f * (float)(index % b);
        index /= b;
    }
    return r;
}
#endif

#endif /* XS_TAA_H */
