// SPDX-License-Identifier: MIT
/**
 * @file xs_samplecache.h
 * @brief The sample cache (seed 000 §3): bindings, parameter/statistics layouts, limits and
 *        defaults, shared by C and GLSL (compiled with -DXRSC_GLSL).
 *
 * Storage (all storage BUFFERS: 64-bit atomics exist only on buffers on lavapipe). Pixel
 * index of eye e, pixel (x, y): pix = (e * height + y) * width + x; "plane" = 2 * width *
 * height. Arrays with a copy index are double buffered (copy c = frame parity: the frame
 * reads copy 1 - cur and writes copy cur, §3.1).
 *   mask[c][pix]                 32 bits: o_s = bit s, v_s = bit s + XS_SC_MAX_SLOTS (§3)
 *   idx[c][slot][pix]            the pool address of the sample in slot s (reprojection
 *                                moves this 4-byte index, never the sample: issue 19);
 *                                XS_SC_POOL_NONE for a slot without one. Between the
 *                                reprojection and sc_copy.comp, copy cur holds the
 *                                reservation keys (XS_SC_SRC_*) instead
 *   fh[K][pix]                   the sample pool, ONE resident copy (K = xs_sc_params.pool_k
 *                                entries per pixel; address a = k * plane + pix): the first
 *                                hit packed as Listing 1 (xs_sc_math.h), uvec4
 *   rad[K][pix]                  demodulated radiance L_s (rgb) and count c_s of pool entry
 *                                a, four halves (XS_SC_RAD_BYTES: uvec2 of packHalf2x16
 *                                (r, g), (b, c_s)); sc_rad_load / sc_rad_store
 *   used[pix]                    bit k = pool entry k * plane + pix is taken this frame:
 *                                cleared before the reprojection, set by every slot that
 *                                takes an entry (reprojection, copy) and by sc_pool_alloc
 *                                (new samples), so the entries nothing carried are free
 *                                again each frame (the pool's compaction)
 *   depth_min[pix]               uint64: closest distance t (float bits, high 32) | slope
 *                                Delta of that sample (Eq. 1, float bits, low 32), atomicMin
 *   depth_max[pix]               uint: farthest distance (float bits), atomicMax
 *   src[slot][pix]               `isrt`: the 64-bit key of each cell (XS_SC_ISRT_KEY_*; a
 *                                16-byte stub otherwise)
 *   plan[pix]                    uvec4: trace bits, new-sample bits, shade bits, visible count
 *                                (variance-guided shading: then XS_SC_PLAN_RANGE_*)
 *   stats[c][eye]                xs_sc_stats: importance bounds and histogram (§3.5)
 *   shade list                   a work list: a count, the pool's failed allocations this
 *                                frame (sc_pool_alloc), the shading pass's ray count
 *                                (uint64), then entries. From the density pass to the trace
 *                                pass the pixels with rays to trace (pix); then the samples
 *                                chosen for shading, compacted (§3.5):
 *                                pix << XS_SC_SHADE_SLOT_BITS | slot
 *   foreign[c][pix]              cross-eye reuse (xs_sc_params.cross_eye): bit s = slot s holds
 *                                a copy of the OTHER eye's sample (a 16-byte stub when off)
 * Slot s of a pixel lives in "layer" s, as in the paper's array of textures (Fig. 3).
 */
#ifndef XS_SAMPLECACHE_H
#define XS_SAMPLECACHE_H

#include "xrsc_shared.h"

/* The cache's own bindings: set 1 of the ray-tracing programs, set 0 (next to the scene's
 * XS_BIND_* ones, which stay below XS_SC_BIND_FIRST) of the compute programs. */
