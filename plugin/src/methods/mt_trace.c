// SPDX-License-Identifier: MIT
/**
 * @file mt_trace.c
 * @brief Shared resources and the one-trace frame of the `primary` and `spp` methods.
 */
#include "mt_trace.h"

#include "u_diag.h"

#include <math.h>
#include <string.h>

xrsc_result mt_trace_init(mt_trace *t, const mt_env *env, const char *raygen, xrsc_diag *diag)
{
    memset(t, 0, sizeof(*t));
    t->env = *env;
    gpu_context *ctx = env->gpu;
    uint32_t w = env->width, h = env->height;
    xrsc_result res;
    gpu_rt_program_desc desc = {.raygen = raygen};
    if ((res = gpu_rt_program_create(ctx, &desc, &t->program, diag)) != XRSC_OK)
        goto fail;
    /* Formats per xrsc_shared.h: XS_BIND_OUT_* and XS_BIND_ACCUM. */
    if ((res = gpu_image_create_storage(ctx, VK_FORMAT_R32G32B32A32_SFLOAT, w, h, 2, &t->color,
                                        diag)) != XRSC_OK ||
        (res = gpu_image_create_storage(ctx, VK_FORMAT_R32G32B32A32_SFLOAT, w, h, 2, &t->albedo,
                                        diag)) != XRSC_OK ||
        (res = gpu_image_create_storage(ctx, VK_FORMAT_R32_SFLOAT, w, h, 2, &t->depth, diag)) !=
            XRSC_OK ||
        (res = gpu_image_create_storage(ctx, VK_FORMAT_R32G32B32A32_UINT, w, h, 2, &t->hitid,
                                        diag)) != XRSC_OK ||
        (res = gpu_image_create_storage(ctx, VK_FORMAT_R32G32B32A32_SFLOAT, w, h, 2, &t->accum,
                                        diag)) != XRSC_OK)
        goto fail;
    if ((res = gpu_buffer_create(ctx, sizeof(xs_frame), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                                 GPU_MEMORY_UPLOAD, &t->frame_ubo, diag)) != XRSC_OK ||
        (res = gpu_buffer_create(ctx, sizeof(uint64_t),
                                 VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                     VK_BUFFER_USAGE_TRANSFER_SRC_BIT |
                                     VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                 GPU_MEMORY_DEVICE, &t->ray_counter, diag)) != XRSC_OK ||
        (res = gpu_buffer_create(ctx, sizeof(uint64_t), VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                 GPU_MEMORY_READBACK, &t->ray_readback, diag)) != XRSC_OK)
        goto fail;
    memset(t->frame_ubo.mapped, 0, sizeof(xs_frame));
    gpu_buffer_flush(ctx, &t->frame_ubo);
    if ((res = gpu_timer_create(ctx, &t->timer, diag)) != XRSC_OK)
        goto fail;

    gpu_descriptors *set0 = &t->program.set0;
    gpu_scene_write_descriptors(ctx, env->scene, set0);
    gpu_descriptors_write_buffer(ctx, set0, XS_BIND_FRAME, &t->frame_ubo);
    gpu_descriptors_write_storage_image(ctx, set0, XS_BIND_OUT_COLOR, &t->color);
    gpu_descriptors_write_storage_image(ctx, set0, XS_BIND_OUT_ALBEDO, &t->albedo);
    gpu_descriptors_write_storage_image(ctx, set0, XS_BIND_OUT_DEPTH, &t->depth);
    gpu_descriptors_write_storage_image(ctx, set0, XS_BIND_OUT_HITID, &t->hitid);
    gpu_descriptors_write_storage_image(ctx, set0, XS_BIND_ACCUM, &t->accum);
    gpu_descriptors_write_buffer(ctx, set0, XS_BIND_RAY_COUNTER, &t->ray_counter);
    return XRSC_OK;
fail:
    mt_trace_fini(t);
    return res;
}

void mt_trace_fini(mt_trace *t)
{
    gpu_context *ctx = t->env.gpu;
    if (!ctx)
        return;
    vkDeviceWaitIdle(ctx->device);
    gpu_timer_destroy(ctx, &t->timer);
    gpu_buffer_destroy(ctx, &t->ray_readback);
    gpu_buffer_destroy(ctx, &t->ray_counter);
    gpu_buffer_destroy(ctx, &t->frame_ubo);
    gpu_image_destroy(ctx, &t->accum);
    gpu_image_destroy(ctx, &t->hitid);
    gpu_image_destroy(ctx, &t->depth);
    gpu_image_destroy(ctx, &t->albedo);
    gpu_image_destroy(ctx, &t->color);
    gpu_rt_program_destroy(ctx, &t->program);
    memset(t, 0, sizeof(*t));
}

static void copy_mat(xs_mat4 *dst, const float m[16]) { memcpy(dst->m, m, sizeof(dst->m)); }

