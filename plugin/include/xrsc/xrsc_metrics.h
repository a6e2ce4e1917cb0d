// SPDX-License-Identifier: MIT
/**
 * @file xrsc_metrics.h
 * @brief Image metrics for speed-vs-accuracy claims: relMSE/RMSE and SSIM against a reference,
 *        CPBD sharpness, and the reprojected temporal and stereo differences (CPU only).
 *
 * Images are as the renderer outputs them (xrsc.h, XRSC_OUTPUT_COLOR / XRSC_OUTPUT_DEPTH):
 * colour is w*h RGBA float (linear radiance, rows top to bottom, alpha ignored), depth is w*h
 * float view-space distance along -Z in metres, 0 (or anything <= 0) = background.
 *
 * Pixel and camera conventions are the renderer's (shaders/xs_camera.glsl): pixel (x, y) has its
 * centre at ((x + 0.5) / w, (y + 0.5) / h) = (u, v), y down from the top row; its eye-space ray is
 * (mix(tanL, tanR, u), mix(tanU, tanD, v), -1), so the eye-space point at depth d is
 * d * (mix(tanL, tanR, u), mix(tanU, tanD, v), -1).
 *
 * Every function checks its input: XRSC_ERROR_INVALID_ARGUMENT for NULL images, zero or
 * mismatched sizes (and images too small for SSIM's window), XRSC_ERROR_NAN for a NaN or infinite
 * value in any colour or depth input, XRSC_ERROR_OUT_OF_MEMORY when scratch memory cannot be had.
 * Functions are pure (no global state); any thread may call them concurrently.
 */
#pragma once

#include "xrsc/result.h"
#include "xrsc/xrsc_math.h"

#include <stdbool.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** relMSE's epsilon: (x - r)^2 / (r^2 + eps); 1e-2 as is usual in rendering papers. */
#define XRSC_METRICS_RELMSE_EPSILON 1e-2
/** Display range L: luminance is clamped to [0, L] and divided by L for SSIM and CPBD. */
#define XRSC_METRICS_DISPLAY_RANGE 1.0
/** Relative depth tolerance of the reprojection's depth test (5 %). */
#define XRSC_METRICS_DEPTH_TOLERANCE 0.05

/** SSIM (Wang, Bovik, Sheikh, Simoncelli 2004, §III-C): 11 x 11 Gaussian window, sigma 1.5. */
#define XRSC_SSIM_WINDOW 11
#define XRSC_SSIM_SIGMA 1.5
#define XRSC_SSIM_K1 0.01
#define XRSC_SSIM_K2 0.03

/** CPBD (Narvekar & Karam 2011): the paper's constants and its reference implementation's. */
#define XRSC_CPBD_BLOCK 64                  /**< block side in pixels */
#define XRSC_CPBD_EDGE_BLOCK_FRACTION 0.002 /**< edge block: edge pixels > 0.2 % of the block */
#define XRSC_CPBD_BETA 3.6                  /**< P = 1 - exp(-|w / w_JNB|^beta) */
#define XRSC_CPBD_WJNB_LOW 5.0              /**< w_JNB for block contrast <= 50 (8-bit levels) */
#define XRSC_CPBD_WJNB_HIGH 3.0             /**< w_JNB for block contrast > 50 */
#define XRSC_CPBD_CONTRAST_SPLIT 50         /**< contrast (max - min of the block) threshold */
#define XRSC_CPBD_SOBEL_THRESHOLD_SCALE 4.0 /**< edge: |grad|^2 > 4 mean |grad|^2 */

