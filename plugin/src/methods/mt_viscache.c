// SPDX-License-Identifier: MIT
/**
 * @file mt_viscache.c
 * @brief The shading pass's shadow visibility cache (seed 002): defaults, buffers, the frame's
 *        parameters and the counters' read-back.
 */
#include "mt_viscache.h"

#include "u_diag.h"

#include <math.h>
#include <stddef.h>
#include <string.h>

_Static_assert(XS_VC_REFINE_ADAPTIVE == XRSC_SC_VIS_REFINE_ADAPTIVE - 1 &&
                   XS_VC_REFINE_STRICT == XRSC_SC_VIS_REFINE_STRICT - 1 &&
                   XS_VC_REFINE_NONE == XRSC_SC_VIS_REFINE_NONE - 1,
               "refinement: public value - 1");

/* Bytes of the table when the cache is off (keeps the binding valid). */
#define MT_VC_STUB_BYTES 16u
/* Limits of the options (xrsc.h). */
#define MT_VC_MAX_BINS 64u
#define MT_VC_MAX_RESOLUTION_BASE 4.0f

const gpu_binding mt_viscache_bindings[2] = {
    {XS_VC_BIND_STATE, GPU_BINDING_STORAGE_BUFFER, 1},
    {XS_VC_BIND_TABLE, GPU_BINDING_STORAGE_BUFFER, 1},
};

void mt_viscache_fill_defaults(xrsc_sc_visibility_options *o)
{
    if (o->error_px == 0.0f)
        o->error_px = (float)XS_VC_DEFAULT_ERROR_PX;
    if (o->levels == 0) { /* §3.6: C_MSR = log2 C_E */
        long l = lround(log2(o->error_px > 0.0f ? o->error_px : 1.0f));
        o->levels = l < 1 ? 1u : l > (long)XS_VC_MAX_LEVELS ? XS_VC_MAX_LEVELS : (uint32_t)l;
    }
    if (o->normal_bins == 0)
        o->normal_bins = XS_VC_DEFAULT_NORMAL_BINS;
    if (o->depth_ratio == 0)
        o->depth_ratio = XS_VC_DEFAULT_DEPTH_RATIO;
    if (o->resolution_base == 0.0f)
        o->resolution_base = (float)XS_VC_DEFAULT_RESOLUTION_BASE;
    if (o->refine == XRSC_SC_VIS_REFINE_DEFAULT)
        o->refine = XRSC_SC_VIS_REFINE_ADAPTIVE;
}

xrsc_result mt_viscache_check(const xrsc_sc_visibility_options *o, xrsc_diag *diag)
{
    const char *field = NULL;
    if (!(o->error_px > 0.0f) || !isfinite(o->error_px))
        field = "visibility.error_px";
    else if (o->levels < 1 || o->levels > XS_VC_MAX_LEVELS)
        field = "visibility.levels";
    else if (o->normal_bins < 1 || o->normal_bins > MT_VC_MAX_BINS)
        field = "visibility.normal_bins";
    else if (o->depth_ratio < 1 || o->depth_ratio > MT_VC_MAX_BINS)
        field = "visibility.depth_ratio";
    else if (!(o->resolution_base > 1.0f && o->resolution_base <= MT_VC_MAX_RESOLUTION_BASE))
        field = "visibility.resolution_base";
    else if (o->refine > XRSC_SC_VIS_REFINE_NONE)
        field = "visibility.refine";
    else if (o->table_entries != 0 &&
             (o->table_entries < XS_VC_MIN_ENTRIES || o->table_entries > XS_VC_MAX_ENTRIES))
        field = "visibility.table_entries";
    if (field)
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, field,
                          "visibility cache option out of range (xrsc.h)");
    return XRSC_OK;
}

/** Default table size: XS_VC_DEFAULT_ENTRIES_PER_PX per pixel of both eyes, a power of two. */
static uint32_t default_entries(uint32_t w, uint32_t h)
{
    uint64_t want = (uint64_t)XS_VC_DEFAULT_ENTRIES_PER_PX * 2u * w * h;
    uint64_t n = XS_VC_MIN_ENTRIES;
    while (n < want && n < XS_VC_MAX_ENTRIES)
        n <<= 1;
    return (uint32_t)n;
}