void mt_trace_frame_constants(const mt_trace *t, const xrsc_frame *frame, xs_frame *xf)
{
    memset(xf, 0, sizeof(*xf));
    for (int e = 0; e < 2; e++) {
        const xrsc_view *v = &frame->views[e];
        float m[16];
        xrsc_pose_view_matrix(v->pose, m);
        copy_mat(&xf->eyes[e].view, m);
        xrsc_pose_to_matrix(v->pose, m);
        copy_mat(&xf->eyes[e].view_inv, m);
        xrsc_fov_projection(v->fov, MT_NEAR_M, MT_FAR_M, m);
        copy_mat(&xf->eyes[e].proj, m);
        xf->eyes[e].tan_fov = (xs_vec4){tanf(v->fov.angleLeft), tanf(v->fov.angleRight),
                                        tanf(v->fov.angleUp), tanf(v->fov.angleDown)};
    }
    const sc_scene *s = t->env.cpu_scene;
    xf->environment = (xs_vec4){s->environment[0], s->environment[1], s->environment[2], 0.0f};
    if (s->sun.present) {
        xf->sun_direction =
            (xs_vec4){s->sun.direction[0], s->sun.direction[1], s->sun.direction[2], 1.0f};
        xf->sun_radiance =
            (xs_vec4){s->sun.radiance[0], s->sun.radiance[1], s->sun.radiance[2], 0.0f};
    }
    xf->width = t->env.width;
    xf->height = t->env.height;
    xf->frame_index = frame->frame_index;
    xf->samples_per_pixel = 1;
    xf->emitter_count = gpu_scene_emitter_count(t->env.scene);
    xf->jitter = 0;
    xf->seed = t->env.seed;
}

static void cmd_barrier(VkCommandBuffer cmd, VkPipelineStageFlags src_stage, VkAccessFlags src,
                        VkPipelineStageFlags dst_stage, VkAccessFlags dst)
{
    VkMemoryBarrier mb = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
                          .srcAccessMask = src,
                          .dstAccessMask = dst};
    vkCmdPipelineBarrier(cmd, src_stage, dst_stage, 0, 1, &mb, 0, NULL, 0, NULL);
}

xrsc_result mt_trace_run(mt_trace *t, const xs_frame *xf, bool clear_accum, xrsc_diag *diag)
{
    gpu_context *ctx = t->env.gpu;
    memcpy(t->frame_ubo.mapped, xf, sizeof(*xf));
    gpu_buffer_flush(ctx, &t->frame_ubo);
    VkCommandBuffer cmd;
    xrsc_result res = gpu_cmd_begin(ctx, &cmd, diag);
    if (res != XRSC_OK)
        return res;
    /* Earlier submissions (scene upload, TLAS update, read-backs) before anything here. */
    gpu_cmd_barrier_all(cmd);
    gpu_timer_cmd_reset(cmd, &t->timer);
    if (clear_accum)
        gpu_image_cmd_clear(cmd, &t->accum);
    vkCmdFillBuffer(cmd, t->ray_counter.buffer, 0, sizeof(uint64_t), 0);
    cmd_barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                VK_PIPELINE_STAGE_RAY_TRACING_SHADER_BIT_KHR,
                VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
    uint32_t pass = gpu_timer_cmd_begin(cmd, &t->timer, "trace");
    gpu_rt_program_cmd_trace(ctx, cmd, &t->program, NULL, t->env.width, t->env.height, 2);
    gpu_timer_cmd_end(cmd, &t->timer, pass);
    cmd_barrier(cmd, VK_PIPELINE_STAGE_RAY_TRACING_SHADER_BIT_KHR, VK_ACCESS_SHADER_WRITE_BIT,
                VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
    VkBufferCopy region = {0, 0, sizeof(uint64_t)};
    vkCmdCopyBuffer(cmd, t->ray_counter.buffer, t->ray_readback.buffer, 1, &region);
    cmd_barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
    res = gpu_cmd_submit_wait(ctx, cmd, diag);
    if (res != XRSC_OK)
        return res;
    res = gpu_timer_resolve(ctx, &t->timer, diag);
    if (res != XRSC_OK)
        return res;
    gpu_buffer_invalidate(ctx, &t->ray_readback);
    memcpy(&t->rays, t->ray_readback.mapped, sizeof(uint64_t));
    return XRSC_OK;
}

static const gpu_image *output_image(const mt_trace *t, xrsc_output output)
{
    switch (output) {
    case XRSC_OUTPUT_COLOR:
        return &t->color;
    case XRSC_OUTPUT_ALBEDO:
        return &t->albedo;
    case XRSC_OUTPUT_DEPTH:
        return &t->depth;
    case XRSC_OUTPUT_HIT_ID:
        return &t->hitid;
    }
    return NULL;
}

size_t mt_trace_output_size(const mt_trace *t, xrsc_output output)
{
    const gpu_image *img = output_image(t, output);
    return img ? (size_t)img->width * img->height * img->texel_size : 0;
}

xrsc_result mt_trace_read(mt_trace *t, uint32_t eye, xrsc_output output, void *dst,
                          size_t dst_size, xrsc_diag *diag)
{
    const gpu_image *img = output_image(t, output);
    if (!img || eye > 1)
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "output",
                          "unknown output %d or eye %u", (int)output, eye);
    return gpu_image_read_layer(t->env.gpu, img, eye, dst, dst_size, diag);
}

uint32_t mt_trace_timings(const mt_trace *t, xrsc_pass_timing *out, uint32_t max_count)
{
    uint32_t n = 0;
    for (; n < t->timer.pass_count && n < max_count; n++) {
        out[n].name = t->timer.names[n];
        out[n].gpu_ms = t->timer.ms[n];
    }
    return n;
}
