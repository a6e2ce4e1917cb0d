// SPDX-License-Identifier: MIT
/**
 * @file mt_samplecache.c
 * @brief Method `samplecache`: the per-eye sample cache of seed 000 §3 (reprojection with
 *        the trace mask, density control, tracing, shading, reconstruction) on compute and
 *        ray-tracing programs, both eyes per dispatch (z = eye).
 */
#include "mt_samplecache.h"

#include "mt_trace.h"
#include "mt_viscache.h"
#include "u_diag.h"
#include "u_half.h"
#include "xs_sc_math.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

_Static_assert(XS_SC_TRACE_SINGLE == XRSC_SC_TRACE_SINGLE - 1 &&
                   XS_SC_TRACE_MULTI == XRSC_SC_TRACE_MULTI - 1 &&
                   XS_SC_TRACE_ADAPTIVE == XRSC_SC_TRACE_ADAPTIVE - 1,
               "trace modes: public value - 1");
_Static_assert(XS_SC_SHADE_UNIFORM == XRSC_SC_SHADE_UNIFORM - 1 &&
                   XS_SC_SHADE_ADAPTIVE == XRSC_SC_SHADE_ADAPTIVE - 1 &&
                   XS_SC_SHADE_ADAPTIVE_VARIANCE == XRSC_SC_SHADE_ADAPTIVE_VARIANCE - 1,
               "shading modes: public value - 1");
_Static_assert(XS_SC_ALPHA_CLAMPED == XRSC_SC_ALPHA_CLAMPED - 1 &&
                   XS_SC_ALPHA_FIXED == XRSC_SC_ALPHA_FIXED - 1,
               "alpha modes: public value - 1");

/* Self-test dispatch width (local_size_x of sc_selftest.comp). */
#define MT_SC_SELFTEST_GROUP 64u
/* Fill value of the closest-depth words: "no sample" for the 64-bit atomicMin. */
#define MT_SC_DEPTH_MIN_NONE 0xFFFFFFFFu

enum {
    PROG_REPROJECT,
    PROG_COPY, /* + the trace mask (issue 19: fused, it only fed the density pass) */
    PROG_DENSITY,
    PROG_SHADE_SELECT,
    PROG_RECONSTRUCT,
    PROG_SHADE_IMPORTANCE,
    PROG_COUNT
};
static const char *const prog_shader[PROG_COUNT] = {
    "sc_reproject.comp",    "sc_copy.comp",        "sc_density.comp",
    "sc_shade_select.comp", "sc_reconstruct.comp", "sc_shade_importance.comp",
};

/* The cache bindings (set 1 of the ray-tracing programs). */
static const gpu_binding cache_bindings[] = {
    {XS_SC_BIND_PARAMS, GPU_BINDING_UNIFORM_BUFFER, 1},
    {XS_SC_BIND_MASK, GPU_BINDING_STORAGE_BUFFER, 1},
    {XS_SC_BIND_FH, GPU_BINDING_STORAGE_BUFFER, 1},
    {XS_SC_BIND_RAD, GPU_BINDING_STORAGE_BUFFER, 1},
    {XS_SC_BIND_DEPTH_MIN, GPU_BINDING_STORAGE_BUFFER, 1},
    {XS_SC_BIND_DEPTH_MAX, GPU_BINDING_STORAGE_BUFFER, 1},
    {XS_SC_BIND_SRC, GPU_BINDING_STORAGE_BUFFER, 1},
    {XS_SC_BIND_PLAN, GPU_BINDING_STORAGE_BUFFER, 1},
    {XS_SC_BIND_STATS, GPU_BINDING_STORAGE_BUFFER, 1},
    {XS_SC_BIND_SHADE_LIST, GPU_BINDING_STORAGE_BUFFER, 1},
    {XS_SC_BIND_FOREIGN, GPU_BINDING_STORAGE_BUFFER, 1},
    {XS_SC_BIND_IDX, GPU_BINDING_STORAGE_BUFFER, 1},
    {XS_SC_BIND_USED, GPU_BINDING_STORAGE_BUFFER, 1},
};
#define CACHE_BINDING_COUNT (sizeof(cache_bindings) / sizeof(cache_bindings[0]))

/* Frame passes after "tlas", in order (mt_samplecache_debug_stop_after). */
enum {
    STAGE_REPROJECT, /* + the trace mask (sc_copy.comp) */
    STAGE_DENSITY,
    STAGE_TRACE,
    STAGE_SHADE,
    STAGE_RECONSTRUCT
};
static const char *const stage_name[] = {MT_SC_PASS_REPROJECT, MT_SC_PASS_DENSITY, MT_SC_PASS_TRACE,
                                         MT_SC_PASS_SHADE, MT_SC_PASS_RECONSTRUCT};
#define STAGE_COUNT (sizeof(stage_name) / sizeof(stage_name[0]))

typedef struct mt_samplecache {
    mt_method base;
    mt_trace trace; /**< sc_trace.rgen + outputs, frame UBO, ray counter, timer, read-back */
    gpu_rt_program shade;
    gpu_compute_program prog[PROG_COUNT];
    gpu_buffer params;         /**< xs_sc_params, host-visible */
    gpu_buffer shade_readback; /**< the shade list's header after the last frame (host) */
    uint32_t shaded;           /**< samples shaded in the last frame, both eyes */
    uint32_t pool_full;        /**< new samples the full pool refused in the last frame */
    uint64_t shade_rays;       /**< rays the shading pass traced in the last frame */
    gpu_buffer mask, fh, rad, depth_min, depth_max, src, plan, stats, shade_list, foreign;
    gpu_buffer idx, used;         /**< the slots' pool addresses, the pool's taken entries */
    xrsc_samplecache_options opt; /**< defaults filled in */
    xs_sc_params p;
    uint32_t plane;      /**< 2 * width * height */
    uint32_t frames;     /**< rendered so far (0: the previous copy must be cleared) */
    uint32_t stop_after; /**< last STAGE_* recorded (debug; STAGE_RECONSTRUCT = all) */
    const struct mt_sc_hybrid *hybrid; /**< `hybrid` (mt_hybrid.c, borrowed), else NULL */
    bool albedo_stale; /**< the last frame's reconstruct left the albedo out (XS_SC_RC_*) */
    mt_viscache vis;   /**< the shading pass's visibility cache (seed 002; not in `hybrid`) */
} mt_samplecache;

_Static_assert(offsetof(mt_samplecache, base) == 0, "base first");

/* Adaptive shading chooses rate x pixels samples in expectation (coin tosses): the shade list
 * holds that with this much headroom (plus the base rate); more are dropped that frame. */
#define MT_SC_SHADE_HEADROOM 1.25

/** Entries of the shade list for both eyes: uniform shading needs one per pixel, and so does
 *  the trace list that uses the same buffer before it (at least one entry per pixel); the
 *  moving-sample rule (moving) and the cover rule (cover) one more per pixel each
 *  (sc_shade_select.comp), at most slots. */