/**
 * Options; zero fields mean the defaults in brackets.
 * - relmse_epsilon: eps of relMSE [XRSC_METRICS_RELMSE_EPSILON = 1e-2].
 * - display_range: L of SSIM and CPBD [XRSC_METRICS_DISPLAY_RANGE = 1]. HDR luminance is
 *   clamped to [0, L] (no tone curve), so SSIM is computed on linear values as seed 004 §5
 *   measures image quality "in linear RGB space", with C1 = (K1 L')^2, C2 = (K2 L')^2, L' = 1
 *   after division by L.
 * - cpbd_linear: false [default]: CPBD runs on the sRGB-encoded clamped luminance quantised to
 *   8 bits (the JNB widths and the contrast split 50 were measured on displayed 8-bit images);
 *   true: on the clamped linear luminance x 255, quantised.
 * - depth_tolerance: relative depth test of the reprojection [XRSC_METRICS_DEPTH_TOLERANCE].
 */
typedef struct xrsc_metrics_options {
    double relmse_epsilon;
    double display_range;
    bool cpbd_linear;
    double depth_tolerance;
} xrsc_metrics_options;

/** Luminance of linear Rec. 709 / sRGB primaries: 0.2126 R + 0.7152 G + 0.0722 B. */
double xrsc_metrics_luminance(const float rgba[4]);

/* ---- error against a reference ---- */

/**
 * Pixel error of a test image x against a reference r, over all pixels and the R, G, B
 * channels (N = 3 w h values):
 * - mse = sum (x - r)^2 / N, rmse = sqrt(mse);
 * - relmse = sum (x - r)^2 / (r^2 + eps) / N (the RSE of seed 000 §5.1 Fig. 12).
 */
typedef struct xrsc_error_metrics {
    double mse;
    double rmse;
    double relmse;
} xrsc_error_metrics;

xrsc_result xrsc_metrics_error(const float *test_rgba, const float *ref_rgba, uint32_t width,
                               uint32_t height, const xrsc_metrics_options *options,
                               xrsc_error_metrics *out);

/**
 * Mean SSIM of the luminance of test vs reference (Wang et al. 2004, Eq. 13 and the mean of
 * Eq. 17), each luminance clamped to [0, L] and divided by L. The SSIM map covers the positions
 * where the whole window lies inside the image ("valid" filtering, as in Wang's reference code,
 * without its automatic downsampling): (w - 10) x (h - 10) values, row-major, top row first.
 * Images must be at least 11 x 11. out_map (optional, may be NULL) receives the map.
 */
xrsc_result xrsc_metrics_ssim(const float *test_rgba, const float *ref_rgba, uint32_t width,
                              uint32_t height, const xrsc_metrics_options *options,
                              double *out_mssim, float *out_map);

/** The normalised 11 x 11 SSIM window (sums to 1), row-major. */
void xrsc_metrics_ssim_window(double out_w[XRSC_SSIM_WINDOW * XRSC_SSIM_WINDOW]);

/* ---- sharpness ---- */

/**
 * CPBD result. cpbd is the fraction of measured edges whose probability of blur detection
 * P = 1 - exp(-(w / w_JNB)^3.6) is at most P_JNB = 1 - exp(-1) (the paper's 63 %, reached at
 * w = w_JNB), in [0, 1], higher = sharper. With no measured edge (e.g. a constant image) cpbd
 * is 0 and edge_count 0 (the limit of ever stronger blur; callers can tell by edge_count).
 */
typedef struct xrsc_cpbd {
    double cpbd;
    uint64_t edge_count;       /**< edges whose width was measured, in edge blocks */
    uint32_t edge_block_count; /**< blocks classified as edge blocks */
    uint32_t block_count;      /**< all blocks (partial ones at the right/bottom included) */
} xrsc_cpbd;

