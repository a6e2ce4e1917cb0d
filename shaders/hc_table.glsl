// SPDX-License-Identifier: MIT
/**
 * @file hc_table.glsl
 * @brief The hash cache's table (seed 000 §4, seed 001): voxel keys with distance-based LoD,
 *        voxel jitter, double hashing into 2D tiles (BMdD*23), bounded linear probing with
 *        last-access stamps, and the running-mean update. Shared by `hashcache` and `hybrid`.
 *
 * Layout and word format: xs_hashcache.h. Include after xs_bindings.glsl and xs_rng.glsl.
 * Ray-tracing shaders define HC_SET XS_HC_RT_SET first; compute shaders get set 0.
 *
 * Lookup (hc_lookup): the index hash h1 of the key's coarse part picks the first tile, the
 * checksum h2 of the whole key identifies the voxel inside an entry. Probing visits tiles
 * tile0, tile0 + 1, ... (mod tiles) at the same in-tile position, at most XS_HC_MAX_PROBE:
 * - an entry with the key's checksum is the voxel: its stamp becomes this frame (CAS); the one
 *   invocation whose CAS moved the stamp to this frame "reserves" it: it alone traces and
 *   updates this frame (seed 000 §5.1: nearby pixels hitting one voxel trace only once);
 * - an empty entry (stamp 0) ends the search: the key was never inserted beyond it (entries
 *   are never emptied, only overwritten);
 * - the first empty or stale entry (frame - stamp > max_age) seen is where an insert goes
 *   (CAS from the word seen; a stale entry overwritten counts as an eviction). A new entry
 *   carries XS_HC_PENDING until its reserver has written the radiance (hc_store), so no
 *   other invocation ever reads a value written for another voxel.
 * A lost CAS re-reads the entry and decides again; an insert whose CAS is lost to another key
 * fails for this frame. Checksums are 31 bits: two keys of one probe window with equal
 * checksums (probability ~2^-31 per pair) would share an entry.
 */
#ifndef HC_TABLE_GLSL
#define HC_TABLE_GLSL

#extension GL_KHR_memory_scope_semantics : require

#include "xs_hashcache.h"
#include "xs_sc_math.h"

#ifndef HC_SET
#define HC_SET 0
#endif

layout(set = HC_SET, binding = XS_HC_BIND_PARAMS, std140) uniform XsHcParamsBlock
{
    xs_hc_params hcp;
};
layout(set = HC_SET, binding = XS_HC_BIND_WORDS, std430) coherent buffer XsHcWordsBlock
{
    uint64_t hc_words[];
};
layout(set = HC_SET, binding = XS_HC_BIND_RAD, std430) coherent buffer XsHcRadBlock
{
    vec4 hc_rad[];
};
layout(set = HC_SET, binding = XS_HC_BIND_STATS, std430) buffer XsHcStatsBlock
{
    xs_hc_stats hc_stats;
};

/* Seeds of the two hash chains (arbitrary distinct constants). */
#define HC_SEED_INDEX 0x9E3779B9u
#define HC_SEED_CHECK 0x85EBCA6Bu

/** A voxel: integer coordinates at LoD `lod` (edge 2^lod m), the major axis of the hit normal
 *  (0..2) and its sign (0: +, 1: -). */
struct hc_key {
    ivec3 c;
    int lod;
    uint axis;
    uint neg;
};

/** A lookup's outcome: entry -1 = not found (hc_lookup without insert) or failed insert. */
struct hc_slot {
    int entry;
    bool reserved; /* this invocation moved the stamp to this frame: it traces and updates */
    bool fresh;    /* inserted now: no radiance yet (written by hc_store) */
    bool pending;  /* someone else's fresh entry whose radiance is not written yet */
};

uint hc_chain(uint seed, ivec3 c, int lod, uint axis6)
{
    uint h = xs_hash(seed + uint(c.x));
    h = xs_hash(h + uint(c.y));
    h = xs_hash(h + uint(c.z));
    h = xs_hash(h + uint(lod));
    return xs_hash(h + axis6);
}

/** The two in-plane axes (u, v) of major axis w: cyclic order. */
uvec2 hc_plane_axes(uint w) { return uvec2((w + 1u) % 3u, (w + 2u) % 3u); }

/** Pixel footprint per metre of distance of eye. */
float hc_px(uint eye) { return eye == 0u ? hcp.px_left : hcp.px_right; }

