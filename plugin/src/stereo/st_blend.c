// SPDX-License-Identifier: MIT
/**
 * @file st_blend.c
 * @brief The stereo blend pass: none, PFJ23 neighbourhood (seed 004 Eq. 4, 10-11), raw moments
 *        with sharpness R (seed 000 Eq. 5-8, §5.2) — stereo_blend.comp.
 */
#include "st_blend.h"

#include "u_diag.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Near/far of the eyes' projection: only x/w, y/w and w = -z are read by the blend. */
#define ST_NEAR_M 0.05f
#define ST_FAR_M 1000.0f

_Static_assert(XS_ST_MODE_NONE == XRSC_BLEND_NONE && XS_ST_MODE_PFJ23 == XRSC_BLEND_PFJ23 &&
                   XS_ST_MODE_MOMENTS == XRSC_BLEND_MOMENTS,
               "blend modes: public value = shader mode");

static const gpu_binding st_bindings[] = {
    {XS_ST_BIND_PARAMS, GPU_BINDING_UNIFORM_BUFFER, 1},
    {XS_ST_BIND_SRC, GPU_BINDING_STORAGE_IMAGE, 1},
    {XS_ST_BIND_DEPTH, GPU_BINDING_STORAGE_IMAGE, 1},
    {XS_ST_BIND_MU1, GPU_BINDING_STORAGE_IMAGE, 1},
    {XS_ST_BIND_MU2, GPU_BINDING_STORAGE_IMAGE, 1},
    {XS_ST_BIND_OUT, GPU_BINDING_STORAGE_IMAGE, 1},
    {XS_ST_BIND_AUX, GPU_BINDING_STORAGE_IMAGE, 1},
    {XS_ST_BIND_HITID, GPU_BINDING_STORAGE_IMAGE, 1},
};

static bool size_ok(const gpu_image *img, uint32_t w, uint32_t h)
{
    return img && img->image && img->width == w && img->height == h && img->layers >= 2;
}

void st_blend_destroy(st_blend **stp)
{
    if (!stp || !*stp)
        return;
    st_blend *st = *stp;
    if (st->ctx) {
        vkDeviceWaitIdle(st->ctx->device);
        gpu_compute_program_destroy(st->ctx, &st->prog);
        gpu_buffer_destroy(st->ctx, &st->params);
        gpu_image_destroy(st->ctx, &st->src);
        gpu_image_destroy(st->ctx, &st->aux);
        gpu_image_destroy(st->ctx, &st->stub);
        gpu_image_destroy(st->ctx, &st->stub_hitid);
    }
    free(st);
    *stp = NULL;
}

xrsc_result st_blend_create(gpu_context *ctx, uint32_t width, uint32_t height,
                            const st_settings *settings, const st_images *imgs, st_blend **out,
                            xrsc_diag *diag)
{
    *out = NULL;
    st_settings set = settings ? *settings : (st_settings){0};
    if (set.depth_tolerance == 0.0f)
        set.depth_tolerance = XS_ST_DEPTH_TOLERANCE;
    if ((unsigned)set.blend > XRSC_BLEND_MOMENTS)
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "blend", "unknown blend %d",
                          (int)set.blend);
    if (!(set.r >= 0.0f && set.r <= 1.0f))
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "blend_r",
                          "R = %g is not in [0, 1]", (double)set.r);
    if (!(set.depth_tolerance > 0.0f))
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "depth_tolerance",
                          "%g", (double)set.depth_tolerance);
    if (!imgs || !size_ok(imgs->color, width, height) || !size_ok(imgs->depth, width, height))
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "images",
                          "colour and depth of %u x %u x 2 needed", width, height);
    bool have_mu = size_ok(imgs->mu1, width, height) && size_ok(imgs->mu2, width, height);
    if (set.blend == XRSC_BLEND_MOMENTS && !have_mu)
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "blend",
                          "the moments blend needs the method's mu_1/mu_2 (spp, samplecache)");
    st_blend *st = calloc(1, sizeof(*st));
    if (!st)
        return u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, "", 0, "", "out of memory");
    st->ctx = ctx;
    st->width = width;
    st->height = height;
    st->set = set;
    xrsc_result res;
    if ((res = gpu_compute_program_create(ctx, "stereo_blend.comp", st_bindings,
                                          sizeof(st_bindings) / sizeof(st_bindings[0]), 0,
                                          &st->prog, diag)) != XRSC_OK ||
        (res = gpu_buffer_create(ctx, sizeof(xs_st_params), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                                 GPU_MEMORY_UPLOAD, &st->params, diag)) != XRSC_OK ||
        (res = gpu_image_create_storage(ctx, VK_FORMAT_R32G32B32A32_SFLOAT, width, height, 2,
                                        &st->src, diag)) != XRSC_OK ||
        (res = gpu_image_create_storage(ctx, VK_FORMAT_R32G32B32A32_SFLOAT, width, height, 2,
                                        &st->aux, diag)) != XRSC_OK ||
        (!have_mu && (res = gpu_image_create_storage(ctx, VK_FORMAT_R32G32B32A32_SFLOAT, 1, 1, 2,
                                                     &st->stub, diag)) != XRSC_OK) ||
        (!imgs->hitid && (res = gpu_image_create_storage(ctx, VK_FORMAT_R32G32B32A32_UINT, 1, 1,
                                                         2, &st->stub_hitid, diag)) != XRSC_OK))
        goto fail;
    memset(st->params.mapped, 0, sizeof(xs_st_params));
    gpu_buffer_flush(ctx, &st->params);
    gpu_descriptors *d = &st->prog.set0;
    gpu_descriptors_write_buffer(ctx, d, XS_ST_BIND_PARAMS, &st->params);
    gpu_descriptors_write_storage_image(ctx, d, XS_ST_BIND_SRC, &st->src);
    gpu_descriptors_write_storage_image(ctx, d, XS_ST_BIND_DEPTH, imgs->depth);
    gpu_descriptors_write_storage_image(ctx, d, XS_ST_BIND_MU1, have_mu ? imgs->mu1 : &st->stub);
    gpu_descriptors_write_storage_image(ctx, d, XS_ST_BIND_MU2, have_mu ? imgs->mu2 : &st->stub);
    gpu_descriptors_write_storage_image(ctx, d, XS_ST_BIND_OUT, imgs->color);
    gpu_descriptors_write_storage_image(ctx, d, XS_ST_BIND_AUX, &st->aux);
    gpu_descriptors_write_storage_image(ctx, d, XS_ST_BIND_HITID,
                                        imgs->hitid ? imgs->hitid : &st->stub_hitid);
    /* remembered for the copy colour -> src */
    st->color = imgs->color;
    st->hitid_given = imgs->hitid != NULL;
    *out = st;
    return XRSC_OK;
