// SPDX-License-Identifier: MIT
/**
 * @file sc_copy.comp
 * @brief Sample cache pass "reproject", second half of the 2-pass variant (seed 000 §3.1):
 *        copies each reserved slot's sample from the source address sc_reproject.comp wrote.
 *
 * One invocation per target pixel (x, y, eye), looping over its slots; data and the mask's
 * occupancy/visibility bits then always belong to the same sample. Counts importance (§3.5).
 */
#version 460
#extension GL_GOOGLE_include_directive : require
#define XS_NO_TLAS
#include "xs_bindings.glsl"
#include "xs_hitinfo.glsl"
#include "sc_common.glsl"

layout(local_size_x = XS_SC_GROUP, local_size_y = XS_SC_GROUP, local_size_z = 1) in;

void main()
{
    uvec3 g = gl_GlobalInvocationID;
    if (g.x >= frame.width || g.y >= frame.height)
        return;
    uint eye = g.z;
    uint pix = sc_pix(eye, g.xy);
    uint plane = sc_plane();
    uint prev = sc_prev();
    uint cur = scp.cur;
    for (uint s = 0u; s < scp.slots; s++) {
        uint w = sc_src[s * plane + pix];
        if (w == 0u)
            continue;
        uint addr = (w & XS_SC_SRC_ADDR_MASK) - 1u;
        uint src_slot = addr / plane;
        uint src_pix = addr - src_slot * plane;
        uint src_at = sc_slot_at(prev, src_slot, src_pix);
        uint dst_at = sc_slot_at(cur, s, pix);
        uvec4 fh = sc_fh[src_at];
        vec4 rad = scp.shade_cache != 0u ? sc_rad[sc_rad_at(prev, src_slot, src_pix)] : vec4(0.0);
        sc_fh[dst_at] = fh;
        sc_rad[sc_rad_at(cur, s, pix)] = rad;
        if ((w & XS_SC_SRC_VISIBLE) != 0u && !sc_is_background(fh) &&
            scp.shade_mode == XS_SC_SHADE_ADAPTIVE)
            sc_count_importance(eye, xs_sc_importance(rad.w));
    }
}
