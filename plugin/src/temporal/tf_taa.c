// SPDX-License-Identifier: MIT
/**
 * @file tf_taa.c
 * @brief The TAA post-pass: reprojection with camera and instance motion, disocclusion
 *        rejection, YCoCg variance clipping and a fixed alpha ([YLS20]), or seed 004's per-pixel
 *        weights (Eq. 4 with Eq. 10-11, §4.2) — taa.comp.
 */
#include "tf_taa.h"

#include "u_diag.h"

#include <stdlib.h>
#include <string.h>

_Static_assert(XS_TF_MODE_ON == XRSC_TAA_ON && XS_TF_MODE_PFJ23 == XRSC_TAA_PFJ23,
               "TAA modes: public value = shader mode");
_Static_assert(XS_TF_BIND_PARAMS > XS_BIND_RAY_COUNTER, "TAA bindings follow set 0's");

/** Bytes of one instance transform in the transform buffers (a mat4). */
#define TF_XFORM_BYTES 64u

enum { TF_OWN_BINDING_COUNT = 13 };
static const gpu_binding tf_own_bindings[TF_OWN_BINDING_COUNT] = {
    {XS_TF_BIND_PARAMS, GPU_BINDING_UNIFORM_BUFFER, 1},
    {XS_TF_BIND_SRC, GPU_BINDING_STORAGE_IMAGE, 1},
    {XS_TF_BIND_DEPTH, GPU_BINDING_STORAGE_IMAGE, 1},
    {XS_TF_BIND_HITID, GPU_BINDING_STORAGE_IMAGE, 1},
    {XS_TF_BIND_HISTORY, GPU_BINDING_STORAGE_IMAGE, 1},
    {XS_TF_BIND_PREV_GEO, GPU_BINDING_STORAGE_IMAGE, 1},
    {XS_TF_BIND_NEXT_GEO, GPU_BINDING_STORAGE_IMAGE, 1},
    {XS_TF_BIND_OUT, GPU_BINDING_STORAGE_IMAGE, 1},
    {XS_TF_BIND_AUX, GPU_BINDING_STORAGE_IMAGE, 1},
    {XS_TF_BIND_REPROJ, GPU_BINDING_STORAGE_IMAGE, 1},
    {XS_TF_BIND_PREV_XFORM, GPU_BINDING_STORAGE_BUFFER, 1},
    {XS_TF_BIND_NEXT_XFORM, GPU_BINDING_STORAGE_BUFFER, 1},
    {XS_TF_BIND_PREV_POS, GPU_BINDING_STORAGE_BUFFER, 1},
};

struct tf_taa {
    gpu_context *ctx;
    uint32_t width, height, instance_count;
    tf_settings set;
    gpu_compute_program prog;
    gpu_buffer params;    /**< xs_tf_params, host-visible */
    gpu_buffer frame_ubo; /**< xs_frame of the frame being filtered, host-visible */
    gpu_buffer prev_xform, next_xform;
    gpu_buffer no_prev_pos; /**< bound as XS_TF_BIND_PREV_POS when no mesh deforms */
    bool deform;            /**< the scene has deformed meshes (their last-frame positions) */
    gpu_image src, history, prev_geo, next_geo, aux, reproj;
    tf_images imgs; /**< borrowed */
    bool have_history;
    xs_eye prev_eyes[2];
};

static bool size_ok(const gpu_image *img, uint32_t w, uint32_t h)
{
    return img && img->image && img->width == w && img->height == h && img->layers >= 2;
}

void tf_taa_destroy(tf_taa **taap)
{
    if (!taap || !*taap)
        return;
    tf_taa *t = *taap;
    if (t->ctx) {
        vkDeviceWaitIdle(t->ctx->device);
        gpu_compute_program_destroy(t->ctx, &t->prog);
        gpu_buffer_destroy(t->ctx, &t->params);
        gpu_buffer_destroy(t->ctx, &t->frame_ubo);
        gpu_buffer_destroy(t->ctx, &t->prev_xform);
        gpu_buffer_destroy(t->ctx, &t->no_prev_pos);
        gpu_buffer_destroy(t->ctx, &t->next_xform);
        gpu_image *imgs[] = {&t->src, &t->history, &t->prev_geo, &t->next_geo, &t->aux, &t->reproj};
        for (size_t i = 0; i < sizeof(imgs) / sizeof(imgs[0]); i++)
            gpu_image_destroy(t->ctx, imgs[i]);
    }
    free(t);
    *taap = NULL;
}