static uint32_t shade_capacity(const xrsc_samplecache_options *o, bool moving, bool cover,
                               uint32_t w, uint32_t h)
{
    double px = 2.0 * w * h;
    double per_pixel = 1.0;
    if (o->shade == XRSC_SC_SHADE_ADAPTIVE || o->shade == XRSC_SC_SHADE_ADAPTIVE_VARIANCE)
        per_pixel = o->shade_rate * MT_SC_SHADE_HEADROOM + 1.0 / ((double)o->block * o->block);
    if (per_pixel > o->slots)
        per_pixel = o->slots;
    if (per_pixel < 1.0)
        per_pixel = 1.0;
    if (moving && per_pixel + 1.0 <= o->slots)
        per_pixel += 1.0;
    if (cover && per_pixel + 1.0 <= o->slots) /* a first frame covers every pixel */
        per_pixel += 1.0;
    return (uint32_t)ceil(px * per_pixel);
}

/** The pool's entries per pixel (XS_SC_POOL_*): isrt fills every cell, so twice its slots
 *  (a pool exactly as large as the cells would leave new samples to find its last free
 *  entries by probing). */
static uint32_t pool_entries_per_pixel(const xrsc_samplecache_options *o, uint32_t isrt_m)
{
    if (isrt_m)
        return XS_SC_POOL_ISRT_FACTOR * o->slots;
    uint32_t k = (uint32_t)ceil(XS_SC_POOL_PER_TARGET * o->n_target);
    if (k < XS_SC_POOL_MIN_PER_PX)
        k = XS_SC_POOL_MIN_PER_PX;
    return k < o->slots ? k : o->slots;
}

static void fill_defaults(xrsc_samplecache_options *o)
{
    if (o->slots == 0)
        o->slots = XS_SC_DEFAULT_SLOTS;
    if (o->n_target == 0.0f)
        o->n_target = (float)XS_SC_DEFAULT_N_TARGET;
    if (o->delta == 0.0f)
        o->delta = (float)XS_SC_DEFAULT_DELTA;
    if (o->eps0 == 0.0f)
        o->eps0 = (float)XS_SC_DEFAULT_EPS0;
    if (o->eps1 == 0.0f)
        o->eps1 = (float)XS_SC_DEFAULT_EPS1;
    if (o->block == 0)
        o->block = XS_SC_DEFAULT_BLOCK;
    if (o->trace == XRSC_SC_TRACE_DEFAULT)
        o->trace = XRSC_SC_TRACE_ADAPTIVE;
    if (o->reproject == XRSC_SC_REPROJECT_DEFAULT)
        o->reproject = XRSC_SC_REPROJECT_1PASS;
    if (o->shade == XRSC_SC_SHADE_DEFAULT)
        o->shade = XRSC_SC_SHADE_UNIFORM;
    if (o->shade_rate == 0.0f)
        o->shade_rate = (float)XS_SC_DEFAULT_SHADE_RATE;
    if (o->alpha == XRSC_SC_ALPHA_DEFAULT)
        o->alpha = XRSC_SC_ALPHA_CLAMPED;
    if (o->alpha_fixed == 0.0f)
        o->alpha_fixed = (float)XS_SC_DEFAULT_ALPHA_FIXED;
    if (o->max_bounces == 0)
        o->max_bounces = XS_DEFAULT_MAX_BOUNCES;
    mt_viscache_fill_defaults(&o->visibility);
}

/** The compute programs' set 0: the ray-tracing programs' set 0 (the compute shaders never
 *  read the TLAS, but gpu_scene_write_descriptors writes it), then the cache's bindings and
 *  the moment images. */
static uint32_t compute_bindings(gpu_binding *out)
{
    uint32_t n0, n = 0;
    const gpu_binding *b0 = gpu_rt_set0_bindings(&n0);
    for (uint32_t i = 0; i < n0; i++)
        out[n++] = b0[i];
    for (uint32_t i = 0; i < CACHE_BINDING_COUNT; i++)
        out[n++] = cache_bindings[i];
    out[n++] = (gpu_binding){XS_SC_BIND_OUT_MU1, GPU_BINDING_STORAGE_IMAGE, 1};
    out[n++] = (gpu_binding){XS_SC_BIND_OUT_MU2, GPU_BINDING_STORAGE_IMAGE, 1};
    return n;
}

static void write_cache(mt_samplecache *s, gpu_descriptors *d)
{
    gpu_context *ctx = s->trace.env.gpu;
    gpu_descriptors_write_buffer(ctx, d, XS_SC_BIND_PARAMS, &s->params);
    gpu_descriptors_write_buffer(ctx, d, XS_SC_BIND_MASK, &s->mask);
    gpu_descriptors_write_buffer(ctx, d, XS_SC_BIND_FH, &s->fh);
    gpu_descriptors_write_buffer(ctx, d, XS_SC_BIND_RAD, &s->rad);
    gpu_descriptors_write_buffer(ctx, d, XS_SC_BIND_DEPTH_MIN, &s->depth_min);
    gpu_descriptors_write_buffer(ctx, d, XS_SC_BIND_DEPTH_MAX, &s->depth_max);
    gpu_descriptors_write_buffer(ctx, d, XS_SC_BIND_SRC, &s->src);
    gpu_descriptors_write_buffer(ctx, d, XS_SC_BIND_PLAN, &s->plan);
    gpu_descriptors_write_buffer(ctx, d, XS_SC_BIND_STATS, &s->stats);
    gpu_descriptors_write_buffer(ctx, d, XS_SC_BIND_SHADE_LIST, &s->shade_list);
    gpu_descriptors_write_buffer(ctx, d, XS_SC_BIND_FOREIGN, &s->foreign);
    gpu_descriptors_write_buffer(ctx, d, XS_SC_BIND_IDX, &s->idx);
    gpu_descriptors_write_buffer(ctx, d, XS_SC_BIND_USED, &s->used);
}

/** Angle subtended by the diagonal of the centre pixel of an eye (Eq. 1's phi). */
static float pixel_phi(const XrFovf *fov, uint32_t w, uint32_t h)
{
    double dx = (tan(fov->angleRight) - tan(fov->angleLeft)) / w;
    double dy = (tan(fov->angleUp) - tan(fov->angleDown)) / h;
    return (float)atan(sqrt(dx * dx + dy * dy));
}

static void cmd_fill(VkCommandBuffer cmd, const gpu_buffer *b, VkDeviceSize offset,
                     VkDeviceSize size, uint32_t value)
{
    vkCmdFillBuffer(cmd, b->buffer, offset, size, value);
}

/* One invocation per pixel of both eyes; push: the program's push constant, or NULL. */
static void dispatch_push(VkCommandBuffer cmd, const mt_samplecache *s, int prog, const void *push)
{
    uint32_t gx = (s->trace.env.width + XS_SC_GROUP - 1) / XS_SC_GROUP;
    uint32_t gy = (s->trace.env.height + XS_SC_GROUP - 1) / XS_SC_GROUP;
    gpu_compute_program_cmd_dispatch(cmd, &s->prog[prog], push, gx, gy, 2);
}

