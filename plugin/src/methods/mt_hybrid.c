// SPDX-License-Identifier: MIT
/**
 * @file mt_hybrid.c
 * @brief Method `hybrid` (seed 000 §4): the sample cache without its shading storage does the
 *        adaptive first-hit tracing and gives stable lookups into the hash cache, which holds
 *        the radiance (mt_hashcache.h), except on view-dependent surfaces (smooth metal,
 *        glass: hc_view_dependent), which get their own path of this frame.
 *
 * A thin wrapper: the inner `samplecache` method (mt_samplecache_create_variant with an
 * mt_sc_hybrid) records every pass; this file owns the hash table, updates its parameters
 * before each frame, reads its statistics after it, and forwards the rest. Deforming
 * (skinned, morphed) surfaces follow their last-frame position in the table as in `hashcache`
 * (xs_hashcache.h): the scene's last-frame posed positions are bound beside the table.
 */
#include "mt_hashcache.h"

#include "gpu_scene.h"
#include "mt_hctable.h"
#include "mt_samplecache.h"
#include "u_diag.h"

#include <stdlib.h>
#include <string.h>

typedef struct mt_hybrid {
    mt_method base;
    mt_method *sc; /**< the inner sample cache (name "hybrid") */
    mt_hctable table;
    const gpu_buffer *prev_pos; /**< the scene's last-frame posed positions, or no_prev_pos */
    gpu_buffer no_prev_pos;     /**< bound as XS_HC_BIND_PREV_POS when no mesh deforms */
    struct mt_sc_hybrid hook;
    gpu_binding bindings[MT_HCTABLE_BINDING_COUNT + 1]; /**< the table's + XS_HC_BIND_PREV_POS */
    uint32_t width, height;
} mt_hybrid;

_Static_assert(offsetof(mt_hybrid, base) == 0, "base first");

static void hook_write(void *user, gpu_descriptors *d)
{
    mt_hybrid *h = user;
    mt_hctable_write(&h->table, d);
    gpu_descriptors_write_buffer(h->table.gpu, d, XS_HC_BIND_PREV_POS, h->prev_pos);
}
static void hook_begin(void *user, VkCommandBuffer cmd)
{
    mt_hctable_cmd_begin(&((mt_hybrid *)user)->table, cmd);
}
static void hook_end(void *user, VkCommandBuffer cmd)
{
    mt_hctable_cmd_end(&((mt_hybrid *)user)->table, cmd);
}

static xrsc_result hy_render(mt_method *m, const xrsc_frame *frame, xrsc_diag *diag)
{
    mt_hybrid *h = (mt_hybrid *)m;
    mt_hctable_frame_begin(&h->table, frame, h->width, h->height);
    xrsc_result res = mt_method_render(h->sc, frame, diag);
    mt_hctable_frame_done(&h->table, res == XRSC_OK);
    return res;
}

static size_t hy_output_size(const mt_method *m, xrsc_output output)
{
    return mt_method_output_size(((const mt_hybrid *)m)->sc, output);
}

static xrsc_result hy_read(mt_method *m, uint32_t eye, xrsc_output output, void *dst,
                           size_t dst_size, xrsc_diag *diag)
{
    return mt_method_read(((mt_hybrid *)m)->sc, eye, output, dst, dst_size, diag);
}

static uint32_t hy_timings(const mt_method *m, xrsc_pass_timing *out, uint32_t max_count)
{
    return mt_method_timings(((const mt_hybrid *)m)->sc, out, max_count);
}

static uint64_t hy_rays(const mt_method *m)
{
    return mt_method_rays_last_frame(((const mt_hybrid *)m)->sc);
}

static const gpu_image *hy_output_image(const mt_method *m, xrsc_output output)
{
    return mt_method_output_image(((const mt_hybrid *)m)->sc, output);
}

static uint32_t hy_counters(const mt_method *m, xrsc_counter *out, uint32_t max_count)
{
    /* the occupancy is counted on the first request after a frame (cached in the table) */
    return mt_hctable_counters(&((mt_hybrid *)m)->table, out, max_count);
}

