// SPDX-License-Identifier: MIT
/**
 * @file mt_trace.c
 * @brief Shared resources and the one-trace frame of the `primary`, `spp` and `taa` methods.
 */
#include "mt_trace.h"

#include "u_diag.h"

#include <math.h>
#include <string.h>

xrsc_result mt_trace_init(mt_trace *t, const mt_env *env, const char *raygen, xrsc_diag *diag)
{
    gpu_rt_program_desc desc = {.raygen = raygen};
    return mt_trace_init_program(t, env, &desc, diag);
}

xrsc_result mt_trace_init_program(mt_trace *t, const mt_env *env,
                                  const gpu_rt_program_desc *desc, xrsc_diag *diag)
{
    memset(t, 0, sizeof(*t));
    t->env = *env;
    gpu_context *ctx = env->gpu;
    uint32_t w = env->width, h = env->height;
    xrsc_result res;
    gpu_rt_program_desc d = *desc;
    d.glass = gpu_scene_glass_count(env->scene) > 0;
    if ((res = gpu_rt_program_create(ctx, &d, &t->program, diag)) != XRSC_OK)
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
        (res = gpu_buffer_create_storage(ctx, sizeof(uint64_t), &t->ray_counter, diag)) !=
            XRSC_OK ||
        (res = gpu_buffer_create(ctx, sizeof(uint64_t), VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                 GPU_MEMORY_READBACK, &t->ray_readback, diag)) != XRSC_OK)
        goto fail;
    memset(t->frame_ubo.mapped, 0, sizeof(xs_frame));
    gpu_buffer_flush(ctx, &t->frame_ubo);
    if ((res = gpu_timer_create(ctx, &t->timer, diag)) != XRSC_OK)
        goto fail;

    mt_trace_write_set0(t, &t->program.set0);
    return XRSC_OK;
fail:
    mt_trace_fini(t);
    return res;
}

xrsc_result mt_trace_create_moments(mt_trace *t, xrsc_diag *diag)
{
    gpu_context *ctx = t->env.gpu;
    uint32_t w = t->env.width, h = t->env.height;
    xrsc_result res =
        gpu_image_create_storage(ctx, VK_FORMAT_R32G32B32A32_SFLOAT, w, h, 2, &t->mu1, diag);
    if (res != XRSC_OK)
        return res;
    return gpu_image_create_storage(ctx, VK_FORMAT_R32G32B32A32_SFLOAT, w, h, 2, &t->mu2, diag);
}

void mt_trace_write_set0(const mt_trace *t, gpu_descriptors *d)
{
    gpu_context *ctx = t->env.gpu;
    gpu_scene_write_descriptors(ctx, t->env.scene, d);
    gpu_descriptors_write_buffer(ctx, d, XS_BIND_FRAME, &t->frame_ubo);
    gpu_descriptors_write_storage_image(ctx, d, XS_BIND_OUT_COLOR, &t->color);
    gpu_descriptors_write_storage_image(ctx, d, XS_BIND_OUT_ALBEDO, &t->albedo);
    gpu_descriptors_write_storage_image(ctx, d, XS_BIND_OUT_DEPTH, &t->depth);
    gpu_descriptors_write_storage_image(ctx, d, XS_BIND_OUT_HITID, &t->hitid);
    gpu_descriptors_write_storage_image(ctx, d, XS_BIND_ACCUM, &t->accum);
    gpu_descriptors_write_buffer(ctx, d, XS_BIND_RAY_COUNTER, &t->ray_counter);
}

void mt_trace_fini(mt_trace *t)
{
    gpu_context *ctx = t->env.gpu;
    if (!ctx)
        return;
    vkDeviceWaitIdle(ctx->device);
    gpu_timer_destroy(ctx, &t->timer);
    for (uint32_t o = 0; o < MT_OUTPUT_COUNT; o++)
        gpu_buffer_destroy(ctx, &t->readback[o]);
    gpu_buffer_destroy(ctx, &t->ray_readback);
    gpu_buffer_destroy(ctx, &t->ray_counter);
    gpu_buffer_destroy(ctx, &t->frame_ubo);
    gpu_image_destroy(ctx, &t->mu2);
    gpu_image_destroy(ctx, &t->mu1);
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
        /* a disk sun (the sky's): its cone, xs_env.glsl; 0 keeps the delta light */
        if (s->sun.angular_radius_rad > 0.0f)
            xf->sun_cos_max = (float)cos((double)s->sun.angular_radius_rad);
    }
    xf->env_width = s->env_map.width;
    xf->env_height = s->env_map.height;
    xf->env_sampling = s->env_map.sampling ? 1u : 0u;
    xf->env_rotation = s->env_rotation_rad;
    xf->width = t->env.width;
    xf->height = t->env.height;
    xf->frame_index = frame->frame_index;
    xf->samples_per_pixel = 1;
    xf->emitter_count = gpu_scene_emitter_count(t->env.scene);
    xf->light_count = gpu_scene_light_count(t->env.scene);
    xf->glass_instances = gpu_scene_glass_count(t->env.scene);
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

