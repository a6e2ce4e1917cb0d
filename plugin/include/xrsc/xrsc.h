// SPDX-License-Identifier: MIT
/**
 * @file xrsc.h
 * @brief The public C API of libxrsc: a Vulkan context, scenes, and per-eye renderers.
 *
 * Thread rules: one context, its scenes and renderers are used from one thread at a time.
 * Ownership: every *_create / *_load has a *_destroy taking T ** that accepts NULL and sets
 * the pointer to NULL. Options are zero-initialised structs; zero fields mean the documented
 * defaults.
 */
#pragma once

#include "xrsc/result.h"
#include "xrsc/xrsc_math.h"

#include <openxr/openxr.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct xrsc_context xrsc_context;
typedef struct xrsc_scene xrsc_scene;
typedef struct xrsc_renderer xrsc_renderer;

/**
 * Context options.
 * - device: which Vulkan device to use. NULL/"": the environment variable XRSC_DEVICE if set,
 *   else the first non-CPU device with ray-tracing pipelines, else lavapipe (llvmpipe).
 *   "cpu" picks lavapipe, "gpu" the first non-CPU device, a number picks that
 *   physical-device index, any other text picks the first device whose name contains it.
 * - validation: enable VK_LAYER_KHRONOS_validation and count its errors (also enabled when
 *   the environment variable XRSC_VALIDATION=1).
 */
typedef struct xrsc_context_options {
    const char *device;
    bool validation;
} xrsc_context_options;

xrsc_result xrsc_context_create(const xrsc_context_options *options, xrsc_context **out_ctx,
                                xrsc_diag *out_diag);
void xrsc_context_destroy(xrsc_context **ctx);
/** The selected device's name, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)". */
const char *xrsc_context_device_name(const xrsc_context *ctx);
/** True when the selected device is a CPU implementation (lavapipe). */
bool xrsc_context_is_cpu(const xrsc_context *ctx);
/** Validation-layer messages of severity ERROR seen so far (0 when validation is off). */
uint32_t xrsc_context_validation_errors(const xrsc_context *ctx);

/**
 * Scene options. environment: see sc_load_options (constant environment radiance override
 * when env_set). keep_triangle_order: skip the Morton sort of each mesh's triangles done
 * before the BLAS build (for benchmarks of its effect; primitive ids then follow the file).
 */
typedef struct xrsc_scene_options {
    bool env_set;
    float environment[3];
    bool keep_triangle_order;
} xrsc_scene_options;

typedef struct xrsc_scene_info {
    uint64_t triangle_count;
    uint32_t instance_count, material_count, emitter_count;
    float animation_duration_s;
    bool has_camera;
    XrPosef viewpoint; /**< where a replay's first pose is anchored by default */
    float bounds_min[3], bounds_max[3];
    double blas_build_ms; /**< GPU time of the BLAS builds at load (timestamp queries) */
} xrsc_scene_info;

/** Loads a glTF 2.0 file and uploads it (BLAS/TLAS built). */
xrsc_result xrsc_scene_load(xrsc_context *ctx, const char *path,
                            const xrsc_scene_options *options, xrsc_scene **out_scene,
                            xrsc_diag *out_diag);
void xrsc_scene_destroy(xrsc_scene **scene);
void xrsc_scene_get_info(const xrsc_scene *scene, xrsc_scene_info *out_info);

/**
 * Rendering methods.
 * - XRSC_METHOD_SPP: path tracer, N samples per pixel per frame (seed 000 §5.1).
 * - XRSC_METHOD_PRIMARY: one primary ray per pixel through its centre, no shading: colour is
 *   the first hit's albedo (environment for misses). For previews and primary-ray Mrays/s.
 */
typedef enum xrsc_method { XRSC_METHOD_SPP = 0, XRSC_METHOD_PRIMARY = 1 } xrsc_method;
/** "spp" / "primary"; NULL for unknown values. */
const char *xrsc_method_name(xrsc_method method);
/** Parses a method name; XRSC_ERROR_UNKNOWN_METHOD when unknown. */
xrsc_result xrsc_method_from_name(const char *name, xrsc_method *out_method);

