// SPDX-License-Identifier: MIT
/**
 * @file sc_shade_select.comp
 * @brief Sample cache pass "shade", part 1 (seed 000 §3.3, §3.5): which visible samples are
 *        re-shaded this frame (plan.z).
 *
 * Candidates are the visible surface samples (background samples need no shading).
 * - uniform: one candidate per pixel, round robin over the slots (§3.3);
 * - adaptive: one candidate of one pixel per block x block block as base rate (as in
 *   sc_copy.comp's trace mask), plus a share of all candidates chosen by importance
 *   w = 1 / (1 + c_s)
 *   (adaptive-variance: w = the relative variance of the sample's mean, v / (1 + c_s), v from
 *   the spread of the pixel's samples, which sc_shade_importance.comp leaves in plan.z, with
 *   the candidates in plan.y's upper half and this frame's histogram):
 *   the budget B = shade_rate * width * height - (base-rate shadings) is met by walking the
 *   histogram of this frame (counted during reprojection and tracing into XS_SC_BUCKETS
 *   logarithmic buckets between the previous frame's w_min and w_max) from the most important
 *   bucket down: buckets above the one where the prefix sum crosses B are all shaded, that
 *   bucket's samples by a coin toss with probability (B - above) / count, so B samples are
 *   shaded in expectation (§3.5, Fig. 5). With adaptive-variance, a pixel whose candidates'
 *   buckets (plan.w's range) all lie above or all below that bucket is decided without
 *   loading them again (decided()).
 * With the moving-sample rule (scp.moving, xrsc_samplecache_options.moving; off by default)
 * a pixel with samples whose instance turned since the previous frame shades one of them more,
 * in every mode: the next moving one in a round robin over them that is not chosen yet
 * (XS_SC_MOVING_ALPHA_MIN: their cached radiance belongs to the old pose); at most one more
 * shading per pixel, so a view full of moving objects costs at most one shading more per
 * pixel. Without the rule (and in a scene without animation) the choice is the one above.
 * The chosen samples are recorded per pixel in plan.z and compacted into the shade list (one
 * atomicAdd per pixel), which sc_shade.rgen walks, so pixels with many chosen samples do not
 * serialise the shading launch; entries beyond scp.shade_capacity are dropped (the count
 * keeps the total; mt_samplecache.c sizes the capacity).
 */
#version 460
#extension GL_GOOGLE_include_directive : require
#define XS_NO_TLAS
#include "xs_bindings.glsl"
#include "xs_hitinfo.glsl"
#include "xs_rng.glsl"
#include "sc_common.glsl"

layout(local_size_x = XS_SC_GROUP, local_size_y = XS_SC_GROUP, local_size_z = 1) in;

/* RNG stream of the coin tosses (sample index of xs_rng_seed). */
#define SC_SHADE_STREAM 0x5EADE000u
/* Offset of the shading round robin against the tracing one (different slots when possible). */
#define SC_SHADE_RR_OFFSET 1u

/** The ((k mod n) + 1)-th lowest set bit of bits (n of them), or -1 when bits is 0: a round
 *  robin over a pixel's moving candidates, each chosen once in n frames while the set stays. */
int moving_rank(uint bits, uint k)
{
    uint n = uint(bitCount(bits));
    if (n == 0u)
        return -1;
    for (uint i = k % n; i > 0u; i--)
        bits &= bits - 1u;
    return findLSB(bits);
}

/** The candidates among cand whose instance turned since the previous frame (a pixel's samples
 *  mostly share one instance: its transforms are compared once per run of them). */
uint moving_candidates(uint cur, uint pix, uint cand)
{
    uint moving = 0u, last = XS_SC_BACKGROUND;
    bool moved = false;
    for (uint cb = cand; cb != 0u; cb &= cb - 1u) {
        uint s = uint(findLSB(cb));
        uint instance = sc_fh[sc_slot_at(cur, s, pix)].w;
        if (instance != last)
            moved = sc_instance_turned(instance);
        last = instance;
        if (moved)
            moving |= sc_obit(s);
    }
    return moving;
}

/* RNG stream of cross-eye reuse's uniform shading coin (sample index of xs_rng_seed). */
#define SC_SHADE_SHARE_STREAM 0x5EADE5E1u

/**
 * Uniform shading with cross-eye reuse: the pixel's share of one shading, bitCount(own) /
 * bitCount(cand) (the other eye's copies are its owner's to shade), given to one own sample by
 * the round robin over the own samples. The round robin over all candidates would skip to a
 * copy whenever one sits in the slots it favours (a free-slot reservation puts samples into
 * the lowest free slots, so slots are not equally likely).
 */
uint uniform_share(uvec3 g, uint cand, uint foreign, uint start)
{
    uint own = cand & ~foreign;
    int rr = sc_round_robin(own, start);
    if (rr < 0)
        return 0u;
    xs_rng rng = xs_rng_seed(g.xy, g.z, frame.frame_index, SC_SHADE_SHARE_STREAM, frame.seed);
    float p = float(bitCount(own)) / float(bitCount(cand));
    return xs_rng_next(rng) < p ? sc_obit(uint(rr)) : 0u;
}

/**
 * Variance-guided shading: whether the bucket range that sc_shade_importance.comp left in
 * plan.w (XS_SC_PLAN_RANGE_*) decides all of the pixel's candidates against threshold bucket k
 * at once: all above it (all chosen, added to bits) or all below (none). The loop below would
 * choose the same: a candidate is chosen when its bucket is above k, by a coin when it is k.
 * Its coins come from the pixel's own stream, which nothing draws from afterwards. On lavapipe
 * this skips two per-lane loads per candidate (pool address, radiance record) for most pixels.
 */
