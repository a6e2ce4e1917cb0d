// SPDX-License-Identifier: MIT
/**
 * @file xs_viscache.h
 * @brief The shading pass's shadow visibility cache (seed 002, AQVC): bindings, the state
 *        layout (parameters + counters), table word format and defaults, shared by C and GLSL
 *        (compiled with -DXRSC_GLSL). The shader side is xs_viscache.glsl.
 *
 * Storage (set 1 of sc_shade.rgen, beside the sample cache's XS_SC_BIND_* bindings):
 *   state    xs_vc_state: the frame's parameters (written by the host with vkCmdUpdateBuffer
 *            at the start of the shade pass, which also zeroes the counters)
 *   table    uint64 words[2 entries]: the entries, cleared (vkCmdFillBuffer 0) before every
 *            frame's shade pass (seed 002 Alg. 1 line 1: "initialized to nil on every frame"),
 *            so no visibility outlives its frame and animated scenes never read stale
 *            entries; then one claim word per entry (all ones = unclaimed), the smallest
 *            claim key of the queries that asked to insert there (xs_viscache.glsl).
 * Word: 0 = empty (nil); else bits 2..63 = the cluster's 62-bit fingerprint (the §4.1
 * message digest, here wider than the paper's 31 bits so that a false match is ~2^-62),
 * bits 0..1 = XS_VC_OCCLUDED or XS_VC_VISIBLE (XS_VC_PENDING is never stored any more).
 */
#ifndef XS_VISCACHE_H
#define XS_VISCACHE_H

#include "xrsc_shared.h"

#define XS_VC_BIND_STATE 29 /* buffer xs_vc_state */
#define XS_VC_BIND_TABLE 30 /* buffer uint64 words[entries] */

/* Word states (low 2 bits; 0 only in the empty word). */
#define XS_VC_PENDING 1u
#define XS_VC_OCCLUDED 2u
#define XS_VC_VISIBLE 3u
#define XS_VC_STATE_MASK 3u

/* xs_vc_params.phase: the shading launch (0), or a pre-pass launch of round r (0-based, r <
 * levels): 2 r + 1 = request, 2 r + 2 = insert (xs_viscache.glsl). */
#define XS_VC_PHASE_SHADE 0u
#define XS_VC_PHASE_REQUEST(r) (2u * (r) + 1u)
#define XS_VC_PHASE_INSERT(r) (2u * (r) + 2u)

/* Refinement (xs_vc_params.refine; public value - 1, checked in C). */
#define XS_VC_REFINE_ADAPTIVE 0u /* seed 002 Alg. 2 */
#define XS_VC_REFINE_STRICT 1u   /* zero refinement error tolerance (xrsc.h) */
#define XS_VC_REFINE_NONE 2u     /* Alg. 1: quantisation only */

/* Semantics of a query's light end (§3.5: "a two-bit index that specifies the semantics"). */
#define XS_VC_LIGHT_DIRECTION 1u   /* a delta light's direction omega (K(X, omega)) */
#define XS_VC_LIGHT_SOLID_ANGLE 2u /* a sampled direction with a solid-angle pdf (env, sun disk) */
#define XS_VC_LIGHT_AREA 3u        /* a point Y on an emissive triangle */
/* a punctual (point or spot) light's position Y; 8, not 4: bit 2 is the `below` side bit of
 * the light digest (xs_viscache.glsl) */
#define XS_VC_LIGHT_POINT 8u

/* Defaults of seed 002: §3.3 (C_N = C_Z = 8), §3.4 (C_R = 1.2), §3.6 (C_MSR = log2 C_E). C_E
 * has no single value there (§5: 4..18 px for directional lights without anti-aliasing, 4..24
 * for area and environment light); 4 px is the conservative end of both. */
#define XS_VC_DEFAULT_ERROR_PX 4.0
#define XS_VC_DEFAULT_NORMAL_BINS 8u
#define XS_VC_DEFAULT_DEPTH_RATIO 8u
#define XS_VC_DEFAULT_RESOLUTION_BASE 1.2
/* Table entries by default: XS_VC_DEFAULT_ENTRIES_PER_PX per pixel of both eyes, rounded up to
 * a power of two, within [XS_VC_MIN_ENTRIES, XS_VC_MAX_ENTRIES] (8 B each). */
#define XS_VC_DEFAULT_ENTRIES_PER_PX 16u
#define XS_VC_MIN_ENTRIES 4096u
#define XS_VC_MAX_ENTRIES (1u << 26)
#define XS_VC_MAX_LEVELS 8u
/* Lower clamp of |cos theta| in the pixel footprint t a / sqrt(|cos theta|) (grazing views). */
#define XS_VC_COS_MIN 0.1
/* Upper clamp of Eq. 8's exponent k (C_R^k stays a float; beyond: finer than float steps). */
#define XS_VC_MAX_EXPONENT 120

XS_STRUCT(xs_vc_params)
{
    xs_uint enabled;  /* 0: every light sample traces its shadow ray (the counters still count) */
    xs_uint refine;   /* XS_VC_REFINE_* */
    xs_uint levels;   /* C_MSR >= 1: refinement levels C_E, C_E / 2, ... */
    xs_uint entries;  /* table words */
    xs_float error_px;        /* C_E */
    xs_float normal_bins;     /* C_N (Eq. 4) */
    xs_float depth_ratio;     /* C_Z (§3.3) */
    xs_float log_resolution_base; /* ln C_R (Eq. 8) */
    xs_float scene_diameter;  /* 2 B_R (Eq. 5-8): the scene bounds' diagonal, m */
    xs_float pixel_tan_left;  /* per eye: sqrt of the tan-space area of a pixel at the centre */
    xs_float pixel_tan_right;
    xs_float eye_samples_per_px; /* shaded samples per pixel per frame (P(p_e) N_S, Eq. 7) */
    xs_uint phase;    /* XS_VC_PHASE_*: set by the host before each launch of the frame */
    xs_uint pad0, pad1, pad2;
}
XS_END(xs_vc_params);

XS_STRUCT(xs_vc_state)
{
    xs_vc_params p;
    xs_uint queries;     /* light-sample shadow queries at first vertices (the cache's domain) */
    xs_uint cached;      /* of those, answered from the cache (no ray) */
    xs_uint shadow_rays; /* light-sample shadow rays traced by the shading pass, all vertices */
    xs_uint refined;     /* queries that went past refinement level 0 (§3.6) */
}
XS_END(xs_vc_state);

#ifndef XRSC_GLSL
_Static_assert(sizeof(xs_vc_params) == 64, "xs_vc_params layout (std430)");
_Static_assert(sizeof(xs_vc_state) == 80, "xs_vc_state layout (std430)");
#endif

#endif /* XS_VISCACHE_H */
