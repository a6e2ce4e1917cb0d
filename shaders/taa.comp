// SPDX-License-Identifier: MIT
/**
 * @file taa.comp
 * @brief Pass "taa": temporal antialiasing after any method ([YLS20] as seed 000 §5.1 uses it;
 *        seed 004 §4.2 for mode PFJ23), both eyes per dispatch (z = eye).
 *
 * Per pixel of eye e:
 * 1. Reprojection ([YLS20], with camera and instance motion): a hit pixel's point is the
 *    pixel centre's camera ray at the pixel's depth (as xs_camera.glsl shoots rays), taken to
 *    object space with the inverse of its instance's current object_to_world (instance from the
 *    hit id; the inverse from normal_to_world, instance transforms being affine) and back to
 *    world space with that instance's transform of the LAST frame (kept by the pass in
 *    XS_TF_BIND_PREV_XFORM), then projected with the last frame's eye. The pixel
 *    centre rather than the hit's barycentrics is reprojected so any sub-pixel jitter (random,
 *    Halton, none) reprojects a still view onto pixel centres exactly. A background pixel's
 *    direction is rotated into the last frame's eye (camera rotation only).
 * 2. Validation: the history is read at the 2 x 2 bilinear taps around the reprojected
 *    position; a tap counts when it is inside the image and the last frame showed the same
 *    surface at it or at one of its 8 neighbours: the same instance (background: background)
 *    at the point's expected depth in the last frame, give or take depth_tolerance (relative)
 *    plus XS_TF_SLOPE_PX times the surface's depth step per pixel here (grazing surfaces). The
 *    neighbours make the test blind to sub-pixel flips at edges (a jittered sample lands on
 *    either side of an edge from frame to frame; the clipping of step 3 handles those), while a
 *    surface that was nowhere near (disocclusion) rejects the tap. A tap accepted through a
 *    neighbour is read there (the first in row order), unless the tap's own footprint holds
 *    the reprojected point: that pixel covered the surface, so its history is a legitimate
 *    mix at an edge (what antialiases jittered edges); any other such tap may lie wholly on
 *    another surface, and read at the tap a bright one leaked into a ring around it (the
 *    Cornell light panel's rim into the ceiling). Fewer than min_weight of the bilinear
 *    weight accepted (disocclusion,
 *    off-screen, no history): the output is the current frame (status REJECTED /
 *    NO_HISTORY). Else the history is the accepted taps' renormalised bilinear mean, taken in
 *    the resolve space (below).
 * Steps 2-4 work in a tonemapped "resolve space", c / (1 + Y) with Y the YCoCg luma, inverted
 * at the end (c / (1 - Y)): luma weighting as in Karis, "High-quality temporal supersampling"
 * (SIGGRAPH 2014 course). In linear radiance one bright tap
 * (the Cornell light panel, ~250 x its ceiling) dominates the bilinear mean and the current
 * 3 x 3 box, so an emitter's rim leaked into the ceiling beside it and the box (which holds
 * the emitter too) never clipped it back: relMSE 25-42 x higher than without TAA on the
 * Cornell orbit (issue 19). In the resolve space every value is below 1 and a bright tap
 * weighs as a saturated one.
 * 3. ON: the history is clipped towards the mean of the current 3 x 3 neighbourhood to the box
 *    mean +- gamma sigma in YCoCg (variance clipping, [Sal16], [YLS20]) and blended with
 *    alpha for its trusted share, XS_TF_UNTRUSTED_ALPHA for the rest (history_at: taps not
 *    showing the surface themselves, which a box spanning an edge cannot clip; issue 19).
 *    With the motion rule (motion_px2 > 0, XS_TF_MOTION_*) alpha rises with the blur the
 *    bilinear resampling added this frame (fx (1 - fx) + fy (1 - fy) px^2); with
 *    motion_edges only on the dark side of an edge between surfaces: where the 3 x 3
 *    neighbourhood shows another instance (or background beside a hit) and the pixel's luma
 *    is below the neighbourhood's mean. There the blur carries the bright side's radiance
 *    in: the Cornell light panel's (~15) into the ceiling beside it (~0.05), half of the
 *    default's relMSE on the Cornell orbit (issue 19; bench/results/issue19-cornell/).
 *    The history is resampled bilinearly, or with Catmull-Rom (history_filter). PFJ23 (seed 004 §4.2): no rectification (seed 004 §5.1 leaves history
 *    rectification out); alpha per channel = Eq. 4 with sigma_Y^2 from the current 3 x 3
 *    neighbourhood (Eq. 10) and E[(X - Y)^2] from the history X against each neighbour (Eq. 11),
 *    xs_st_beta_pfj23 of the stereo blend with the history in place of the other eye.
 * 4. out = lerp(history, current, alpha), back to radiance, into the method's colour image;
 *    aux = alpha, status.
 * Invocation i < instance_count (flattened over both eyes) also stores instance i's current
 * object_to_world for the next frame (copied to PREV_XFORM after the dispatch).
 */
