// SPDX-License-Identifier: MIT
/**
 * @file mt_method.h
 * @brief The rendering-method interface: one struct of function pointers per method, created
 *        by mt_<name>_create and destroyed with ::mt_method_destroy.
 *
 * A method renders both eyes of one ::xrsc_frame into per-eye output images (layer = eye),
 * times its passes with timestamp queries and counts the rays it traced. Implementations embed
 * ::mt_method as their first member named `base`.
 */
#pragma once

#include "gpu_scene.h"
#include "gpu_timer.h"
#include "xrsc_shared.h"
#include "sc_scene.h"
#include "xrsc/xrsc.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct mt_method mt_method;

struct mt_method {
    const char *name; /**< "primary", "spp", ... */
    /** Renders both eyes of frame and waits for the GPU. */
    xrsc_result (*render)(mt_method *m, const xrsc_frame *frame, xrsc_diag *diag);
    /** Bytes of one eye's image of output (width * height * texel size), 0 if not produced. */
    size_t (*output_size)(const mt_method *m, xrsc_output output);
    /** Copies one eye's output of the last frame into dst (rows top to bottom). */
    xrsc_result (*read)(mt_method *m, uint32_t eye, xrsc_output output, void *dst,
                        size_t dst_size, xrsc_diag *diag);
    /** GPU time per pass of the last frame; returns the number written. */
    uint32_t (*timings)(const mt_method *m, xrsc_pass_timing *out, uint32_t max_count);
    /** Rays traced in the last frame. */
    uint64_t (*rays_last_frame)(const mt_method *m);
    void (*destroy)(mt_method *m);
    /** Optional (NULL: not offered): the GPU image holding output for both eyes (layer =
     *  eye, layout GENERAL, valid after render returned), for copies on the GPU (the XR
     *  front end's swapchain copies); NULL if the output is not produced. */
    const gpu_image *(*output_image)(const mt_method *m, xrsc_output output);
    /** Optional (NULL: none): the method's statistics of the last frame
     *  (xrsc_renderer_counters); returns the number written. */
    uint32_t (*counters)(const mt_method *m, xrsc_counter *out, uint32_t max_count);
};

/**
 * Work recorded after the method's last pass into its frame's one command buffer, before the
 * read-back copies (TAA, plugin/src/temporal/, then the stereo blend, plugin/src/stereo/):
 * record(user, cmd, timer, xf) with the method's pass timer and the frame's constants (TAA
 * reads xf's eyes as the current views). record NULL: nothing.
 */
typedef struct mt_post {
    void (*record)(void *user, VkCommandBuffer cmd, gpu_timer *timer, const xs_frame *xf);
    void *user;
} mt_post;

static inline void mt_post_record(const mt_post *post, VkCommandBuffer cmd, gpu_timer *timer,
                                  const xs_frame *xf)
{
    if (post && post->record)
        post->record(post->user, cmd, timer, xf);
}

/** What every method renders with: borrowed pointers that outlive the method. */
typedef struct mt_env {
    gpu_context *gpu;
    gpu_scene *scene;
    const sc_scene *cpu_scene; /**< environment and sun */
    uint32_t width, height;    /**< per eye, pixels (non-zero) */
    uint32_t seed;
    const mt_post *post; /**< optional, borrowed: read at every frame */
} mt_env;

static inline xrsc_result mt_method_render(mt_method *m, const xrsc_frame *frame,
                                           xrsc_diag *diag)
{
    return m->render(m, frame, diag);
}
static inline size_t mt_method_output_size(const mt_method *m, xrsc_output output)
{
    return m->output_size(m, output);
}
static inline xrsc_result mt_method_read(mt_method *m, uint32_t eye, xrsc_output output,
                                         void *dst, size_t dst_size, xrsc_diag *diag)
{
    return m->read(m, eye, output, dst, dst_size, diag);
}
static inline uint32_t mt_method_timings(const mt_method *m, xrsc_pass_timing *out,
                                         uint32_t max_count)
{
    return m->timings(m, out, max_count);
}
static inline uint64_t mt_method_rays_last_frame(const mt_method *m)
{
    return m->rays_last_frame(m);
}
/** The output's GPU image, or NULL when the method does not offer it. */
static inline const gpu_image *mt_method_output_image(const mt_method *m, xrsc_output output)
{
    return m->output_image ? m->output_image(m, output) : NULL;
}
/** The method's counters of the last frame; 0 when it has none. */
static inline uint32_t mt_method_counters(const mt_method *m, xrsc_counter *out,
                                          uint32_t max_count)
{
    return m->counters ? m->counters(m, out, max_count) : 0;
}
/** Destroys the method; accepts NULL and sets *m to NULL. */
static inline void mt_method_destroy(mt_method **m)
{
    if (m && *m) {
        (*m)->destroy(*m);
        *m = NULL;
    }
}

/**
 * `primary`: one ray per pixel through its centre (primary.rgen); colour = first-hit albedo.
 * No options.
 */
xrsc_result mt_primary_create(const mt_env *env, mt_method **out, xrsc_diag *diag);

/**
 * `spp`: path tracer (spp.rgen), options as ::xrsc_spp_options (zero = defaults:
 * 1 sample per pixel, XS_DEFAULT_MAX_BOUNCES bounces, jitter on, no accumulation).
 */
xrsc_result mt_spp_create(const mt_env *env, const xrsc_spp_options *options, mt_method **out,
                          xrsc_diag *diag);

/** Sets xf's sub-pixel jitter (jitter, jitter_x, jitter_y) for frame; see mt_spp_create_variant. */
typedef void (*mt_spp_jitter_fn)(const xrsc_frame *frame, xs_frame *xf);

/** `spp` (mt_spp_create) named `name`, for methods that are `spp` with another jitter (`taa`):
 *  jitter, when not NULL, runs every frame after spp set its own jitter (options->no_jitter).
 *  name is a static string. */
xrsc_result mt_spp_create_variant(const mt_env *env, const xrsc_spp_options *options,
                                  const char *name, mt_spp_jitter_fn jitter, mt_method **out,
                                  xrsc_diag *diag);

/**
 * `taa`'s rendering (mt_taa.c): 1 path-traced sample per pixel (spp.rgen) at the Halton(2,3)
 * point (frame_index mod XS_TF_HALTON_PERIOD) + 1, the same sub-pixel offset in both eyes;
 * max_bounces from options as `spp` (other fields ignored). The TAA itself is the renderer's
 * post-pass (plugin/src/temporal/), on by default for this method.
 */
xrsc_result mt_taa_create(const mt_env *env, const xrsc_spp_options *options, mt_method **out,
                          xrsc_diag *diag);

#ifdef __cplusplus
}
#endif
