// SPDX-License-Identifier: MIT
/**
 * @file gpu_timer.c
 * @brief Timestamp query pool with named passes.
 */
#include "gpu_timer.h"

#include <string.h>

xrsc_result gpu_timer_create(gpu_context *ctx, gpu_timer *out, xrsc_diag *diag)
{
    xrsc_result res = XRSC_OK;
    memset(out, 0, sizeof(*out));
    out->period_ns = ctx->properties.limits.timestampPeriod;
    uint32_t bits = ctx->timestamp_valid_bits;
    out->valid_mask = bits >= 64 ? UINT64_MAX : bits == 0 ? 0 : ((uint64_t)1 << bits) - 1;
    if (bits == 0)
        return XRSC_OK;
    VkQueryPoolCreateInfo qci = {
        .sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO,
        .queryType = VK_QUERY_TYPE_TIMESTAMP,
        .queryCount = 2 * GPU_TIMER_MAX_PASSES,
    };
    GPU_CHECK(res, diag, fail, vkCreateQueryPool(ctx->device, &qci, NULL, &out->pool));
fail:
    return res;
}

void gpu_timer_destroy(gpu_context *ctx, gpu_timer *timer)
{
    if (!timer)
        return;
    if (timer->pool)
        vkDestroyQueryPool(ctx->device, timer->pool, NULL);
    memset(timer, 0, sizeof(*timer));
}

void gpu_timer_cmd_reset(VkCommandBuffer cmd, gpu_timer *timer)
{
    timer->pass_count = 0;
    if (timer->pool)
        vkCmdResetQueryPool(cmd, timer->pool, 0, 2 * GPU_TIMER_MAX_PASSES);
}

uint32_t gpu_timer_cmd_begin(VkCommandBuffer cmd, gpu_timer *timer, const char *name)
{
    if (timer->pass_count >= GPU_TIMER_MAX_PASSES)
        return UINT32_MAX;
    uint32_t pass = timer->pass_count++;
    timer->names[pass] = name;
    timer->ms[pass] = 0.0;
    if (timer->pool)
        vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, timer->pool, 2 * pass);
    return pass;
}

void gpu_timer_cmd_end(VkCommandBuffer cmd, gpu_timer *timer, uint32_t pass)
{
    if (pass < timer->pass_count && timer->pool)
        vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, timer->pool,
                            2 * pass + 1);
}

xrsc_result gpu_timer_resolve(gpu_context *ctx, gpu_timer *timer, xrsc_diag *diag)
{
    xrsc_result res = XRSC_OK;
    if (!timer->pool || timer->pass_count == 0)
        return XRSC_OK;
    uint64_t ts[2 * GPU_TIMER_MAX_PASSES];
    GPU_CHECK(res, diag, fail,
              vkGetQueryPoolResults(ctx->device, timer->pool, 0, 2 * timer->pass_count,
                                    sizeof(ts), ts, sizeof(uint64_t),
                                    VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
    for (uint32_t i = 0; i < timer->pass_count; i++) {
        uint64_t t0 = ts[2 * i] & timer->valid_mask, t1 = ts[2 * i + 1] & timer->valid_mask;
        uint64_t dt = (t1 - t0) & timer->valid_mask;
        timer->ms[i] = (double)dt * timer->period_ns * 1e-6;
    }
fail:
    return res;
}
