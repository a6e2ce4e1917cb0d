// SPDX-License-Identifier: MIT
/**
 * @file sc_reconstruct.comp
 * @brief Sample cache pass "reconstruct" (seed 000 §3.3, §3.6): the pixel colour from the
 *        visible samples, plus albedo, depth, hit id and the raw moments mu_1, mu_2 (Eq. 5);
 *        the push constant (XS_SC_RC_*) leaves the albedo out, or writes it alone.
 *
 * Per pixel, over the visible samples: surface samples give emission + albedo * L_s (their
 * demodulated radiance remodulated, xs_demod_albedo through sc_demod) with weight c_s, and
 * count only once shaded (c_s > 0: an unshaded sample has observed nothing yet); background
 * samples give the environment along their own direction (xs_env_escape: the map and sun
 * disk, or the constant). colour = mean of the observed samples' values (§3.3:
 * "average the observed radiance of all visible samples"); mu_1 = sum c_s X_s / c_X,
 * mu_2 = sum c_s X_s^2 / c_X (Eq. 5, 6; rgb, alpha = c_X), where a background sample (exact,
 * no count of its own) weighs as the pixel's mean surface c_s (1 without surface samples),
 * so mu_1 equals the colour whenever the counts agree. albedo = mean xs_demod_albedo of
 * all visible samples (1 for background); depth and hit id are those of the closest visible
 * sample (§3.6: its depth is the most stable), as the `spp` outputs define them.
 * A sample on the triangle (material) of the one before reuses its corners (albedo and
 * emission): sc_tri, rc_material; the values are those of xs_surface_at and xs_material_at.
 */
#version 460
#extension GL_GOOGLE_include_directive : require
#define XS_NO_TLAS
#include "xs_bindings.glsl"
#include "xs_hitinfo.glsl"
#include "xs_env.glsl"
#include "sc_common.glsl"

layout(local_size_x = XS_SC_GROUP, local_size_y = XS_SC_GROUP, local_size_z = 1) in;

layout(set = 0, binding = XS_SC_BIND_OUT_MU1, rgba32f) uniform writeonly image2DArray out_mu1;
layout(set = 0, binding = XS_SC_BIND_OUT_MU2, rgba32f) uniform writeonly image2DArray out_mu2;
layout(push_constant) uniform XsScRcPush
{
    uint rc_outputs; /* XS_SC_RC_* */
};

/** The last material one invocation looked up: a material without textures has one albedo
 *  and emission, so it is evaluated once per run of samples with that material (most pixels'
 *  samples share one), a textured one at every sample's uv. */
struct rc_material {
    uint id; /* 0xFFFFFFFF: none yet */
    bool constant;
    vec3 albedo;   /* xs_demod_albedo */
    vec3 emission; /* xs_mat.emission */
    bool double_sided;
    bool specific; /* xs_sc_eye_specific (cross-eye reuse) */
};

/** Cross-eye reuse: whether material values mt are eye-specific (false when the reuse is off:
 *  no stratum to weigh then). */
bool rc_specific(xs_mat mt)
{
    return scp.cross_eye != 0u &&
           xs_sc_eye_specific(mt.metallic, mt.transmission, mt.roughness, mt.ior) != 0u;
}

/** Albedo (xs_demod_albedo) and emitted radiance towards the eye (xs_emitted) of surface
 *  sample fh on tri (fetched), seen along unit direction wo (sample to eye). A constant
 *  material whose emission does not depend on the side (none, or double-sided) needs neither
 *  the uv nor the side, so tri's vertex attributes are loaded only for the others (on
 *  lavapipe they were most of this pass's loads); the values are the same either way. */
void rc_material_at(inout rc_material c, inout sc_tri tri, uvec4 fh, vec3 wo, out vec3 albedo,
                    out vec3 emitted, out bool specific)
{
    uint id = sc_material(fh);
    if (c.id != id) {
        xs_material m = materials[id];
        c.id = id;
        c.constant = m.base_color_tex == XS_NO_TEXTURE && m.metal_rough_tex == XS_NO_TEXTURE &&
                     m.emission_tex == XS_NO_TEXTURE;
        if (c.constant) {
            xs_mat mt = xs_material_at(id, vec2(0.0));
            c.albedo = xs_demod_albedo(mt);
            c.emission = mt.emission;
            c.double_sided = mt.double_sided;
            c.specific = rc_specific(mt);
        }
    }
    if (c.constant && (c.double_sided || all(equal(c.emission, vec3(0.0))))) {
        albedo = c.albedo;
        emitted = c.emission;
        specific = c.specific;
        return;
    }
    sc_tri_fetch(tri, fh, true);
    bool outside = sc_tri_outside(tri, fh, wo);
    if (c.constant) {
        albedo = c.albedo;
        emitted = outside ? c.emission : vec3(0.0);
        specific = c.specific;
        return;
    }
    xs_mat mt = xs_material_at(id, sc_tri_uv(tri, fh));
    albedo = xs_demod_albedo(mt);
    emitted = xs_emitted(mt, outside);
    specific = rc_specific(mt);
}