/**
 * LoD of a hit at distance dist from eye, seen along unit view direction wo (towards the
 * eye), unit normal n: edge = 2^lod <= voxel_scale * footprint < 2^(lod + 1), the footprint
 * being dist * hc_px(eye), divided by max(|cos theta|, XS_HC_COS_MIN) with distance-normal LoD
 * (seed 000 Fig. 9: coarser at grazing incidence, like trilinear filtering).
 */
int hc_lod(uint eye, float dist, vec3 wo, vec3 n)
{
    float foot = dist * hc_px(eye);
    if (hcp.lod_mode == XS_HC_LOD_DISTANCE_NORMAL)
        foot /= max(abs(dot(wo, n)), XS_HC_COS_MIN);
    float target = hcp.voxel_scale * foot;
    int lod = target > 0.0 ? int(floor(log2(target))) : XS_HC_LOD_MIN;
    return clamp(lod, XS_HC_LOD_MIN, XS_HC_LOD_MAX);
}

/**
 * The key of world point p with unit normal n at LoD lod. With jitter, p first moves by
 * (ju, jv) - 0.5 voxels (ju, jv uniform in [0, 1)) along the two in-plane axes of n's major
 * axis [BFK18]: stochastic filtering over the 2 x 2 neighbouring voxels, which also keeps them
 * alive; never along the normal (that would pick voxels off the surface).
 */
hc_key hc_key_at(vec3 p, vec3 n, int lod, bool jitter, vec2 ju)
{
    vec3 an = abs(n);
    uint w = an.x >= an.y && an.x >= an.z ? 0u : (an.y >= an.z ? 1u : 2u);
    float edge = exp2(float(lod));
    if (jitter) {
        uvec2 uv = hc_plane_axes(w);
        p[uv.x] += (ju.x - 0.5) * edge;
        p[uv.y] += (ju.y - 0.5) * edge;
    }
    hc_key k;
    k.c = ivec3(floor(p / edge));
    k.lod = lod;
    k.axis = w;
    k.neg = n[w] < 0.0 ? 1u : 0u;
    return k;
}

/**
 * True for a view-dependent first hit, which the cache does not serve: the radiance leaving a
 * smooth metal or glass lobe changes with the view direction, so a voxel's mean (shared by all
 * pixels, both eyes and, in `hybrid`, the parent level) is the wrong colour for nearly every
 * pixel that reads it, and a rare bright path (a reflected or refracted light) stored in it
 * lights up the whole voxel. Like hash radiance caches in the literature, such surfaces take
 * this frame's own path through the pixel (the 1 spp path tracer's estimate) and leave the
 * table alone; diffuse and rough surfaces use the cache. The decision is the sample cache's:
 * its App. C clamp (xs_sc_alpha_min_material) above XS_HC_VIEW_DEP_ALPHA_MIN.
 */
bool hc_view_dependent(float metallic, float transmission, float roughness)
{
    return xs_sc_alpha_min_material(metallic, transmission, roughness) > XS_HC_VIEW_DEP_ALPHA_MIN;
}

/**
 * `hybrid`: the tag that hc_hybrid_shade.rgen stores in the alpha of XS_BIND_ACCUM (unused by
 * `hybrid` otherwise) next to the own-path radiance of view-dependent sample s of a pixel, so
 * hc_hybrid_reconstruct.comp uses only this frame's (hcp.frame) value of that very sample
 * (exact in float: < 2^24).
 */
float hc_own_tag(uint s)
{
    return float(1u + s + XS_SC_MAX_SLOTS * (hcp.frame & 0xFFFFu));
}

/** The key one LoD above (edge x 2; the levels nest: floor(c / 2)). */
hc_key hc_parent(hc_key k)
{
    hc_key p = k;
    p.c = k.c >> 1; /* arithmetic shift: floor division for negative coordinates too */
    p.lod = k.lod + 1;
    return p;
}

/* This invocation's statistics: summed here, added to hc_stats once by hc_stats_flush (one
 * atomic per field and invocation instead of several per lookup; hybrid's reconstruction does
 * two lookups per visible sample). */
uint hc_n_lookups = 0u, hc_n_probes = 0u, hc_n_probe_max = 0u, hc_n_found = 0u;
uint hc_n_inserts = 0u, hc_n_evictions = 0u, hc_n_failed = 0u, hc_n_traced = 0u;