bool decided(uint range, int k, uint cand, inout uint bits)
{
    if ((range & XS_SC_PLAN_RANGE_SET) == 0u)
        return false;
    int lo = int(range & XS_SC_PLAN_RANGE_MASK);
    int hi = int((range >> XS_SC_PLAN_RANGE_HI_SHIFT) & XS_SC_PLAN_RANGE_MASK);
    if (lo > k) {
        bits |= cand;
        return true;
    }
    return hi < k;
}

void main()
{
    uvec3 g = gl_GlobalInvocationID;
    if (g.x >= frame.width || g.y >= frame.height)
        return;
    g = sc_work_item(g);
    uint eye = g.z;
    uint pix = sc_pix(eye, g.xy);
    uint cur = scp.cur;
    uint cand;
    if (scp.shade_mode == XS_SC_SHADE_ADAPTIVE_VARIANCE) { /* sc_shade_importance.comp's */
        uint y = sc_plan[pix].y;
        cand = y >> XS_SC_MAX_SLOTS;
        sc_plan[pix].y = y & ((1u << XS_SC_MAX_SLOTS) - 1u); /* the new-sample bits again */
    } else {
        cand = sc_shade_candidates(cur, pix);
    }
    uint foreign = sc_foreign_bits(cur, pix); /* cross-eye reuse: the other eye's copies */
    uint start = (frame.frame_index + SC_SHADE_RR_OFFSET) % scp.slots;
    int rr = sc_round_robin(cand, start);
    uint one = rr >= 0 ? sc_obit(uint(rr)) : 0u;
    uint bits = 0u;
    if (scp.shade_mode == XS_SC_SHADE_UNIFORM && scp.cross_eye != 0u) {
        bits = uniform_share(g, cand, foreign, start);
    } else if (scp.shade_mode == XS_SC_SHADE_UNIFORM) {
        bits = one;
    } else {
        uint b = scp.block;
        uvec2 blk = g.xy / b;
        uint local = (g.x % b) + (g.y % b) * b;
        uint pick = (frame.frame_index + xs_hash(xs_hash(blk.x + eye + SC_SHADE_RR_OFFSET) + blk.y)) %
                    (b * b);
        bits = local == pick ? one : 0u;

        uint base_count = ((frame.width + b - 1u) / b) * ((frame.height + b - 1u) / b);
        float budget = max(scp.shade_rate * float(frame.width * frame.height) - float(base_count),
                           0.0);
        xs_sc_stats st = sc_stats[sc_stats_at(cur, eye)];
        int k = -1; /* threshold bucket; -1: everything fits */
        float p = 1.0;
        float above = 0.0;
        for (int j = int(XS_SC_BUCKETS) - 1; j >= 0; j--) {
            float h = float(st.hist[j]);
            if (above + h >= budget) {
                k = j;
                p = h > 0.0 ? (budget - above) / h : 0.0;
                break;
            }
            above += h;
        }
        bool by_variance = scp.shade_mode == XS_SC_SHADE_ADAPTIVE_VARIANCE;
        /* the candidates left to the coins: none when the bucket range decides them all */
        uint open = by_variance && decided(sc_plan[pix].w, k, cand, bits) ? 0u : cand;
        float w_min, w_max;
        bool bounded = sc_prev_bounds(eye, w_min, w_max);
        xs_rng rng = xs_rng_seed(g.xy, eye, frame.frame_index, SC_SHADE_STREAM, frame.seed);
        /* the pixel's variance, as sc_shade_importance.comp computed it */
        float v = by_variance && open != 0u ? uintBitsToFloat(sc_plan[pix].z) : 0.0;
        for (uint cb = open; cb != 0u; cb &= cb - 1u) {
            uint s = uint(findLSB(cb));
            float c_s = sc_rad_load(sc_rad_at(cur, s, pix)).w;
            float w = by_variance ? xs_sc_variance_importance(v, c_s) : xs_sc_importance(c_s);
            int bucket = bounded ? int(xs_sc_bucket(w, w_min, w_max)) : int(XS_SC_BUCKETS) - 1;
            float u = xs_rng_next(rng);
            if (bucket > k || (bucket == k && u < p))
                bits |= sc_obit(s);
        }
        /* the cover rule: a pixel with surface samples but none shaded yet shades one of its
         * own (round robin) outside the budget, else it shows black (XS_SC_PLAN_UNOBSERVED) */
        if (scp.cover != 0u && by_variance && (sc_plan[pix].w & XS_SC_PLAN_UNOBSERVED) != 0u &&
            (bits & ~foreign) == 0u) {
            int ro = sc_round_robin(cand & ~foreign, start);
            bits |= ro >= 0 ? sc_obit(uint(ro)) : 0u;
        }
    }
    if (scp.moving != 0u) { /* one more shading for a pixel with moving samples */
        int rm = moving_rank(moving_candidates(cur, pix, cand) & ~bits & ~foreign,
                             frame.frame_index);
        if (rm >= 0)
            bits |= sc_obit(uint(rm));
    }
    /* cross-eye reuse: the other eye's copies are shaded by their owner (its round robin and
     * its budget); choosing among all of a pixel's samples and skipping the copies keeps each
     * sample's shading rate while each eye shades only its share */
    bits &= ~foreign;
    sc_plan[pix].z = bits;

    /* compaction (§3.5: "writes out sample indices for the shading pass") */
    uint n = uint(bitCount(bits));
    if (n == 0u)
        return;
    uint at = atomicAdd(sc_shade_count, n);
    for (; bits != 0u && at < scp.shade_capacity; bits &= bits - 1u, at++)
        sc_shade_list[at] = (pix << XS_SC_SHADE_SLOT_BITS) | uint(findLSB(bits));
}
