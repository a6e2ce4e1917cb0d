// SPDX-License-Identifier: MIT
/**
 * @file stereo_blend.comp
 * @brief Pass "blend": each eye improved from the other (seed 000 §3.6, seed 004 §4.1), both
 *        eyes per dispatch (z = eye), reading only the unblended inputs, so the two eyes are
 *        treated symmetrically and swapping the eyes swaps the result.
 *
 * Per pixel of eye e with depth d (background pixels are left untouched):
 * 1. Reprojection by depth: the world point seen at the pixel centre at depth d (this eye's
 *    view_inv and tan_fov, as xs_camera.glsl shoots rays) is projected into the other eye o
 *    (view, proj of o); its depth there d_exp = -z_o.
 * 2. Resampling of the other eye around that position: the colour X with the bilinear tent
 *    (2 x 2 taps, a texture fetch) for both blends; moments only: the other eye's mu_1, mu_2
 *    with Dodgson's quadratic kernel with spline parameter R (3 x 3 taps, xs_st_dodgson). R
 *    smooths the estimates, not the colour that enters Eq. 3 (seed 000 §5.2: R "controls how
 *    much the 1st and 2nd raw moments are blurred"; Dodgson's R = 0 kernel is a [1 2 1] / 4
 *    blur, which on X itself biased edges and highlights and lowered sharpness).
 *    Taps outside the image or failing xs_st_depth_ok(d_tap, d_exp) (with instance_test, also
 *    taps showing another instance than the pixel's hit id) are dropped and the rest
 *    renormalised; below min_weight of the colour's kernel left the pixel is disoccluded and
 *    kept (status XS_ST_STATUS_REJECTED, beta = 1), the same test for every blend and R (the
 *    moments kernel's accepted taps only need to carry samples, c_X > 0: where its wider
 *    support reaches across a depth edge the estimate comes from the taps left, it does not
 *    make the pixel disoccluded).
 * 3. beta per colour channel:
 *    - PFJ23 (seed 004 Eq. 10-11): sigma_Y^2 over the 3 x 3 colour neighbourhood of this eye,
 *      E[(X - Y)^2] from X against each neighbour (xs_st_beta_pfj23).
 *    - moments (seed 000 Eq. 5-8): this eye's mu_1, mu_2 pooled over 3 x 3 with weights
 *      xs_st_blur_weight (1 centre, 1 - R off centre; neighbours failing the depth test against
 *      d are skipped) times c_X; the other eye's pooled over the kernel taps with weights
 *      h_Dodgson,R times c_X; xs_st_beta_eq8. Pooling with c_X weighs every pixel's moments by
 *      its effective sample count, i.e. pools the samples (Eq. 5-6 over the union).
 * 4. out = lerp(X, Y, beta) (Eq. 3), X the bilinearly resampled other-eye colour.
 */
#version 460
#extension GL_GOOGLE_include_directive : require
#include "xs_stereo.h"

layout(local_size_x = XS_ST_GROUP, local_size_y = XS_ST_GROUP, local_size_z = 1) in;

layout(set = 0, binding = XS_ST_BIND_PARAMS, std140) uniform XsStParamsBlock
{
    xs_st_params stp;
};
layout(set = 0, binding = XS_ST_BIND_SRC, rgba32f) uniform readonly image2DArray st_src;
layout(set = 0, binding = XS_ST_BIND_DEPTH, r32f) uniform readonly image2DArray st_depth;
layout(set = 0, binding = XS_ST_BIND_MU1, rgba32f) uniform readonly image2DArray st_mu1;
layout(set = 0, binding = XS_ST_BIND_MU2, rgba32f) uniform readonly image2DArray st_mu2;
layout(set = 0, binding = XS_ST_BIND_OUT, rgba32f) uniform writeonly image2DArray st_out;
layout(set = 0, binding = XS_ST_BIND_AUX, rgba32f) uniform writeonly image2DArray st_aux;
layout(set = 0, binding = XS_ST_BIND_HITID, rgba32ui) uniform readonly uimage2DArray st_hitid;