#version 460
#extension GL_GOOGLE_include_directive : require
#define XS_NO_TLAS
#include "xs_bindings.glsl"
#include "xs_stereo.h"
#include "xs_taa.h"

layout(local_size_x = XS_TF_GROUP, local_size_y = XS_TF_GROUP, local_size_z = 1) in;

layout(set = 0, binding = XS_TF_BIND_PARAMS, std140) uniform XsTfParamsBlock
{
    xs_tf_params tfp;
};
layout(set = 0, binding = XS_TF_BIND_SRC, rgba32f) uniform readonly image2DArray tf_src;
layout(set = 0, binding = XS_TF_BIND_DEPTH, r32f) uniform readonly image2DArray tf_depth;
layout(set = 0, binding = XS_TF_BIND_HITID, rgba32ui) uniform readonly uimage2DArray tf_hitid;
layout(set = 0, binding = XS_TF_BIND_HISTORY, rgba32f) uniform readonly image2DArray tf_history;
/* depth and instance of a frame in one texel: one load per pixel compared */
layout(set = 0, binding = XS_TF_BIND_PREV_GEO, rg32ui) uniform readonly uimage2DArray tf_prev_geo;
layout(set = 0, binding = XS_TF_BIND_NEXT_GEO, rg32ui) uniform writeonly uimage2DArray tf_next_geo;
layout(set = 0, binding = XS_TF_BIND_OUT, rgba32f) uniform writeonly image2DArray tf_out;
layout(set = 0, binding = XS_TF_BIND_AUX, rgba32f) uniform writeonly image2DArray tf_aux;
layout(set = 0, binding = XS_TF_BIND_REPROJ, rgba32f) uniform writeonly image2DArray tf_reproj;
layout(set = 0, binding = XS_TF_BIND_PREV_XFORM, std430) readonly buffer XsTfPrevXform
{
    mat4 tf_prev_xform[];
};
layout(set = 0, binding = XS_TF_BIND_NEXT_XFORM, std430) writeonly buffer XsTfNextXform
{
    mat4 tf_next_xform[];
};
layout(set = 0, binding = XS_TF_BIND_PREV_POS, std430) readonly buffer XsTfPrevPos
{
    vec4 tf_prev_pos[];
};

/** A skinned or morphed surface's motion in object space at the pixel's hit (hit ids: instance,
 *  primitive, barycentrics): last frame's posed point minus this frame's (0 for rigid meshes,
 *  whose prev positions equal their vertices). */
vec3 deform_motion(uvec4 hid)
{
    uint base = instances[hid.x].first_index + 3u * hid.y;
    vec2 b = uintBitsToFloat(hid.zw);
    vec3 w = vec3(1.0 - b.x - b.y, b.x, b.y), d = vec3(0.0);
    for (uint c = 0u; c < 3u; c++) {
        uint vi = indices[base + c];
        d += w[c] * (tf_prev_pos[vi].xyz - vertices[vi].position_u.xyz);
    }
    return d;
}

vec3 rgb_to_ycocg(vec3 c)
{
    return vec3(0.25 * c.r + 0.5 * c.g + 0.25 * c.b, 0.5 * c.r - 0.5 * c.b,
                -0.25 * c.r + 0.5 * c.g - 0.25 * c.b);
}

vec3 ycocg_to_rgb(vec3 c) { return vec3(c.x + c.y - c.z, c.x + c.z, c.x - c.y - c.z); }

/** The resolve's space (xs_taa.h, XS_TF_TONEMAP_*): c / (1 + Y), Y its YCoCg luma (>= 0). */
vec3 to_resolve(vec3 c)
{
    return c / (1.0 + max(rgb_to_ycocg(c).x, 0.0));
}