static void hy_destroy(mt_method *m)
{
    mt_hybrid *h = (mt_hybrid *)m;
    mt_method_destroy(&h->sc);
    if (h->table.gpu) {
        vkDeviceWaitIdle(h->table.gpu->device);
        gpu_buffer_destroy(h->table.gpu, &h->no_prev_pos);
    }
    mt_hctable_fini(&h->table);
    free(h);
}

mt_method *mt_hybrid_samplecache(mt_method *hybrid)
{
    return ((mt_hybrid *)hybrid)->sc;
}

void mt_hybrid_set_deform_follow(mt_method *m, bool follow)
{
    ((mt_hybrid *)m)->table.p.deform_follow = follow ? 1u : 0u;
}

void mt_hybrid_deform_stats(const mt_method *m, uint32_t *out_lookups, uint32_t *out_history)
{
    const mt_hctable *t = &((const mt_hybrid *)m)->table;
    *out_lookups = t->have_last ? t->last.deform_lookups : 0u;
    *out_history = t->have_last ? t->last.deform_history : 0u;
}

xrsc_result mt_hybrid_create(const mt_env *env, const xrsc_samplecache_options *sc,
                             const xrsc_hashcache_options *hc, mt_method **out, xrsc_diag *diag)
{
    *out = NULL;
    xrsc_samplecache_options so = {0};
    if (sc)
        so = *sc;
    if (so.shade == XRSC_SC_SHADE_ADAPTIVE || so.shade == XRSC_SC_SHADE_ADAPTIVE_VARIANCE)
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "shade",
                          "hybrid shades uniformly (adaptive shading needs per-sample counts)");
    if (hc && hc->max_bounces)
        so.max_bounces = hc->max_bounces; /* the path length of the hash-cache updates */
    mt_hybrid *h = calloc(1, sizeof(*h));
    if (!h)
        return u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, "", 0, "", "out of memory");
    h->width = env->width;
    h->height = env->height;
    xrsc_result res = mt_hctable_init(&h->table, env->gpu, hc, diag);
    if (res != XRSC_OK) {
        free(h);
        return res;
    }
    /* deforming surfaces follow their last-frame position (xs_hashcache.h) */
    h->prev_pos = gpu_scene_prev_positions(env->scene);
    h->table.p.deform = h->prev_pos != NULL;
    h->table.p.deform_follow = 1;
    if (!h->prev_pos) {
        res = gpu_buffer_create(env->gpu, 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, GPU_MEMORY_DEVICE,
                                &h->no_prev_pos, diag);
        if (res != XRSC_OK) {
            hy_destroy(&h->base);
            return res;
        }
        h->prev_pos = &h->no_prev_pos;
    }
    uint32_t nb = mt_hctable_bindings(h->bindings);
    h->bindings[nb++] = (gpu_binding){XS_HC_BIND_PREV_POS, GPU_BINDING_STORAGE_BUFFER, 1};
    h->hook = (struct mt_sc_hybrid){
        .shade_raygen = "hc_hybrid_shade.rgen",
        .reconstruct_shader = "hc_hybrid_reconstruct.comp",
        .bindings = h->bindings,
        .binding_count = nb,
        .write = hook_write,
        .record_begin = hook_begin,
        .record_end = hook_end,
        .user = h,
    };
    mt_sc_variant variant = {.name = "hybrid", .hybrid = &h->hook};
    if ((res = mt_samplecache_create_variant(env, &so, &variant, &h->sc, diag)) != XRSC_OK) {
        hy_destroy(&h->base);
        return res;
    }
    h->base = (mt_method){
        .name = "hybrid",
        .render = hy_render,
        .output_size = hy_output_size,
        .read = hy_read,
        .timings = hy_timings,
        .rays_last_frame = hy_rays,
        .destroy = hy_destroy,
        .output_image = hy_output_image,
        .counters = hy_counters,
    };
    *out = &h->base;
    return XRSC_OK;
}