/**
 * CPBD, no-reference sharpness (Narvekar & Karam, IEEE TIP 20(9) 2011), on the luminance
 * prepared as in ::xrsc_metrics_options (8-bit levels I):
 * 1. Sobel gradient (gx, gy) on interior pixels; an edge pixel has |g|^2 above 4 times the mean
 *    of |g|^2 over the interior (MATLAB's default Sobel threshold rule) and is a local maximum
 *    of |g| along its dominant axis (>= the left/upper, > the right/lower neighbour), i.e.
 *    thinned. One detector serves both the edge-block test and the widths (implementations of
 *    the paper use Canny for the former); its adaptive threshold finds no edges in images
 *    whose edges cover more than about a quarter of the pixels.
 * 2. 64 x 64 blocks (partial blocks at the right and bottom included); a block is an edge block
 *    when its edge pixels number more than 0.002 x its pixels.
 * 3. In edge blocks, the width of each edge pixel whose gradient is within 22.5 deg of horizontal
 *    (a vertical edge, the paper's horizontal-search implementation of Marziliano's width) is
 *    the distance between the nearest local extrema of I along the row on either side
 *    (the walk stops where I stops strictly increasing / decreasing); a sharp step has width 1.
 * 4. w_JNB = 5 when the block contrast max(I) - min(I) <= 50, else 3; P as above with beta 3.6;
 *    cpbd = #(P <= P_JNB) / #edges.
 */
xrsc_result xrsc_metrics_cpbd(const float *rgba, uint32_t width, uint32_t height,
                              const xrsc_metrics_options *options, xrsc_cpbd *out);

/**
 * The probability of blur detection of an edge of width width_px in a block whose JNB width is
 * w_jnb_px: 1 - exp(-(width / w_jnb)^3.6). Since P_JNB = 1 - exp(-1), P <= P_JNB exactly when
 * width <= w_jnb, whatever beta: beta shapes P but does not move CPBD's threshold.
 */
double xrsc_metrics_cpbd_blur_probability(double width_px, double w_jnb_px);

/* ---- reprojection ---- */

/** A camera: eye pose in world space, OpenXR field of view, image size in pixels. */
typedef struct xrsc_metrics_camera {
    XrPosef pose;
    XrFovf fov;
    uint32_t width, height;
} xrsc_metrics_camera;

/**
 * Reprojects the point seen at image position (x_px, y_px) (pixels from the top-left image
 * corner; pixel centres at +0.5) at depth depth_m in camera `from` into camera `to`: the image
 * position there and the point's depth along to's -Z. Uses xrsc_pose_to_matrix,
 * xrsc_pose_view_matrix and xrsc_fov_projection. Returns false (outputs untouched) when the
 * point is not in front of `to` (depth <= 0); positions outside to's image are returned as they
 * are (the caller tests bounds).
 */
bool xrsc_metrics_reproject(const xrsc_metrics_camera *from, double x_px, double y_px,
                            double depth_m, const xrsc_metrics_camera *to, double *out_x_px,
                            double *out_y_px, double *out_depth_m);

/** One rendered view: colour, depth and the camera they were rendered with. */
typedef struct xrsc_metrics_view {
    const float *rgba;    /**< w*h RGBA */
    const float *depth_m; /**< w*h, along -Z; <= 0 is background */
    xrsc_metrics_camera camera;
} xrsc_metrics_view;

/** Per-pixel outcome of a reprojected difference (out_status). */
typedef enum xrsc_reproj_status {
    XRSC_REPROJ_BACKGROUND = 0,     /**< the target pixel has no depth */
    XRSC_REPROJ_VALID = 1,          /**< counted */
    XRSC_REPROJ_OUTSIDE = 2,        /**< lands outside the source image or behind its camera */
    XRSC_REPROJ_DEPTH_MISMATCH = 3, /**< a source tap is background or another surface */
} xrsc_reproj_status;

/** Result of a reprojected difference. */
typedef struct xrsc_reproj_diff {
    double
        mean_sq_diff; /**< mean over valid pixels and R, G, B of (target - source)^2; 0 if none */
    uint64_t valid_count;      /**< valid pixels */
    uint64_t foreground_count; /**< target pixels with depth (the valid ones among them) */
} xrsc_reproj_diff;