#define XS_SC_BIND_FIRST 16
#define XS_SC_BIND_PARAMS 16     /* uniform xs_sc_params */
#define XS_SC_BIND_MASK 17       /* buffer uint[2][plane] */
#define XS_SC_BIND_FH 18         /* buffer uvec4[2][N][plane] */
#define XS_SC_BIND_RAD 19        /* buffer uvec2[2][N][plane]: 4 halves (XS_SC_RAD_BYTES) */
#define XS_SC_BIND_DEPTH_MIN 20  /* buffer uint64[plane] */
#define XS_SC_BIND_DEPTH_MAX 21  /* buffer uint[plane] */
#define XS_SC_BIND_SRC 22        /* buffer uint[N][plane] */
#define XS_SC_BIND_PLAN 23       /* buffer uvec4[plane] */
#define XS_SC_BIND_STATS 24      /* buffer xs_sc_stats[2][2] */
#define XS_SC_BIND_OUT_MU1 25    /* rgba32f image2DArray: mu_1 per pixel (Eq. 5) */
#define XS_SC_BIND_OUT_MU2 26    /* rgba32f image2DArray: mu_2 per pixel (Eq. 5) */
#define XS_SC_BIND_SHADE_LIST 27 /* buffer: uint count, 3 pads, uint entries[capacity] */
#define XS_SC_BIND_SELFTEST 28   /* buffer xs_sc_selftest_io[] (sc_selftest.comp only) */
#define XS_SC_BIND_FOREIGN 31    /* buffer uint[2][plane]: cross-eye copies (bit s = slot s) */
#define XS_SC_BIND_IDX 39        /* buffer uint[2][N][plane]: pool address of each slot */
#define XS_SC_BIND_USED 40       /* buffer uint[plane]: taken pool entries (bit k) */

/* Descriptor set of the cache bindings in ray-tracing programs (compute programs: 0). */
#define XS_SC_RT_SET 1

/* Limits (§3: 2 bits per slot in a 32-bit mask). */
#define XS_SC_MAX_SLOTS 16u
#define XS_SC_OCC_MASK 0xFFFFu
/* Importance buckets of adaptive shading (§3.5: M = 13 logarithmic buckets). */
#define XS_SC_BUCKETS 13u
#define XS_SC_BUCKETS_STORED 16u

/* Defaults (seed 000 §4, §3.2, §3.4, App. C). */
#define XS_SC_DEFAULT_SLOTS 12u
#define XS_SC_DEFAULT_N_TARGET 4.0
#define XS_SC_DEFAULT_DELTA 1.0
#define XS_SC_DEFAULT_EPS0 0.001
#define XS_SC_DEFAULT_EPS1 0.005
#define XS_SC_DEFAULT_BLOCK 4u
#define XS_SC_DEFAULT_SHADE_RATE 1.0
#define XS_SC_DEFAULT_ALPHA_FIXED 0.1
/* App. C: alpha_min = (1 - a_GGX) * XS_SC_ALPHA_MIN_SMOOTH + a_GGX * XS_SC_ALPHA_MIN_ROUGH. */
#define XS_SC_ALPHA_MIN_SMOOTH 0.5
#define XS_SC_ALPHA_MIN_ROUGH 0.1
/* App. C's clamp exists because view-dependent shading "cannot be accumulated indefinitely when
 * the camera moves": its transmission part is scaled by how far the view of the sample turned
 * since the previous frame (xs_sc_view_motion, xs_sc_alpha_min_glass), full from this fraction
 * of a pixel's diagonal per frame, none for a still view. The history it keeps then spans at most this / alpha_min of view change (a
 * quarter of a pixel for smooth lobes), so lag stays below a pixel while a still view
 * accumulates glass and metal like any other surface (issue 18: TransmissionTest's glass stayed
 * grainy, blended with alpha 0.5 for ever under a still pose). */
#define XS_SC_VIEW_MOTION_PIXELS 0.125

/* Modes (values of xs_sc_params fields; equal to the public enums, checked in C). */
#define XS_SC_TRACE_SINGLE 0u
#define XS_SC_TRACE_MULTI 1u
#define XS_SC_TRACE_ADAPTIVE 2u
#define XS_SC_SHADE_UNIFORM 0u
#define XS_SC_SHADE_ADAPTIVE 1u
#define XS_SC_SHADE_ADAPTIVE_VARIANCE 2u
#define XS_SC_ALPHA_CLAMPED 0u
#define XS_SC_ALPHA_FIXED 1u

/* xs_sc_params.shade_cache of `hybrid` (mt_hybrid.c): no per-sample radiance at all; rad[]
 * is a one-entry dummy that every sc_rad_at index maps to (0: one copy, 1: two copies). */
#define XS_SC_RAD_NONE 2u