static void dispatch(VkCommandBuffer cmd, const mt_samplecache *s, int prog)
{
    dispatch_push(cmd, s, prog, NULL);
}

/* The frame's reconstruction: the albedo only when it was read after the last frame (then
 * mt_trace stages it at this frame's end) or `hybrid` (its own shader writes it always);
 * other reads of it run sc_reconstruct.comp again (sc_read). */
static void record_reconstruct(mt_samplecache *s, VkCommandBuffer cmd)
{
    bool albedo = s->hybrid || (s->trace.read_mask >> XRSC_OUTPUT_ALBEDO & 1u);
    uint32_t outputs = albedo ? XS_SC_RC_ALL : XS_SC_RC_NO_ALBEDO;
    dispatch_push(cmd, s, PROG_RECONSTRUCT, &outputs);
    s->albedo_stale = !albedo;
}

/** Launches program over a work list of up to `entries` entries (sc_list_entry): blocks of
 *  XS_SC_LIST_BLOCK rows of XS_SC_LIST_WIDTH entries, striped over XS_SC_SHADE_STRIPES bands
 *  of the launch; entries past the list's count exit at once. */
static void cmd_trace_list(gpu_context *ctx, VkCommandBuffer cmd, const gpu_rt_program *program,
                           uint32_t entries)
{
    uint32_t per_block = XS_SC_LIST_WIDTH * XS_SC_LIST_BLOCK;
    uint32_t blocks = (entries + per_block - 1) / per_block;
    uint32_t q = (blocks + XS_SC_SHADE_STRIPES - 1) / XS_SC_SHADE_STRIPES;
    gpu_rt_program_cmd_trace(ctx, cmd, program, NULL, XS_SC_LIST_WIDTH,
                             XS_SC_SHADE_STRIPES * XS_SC_LIST_BLOCK * q, 1);
}

/* Stage "reproject": this copy's masks, statistics and depth words cleared (and on the first
 * frame the previous copy's), the work list's counts too (the density pass appends to it), then
 * sc_reproject.comp and sc_copy.comp (every variant: the order-independent reservation of
 * sc_reproject.comp leaves keys that sc_copy.comp copies; sc_copy.comp also writes the trace
 * mask, from the depth words sc_reproject.comp wrote before the barrier). */
static void record_reproject(mt_samplecache *s, VkCommandBuffer cmd)
{
    VkDeviceSize plane = s->plane, cur = s->p.cur;
    VkDeviceSize cur_plane = cur * plane * sizeof(uint32_t), plane_bytes = plane * sizeof(uint32_t);
    /* Empty history: both copies cleared at once (a second fill of the same bytes would be a
     * write-after-write needing a barrier); later frames clear this copy only. */
    if (s->frames == 0) {
        cmd_fill(cmd, &s->mask, 0, VK_WHOLE_SIZE, 0);
        cmd_fill(cmd, &s->stats, 0, VK_WHOLE_SIZE, 0);
        cmd_fill(cmd, &s->foreign, 0, VK_WHOLE_SIZE, 0);
    } else {
        cmd_fill(cmd, &s->mask, cur_plane, plane_bytes, 0);
        if (s->p.cross_eye)
            cmd_fill(cmd, &s->foreign, cur_plane, plane_bytes, 0);
        cmd_fill(cmd, &s->stats, cur * 2 * sizeof(xs_sc_stats), 2 * sizeof(xs_sc_stats), 0);
    }
    cmd_fill(cmd, &s->depth_min, 0, VK_WHOLE_SIZE, MT_SC_DEPTH_MIN_NONE);
    cmd_fill(cmd, &s->depth_max, 0, VK_WHOLE_SIZE, 0);
    /* the keys: all ones = nothing arrived (XS_SC_SRC_NONE in this copy's pool addresses,
     * which hold the reservation keys until sc_copy.comp; isrt: XS_SC_ISRT_KEY_*) */
    VkDeviceSize idx_copy = (VkDeviceSize)s->opt.slots * plane * sizeof(uint32_t);
    cmd_fill(cmd, &s->idx, cur * idx_copy, idx_copy, XS_SC_SRC_NONE);
    if (s->p.isrt_m)
        cmd_fill(cmd, &s->src, 0, VK_WHOLE_SIZE, 0xFFFFFFFFu);
    cmd_fill(cmd, &s->used, 0, VK_WHOLE_SIZE, 0); /* every pool entry free until taken */
    /* the trace list's count and the pool-full count (one fill: the density pass's own fill
     * and barrier are gone) */
    cmd_fill(cmd, &s->shade_list, 0, 2 * sizeof(uint32_t), 0);
    mt_trace_cmd_rays_reset(&s->trace, cmd);
    gpu_cmd_barrier_all(cmd);
    dispatch(cmd, s, PROG_REPROJECT);
    gpu_cmd_barrier_all(cmd);
    dispatch(cmd, s, PROG_COPY);
}

/* The shade launches: the visibility cache's pre-passes (none when it is off or hybrid), then
 * the shading launch, each reading the same shade list. */
static void record_shade_launches(mt_samplecache *s, VkCommandBuffer cmd)
{
    gpu_context *ctx = s->trace.env.gpu;
    uint32_t pre = s->hybrid ? 0u : mt_viscache_prepasses(&s->vis);
    for (uint32_t i = 0; i <= pre; i++) {
        if (i > 0) {
            gpu_cmd_barrier_all(cmd);
            mt_viscache_cmd_phase(&s->vis, cmd, i);
        }
        cmd_trace_list(ctx, cmd, &s->shade, s->p.shade_capacity);
    }
}

/* Records frame stage `stage` (STAGE_*), the work inside its timer pass. */
static void record_stage(mt_samplecache *s, VkCommandBuffer cmd, uint32_t stage)
{
    gpu_context *ctx = s->trace.env.gpu;
    uint32_t w = s->trace.env.width, h = s->trace.env.height;
    switch (stage) {
    case STAGE_REPROJECT:
        record_reproject(s, cmd);
        break;
    case STAGE_DENSITY: /* the trace list's count was cleared with the reprojection's */
        dispatch(cmd, s, PROG_DENSITY);
        break;
    case STAGE_TRACE:
        if (s->p.trace_mode == XS_SC_TRACE_ADAPTIVE) /* the trace list: each pixel at most once */
            cmd_trace_list(ctx, cmd, &s->trace.program, s->plane);
        else
            gpu_rt_program_cmd_trace(ctx, cmd, &s->trace.program, NULL, w, h, 2);
        break;
    case STAGE_SHADE: /* the list's count and ray count */
        if (!s->hybrid)
            mt_viscache_cmd_begin(&s->vis, cmd);
        cmd_fill(cmd, &s->shade_list, 0, sizeof(uint32_t), 0); /* not the pool's count */
        cmd_fill(cmd, &s->shade_list, 2 * sizeof(uint32_t), sizeof(uint64_t), 0);
        gpu_cmd_barrier_all(cmd);
        if (s->p.shade_mode == XS_SC_SHADE_ADAPTIVE_VARIANCE) { /* this frame's histogram */
            dispatch(cmd, s, PROG_SHADE_IMPORTANCE);
            gpu_cmd_barrier_all(cmd);
        }
        dispatch(cmd, s, PROG_SHADE_SELECT);
        gpu_cmd_barrier_all(cmd);
        record_shade_launches(s, cmd);
        break;
    case STAGE_RECONSTRUCT:
        record_reconstruct(s, cmd);
        break;
    }
}