fail:
    st_blend_destroy(&st);
    return res;
}

void st_eyes_from_views(const xrsc_view views[2], xs_eye out_eyes[2])
{
    for (int e = 0; e < 2; e++) {
        const xrsc_view *v = &views[e];
        xrsc_pose_view_matrix(v->pose, out_eyes[e].view.m);
        xrsc_pose_to_matrix(v->pose, out_eyes[e].view_inv.m);
        xrsc_fov_projection(v->fov, ST_NEAR_M, ST_FAR_M, out_eyes[e].proj.m);
        out_eyes[e].tan_fov = (xs_vec4){tanf(v->fov.angleLeft), tanf(v->fov.angleRight),
                                        tanf(v->fov.angleUp), tanf(v->fov.angleDown)};
    }
}

void st_blend_use_source(st_blend *st, const gpu_image *src)
{
    if (!st || !src)
        return;
    gpu_descriptors_write_storage_image(st->ctx, &st->prog.set0, XS_ST_BIND_SRC, src);
    gpu_image_destroy(st->ctx, &st->src); /* its own copy is not needed (16 B per pixel) */
}

void st_blend_cmd_record(st_blend *st, VkCommandBuffer cmd, gpu_timer *timer,
                         const xs_eye eyes[2])
{
    if (!st || st->set.blend == XRSC_BLEND_NONE)
        return;
    xs_st_params p = {
        .width = st->width,
        .height = st->height,
        .mode = (uint32_t)st->set.blend,
        .pixel_mean = st->set.pixel_mean ? 1u : 0u,
        .r = st->set.r,
        .depth_tolerance = st->set.depth_tolerance,
        .min_weight = XS_ST_MIN_WEIGHT,
        .instance_test = st->set.instance_test && st->hitid_given ? 1u : 0u,
    };
    memcpy(p.eyes, eyes, sizeof(p.eyes));
    memcpy(st->params.mapped, &p, sizeof(p));
    gpu_buffer_flush(st->ctx, &st->params);

    gpu_cmd_barrier_all(cmd);
    uint32_t pass = timer ? gpu_timer_cmd_begin(cmd, timer, ST_PASS_BLEND) : 0;
    VkImageCopy region = {
        .srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 2},
        .dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 2},
        .extent = {st->width, st->height, 1},
    };
    if (st->src.image) { /* its own copy of the colour (no st_blend_use_source) */
        vkCmdCopyImage(cmd, st->color->image, VK_IMAGE_LAYOUT_GENERAL, st->src.image,
                       VK_IMAGE_LAYOUT_GENERAL, 1, &region);
        gpu_cmd_barrier_all(cmd);
    }
    gpu_compute_program_cmd_dispatch(cmd, &st->prog, NULL,
                                     (st->width + XS_ST_GROUP - 1) / XS_ST_GROUP,
                                     (st->height + XS_ST_GROUP - 1) / XS_ST_GROUP, 2);
    if (timer)
        gpu_timer_cmd_end(cmd, timer, pass);
    gpu_cmd_barrier_all(cmd);
}