/** The inverse of to_resolve: c / (1 - Y), Y < 1 in the resolve space (floored, see
 *  XS_TF_TONEMAP_FLOOR). */
vec3 from_resolve(vec3 t)
{
    return t / max(1.0 - max(rgb_to_ycocg(t).x, 0.0), XS_TF_TONEMAP_FLOOR);
}

/** Clips c towards the box centre onto the box centre +- extent ([Sal16]). */
vec3 clip_to_box(vec3 c, vec3 centre, vec3 extent)
{
    vec3 v = c - centre;
    vec3 a = abs(v) / max(extent, vec3(1e-7));
    float m = max(a.x, max(a.y, a.z));
    return m > 1.0 ? centre + v / m : c;
}

bool inside(ivec2 p)
{
    return p.x >= 0 && p.y >= 0 && p.x < int(tfp.width) && p.y < int(tfp.height);
}

bool finite3(vec3 v) { return !any(isnan(v)) && !any(isinf(v)); }

/** The instance this frame shows at texel c (XS_MISS_INSTANCE: background), as main reads
 *  the pixel's own. */
uint neighbour_instance(ivec3 c)
{
    uint i = imageLoad(tf_hitid, c).x;
    return imageLoad(tf_depth, c).r <= 0.0 || i >= tfp.instance_count ? XS_MISS_INSTANCE : i;
}


/** Whether a last-frame texel of tf_prev_geo shows instance inst (XS_MISS_INSTANCE:
 *  background) at the expected depth d_exp give or take tol (metres). */
bool same_geo(uvec2 geo, uint inst, float d_exp, float tol)
{
    return geo.y == inst && (inst == XS_MISS_INSTANCE || abs(uintBitsToFloat(geo.x) - d_exp) <= tol);
}

bool same_surface(ivec2 p, uint eye, uint inst, float d_exp, float tol)
{
    return inside(p) && same_geo(imageLoad(tf_prev_geo, ivec3(p, eye)).xy, inst, d_exp, tol);
}

/** The depth tolerance of pixel px (a hit of inst at depth): depth_tolerance relative, plus
 *  XS_TF_SLOPE_PX times the largest depth step to a 4-neighbour on the same instance, as the
 *  taps compared lie up to 2 pixels from the reprojected point (grazing surfaces). */
float depth_tolerance(ivec2 px, uint eye, uint inst, float depth, float d_exp)
{
    float slope = 0.0;
    for (int k = 0; k < 4; k++) {
        ivec2 q = px + ivec2(k == 0 ? -1 : k == 1 ? 1 : 0, k == 2 ? -1 : k == 3 ? 1 : 0);
        if (!inside(q))
            continue;
        float dq = imageLoad(tf_depth, ivec3(q, eye)).r;
        if (dq > 0.0 && imageLoad(tf_hitid, ivec3(q, eye)).x == inst)
            slope = max(slope, abs(dq - depth));
    }
    return tfp.depth_tolerance * d_exp + XS_TF_SLOPE_PX * slope;
}

/** The point (w = 1) or direction (w = 0) of the pixel in the last frame's eye space. */
vec4 reproject_eye_space(uvec2 px, uint eye, float depth, uint inst)
{
    xs_eye ce = frame.eyes[eye];
    vec2 uv = (vec2(px) + 0.5) / vec2(tfp.width, tfp.height);
    vec3 d_eye = vec3(mix(ce.tan_fov.x, ce.tan_fov.y, uv.x), mix(ce.tan_fov.z, ce.tan_fov.w, uv.y),
                      -1.0);
    mat4 prev_view = tfp.prev_eyes[eye].view;
    if (inst == XS_MISS_INSTANCE)
        return vec4(mat3(prev_view) * (mat3(ce.view_inv) * d_eye), 0.0);
    vec3 p_world = (ce.view_inv * vec4(d_eye * depth, 1.0)).xyz;
    /* object space: instance transforms are affine, and normal_to_world's 3 x 3 is the inverse
     * transpose of object_to_world's, so its transpose inverts the linear part */
    xs_instance in_ = instances[inst];
    vec3 p_obj = transpose(mat3(in_.normal_to_world)) * (p_world - in_.object_to_world[3].xyz);
    if (tfp.deform != 0u)
        p_obj += deform_motion(imageLoad(tf_hitid, ivec3(px, eye)));
    vec4 p_prev = tf_prev_xform[inst] * vec4(p_obj, 1.0);
    return vec4((prev_view * p_prev).xyz, 1.0);
}