static xrsc_result check_args(const tf_settings *set, const tf_images *imgs, uint32_t w, uint32_t h,
                              xrsc_diag *diag)
{
    if (set->mode != XRSC_TAA_ON && set->mode != XRSC_TAA_PFJ23)
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "taa.mode",
                          "mode %d is not on or pfj23", (int)set->mode);
    if (!(set->alpha > 0.0f && set->alpha <= 1.0f))
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "taa.alpha",
                          "alpha = %g is not in (0, 1]", (double)set->alpha);
    if ((unsigned)set->history > XRSC_TAA_HISTORY_CATMULL_ROM)
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "taa.history",
                          "history filter %d is not bilinear or catmull-rom", (int)set->history);
    if ((unsigned)set->motion > XRSC_TAA_MOTION_EDGES || !(set->motion_px2 > 0.0f) ||
        !(set->motion_alpha > 0.0f && set->motion_alpha <= 1.0f))
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "taa.motion",
                          "motion rule %d with blur %g px^2 and alpha %g (blur > 0, alpha in "
                          "(0, 1])",
                          (int)set->motion, (double)set->motion_px2, (double)set->motion_alpha);
    if (!imgs || !size_ok(imgs->color, w, h) || !size_ok(imgs->depth, w, h) ||
        !size_ok(imgs->hitid, w, h))
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "images",
                          "TAA needs the method's colour, depth and hit ids of %u x %u x 2", w, h);
    return XRSC_OK;
}

static xrsc_result create_resources(tf_taa *t, xrsc_diag *diag)
{
    gpu_context *ctx = t->ctx;
    uint32_t w = t->width, h = t->height;
    const VkFormat rgba = VK_FORMAT_R32G32B32A32_SFLOAT;
    VkDeviceSize xform_bytes =
        (VkDeviceSize)(t->instance_count ? t->instance_count : 1u) * TF_XFORM_BYTES;
    VkBufferUsageFlags xform_usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                     VK_BUFFER_USAGE_TRANSFER_SRC_BIT |
                                     VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    xrsc_result res;
    if ((res = gpu_buffer_create(ctx, sizeof(xs_tf_params), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                                 GPU_MEMORY_UPLOAD, &t->params, diag)) != XRSC_OK ||
        (res = gpu_buffer_create(ctx, sizeof(xs_frame), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                                 GPU_MEMORY_UPLOAD, &t->frame_ubo, diag)) != XRSC_OK ||
        (res = gpu_buffer_create(ctx, xform_bytes, xform_usage, GPU_MEMORY_DEVICE, &t->prev_xform,
                                 diag)) != XRSC_OK ||
        (res = gpu_buffer_create(ctx, xform_bytes, xform_usage, GPU_MEMORY_DEVICE, &t->next_xform,
                                 diag)) != XRSC_OK ||
        (res = gpu_image_create_storage(ctx, rgba, w, h, 2, &t->src, diag)) != XRSC_OK ||
        (res = gpu_image_create_storage(ctx, rgba, w, h, 2, &t->history, diag)) != XRSC_OK ||
        (res = gpu_image_create_storage(ctx, VK_FORMAT_R32G32_UINT, w, h, 2, &t->prev_geo, diag)) !=
            XRSC_OK ||
        (res = gpu_image_create_storage(ctx, VK_FORMAT_R32G32_UINT, w, h, 2, &t->next_geo, diag)) !=
            XRSC_OK ||
        (res = gpu_image_create_storage(ctx, rgba, w, h, 2, &t->aux, diag)) != XRSC_OK ||
        (res = gpu_buffer_create(ctx, 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, GPU_MEMORY_DEVICE,
                                 &t->no_prev_pos, diag)) != XRSC_OK)
        return res;
    /* without debug the reprojected history is never written: a stub keeps the set complete */
    return gpu_image_create_storage(ctx, rgba, t->set.debug ? w : 1u, t->set.debug ? h : 1u, 2,
                                    &t->reproj, diag);
}