/* Ends the frame's command buffer (the hybrid's statistics, the ray and shade counts, the
 * outputs read last frame), submits it, waits, and reads the counts and timings back. */
static xrsc_result sc_finish(mt_samplecache *s, VkCommandBuffer cmd, xrsc_diag *diag)
{
    mt_trace *t = &s->trace;
    gpu_context *ctx = t->env.gpu;
    if (s->hybrid) /* hybrid: the hash table's statistics */
        s->hybrid->record_end(s->hybrid->user, cmd);
    mt_trace_cmd_rays_copy(t, cmd);
    if (!s->hybrid)
        mt_viscache_cmd_copy(&s->vis, cmd);
    VkBufferCopy count = {0, 0, XS_SC_SHADE_LIST_HEADER * sizeof(uint32_t)};
    vkCmdCopyBuffer(cmd, s->shade_list.buffer, s->shade_readback.buffer, 1, &count);
    mt_trace_cmd_stage_outputs(t, cmd);
    gpu_cmd_barrier_all(cmd);
    xrsc_result res = gpu_cmd_submit_wait(ctx, cmd, diag);
    mt_trace_frame_done(t, res == XRSC_OK);
    if (res != XRSC_OK)
        return res;
    s->frames++;
    if ((res = gpu_timer_resolve(ctx, &t->timer, diag)) != XRSC_OK)
        return res;
    mt_trace_rays_collect(t);
    if (!s->hybrid)
        mt_viscache_collect(&s->vis, ctx);
    gpu_buffer_invalidate(ctx, &s->shade_readback);
    const uint8_t *header = s->shade_readback.mapped;
    memcpy(&s->shaded, header, sizeof(uint32_t));
    memcpy(&s->pool_full, header + sizeof(uint32_t), sizeof(uint32_t));
    memcpy(&s->shade_rays, header + 2 * sizeof(uint32_t), sizeof(uint64_t));
    t->rays += s->shade_rays; /* the shading launch counts its rays there only (one atomic) */
    if (s->shaded > s->p.shade_capacity) /* the rest were dropped, not shaded */
        s->shaded = s->p.shade_capacity;
    return XRSC_OK;
}

static xrsc_result sc_render(mt_method *m, const xrsc_frame *frame, xrsc_diag *diag)
{
    mt_samplecache *s = (mt_samplecache *)m;
    mt_trace *t = &s->trace;
    gpu_context *ctx = t->env.gpu;
    uint32_t w = t->env.width, h = t->env.height;

    xs_frame xf;
    mt_trace_frame_constants(t, frame, &xf);
    xf.max_bounces = s->opt.max_bounces == XRSC_BOUNCES_NONE ? 0u : s->opt.max_bounces;
    xf.jitter = 1;

    s->p.cur = s->frames & 1u;
    s->albedo_stale = false; /* record_reconstruct says otherwise */
    s->p.phi_left = pixel_phi(&frame->views[0].fov, w, h);
    s->p.phi_right = pixel_phi(&frame->views[1].fov, w, h);
    for (int e = 0; e < 2 && s->frames == 0; e++) /* no previous frame (w = 0) */
        s->p.eye_prev[e].w = 0.0f;
    mt_viscache_set_views(&s->vis, frame, w, h);
    memcpy(s->params.mapped, &s->p, sizeof(s->p));
    gpu_buffer_flush(ctx, &s->params);
    for (int e = 0; e < 2; e++) { /* the next frame's xs_sc_params.eye_prev */
        const float *cur = &xf.eyes[e].view_inv.m[12];
        s->p.eye_prev[e] = (xs_vec4){cur[0], cur[1], cur[2], 1.0f};
    }

    VkCommandBuffer cmd;
    xrsc_result res = mt_trace_cmd_frame_begin(t, &xf, &cmd, diag);
    if (res != XRSC_OK)
        return res;
    if (s->hybrid) /* hybrid: the hash table's frame start */
        s->hybrid->record_begin(s->hybrid->user, cmd);
    for (uint32_t stage = 0; stage <= s->stop_after; stage++) {
        uint32_t pass = gpu_timer_cmd_begin(cmd, &t->timer, stage_name[stage]);
        record_stage(s, cmd, stage);
        gpu_timer_cmd_end(cmd, &t->timer, pass);
        gpu_cmd_barrier_all(cmd);
    }
    if (s->stop_after == STAGE_RECONSTRUCT)
        mt_post_record(t->env.post, cmd, &t->timer, &xf); /* the stereo blend, if any */
    return sc_finish(s, cmd, diag);
}

/* Counters: the shading work (seed 000 Fig. 14 compares shading rates) and the cache's size. */
static uint32_t sc_counters(const mt_method *m, xrsc_counter *out, uint32_t max_count)
{
    const mt_samplecache *s = (const mt_samplecache *)m;
    double resident, working;
    mt_samplecache_bytes_per_pixel(m, &resident, &working);
    double px = 2.0 * s->trace.env.width * s->trace.env.height;
    xrsc_counter c[] = {
        {"sc_shaded", (double)s->shaded},
        {"sc_shaded_per_px", (double)s->shaded / px},
        {"sc_shade_rays", (double)s->shade_rays},
        {"sc_bytes_per_px", resident + working},
        {"sc_pool_full", (double)s->pool_full},
    };
    uint32_t n = 0;
    for (; n < max_count && n < sizeof(c) / sizeof(c[0]); n++)
        out[n] = c[n];
    if (!s->hybrid) /* the shading pass's shadow rays and visibility cache (seed 002) */
        n += mt_viscache_counters(&s->vis, out + n, max_count - n);
    return n;
}

static size_t sc_output_size(const mt_method *m, xrsc_output output)
{
    return mt_trace_output_size(&((const mt_samplecache *)m)->trace, output);
}

/* The albedo of the last frame, when its reconstruction left it out: sc_reconstruct.comp
 * again over the same cache, writing the albedo alone (the colour may have been changed by
 * TAA or the blend since). */
static xrsc_result sc_albedo_now(mt_samplecache *s, xrsc_diag *diag)
{
    gpu_context *ctx = s->trace.env.gpu;
    VkCommandBuffer cmd;
    xrsc_result res = gpu_cmd_begin(ctx, &cmd, diag);
    if (res != XRSC_OK)
        return res;
    uint32_t outputs = XS_SC_RC_ALBEDO_ONLY;
    gpu_cmd_barrier_all(cmd);
    dispatch_push(cmd, s, PROG_RECONSTRUCT, &outputs);
    gpu_cmd_barrier_all(cmd);
    if ((res = gpu_cmd_submit_wait(ctx, cmd, diag)) == XRSC_OK)
        s->albedo_stale = false;
    return res;
}

