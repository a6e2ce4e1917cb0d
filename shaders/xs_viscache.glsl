// SPDX-License-Identifier: MIT
/**
 * @file xs_viscache.glsl
 * @brief The shading pass's shadow visibility cache (seed 002, AQVC): the quantisation K of
 *        §3.2-3.5, the hashed table of §4.1 and the adaptive refinement of §3.6 (Alg. 2), for
 *        the light samples of the first vertex of sc_shade.rgen's paths.
 *
 * Layout, word format and defaults: xs_viscache.h. Include after xs_path.glsl (which calls
 * xs_vc_visible through XS_LIGHT_VISIBLE when XS_PATH_VISCACHE is defined) in a ray-tracing
 * shader whose set XS_SC_RT_SET holds XS_VC_BIND_STATE and XS_VC_BIND_TABLE.
 *
 * A query V(X, Y) is quantised to a cluster (§3.3): X's geometric normal to Eq. 4's direction
 * d_z (C_N bins per axis), which orients a virtual grid of cell edge h and depth h / C_Z; the
 * edge comes from Eq. 7 with the screen-space reading of §3.4: a cluster holds C_E x C_E eye
 * samples, so h = C_E x the pixel footprint at X (distance x tan-space pixel size /
 * sqrt(|cos theta| x shaded samples per pixel)); R = 2 B_R / h is quantised by Eq. 8 (C_R).
 * Clusters are world-space, so both eyes share them: where both see X a cluster holds about
 * 2 C_E^2 shading samples (the error region stays C_E x C_E pixels in each eye).
 * The light end (§3.5, light samples per eye path N_P / N_S = 1 for each light):
 * - a delta light: a directional light's direction (the sun's or one of XS_BIND_LIGHTS), a
 *   point or spot light's position Y: its float bits (the light is one point of the light
 *   "patch" grid; a moving light gets new clusters);
 * - a sampled direction (sky sun disk, environment map) with solid-angle pdf P: the cell of an
 *   R x R grid on the octahedral map, R^2 = 4 pi P (a cell of ~4 pi / R^2 sr then holds one
 *   light sample per eye path, as Eq. 7's light patches do; Eq. 9 as printed puts 4 pi in the
 *   denominator, which for a pdf per steradian gives cells (4 pi)^2 times too large);
 * - a point Y on an emissive triangle with area density P = pmf / area: Y's own oriented grid
 *   (its normal) with edge h_l = sqrt(1 / P) (Eq. 7's R(p_l)).
 * The tuple (semantics, side of X the ray leaves from, light end, X's orientation and cell, R)
 * is hashed to a 64-bit digest with §4.1's second scheme (d <- A(C(d)) xor j: an LCG C then a
 * xor-shift A): the table index from its high 32 bits, a 62-bit fingerprint from a further mix.
 *
 * Alg. 2 (C_MSR = vc.p.levels levels, C_E halved per level), made independent of the order
 * in which the invocations of a launch run (a GPU runs them all at once, so "the first query of
 * a cluster inserts, the later ones read" caches nothing there): the frame's shading launch is
 * preceded by C_MSR rounds of two pre-pass launches (XS_VC_PHASE_*, mt_viscache.c), each
 * stopping after the first vertex's light samples. Round r, request: a query whose walk
 * reaches level r at an empty entry atomicMin's its claim key (vc_claim_key: list entry, query
 * number, level) into the entry's claim word; insert: the query holding the claim traces its
 * ray (the cluster's representative, §3.4) and stores the result. Entries of levels < r are
 * final during round r and entries of level r are never read in it, so no launch reads what
 * it writes. The shading launch then only reads: a query whose cluster is empty or foreign
 * (its index went to another cluster, §4.1) traces its own ray; the winner uses its own
 * stored ray (not cached); a known entry answers when its X neighbours agree:
 * entry answers when its X neighbours agree:
 * - adaptive (Alg. 2): the 4 neighbours (u +- 1, v +- 1) agree or are unknown; after the last
 *   level the finest cluster's value answers;
 * - strict (zero refinement error tolerance): all 8 neighbours of the 3 x 3 block known and
 *   agreeing, and after the last level the query traces instead. For a shadow edge that is a
 *   straight line across the block, each side of the line holds a whole neighbour cell, so a
 *   cluster cut by such an edge always finds a known disagreeing neighbour or traces;
 * - none (Alg. 1): the cluster's value, no neighbours.
 * No random number is drawn here, so with every query traced the image equals the uncached one.
 */
#ifndef XS_VISCACHE_GLSL
#define XS_VISCACHE_GLSL

#extension GL_KHR_memory_scope_semantics : require

#include "xs_samplecache.h"
#include "xs_viscache.h"

