// SPDX-License-Identifier: MIT
/**
 * @file mt_samplecache.h
 * @brief Method `samplecache` (seed 000 §3): creation, and the internal read-back of the cache
 *        for tests and benchmarks (masks, first hits, radiance, depth words, plans, statistics).
 *
 * Data per eye (xs_samplecache.h has the exact layouts): a 32-bit mask per pixel (o_s = bit s,
 * v_s = bit 16 + s) and N slots of a 32-bit pool address, double buffered; one resident pool of
 * K samples per pixel (XS_SC_POOL_*), each a 128-bit first hit (Listing 1) and a 64-bit
 * radiance + count (L_s, c_s as halves, read back as floats), and a 32-bit word of its taken
 * entries: reprojection moves a sample's 4-byte address, never the sample (issue 19; its
 * reservation keys use this frame's copy of the addresses until sc_copy.comp replaces them);
 * per frame a 64-bit closest depth + slope, a 32-bit farthest depth, a 128-bit plan (`isrt`: a
 * 64-bit key per slot); with cross-eye reuse a 32-bit mask of the other eye's copies per pixel,
 * double buffered. See ::mt_samplecache_bytes_per_pixel. Counters: sc_shaded
 * (samples shaded in the last frame), sc_shaded_per_px, sc_shade_rays (rays the shading pass
 * traced), sc_bytes_per_px, sc_pool_full (new samples not created in the last frame because
 * the pool was full).
 *
 * Frame: "tlas" (scene update), "reproject" (sc_reproject.comp + sc_copy.comp, which also
 * writes the trace mask), "density" (sc_density.comp), "trace" (sc_trace.rgen),
 * "shade" (sc_shade_select.comp + sc_shade.rgen), "reconstruct" (sc_reconstruct.comp; the
 * albedo only when it was read after the frame before, else when it is read: XS_SC_RC_*).
 */
#pragma once

#include "mt_method.h"
#include "xs_samplecache.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Pass names (xrsc_renderer_timings), in frame order after MT_PASS_TLAS. */
#define MT_SC_PASS_REPROJECT "reproject"
#define MT_SC_PASS_DENSITY "density"
#define MT_SC_PASS_TRACE "trace"
#define MT_SC_PASS_SHADE "shade"
#define MT_SC_PASS_RECONSTRUCT "reconstruct"

/**
 * `samplecache` (options: ::xrsc_samplecache_options, zero fields = defaults). Errors:
 * XRSC_ERROR_INVALID_ARGUMENT for slots > XS_SC_MAX_SLOTS, block 0 after defaults, more than
 * XS_SC_MAX_MATERIALS materials (Listing 1 keeps 16 bits), or an image too large for the
 * 31-bit source addresses of the reservation keys.
 */
xrsc_result mt_samplecache_create(const mt_env *env, const xrsc_samplecache_options *options,
                                  mt_method **out, xrsc_diag *diag);

/**
 * What other methods change in the sample cache (each such method is a file of its own that
 * creates the cache through ::mt_samplecache_create_variant; zero fields = the plain cache):
 * - name: the method name reported (NULL: "samplecache");
 * - isrt_m: `isrt` (mt_isrt.c): M x M fixed sub-pixel slots per pixel [DSK*17] instead of
 *   free sample positions (0: the sample cache's own layout);
 * - hybrid: `hybrid` (mt_hybrid.c): radiance from the world-space hash cache instead of the
 *   per-sample shading storage (seed 000 §4).
 */
/**
 * `hybrid`'s changes to the sample cache (filled in by mt_hybrid.c; borrowed: it must outlive
 * the method). The cache then keeps no per-sample radiance (xs_sc_params.shade_cache =
 * XS_SC_RAD_NONE: rad[] is a 16-byte dummy) and only uniform shading is accepted; the shading
 * and reconstruction programs are replaced, with extra bindings (set 1 of the shading
 * program, set 0 of the reconstruction, after the cache's own) that `write` fills in;
 * record_begin runs right after the frame prologue (before "reproject"), record_end after the
 * last pass (before the read-back copies), both with `user`.
 */
struct mt_sc_hybrid {
    const char *shade_raygen;       /**< replaces sc_shade.rgen */
    const char *reconstruct_shader; /**< replaces sc_reconstruct.comp */
    const gpu_binding *bindings;
    uint32_t binding_count;
    void (*write)(void *user, gpu_descriptors *d);
    void (*record_begin)(void *user, VkCommandBuffer cmd);
    void (*record_end)(void *user, VkCommandBuffer cmd);
    void *user;
};

