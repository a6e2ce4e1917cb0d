// SPDX-License-Identifier: MIT
/**
 * @file sc_density.comp
 * @brief Sample cache pass "density" (seed 000 §3.2 step 2): keeps the density of visible
 *        samples near n_target +- delta, measured as the mean over the 3 x 3 neighbourhood.
 *
 * Each pixel changes only its own samples, so a neighbourhood mean out of the band is
 * corrected by the pixels IN that neighbourhood, each moving its own count towards n_target:
 * - a pixel with fewer than n_target visible samples reserves ceil(n_target - count) new ones
 *   when the mean of some 3 x 3 neighbourhood containing it (its own or a neighbour's) is
 *   below n_target - delta; a pixel without any visible sample always gets at least one;
 * - a pixel with more than n_target visible samples deletes ceil(count - n_target) randomly
 *   chosen visible ones (cleared occupancy and visibility bits), always keeping one, when the
 *   mean of some 3 x 3 neighbourhood containing it is above n_target + delta.
 * (Acting on the pixel's own mean alone, as a literal reading of §3.2 has it, can stall: a
 * pixel with N samples among pixels with one has an in-band mean and never deletes, while
 * its neighbours' means stay above the band and they have nothing to delete.) After one frame
 * every pixel of an out-of-band neighbourhood has moved to floor/ceil(n_target), so on a still
 * view the means enter the band in one frame when delta >= 0.5 (and slots suffice).
 * New samples take free slots first, then invisible ones, picked in random order; they get
 * their occupancy bit and a pool entry (pool_entries) now and are traced through a random
 * point of the pixel by sc_trace.rgen (plan.y). Reads the visible counts of the 5 x 5
 * neighbourhood from plan.w (written by sc_copy.comp; each once) and writes only its own
 * pixel (and, through sc_pool_alloc, bits of other pixels' pool words: which entry a sample
 * gets depends on the order of the invocations, what it holds does not).
 *
 * Cross-eye reuse (scp.cross_eye): the other eye's copies count as visible samples but are not
 * pruned (a pruned copy would come back next frame: the pixel's sample set would change every
 * frame, a flicker under motion); a pixel above the band prunes half its excess from its own
 * samples, since the other eye's pixel of the same surface prunes the other half (pruning the
 * whole excess in both eyes would empty both the next frame); new samples are own.
 *
 * `isrt` (scp.isrt_m > 0): no density control, the M x M layout fixes the count [DSK*17]:
 * every cell without a visible sample gets a new one (traced through the cell's centre by
 * sc_trace.rgen), nothing is pruned.
 */
#version 460
#extension GL_GOOGLE_include_directive : require
#define XS_NO_TLAS
#include "xs_bindings.glsl"
#include "xs_hitinfo.glsl"
#include "xs_rng.glsl"
#include "sc_common.glsl"

layout(local_size_x = XS_SC_GROUP, local_size_y = XS_SC_GROUP, local_size_z = 1) in;

/* RNG stream of this pass (sample index of xs_rng_seed). */
#define SC_DENSITY_STREAM 0x5C0DE115u

/** The k-th set bit (k < bitCount(bits)). */
uint nth_bit(uint bits, uint k)
{
    for (uint i = 0u; i < k; i++)
        bits &= bits - 1u;
    return uint(findLSB(bits));
}

/** Cross-eye reuse: the own sample of pool with the smallest count c_s: `start` (a random
 *  member) unless another has a smaller count, then the lowest such slot. Both eyes trace new samples where a motion stretches the
 *  view, so their pixels overflow once the copies arrive; pruning at random would replace
 *  converged samples by young, noisy ones there. */
uint youngest(uint pix, uint pool, uint start)
{
    uint best = start;
    float c_best = sc_rad_load(sc_rad_at(scp.cur, start, pix)).w;
    for (uint b = pool; b != 0u; b &= b - 1u) {
        uint s = uint(findLSB(b));
        float c = sc_rad_load(sc_rad_at(scp.cur, s, pix)).w;
        if (c < c_best) {
            best = s;
            c_best = c;
        }
    }
    return best;
}