/** Catmull-Rom weights of the taps at offsets -1, 0, 1, 2 for a point at fraction t in [0, 1)
 *  past tap 0 (a cubic with tension 0.5: sums to 1, exact at t = 0). */
vec4 catmull_rom_weights(float t)
{
    float t2 = t * t, t3 = t2 * t;
    return vec4(-0.5 * t3 + t2 - 0.5 * t, 1.5 * t3 - 2.5 * t2 + 1.0,
                -1.5 * t3 + 2.0 * t2 + 0.5 * t, 0.5 * t3 - 0.5 * t2);
}

/** The history at the point whose 2 x 2 bilinear taps start at base (fraction f), resampled
 *  with the 4 x 4 Catmull-Rom taps around it in the resolve space (XS_TF_HISTORY_CATMULL_ROM):
 *  a bilinear fetch every frame is a low-pass filter applied again each frame under sub-pixel
 *  motion, which blurs texture within a surface under a pan (test_taa: 0.75 x the bilinear
 *  fetch's error on a textured pan). inner: the 2 x 2 taps' values (x + 2 y), all showing the
 *  surface. An outer tap off
 *  the image or not showing the surface (same test as the inner ones) takes the value of its
 *  nearest inner tap (clamp to edge), so no other surface leaks in. The result is clamped to
 *  the inner taps' range: the negative lobes cannot ring (overshoot) at an edge, and the
 *  neighbourhood clip of step 3 follows. */
vec3 catmull_rom_history(ivec2 base, vec2 f, uint eye, uint inst, float d_exp, float tol,
                         vec3 inner[4])
{
    vec4 wx = catmull_rom_weights(f.x), wy = catmull_rom_weights(f.y);
    vec3 lo = min(min(inner[0], inner[1]), min(inner[2], inner[3]));
    vec3 hi = max(max(inner[0], inner[1]), max(inner[2], inner[3]));
    vec3 sum = vec3(0.0);
    for (int j = 0; j < 4; j++) {
        for (int i = 0; i < 4; i++) {
            ivec2 o = ivec2(i, j) - 1, c = clamp(o, ivec2(0), ivec2(1));
            vec3 v = inner[c.x + 2 * c.y];
            float w = wx[i] * wy[j];
            if (w != 0.0 && any(notEqual(o, c)) &&
                same_surface(base + o, eye, inst, d_exp, tol))
                v = to_resolve(imageLoad(tf_history, ivec3(base + o, eye)).rgb);
            sum += w * v;
        }
    }
    return clamp(sum, lo, hi);
}

/** The history (resolve space) at pos, the reprojected point of pixel px (inst at depth here,
 *  d_exp = its depth in the last frame), from the 2 x 2 bilinear taps near which the last
 *  frame showed the same surface; out_wsum = their share of the bilinear weight, out_own the
 *  share of the taps it can trust: those that showed the surface themselves, and, in a still
 *  view (the point within XS_TF_STILL_PX of the pixel's centre), those read at the tap as an
 *  edge's mix (the pixel's own antialiased history). Under motion such a tap is the last
 *  frame's colour of another surface beside an edge, and a thin feature's rim smeared by
 *  about a pixel a frame (issue 19's `edges` and `disocclusion` cases). The full
 *  tolerance (slope term) and the neighbours are only looked at for a tap that fails the
 *  relative tolerance alone (which implies the full one). With XS_TF_HISTORY_CATMULL_ROM and
 *  every tap of non-zero weight showing the surface itself, the Catmull-Rom resampling
 *  (catmull_rom_history) replaces the bilinear mean. */