layout(set = XS_SC_RT_SET, binding = XS_VC_BIND_STATE, std430) buffer XsVcStateBlock
{
    xs_vc_state vc;
};
layout(set = XS_SC_RT_SET, binding = XS_VC_BIND_TABLE, std430) coherent buffer XsVcTableBlock
{
    uint64_t vc_words[];
};

/* §4.1's generators: Knuth's 64-bit LCG (C) and Marsaglia's xor-shift (13, 7, 17) (A). */
#define VC_LCG_MUL 6364136223846793005ul
#define VC_LCG_ADD 1442695040888963407ul
#define VC_SEED 0x243F6A8885A308D3ul
/* Integer cell coordinates stay within +-2^30 (float to int conversion). */
#define VC_CELL_MAX 1073741824.0

/* The first vertex of this invocation's shading path (vc_begin). */
float vc_first_t = 0.0;
float vc_foot_per_m = 0.0; /* pixel footprint edge per metre of distance (cos theta = 1) */
vec3 vc_view_dir = vec3(0.0);

/* This invocation's counters, added to vc once by vc_flush. */
uint vc_n_queries = 0u, vc_n_cached = 0u, vc_n_shadow = 0u, vc_n_refined = 0u;
/* This invocation's list entry and its cache queries so far, every pass (the claim keys). */
uint vc_entry = 0u, vc_n_paths_queries = 0u;

/** Whether this launch is one of the frame's pre-passes (xs_path_trace stops after the first
 *  vertex's light samples, sc_shade.rgen stores nothing). */
layout(constant_id = XS_SPEC_VISCACHE_ID) const bool XS_SPEC_VISCACHE = true;

bool xs_vc_prepass()
{
    return XS_SPEC_VISCACHE && vc.p.enabled != 0u && vc.p.phase != XS_VC_PHASE_SHADE;
}

/** The shading sample's eye, distance to and unit direction of its first hit. */
void vc_begin(uint entry, uint eye, float t, vec3 dir)
{
    vc_entry = entry;
    float tan_px = eye == 0u ? vc.p.pixel_tan_left : vc.p.pixel_tan_right;
    vc_first_t = t;
    vc_view_dir = dir;
    vc_foot_per_m = tan_px * inversesqrt(max(vc.p.eye_samples_per_px, 1e-6));
}

void vc_flush()
{
    if (vc_n_shadow > 0u)
        atomicAdd(vc.shadow_rays, vc_n_shadow);
    if (vc_n_queries > 0u)
        atomicAdd(vc.queries, vc_n_queries);
    if (vc_n_cached > 0u)
        atomicAdd(vc.cached, vc_n_cached);
    if (vc_n_refined > 0u)
        atomicAdd(vc.refined, vc_n_refined);
}

uint64_t vc_step(uint64_t d, int j)
{
    d = d * VC_LCG_MUL + VC_LCG_ADD;
    d ^= d << 13;
    d ^= d >> 7;
    d ^= d << 17;
    return d ^ uint64_t(uint(j));
}

/** Fingerprint (bits 2..63) of a final digest: one more mix, so it is not the index's bits. */
uint64_t vc_fingerprint(uint64_t d)
{
    d ^= d >> 30;
    d *= 0xBF58476D1CE4E5B9ul;
    d ^= d >> 27;
    d *= 0x94D049BB133111EBul;
    d ^= d >> 31;
    return d << 2;
}

/** Eq. 8: the exponent k of a resolution R (R < 1: one cell for the whole scene). */
int vc_exponent(float r)
{
    float k = ceil(log(max(r, 1.0)) / vc.p.log_resolution_base + 0.5);
    return int(min(k, float(XS_VC_MAX_EXPONENT)));
}

/** Eq. 8: the quantised resolution floor(C_R^k). */
float vc_resolution(int k)
{
    return max(floor(exp(float(k) * vc.p.log_resolution_base)), 1.0);
}

/** Eq. 4: the quantised direction of unit normal n (its C_N bins, xyz) and the grid's axes. */
struct vc_grid {
    ivec3 bins;
    vec3 t, b, z;
};

vc_grid vc_grid_of(vec3 n)
{
    vc_grid g;
    vec3 wq = floor((n + 1.0) * 0.5 * vc.p.normal_bins);
    g.bins = ivec3(wq);
    g.z = normalize(2.0 * wq / vc.p.normal_bins - 1.0); /* never 0 for a unit n */
    xs_onb(g.z, g.t, g.b);
    return g;
}

int vc_coord(float x)
{
    return int(clamp(floor(x), -VC_CELL_MAX, VC_CELL_MAX));
}