/** Records passes GPU_PASS_SKIN and GPU_PASS_BLAS_UPDATE (the scene's pending pose, only for
 *  scenes with skins or morph targets) and MT_PASS_TLAS: the scene's pending instance update
 *  (gpu_scene_cmd_update). */
static void cmd_scene_update(mt_trace *t, VkCommandBuffer cmd)
{
    /* skinned and morphed meshes first: the TLAS update takes their new BLAS bounds */
    gpu_scene_cmd_deform(t->env.gpu, t->env.scene, cmd, &t->timer);
    uint32_t pass = gpu_timer_cmd_begin(cmd, &t->timer, MT_PASS_TLAS);
    gpu_scene_cmd_update(t->env.gpu, t->env.scene, cmd);
    gpu_timer_cmd_end(cmd, &t->timer, pass);
}

xrsc_result mt_trace_cmd_frame_begin(mt_trace *t, const xs_frame *xf, VkCommandBuffer *out_cmd,
                                     xrsc_diag *diag)
{
    gpu_context *ctx = t->env.gpu;
    memcpy(t->frame_ubo.mapped, xf, sizeof(*xf));
    gpu_buffer_flush(ctx, &t->frame_ubo);
    VkCommandBuffer cmd;
    xrsc_result res = gpu_cmd_begin(ctx, &cmd, diag);
    if (res != XRSC_OK)
        return res;
    /* Earlier submissions (scene upload, read-backs) before anything here. */
    gpu_cmd_barrier_all(cmd);
    gpu_timer_cmd_reset(cmd, &t->timer);
    cmd_scene_update(t, cmd);
    *out_cmd = cmd;
    return XRSC_OK;
}

xrsc_result mt_trace_run(mt_trace *t, const xs_frame *xf, bool clear_accum, xrsc_diag *diag)
{
    gpu_context *ctx = t->env.gpu;
    VkCommandBuffer cmd;
    xrsc_result res = mt_trace_cmd_frame_begin(t, xf, &cmd, diag);
    if (res != XRSC_OK)
        return res;
    if (clear_accum)
        gpu_image_cmd_clear(cmd, &t->accum);
    mt_trace_cmd_rays_reset(t, cmd);
    cmd_barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                VK_PIPELINE_STAGE_RAY_TRACING_SHADER_BIT_KHR,
                VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
    uint32_t pass = gpu_timer_cmd_begin(cmd, &t->timer, MT_PASS_TRACE);
    gpu_rt_program_cmd_trace(ctx, cmd, &t->program, NULL, t->env.width, t->env.height, 2);
    gpu_timer_cmd_end(cmd, &t->timer, pass);
    mt_post_record(t->env.post, cmd, &t->timer, xf); /* the stereo blend, if any */
    cmd_barrier(cmd, VK_PIPELINE_STAGE_RAY_TRACING_SHADER_BIT_KHR, VK_ACCESS_SHADER_WRITE_BIT,
                VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
    mt_trace_cmd_rays_copy(t, cmd);
    cmd_barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
    mt_trace_cmd_stage_outputs(t, cmd);
    res = gpu_cmd_submit_wait(ctx, cmd, diag);
    mt_trace_frame_done(t, res == XRSC_OK);
    if (res != XRSC_OK)
        return res;
    res = gpu_timer_resolve(ctx, &t->timer, diag);
    if (res != XRSC_OK)
        return res;
    mt_trace_rays_collect(t);
    return XRSC_OK;
}

void mt_trace_cmd_rays_reset(mt_trace *t, VkCommandBuffer cmd)
{
    vkCmdFillBuffer(cmd, t->ray_counter.buffer, 0, sizeof(uint64_t), 0);
}

void mt_trace_cmd_rays_copy(mt_trace *t, VkCommandBuffer cmd)
{
    VkBufferCopy region = {0, 0, sizeof(uint64_t)};
    vkCmdCopyBuffer(cmd, t->ray_counter.buffer, t->ray_readback.buffer, 1, &region);
}

void mt_trace_rays_collect(mt_trace *t)
{
    gpu_buffer_invalidate(t->env.gpu, &t->ray_readback);
    memcpy(&t->rays, t->ray_readback.mapped, sizeof(uint64_t));
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
    case XRSC_OUTPUT_MU1:
        return t->mu1.image ? &t->mu1 : NULL;
    case XRSC_OUTPUT_MU2:
        return t->mu2.image ? &t->mu2 : NULL;
    default:
        break;
    }
    return NULL;
}