static xrsc_result sc_read(mt_method *m, uint32_t eye, xrsc_output output, void *dst,
                           size_t dst_size, xrsc_diag *diag)
{
    mt_samplecache *s = (mt_samplecache *)m;
    if (output == XRSC_OUTPUT_ALBEDO && s->albedo_stale) {
        xrsc_result res = sc_albedo_now(s, diag);
        if (res != XRSC_OK)
            return res;
    }
    return mt_trace_read(&s->trace, eye, output, dst, dst_size, diag);
}

static const gpu_image *sc_output_image(const mt_method *m, xrsc_output output)
{
    return mt_trace_output_image(&((const mt_samplecache *)m)->trace, output);
}

static uint32_t sc_timings(const mt_method *m, xrsc_pass_timing *out, uint32_t max_count)
{
    return mt_trace_timings(&((const mt_samplecache *)m)->trace, out, max_count);
}

static uint64_t sc_rays(const mt_method *m)
{
    return ((const mt_samplecache *)m)->trace.rays;
}

static void sc_destroy(mt_method *m)
{
    mt_samplecache *s = (mt_samplecache *)m;
    gpu_context *ctx = s->trace.env.gpu;
    if (ctx) {
        vkDeviceWaitIdle(ctx->device);
        for (int i = 0; i < PROG_COUNT; i++)
            gpu_compute_program_destroy(ctx, &s->prog[i]);
        gpu_rt_program_destroy(ctx, &s->shade);
        gpu_buffer_destroy(ctx, &s->used);
        gpu_buffer_destroy(ctx, &s->idx);
        gpu_buffer_destroy(ctx, &s->foreign);
        gpu_buffer_destroy(ctx, &s->shade_list);
        gpu_buffer_destroy(ctx, &s->shade_readback);
        gpu_buffer_destroy(ctx, &s->stats);
        gpu_buffer_destroy(ctx, &s->plan);
        gpu_buffer_destroy(ctx, &s->src);
        gpu_buffer_destroy(ctx, &s->depth_max);
        gpu_buffer_destroy(ctx, &s->depth_min);
        gpu_buffer_destroy(ctx, &s->rad);
        gpu_buffer_destroy(ctx, &s->fh);
        gpu_buffer_destroy(ctx, &s->mask);
        gpu_buffer_destroy(ctx, &s->params);
        mt_viscache_fini(&s->vis, ctx);
        mt_trace_fini(&s->trace);
    }
    free(s);
}

xrsc_result mt_samplecache_create(const mt_env *env, const xrsc_samplecache_options *options,
                                  mt_method **out, xrsc_diag *diag)
{
    return mt_samplecache_create_variant(env, options, NULL, out, diag);
}

/* The options' limits: slots (mask bits, 31-bit addresses), materials (Listing 1's 16 bits),
 * ranges. */
static xrsc_result check_options(const mt_env *env, const xrsc_samplecache_options *o,
                                 const mt_sc_variant *var, uint64_t plane, xrsc_diag *diag)
{
    if (o->slots > XS_SC_MAX_SLOTS)
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "slots",
                          "%u slots > %u (2 mask bits per slot in 32 bits)", o->slots,
                          XS_SC_MAX_SLOTS);
    if (o->slots * plane >= XS_SC_SRC_ADDR_MASK)
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "slots",
                          "%u slots x %ux%u x 2 eyes exceed the 31-bit sample addresses",
                          o->slots, env->width, env->height);
    if (env->cpu_scene && env->cpu_scene->material_count > XS_SC_MAX_MATERIALS)
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "materials",
                          "%u materials > %u (Listing 1 packs 16 material bits)",
                          env->cpu_scene->material_count, XS_SC_MAX_MATERIALS);
    if (o->n_target < 1.0f || o->delta < 0.0f || o->eps0 < 0.0f || o->eps1 < 0.0f ||
        o->shade_rate < 0.0f || !(o->alpha_fixed > 0.0f && o->alpha_fixed <= 1.0f) ||
        !(o->firefly_clamp == 0.0f || o->firefly_clamp >= 1.0f) ||
        o->trace > XRSC_SC_TRACE_ADAPTIVE || o->reproject > XRSC_SC_REPROJECT_2PASS ||
        o->shade > XRSC_SC_SHADE_ADAPTIVE_VARIANCE || o->alpha > XRSC_SC_ALPHA_FIXED)
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "samplecache",
                          "option out of range");
    if (o->cross_eye && var->isrt_m)
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "cross_eye",
                          "cross-eye reuse needs free sample positions, not isrt's fixed cells");
    if (o->cross_eye && var->hybrid)
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "cross_eye",
                          "cross-eye reuse shares per-sample radiance, which hybrid does not keep");
    return mt_viscache_check(&o->visibility, diag);
}

/* The visibility cache's buffers: 2 B_R = the scene bounds' diagonal (seed 002 Eq. 5), eye
 * samples per pixel = the shading rate (uniform shading: one per pixel). */
static xrsc_result create_viscache(mt_samplecache *s, xrsc_diag *diag)
{
    const sc_scene *sc = s->trace.env.cpu_scene;
    double diameter = 0.0;
    for (int i = 0; sc && i < 3; i++) {
        double e = (double)sc->bounds_max[i] - sc->bounds_min[i];
        diameter += e > 0.0 ? e * e : 0.0;
    }
    float rate = s->opt.shade == XRSC_SC_SHADE_UNIFORM ? 1.0f : s->opt.shade_rate;
    return mt_viscache_init(&s->vis, s->trace.env.gpu, &s->opt.visibility, (float)sqrt(diameter),
                            rate, s->trace.env.width, s->trace.env.height, diag);
}

/* Tests only: XRSC_DEBUG_PERMUTE=1 runs the order-sensitive passes' work items in reverse
 * (xs_sc_params.debug_permute), so a result that depends on invocation order shows up on
 * lavapipe, which runs them in a fixed order (tests/gpu/test_order.c). */
static uint32_t debug_permute(void)
{
    const char *v = getenv("XRSC_DEBUG_PERMUTE");
    return v && strcmp(v, "1") == 0 ? 1u : 0u;
}