/* Cross-eye reuse (issue 12; seed 000 keeps the eyes apart until the blend): a visible sample
 * is also forward-reprojected into the other eye's view, where it is a "foreign" copy:
 * traced for visibility there like any sample, counted by density control, reconstructed, but
 * never shaded there and never carried to the next frame (its owner sends a fresh copy, with
 * the radiance its own shading gave it, every frame). Only samples whose radiance does not
 * depend on the eye are sent: background samples (the environment is the same for both eyes)
 * and surfaces that are not xs_sc_eye_specific (xs_sc_math.h): no metal or glass (App. C's
 * view-dependent weight above XS_SC_CROSS_EYE_VIEW_DEP) and no dielectric whose specular layer
 * is sharper than XS_SC_CROSS_EYE_ROUGHNESS: its lobe (GGX alpha 0.25 at the threshold) must be
 * wide against the ~0.065 rad the eyes' baseline subtends at 1 m. Reconstruction weighs the
 * shared and the eye-specific samples of a pixel by the share of the pixel's OWN samples on
 * each (sc_reconstruct.comp: rc_strata), since copies never come from eye-specific surfaces. */
#define XS_SC_CROSS_EYE_VIEW_DEP 0.05
#define XS_SC_CROSS_EYE_ROUGHNESS 0.5

/* Bytes of one slot's radiance record: L_s and c_s as half floats. Half precision (11
 * significant bits) is below the noise of any cached estimate; radiance above
 * XS_SC_RAD_HALF_MAX (the largest finite half) is clamped to it; c_s stops growing at 2048,
 * where c_s + 1 rounds back to c_s (the plain mean's alpha is then 1/2049, the estimate of
 * 2048 observations). */
#define XS_SC_RAD_BYTES 8u
#define XS_SC_RAD_HALF_MAX 65504.0

/* The sample pool (issue 19): K = min(slots, max(XS_SC_POOL_MIN_PER_PX, ceil(
 * XS_SC_POOL_PER_TARGET x n_target))) entries per pixel (isrt: K = XS_SC_POOL_ISRT_FACTOR x
 * slots, as every cell is filled: slack for the probes), against the slots' N per pixel:
 * density control keeps ~n_target visible samples per pixel and the invisible ones leave at
 * the next full pixel, so most slots are empty. A
 * new sample takes a free entry of its own pixel's K, else of pixels picked at random over
 * the whole pool (at most XS_SC_POOL_PROBES of them); when all are taken it is not created
 * this frame (counter sc_pool_full). */
#define XS_SC_POOL_MIN_PER_PX 10u
#define XS_SC_POOL_PER_TARGET 2.5
#define XS_SC_POOL_PROBES 64u
#define XS_SC_POOL_ISRT_FACTOR 2u
#define XS_SC_POOL_NONE 0xFFFFFFFFu

/* Instance value of a background sample (fh.xyz = unit world direction as float bits). */
#define XS_SC_BACKGROUND XS_MISS_INSTANCE

/* Reservation key per target slot (sc_reproject.comp offer_sorted, sc_copy.comp; stored in
 * idx[cur] until sc_copy.comp replaces it with the pool address): bit 31 =
 * the source sample is INVISIBLE, bits 0..30 = source address + 1 (address = slot * plane +
 * pix in the previous copy); XS_SC_SRC_NONE (the fill value) = nothing arrived. */
#define XS_SC_SRC_INVISIBLE 0x80000000u
#define XS_SC_SRC_NONE 0xFFFFFFFFu
#define XS_SC_SRC_ADDR_MASK 0x7FFFFFFFu

/* `isrt` [DSK*17] (seed 000 §5, Fig. 10): the reprojection's key per slot (64-bit atomicMin in
 * the src[] buffer, then sc_copy.comp copies the winner): bit 63 = the source sample is
 * INVISIBLE, bits 32..62 = its distance to the eye (float bits of t >= 0; +inf = background),
 * bits 0..31 = source address + 1 (address as for XS_SC_SRC_*). The smallest key wins: a
 * visible sample before an invisible one, then the closest, then the lowest address, whatever
 * the order of arrival. All ones = nothing arrived (the fill value). */
