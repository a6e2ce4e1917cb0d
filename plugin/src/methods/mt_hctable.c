// SPDX-License-Identifier: MIT
/**
 * @file mt_hctable.c
 * @brief The hash cache's table on the C side: buffers, parameters, statistics and counters
 *        (seed 000 §4; the GPU side is shaders/hc_table.glsl).
 */
#include "mt_hctable.h"

#include "u_diag.h"
#include "xs_samplecache.h"

#include <math.h>
#include <string.h>

_Static_assert(XS_HC_LOD_DISTANCE == XRSC_HC_LOD_DISTANCE - 1 &&
                   XS_HC_LOD_DISTANCE_NORMAL == XRSC_HC_LOD_DISTANCE_NORMAL - 1,
               "LoD modes: public value - 1");
_Static_assert(XS_HC_BIND_FIRST > XS_SC_BIND_SELFTEST, "hybrid: after the sample cache's bindings");

/* Bytes per entry (seed 000 §4): the 64-bit stamp + checksum word and the float4. */
#define MT_HC_ENTRY_BYTES (sizeof(uint64_t) + 4 * sizeof(float))
/* At most this many entries: rad[] stays below 4 GiB (32-bit buffer ranges). */
#define MT_HC_MAX_ENTRIES (1u << 27)
/* Fill pattern of rad[] at the first frame: a quiet NaN, so a read of an entry that was
 * never written shows up as a non-finite colour in tests instead of plausible garbage. */
#define MT_HC_RAD_POISON 0x7FC00000u

void mt_hctable_defaults(xrsc_hashcache_options *o)
{
    if (o->table_entries == 0)
        o->table_entries = XS_HC_DEFAULT_TABLE_ENTRIES;
    if (o->lod == XRSC_HC_LOD_DEFAULT)
        o->lod = XRSC_HC_LOD_DISTANCE;
    if (o->voxel_scale == 0.0f)
        o->voxel_scale = (float)XS_HC_DEFAULT_VOXEL_SCALE;
    if (o->max_age == 0)
        o->max_age = XS_HC_DEFAULT_MAX_AGE;
    if (o->max_bounces == 0)
        o->max_bounces = XS_DEFAULT_MAX_BOUNCES;
}

static const gpu_binding table_bindings[MT_HCTABLE_BINDING_COUNT] = {
    {XS_HC_BIND_PARAMS, GPU_BINDING_UNIFORM_BUFFER, 1},
    {XS_HC_BIND_WORDS, GPU_BINDING_STORAGE_BUFFER, 1},
    {XS_HC_BIND_RAD, GPU_BINDING_STORAGE_BUFFER, 1},
    {XS_HC_BIND_STATS, GPU_BINDING_STORAGE_BUFFER, 1},
};

uint32_t mt_hctable_bindings(gpu_binding *out)
{
    memcpy(out, table_bindings, sizeof(table_bindings));
    return MT_HCTABLE_BINDING_COUNT;
}

void mt_hctable_write(const mt_hctable *t, gpu_descriptors *d)
{
    gpu_descriptors_write_buffer(t->gpu, d, XS_HC_BIND_PARAMS, &t->params);
    gpu_descriptors_write_buffer(t->gpu, d, XS_HC_BIND_WORDS, &t->words);
    gpu_descriptors_write_buffer(t->gpu, d, XS_HC_BIND_RAD, &t->rad);
    gpu_descriptors_write_buffer(t->gpu, d, XS_HC_BIND_STATS, &t->stats);
}

