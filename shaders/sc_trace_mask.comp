// SPDX-License-Identifier: MIT
/**
 * @file sc_trace_mask.comp
 * @brief Sample cache pass "trace_mask" (seed 000 §3.2 step 1, §3.4): which samples of each
 *        pixel are retraced this frame.
 *
 * - single: one occupied sample per pixel, round robin over the slots;
 * - multi: every occupied sample;
 * - adaptive: one sample (round robin) of one pixel per block x block (4 x 4) block as base
 *   rate, rotating through the block's pixels frame by frame, plus every sample of pixels
 *   whose 3 x 3 neighbourhood fails Eq. 2: t_max < (1 + eps1)(t_min + 2 Delta), t_min and its
 *   slope Delta (Eq. 1) from the 64-bit closest-depth words, t_max from the farthest-depth
 *   words written by the reprojection. Background samples count as infinitely far, so a
 *   neighbourhood mixing background and surfaces is an edge.
 * Writes plan = (trace bits, 0, 0, visible count) for sc_density.comp.
 */
#version 460
#extension GL_GOOGLE_include_directive : require
#define XS_NO_TLAS
#include "xs_bindings.glsl"
#include "xs_hitinfo.glsl"
#include "xs_rng.glsl"
#include "sc_common.glsl"

layout(local_size_x = XS_SC_GROUP, local_size_y = XS_SC_GROUP, local_size_z = 1) in;

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

void main()
{
    uvec3 g = gl_GlobalInvocationID;
    if (g.x >= frame.width || g.y >= frame.height)
        return;
    uint eye = g.z;
    uint pix = sc_pix(eye, g.xy);
    uint m = sc_mask[sc_mask_at(scp.cur, pix)];
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