#define XS_SC_ISRT_KEY_INVISIBLE_SHIFT 63u
#define XS_SC_ISRT_KEY_T_SHIFT 32u
#define XS_SC_ISRT_MAX_M 4u

/* Shade-list entries: pixel index (both eyes' planes) above the slot. */
#define XS_SC_SHADE_SLOT_BITS 4u
#define XS_SC_SHADE_SLOT_MASK 0xFu
/* uints before the entries of the shade list (count, the pool's failed allocations, the
 * shading pass's 64-bit ray count: 16 bytes) */
#define XS_SC_SHADE_LIST_HEADER 4u
/* A work-list launch (the shade list, adaptive tracing's trace list) is XS_SC_LIST_WIDTH x
 * (XS_SC_SHADE_STRIPES * XS_SC_LIST_BLOCK * q) invocations. Launch rows go in blocks of
 * XS_SC_LIST_BLOCK; launch block b takes list block (b % q) * XS_SC_SHADE_STRIPES + b / q
 * (sc_list_entry), so that
 * - every contiguous band of launch rows (lavapipe gives each worker thread one) gets an equal
 *   share of the filled prefix of the list, whatever its count;
 * - the invocations a GPU runs together (a warp of 32: one launch row of 32, or a tile of up to
 *   XS_SC_LIST_BLOCK rows) take neighbouring entries, i.e. samples of neighbouring pixels,
 *   as a launch over the screen does. */
#define XS_SC_SHADE_STRIPES 16u
#define XS_SC_LIST_WIDTH 32u
#define XS_SC_LIST_BLOCK 8u

/* Variance-guided shading: plan.w after sc_shade_importance.comp, the lowest (bits 0..7) and
 * highest (bits 8..15) importance bucket of the pixel's candidates, with XS_SC_PLAN_RANGE_SET
 * (0: no candidates). sc_shade_select.comp decides a pixel whose candidates all lie above or
 * all below the threshold bucket without loading them again. */
#define XS_SC_PLAN_RANGE_SET 0x10000u
#define XS_SC_PLAN_RANGE_HI_SHIFT 8u
#define XS_SC_PLAN_RANGE_MASK 0xFFu
/* Cover rule (xrsc_samplecache_options.cover, issue 19): plan.w's flag, from
 * sc_shade_importance.comp, of a pixel that has surface samples but none shaded yet. Such a
 * pixel's colour is black (sc_reconstruct.comp averages observed samples only): with
 * variance-guided shading at 40 %, 63 % of the pixels of a first frame, 5 % of the fifth,
 * which TAA (alpha 0.1) then held for tens of frames. With the rule, sc_shade_select.comp
 * shades one sample of such a pixel outside the budget, so no pixel with a surface stays
 * black after its first frame. */
#define XS_SC_PLAN_UNOBSERVED 0x20000u

/* Firefly rule (issue 19 item 3, sc_shade.rgen): observations a sample needs before a new
 * one is capped relative to its running mean. */
#define XS_SC_FIREFLY_MIN_COUNT 4.0

/* Moving objects (issue 19, case `moving`; the moving-sample rule, an option off by default:
 * xrsc_samplecache_options.moving, xs_sc_params.moving): a sample rides on its instance
 * (App. D), but the radiance it cached was shaded at the instance's old pose: a turning face
 * sees the light under another angle, a moving one passes through other shadows and indirect
 * light. While its instance turns (the linear part of object_to_world differs from
 * prev_object_to_world's, sc_instance_turned), with the rule on,
 * - its pixel shades one of its turning samples more each frame (sc_shade_select.comp): about
 *   two shadings a frame for a pixel of moving samples (a rotating cone kept its faces' old
 *   shading and came out 12 % too dark at frame 60),
 * - its blend factor is at least XS_SC_MOVING_ALPHA_MIN x min(1, the angle its face turned
 *   since the previous frame / XS_SC_MOVING_TURN_RAD) (sc_shade.rgen): a face that turned
 *   0.01 rad or more keeps this frame's shading alone (TAA after the reconstruction averages
 *   it), a face that only slides (the sun's cosine unchanged) keeps its history. Measured on
 *   `moving` with the default pipeline (TAA on), 2 x 64^2, 24 frames: relMSE 0.00135 without
 *   the rule, 0.00132 / 0.00125 / 0.00119 / 0.00118 with XS_SC_MOVING_ALPHA_MIN 0.25 / 0.5 /
 *   0.75 / 1 (`taa` 0.00118); stop 20 tuned 0.5 without TAA.
 * An instance that only slides is left alone: its faces see a distant light under the same
 * angle, and the one more shading there (the rule's first version took every moving instance)
 * made `disocclusion` (a sliding box) worse, 0.0845 -> 0.0859 at 2 x 64^2.
 * The rule is in force only where the scene has animated instances (mt_samplecache.c), so
 * a still scene renders what it renders without it on any device, and its uniform round robin
 * is the one of every other pixel (stop 20's version, branch `moving`, also changed that round
 * robin for every pixel; bench/results/issue19-moving2/).
 * Skinned and morphed meshes deform without a change of transform: not covered. */
