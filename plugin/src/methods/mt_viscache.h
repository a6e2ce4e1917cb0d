// SPDX-License-Identifier: MIT
/**
 * @file mt_viscache.h
 * @brief The sample cache shading pass's shadow visibility cache (seed 002, AQVC): options,
 *        buffers, per-frame recording and counters, for mt_samplecache.c.
 *
 * The shader side is shaders/xs_viscache.glsl (layouts: shaders/xs_viscache.h). The cache's two
 * bindings (XS_VC_BIND_STATE, XS_VC_BIND_TABLE) go into sc_shade.rgen's set 1. Its state is
 * always there, so the shadow-ray counters are counted with the cache off too; the table is a
 * 16-byte stub when the cache is off.
 */
#pragma once

#include "gpu_context.h"
#include "gpu_pipeline.h"
#include "gpu_resource.h"
#include "xrsc/xrsc.h"
#include "xs_viscache.h"

typedef struct mt_viscache {
    gpu_buffer state;    /**< xs_vc_state (device; vkCmdUpdateBuffer each frame) */
    gpu_buffer table;    /**< uint64 words[p.entries] (16-byte stub when off) */
    gpu_buffer readback; /**< xs_vc_state after the last frame (host) */
    xs_vc_params p;
    xs_vc_state last; /**< the counters of the last frame */
} mt_viscache;

/** The two bindings to add to sc_shade.rgen's set 1. */
extern const gpu_binding mt_viscache_bindings[2];

/** Fills zero fields of o with seed 002's defaults (xrsc.h). */
void mt_viscache_fill_defaults(xrsc_sc_visibility_options *o);
/** XRSC_ERROR_INVALID_ARGUMENT (field named in diag) for options out of range. */
xrsc_result mt_viscache_check(const xrsc_sc_visibility_options *o, xrsc_diag *diag);

/**
 * Creates the buffers for defaulted options o at w x h per eye; scene_diameter_m = 2 B_R
 * (the scene bounds' diagonal); eye_samples_per_px = shaded samples per pixel per frame.
 */
xrsc_result mt_viscache_init(mt_viscache *v, gpu_context *ctx, const xrsc_sc_visibility_options *o,
                             float scene_diameter_m, float eye_samples_per_px, uint32_t w,
                             uint32_t h, xrsc_diag *diag);
/** Frees what init created (NULL-safe on a zeroed struct). */
void mt_viscache_fini(mt_viscache *v, gpu_context *ctx);
void mt_viscache_write(const mt_viscache *v, gpu_context *ctx, gpu_descriptors *d);

/** The frame's pixel sizes (tan-space, per eye) for the footprint of Eq. 7. */
void mt_viscache_set_views(mt_viscache *v, const xrsc_frame *frame, uint32_t w, uint32_t h);
/** Before the shade pass: parameters + zero counters, table cleared (then a barrier). */
void mt_viscache_cmd_begin(const mt_viscache *v, VkCommandBuffer cmd);
/** Pre-pass launches of the frame (xs_viscache.glsl): 2 per refinement level, 0 when off. */
uint32_t mt_viscache_prepasses(const mt_viscache *v);
/** Before launch i of the frame's shade launches (pre-passes 0 .. mt_viscache_prepasses - 1,
 *  then the shading launch): its XS_VC_PHASE_* (then a barrier). Launch 0 needs no call. */
void mt_viscache_cmd_phase(const mt_viscache *v, VkCommandBuffer cmd, uint32_t launch);
/** After the shade pass: the counters to the read-back buffer (then a barrier). */
void mt_viscache_cmd_copy(const mt_viscache *v, VkCommandBuffer cmd);
/** After the frame's wait: reads the counters. */
void mt_viscache_collect(mt_viscache *v, gpu_context *ctx);
/** Counters of the last frame: vc_shadow_rays, vc_queries, vc_cached, vc_cached_frac. */
uint32_t mt_viscache_counters(const mt_viscache *v, xrsc_counter *out, uint32_t max_count);
