// SPDX-License-Identifier: MIT
/**
 * @file mt_trace.h
 * @brief What the single-trace methods (`primary`, `spp`, `taa`) share: their outputs, the
 *        frame uniform, the ray counter, the timer, and one vkCmdTraceRaysKHR per stereo frame;
 *        the multi-pass methods (`hashcache`, `samplecache`) reuse its resources and set-0
 *        bindings, and `spp` and `samplecache` its moment images.
 */
#pragma once

#include "gpu_timer.h"
#include "mt_method.h"
#include "xrsc_shared.h"

#ifdef __cplusplus
extern "C" {
#endif

/**
 * Pass names (xrsc_renderer_timings), static strings. Every frame of a method reports the same
 * passes in the same order, so consumers may index them by position after the first frame:
 * - MT_PASS_TLAS: the scene's instance update (instances[] copy + TLAS update) when animated
 *   instances moved since the last frame; always present, ~0 ms when nothing moved (static
 *   scene or same scene time). Always the first pass.
 * - MT_PASS_TRACE: the one vkCmdTraceRaysKHR of both eyes.
 * Later methods add theirs after MT_PASS_TLAS (e.g. "reproject", "density", "trace",
 * "shade", "reconstruct"); read-back copies are never timed.
 */
#define MT_PASS_TLAS "tlas"
#define MT_PASS_TRACE "trace"

/** Outputs with a persistent read-back buffer (xrsc_output values). */
#define MT_OUTPUT_COUNT 4

/** Near and far planes of xs_eye.proj (only reprojection uses proj; rays use tan_fov). */
#define MT_NEAR_M 0.05f
#define MT_FAR_M 1000.0f

typedef struct mt_trace {
    mt_env env;
    gpu_rt_program program;
    gpu_image color, albedo, depth, hitid, accum; /**< 2 layers: [0] left, [1] right */
    /** Raw moments of each pixel's samples (XRSC_OUTPUT_MU1/MU2, RGBA32F, 2 layers): only
     *  methods that write them create them (mt_trace_create_moments), else zero. */
    gpu_image mu1, mu2;
    gpu_buffer frame_ubo;   /**< xs_frame, host-visible */
    gpu_buffer ray_counter; /**< uint64, device */
    gpu_buffer ray_readback;
    gpu_timer timer;
    uint64_t rays;
    /** Read-back: per output both eyes (layer 0 then 1), created at its first read. An output
     *  read during frame N is copied inside frame N+1's command buffer (reads usually repeat
     *  every frame), others by one submission at their first read after a frame. */
    gpu_buffer readback[MT_OUTPUT_COUNT];
    uint32_t staged_mask; /**< bit o: readback[o] holds the last frame's output o */
    uint32_t read_mask;   /**< bit o: output o was read since the last frame */
} mt_trace;

/** Creates the program for `raygen` and the resources, and writes set 0 (mt_trace_write_set0). */
xrsc_result mt_trace_init(mt_trace *t, const mt_env *env, const char *raygen, xrsc_diag *diag);
/** The same for any program description (tests: a raygen of their own, raygen_spirv). */
xrsc_result mt_trace_init_program(mt_trace *t, const mt_env *env,
                                  const gpu_rt_program_desc *desc, xrsc_diag *diag);
void mt_trace_fini(mt_trace *t);

/** Creates mu1 and mu2 (cleared to zero); mt_trace_fini destroys them. The method binds them
 *  to its programs (their bindings differ per method) and writes them. */
xrsc_result mt_trace_create_moments(mt_trace *t, xrsc_diag *diag);

/** Writes t's set-0 bindings (scene, XS_BIND_FRAME, the outputs, XS_BIND_ACCUM,
 *  XS_BIND_RAY_COUNTER) into d: t's own program's set 0, or that of another program of the
 *  same method sharing t's frame, outputs and counter. */
void mt_trace_write_set0(const mt_trace *t, gpu_descriptors *d);

/** Fills the views, environment, sun, sizes, seed and emitter count of xf from frame; the
 *  method fills samples, bounces, accumulate, jitter and frame_index. */
void mt_trace_frame_constants(const mt_trace *t, const xrsc_frame *frame, xs_frame *xf);

/** The start of a frame's command buffer, for mt_trace_run and methods with their own frame:
 *  uploads xf to frame_ubo (memcpy + flush), begins a command buffer (gpu_cmd_begin), records a
 *  full barrier (after earlier submissions), the timer reset and pass MT_PASS_TLAS (the scene's
 *  pending instance update, gpu_scene_cmd_update). *out_cmd is set only on XRSC_OK; the caller
 *  records the rest and submits it. */
xrsc_result mt_trace_cmd_frame_begin(mt_trace *t, const xs_frame *xf, VkCommandBuffer *out_cmd,
                                     xrsc_diag *diag);

/** Records the zeroing of the ray counter (before the frame's first ray). */
void mt_trace_cmd_rays_reset(mt_trace *t, VkCommandBuffer cmd);
/** Records the copy of the ray counter to its read-back buffer (after the last ray). */
void mt_trace_cmd_rays_copy(mt_trace *t, VkCommandBuffer cmd);
/** After the submission completed: t->rays = the counter copied by mt_trace_cmd_rays_copy. */
void mt_trace_rays_collect(mt_trace *t);

/** Records the copies of the outputs read during the last frame into their read-back
 *  buffers (after the passes that write them; the command buffer's last work). */
void mt_trace_cmd_stage_outputs(mt_trace *t, VkCommandBuffer cmd);
/** After the frame's submission completed (success or not): records which outputs are now
 *  staged. */
void mt_trace_frame_done(mt_trace *t, bool ok);

/** One submission: uploads xf, records pass "tlas" (scene update), (clears the accumulation
 *  image when clear_accum,) zeroes the ray counter, traces width x height x 2 (pass "trace"),
 *  copies the ray counter and the outputs read last frame; waits, then reads the counter and
 *  the timings. */
xrsc_result mt_trace_run(mt_trace *t, const xs_frame *xf, bool clear_accum, xrsc_diag *diag);

size_t mt_trace_output_size(const mt_trace *t, xrsc_output output);
/** The output's image (2 layers, GENERAL), NULL if this method does not produce it (the
 *  moments: NULL unless created). */
const gpu_image *mt_trace_output_image(const mt_trace *t, xrsc_output output);
/** Copies one eye of output (the last frame's) into dst: the MT_OUTPUT_COUNT outputs through
 *  their read-back buffers, the moments directly (gpu_image_read_layer, one submission). */
xrsc_result mt_trace_read(mt_trace *t, uint32_t eye, xrsc_output output, void *dst,
                          size_t dst_size, xrsc_diag *diag);
uint32_t mt_trace_timings(const mt_trace *t, xrsc_pass_timing *out, uint32_t max_count);

#ifdef __cplusplus
}
#endif
