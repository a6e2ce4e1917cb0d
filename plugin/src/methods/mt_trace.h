// SPDX-License-Identifier: MIT
/**
 * @file mt_trace.h
 * @brief What the single-trace methods (`primary`, `spp`) share: their outputs, the frame
 *        uniform, the ray counter, the timer, and one vkCmdTraceRaysKHR per stereo frame.
 */
#pragma once

#include "gpu_timer.h"
#include "mt_method.h"
#include "xrsc_shared.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Near and far planes of xs_eye.proj (only reprojection uses proj; rays use tan_fov). */
#define MT_NEAR_M 0.05f
#define MT_FAR_M 1000.0f

typedef struct mt_trace {
    mt_env env;
    gpu_rt_program program;
    gpu_image color, albedo, depth, hitid, accum; /**< 2 layers: [0] left, [1] right */
    gpu_buffer frame_ubo;   /**< xs_frame, host-visible */
    gpu_buffer ray_counter; /**< uint64, device */
    gpu_buffer ray_readback;
    gpu_timer timer;
    uint64_t rays;
} mt_trace;

/** Creates the program for `raygen` and the resources, and writes set 0. */
xrsc_result mt_trace_init(mt_trace *t, const mt_env *env, const char *raygen, xrsc_diag *diag);
void mt_trace_fini(mt_trace *t);

/** Fills the views, environment, sun, sizes, seed and emitter count of xf from frame; the
 *  method fills samples, bounces, accumulate, jitter and frame_index. */
void mt_trace_frame_constants(const mt_trace *t, const xrsc_frame *frame, xs_frame *xf);

/** Uploads xf, (clears the accumulation image when clear_accum,) zeroes the ray counter,
 *  traces width x height x 2 (pass "trace"), reads back the counter and timings. Waits. */
xrsc_result mt_trace_run(mt_trace *t, const xs_frame *xf, bool clear_accum, xrsc_diag *diag);

size_t mt_trace_output_size(const mt_trace *t, xrsc_output output);
xrsc_result mt_trace_read(mt_trace *t, uint32_t eye, xrsc_output output, void *dst,
                          size_t dst_size, xrsc_diag *diag);
uint32_t mt_trace_timings(const mt_trace *t, xrsc_pass_timing *out, uint32_t max_count);

#ifdef __cplusplus
}
#endif