/** The cell (u, v, w) of p in grid g for a wanted edge of edge_m metres, and Eq. 8's k. */
ivec4 vc_cell(vc_grid g, vec3 p, float edge_m)
{
    int k = vc_exponent(vc.p.scene_diameter / max(edge_m, 1e-30));
    float h = vc.p.scene_diameter / vc_resolution(k);
    return ivec4(vc_coord(dot(p, g.t) / h), vc_coord(dot(p, g.b) / h),
                 vc_coord(dot(p, g.z) * vc.p.depth_ratio / h), k);
}

/** Octahedral map of unit w onto [0, 1]^2 (§3.5, [ED08]). */
vec2 vc_octahedral(vec3 w)
{
    w /= abs(w.x) + abs(w.y) + abs(w.z);
    vec2 p = w.xy;
    if (w.z < 0.0) {
        vec2 s = vec2(p.x >= 0.0 ? 1.0 : -1.0, p.y >= 0.0 ? 1.0 : -1.0);
        p = (1.0 - abs(p.yx)) * s;
    }
    return p * 0.5 + 0.5;
}

/** The digest of the light end and the semantics (§3.5), the prefix of every level's tuple. */
uint64_t vc_light_digest(uint kind, bool below, vec3 lp, vec3 ln, float density)
{
    uint64_t h = vc_step(VC_SEED, int(kind | (below ? 4u : 0u)));
    if (kind == XS_VC_LIGHT_DIRECTION || kind == XS_VC_LIGHT_POINT) {
        ivec3 b = floatBitsToInt(lp);
        h = vc_step(vc_step(vc_step(h, b.x), b.y), b.z);
    } else if (kind == XS_VC_LIGHT_SOLID_ANGLE) {
        int k = vc_exponent(sqrt(4.0 * XS_PI * density));
        float r = vc_resolution(k);
        vec2 c = min(floor(vc_octahedral(lp) * r), vec2(r - 1.0));
        h = vc_step(vc_step(vc_step(h, int(c.x)), int(c.y)), k);
    } else {
        vc_grid g = vc_grid_of(ln);
        ivec4 c = vc_cell(g, lp, inversesqrt(density));
        h = vc_step(vc_step(vc_step(h, g.bins.x), g.bins.y), g.bins.z);
        h = vc_step(vc_step(vc_step(vc_step(h, c.x), c.y), c.z), c.w);
    }
    return h;
}

/** Digest of the full tuple: prefix (light end, X's orientation), then X's cell and k. */
uint64_t vc_digest(uint64_t prefix, ivec4 c)
{
    return vc_step(vc_step(vc_step(vc_step(vc_step(prefix, c.x), c.y), c.z), c.w), 0);
}

uint vc_index(uint64_t d)
{
    return uint(d >> 32) % vc.p.entries;
}

/** The state of the cluster of digest d: 0 (nil: empty, foreign key), or XS_VC_* of its word. */
uint vc_lookup(uint64_t d, out uint index, out uint64_t word)
{
    index = vc_index(d);
    word = atomicLoad(vc_words[index], gl_ScopeDevice, gl_StorageSemanticsBuffer,
                      gl_SemanticsRelaxed);
    return (word & ~uint64_t(XS_VC_STATE_MASK)) == vc_fingerprint(d)
               ? uint(word) & XS_VC_STATE_MASK
               : 0u;
}

vec3 vc_trace(vec3 o, vec3 d, float tmax, inout uint rays)
{
    vc_n_shadow++;
    return xs_visible(o, d, tmax, rays);
}

/** The claim word of table entry index (the second half of the table, xs_viscache.h). */
uint64_t vc_claim_at(uint index)
{
    return vc_words[vc.p.entries + index];
}

/** This query's claim key at a level: its list entry (pixel and slot, fixed by the sample,
 *  not by the invocation running it), its number among the path's queries and the level, so
 *  the smallest key, the winner, is the same whatever order the invocations run in. */
uint64_t vc_claim_key(uint query, uint level)
{
    return (uint64_t(vc_entry) << 24) | (uint64_t(query) << 8) | uint64_t(level);
}

/** Round `round`'s pre-pass at a query's cluster of that level (index, fingerprint of d):
 *  request (an empty entry: atomicMin of the key, order-independent) or insert (the winner
 *  traces its ray, the cluster's representative, §3.4, and stores it). A ray through glass
 *  (neither 0 nor 1, xs_visible) is not a binary state: nothing is stored, the entry stays
 *  empty and the cluster's queries trace. */
