// SPDX-License-Identifier: MIT
/**
 * @file mt_hashcache.c
 * @brief Method `hashcache`: jittered 1 spp first hits, then per pixel a lookup/reservation in
 *        the world-space hash cache, one secondary path per reserved voxel and the final
 *        colour, in two passes (seed 000 §4; mt_hashcache.h).
 */
#include "mt_hashcache.h"

#include "mt_hctable.h"
#include "mt_trace.h"
#include "u_diag.h"

#include <stdlib.h>
#include <string.h>

/* The first-hit buffer of pass 1 (set 1 of both programs, next to the table in pass 2). */
static const gpu_binding hits_binding = {XS_HC_BIND_HITS, GPU_BINDING_STORAGE_BUFFER, 1};

typedef struct mt_hashcache {
    mt_method base;
    mt_trace trace;       /**< hc_trace.rgen + outputs, frame UBO, ray counter, timer */
    gpu_rt_program shade; /**< hc_shade.rgen */
    gpu_buffer hits;      /**< uvec4 per pixel of both eyes */
    gpu_buffer no_prev_pos; /**< bound as XS_HC_BIND_PREV_POS when no mesh deforms */
    mt_hctable table;
} mt_hashcache;

_Static_assert(offsetof(mt_hashcache, base) == 0, "base first");

static xrsc_result hc_render(mt_method *m, const xrsc_frame *frame, xrsc_diag *diag)
{
    mt_hashcache *s = (mt_hashcache *)m;
    mt_trace *t = &s->trace;
    gpu_context *ctx = t->env.gpu;
    uint32_t w = t->env.width, h = t->env.height;
    xs_frame xf;
    mt_trace_frame_constants(t, frame, &xf);
    uint32_t bounces = s->table.opt.max_bounces;
    xf.max_bounces = bounces == XRSC_BOUNCES_NONE ? 0u : bounces;
    xf.jitter = 1; /* jittered first hits (seed 000 §4) */
    mt_hctable_frame_begin(&s->table, frame, w, h);

    VkCommandBuffer cmd;
    xrsc_result res = mt_trace_cmd_frame_begin(t, &xf, &cmd, diag);
    if (res != XRSC_OK)
        return res;
    mt_hctable_cmd_begin(&s->table, cmd);
    mt_trace_cmd_rays_reset(t, cmd);
    gpu_cmd_barrier_all(cmd);
    uint32_t pass = gpu_timer_cmd_begin(cmd, &t->timer, MT_HC_PASS_TRACE);
    gpu_rt_program_cmd_trace(ctx, cmd, &t->program, NULL, w, h, 2);
    gpu_timer_cmd_end(cmd, &t->timer, pass);
    gpu_cmd_barrier_all(cmd);
    pass = gpu_timer_cmd_begin(cmd, &t->timer, MT_HC_PASS_SHADE);
    gpu_rt_program_cmd_trace(ctx, cmd, &s->shade, NULL, w, h, 2);
    gpu_timer_cmd_end(cmd, &t->timer, pass);
    gpu_cmd_barrier_all(cmd);
    mt_hctable_cmd_end(&s->table, cmd);
    mt_post_record(t->env.post, cmd, &t->timer, &xf); /* TAA, stereo blend, if any */
    gpu_cmd_barrier_all(cmd);
    mt_trace_cmd_rays_copy(t, cmd);
    mt_trace_cmd_stage_outputs(t, cmd);
    gpu_cmd_barrier_all(cmd);
    res = gpu_cmd_submit_wait(ctx, cmd, diag);
    mt_trace_frame_done(t, res == XRSC_OK);
    mt_hctable_frame_done(&s->table, res == XRSC_OK);
    if (res != XRSC_OK)
        return res;
    if ((res = gpu_timer_resolve(ctx, &t->timer, diag)) != XRSC_OK)
        return res;
    mt_trace_rays_collect(t);
    return XRSC_OK;
}

static size_t hc_output_size(const mt_method *m, xrsc_output output)
{
    return mt_trace_output_size(&((const mt_hashcache *)m)->trace, output);
}

static xrsc_result hc_read(mt_method *m, uint32_t eye, xrsc_output output, void *dst,
                           size_t dst_size, xrsc_diag *diag)
{
    return mt_trace_read(&((mt_hashcache *)m)->trace, eye, output, dst, dst_size, diag);
}

static uint32_t hc_timings(const mt_method *m, xrsc_pass_timing *out, uint32_t max_count)
{
    return mt_trace_timings(&((const mt_hashcache *)m)->trace, out, max_count);
}

static uint64_t hc_rays(const mt_method *m)
{
    return ((const mt_hashcache *)m)->trace.rays;
}

static const gpu_image *hc_output_image(const mt_method *m, xrsc_output output)
{
    return mt_trace_output_image(&((const mt_hashcache *)m)->trace, output);
}