bool inside(ivec2 p) { return p.x >= 0 && p.y >= 0 && p.x < int(stp.width) && p.y < int(stp.height); }

float depth_at(ivec2 p, uint eye) { return imageLoad(st_depth, ivec3(p, eye)).r; }

/** A tap at t of eye `eye` may stand for the point expected at depth d_exp on instance inst:
 *  the depth test, and with instance_test the same instance (a surface 1 cm from another,
 *  the Cornell light panel under the ceiling, passes the depth test alone). */
bool tap_ok(ivec2 t, uint eye, float d_exp, uint inst)
{
    return xs_st_depth_ok(depth_at(t, eye), d_exp, stp.depth_tolerance) &&
           (stp.instance_test == 0u || imageLoad(st_hitid, ivec3(t, eye)).x == inst);
}

void main()
{
    uvec3 g = gl_GlobalInvocationID;
    if (g.x >= stp.width || g.y >= stp.height)
        return;
    uint eye = g.z, other = 1u - g.z;
    ivec2 p = ivec2(g.xy);
    ivec3 coord = ivec3(g);
    vec4 y4 = imageLoad(st_src, coord);
    vec3 y = y4.rgb;
    float d = depth_at(p, eye);
    if (stp.mode == XS_ST_MODE_NONE || !(d > 0.0)) {
        imageStore(st_out, coord, y4);
        imageStore(st_aux, coord, vec4(vec3(1.0), d > 0.0 ? XS_ST_STATUS_REJECTED
                                                          : XS_ST_STATUS_BACKGROUND));
        return;
    }

    uint inst = stp.instance_test != 0u ? imageLoad(st_hitid, coord).x : 0u;

    /* 1. this eye's point at the pixel centre -> the other eye */
    xs_eye e = stp.eyes[eye], o = stp.eyes[other];
    vec2 uv = (vec2(p) + 0.5) / vec2(stp.width, stp.height);
    vec3 pe = d * vec3(mix(e.tan_fov.x, e.tan_fov.y, uv.x), mix(e.tan_fov.z, e.tan_fov.w, uv.y),
                       -1.0);
    vec4 world = e.view_inv * vec4(pe, 1.0);
    vec4 clip = o.proj * (o.view * world);
    bool ok = clip.w > 0.0;
    float d_exp = clip.w; /* proj's w = -z of the other eye */
    vec2 q = ok ? ((clip.xy / clip.w) * 0.5 + 0.5) * vec2(stp.width, stp.height) - 0.5
                : vec2(0.0); /* continuous position in pixel-centre units */

    /* 2. resample the other eye: the colour X with the bilinear tent (2 x 2 taps, a texture
     *    fetch, seed 000 §3.6) for both blends; moments: the other eye's raw moments also with
     *    Dodgson's kernel of spline parameter R (3 x 3 taps), which smooths the ESTIMATES only
     *    (seed 000 §5.2: R "controls how much the 1st and 2nd raw moments are blurred"), never
     *    the colour that enters Eq. 3 */
    bool moments = stp.mode == XS_ST_MODE_MOMENTS;
    vec3 x = vec3(0.0), m1x = vec3(0.0), m2x = vec3(0.0);
    float wsum = 0.0, cwsum = 0.0, w2c = 0.0; /* w2c: sum w^2 / c_X of the colour taps */
    if (ok) {
        ivec2 base = ivec2(floor(q));
        for (int j = 0; j < 2; j++) {
            for (int i = 0; i < 2; i++) {
                ivec2 t = base + ivec2(i, j);
                vec2 s = q - vec2(t);
                float w = max(1.0 - abs(s.x), 0.0) * max(1.0 - abs(s.y), 0.0);
                if (w == 0.0 || !inside(t) || !tap_ok(t, other, d_exp, inst))
                    continue;
                x += w * imageLoad(st_src, ivec3(t, other)).rgb;
                wsum += w;
                if (moments) {
                    float c = imageLoad(st_mu1, ivec3(t, other)).a;
                    w2c += c > 0.0 ? w * w / c : 0.0;
                }
            }
        }
        if (moments) {
            base = ivec2(floor(q + 0.5)) - 1;
            for (int j = 0; j < 3; j++) {
                for (int i = 0; i < 3; i++) {
                    ivec2 t = base + ivec2(i, j);
                    vec2 s = q - vec2(t);
                    float w = xs_st_dodgson(s.x, stp.r) * xs_st_dodgson(s.y, stp.r);
                    if (w == 0.0 || !inside(t) || !tap_ok(t, other, d_exp, inst))
                        continue;
                    vec4 a = imageLoad(st_mu1, ivec3(t, other));
                    vec4 b = imageLoad(st_mu2, ivec3(t, other));
                    float cw = w * a.a;
                    m1x += cw * a.rgb;
                    m2x += cw * b.rgb;
                    cwsum += cw;
                }
            }
        }
    }
    if (!(wsum >= stp.min_weight) || (moments && !(cwsum > 0.0))) {
        imageStore(st_out, coord, y4);
        imageStore(st_aux, coord, vec4(vec3(1.0), XS_ST_STATUS_REJECTED));
        return;
    }
    x /= wsum;

    /* 3. beta per channel */
    vec3 beta;
    if (moments) {
        m1x /= cwsum;
        m2x /= cwsum;
        vec3 m1y = vec3(0.0), m2y = vec3(0.0);
        float cy = 0.0;
        for (int dy = -1; dy <= 1; dy++) {
            for (int dx = -1; dx <= 1; dx++) {
                ivec2 t = p + ivec2(dx, dy);
                float w = xs_st_blur_weight(dx, dy, stp.r);
                if (w == 0.0 || !inside(t))
                    continue;
                if ((dx != 0 || dy != 0) && !tap_ok(t, eye, d, inst))
                    continue;
                vec4 a = imageLoad(st_mu1, ivec3(t, eye));
                vec4 b = imageLoad(st_mu2, ivec3(t, eye));
                float cw = w * a.a;
                m1y += cw * a.rgb;
                m2y += cw * b.rgb;
                cy += cw;
            }
        }
        if (!(cy > 0.0)) { /* no samples in this pixel: nothing known about Y, take X */
            beta = vec3(0.0);
        } else {
            m1y /= cy;
            m2y /= cy;
            /* effective sample counts of the two pixel values: Y averages its own c_X samples,
             * X the colour's bilinear taps, Var(X) = sigma^2 sum (w_i / W)^2 / c_i */
            float n_y = max(imageLoad(st_mu1, coord).a, 1e-6);
            float n_x = w2c > 0.0 ? wsum * wsum / w2c : 1.0;
            for (int c = 0; c < 3; c++)
                beta[c] = stp.pixel_mean == 0u
                              ? xs_st_beta_eq8(m1x[c], m2x[c], m1y[c], m2y[c])
                              : xs_st_beta_eq8_mean(m1x[c], m2x[c], n_x, m1y[c], m2y[c], n_y);
        }
    } else {
        vec3 sy = vec3(0.0), sy2 = vec3(0.0), sd2 = vec3(0.0);
        float n = 0.0;
        for (int dy = -1; dy <= 1; dy++) {
            for (int dx = -1; dx <= 1; dx++) {
                ivec2 t = clamp(p + ivec2(dx, dy), ivec2(0),
                                ivec2(int(stp.width) - 1, int(stp.height) - 1));
                vec3 yi = imageLoad(st_src, ivec3(t, eye)).rgb;
                sy += yi;
                sy2 += yi * yi;
                sd2 += (x - yi) * (x - yi);
                n += 1.0;
            }
        }
        for (int c = 0; c < 3; c++)
            beta[c] = xs_st_beta_pfj23(sy[c], sy2[c], sd2[c], n);
    }

    /* 4. Eq. 3 */
    vec3 outc;
    for (int c = 0; c < 3; c++)
        outc[c] = xs_st_lerp(x[c], y[c], beta[c]);
    imageStore(st_out, coord, vec4(outc, y4.a));
    imageStore(st_aux, coord, vec4(beta, XS_ST_STATUS_BLENDED));
}