#define XS_SC_MOVING_ALPHA_MIN 1.0
#define XS_SC_MOVING_TURN_RAD 0.01

/* Stratified new samples (xs_sc_params.stratify, issue 19, beyond seed 000): the pixel is cut
 * into G x G strata, G = round(sqrt(n_target)) clamped to 1..XS_SC_STRATA_MAX_G, and each new
 * sample goes through a random point of a stratum holding the fewest of the pixel's visible
 * samples (they are projected to find theirs). A pixel keeps its ~n_target points while the
 * view is still, and on a pixel cut by an edge the mean of stratified points has a smaller
 * coverage error than the mean of independent uniform ones (bench/results/issue19-edges/). */
#define XS_SC_STRATA_MAX_G 4u

/* Compute workgroup size (x, y) of every sample-cache compute shader. */
#define XS_SC_GROUP 8u

/* sc_reconstruct.comp's push constant (one uint, issue 19): the outputs it writes. Nothing in
 * a frame reads the albedo (on lavapipe its store cost about 2 ms of the pass at 2 x 256^2),
 * so the frame's pass writes it only when it was read after the frame before (mt_trace then
 * stages it at the frame's end); any other read runs the pass again for the albedo alone,
 * over the same cache, so the values are the same. */
#define XS_SC_RC_ALL 0u
#define XS_SC_RC_NO_ALBEDO 1u
#define XS_SC_RC_ALBEDO_ONLY 2u

XS_STRUCT(xs_sc_params)
{
    xs_uint slots;        /* N */
    xs_uint cur;          /* copy written this frame (prev = 1 - cur) */
    xs_uint trace_mode;   /* XS_SC_TRACE_* */
    xs_uint two_pass;     /* 1: 2-pass (both reserve through keys now, sc_reproject.comp) */
    xs_uint shade_cache;  /* 0: radiance is not carried between frames; XS_SC_RAD_NONE */
    xs_uint shade_mode;   /* XS_SC_SHADE_* */
    xs_uint alpha_mode;   /* XS_SC_ALPHA_* */
    xs_uint block;        /* base-rate block size (4) */
    xs_float n_target;    /* §3.2 */
    xs_float delta;       /* §3.2 tolerance */
    xs_float eps0;        /* §3.2 retrace tolerance (relative distance) */
    xs_float eps1;        /* Eq. 2 */
    xs_float shade_rate;  /* §3.5: shadings per pixel (1 = 100 %) */
    xs_float alpha_fixed; /* XS_SC_ALPHA_FIXED */
    xs_float phi_left;    /* per eye: angle subtended by a pixel's diagonal (Eq. 1), rad */
    xs_float phi_right;
    xs_uint shade_capacity; /* entries of the shade list (more chosen samples are dropped) */
    xs_uint isrt_m; /* `isrt` (mt_isrt.c): M > 0 = slot s is sub-pixel cell (s % M, s / M) of
                       an M x M grid, see XS_SC_ISRT_* (0: the plain sample cache) */
    xs_uint cross_eye; /* 1: cross-eye reuse (XS_SC_BIND_FOREIGN) */
    xs_float firefly_k; /* firefly rule (sc_shade.rgen): cap / running mean; 0 = off */
    xs_uint debug_permute; /* tests only (XRSC_DEBUG_PERMUTE, mt_samplecache.c): 1 = the
                              reproject, density, trace, shade select and shade launches take
                              their work items in reverse order (sc_work_item, sc_list_entry) */
    xs_uint pool_k;    /* pool entries per pixel (XS_SC_POOL_*) */
    xs_uint stratify; /* 1: new samples fill the pixel's emptiest strata (sc_trace.rgen,
                         XS_SC_STRATA_MAX_G; issue 19) */
    xs_uint moving;   /* 1: the moving-sample rule (XS_SC_MOVING_ALPHA_MIN) on this run: the
                         option xrsc_samplecache_options.moving and a scene with animation */
    xs_uint cover;    /* 1: the cover rule (XS_SC_PLAN_UNOBSERVED) on this run: the option
                         xrsc_samplecache_options.cover with variance-guided shading */
    xs_uint pad_c0;   /* eye_prev's 16-byte alignment */
    xs_uint pad_c1;
    xs_uint pad_c2;
    xs_vec4 eye_prev[2]; /* per eye: xyz its position in the previous frame, w = 1 when there
                            was one (sc_shade.rgen: App. C's clamp follows the view's motion) */
}
XS_END(xs_sc_params);