/**
 * Cross-eye reuse: the other eye's copies are only of eye-independent surfaces and the
 * background, so in a pixel that also shows an eye-specific surface (a metal sphere's
 * silhouette) they would outweigh it. The pixel is then estimated per stratum, each stratum's
 * share of the pixel taken from this eye's OWN samples (placed by its own rays, so in
 * proportion to coverage): value = (1 - phi) x shared mean + phi x eye-specific mean.
 * own_spec, own_all: own visible samples (eye-specific, all); a_*: the stratum's value (colour
 * mean or moment) over all observed samples, s_*: over the eye-specific ones (n_* observed).
 */
vec3 rc_strata(vec3 a_sum, float a_n, vec3 s_sum, float s_n, float own_spec, float own_all)
{
    float sh_n = a_n - s_n;
    if (!(s_n > 0.0) || !(sh_n > 0.0) || !(own_all > 0.0))
        return a_n > 0.0 ? a_sum / a_n : vec3(0.0);
    float phi = own_spec / own_all;
    return (1.0 - phi) * ((a_sum - s_sum) / sh_n) + phi * (s_sum / s_n);
}

/** A pixel's sums over its visible samples (Eq. 5, 6 and the colour of §3.3), the closest
 *  sample's outputs, and cross-eye reuse's eye-specific stratum (rc_strata). */
struct rc_sums {
    vec3 sum, sum_w1, sum_w2, albedo_sum, bg_w1, bg_w2;
    float n_obs, c_total, n_vis, n_surf, n_bg;
    float best_t, depth;
    uvec4 hitid;
    vec3 sp_sum, sp_w1, sp_w2;
    float sp_obs, sp_c, own_spec, own_all;
};

void rc_sums_init(out rc_sums r)
{
    r.sum = r.sum_w1 = r.sum_w2 = r.albedo_sum = r.bg_w1 = r.bg_w2 = vec3(0.0);
    r.n_obs = r.c_total = r.n_vis = r.n_surf = r.n_bg = 0.0;
    r.best_t = SC_T_BACKGROUND;
    r.depth = 0.0;
    r.hitid = uvec4(XS_MISS_INSTANCE, 0u, 0u, 0u);
    r.sp_sum = r.sp_w1 = r.sp_w2 = vec3(0.0);
    r.sp_obs = r.sp_c = r.own_spec = r.own_all = 0.0;
}

/** Value x and count c of surface sample fh (pool address addr) seen from eye e at o: emission
 *  + albedo x L_s; also its albedo, eye-specificity and, when closest so far, depth and hit id. */
void rc_surface(inout rc_sums r, inout sc_tri tri, inout rc_material mc, uvec4 fh, uint addr,
                vec3 o, xs_eye e, out vec3 x, out float c, out bool specific)
{
    sc_tri_fetch(tri, fh, false);
    vec3 sp = sc_tri_position(tri, fh);
    vec3 d = sp - o;
    float t = length(d);
    vec3 a, emitted;
    rc_material_at(mc, tri, fh, -d / max(t, 1e-30), a, emitted, specific);
    r.albedo_sum += a;
    if (t < r.best_t) {
        r.best_t = t;
        vec2 bary = sc_bary(fh);
        r.hitid = uvec4(fh.w, fh.z, floatBitsToUint(bary.x), floatBitsToUint(bary.y));
        r.depth = -(e.view * vec4(sp, 1.0)).z;
    }
    vec4 rad = sc_rad_load(sc_rad_of(addr));
    c = rad.w;
    x = emitted + sc_demod(a) * rad.rgb;
}