void vc_prepass_at(bool insert, uint64_t d, uint index, uint64_t key, vec3 o, vec3 dir,
                   float tmax, inout uint rays)
{
    if (!insert) {
        if (vc_words[index] == 0ul) /* stable: nothing writes words in a request pass */
            atomicMin(vc_words[vc.p.entries + index], key);
        return;
    }
    if (vc_claim_at(index) != key)
        return;
    vec3 v = vc_trace(o, dir, tmax, rays);
    if (all(equal(v, vec3(0.0))) || all(equal(v, vec3(1.0))))
        vc_words[index] = vc_fingerprint(d) | uint64_t(v.x > 0.0 ? XS_VC_VISIBLE : XS_VC_OCCLUDED);
}

/** §3.6: do X's neighbouring clusters agree with state st? Adaptive: the 4 edge neighbours,
 *  unknown ones agree; strict: all 8 of the 3 x 3 block, unknown ones disagree. */
bool vc_neighbours_agree(uint64_t prefix, ivec4 c, uint st, bool strict)
{
    for (int dy = -1; dy <= 1; dy++)
        for (int dx = -1; dx <= 1; dx++) {
            if ((dx == 0 && dy == 0) || (!strict && dx != 0 && dy != 0))
                continue;
            uint index;
            uint64_t word;
            uint n = vc_lookup(vc_digest(prefix, c + ivec4(dx, dy, 0, 0)), index, word);
            if (n == 0u ? strict : n != st)
                return false;
        }
    return true;
}

/**
 * V(X, Y) of a light sample: from the cache at the first vertex (bounce 0) when enabled, else
 * traced. o, d, tmax: the shadow ray; s: X; below: the ray leaves below X's surface
 * (transmission); kind: XS_VC_LIGHT_*; lp: the direction (DIRECTION, SOLID_ANGLE) or Y (AREA,
 * POINT: the light's position); ln: Y's normal (AREA); density: the light sample's pdf
 * (solid angle, or per m^2 for AREA; delta lights pass 1).
 */
vec3 xs_vc_visible(vec3 o, vec3 d, float tmax, uint bounce, xs_surface s, bool below,
                   uint kind, vec3 lp, vec3 ln, float density, inout uint rays)
{
    uint phase = vc.p.phase;
    bool pre = phase != XS_VC_PHASE_SHADE;
    if (!XS_SPEC_VISCACHE || vc.p.enabled == 0u || bounce != 0u || !(density > 0.0) || !(vc_first_t > 0.0))
        return pre ? vec3(0.0) : vc_trace(o, d, tmax, rays);
    uint round = (phase - 1u) >> 1; /* pre-passes: XS_VC_PHASE_* */
    bool insert = (phase & 1u) == 0u;
    uint query = vc_n_paths_queries++;
    if (!pre)
        vc_n_queries++;
    vc_grid gx = vc_grid_of(s.ng);
    uint64_t prefix = vc_light_digest(kind, below, lp, ln, density);
    prefix = vc_step(vc_step(vc_step(prefix, gx.bins.x), gx.bins.y), gx.bins.z);
    float cos_t = max(abs(dot(vc_view_dir, s.ng)), XS_VC_COS_MIN);
    float foot = vc_first_t * vc_foot_per_m * inversesqrt(cos_t); /* one sample's footprint */
    float ce = vc.p.error_px;
    bool strict = vc.p.refine == XS_VC_REFINE_STRICT;
    uint finest = 0u; /* the state of the last level's cluster */
    bool agreed = false;
    for (uint level = 0u; level < vc.p.levels; level++) {
        if (level == 1u && !pre)
            vc_n_refined++;
        ivec4 c = vc_cell(gx, s.p, ce * foot);
        uint64_t dg = vc_digest(prefix, c);
        uint64_t key = vc_claim_key(query, level);
        uint index = vc_index(dg);
        if (pre && level == round) { /* this round's clusters: not looked up while written */
            vc_prepass_at(insert, dg, index, key, o, d, tmax, rays);
            return vec3(0.0);
        }
        uint64_t word;
        uint st = vc_lookup(dg, index, word);
        if (st == 0u) /* not inserted (lost to another cluster of its index): its own ray */
            return pre ? vec3(0.0) : vc_trace(o, d, tmax, rays);
        if (vc_claim_at(index) == key) /* this query's ray, traced by its insert pass */
            return vec3(st == XS_VC_VISIBLE ? 1.0 : 0.0);
        finest = st;
        agreed = vc.p.refine == XS_VC_REFINE_NONE || vc_neighbours_agree(prefix, c, st, strict);
        if (agreed)
            break;
        ce *= 0.5; /* §3.6: halve C_E and recurse */
    }
    if (pre)
        return vec3(0.0);
    if (!agreed && strict) /* zero tolerance: disagreement down to the last level traces */
        return vc_trace(o, d, tmax, rays);
    vc_n_cached++; /* adaptive without agreement: Alg. 2 returns the finest cluster's value */
    return vec3(finest == XS_VC_VISIBLE ? 1.0 : 0.0);
}

#endif
