// SPDX-License-Identifier: MIT
/**
 * @file sc_shade_importance.comp
 * @brief Sample cache pass "shade", part 0 of variance-guided shading
 *        (XS_SC_SHADE_ADAPTIVE_VARIANCE): this frame's importance histogram.
 *
 * Count-based adaptive shading counts each sample's importance 1 / (1 + c_s) as it arrives
 * (reprojection, tracing). A sample's variance-guided importance v / (1 + c_s) depends on the
 * other samples of its pixel (v: xs_sc_pixel_variance), known only once the pixel's set of
 * visible samples is final, so this pass counts them after tracing, one invocation per pixel,
 * with the same sc_count_importance (§3.5: logarithmic buckets between the previous frame's
 * bounds). sc_shade_select.comp then walks the histogram as for count-based importance.
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
    uint cur = scp.cur;
    uint cand = sc_shade_candidates(cur, pix);
    float v = sc_pixel_variance(cur, pix, cand);
    for (uint b = cand; b != 0u; b &= b - 1u) {
        float c_s = sc_rad_load(sc_rad_at(cur, uint(findLSB(b)), pix)).w;
        sc_count_importance(eye, xs_sc_variance_importance(v, c_s));
    }
}
