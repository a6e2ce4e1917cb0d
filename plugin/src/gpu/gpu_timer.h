// SPDX-License-Identifier: MIT
/**
 * @file gpu_timer.h
 * @brief Timestamp queries with named passes: GPU milliseconds per pass of one submission.
 */
#pragma once

#include "gpu_context.h"

#ifdef __cplusplus
extern "C" {
#endif

#define GPU_TIMER_MAX_PASSES 16

typedef struct gpu_timer {
    VkQueryPool pool;
    uint32_t pass_count;
    const char *names[GPU_TIMER_MAX_PASSES]; /**< static strings */
    double ms[GPU_TIMER_MAX_PASSES];         /**< valid after gpu_timer_resolve */
    double period_ns;                        /**< timestampPeriod */
    uint64_t valid_mask;                     /**< from timestampValidBits */
} gpu_timer;

/** Creates the query pool (2 queries per pass). A device without timestamps gives a timer
 *  whose passes all read 0 ms. */
xrsc_result gpu_timer_create(gpu_context *ctx, gpu_timer *out, xrsc_diag *diag);
void gpu_timer_destroy(gpu_context *ctx, gpu_timer *timer);
/** Records the reset of all queries and forgets the passes; call first in a command buffer. */
void gpu_timer_cmd_reset(VkCommandBuffer cmd, gpu_timer *timer);
/** Records the start of a pass named name (static string); returns its index or UINT32_MAX
 *  when all GPU_TIMER_MAX_PASSES are used. */
uint32_t gpu_timer_cmd_begin(VkCommandBuffer cmd, gpu_timer *timer, const char *name);
/** Records the end of pass `pass` (from gpu_timer_cmd_begin). */
void gpu_timer_cmd_end(VkCommandBuffer cmd, gpu_timer *timer, uint32_t pass);
/** After the submission completed: reads the queries into ms[]. */
xrsc_result gpu_timer_resolve(gpu_context *ctx, gpu_timer *timer, xrsc_diag *diag);

#ifdef __cplusplus
}
#endif