/* ---- tests: host images in, host images out ---- */

/** Records a copy of host data (2 layers, tightly packed) into img through staging. */
static xrsc_result stage_upload(gpu_context *ctx, VkCommandBuffer cmd, const gpu_image *img,
                                const void *data, gpu_buffer *staging, xrsc_diag *diag)
{
    VkDeviceSize layer = (VkDeviceSize)img->width * img->height * img->texel_size;
    xrsc_result res = gpu_buffer_create(ctx, 2 * layer, VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                                        GPU_MEMORY_UPLOAD, staging, diag);
    if (res != XRSC_OK)
        return res;
    memcpy(staging->mapped, data, 2 * layer);
    gpu_buffer_flush(ctx, staging);
    VkBufferImageCopy regions[2];
    for (uint32_t l = 0; l < 2; l++)
        regions[l] = (VkBufferImageCopy){
            .bufferOffset = l * layer,
            .imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, l, 1},
            .imageExtent = {img->width, img->height, 1},
        };
    vkCmdCopyBufferToImage(cmd, staging->buffer, img->image, VK_IMAGE_LAYOUT_GENERAL, 2,
                           regions);
    return XRSC_OK;
}

xrsc_result st_blend_run_host(gpu_context *ctx, uint32_t width, uint32_t height,
                              const st_settings *settings, const xrsc_view views[2],
                              const float *color, const float *depth, const float *mu1,
                              const float *mu2, float *out_rgba, float *out_aux,
                              xrsc_diag *diag)
{
    enum { IMG_COLOR, IMG_DEPTH, IMG_MU1, IMG_MU2, IMG_COUNT };
    gpu_image img[IMG_COUNT] = {{0}};
    gpu_buffer staging[IMG_COUNT] = {{0}};
    const void *data[IMG_COUNT] = {color, depth, mu1, mu2};
    st_blend *st = NULL;
    bool have_mu = mu1 && mu2;
    xrsc_result res = XRSC_OK;
    for (int i = 0; i < IMG_COUNT && res == XRSC_OK; i++) {
        if (!data[i])
            continue;
        res = gpu_image_create_storage(ctx,
                                       i == IMG_DEPTH ? VK_FORMAT_R32_SFLOAT
                                                      : VK_FORMAT_R32G32B32A32_SFLOAT,
                                       width, height, 2, &img[i], diag);
    }
    if (res != XRSC_OK)
        goto done;
    st_images imgs = {&img[IMG_COLOR], &img[IMG_DEPTH], have_mu ? &img[IMG_MU1] : NULL,
                      have_mu ? &img[IMG_MU2] : NULL, NULL};
    if ((res = st_blend_create(ctx, width, height, settings, &imgs, &st, diag)) != XRSC_OK)
        goto done;
    VkCommandBuffer cmd;
    if ((res = gpu_cmd_begin(ctx, &cmd, diag)) != XRSC_OK)
        goto done;
    gpu_cmd_barrier_all(cmd);
    for (int i = 0; i < IMG_COUNT && res == XRSC_OK; i++)
        if (data[i])
            res = stage_upload(ctx, cmd, &img[i], data[i], &staging[i], diag);
    if (res != XRSC_OK) {
        gpu_cmd_submit_wait(ctx, cmd, NULL);
        goto done;
    }
    xs_eye eyes[2];
    st_eyes_from_views(views, eyes);
    st_blend_cmd_record(st, cmd, NULL, eyes);
    if ((res = gpu_cmd_submit_wait(ctx, cmd, diag)) != XRSC_OK)
        goto done;
    size_t layer = (size_t)width * height * 4 * sizeof(float);
    for (uint32_t e = 0; e < 2 && res == XRSC_OK; e++) {
        res = gpu_image_read_layer(ctx, &img[IMG_COLOR], e, out_rgba + e * layer / sizeof(float),
                                   layer, diag);
        if (res == XRSC_OK && out_aux)
            res = gpu_image_read_layer(ctx, &st->aux, e, out_aux + e * layer / sizeof(float),
                                       layer, diag);
    }
done:
    st_blend_destroy(&st);
    for (int i = 0; i < IMG_COUNT; i++) {
        gpu_buffer_destroy(ctx, &staging[i]);
        gpu_image_destroy(ctx, &img[i]);
    }
    return res;
}