vec3 history_at(vec2 pos, ivec2 px, uint eye, uint inst, float depth, float d_exp,
                out float out_wsum, out float out_own, out float out_blur)
{
    float tol_rel = tfp.depth_tolerance * d_exp, tol = -1.0, wsum = 0.0, own = 0.0;
    /* a still view (the point at the pixel's own centre, any jitter) */
    bool still = all(lessThan(abs(pos - (vec2(px) + 0.5)), vec2(XS_TF_STILL_PX)));
    vec2 b = pos - 0.5;
    ivec2 base = ivec2(floor(b));
    ivec2 home = ivec2(floor(pos)); /* the last frame's pixel holding the point */
    vec2 f = b - vec2(base);
    out_blur = f.x * (1.0 - f.x) + f.y * (1.0 - f.y); /* the bilinear kernel's variance, px^2 */
    vec3 x = vec3(0.0), inner[4];
    uint have = 0u;      /* bit k: inner[k] read */
    bool own_all = true; /* every tap of non-zero weight accepted at itself */
    for (int k = 0; k < 4; k++) {
        ivec2 o = ivec2(k & 1, k >> 1);
        ivec2 p = base + o;
        float w = (o.x == 1 ? f.x : 1.0 - f.x) * (o.y == 1 ? f.y : 1.0 - f.y);
        if (w <= 0.0)
            continue;
        own_all = own_all && inside(p);
        if (!inside(p))
            continue;
        uvec2 geo = imageLoad(tf_prev_geo, ivec3(p, eye)).xy;
        bool near = same_geo(geo, inst, d_exp, tol_rel);
        if (!near && inst != XS_MISS_INSTANCE) {
            if (tol < 0.0)
                tol = depth_tolerance(px, eye, inst, depth, d_exp);
            near = same_geo(geo, inst, d_exp, tol);
        }
        own_all = own_all && near;
        bool trusted = near;
        /* a tap accepted through neighbour q is read at q unless its footprint holds
         * the point (then it covered the surface: an edge's mix, antialiasing);
         * read at the tap, a light panel's rim leaked into the ceiling around it */
        ivec2 src = p;
        for (int n = 0; n < 9 && !near; n++) {
            ivec2 q = p + ivec2(n % 3 - 1, n / 3 - 1);
            if (n != 4 && same_surface(q, eye, inst, d_exp, max(tol, 0.0))) {
                near = true;
                src = p == home ? p : q;
                trusted = p == home && still;
            }
        }
        if (!near)
            continue;
        inner[k] = to_resolve(imageLoad(tf_history, ivec3(src, eye)).rgb);
        have |= 1u << k;
        own += trusted ? w : 0.0;
        x += w * inner[k];
        wsum += w;
    }
    out_wsum = wsum;
    out_own = own;
    if (wsum <= 0.0)
        return x;
    x /= wsum;
    if (tfp.history_filter != XS_TF_HISTORY_CATMULL_ROM || !own_all)
        return x;
    for (int k = 0; k < 4; k++) /* taps of zero weight: zero weight in both filters */
        inner[k] = (have & (1u << k)) != 0u ? inner[k] : x;
    if (tol < 0.0 && inst != XS_MISS_INSTANCE)
        tol = depth_tolerance(px, eye, inst, depth, d_exp);
    return catmull_rom_history(base, f, eye, inst, d_exp, max(tol, tol_rel), inner);
}