xrsc_result mt_hctable_init(mt_hctable *t, gpu_context *ctx, const xrsc_hashcache_options *o,
                            xrsc_diag *diag)
{
    memset(t, 0, sizeof(*t));
    xrsc_hashcache_options opt = {0};
    if (o)
        opt = *o;
    mt_hctable_defaults(&opt);
    opt.table_entries -= opt.table_entries % XS_HC_TILE_ENTRIES;
    if (opt.table_entries < XS_HC_TILE_ENTRIES || opt.table_entries > MT_HC_MAX_ENTRIES)
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "table_entries",
                          "%u entries, not %u..%u", o ? o->table_entries : 0u, XS_HC_TILE_ENTRIES,
                          MT_HC_MAX_ENTRIES);
    if (!(opt.voxel_scale > 0.0f && isfinite(opt.voxel_scale)) ||
        opt.lod > XRSC_HC_LOD_DISTANCE_NORMAL)
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "hashcache",
                          "option out of range (voxel_scale %g, lod %d)", opt.voxel_scale,
                          (int)opt.lod);
    t->gpu = ctx;
    t->opt = opt;
    t->p = (xs_hc_params){
        .max_age = opt.max_age,
        .tiles = opt.table_entries / XS_HC_TILE_ENTRIES,
        .lod_mode = (uint32_t)opt.lod - 1u,
        .jitter = opt.no_voxel_jitter ? 0u : 1u,
        .entries = opt.table_entries,
        .voxel_scale = opt.voxel_scale,
    };
    VkDeviceSize e = opt.table_entries;
    xrsc_result res;
    gpu_binding b[MT_HCTABLE_BINDING_COUNT];
    uint32_t nb = mt_hctable_bindings(b);
    if ((res = gpu_buffer_create(ctx, sizeof(xs_hc_params), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                                 GPU_MEMORY_UPLOAD, &t->params, diag)) != XRSC_OK ||
        (res = gpu_buffer_create_storage(ctx, e * sizeof(uint64_t), &t->words, diag)) != XRSC_OK ||
        (res = gpu_buffer_create_storage(ctx, e * 4 * sizeof(float), &t->rad, diag)) != XRSC_OK ||
        (res = gpu_buffer_create_storage(ctx, sizeof(xs_hc_stats), &t->stats, diag)) != XRSC_OK ||
        (res = gpu_buffer_create(ctx, sizeof(xs_hc_stats), VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                 GPU_MEMORY_READBACK, &t->stats_readback, diag)) != XRSC_OK ||
        (res = gpu_compute_program_create(ctx, "hc_occupancy.comp", b, nb, 0, &t->occupancy,
                                          diag)) != XRSC_OK) {
        mt_hctable_fini(t);
        return res;
    }
    mt_hctable_write(t, &t->occupancy.set0);
    memcpy(t->params.mapped, &t->p, sizeof(t->p));
    gpu_buffer_flush(ctx, &t->params);
    return XRSC_OK;
}

void mt_hctable_fini(mt_hctable *t)
{
    gpu_context *ctx = t->gpu;
    if (!ctx) {
        memset(t, 0, sizeof(*t));
        return;
    }
    vkDeviceWaitIdle(ctx->device);
    gpu_compute_program_destroy(ctx, &t->occupancy);
    gpu_buffer_destroy(ctx, &t->stats_readback);
    gpu_buffer_destroy(ctx, &t->stats);
    gpu_buffer_destroy(ctx, &t->rad);
    gpu_buffer_destroy(ctx, &t->words);
    gpu_buffer_destroy(ctx, &t->params);
    memset(t, 0, sizeof(*t));
}

/** Pixel footprint per metre of distance: the larger tan-space pixel side (image centre). */
static float pixel_footprint(const XrFovf *fov, uint32_t w, uint32_t h)
{
    double dx = (tan(fov->angleRight) - tan(fov->angleLeft)) / w;
    double dy = (tan(fov->angleUp) - tan(fov->angleDown)) / h;
    return (float)(dx > dy ? dx : dy);
}

void mt_hctable_frame_begin(mt_hctable *t, const xrsc_frame *frame, uint32_t w, uint32_t h)
{
    t->frames++;
    t->p.frame = t->frames; /* >= 1: stamp 0 marks entries never used */
    t->p.px_left = pixel_footprint(&frame->views[0].fov, w, h);
    t->p.px_right = pixel_footprint(&frame->views[1].fov, w, h);
    memcpy(t->params.mapped, &t->p, sizeof(t->p));
    gpu_buffer_flush(t->gpu, &t->params);
}

void mt_hctable_cmd_begin(mt_hctable *t, VkCommandBuffer cmd)
{
    if (!t->cleared) {
        vkCmdFillBuffer(cmd, t->words.buffer, 0, VK_WHOLE_SIZE, 0);
        vkCmdFillBuffer(cmd, t->rad.buffer, 0, VK_WHOLE_SIZE, MT_HC_RAD_POISON);
        t->cleared = true;
    }
    vkCmdFillBuffer(cmd, t->stats.buffer, 0, VK_WHOLE_SIZE, 0);
}

void mt_hctable_cmd_end(mt_hctable *t, VkCommandBuffer cmd)
{
    gpu_cmd_barrier_all(cmd);
    VkBufferCopy region = {0, 0, sizeof(xs_hc_stats)};
    vkCmdCopyBuffer(cmd, t->stats.buffer, t->stats_readback.buffer, 1, &region);
}

void mt_hctable_frame_done(mt_hctable *t, bool ok)
{
    t->have_last = ok;
    t->occupancy_known = false;
    if (!ok) {
        t->cleared = false; /* the clear may not have run: redo it */
        return;
    }
    gpu_buffer_invalidate(t->gpu, &t->stats_readback);
    memcpy(&t->last, t->stats_readback.mapped, sizeof(t->last));
}

