// SPDX-License-Identifier: MIT
/**
 * @file sc_copy.comp
 * @brief Sample cache pass "reproject", second half (seed 000 §3.1): moves each slot's sample
 *        from the source address of the key sc_reproject.comp left there (XS_SC_SRC_*): the
 *        sample's 4-byte pool address replaces the key in idx[cur] (issue 19); the sample
 *        itself stays where it is in the pool, and its entry is marked taken.
 *
 * One invocation per target pixel (x, y, eye), looping over its slots; it writes the pixel's
 * mask (and the foreign bits of cross-eye copies: sources in the other eye), which nothing
 * else touches in this pass, so data and the mask's occupancy/visibility bits always belong to
 * the same sample. Counts importance (§3.5).
 *
 * `isrt` (scp.isrt_m > 0) always runs this pass: each cell's winning key (sc_reproject.comp,
 * XS_SC_ISRT_KEY_*) names the sample to copy, and this invocation writes the pixel's mask,
 * which nothing else touches in that variant.
 *
 * Fused with the trace mask (seed 000 §3.2 step 1, §3.4; issue 19: the trace mask only fed
 * the density pass, and a dispatch of its own cost one more barrier and a mask load per pixel):
 * with the pixel's new mask in hand, this invocation decides which samples are retraced
 * this frame and writes plan = (trace bits, 0, 0, visible count) for sc_density.comp:
 * - single: one occupied sample per pixel, round robin over the slots;
 * - multi: every occupied sample;
 * - adaptive: one sample (round robin) of one pixel per block x block (4 x 4) block as base
 *   rate, rotating through the block's pixels frame by frame, plus every sample of pixels
 *   whose 3 x 3 neighbourhood fails Eq. 2: t_max < (1 + eps1)(t_min + 2 Delta), t_min and its
 *   slope Delta (Eq. 1) from the 64-bit closest-depth words, t_max from the farthest-depth
 *   words. Background samples count as infinitely far, so a neighbourhood mixing background
 *   and surfaces is an edge.
 * The depth words are final here: sc_reproject.comp wrote them in the dispatch before (a
 * barrier between); the plan is written for the own pixel only and nothing in this pass
 * reads it.
 */
#version 460
#extension GL_GOOGLE_include_directive : require
#define XS_NO_TLAS
#include "xs_bindings.glsl"
#include "xs_hitinfo.glsl"
#include "xs_rng.glsl"
#include "sc_common.glsl"

layout(local_size_x = XS_SC_GROUP, local_size_y = XS_SC_GROUP, local_size_z = 1) in;

/** Moves the sample of the previous copy at address addr into slot s of pix (copy cur): its
 *  pool address, taken (the sample itself stays in the pool). */
void copy_sample(uint eye, uint pix, uint s, uint addr, bool visible)
{
    uint plane = sc_plane();
    uint prev = sc_prev();
    uint src_slot = addr / plane;
    uint src_pix = addr - src_slot * plane;
    uint a = sc_slot_at(prev, src_slot, src_pix);
    sc_idx[sc_idx_at(scp.cur, s, pix)] = a;
    sc_pool_take(a);
    if (scp.shade_cache == 0u) /* radiance is not carried between frames */
        sc_rad[a] = uvec2(0u);
    /* the first hit is read only here (16 bytes per sample less to move otherwise) */
    if (visible && scp.shade_mode == XS_SC_SHADE_ADAPTIVE && !sc_is_background(sc_fh[a])) {
        /* the radiance record is read only here: 8 bytes per sample less to move */
        uvec2 rad = scp.shade_cache != 0u ? sc_rad[sc_rad_of(a)] : uvec2(0u);
        sc_count_importance(eye, xs_sc_importance(unpackHalf2x16(rad.y).y));
    }
}

/** `isrt`: the winner of each cell; returns the pixel's mask. */
uint copy_isrt(uint eye, uint pix)
{
    uint m = 0u;
    for (uint s = 0u; s < scp.slots; s++) {
        uint64_t key = sc_src_key[s * sc_plane() + pix];
        if (key == SC_DEPTH_MIN_NONE)
            continue;
        bool visible = (key >> XS_SC_ISRT_KEY_INVISIBLE_SHIFT) == 0ul;
        copy_sample(eye, pix, s, uint(key & 0xFFFFFFFFul) - 1u, visible);
        m |= sc_obit(s) | (visible ? sc_vbit(s) : 0u);
    }
    return m;
}