/* Importance statistics of one eye and copy (§3.5). w_min_inv holds ~floatBitsToUint(w_min)
 * (atomicMax of it is a min of w > 0; 0 = no sample), w_max the float bits of w_max
 * (atomicMax; 0 = no sample), so a zero fill clears both. */
XS_STRUCT(xs_sc_stats)
{
    xs_uint w_min_inv;
    xs_uint w_max;
    xs_uint count; /* samples counted into hist */
    xs_uint pad0;
    xs_uint hist[XS_SC_BUCKETS_STORED];
}
XS_END(xs_sc_stats);

/* Self-test record (sc_selftest.comp): Listing 1 round trip and the Eq. 1 / Eq. 2 test on
 * the device, compared by tests with the C build of xs_sc_math.h. */
XS_STRUCT(xs_sc_selftest_io)
{
    /* in */
    xs_float bary_u, bary_v;
    xs_uint instance, primitive;
    xs_uint material;
    xs_float t, cos_theta, phi;  /* Eq. 1 */
    xs_float t_min, t_max, eps1; /* Eq. 2 (with the Delta of Eq. 1) */
    xs_uint pad0;
    /* out */
    xs_uvec4 packed;
    xs_float out_u, out_v;
    xs_uint out_instance, out_primitive;
    xs_uint out_material;
    xs_float out_delta;
    xs_uint out_consistent;
    xs_uint pad1;
}
XS_END(xs_sc_selftest_io);

#ifndef XRSC_GLSL
_Static_assert(sizeof(xs_sc_params) == 144, "xs_sc_params layout (std140)");
_Static_assert(offsetof(xs_sc_params, eye_prev) == 112, "xs_sc_params layout (std140)");
_Static_assert(offsetof(xs_sc_params, phi_left) == 56, "xs_sc_params layout (std140)");
_Static_assert(sizeof(xs_sc_stats) == 80, "xs_sc_stats layout (std430)");
_Static_assert(sizeof(xs_sc_selftest_io) == 96, "xs_sc_selftest_io layout (std430)");
_Static_assert(offsetof(xs_sc_selftest_io, packed) == 48, "xs_sc_selftest_io layout");
_Static_assert(XS_SC_BUCKETS <= XS_SC_BUCKETS_STORED, "histogram storage");
_Static_assert(XS_SC_GROUP * XS_SC_GROUP >= 2u * XS_SC_BUCKETS_STORED,
               "sc_shade_importance.comp: a workgroup clears and adds both eyes' histograms");
_Static_assert((1u << XS_SC_SHADE_SLOT_BITS) >= XS_SC_MAX_SLOTS, "shade-list slot bits");
_Static_assert(XS_SC_POOL_NONE == XS_SC_SRC_NONE, "a slot no key reached: no pool address");
_Static_assert(XS_SC_POOL_ISRT_FACTOR * XS_SC_MAX_SLOTS <= 32u, "pool entries: 32-bit used word");
_Static_assert(XS_SC_BIND_FIRST > XS_BIND_RAY_COUNTER, "cache bindings after the scene's");
#endif

#endif /* XS_SAMPLECACHE_H */