/** Adds this invocation's statistics to hc_stats: call before every exit after a lookup. */
void hc_stats_flush()
{
    if (hc_n_lookups == 0u)
        return;
    atomicAdd(hc_stats.lookups, hc_n_lookups);
    atomicAdd(hc_stats.probe_sum, hc_n_probes);
    atomicMax(hc_stats.probe_max, hc_n_probe_max);
    if (hc_n_found > 0u)
        atomicAdd(hc_stats.found, hc_n_found);
    if (hc_n_inserts > 0u)
        atomicAdd(hc_stats.inserts, hc_n_inserts);
    if (hc_n_evictions > 0u)
        atomicAdd(hc_stats.evictions, hc_n_evictions);
    if (hc_n_failed > 0u)
        atomicAdd(hc_stats.failed, hc_n_failed);
    if (hc_n_traced > 0u)
        atomicAdd(hc_stats.traced, hc_n_traced);
    hc_n_lookups = 0u;
}

uint hc_word_stamp(uint64_t w) { return uint(w >> XS_HC_STAMP_SHIFT); }
uint hc_word_check(uint64_t w) { return uint(w) & XS_HC_CHECKSUM_MASK; }
bool hc_word_pending(uint64_t w) { return (uint(w) & XS_HC_PENDING) != 0u; }

/**
 * Finds the key's entry, refreshing its stamp; with insert, claims an entry for it when
 * absent. Counts the lookup (and insert, eviction, failure) for hc_stats_flush.
 */
hc_slot hc_lookup(hc_key k, bool insert)
{
    uvec2 uv = hc_plane_axes(k.axis);
    int cu = k.c[uv.x], cv = k.c[uv.y], cw = k.c[k.axis];
    uint axis6 = k.axis * 2u + k.neg;
    uint tile0 = hc_chain(HC_SEED_INDEX, ivec3(cu >> XS_HC_TILE_SHIFT, cv >> XS_HC_TILE_SHIFT, cw),
                          k.lod, axis6) % hcp.tiles;
    uint in_tile = uint(cu & int(XS_HC_TILE - 1u)) + XS_HC_TILE * uint(cv & int(XS_HC_TILE - 1u));
    uint check = hc_chain(HC_SEED_CHECK, k.c, k.lod, axis6) & XS_HC_CHECKSUM_MASK;
    uint frame_stamp = hcp.frame;
    uint64_t now = uint64_t(frame_stamp) << XS_HC_STAMP_SHIFT;

    hc_slot r;
    r.entry = -1;
    r.reserved = false;
    r.fresh = false;
    r.pending = false;
    int cand = -1;
    uint64_t cand_word = 0ul;
    uint probes = 0u;
    for (uint i = 0u; i < XS_HC_MAX_PROBE && r.entry < 0; i++) {
        uint e = ((tile0 + i) % hcp.tiles) * XS_HC_TILE_ENTRIES + in_tile;
        probes = i + 1u;
        uint64_t w = atomicLoad(hc_words[e], gl_ScopeDevice, gl_StorageSemanticsBuffer,
                                gl_SemanticsRelaxed);
        bool stop = false;
        /* at most two decisions per entry: a lost CAS leaves the entry stamped this frame */
        for (uint attempt = 0u; attempt < 2u; attempt++) {
            uint stamp = hc_word_stamp(w);
            if (stamp == 0u) { /* empty: the key is not further on */
                if (cand < 0) {
                    cand = int(e);
                    cand_word = w;
                }
                stop = true;
                break;
            }
            if (hc_word_check(w) == check) {
                r.entry = int(e);
                if (stamp == frame_stamp) {
                    r.pending = hc_word_pending(w);
                    break;
                }
                uint64_t nw = now | uint64_t(uint(w)); /* same checksum (old entries never pend) */
                uint64_t old = atomicCompSwap(hc_words[e], w, nw);
                if (old == w) {
                    r.reserved = true;
                    break;
                }
                r.entry = -1;
                w = old;
                continue;
            }
            if (cand < 0 && frame_stamp - stamp > hcp.max_age) {
                cand = int(e);
                cand_word = w;
            }
            break;
        }
        if (stop)
            break;
    }
    if (r.entry < 0 && insert) {
        if (cand >= 0) {
            uint64_t nw = now | uint64_t(XS_HC_PENDING | check);
            uint64_t old = atomicCompSwap(hc_words[cand], cand_word, nw);
            if (old == cand_word) {
                r.entry = cand;
                r.reserved = true;
                r.fresh = true;
                hc_n_inserts++;
                if (hc_word_stamp(cand_word) != 0u)
                    hc_n_evictions++;
            } else if (hc_word_check(old) == check) { /* inserted by a neighbour meanwhile */
                r.entry = cand;
                r.pending = hc_word_pending(old);
            }
        }
        if (r.entry < 0)
            hc_n_failed++;
    }
    if (r.entry >= 0 && !r.fresh)
        hc_n_found++;
    hc_n_lookups++;
    hc_n_probes += probes;
    hc_n_probe_max = max(hc_n_probe_max, probes);
    return r;
}