void main()
{
    uvec3 g = gl_GlobalInvocationID;
    if (g.x >= tfp.width || g.y >= tfp.height)
        return;
    uint total = 2u * tfp.width * tfp.height;
    for (uint i = (g.z * tfp.height + g.y) * tfp.width + g.x; i < tfp.instance_count; i += total)
        tf_next_xform[i] = instances[i].object_to_world;

    uint eye = g.z;
    ivec3 coord = ivec3(g);
    ivec2 size = ivec2(tfp.width, tfp.height);
    vec4 y4 = imageLoad(tf_src, coord);
    vec3 y = y4.rgb;

    /* 1. reprojection */
    float depth = imageLoad(tf_depth, coord).r;
    uint inst = imageLoad(tf_hitid, coord).x;
    if (depth <= 0.0 || inst >= tfp.instance_count)
        inst = XS_MISS_INSTANCE;
    imageStore(tf_next_geo, coord, uvec4(floatBitsToUint(depth), inst, 0u, 0u));
    float status = XS_TF_STATUS_NO_HISTORY;
    vec3 x = vec3(0.0);
    float wsum = 0.0, own = 0.0, blur = 0.0;
    if (tfp.history_valid != 0u) {
        status = XS_TF_STATUS_REJECTED;
        vec4 q = reproject_eye_space(g.xy, eye, depth, inst);
        if (q.z < 0.0) {
            vec4 tf = tfp.prev_eyes[eye].tan_fov;
            vec2 t = q.xy / -q.z;
            vec2 pos = vec2((t.x - tf.x) / (tf.y - tf.x), (t.y - tf.z) / (tf.w - tf.z)) *
                       vec2(size);
            /* 2. the history at pos from the taps that show the same surface */
            x = history_at(pos, ivec2(g.xy), eye, inst, depth, -q.z, wsum, own, blur);
            if (wsum >= tfp.min_weight && finite3(x))
                status = XS_TF_STATUS_BLENDED;
        }
    }
    if (tfp.debug != 0u)
        imageStore(tf_reproj, coord,
                   vec4(status == XS_TF_STATUS_BLENDED ? from_resolve(x) : vec3(0.0), wsum));
    if (status != XS_TF_STATUS_BLENDED) {
        imageStore(tf_out, coord, y4);
        imageStore(tf_aux, coord, vec4(1.0, 1.0, 1.0, status));
        return;
    }

    /* 3. the current 3 x 3 neighbourhood (clamped at the image border), in the resolve space
     * as the history is */
    vec3 m1 = vec3(0.0), m2 = vec3(0.0);    /* YCoCg moments (ON) */
    vec3 sy = vec3(0.0), sy2 = vec3(0.0), sd2 = vec3(0.0); /* RGB sums (PFJ23, Eq. 10-11) */
    bool edge = false; /* motion_edges: a neighbour shows another surface */
    for (int dy = -1; dy <= 1; dy++) {
        for (int dx = -1; dx <= 1; dx++) {
            ivec2 p = clamp(ivec2(g.xy) + ivec2(dx, dy), ivec2(0), size - 1);
            if (tfp.motion_edges != 0u && !edge)
                edge = neighbour_instance(ivec3(p, eye)) != inst;
            vec3 yi = to_resolve(imageLoad(tf_src, ivec3(p, eye)).rgb);
            vec3 c = rgb_to_ycocg(yi);
            m1 += c;
            m2 += c * c;
            sy += yi;
            sy2 += yi * yi;
            sd2 += (x - yi) * (x - yi);
        }
    }
    vec3 alpha;
    if (tfp.mode == XS_TF_MODE_PFJ23) {
        for (int c = 0; c < 3; c++)
            alpha[c] = xs_st_beta_pfj23(sy[c], sy2[c], sd2[c], 9.0);
    } else {
        vec3 mean = m1 / 9.0;
        vec3 sigma = sqrt(max(m2 / 9.0 - mean * mean, vec3(0.0)));
        x = ycocg_to_rgb(clip_to_box(rgb_to_ycocg(x), mean, tfp.gamma * sigma));
        /* the history's trusted share (own, see history_at) keeps alpha; the rest of the
         * weight, read through a neighbour or renormalised over fewer taps, is an
         * extrapolation that a box spanning both sides of an edge cannot clip: it takes
         * the current frame at XS_TF_UNTRUSTED_ALPHA */
        float a = tfp.alpha;
        /* the motion rule (XS_TF_MOTION_*): the trusted history's weight shrinks with the
         * blur its resampling added this frame */
        /* motion_edges: only on the dark side of an edge between two surfaces (the pixel's
         * luma below its neighbourhood's mean), where the blur carries the bright side's
         * radiance in: a relative error many times the bright side's (issue 19, Cornell) */
        if (tfp.motion_edges != 0u)
            edge = edge && rgb_to_ycocg(to_resolve(y)).x < mean.x;
        if (tfp.motion_px2 > 0.0 && (tfp.motion_edges == 0u || edge))
            a += max(tfp.motion_alpha - a, 0.0) * min(blur / tfp.motion_px2, 1.0);
        alpha = vec3(a + (max(XS_TF_UNTRUSTED_ALPHA, a) - a) * (1.0 - own));
    }

    /* 4. out = lerp(history, current, alpha) in the resolve space, back to radiance */
    vec3 outc, yt = to_resolve(y);
    for (int c = 0; c < 3; c++)
        outc[c] = xs_st_lerp(x[c], yt[c], alpha[c]);
    imageStore(tf_out, coord, vec4(from_resolve(outc), y4.a));
    imageStore(tf_aux, coord, vec4(alpha, status));
}
