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
 */
#version 460
#extension GL_GOOGLE_include_directive : require
#define XS_NO_TLAS
#include "xs_bindings.glsl"
#include "xs_hitinfo.glsl"
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

/** `isrt`: the winner of each cell, and the pixel's mask. */
void copy_isrt(uint eye, uint pix)
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
    sc_mask[sc_mask_at(scp.cur, pix)] = m;
}

void main()
{
    uvec3 g = gl_GlobalInvocationID;
    if (g.x >= frame.width || g.y >= frame.height)
        return;
    uint eye = g.z;
    uint pix = sc_pix(eye, g.xy);
    if (sc_isrt()) {
        copy_isrt(eye, pix);
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
}