typedef struct mt_sc_variant {
    const char *name;
    uint32_t isrt_m;
    const struct mt_sc_hybrid *hybrid;
} mt_sc_variant;

/** The sample cache changed as variant says (NULL: the plain cache, = mt_samplecache_create). */
xrsc_result mt_samplecache_create_variant(const mt_env *env,
                                          const xrsc_samplecache_options *options,
                                          const mt_sc_variant *variant, mt_method **out,
                                          xrsc_diag *diag);

/**
 * `isrt` (mt_isrt.c): the sample cache with M x M fixed sub-pixel slots (M = isrt->m, 1..4, 0:
 * 2) and the shading options of `samplecache` (its slots, n_target, delta and reproject are
 * not used). XRSC_ERROR_INVALID_ARGUMENT for M > 4, and as ::mt_samplecache_create.
 */
xrsc_result mt_isrt_create(const mt_env *env, const xrsc_isrt_options *isrt,
                           const xrsc_samplecache_options *options, mt_method **out,
                           xrsc_diag *diag);

/** The options in use, defaults filled in (m must be a `samplecache` method). */
const xrsc_samplecache_options *mt_samplecache_options(const mt_method *m);

/** Cache bytes per pixel per eye: resident (both copies of mask and pool addresses, the pool's
 *  first hits, radiance and taken-entry word) plus
 *  per-frame working buffers (depth words, plan, isrt's keys, shade list, visibility
 *  cache table). */
void mt_samplecache_bytes_per_pixel(const mt_method *m, double *out_resident, double *out_working);

/**
 * One eye's cache after the last rendered frame (the copy that frame wrote), for tests. Pixel
 * p = y * width + x, rows top to bottom. Owned arrays: free with ::mt_sc_snapshot_free.
 */
typedef struct mt_sc_snapshot {
    uint32_t width, height, slots;
    uint32_t *mask;       /**< [p]: o_s = bit s, v_s = bit XS_SC_MAX_SLOTS + s */
    uint32_t *fh;         /**< [(s * width * height + p) * 4 + k]: Listing 1 words x, y, z, w */
    float *rad;           /**< [(s * width * height + p) * 4 + k]: L_s rgb, c_s (hybrid: 0) */
    uint64_t *depth_min;  /**< [p]: closest distance bits << 32 | slope bits; all ones = none */
    uint32_t *depth_max;  /**< [p]: farthest distance bits (0 = none, +inf = background) */
    uint32_t *plan;       /**< [p * 4 + k]: trace bits, new bits, shade bits, visible count
                               (visible count as measured before density control) */
    xs_sc_stats stats;    /**< importance bounds and histogram counted this frame */
    uint32_t shade_count; /**< samples chosen for shading this frame, both eyes (may exceed the
                               shade list's capacity: the rest were not shaded) */
    uint32_t cur;         /**< the copy index this frame wrote */
    uint32_t *foreign;    /**< [p]: bit s = slot s is the other eye's copy (cross-eye reuse;
                               all 0 when off) */
    uint64_t shade_rays;  /**< rays the shading pass traced this frame, both eyes */
    uint32_t *addr;       /**< [s * width * height + p]: the slot's pool address (issue 19;
                               XS_SC_POOL_NONE for a slot without a sample) */
    uint32_t pool_full;   /**< new samples the full pool refused this frame, both eyes */
} mt_sc_snapshot;

xrsc_result mt_samplecache_snapshot(mt_method *m, uint32_t eye, mt_sc_snapshot *out,
                                    xrsc_diag *diag);
void mt_sc_snapshot_free(mt_sc_snapshot *s);

/**
 * Debug (tests): the following frames stop after the named pass (one of the MT_SC_PASS_*
 * names; NULL or MT_SC_PASS_RECONSTRUCT = the whole frame), so ::mt_samplecache_snapshot shows
 * the cache as that pass left it (e.g. right after forward reprojection). The skipped passes
 * are neither recorded nor timed and the outputs keep their old contents. The frame still
 * counts (its copy becomes the previous one). XRSC_ERROR_INVALID_ARGUMENT for another name.
 */
xrsc_result mt_samplecache_debug_stop_after(mt_method *m, const char *pass, xrsc_diag *diag);

/** Runs sc_selftest.comp over io[0..count) (Listing 1 round trip, Eq. 1, Eq. 2 on the
 *  device); the records' outputs are filled in. */
xrsc_result mt_sc_selftest_run(gpu_context *ctx, xs_sc_selftest_io *io, uint32_t count,
                               xrsc_diag *diag);

#ifdef __cplusplus
}
#endif