/**
 * Options of the `spp` method (path tracer, seed 000 §5.1). Defaults: samples_per_pixel 1,
 * max_bounces 3 (Russian roulette from the 2nd), jitter on, no accumulation.
 * - accumulate: progressive accumulation over frames while the views stay the same (for
 *   references); any change of view or scene time restarts it.
 * - no_jitter: every sample through the pixel centre (for exact primary-hit tests).
 * - max_bounces: 0 means the default 3; XRSC_BOUNCES_NONE asks for direct lighting only.
 */
#define XRSC_BOUNCES_NONE UINT32_MAX
typedef struct xrsc_spp_options {
    uint32_t samples_per_pixel;
    uint32_t max_bounces;
    bool accumulate;
    bool no_jitter;
} xrsc_spp_options;

/** Renderer options. width/height per eye (default 256 x 256); seed 0 is a valid seed. */
typedef struct xrsc_renderer_options {
    xrsc_method method;
    uint32_t width, height;
    uint32_t seed;
    xrsc_spp_options spp;
} xrsc_renderer_options;

/** One eye's view. */
typedef struct xrsc_view {
    XrPosef pose; /**< eye pose in scene (world) space */
    XrFovf fov;
} xrsc_view;

/** One stereo frame to render. */
typedef struct xrsc_frame {
    xrsc_view views[2];      /**< [0] left, [1] right */
    int64_t display_time_ns; /**< scene time for animation (relative to the replay start) */
    uint32_t frame_index;    /**< selects the random stream */
} xrsc_frame;

xrsc_result xrsc_renderer_create(xrsc_context *ctx, xrsc_scene *scene,
                                 const xrsc_renderer_options *options,
                                 xrsc_renderer **out_renderer, xrsc_diag *out_diag);
void xrsc_renderer_destroy(xrsc_renderer **renderer);
/** Renders both eyes and waits for completion. */
xrsc_result xrsc_renderer_render(xrsc_renderer *renderer, const xrsc_frame *frame);

/** Per-eye outputs. */
typedef enum xrsc_output {
    XRSC_OUTPUT_COLOR,  /**< float RGBA, linear HDR radiance */
    XRSC_OUTPUT_ALBEDO, /**< float RGBA, demodulated first-hit albedo */
    XRSC_OUTPUT_DEPTH,  /**< float, view-space distance along -Z (m), 0 = background */
    XRSC_OUTPUT_HIT_ID, /**< uint32 x4: instance (UINT32_MAX = miss), primitive, bary u, v bits */
} xrsc_output;

/** Bytes one eye's image of that output takes (width * height * texel size). */
size_t xrsc_renderer_output_size(const xrsc_renderer *renderer, xrsc_output output);
/** Copies one eye's output of the last rendered frame into dst (rows top to bottom). */
xrsc_result xrsc_renderer_read(xrsc_renderer *renderer, uint32_t eye, xrsc_output output,
                               void *dst, size_t dst_size);

#define XRSC_MAX_PASSES 16
typedef struct xrsc_pass_timing {
    const char *name; /**< static string, e.g. "trace" */
    double gpu_ms;    /**< from Vulkan timestamp queries */
} xrsc_pass_timing;

/**
 * GPU time per pass of the last frame (Vulkan timestamp queries around each pass of the
 * frame's one command buffer); returns the number of passes written.
 * A renderer reports the same passes in the same order every frame (so they can be indexed by
 * position after the first frame). The first is always "tlas": the update of moved
 * (animated) instances and of the TLAS, about 0 ms when nothing moved (static scenes, or the
 * same display time as the last frame). Then the method's passes: `spp` and `primary` have
 * one, "trace" (both eyes). Read-back copies for xrsc_renderer_read are not timed.
 */
uint32_t xrsc_renderer_timings(const xrsc_renderer *renderer, xrsc_pass_timing *out,
                               uint32_t max_count);
/** Rays traced in the last frame (primary + secondary + shadow), for Mrays/s. */
uint64_t xrsc_renderer_rays_last_frame(const xrsc_renderer *renderer);

#ifdef __cplusplus
}
#endif