xrsc_result mt_viscache_init(mt_viscache *v, gpu_context *ctx, const xrsc_sc_visibility_options *o,
                             float scene_diameter_m, float eye_samples_per_px, uint32_t w,
                             uint32_t h, xrsc_diag *diag)
{
    memset(v, 0, sizeof(*v));
    v->p = (xs_vc_params){
        .enabled = o->enabled ? 1u : 0u,
        .refine = (uint32_t)o->refine - 1u,
        .levels = o->levels,
        .entries = o->table_entries ? o->table_entries : default_entries(w, h),
        .error_px = o->error_px,
        .normal_bins = (float)o->normal_bins,
        .depth_ratio = (float)o->depth_ratio,
        .log_resolution_base = logf(o->resolution_base),
        .scene_diameter = scene_diameter_m > 0.0f ? scene_diameter_m : 1.0f,
        .eye_samples_per_px = eye_samples_per_px,
    };
    VkDeviceSize table =
        o->enabled ? 2u * (VkDeviceSize)v->p.entries * sizeof(uint64_t) : MT_VC_STUB_BYTES;
    xrsc_result res;
    if ((res = gpu_buffer_create_storage(ctx, sizeof(xs_vc_state), &v->state, diag)) != XRSC_OK ||
        (res = gpu_buffer_create_storage(ctx, table, &v->table, diag)) != XRSC_OK ||
        (res = gpu_buffer_create(ctx, sizeof(xs_vc_state), VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                 GPU_MEMORY_READBACK, &v->readback, diag)) != XRSC_OK)
        return res;
    return XRSC_OK;
}

void mt_viscache_fini(mt_viscache *v, gpu_context *ctx)
{
    gpu_buffer_destroy(ctx, &v->readback);
    gpu_buffer_destroy(ctx, &v->table);
    gpu_buffer_destroy(ctx, &v->state);
}

void mt_viscache_write(const mt_viscache *v, gpu_context *ctx, gpu_descriptors *d)
{
    gpu_descriptors_write_buffer(ctx, d, XS_VC_BIND_STATE, &v->state);
    gpu_descriptors_write_buffer(ctx, d, XS_VC_BIND_TABLE, &v->table);
}

/** sqrt of the tan-space area of the centre pixel: the footprint per metre at normal view. */
static float pixel_tan(const XrFovf *fov, uint32_t w, uint32_t h)
{
    double dx = (tan(fov->angleRight) - tan(fov->angleLeft)) / w;
    double dy = (tan(fov->angleUp) - tan(fov->angleDown)) / h;
    return (float)sqrt(fabs(dx * dy));
}

void mt_viscache_set_views(mt_viscache *v, const xrsc_frame *frame, uint32_t w, uint32_t h)
{
    v->p.pixel_tan_left = pixel_tan(&frame->views[0].fov, w, h);
    v->p.pixel_tan_right = pixel_tan(&frame->views[1].fov, w, h);
}

/* The phase of shade launch i of a frame with the cache on: request and insert of round 0,
 * 1, ..., then the shading launch. */
static uint32_t launch_phase(const mt_viscache *v, uint32_t launch)
{
    if (launch >= mt_viscache_prepasses(v))
        return XS_VC_PHASE_SHADE;
    return launch % 2u ? XS_VC_PHASE_INSERT(launch / 2u) : XS_VC_PHASE_REQUEST(launch / 2u);
}

void mt_viscache_cmd_begin(const mt_viscache *v, VkCommandBuffer cmd)
{
    xs_vc_state st = {.p = v->p}; /* counters 0 */
    st.p.phase = launch_phase(v, 0);
    vkCmdUpdateBuffer(cmd, v->state.buffer, 0, sizeof(st), &st);
    if (v->p.enabled) { /* Alg. 1 line 1: nil on every frame; claim words all ones */
        VkDeviceSize half = (VkDeviceSize)v->p.entries * sizeof(uint64_t);
        vkCmdFillBuffer(cmd, v->table.buffer, 0, half, 0);
        vkCmdFillBuffer(cmd, v->table.buffer, half, half, 0xFFFFFFFFu);
    }
    gpu_cmd_barrier_all(cmd);
}

uint32_t mt_viscache_prepasses(const mt_viscache *v)
{
    return v->p.enabled ? 2u * v->p.levels : 0u;
}

void mt_viscache_cmd_phase(const mt_viscache *v, VkCommandBuffer cmd, uint32_t launch)
{
    uint32_t phase = launch_phase(v, launch);
    vkCmdUpdateBuffer(cmd, v->state.buffer, offsetof(xs_vc_state, p.phase), sizeof(phase),
                      &phase);
    gpu_cmd_barrier_all(cmd);
}

void mt_viscache_cmd_copy(const mt_viscache *v, VkCommandBuffer cmd)
{
    VkBufferCopy region = {0, 0, sizeof(xs_vc_state)};
    vkCmdCopyBuffer(cmd, v->state.buffer, v->readback.buffer, 1, &region);
}

void mt_viscache_collect(mt_viscache *v, gpu_context *ctx)
{
    gpu_buffer_invalidate(ctx, &v->readback);
    memcpy(&v->last, v->readback.mapped, sizeof(v->last));
}

uint32_t mt_viscache_counters(const mt_viscache *v, xrsc_counter *out, uint32_t max_count)
{
    const xs_vc_state *s = &v->last;
    xrsc_counter c[] = {
        {"vc_shadow_rays", (double)s->shadow_rays},
        {"vc_queries", (double)s->queries},
        {"vc_cached", (double)s->cached},
        {"vc_cached_frac", s->queries ? (double)s->cached / s->queries : 0.0},
    };
    uint32_t n = 0;
    for (; n < max_count && n < sizeof(c) / sizeof(c[0]); n++)
        out[n] = c[n];
    return n;
}