/**
 * The key's written (mean, count) without touching the table: no stamp refresh, no insert, not
 * counted as a lookup; vec4(0) when absent, pending or empty. `hashcache` reads the voxel of a
 * deforming hit's last-frame position with it (xs_hashcache.h, deforming surfaces).
 */
vec4 hc_peek(hc_key k)
{
    uvec2 uv = hc_plane_axes(k.axis);
    int cu = k.c[uv.x], cv = k.c[uv.y], cw = k.c[k.axis];
    uint axis6 = k.axis * 2u + k.neg;
    uint tile0 = hc_chain(HC_SEED_INDEX, ivec3(cu >> XS_HC_TILE_SHIFT, cv >> XS_HC_TILE_SHIFT, cw),
                          k.lod, axis6) % hcp.tiles;
    uint in_tile = uint(cu & int(XS_HC_TILE - 1u)) + XS_HC_TILE * uint(cv & int(XS_HC_TILE - 1u));
    uint check = hc_chain(HC_SEED_CHECK, k.c, k.lod, axis6) & XS_HC_CHECKSUM_MASK;
    for (uint i = 0u; i < XS_HC_MAX_PROBE; i++) {
        uint e = ((tile0 + i) % hcp.tiles) * XS_HC_TILE_ENTRIES + in_tile;
        uint64_t w = atomicLoad(hc_words[e], gl_ScopeDevice, gl_StorageSemanticsBuffer,
                                gl_SemanticsRelaxed);
        if (hc_word_stamp(w) == 0u)
            break;
        if (hc_word_check(w) != check)
            continue;
        if (hc_word_pending(w))
            break;
        memoryBarrierBuffer(); /* acquire, as hc_read */
        vec4 v = hc_rad[e];
        return v.w > 0.0 && xs_finite(v.rgb) ? v : vec4(0.0);
    }
    return vec4(0.0);
}

/** The entry's demodulated radiance mean and count; count 0 when pending (nothing written). */
vec4 hc_read(hc_slot s)
{
    if (s.entry < 0 || s.pending || s.fresh)
        return vec4(0.0);
    memoryBarrierBuffer(); /* acquire: pairs with hc_store's release of XS_HC_PENDING */
    vec4 v = hc_rad[s.entry];
    return v.w > 0.0 ? v : vec4(0.0);
}

/**
 * The reserver's update with one new demodulated observation l: a fresh entry starts at
 * (l, 1) and drops XS_HC_PENDING; an existing one takes the running mean with count
 * min(c + 1, XS_HC_MAX_COUNT). Non-finite l leaves the mean (a fresh entry: count 0).
 * Returns the new (mean, count).
 */
vec4 hc_store_carry(hc_slot s, vec3 l, vec4 prior);
vec4 hc_store(hc_slot s, vec3 l) { return hc_store_carry(s, l, vec4(0.0)); }

/**
 * hc_store, but a fresh entry starts from prior (a mean and count carried from another voxel,
 * count 0: none) as an existing entry would: (mix(prior, l, 1 / c), c = min(prior count + 1,
 * XS_HC_MAX_COUNT)); non-finite l leaves prior.
 */
vec4 hc_store_carry(hc_slot s, vec3 l, vec4 prior)
{
    bool ok = xs_finite(l);
    vec4 v;
    if (s.fresh) {
        float c = min(prior.w + 1.0, XS_HC_MAX_COUNT);
        v = ok ? vec4(prior.w > 0.0 ? mix(prior.rgb, l, 1.0 / c) : l, prior.w > 0.0 ? c : 1.0)
               : prior;
        hc_rad[s.entry] = v;
        memoryBarrierBuffer(); /* release: the radiance before the cleared flag (hc_read) */
        atomicAnd(hc_words[s.entry], ~uint64_t(XS_HC_PENDING));
        return v;
    }
    v = hc_rad[s.entry];
    if (ok) {
        float c = min(v.w + 1.0, XS_HC_MAX_COUNT);
        v = vec4(mix(v.rgb, l, 1.0 / c), c);
        hc_rad[s.entry] = v;
    }
    return v;
}

#endif