/** Counts the occupied entries of the last frame into t->last.occupied (one submission). */
static void count_occupancy(mt_hctable *t)
{
    gpu_context *ctx = t->gpu;
    VkCommandBuffer cmd;
    if (gpu_cmd_begin(ctx, &cmd, NULL) != XRSC_OK)
        return;
    gpu_cmd_barrier_all(cmd);
    vkCmdFillBuffer(cmd, t->stats.buffer, offsetof(xs_hc_stats, occupied), sizeof(uint32_t), 0);
    gpu_cmd_barrier_all(cmd);
    uint32_t per_group = XS_HC_SCAN_GROUP * XS_HC_SCAN_PER_INVOCATION;
    gpu_compute_program_cmd_dispatch(cmd, &t->occupancy, NULL,
                                     (t->p.entries + per_group - 1) / per_group, 1, 1);
    gpu_cmd_barrier_all(cmd);
    VkBufferCopy region = {offsetof(xs_hc_stats, occupied), offsetof(xs_hc_stats, occupied),
                           sizeof(uint32_t)};
    vkCmdCopyBuffer(cmd, t->stats.buffer, t->stats_readback.buffer, 1, &region);
    gpu_cmd_barrier_all(cmd);
    if (gpu_cmd_submit_wait(ctx, cmd, NULL) != XRSC_OK)
        return;
    gpu_buffer_invalidate(ctx, &t->stats_readback);
    memcpy(&t->last.occupied,
           (const uint8_t *)t->stats_readback.mapped + offsetof(xs_hc_stats, occupied),
           sizeof(uint32_t));
    t->occupancy_known = true;
}

uint32_t mt_hctable_counters(mt_hctable *t, xrsc_counter *out, uint32_t max_count)
{
    if (!t->have_last)
        return 0;
    if (!t->occupancy_known)
        count_occupancy(t);
    const xs_hc_stats *s = &t->last;
    double entries = t->p.entries;
    const xrsc_counter all[MT_HCTABLE_COUNTER_COUNT] = {
        {"hc_table_bytes", entries * (double)MT_HC_ENTRY_BYTES},
        {"hc_occupancy", t->occupancy_known ? s->occupied / entries : NAN},
        {"hc_probe_mean", s->lookups ? (double)s->probe_sum / s->lookups : 0.0},
        {"hc_probe_max", s->probe_max},
        {"hc_lookups", s->lookups},
        {"hc_inserts", s->inserts},
        {"hc_evictions", s->evictions},
        {"hc_failed_inserts", s->failed},
        {"hc_traced", s->traced},
    };
    uint32_t n = 0;
    for (; n < MT_HCTABLE_COUNTER_COUNT && n < max_count; n++)
        out[n] = all[n];
    return n;
}

xrsc_result mt_hctable_selftest_run(mt_hctable *t, xs_hc_selftest_io *io, uint32_t count,
                                    xrsc_diag *diag)
{
    gpu_context *ctx = t->gpu;
    gpu_binding b[MT_HCTABLE_BINDING_COUNT + 1];
    uint32_t nb = mt_hctable_bindings(b);
    b[nb++] = (gpu_binding){XS_HC_BIND_SELFTEST, GPU_BINDING_STORAGE_BUFFER, 1};
    gpu_compute_program prog = {0};
    gpu_buffer buf = {0};
    VkDeviceSize size = (VkDeviceSize)count * sizeof(*io);
    xrsc_result res = gpu_compute_program_create(ctx, "hc_selftest.comp", b, nb,
                                                 sizeof(uint32_t), &prog, diag);
    if (res != XRSC_OK)
        return res;
    if ((res = gpu_buffer_create_with_data(
             ctx, io, size, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
             &buf, diag)) != XRSC_OK)
        goto done;
    mt_hctable_write(t, &prog.set0);
    gpu_descriptors_write_buffer(ctx, &prog.set0, XS_HC_BIND_SELFTEST, &buf);
    VkCommandBuffer cmd;
    if ((res = gpu_cmd_begin(ctx, &cmd, diag)) != XRSC_OK)
        goto done;
    gpu_cmd_barrier_all(cmd);
    mt_hctable_cmd_begin(t, cmd);
    gpu_cmd_barrier_all(cmd);
    gpu_compute_program_cmd_dispatch(cmd, &prog, &count,
                                     (count + XS_HC_SELFTEST_GROUP - 1) / XS_HC_SELFTEST_GROUP, 1,
                                     1);
    mt_hctable_cmd_end(t, cmd);
    gpu_cmd_barrier_all(cmd);
    res = gpu_cmd_submit_wait(ctx, cmd, diag);
    mt_hctable_frame_done(t, res == XRSC_OK);
    if (res == XRSC_OK)
        res = gpu_buffer_download(ctx, &buf, 0, io, size, diag);
done:
    gpu_buffer_destroy(ctx, &buf);
    gpu_compute_program_destroy(ctx, &prog);
    return res;
}