/* The cache's buffers (xs_samplecache.h) and the moment images. */
static xrsc_result create_buffers(mt_samplecache *s, xrsc_diag *diag)
{
    gpu_context *ctx = s->trace.env.gpu;
    VkDeviceSize plane = s->plane, slot_plane = (VkDeviceSize)s->opt.slots * plane;
    VkDeviceSize pool = (VkDeviceSize)s->p.pool_k * plane; /* pool entries */
    /* isrt's 64-bit keys (XS_SC_ISRT_KEY_*); the sample cache's reservation keys live in this
     * frame's copy of the pool addresses (idx) instead: a stub keeps the binding valid */
    VkDeviceSize src_size = s->p.isrt_m ? slot_plane * sizeof(uint64_t) : 0;
    VkDeviceSize rad_size = s->hybrid ? 16 : pool * XS_SC_RAD_BYTES;
    VkDeviceSize list_size =
        (XS_SC_SHADE_LIST_HEADER + (VkDeviceSize)s->p.shade_capacity) * sizeof(uint32_t);
    xrsc_result res;
    if ((res = gpu_buffer_create(ctx, sizeof(xs_sc_params), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                                 GPU_MEMORY_UPLOAD, &s->params, diag)) != XRSC_OK ||
        (res = gpu_buffer_create(ctx, XS_SC_SHADE_LIST_HEADER * sizeof(uint32_t),
                                 VK_BUFFER_USAGE_TRANSFER_DST_BIT, GPU_MEMORY_READBACK,
                                 &s->shade_readback, diag)) != XRSC_OK ||
        (res = gpu_buffer_create_storage(ctx, 2 * plane * sizeof(uint32_t), &s->mask, diag)) !=
            XRSC_OK ||
        (res = gpu_buffer_create_storage(ctx, pool * 16, &s->fh, diag)) != XRSC_OK ||
        (res = gpu_buffer_create_storage(ctx, 2 * slot_plane * sizeof(uint32_t), &s->idx,
                                         diag)) != XRSC_OK ||
        (res = gpu_buffer_create_storage(ctx, plane * sizeof(uint32_t), &s->used, diag)) !=
            XRSC_OK ||
        (res = gpu_buffer_create_storage(ctx, rad_size, &s->rad, diag)) != XRSC_OK ||
        (res = gpu_buffer_create_storage(ctx, plane * sizeof(uint64_t), &s->depth_min, diag)) !=
            XRSC_OK ||
        (res = gpu_buffer_create_storage(ctx, plane * sizeof(uint32_t), &s->depth_max, diag)) !=
            XRSC_OK ||
        (res = gpu_buffer_create_storage(ctx, src_size, &s->src, diag)) != XRSC_OK ||
        (res = gpu_buffer_create_storage(ctx, plane * 16, &s->plan, diag)) != XRSC_OK ||
        (res = gpu_buffer_create_storage(ctx, 4 * sizeof(xs_sc_stats), &s->stats, diag)) !=
            XRSC_OK ||
        (res = gpu_buffer_create_storage(ctx, list_size, &s->shade_list, diag)) != XRSC_OK ||
        (res = gpu_buffer_create_storage(ctx, s->p.cross_eye ? 2 * plane * sizeof(uint32_t) : 0,
                                         &s->foreign, diag)) != XRSC_OK ||
        (res = create_viscache(s, diag)) != XRSC_OK)
        return res;
    return mt_trace_create_moments(&s->trace, diag);
}

/* The shade program and the compute programs (hybrid: its shade and reconstruct programs,
 * with the cache's bindings and its own). */
static xrsc_result create_programs(mt_samplecache *s, xrsc_diag *diag)
{
    gpu_context *ctx = s->trace.env.gpu;
    gpu_binding cb[GPU_MAX_BINDINGS], sb[GPU_MAX_BINDINGS], hb[GPU_MAX_BINDINGS];
    memcpy(sb, cache_bindings, sizeof(cache_bindings)); /* + the visibility cache's */
    memcpy(sb + CACHE_BINDING_COUNT, mt_viscache_bindings, sizeof(mt_viscache_bindings));
    gpu_rt_program_desc shade_desc = {
        .raygen = "sc_shade.rgen",
        .set1 = sb,
        .set1_count = CACHE_BINDING_COUNT + sizeof(mt_viscache_bindings) / sizeof(gpu_binding)};
    uint32_t cb_count = compute_bindings(cb), hb_count = cb_count;
    const struct mt_sc_hybrid *hy = s->hybrid;
    if (hy) {
        memcpy(sb, cache_bindings, sizeof(cache_bindings));
        memcpy(sb + CACHE_BINDING_COUNT, hy->bindings, hy->binding_count * sizeof(gpu_binding));
        shade_desc = (gpu_rt_program_desc){.raygen = hy->shade_raygen, .set1 = sb,
                                           .set1_count = CACHE_BINDING_COUNT + hy->binding_count};
        memcpy(hb, cb, cb_count * sizeof(gpu_binding));
        memcpy(hb + cb_count, hy->bindings, hy->binding_count * sizeof(gpu_binding));
        hb_count = cb_count + hy->binding_count;
    }
    shade_desc.glass = gpu_scene_glass_count(s->trace.env.scene) > 0;
    shade_desc.viscache = !hy && s->opt.visibility.enabled;
    xrsc_result res = gpu_rt_program_create(ctx, &shade_desc, &s->shade, diag);
    for (int i = 0; res == XRSC_OK && i < PROG_COUNT; i++) {
        bool own = hy && i == PROG_RECONSTRUCT;
        uint32_t push = !hy && i == PROG_RECONSTRUCT ? sizeof(uint32_t) : 0; /* XS_SC_RC_* */
        res = gpu_compute_program_create(ctx, own ? hy->reconstruct_shader : prog_shader[i],
                                         own ? hb : cb, own ? hb_count : cb_count, push,
                                         &s->prog[i], diag);
    }
    return res;
}

/* Every program's descriptors: the scene's set 0, the cache's bindings, the moment images. */
static void write_descriptors(mt_samplecache *s)
{
    gpu_context *ctx = s->trace.env.gpu;
    write_cache(s, &s->trace.program.set1);
    mt_trace_write_set0(&s->trace, &s->shade.set0);
    write_cache(s, &s->shade.set1);
    if (!s->hybrid)
        mt_viscache_write(&s->vis, ctx, &s->shade.set1);
    for (int i = 0; i < PROG_COUNT; i++) {
        gpu_descriptors *d = &s->prog[i].set0;
        mt_trace_write_set0(&s->trace, d);
        write_cache(s, d);
        gpu_descriptors_write_storage_image(ctx, d, XS_SC_BIND_OUT_MU1, &s->trace.mu1);
        gpu_descriptors_write_storage_image(ctx, d, XS_SC_BIND_OUT_MU2, &s->trace.mu2);
    }
    if (s->hybrid) {
        s->hybrid->write(s->hybrid->user, &s->shade.set1);
        s->hybrid->write(s->hybrid->user, &s->prog[PROG_RECONSTRUCT].set0);
    }
}

