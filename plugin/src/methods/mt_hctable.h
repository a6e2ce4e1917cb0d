// SPDX-License-Identifier: MIT
/**
 * @file mt_hctable.h
 * @brief The hash cache's table on the C side (shared by `hashcache` and `hybrid`): its
 *        buffers, per-frame parameters, statistics and counters. The table logic runs on the
 *        GPU (shaders/hc_table.glsl); layouts and bindings are in shaders/xs_hashcache.h.
 *
 * Per frame, in this order: ::mt_hctable_frame_begin (host: next stamp, parameters), then
 * inside the frame's command buffer ::mt_hctable_cmd_begin (zeroes the statistics; clears the
 * table on the first frame) before the passes that use the table and ::mt_hctable_cmd_end
 * after them (copies the statistics for read-back), then after the submission
 * ::mt_hctable_frame_done.
 */
#pragma once

#include "gpu_pipeline.h"
#include "xrsc/xrsc.h"
#include "xs_hashcache.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Bindings of the table (XS_HC_BIND_PARAMS .. XS_HC_BIND_STATS). */
#define MT_HCTABLE_BINDING_COUNT 4u

/** Counters (xrsc_renderer_counters), in this order:
 *  hc_table_bytes (entries x 24 B), hc_occupancy (entries with a stamp within max_age /
 *  entries, after the frame), hc_probe_mean, hc_probe_max (tiles visited per lookup),
 *  hc_lookups, hc_inserts, hc_evictions (stale entries overwritten), hc_failed_inserts
 *  (probe limit or a lost race), hc_traced (secondary paths traced for the cache). */
#define MT_HCTABLE_COUNTER_COUNT 9u

typedef struct mt_hctable {
    gpu_context *gpu;
    xrsc_hashcache_options opt; /**< defaults filled in */
    xs_hc_params p;
    gpu_buffer params; /**< xs_hc_params, host-visible */
    gpu_buffer words, rad, stats, stats_readback;
    gpu_compute_program occupancy;
    uint32_t frames;      /**< frames begun */
    bool cleared;         /**< the table was cleared (first frame recorded) */
    xs_hc_stats last;     /**< statistics of the last frame */
    bool have_last;       /**< last is valid */
    bool occupancy_known; /**< last.occupied was counted for the last frame */
} mt_hctable;

/** Fills the defaults of xrsc_hashcache_options (table_entries 2^22, lod distance,
 *  voxel_scale 0.5, max_age 64, max_bounces 3) into *o. */
void mt_hctable_defaults(xrsc_hashcache_options *o);

/**
 * Creates the table for options (zero fields = defaults; table_entries rounded down to a
 * multiple of XS_HC_TILE_ENTRIES). XRSC_ERROR_INVALID_ARGUMENT for fewer than
 * XS_HC_TILE_ENTRIES or more than 2^27 entries, a voxel_scale <= 0 or not finite, or an
 * unknown lod. On failure *t is zeroed.
 */
xrsc_result mt_hctable_init(mt_hctable *t, gpu_context *ctx, const xrsc_hashcache_options *o,
                            xrsc_diag *diag);
/** Frees everything (waits for the device); accepts a zeroed table. */
void mt_hctable_fini(mt_hctable *t);

/** The table's bindings (set 1 of ray-tracing programs, set 0 of compute programs) into out
 *  (MT_HCTABLE_BINDING_COUNT entries); returns the count. */
uint32_t mt_hctable_bindings(gpu_binding *out);
/** Writes the table's buffers to those bindings of d. */
void mt_hctable_write(const mt_hctable *t, gpu_descriptors *d);

/** Host side of a frame's start: next stamp and the eyes' pixel footprints (w x h per eye);
 *  uploads the parameters. */
void mt_hctable_frame_begin(mt_hctable *t, const xrsc_frame *frame, uint32_t w, uint32_t h);
void mt_hctable_cmd_begin(mt_hctable *t, VkCommandBuffer cmd);
void mt_hctable_cmd_end(mt_hctable *t, VkCommandBuffer cmd);
/** After the frame's submission completed: reads the statistics (ok false: none). */
void mt_hctable_frame_done(mt_hctable *t, bool ok);

/** The counters of the last frame (MT_HCTABLE_COUNTER_COUNT, names above); the occupancy is
 *  counted by one extra submission (hc_occupancy.comp) at the first call after a frame.
 *  Returns the number written (0 before the first frame). */
uint32_t mt_hctable_counters(mt_hctable *t, xrsc_counter *out, uint32_t max_count);

/**
 * Tests: one "frame" of hc_selftest.comp over io[0..count) (one hc_lookup per record, in
 * parallel), between ::mt_hctable_cmd_begin and ::mt_hctable_cmd_end, so the statistics and
 * counters are those of this frame; call ::mt_hctable_frame_begin first (the stamp). Fills the
 * records' outputs; waits.
 */
xrsc_result mt_hctable_selftest_run(mt_hctable *t, xs_hc_selftest_io *io, uint32_t count,
                                    xrsc_diag *diag);

#ifdef __cplusplus
}
#endif