/**
 * Pool entries for the new samples `newbits` of pix (issue 19): a slot that held one of the
 * pixel's own invisible samples keeps that sample's entry (nothing else refers to it: copies
 * for the other eye are made of visible samples only), the
 * others take a free one (sc_pool_alloc). Returns the new samples that got an entry; a slot
 * without one gets no new sample this frame (it keeps its old sample when it had one, else it
 * is freed in occ).
 */
uint pool_entries(uint pix, uint newbits, uint old_occ, uint foreign, inout uint occ)
{
    uint got = 0u;
    for (uint b = newbits; b != 0u; b &= b - 1u) {
        uint s = uint(findLSB(b));
        if ((old_occ & ~foreign & sc_obit(s)) != 0u) {
            got |= sc_obit(s);
            continue;
        }
        uint a = sc_pool_alloc(pix);
        if (a == XS_SC_POOL_NONE) {
            occ &= old_occ | ~sc_obit(s);
            continue;
        }
        sc_idx[sc_idx_at(scp.cur, s, pix)] = a;
        got |= sc_obit(s);
    }
    return got;
}

/** `isrt`: every cell without a visible sample gets a new one, nothing is pruned. */
void density_isrt(uint pix)
{
    uint mi = sc_mask_at(scp.cur, pix);
    uint m = sc_mask[mi];
    uint vis = sc_vis(m) & sc_all_slots();
    uint occ = sc_occ(m) | (sc_all_slots() & ~vis);
    uint empty = pool_entries(pix, sc_all_slots() & ~vis, sc_occ(m), 0u, occ);
    sc_mask[mi] = occ | (vis << XS_SC_MAX_SLOTS);
    uint trace = sc_plan[pix].x & ~empty;
    sc_plan[pix].x = trace;
    sc_plan[pix].y = empty;
    if (scp.trace_mode == XS_SC_TRACE_ADAPTIVE && (trace | empty) != 0u)
        sc_list_append(pix);
}

/**
 * The smallest and largest of the 3 x 3 means of the neighbourhoods containing pixel p (each
 * clipped to the image, as each of those pixels measures its own), from the visible counts
 * of the 5 x 5 window loaded once (pixels outside the image count 0; integer sums, so the
 * order of summation does not matter).
 */
void neighbourhood_means(uvec2 p, uint eye, out float mean_min, out float mean_max)
{
    uint cnt[5][5];
    ivec2 size = ivec2(frame.width, frame.height);
    for (int dy = 0; dy < 5; dy++)
        for (int dx = 0; dx < 5; dx++) {
            ivec2 c = ivec2(p) + ivec2(dx - 2, dy - 2);
            bool inside = all(greaterThanEqual(c, ivec2(0))) && all(lessThan(c, size));
            cnt[dy][dx] = inside ? sc_plan[sc_pix(eye, uvec2(c))].w : 0u;
        }
    mean_min = 1e30;
    mean_max = 0.0;
    for (int oy = -1; oy <= 1; oy++)
        for (int ox = -1; ox <= 1; ox++) {
            ivec2 q = ivec2(p) + ivec2(ox, oy);
            if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size)))
                continue;
            uint sum = 0u;
            for (int y = 0; y < 3; y++)
                for (int x = 0; x < 3; x++)
                    sum += cnt[oy + 1 + y][ox + 1 + x];
            /* pixels of q's clipped neighbourhood */
            ivec2 ext = min(q + 1, size - 1) - max(q - 1, ivec2(0)) + 1;
            float mean = float(sum) / float(uint(ext.x * ext.y));
            mean_min = min(mean_min, mean);
            mean_max = max(mean_max, mean);
        }
}

/** New samples for a pixel below the band (at least one when it has no visible sample): free
 *  slots first, then invisible ones, in random order; returns their bits (added to occ). */