static uint32_t hc_counters(const mt_method *m, xrsc_counter *out, uint32_t max_count)
{
    /* the occupancy is counted on the first request after a frame (cached in the table) */
    return mt_hctable_counters(&((mt_hashcache *)m)->table, out, max_count);
}

static void hc_destroy(mt_method *m)
{
    mt_hashcache *s = (mt_hashcache *)m;
    gpu_context *ctx = s->trace.env.gpu;
    if (ctx) {
        vkDeviceWaitIdle(ctx->device);
        gpu_rt_program_destroy(ctx, &s->shade);
        gpu_buffer_destroy(ctx, &s->hits);
        gpu_buffer_destroy(ctx, &s->no_prev_pos);
    }
    mt_hctable_fini(&s->table);
    mt_trace_fini(&s->trace);
    free(s);
}

xrsc_result mt_hashcache_create(const mt_env *env, const xrsc_hashcache_options *options,
                                mt_method **out, xrsc_diag *diag)
{
    *out = NULL;
    mt_hashcache *s = calloc(1, sizeof(*s));
    if (!s)
        return u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, "", 0, "", "out of memory");
    gpu_context *ctx = env->gpu;
    xrsc_result res = mt_hctable_init(&s->table, ctx, options, diag);
    if (res != XRSC_OK) {
        free(s);
        return res;
    }
    gpu_rt_program_desc trace_desc = {
        .raygen = "hc_trace.rgen", .set1 = &hits_binding, .set1_count = 1};
    if ((res = mt_trace_init_program(&s->trace, env, &trace_desc, diag)) != XRSC_OK) {
        mt_hctable_fini(&s->table);
        free(s);
        return res;
    }
    s->base = (mt_method){
        .name = "hashcache",
        .render = hc_render,
        .output_size = hc_output_size,
        .read = hc_read,
        .timings = hc_timings,
        .rays_last_frame = hc_rays,
        .destroy = hc_destroy,
        .output_image = hc_output_image,
        .counters = hc_counters,
    };
    /* from here on hc_destroy frees whatever was created */
    gpu_binding shade_set1[MT_HCTABLE_BINDING_COUNT + 2];
    uint32_t n = mt_hctable_bindings(shade_set1);
    shade_set1[n++] = hits_binding;
    shade_set1[n++] = (gpu_binding){XS_HC_BIND_PREV_POS, GPU_BINDING_STORAGE_BUFFER, 1};
    gpu_rt_program_desc shade_desc = {
        .raygen = "hc_shade.rgen", .set1 = shade_set1, .set1_count = n,
        .glass = gpu_scene_glass_count(env->scene) > 0};
    VkDeviceSize hits_size = 2ull * env->width * env->height * 4 * sizeof(uint32_t);
    if ((res = gpu_buffer_create_storage(ctx, hits_size, &s->hits, diag)) != XRSC_OK ||
        (res = gpu_buffer_create(ctx, 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, GPU_MEMORY_DEVICE,
                                 &s->no_prev_pos, diag)) != XRSC_OK ||
        (res = gpu_rt_program_create(ctx, &shade_desc, &s->shade, diag)) != XRSC_OK) {
        hc_destroy(&s->base);
        return res;
    }
    gpu_descriptors_write_buffer(ctx, &s->trace.program.set1, XS_HC_BIND_HITS, &s->hits);
    /* pass 2: the same set 0 as pass 1 (scene, frame, outputs, ray counter) */
    mt_trace_write_set0(&s->trace, &s->shade.set0);
    mt_hctable_write(&s->table, &s->shade.set1);
    gpu_descriptors_write_buffer(ctx, &s->shade.set1, XS_HC_BIND_HITS, &s->hits);
    /* deforming surfaces follow their last-frame position (xs_hashcache.h) */
    const gpu_buffer *prev_pos = gpu_scene_prev_positions(env->scene);
    s->table.p.deform = prev_pos != NULL;
    s->table.p.deform_follow = 1;
    gpu_descriptors_write_buffer(ctx, &s->shade.set1, XS_HC_BIND_PREV_POS,
                                 prev_pos ? prev_pos : &s->no_prev_pos);
    *out = &s->base;
    return XRSC_OK;
}

void mt_hashcache_set_deform_follow(mt_method *m, bool follow)
{
    ((mt_hashcache *)m)->table.p.deform_follow = follow ? 1u : 0u;
}

void mt_hashcache_deform_stats(const mt_method *m, uint32_t *out_lookups, uint32_t *out_history)
{
    const mt_hctable *t = &((const mt_hashcache *)m)->table;
    *out_lookups = t->have_last ? t->last.deform_lookups : 0u;
    *out_history = t->have_last ? t->last.deform_history : 0u;
}