/**
 * Backward reprojection of `source` into `target`: every target pixel with depth is moved by its
 * depth into the source camera (::xrsc_metrics_reproject) and the source colour there is read
 * bilinearly between the four nearest pixel centres (clamped to the image edge; positions within
 * 1e-3 pixel of a centre read that pixel alone). The pixel is valid when the position lies inside
 * the source image, in front of its camera, and every tap used has depth d with
 * |d - d_expected| <= depth_tolerance * d_expected (so disocclusions and background are
 * excluded). Scene motion is not modelled: the scene is assumed static between the two views.
 *
 * out_status (optional, w*h bytes of ::xrsc_reproj_status) and out_sq_diff (optional, w*h
 * floats: the pixel's mean over R, G, B of the squared difference, 0 where not valid) are in
 * the target's pixels. Both views may have different sizes.
 */
xrsc_result xrsc_metrics_reprojected_diff(const xrsc_metrics_view *target,
                                          const xrsc_metrics_view *source,
                                          const xrsc_metrics_options *options,
                                          xrsc_reproj_diff *out, uint8_t *out_status,
                                          float *out_sq_diff);

/**
 * Temporal difference: frame t (`current`) against frame t-1 (`previous`) reprojected into it
 * (seed 000 Fig. 10, "frame-to-frame reprojected difference"). Same as
 * ::xrsc_metrics_reprojected_diff(current, previous, ...).
 */
xrsc_result xrsc_metrics_temporal_diff(const xrsc_metrics_view *current,
                                       const xrsc_metrics_view *previous,
                                       const xrsc_metrics_options *options, xrsc_reproj_diff *out,
                                       uint8_t *out_status, float *out_sq_diff);

/**
 * Stereo discrepancy (seed 004 §4.1 and Fig. 2; seed 000 §5.2 Fig. 15): the squared radiance
 * difference between one eye and the other eye reprojected into it by depth, disocclusions
 * excluded by the depth test. Same as ::xrsc_metrics_reprojected_diff(eye, other_eye, ...);
 * seed 000 Fig. 15 reprojects the left eye onto the right view: eye = right, other_eye = left.
 */
xrsc_result xrsc_metrics_stereo_discrepancy(const xrsc_metrics_view *eye,
                                            const xrsc_metrics_view *other_eye,
                                            const xrsc_metrics_options *options,
                                            xrsc_reproj_diff *out, uint8_t *out_status,
                                            float *out_sq_diff);

/* ---- regions (issue 9: where methods fail) ---- */

/**
 * Image regions, one bit each in a region mask (::xrsc_metrics_regions). Masks come from the
 * first-hit ids (XRSC_OUTPUT_HIT_ID: instance, UINT32_MAX = miss) and depth of the frame, so
 * every method is scored on the same pixels.
 */
typedef enum xrsc_region {
    XRSC_REGION_ALL = 0,   /**< every foreground pixel (a hit with depth > 0) */
    XRSC_REGION_EDGE,      /**< a 3x3 neighbour hits another instance (or misses), or its depth
                                differs by more than XRSC_REGION_EDGE_DEPTH_RATIO; both sides of
                                a silhouette, background pixels included */
    XRSC_REGION_OBJECT,    /**< first hit on an instance flagged XRSC_INSTANCE_FLAG_OBJECT */
    XRSC_REGION_UNCOVERED, /**< foreground now, not visible last frame: reprojected by depth into
                                the previous frame (static scene assumed) it lands outside the
                                image, or none of its 2x2 nearest pixels there shows the same
                                instance at the expected depth (depth_tolerance) */
    XRSC_REGION_SPECULAR,  /**< first hit on an instance flagged XRSC_INSTANCE_FLAG_SPECULAR */
    XRSC_REGION_ONE_EYE,   /**< foreground seen by this eye only: the same test into the other
                                eye (instance only when other_hit_id is given) */
    XRSC_REGION_COUNT
} xrsc_region;
#define XRSC_REGION_BIT(r) (1u << (r))
/** Edge test: depth ratio between 3x3 neighbours above which a silhouette/crease is assumed.
 *  Neighbours on one plane differ by a few percent except at grazing angles. */
#define XRSC_REGION_EDGE_DEPTH_RATIO 0.1