xrsc_result mt_samplecache_create_variant(const mt_env *env,
                                          const xrsc_samplecache_options *options,
                                          const mt_sc_variant *variant, mt_method **out,
                                          xrsc_diag *diag)
{
    *out = NULL;
    mt_sc_variant var = {0};
    if (variant)
        var = *variant;
    xrsc_samplecache_options o = {0};
    if (options)
        o = *options;
    fill_defaults(&o);
    if (var.isrt_m) { /* isrt [DSK*17]: M x M cells; its own two reprojection steps */
        if (var.isrt_m > XS_SC_ISRT_MAX_M)
            return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "m", "isrt M = %u > %u",
                              var.isrt_m, XS_SC_ISRT_MAX_M);
        o.slots = var.isrt_m * var.isrt_m;
        o.reproject = XRSC_SC_REPROJECT_1PASS;
    }
    uint64_t plane = 2ull * env->width * env->height;
    xrsc_result res = check_options(env, &o, &var, plane, diag);
    if (res != XRSC_OK)
        return res;

    mt_samplecache *s = calloc(1, sizeof(*s));
    if (!s)
        return u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, "", 0, "", "out of memory");
    s->opt = o;
    s->plane = (uint32_t)plane;
    s->stop_after = STAGE_RECONSTRUCT;
    s->p = (xs_sc_params){
        .slots = o.slots,
        .trace_mode = (uint32_t)o.trace - 1u,
        .two_pass = o.reproject == XRSC_SC_REPROJECT_2PASS ? 1u : 0u,
        .shade_cache = o.no_shading_cache ? 0u : 1u,
        .shade_mode = (uint32_t)o.shade - 1u,
        .alpha_mode = (uint32_t)o.alpha - 1u,
        .block = o.block,
        .n_target = o.n_target,
        .delta = o.delta,
        .eps0 = o.eps0,
        .eps1 = o.eps1,
        .shade_rate = o.shade_rate,
        .alpha_fixed = o.alpha_fixed,
        .cross_eye = o.cross_eye ? 1u : 0u,
        .firefly_k = o.firefly_clamp,
        .stratify = o.stratify ? 1u : 0u,
        .debug_permute = debug_permute(),
    };
    /* the moving-sample rule only where instances move: a still scene's work is unchanged */
    s->p.moving = o.moving && gpu_scene_animated(env->scene) ? 1u : 0u;
    /* the cover rule only with variance-guided shading, which leaves pixels unshaded */
    s->p.cover = o.cover && o.shade == XRSC_SC_SHADE_ADAPTIVE_VARIANCE ? 1u : 0u;
    s->p.shade_capacity = shade_capacity(&o, s->p.moving != 0u, s->p.cover != 0u, env->width,
                                         env->height);
    s->p.isrt_m = var.isrt_m;
    s->p.pool_k = pool_entries_per_pixel(&o, var.isrt_m);
    s->hybrid = var.hybrid; /* hybrid: no per-sample radiance; its own shade and reconstruct */
    if (s->hybrid)
        s->p.shade_cache = XS_SC_RAD_NONE;
    s->base = (mt_method){
        .name = var.name ? var.name : "samplecache",
        .render = sc_render,
        .output_size = sc_output_size,
        .read = sc_read,
        .timings = sc_timings,
        .rays_last_frame = sc_rays,
        .destroy = sc_destroy,
        .output_image = sc_output_image,
        .counters = sc_counters,
    };
    gpu_rt_program_desc trace_desc = {
        .raygen = "sc_trace.rgen", .set1 = cache_bindings, .set1_count = CACHE_BINDING_COUNT};
    if ((res = mt_trace_init_program(&s->trace, env, &trace_desc, diag)) != XRSC_OK) {
        free(s);
        return res;
    }
    /* from here on sc_destroy frees whatever was created */
    if ((res = create_buffers(s, diag)) != XRSC_OK || (res = create_programs(s, diag)) != XRSC_OK)
        goto fail;
    write_descriptors(s);
    *out = &s->base;
    return XRSC_OK;
fail:
    sc_destroy(&s->base);
    return res;
}

const xrsc_samplecache_options *mt_samplecache_options(const mt_method *m)
{
    return &((const mt_samplecache *)m)->opt;
}

void mt_samplecache_bytes_per_pixel(const mt_method *m, double *out_resident, double *out_working)
{
    const mt_samplecache *s = (const mt_samplecache *)m;
    double n = s->opt.slots;
    double k = s->p.pool_k, rad = s->p.shade_cache == XS_SC_RAD_NONE ? 0.0 : XS_SC_RAD_BYTES;
    /* per copy: mask 4 B, a 4-byte pool address per slot; one pool of K entries (first hit
     * 16 B, radiance XS_SC_RAD_BYTES) and its 4-byte word of taken entries */
    *out_resident = 2.0 * (4.0 + 4.0 * n) + k * (16.0 + rad) + 4.0 +
                    (s->p.cross_eye ? 2.0 * 4.0 : 0.0); /* the foreign masks */
    /* depth_min 8 + depth_max 4 + plan 16, isrt's 64-bit keys, the shade list (the sample
     * cache's reservation keys use this frame's pool addresses: no bytes of their own) */
    double plane = 2.0 * s->trace.env.width * s->trace.env.height;
    *out_working = 8.0 + 4.0 + 16.0 + (s->p.isrt_m ? 8.0 * n : 0.0) +
                   4.0 * s->p.shade_capacity / plane +
                   (s->vis.p.enabled ? sizeof(uint64_t) * (double)s->vis.p.entries / plane : 0.0);
}

xrsc_result mt_samplecache_debug_stop_after(mt_method *m, const char *pass, xrsc_diag *diag)
{
    mt_samplecache *s = (mt_samplecache *)m;
    if (!pass) {
        s->stop_after = STAGE_RECONSTRUCT;
        return XRSC_OK;
    }
    for (uint32_t i = 0; i < STAGE_COUNT; i++)
        if (!strcmp(pass, stage_name[i])) {
            s->stop_after = i;
            return XRSC_OK;
        }
    return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "pass", "no pass \"%s\"", pass);
}

/* ---- read-back for tests ---- */

/** Reads px radiance records (XS_SC_RAD_BYTES each: four halves) at offset as float rgba. */
static xrsc_result read_radiance(gpu_context *ctx, const gpu_buffer *b, VkDeviceSize offset,
                                 size_t px, float *dst, xrsc_diag *diag)
{
    _Static_assert(XS_SC_RAD_BYTES == 4 * sizeof(uint16_t), "four halves");
    uint16_t *h = malloc(px * XS_SC_RAD_BYTES);
    if (!h)
        return u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, "", 0, "", "out of memory");
    xrsc_result res = gpu_buffer_download(ctx, b, offset, h, px * XS_SC_RAD_BYTES, diag);
    for (size_t i = 0; res == XRSC_OK && i < 4 * px; i++)
        dst[i] = u_half_to_float(h[i]);
    free(h);
    return res;
}

/** The snapshot's slots of eye in copy cur, gathered from the pool through the slots' pool
 *  addresses (out->mask read already); slots without a sample read as zeros. */