/** Adds an observed sample (value x, count c) to the sums. */
void rc_add(inout rc_sums r, vec3 x, float c, bool background, bool specific)
{
    if (specific) {
        r.sp_sum += x;
        r.sp_obs += 1.0;
        r.sp_w1 += c * x;
        r.sp_w2 += c * x * x;
        r.sp_c += c;
    }
    r.sum += x;
    r.n_obs += 1.0;
    if (background) {
        r.n_bg += 1.0;
        r.bg_w1 += x;
        r.bg_w2 += x * x;
    } else {
        r.n_surf += 1.0;
        r.sum_w1 += c * x;
        r.sum_w2 += c * x * x;
        r.c_total += c;
    }
}

/** The pixel's outputs from its sums. */
void rc_store(inout rc_sums r, ivec3 coord)
{
    /* background samples are exact: they count as much as the pixel's mean surface sample */
    float c_bg = r.n_surf > 0.0 ? r.c_total / r.n_surf : 1.0;
    r.sum_w1 += c_bg * r.bg_w1;
    r.sum_w2 += c_bg * r.bg_w2;
    r.c_total += c_bg * r.n_bg;
    vec3 color = r.n_obs > 0.0 ? r.sum / r.n_obs : vec3(0.0);
    vec3 albedo = r.n_vis > 0.0 ? r.albedo_sum / r.n_vis : vec3(1.0);
    vec3 mu1 = r.c_total > 0.0 ? r.sum_w1 / r.c_total : vec3(0.0);
    vec3 mu2 = r.c_total > 0.0 ? r.sum_w2 / r.c_total : vec3(0.0);
    if (scp.cross_eye != 0u) {
        color = rc_strata(r.sum, r.n_obs, r.sp_sum, r.sp_obs, r.own_spec, r.own_all);
        mu1 = rc_strata(r.sum_w1, r.c_total, r.sp_w1, r.sp_c, r.own_spec, r.own_all);
        mu2 = rc_strata(r.sum_w2, r.c_total, r.sp_w2, r.sp_c, r.own_spec, r.own_all);
    }
    if (rc_outputs != XS_SC_RC_NO_ALBEDO)
        imageStore(out_albedo, coord, vec4(albedo, 1.0));
    if (rc_outputs == XS_SC_RC_ALBEDO_ONLY)
        return; /* the frame's other outputs may have changed since (TAA, the blend) */
    imageStore(out_color, coord, vec4(color, 1.0));
    imageStore(out_depth, coord, vec4(r.depth));
    imageStore(out_hitid, coord, r.hitid);
    imageStore(out_mu1, coord, vec4(mu1, r.c_total));
    imageStore(out_mu2, coord, vec4(mu2, r.c_total));
}

void main()
{
    uvec3 g = gl_GlobalInvocationID;
    if (g.x >= frame.width || g.y >= frame.height)
        return;
    uint eye = g.z;
    uint pix = sc_pix(eye, g.xy);
    uint m = sc_mask[sc_mask_at(scp.cur, pix)];
    vec3 o = sc_eye_pos(eye);
    xs_eye e = frame.eyes[eye];
    rc_sums r;
    rc_sums_init(r);
    sc_tri tri;
    sc_tri_init(tri);
    rc_material mc;
    mc.id = 0xFFFFFFFFu;
    mc.constant = false;
    mc.albedo = mc.emission = vec3(0.0);
    mc.double_sided = false;
    mc.specific = false;
    uint foreign = sc_foreign_bits(scp.cur, pix); /* cross-eye reuse: the other eye's copies */
    for (uint bits = sc_vis(m) & sc_occ(m) & sc_all_slots(); bits != 0u; bits &= bits - 1u) {
        uint s = uint(findLSB(bits));
        uint a = sc_slot_at(scp.cur, s, pix); /* loaded once: 4 bytes per sample less */
        uvec4 fh = sc_fh[a];
        vec3 x;
        float c;
        bool specific = false;
        bool background = sc_is_background(fh);
        r.n_vis += 1.0;
        if (background) {
            /* what the sample's own ray sees: the map and sun disk, or the constant */
            x = xs_env_escape(sc_background_dir(fh), true, 0.0);
            c = 1.0;
            r.albedo_sum += vec3(1.0);
        } else {
            rc_surface(r, tri, mc, fh, a, o, e, x, c, specific);
        }
        if ((foreign & sc_obit(s)) == 0u) {
            r.own_all += 1.0;
            r.own_spec += specific ? 1.0 : 0.0;
        }
        if (c > 0.0 && xs_finite(x))
            rc_add(r, x, c, background, specific);
    }
    rc_store(r, ivec3(g));
}