uint add_samples(float mean_min, uint nvis, uint vis, inout uint occ, inout xs_rng rng)
{
    uint all_slots = sc_all_slots();
    uint add = 0u;
    if (mean_min < scp.n_target - scp.delta && float(nvis) < scp.n_target)
        add = uint(ceil(scp.n_target - float(nvis)));
    if (nvis == 0u)
        add = max(add, 1u);
    uint newbits = 0u;
    for (uint k = 0u; k < add; k++) {
        uint free_slots = ~occ & all_slots;
        uint pool = free_slots != 0u ? free_slots : (occ & ~vis & ~newbits & all_slots);
        if (pool == 0u)
            break;
        uint s = nth_bit(pool, xs_rng_next_uint(rng) % uint(bitCount(pool)));
        occ |= sc_obit(s);
        newbits |= sc_obit(s);
    }
    return newbits;
}

/** Prunes a pixel above the band: randomly chosen visible samples, always keeping one
 *  (cross-eye reuse: own samples only, half the excess, the youngest first). */
void prune_samples(uint pix, float mean_max, uint nvis, uint foreign, inout uint vis,
                   inout uint occ, inout xs_rng rng)
{
    if (!(mean_max > scp.n_target + scp.delta && float(nvis) > scp.n_target && nvis > 1u))
        return;
    uint remove = min(uint(ceil(float(nvis) - scp.n_target)), nvis - 1u);
    /* cross-eye reuse: own samples only, half the excess (the other eye prunes its own
     * half); pruned copies would come back next frame, a flicker under motion */
    uint pool = vis & ~foreign;
    if (scp.cross_eye != 0u)
        remove = min(uint(ceil(0.5 * (float(nvis) - scp.n_target))), uint(bitCount(pool)));
    for (uint k = 0u; k < remove; k++) {
        uint s = nth_bit(pool, xs_rng_next_uint(rng) % uint(bitCount(pool)));
        if (scp.cross_eye != 0u)
            s = youngest(pix, pool, s);
        pool &= ~sc_obit(s);
        vis &= ~sc_obit(s);
        occ &= ~sc_obit(s);
    }
}

void main()
{
    uvec3 g = gl_GlobalInvocationID;
    if (g.x >= frame.width || g.y >= frame.height)
        return;
    g = sc_work_item(g); /* tests: the pool's allocations in another order */
    uint eye = g.z;
    uint pix = sc_pix(eye, g.xy);
    if (sc_isrt()) {
        density_isrt(pix);
        return;
    }
    float mean_min, mean_max;
    neighbourhood_means(g.xy, eye, mean_min, mean_max);

    uint mi = sc_mask_at(scp.cur, pix);
    uint m = sc_mask[mi];
    uint occ = sc_occ(m) & sc_all_slots();
    uint vis = sc_vis(m) & sc_all_slots();
    uint nvis = uint(bitCount(vis));
    uvec4 plan = sc_plan[pix];
    uint foreign = sc_foreign_bits(scp.cur, pix);
    xs_rng rng = xs_rng_seed(g.xy, eye, frame.frame_index, SC_DENSITY_STREAM, frame.seed);
    uint old_occ = occ;
    uint newbits = add_samples(mean_min, nvis, vis, occ, rng);
    prune_samples(pix, mean_max, nvis, foreign, vis, occ, rng);
    newbits = pool_entries(pix, newbits, old_occ, foreign, occ);

    /* new samples start invisible (sc_trace.rgen sets the bit); pruned ones are gone */
    vis &= ~newbits;
    sc_mask[mi] = occ | (vis << XS_SC_MAX_SLOTS);
    /* cross-eye reuse: new samples are this eye's own */
    if (scp.cross_eye != 0u)
        sc_foreign[mi] = foreign & occ & ~newbits;
    /* x and y only: neighbours read w concurrently */
    uint trace = plan.x & occ & ~newbits;
    sc_plan[pix].x = trace;
    sc_plan[pix].y = newbits;
    /* adaptive tracing: the trace list of the pixels with rays to trace (sc_trace.rgen) */
    if (scp.trace_mode == XS_SC_TRACE_ADAPTIVE && (trace | newbits) != 0u)
        sc_list_append(pix);
}