/** Eq. 2 over the 3 x 3 neighbourhood of p (true: looks like one flat smooth surface). */
bool neighbourhood_consistent(uint eye, uvec2 p)
{
    uvec2 lo, hi;
    sc_neighbourhood(p, lo, hi);
    uint64_t dmin = SC_DEPTH_MIN_NONE;
    uint dmax = 0u;
    for (uint y = lo.y; y <= hi.y; y++)
        for (uint x = lo.x; x <= hi.x; x++) {
            uint q = sc_pix(eye, uvec2(x, y));
            dmin = min(dmin, sc_depth_min[q]);
            dmax = max(dmax, sc_depth_max[q]);
        }
    if (dmin == SC_DEPTH_MIN_NONE)
        return true; /* only background (or nothing) around: nothing to resolve */
    float t_min = uintBitsToFloat(uint(dmin >> 32));
    float delta = uintBitsToFloat(uint(dmin & 0xFFFFFFFFul));
    return xs_sc_consistent(t_min, uintBitsToFloat(dmax), delta, scp.eps1);
}

/** The trace mask of pixel g (eye g.z) with mask m: plan = (trace bits, 0, 0, visible count). */
void trace_mask(uvec3 g, uint pix, uint m)
{
    uint eye = g.z;
    uint occ = sc_occ(m) & sc_all_slots();
    uint start = frame.frame_index % scp.slots;
    int rr = sc_round_robin(occ, start);
    uint one = rr >= 0 ? sc_obit(uint(rr)) : 0u;

    uint bits = 0u;
    if (scp.trace_mode == XS_SC_TRACE_SINGLE) {
        bits = one;
    } else if (scp.trace_mode == XS_SC_TRACE_MULTI) {
        bits = occ;
    } else {
        uint b = scp.block;
        uvec2 blk = g.xy / b;
        uint local = (g.x % b) + (g.y % b) * b;
        uint pick = (frame.frame_index + xs_hash(xs_hash(blk.x + eye) + blk.y)) % (b * b);
        bits = local == pick ? one : 0u;
        if (!neighbourhood_consistent(eye, g.xy))
            bits = occ;
    }
    sc_plan[pix] = uvec4(bits, 0u, 0u, uint(bitCount(sc_vis(m) & sc_all_slots())));
}

void main()
{
    uvec3 g = gl_GlobalInvocationID;
    if (g.x >= frame.width || g.y >= frame.height)
        return;
    uint eye = g.z;
    uint pix = sc_pix(eye, g.xy);
    if (sc_isrt()) {
        uint m = copy_isrt(eye, pix);
        sc_mask[sc_mask_at(scp.cur, pix)] = m;
        trace_mask(g, pix, m);
        return;
    }
    uint m = 0u, foreign = 0u, per_eye = frame.width * frame.height;
    for (uint s = 0u; s < scp.slots; s++) {
        uint w = sc_idx[sc_idx_at(scp.cur, s, pix)]; /* the key, replaced by copy_sample */
        if (w == XS_SC_SRC_NONE)
            break; /* the keys fill the slots from 0; the rest stay XS_SC_POOL_NONE */
        bool visible = (w & XS_SC_SRC_INVISIBLE) == 0u;
        uint addr = (w & XS_SC_SRC_ADDR_MASK) - 1u;
        copy_sample(eye, pix, s, addr, visible);
        m |= sc_obit(s) | (visible ? sc_vbit(s) : 0u);
        if ((addr % sc_plane()) / per_eye != eye)
            foreign |= sc_obit(s);
    }
    sc_mask[sc_mask_at(scp.cur, pix)] = m;
    if (scp.cross_eye != 0u)
        sc_foreign[sc_mask_at(scp.cur, pix)] = foreign;
    trace_mask(g, pix, m);
}