const gpu_image *mt_trace_output_image(const mt_trace *t, xrsc_output output)
{
    return output_image(t, output);
}

size_t mt_trace_output_size(const mt_trace *t, xrsc_output output)
{
    const gpu_image *img = output_image(t, output);
    return img ? (size_t)img->width * img->height * img->texel_size : 0;
}

static void cmd_copy_output(VkCommandBuffer cmd, const gpu_image *img, const gpu_buffer *dst)
{
    VkBufferImageCopy regions[2];
    VkDeviceSize layer_bytes = (VkDeviceSize)img->width * img->height * img->texel_size;
    for (uint32_t l = 0; l < 2; l++)
        regions[l] = (VkBufferImageCopy){
            .bufferOffset = l * layer_bytes,
            .imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, l, 1},
            .imageExtent = {img->width, img->height, 1},
        };
    vkCmdCopyImageToBuffer(cmd, img->image, VK_IMAGE_LAYOUT_GENERAL, dst->buffer, 2, regions);
}

void mt_trace_cmd_stage_outputs(mt_trace *t, VkCommandBuffer cmd)
{
    uint32_t mask = 0;
    t->staged_mask = 0; /* this frame overwrites the outputs */
    for (uint32_t o = 0; o < MT_OUTPUT_COUNT; o++)
        if ((t->read_mask >> o & 1u) && t->readback[o].buffer)
            mask |= 1u << o;
    if (!mask)
        return;
    cmd_barrier(cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
                VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT,
                VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
    for (uint32_t o = 0; o < MT_OUTPUT_COUNT; o++)
        if (mask >> o & 1u)
            cmd_copy_output(cmd, output_image(t, (xrsc_output)o), &t->readback[o]);
    cmd_barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
    t->staged_mask = mask; /* made valid by mt_trace_frame_done */
}

void mt_trace_frame_done(mt_trace *t, bool ok)
{
    if (!ok)
        t->staged_mask = 0;
    for (uint32_t o = 0; o < MT_OUTPUT_COUNT; o++)
        if (t->staged_mask >> o & 1u)
            gpu_buffer_invalidate(t->env.gpu, &t->readback[o]);
    t->read_mask = 0;
}

/** Copies both eyes of output o into its read-back buffer now (one submission). */
static xrsc_result stage_output(mt_trace *t, xrsc_output o, xrsc_diag *diag)
{
    gpu_context *ctx = t->env.gpu;
    const gpu_image *img = output_image(t, o);
    xrsc_result res;
    if (!t->readback[o].buffer &&
        (res = gpu_buffer_create(ctx, 2 * (VkDeviceSize)img->width * img->height *
                                          img->texel_size,
                                 VK_BUFFER_USAGE_TRANSFER_DST_BIT, GPU_MEMORY_READBACK,
                                 &t->readback[o], diag)) != XRSC_OK)
        return res;
    VkCommandBuffer cmd;
    if ((res = gpu_cmd_begin(ctx, &cmd, diag)) != XRSC_OK)
        return res;
    gpu_cmd_barrier_all(cmd);
    cmd_copy_output(cmd, img, &t->readback[o]);
    cmd_barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
    if ((res = gpu_cmd_submit_wait(ctx, cmd, diag)) != XRSC_OK)
        return res;
    gpu_buffer_invalidate(ctx, &t->readback[o]);
    t->staged_mask |= 1u << o;
    return XRSC_OK;
}

xrsc_result mt_trace_read(mt_trace *t, uint32_t eye, xrsc_output output, void *dst,
                          size_t dst_size, xrsc_diag *diag)
{
    const gpu_image *img = output_image(t, output);
    if (img && (uint32_t)output >= MT_OUTPUT_COUNT) { /* the moments: not staged */
        if (eye > 1)
            return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "eye", "eye %u", eye);
        return gpu_image_read_layer(t->env.gpu, img, eye, dst, dst_size, diag);
    }
    if (!img || eye > 1 || (uint32_t)output >= MT_OUTPUT_COUNT)
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "output",
                          "unknown output %d or eye %u", (int)output, eye);
    size_t bytes = (size_t)img->width * img->height * img->texel_size;
    if (!dst || dst_size < bytes)
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "dst",
                          "dst_size %zu < %zu", dst_size, bytes);
    t->read_mask |= 1u << output;
    if (!(t->staged_mask >> output & 1u)) {
        xrsc_result res = stage_output(t, output, diag);
        if (res != XRSC_OK)
            return res;
    }
    memcpy(dst, (const uint8_t *)t->readback[output].mapped + eye * bytes, bytes);
    return XRSC_OK;
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