/** Per-instance flags (::xrsc_scene_instance_flags in xrsc.h fills them from a scene). */
#define XRSC_INSTANCE_FLAG_OBJECT 1u   /**< animated (the node or an ancestor is) */
#define XRSC_INSTANCE_FLAG_SPECULAR 2u /**< (metallic >= 0.5 or transmission > 0) and roughness
                                            < 0.5: glossy metal, glass (seed 000 App. C) */

/** Name of a region ("all", "edge", "object", "uncovered", "specular", "one_eye"), or "?". */
const char *xrsc_region_name(xrsc_region region);

/**
 * What the region masks are made of. Cameras' width/height must equal width/height. Optional
 * inputs (NULL) leave their regions empty: prev_* UNCOVERED, other_depth_m ONE_EYE,
 * instance_flags OBJECT and SPECULAR (instances >= instance_count have no flags).
 */
typedef struct xrsc_region_input {
    uint32_t width, height;
    const uint32_t *hit_id; /**< w*h*4 (XRSC_OUTPUT_HIT_ID of this eye, this frame) */
    const float *depth_m;   /**< w*h */
    xrsc_metrics_camera camera;
    const uint32_t *prev_hit_id; /**< optional: last frame, same eye (w*h*4) */
    const float *prev_depth_m;   /**< optional with prev_hit_id */
    xrsc_metrics_camera prev_camera;
    const float *other_depth_m; /**< optional: the other eye, this frame */
    xrsc_metrics_camera other_camera;
    const uint8_t *instance_flags; /**< optional: per instance, XRSC_INSTANCE_FLAG_* */
    uint32_t instance_count;
    const uint32_t *other_hit_id; /**< optional with other_depth_m: adds the instance test */
} xrsc_region_input;

/** Fills out_mask (w*h bytes): bit XRSC_REGION_BIT(r) set when the pixel is in region r. */
xrsc_result xrsc_metrics_regions(const xrsc_region_input *in, const xrsc_metrics_options *options,
                                 uint8_t *out_mask);

/**
 * ::xrsc_metrics_error over the pixels whose mask has bit `region` only (N = 3 x their count).
 * With no such pixel the errors are 0 and *out_count 0. out_count may be NULL.
 */
xrsc_result xrsc_metrics_region_error(const float *test_rgba, const float *ref_rgba,
                                      const uint8_t *mask, xrsc_region region, uint32_t width,
                                      uint32_t height, const xrsc_metrics_options *options,
                                      xrsc_error_metrics *out, uint64_t *out_count);

/**
 * Recovery frames after an event (seed 000 Fig. 12's head turn): baseline = mean of err over
 * the pre_frames frames before event_frame (0: all of them); the spike is the maximum of err at
 * or after event_frame. Returns k - event_frame for the first k at or after the spike with
 * err[k] <= factor * baseline (0 when the spike stays within it), UINT32_MAX when err never
 * comes back, or no baseline can be formed (event_frame 0 or >= count, no finite value before
 * it). NaN entries are frames without a measurement (e.g. unscored) and are skipped.
 */
uint32_t xrsc_metrics_recovery_frames(const double *err, uint32_t count, uint32_t event_frame,
                                      uint32_t pre_frames, double factor);

/**
 * ::xrsc_metrics_recovery_frames for an event that lasts (a head turn from event_frame to
 * end_frame): the baseline is taken before event_frame, the spike at or after it, and recovery
 * is counted from end_frame: k - end_frame for the first k >= max(spike, end_frame) with
 * err[k] <= factor * baseline. end_frame == event_frame is ::xrsc_metrics_recovery_frames.
 * UINT32_MAX also when end_frame < event_frame or end_frame >= count.
 */
uint32_t xrsc_metrics_recovery_frames_after(const double *err, uint32_t count,
                                            uint32_t event_frame, uint32_t pre_frames,
                                            uint32_t end_frame, double factor);

#ifdef __cplusplus
}
#endif
