// SPDX-License-Identifier: MIT
/**
 * @file mt_hashcache.h
 * @brief Methods `hashcache` (world-space hashed voxel radiance cache, seed 000 §4, seed 001)
 *        and `hybrid` (the sample cache's visibility with the hash cache's radiance).
 *
 * `hashcache`, two passes per frame after "tlas" (seed 000 §4: "only two passes"):
 * - "trace" (hc_trace.rgen): jittered 1 spp first hits; albedo, depth and hit id outputs;
 * - "shade" (hc_shade.rgen): per pixel the hit's voxel is looked up or reserved, the one
 *   pixel that reserves it this frame traces one secondary path and updates its running mean
 *   of demodulated radiance; colour = emission + albedo x voxel mean.
 * `hybrid`: the sample cache's passes (mt_samplecache.h) with "shade" replaced by
 * hc_hybrid_shade.rgen (selected samples update the hit voxel or its parent, chosen at
 * random) and "reconstruct" by hc_hybrid_reconstruct.comp (count-weighted mean of the hit voxel
 * and its parent per visible sample).
 * View-dependent surfaces are not served from the cache in either method (hc_view_dependent in
 * hc_table.glsl): a first hit whose sample-cache clamp (seed 000 App. C, smooth metal or glass
 * lobes: xs_sc_alpha_min_material > XS_HC_VIEW_DEP_ALPHA_MIN) takes this frame's own path
 * through the pixel, as the 1 spp path tracer would (the TAA post-pass averages it), and never
 * touches the table; its outgoing radiance depends on the view direction, so a voxel mean
 * shared between pixels, eyes, frames and (hybrid) levels is wrong there. In `hybrid` the
 * own path travels from shade to reconstruct in the unused XS_BIND_ACCUM image.
 * `hashcache` follows deforming (skinned, morphed) surfaces: a voxel inserted for a hit that
 * moved since the last frame starts from the running mean of the voxel of the hit's last-frame
 * position (xs_hashcache.h, issue 21 item 3); `hybrid` likewise for the voxels its shading
 * inserts, and its reconstruction reads the last-frame position's voxels where the two
 * voxels of a deforming sample hold nothing yet.
 * Both report the table's counters (mt_hctable.h) through mt_method.counters.
 */
#pragma once

#include "mt_method.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Pass names of `hashcache` (xrsc_renderer_timings), after MT_PASS_TLAS. */
#define MT_HC_PASS_TRACE "trace"
#define MT_HC_PASS_SHADE "shade"

/**
 * `hashcache` with options (zero fields = defaults, ::xrsc_hashcache_options).
 * XRSC_ERROR_INVALID_ARGUMENT for options out of range (mt_hctable_init).
 */
xrsc_result mt_hashcache_create(const mt_env *env, const xrsc_hashcache_options *options,
                                mt_method **out, xrsc_diag *diag);

/** Tests (issue 21 item 3): false stops deforming surfaces from following their last-frame
 *  position (xs_hashcache.h): their voxels are keyed by this frame's position only. */
void mt_hashcache_set_deform_follow(mt_method *hashcache, bool follow);
/** The last frame's lookups of hits on deforming surfaces and, of those, the ones whose voxel
 *  holds earlier frames' samples (xs_hc_stats deform_lookups, deform_history). */
void mt_hashcache_deform_stats(const mt_method *hashcache, uint32_t *out_lookups,
                               uint32_t *out_history);

/**
 * `hybrid`: visibility from the sample cache with sc (its trace, reprojection, density and
 * shading-selection options; shade must be uniform: adaptive shading's importance needs the
 * per-sample counts hybrid does not store), radiance from the hash cache with hc. The path
 * length is hc->max_bounces when set, else sc->max_bounces. XRSC_ERROR_INVALID_ARGUMENT as
 * ::mt_samplecache_create and ::mt_hashcache_create, and for adaptive shading.
 */
xrsc_result mt_hybrid_create(const mt_env *env, const xrsc_samplecache_options *sc,
                             const xrsc_hashcache_options *hc, mt_method **out, xrsc_diag *diag);

/** `hybrid`'s inner `samplecache` method (for mt_samplecache_snapshot in tests). */
mt_method *mt_hybrid_samplecache(mt_method *hybrid);

/** Tests (issue 21 item 3): ::mt_hashcache_set_deform_follow for `hybrid`. */
void mt_hybrid_set_deform_follow(mt_method *hybrid, bool follow);
/** The last frame's reconstruction lookups of samples on deforming surfaces and, of those, the
 *  ones whose radiance holds more than one sample (a voxel or its parent with a count > 1). */
void mt_hybrid_deform_stats(const mt_method *hybrid, uint32_t *out_lookups, uint32_t *out_history);

#ifdef __cplusplus
}
#endif