static xrsc_result snapshot_slots(mt_samplecache *s, uint32_t eye, uint32_t cur,
                                  mt_sc_snapshot *out, xrsc_diag *diag)
{
    gpu_context *ctx = s->trace.env.gpu;
    size_t px = (size_t)out->width * out->height, n = out->slots;
    size_t pool = (size_t)s->p.pool_k * s->plane;
    bool no_rad = s->p.shade_cache == XS_SC_RAD_NONE; /* hybrid: radiance all zeros */
    uint32_t *idx = out->addr;
    uint32_t *fh = malloc(pool * 16);
    float *rad = no_rad ? NULL : malloc(pool * 16);
    xrsc_result res = XRSC_OK;
    if (!idx || !fh || (!no_rad && !rad)) {
        res = u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, "", 0, "", "out of memory");
        goto done;
    }
    for (size_t k = 0; res == XRSC_OK && k < n; k++)
        res = gpu_buffer_download(ctx, &s->idx,
                                  ((VkDeviceSize)(cur * n + k) * s->plane + eye * px) * 4,
                                  idx + k * px, px * 4, diag);
    if (res != XRSC_OK || (res = gpu_buffer_download(ctx, &s->fh, 0, fh, pool * 16, diag)) !=
                              XRSC_OK ||
        (!no_rad && (res = read_radiance(ctx, &s->rad, 0, pool, rad, diag)) != XRSC_OK))
        goto done;
    memset(out->fh, 0, px * n * 16);
    memset(out->rad, 0, px * n * 16);
    for (size_t k = 0; k < n; k++)
        for (size_t p = 0; p < px; p++) {
            size_t a = idx[k * px + p];
            if (!(out->mask[p] >> k & 1u) || a >= pool) {
                idx[k * px + p] = XS_SC_POOL_NONE;
                continue;
            }
            memcpy(out->fh + (k * px + p) * 4, fh + a * 4, 16);
            if (!no_rad)
                memcpy(out->rad + (k * px + p) * 4, rad + a * 4, 16);
        }
done:
    free(fh);
    free(rad);
    return res;
}

void mt_sc_snapshot_free(mt_sc_snapshot *s)
{
    if (!s)
        return;
    free(s->mask);
    free(s->fh);
    free(s->rad);
    free(s->depth_min);
    free(s->depth_max);
    free(s->plan);
    free(s->foreign);
    free(s->addr);
    memset(s, 0, sizeof(*s));
}

xrsc_result mt_samplecache_snapshot(mt_method *m, uint32_t eye, mt_sc_snapshot *out,
                                    xrsc_diag *diag)
{
    memset(out, 0, sizeof(*out));
    mt_samplecache *s = (mt_samplecache *)m;
    if (eye > 1 || s->frames == 0)
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "eye",
                          "eye %u (or no frame rendered yet)", eye);
    gpu_context *ctx = s->trace.env.gpu;
    uint32_t w = s->trace.env.width, h = s->trace.env.height, n = s->opt.slots;
    size_t px = (size_t)w * h;
    uint32_t cur = (s->frames - 1) & 1u;
    out->width = w;
    out->height = h;
    out->slots = n;
    out->cur = cur;
    out->mask = malloc(px * sizeof(uint32_t));
    out->fh = malloc(px * n * 16);
    out->rad = malloc(px * n * 16);
    out->depth_min = malloc(px * sizeof(uint64_t));
    out->depth_max = malloc(px * sizeof(uint32_t));
    out->plan = malloc(px * 16);
    out->foreign = calloc(px, sizeof(uint32_t));
    out->shade_rays = s->shade_rays;
    out->pool_full = s->pool_full;
    out->addr = malloc(px * n * sizeof(uint32_t));
    xrsc_result res = XRSC_OK;
    if (!out->mask || !out->fh || !out->rad || !out->depth_min || !out->depth_max || !out->plan ||
        !out->foreign || !out->addr) {
        res = u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, "", 0, "", "out of memory");
        goto fail;
    }
    VkDeviceSize plane = s->plane, eye_off = (VkDeviceSize)eye * px;
    if ((res = gpu_buffer_download(ctx, &s->mask, (cur * plane + eye_off) * 4, out->mask, px * 4,
                                   diag)) != XRSC_OK ||
        (res = gpu_buffer_download(ctx, &s->depth_min, eye_off * 8, out->depth_min, px * 8,
                                   diag)) != XRSC_OK ||
        (res = gpu_buffer_download(ctx, &s->depth_max, eye_off * 4, out->depth_max, px * 4,
                                   diag)) != XRSC_OK ||
        (res = gpu_buffer_download(ctx, &s->plan, eye_off * 16, out->plan, px * 16, diag)) !=
            XRSC_OK ||
        (res = gpu_buffer_download(ctx, &s->stats, (cur * 2 + eye) * sizeof(xs_sc_stats),
                                   &out->stats, sizeof(xs_sc_stats), diag)) != XRSC_OK ||
        (res = gpu_buffer_download(ctx, &s->shade_list, 0, &out->shade_count, sizeof(uint32_t),
                                   diag)) != XRSC_OK ||
        (s->p.cross_eye && (res = gpu_buffer_download(ctx, &s->foreign, (cur * plane + eye_off) * 4,
                                                      out->foreign, px * 4, diag)) != XRSC_OK))
        goto fail;
    if ((res = snapshot_slots(s, eye, cur, out, diag)) != XRSC_OK)
        goto fail;
    return XRSC_OK;
fail:
    mt_sc_snapshot_free(out);
    return res;
}

/* ---- device self-test of xs_sc_math.h ---- */

xrsc_result mt_sc_selftest_run(gpu_context *ctx, xs_sc_selftest_io *io, uint32_t count,
                               xrsc_diag *diag)
{
    static const gpu_binding binding = {XS_SC_BIND_SELFTEST, GPU_BINDING_STORAGE_BUFFER, 1};
    gpu_compute_program prog = {0};
    gpu_buffer buf = {0};
    VkDeviceSize size = (VkDeviceSize)count * sizeof(*io);
    xrsc_result res = gpu_compute_program_create(ctx, "sc_selftest.comp", &binding, 1,
                                                 sizeof(uint32_t), &prog, diag);
    if (res != XRSC_OK)
        return res;
    if ((res = gpu_buffer_create_with_data(
             ctx, io, size, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
             &buf, diag)) != XRSC_OK)
        goto done;
    gpu_descriptors_write_buffer(ctx, &prog.set0, XS_SC_BIND_SELFTEST, &buf);
    VkCommandBuffer cmd;
    if ((res = gpu_cmd_begin(ctx, &cmd, diag)) != XRSC_OK)
        goto done;
    gpu_cmd_barrier_all(cmd);
    gpu_compute_program_cmd_dispatch(
        cmd, &prog, &count, (count + MT_SC_SELFTEST_GROUP - 1) / MT_SC_SELFTEST_GROUP, 1, 1);
    if ((res = gpu_cmd_submit_wait(ctx, cmd, diag)) != XRSC_OK)
        goto done;
    res = gpu_buffer_download(ctx, &buf, 0, io, size, diag);
done:
    gpu_buffer_destroy(ctx, &buf);
    gpu_compute_program_destroy(ctx, &prog);
    return res;
}
