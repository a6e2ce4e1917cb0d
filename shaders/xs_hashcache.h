// SPDX-License-Identifier: MIT
/**
 * @file xs_hashcache.h
 * @brief The world-space hash cache of `hashcache` and `hybrid` (seed 000 §4, seed 001):
 *        bindings, parameter/statistics layouts, entry format, limits and defaults, shared by
 *        C and GLSL (compiled with -DXRSC_GLSL). The table logic is shaders/hc_table.glsl.
 *
 * Storage (storage BUFFERS: lavapipe has 64-bit atomics on buffers only), E = table entries,
 * a multiple of XS_HC_TILE_ENTRIES; 24 B per entry (seed 000 §4):
 *   words[E]  uint64: last-access stamp (bits 32..63, frame number >= 1; 0 = never used) |
 *             XS_HC_PENDING (bit 31: reserved this frame, radiance not written yet) |
 *             checksum (bits 0..30, the second hash of the voxel key); 64-bit atomics
 *   rad[E]    vec4: running mean of DEMODULATED radiance (rgb) and its sample count (a)
 * Entries come in tiles of XS_HC_TILE x XS_HC_TILE (BMdD*23): the voxel key is (integer voxel
 * coordinates c at LoD l, l, the hit normal's major axis and its sign); with u, v the two axes
 * other than the major axis w, the index hash of (c_u >> 2, c_v >> 2, c_w, l, axis) picks the
 * tile and (c_u & 3, c_v & 3) the entry inside it, so a 4 x 4 patch of neighbouring voxels on a
 * surface facing w lies in 16 consecutive entries. Linear probing moves to the next TILE at
 * the same in-tile position (tile + i mod tiles, i < XS_HC_MAX_PROBE), so a patch probes
 * together and stays coherent.
 */
#ifndef XS_HASHCACHE_H
#define XS_HASHCACHE_H

#include "xrsc_shared.h"

/* Bindings: set 1 of the ray-tracing programs; set 0 of the compute programs (next to the
 * scene's XS_BIND_* and, in `hybrid`, the sample cache's XS_SC_BIND_* 16..28). */
#define XS_HC_BIND_FIRST 32
#define XS_HC_BIND_PARAMS 32 /* uniform xs_hc_params */
#define XS_HC_BIND_WORDS 33  /* buffer uint64[E] */
#define XS_HC_BIND_RAD 34    /* buffer vec4[E] */
#define XS_HC_BIND_STATS 35  /* buffer xs_hc_stats */
#define XS_HC_BIND_HITS 36   /* `hashcache` only: buffer uvec4[2 * W * H], pass 1's first hits */
#define XS_HC_BIND_SELFTEST 37 /* buffer xs_hc_selftest_io[] (hc_selftest.comp only) */
#define XS_HC_BIND_PREV_POS 38 /* readonly buffer vec4[], last frame's posed
                                * object-space position per scene vertex (gpu_deform.h) */
/* Descriptor set of these bindings in ray-tracing programs. */
#define XS_HC_RT_SET 1

/* Entry word fields. */
#define XS_HC_STAMP_SHIFT 32u
#define XS_HC_PENDING 0x80000000u
#define XS_HC_CHECKSUM_MASK 0x7FFFFFFFu

/* Tiles (BMdD*23): XS_HC_TILE x XS_HC_TILE entries, in-tile position from the low
 * XS_HC_TILE_SHIFT bits of the two in-plane voxel coordinates. */
#define XS_HC_TILE_SHIFT 2u
#define XS_HC_TILE (1u << XS_HC_TILE_SHIFT)
#define XS_HC_TILE_ENTRIES (XS_HC_TILE * XS_HC_TILE)
/* Linear probing: tiles visited at most (a lookup that finds neither its key, an empty entry
 * nor a stale one within them fails: counted as a failed insert). */
#define XS_HC_MAX_PROBE 8u

/* Level of detail: voxel edge = 2^lod metres, lod = floor(log2(voxel_scale * pixel footprint
 * at the hit)), clamped to [XS_HC_LOD_MIN, XS_HC_LOD_MAX] (2^-20 m ~ 1 um .. 1 km). */
#define XS_HC_LOD_MIN (-20)
#define XS_HC_LOD_MAX 10
/* distance-normal LoD: the footprint grows as 1 / |cos theta|, with |cos theta| >= this
 * (at most ~4.3 levels coarser at grazing incidence). */
#define XS_HC_COS_MIN 0.05
/* Running mean: the count stops growing here (an exponential average with weight 1/this
 * afterwards, so lighting changes still fade in). */
#define XS_HC_MAX_COUNT 256.0
/* View-dependent surfaces are not served from the cache (hc_view_dependent in hc_table.glsl):
 * a first hit whose sample-cache clamp (App. C, xs_sc_alpha_min_material) exceeds this gets
 * its own path instead. Full metal or glass: GGX alpha < 0.5 (roughness < ~0.71); a half
 * metallic surface never (its clamp is at most 0.25). */
#define XS_HC_VIEW_DEP_ALPHA_MIN 0.3

/* Defaults (xrsc_hashcache_options). */
#define XS_HC_DEFAULT_TABLE_ENTRIES (1u << 22)
#define XS_HC_DEFAULT_VOXEL_SCALE 0.5
#define XS_HC_DEFAULT_MAX_AGE 64u

/* Values of xs_hc_params.lod_mode (= public xrsc_hc_lod - 1, checked in C). */
#define XS_HC_LOD_DISTANCE 0u
#define XS_HC_LOD_DISTANCE_NORMAL 1u