static void write_descriptors(tf_taa *t, gpu_scene *scene)
{
    gpu_context *ctx = t->ctx;
    gpu_descriptors *d = &t->prog.set0;
    /* the scene's vertices and instances (and the rest of set 0, which the shader ignores) */
    gpu_scene_write_descriptors(ctx, scene, d);
    gpu_descriptors_write_buffer(ctx, d, XS_BIND_FRAME, &t->frame_ubo);
    gpu_descriptors_write_buffer(ctx, d, XS_TF_BIND_PARAMS, &t->params);
    gpu_descriptors_write_storage_image(ctx, d, XS_TF_BIND_SRC, &t->src);
    gpu_descriptors_write_storage_image(ctx, d, XS_TF_BIND_DEPTH, t->imgs.depth);
    gpu_descriptors_write_storage_image(ctx, d, XS_TF_BIND_HITID, t->imgs.hitid);
    gpu_descriptors_write_storage_image(ctx, d, XS_TF_BIND_HISTORY, &t->history);
    gpu_descriptors_write_storage_image(ctx, d, XS_TF_BIND_PREV_GEO, &t->prev_geo);
    gpu_descriptors_write_storage_image(ctx, d, XS_TF_BIND_NEXT_GEO, &t->next_geo);
    gpu_descriptors_write_storage_image(ctx, d, XS_TF_BIND_OUT, t->imgs.color);
    gpu_descriptors_write_storage_image(ctx, d, XS_TF_BIND_AUX, &t->aux);
    gpu_descriptors_write_storage_image(ctx, d, XS_TF_BIND_REPROJ, &t->reproj);
    gpu_descriptors_write_buffer(ctx, d, XS_TF_BIND_PREV_XFORM, &t->prev_xform);
    gpu_descriptors_write_buffer(ctx, d, XS_TF_BIND_NEXT_XFORM, &t->next_xform);
    const gpu_buffer *prev_pos = gpu_scene_prev_positions(scene);
    t->deform = prev_pos != NULL && !t->set.no_deform_motion;
    gpu_descriptors_write_buffer(ctx, d, XS_TF_BIND_PREV_POS, prev_pos ? prev_pos : &t->no_prev_pos);
}

xrsc_result tf_taa_create(gpu_context *ctx, gpu_scene *scene, uint32_t instance_count,
                          uint32_t width, uint32_t height, const tf_settings *settings,
                          const tf_images *imgs, tf_taa **out, xrsc_diag *diag)
{
    *out = NULL;
    tf_settings set = settings ? *settings : (tf_settings){0};
    if (set.alpha == 0.0f)
        set.alpha = XS_TF_DEFAULT_ALPHA;
    if (set.history == XRSC_TAA_HISTORY_DEFAULT)
        set.history = XRSC_TAA_HISTORY_BILINEAR;
    if (set.motion_px2 == 0.0f)
        set.motion_px2 = XS_TF_MOTION_PX2;
    if (set.motion_alpha == 0.0f)
        set.motion_alpha = XS_TF_MOTION_ALPHA;
    xrsc_result res = check_args(&set, imgs, width, height, diag);
    if (res != XRSC_OK)
        return res;
    tf_taa *t = calloc(1, sizeof(*t));
    if (!t)
        return u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, "", 0, "", "out of memory");
    t->ctx = ctx;
    t->width = width;
    t->height = height;
    t->instance_count = instance_count;
    t->set = set;
    t->imgs = *imgs;
    /* set 0 = the ray-tracing programs' set 0 + the pass's own bindings */
    gpu_binding bindings[GPU_MAX_BINDINGS];
    uint32_t n0, n = 0;
    const gpu_binding *b0 = gpu_rt_set0_bindings(&n0);
    for (uint32_t i = 0; i < n0; i++)
        bindings[n++] = b0[i];
    for (uint32_t i = 0; i < TF_OWN_BINDING_COUNT; i++)
        bindings[n++] = tf_own_bindings[i];
    if ((res = gpu_compute_program_create(ctx, "taa.comp", bindings, n, 0, &t->prog, diag)) !=
            XRSC_OK ||
        (res = create_resources(t, diag)) != XRSC_OK) {
        tf_taa_destroy(&t);
        return res;
    }
    write_descriptors(t, scene);
    *out = t;
    return XRSC_OK;
}

void tf_taa_reset(tf_taa *taa)
{
    if (taa)
        taa->have_history = false;
}