/* Compute workgroup size of hc_occupancy.comp and the entries each invocation scans. */
#define XS_HC_SCAN_GROUP 256u
#define XS_HC_SCAN_PER_INVOCATION 16u

XS_STRUCT(xs_hc_params)
{
    xs_uint frame;        /* the stamp of this frame (>= 1, +1 per rendered frame) */
    xs_uint max_age;      /* entries with frame - stamp > max_age may be overwritten */
    xs_uint tiles;        /* table entries / XS_HC_TILE_ENTRIES */
    xs_uint lod_mode;     /* XS_HC_LOD_* */
    xs_uint jitter;       /* 1: voxel jitter [BFK18] before the lookup */
    xs_uint entries;      /* table entries */
    xs_uint deform;        /* 1 = XS_HC_BIND_PREV_POS holds deformed meshes' last
                              poses (their lookups are counted in deform_*) */
    xs_uint deform_follow; /* 1 (with deform): deforming hits follow their surface (below) */
    xs_float voxel_scale; /* voxel edge / pixel footprint (before rounding down to 2^lod) */
    xs_float px_left;     /* per eye: pixel footprint per metre of distance (tan-space pixel
                             size at the image centre, the larger of width and height) */
    xs_float px_right;
    xs_float pad2;
}
XS_END(xs_hc_params);

/* Per-frame statistics (zeroed at the frame start; hc_occupancy.comp fills `occupied` on
 * request). A lookup is one probe sequence; inserts count claimed entries (empty or stale),
 * evictions those of them that were stale (held another voxel), failed the lookups that
 * wanted to insert and could not. */
XS_STRUCT(xs_hc_stats)
{
    xs_uint lookups;
    xs_uint probe_sum; /* tiles visited, summed over lookups */
    xs_uint probe_max;
    xs_uint found;
    xs_uint inserts;
    xs_uint evictions;
    xs_uint failed;
    xs_uint traced;   /* secondary paths traced for the cache */
    xs_uint occupied; /* entries with a stamp within max_age (hc_occupancy.comp) */
    xs_uint deform_lookups; /* lookups of hits on a deforming surface (params.deform;
                               `hybrid`: its reconstruction's) */
    xs_uint deform_history; /* of those, the ones whose voxel value holds earlier frames'
                               samples (count > 1 after this frame's update; `hybrid`: the
                               voxel's or its parent's) */
    xs_uint pad0;
}
XS_END(xs_hc_stats);

/* Deforming surfaces (issue 21 item 3; `hashcache` and `hybrid` with params.deform_follow;
 * hc_deform.glsl): a hit on a
 * skinned or morphed mesh whose posed point moved since the last frame keys its voxel by this
 * frame's world position as any hit does, but when that voxel is inserted now (fresh), the
 * running mean of the voxel of the hit's LAST-frame position (same triangle and barycentrics
 * on XS_HC_BIND_PREV_POS, through prev_object_to_world; same LoD, normal axis and jitter) is
 * carried into it: the new voxel starts at that (mean, count) plus this frame's sample, so a
 * walking figure keeps its history instead of restarting every voxel it moves into (a pixel
 * whose voxel holds no value yet uses that carried mean plus its own path likewise). The old
 * voxel is only read (its stamp is not refreshed). Rigid meshes and still vertices never take
 * this path (their motion is 0). `hybrid` carries the mean into the voxels its shading pass
 * inserts (at the sample's level, its parent's or its own, with its jitter), and its
 * reconstruction, whose two unjittered voxels of a deforming sample may hold nothing yet, reads
 * those of the last-frame position instead. */

/* Self-test record (hc_selftest.comp, tests): one lookup of a given key. mode
 * XS_HC_SELFTEST_STORE: hc_lookup with insert, and the reserver stores `value` (rgb); mode
 * XS_HC_SELFTEST_LOOKUP: hc_lookup without insert and hc_read. */
#define XS_HC_SELFTEST_GROUP 64u /* local_size_x of hc_selftest.comp */
#define XS_HC_SELFTEST_STORE 0u
#define XS_HC_SELFTEST_LOOKUP 1u
XS_STRUCT(xs_hc_selftest_io)
{
    /* in */
    xs_uint cx, cy, cz; /* voxel coordinates (int bits) */
    xs_uint lod;        /* int bits */
    xs_uint axis6;      /* major axis * 2 + (normal component < 0) */
    xs_uint mode;       /* XS_HC_SELFTEST_* */
    xs_float value;
    xs_uint pad0;
    /* out */
    xs_uint found;    /* the lookup returned an entry (found or inserted) */
    xs_uint reserved; /* this invocation reserved it (moved its stamp to this frame) */
    xs_float read;    /* LOOKUP: hc_read's mean (red channel) ... */
    xs_float read_count; /* ... and count (0: nothing written) */
}
XS_END(xs_hc_selftest_io);

#ifndef XRSC_GLSL
_Static_assert(sizeof(xs_hc_selftest_io) == 48, "xs_hc_selftest_io layout (std430)");
_Static_assert(sizeof(xs_hc_params) == 48, "xs_hc_params layout (std140)");
_Static_assert(sizeof(xs_hc_stats) == 48, "xs_hc_stats layout (std430)");
_Static_assert(XS_HC_BIND_FIRST > XS_BIND_RAY_COUNTER, "after the scene's bindings");
#endif

#endif /* XS_HASHCACHE_H */