static void cmd_copy_image(VkCommandBuffer cmd, const gpu_image *src, const gpu_image *dst)
{
    VkImageCopy region = {
        .srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 2},
        .dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 2},
        .extent = {src->width, src->height, 1},
    };
    vkCmdCopyImage(cmd, src->image, VK_IMAGE_LAYOUT_GENERAL, dst->image, VK_IMAGE_LAYOUT_GENERAL, 1,
                   &region);
}

/** Fills the parameters of this frame's dispatch (host-visible, read by this frame only). */
static void upload_constants(tf_taa *t, const xs_frame *xf)
{
    xs_tf_params p = {
        .width = t->width,
        .height = t->height,
        .mode = (uint32_t)t->set.mode,
        .history_valid = t->have_history ? 1u : 0u,
        .alpha = t->set.alpha,
        .gamma = XS_TF_GAMMA,
        .depth_tolerance = XS_TF_DEPTH_TOLERANCE,
        .min_weight = XS_TF_MIN_WEIGHT,
        .instance_count = t->instance_count,
        .debug = t->set.debug ? 1u : 0u,
        .deform = t->deform ? 1u : 0u,
        .history_filter = t->set.history == XRSC_TAA_HISTORY_CATMULL_ROM ? XS_TF_HISTORY_CATMULL_ROM
                                                                         : XS_TF_HISTORY_BILINEAR,
        .motion_px2 = t->set.motion >= XRSC_TAA_MOTION_ON ? t->set.motion_px2 : 0.0f,
        .motion_edges = t->set.motion == XRSC_TAA_MOTION_EDGES,
        .motion_alpha = t->set.motion_alpha,
    };
    memcpy(p.prev_eyes, t->prev_eyes, sizeof(p.prev_eyes));
    memcpy(t->params.mapped, &p, sizeof(p));
    gpu_buffer_flush(t->ctx, &t->params);
    memcpy(t->frame_ubo.mapped, xf, sizeof(*xf));
    gpu_buffer_flush(t->ctx, &t->frame_ubo);
}

void tf_taa_cmd_record(tf_taa *t, VkCommandBuffer cmd, gpu_timer *timer, const xs_frame *xf)
{
    if (!t)
        return;
    upload_constants(t, xf);
    gpu_cmd_barrier_all(cmd);
    uint32_t pass = timer ? gpu_timer_cmd_begin(cmd, timer, TF_PASS_TAA) : 0;
    cmd_copy_image(cmd, t->imgs.color, &t->src);
    gpu_cmd_barrier_all(cmd);
    gpu_compute_program_cmd_dispatch(cmd, &t->prog, NULL,
                                     (t->width + XS_TF_GROUP - 1) / XS_TF_GROUP,
                                     (t->height + XS_TF_GROUP - 1) / XS_TF_GROUP, 2);
    gpu_cmd_barrier_all(cmd);
    /* this frame becomes the history: TAA output, depth + instance, instance transforms */
    cmd_copy_image(cmd, t->imgs.color, &t->history);
    cmd_copy_image(cmd, &t->next_geo, &t->prev_geo);
    VkBufferCopy region = {0, 0, t->prev_xform.size};
    vkCmdCopyBuffer(cmd, t->next_xform.buffer, t->prev_xform.buffer, 1, &region);
    gpu_cmd_barrier_all(cmd); /* before the end stamp: the span holds the copies' completion */
    if (timer)
        gpu_timer_cmd_end(cmd, timer, pass);
    memcpy(t->prev_eyes, xf->eyes, sizeof(t->prev_eyes));
    t->have_history = true;
}

const gpu_image *tf_taa_history(const tf_taa *t)
{
    return t ? &t->history : NULL;
}

xrsc_result tf_taa_read(tf_taa *t, uint32_t eye, tf_image_kind kind, float *dst, size_t dst_size,
                        xrsc_diag *diag)
{
    const gpu_image *img = kind == TF_IMAGE_SRC   ? &t->src
                           : kind == TF_IMAGE_AUX ? &t->aux
                           : t->set.debug         ? &t->reproj
                                                  : NULL;
    if (!img || eye > 1)
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "kind",
                          "image %d of eye %u not kept", (int)kind, eye);
    return gpu_image_read_layer(t->ctx, img, eye, dst, dst_size, diag);
}
