// SPDX-License-Identifier: MIT
/**
 * @file hc_hybrid_reconstruct.comp
 * @brief Method `hybrid`, pass "reconstruct" (seed 000 §4): replaces sc_reconstruct.comp; the
 *        pixel colour from the visible samples with radiance from the hash cache.
 *
 * The sample loop, albedo, depth, hit id and the moments are sc_reconstruct.comp's (so hybrid's
 * visibility outputs equal samplecache's); only a surface sample's radiance differs: its hit
 * voxel V (LoD from its distance, no jitter: a stable lookup) and V's parent P one LoD above
 * are looked up (hc_lookup without insert, refreshing their stamps), and their demodulated
 * means combine weighted by their counts, L = (c_V L_V + c_P L_P) / (c_V + c_P), with c_s =
 * c_V + c_P the sample's count (so the finer voxel dominates once it has as many samples as
 * its parent). A sample with c_s = 0 (neither voxel written) has observed nothing and is left
 * out, as an unshaded sample of the sample cache is.
 *
 * A view-dependent sample (hc_view_dependent: smooth metal or glass) is never read from the
 * table: its radiance is its own path of this frame, which hc_hybrid_shade.rgen left in the
 * pixel's XS_BIND_ACCUM texel tagged hc_own_tag(slot), with count 1; when another sample of
 * the pixel was shaded this frame it has no observation and is left out as above.
 *
 * A sample on a deforming surface (skinned or morphed, params.deform_follow; xs_hashcache.h)
 * whose V and P hold nothing yet reads the voxels of its last-frame position instead (hc_peek:
 * no stamp refresh), where its radiance was before the surface moved; hc_hybrid_shade.rgen
 * carries that mean into the new voxels. Such samples are counted in deform_lookups, and in
 * deform_history when the radiance they use holds more than one sample.
 */
#version 460
#extension GL_GOOGLE_include_directive : require
#define XS_NO_TLAS
#include "xs_bindings.glsl"
#include "xs_hitinfo.glsl"
#include "xs_rng.glsl"
#include "xs_camera.glsl"
#include "xs_env.glsl"
#include "sc_common.glsl"
#include "hc_table.glsl"
#include "hc_deform.glsl"

layout(local_size_x = XS_SC_GROUP, local_size_y = XS_SC_GROUP, local_size_z = 1) in;

layout(set = 0, binding = XS_SC_BIND_OUT_MU1, rgba32f) uniform writeonly image2DArray out_mu1;
layout(set = 0, binding = XS_SC_BIND_OUT_MU2, rgba32f) uniform writeonly image2DArray out_mu2;

/** The count-weighted radiance of a surface hit fh's voxel and its parent (rgb, count); on a
 *  deforming surface whose two voxels hold nothing, those of its last-frame position. */
vec4 hy_radiance(uint eye, uvec4 fh, xs_surface sf, float t, vec3 wo)
{
    int lod = hc_lod(eye, t, wo, sf.ng);
    hc_key k = hc_key_at(sf.p, sf.ng, lod, false, vec2(0.0));
    vec4 v = hc_read(hc_lookup(k, false));
    vec4 p = hc_read(hc_lookup(hc_parent(k), false));
    if (hcp.deform != 0u) {
        bool moved;
        vec3 pp = hc_prev_point(fh.w, fh.z, sc_bary(fh), moved);
        if (moved && hcp.deform_follow != 0u && !(v.w + p.w > 0.0)) {
            hc_key kp = hc_key_at(pp, sf.ng, lod, false, vec2(0.0));
            v = hc_peek(kp);
            p = hc_peek(hc_parent(kp));
        }
        if (moved) {
            atomicAdd(hc_stats.deform_lookups, 1u);
            if (max(v.w, p.w) > 1.0)
                atomicAdd(hc_stats.deform_history, 1u);
        }
    }
    float c = v.w + p.w;
    return c > 0.0 ? vec4((v.w * v.rgb + p.w * p.rgb) / c, c) : vec4(0.0);
}

void main()
{
    uvec3 g = gl_GlobalInvocationID;
    if (g.x >= frame.width || g.y >= frame.height)
        return;
    uint eye = g.z;
    uint pix = sc_pix(eye, g.xy);
    uint cur = scp.cur;
    uint m = sc_mask[sc_mask_at(cur, pix)];
    vec3 o = sc_eye_pos(eye);
    xs_eye e = frame.eyes[eye];
    /* background samples: the environment map through the pixel centre, when there is one */
    vec3 bg = frame.env_width > 0u
                  ? xs_env_escape(xs_camera_ray(eye, vec2(g.xy) + 0.5).dir, true, 0.0)
                  : frame.environment.rgb;

    vec3 sum = vec3(0.0), sum_w1 = vec3(0.0), sum_w2 = vec3(0.0), albedo_sum = vec3(0.0);
    vec3 bg_w1 = vec3(0.0), bg_w2 = vec3(0.0);
    float n_obs = 0.0, c_total = 0.0, n_vis = 0.0, n_surf = 0.0, n_bg = 0.0;
    float best_t = SC_T_BACKGROUND;
    uvec4 hitid = uvec4(XS_MISS_INSTANCE, 0u, 0u, 0u);
    float depth = 0.0;
    for (uint bits = sc_vis(m) & sc_occ(m) & sc_all_slots(); bits != 0u; bits &= bits - 1u) {
        uint s = uint(findLSB(bits));
        uvec4 fh = sc_fh[sc_slot_at(cur, s, pix)];
        vec3 x;
        float c;
        n_vis += 1.0;
        if (sc_is_background(fh)) {
            x = bg;
            c = 1.0;
            albedo_sum += vec3(1.0);
        } else {
            xs_surface sf = sc_surface(fh);
            vec3 d = sf.p - o;
            float t = length(d);
            vec3 wo = -d / max(t, 1e-30);
            xs_surface_orient(sf, wo);
            xs_mat mt = xs_material_at(sf.material, sf.uv);
            vec3 a = xs_demod_albedo(mt);
            albedo_sum += a;
            if (t < best_t) {
                best_t = t;
                vec2 bary = sc_bary(fh);
                hitid = uvec4(fh.w, fh.z, floatBitsToUint(bary.x), floatBitsToUint(bary.y));
                depth = -(e.view * vec4(sf.p, 1.0)).z;
            }
            vec4 rad;
            if (hc_view_dependent(mt.metallic, mt.transmission, mt.roughness)) {
                /* not cached: this frame's own path of this sample, if it was shaded */
                vec4 own = imageLoad(accum, ivec3(g));
                rad = own.w == hc_own_tag(s) ? vec4(own.rgb, 1.0) : vec4(0.0);
            } else {
                rad = hy_radiance(eye, fh, sf, t, wo);
            }
            c = rad.w;
            x = xs_emitted(mt, sf.outside) + sc_demod(a) * rad.rgb;
        }
        if (!(c > 0.0 && xs_finite(x)))
            continue;
        sum += x;
        n_obs += 1.0;
        if (sc_is_background(fh)) {
            n_bg += 1.0;
            bg_w1 += x;
            bg_w2 += x * x;
        } else {
            n_surf += 1.0;
            sum_w1 += c * x;
            sum_w2 += c * x * x;
            c_total += c;
        }
    }
    /* background samples are exact: they count as much as the pixel's mean surface sample */
    float c_bg = n_surf > 0.0 ? c_total / n_surf : 1.0;
    sum_w1 += c_bg * bg_w1;
    sum_w2 += c_bg * bg_w2;
    c_total += c_bg * n_bg;
    vec3 color = n_obs > 0.0 ? sum / n_obs : vec3(0.0);
    vec3 albedo = n_vis > 0.0 ? albedo_sum / n_vis : vec3(1.0);
    vec3 mu1 = c_total > 0.0 ? sum_w1 / c_total : vec3(0.0);
    vec3 mu2 = c_total > 0.0 ? sum_w2 / c_total : vec3(0.0);
    hc_stats_flush();
    ivec3 coord = ivec3(g);
    imageStore(out_color, coord, vec4(color, 1.0));
    imageStore(out_albedo, coord, vec4(albedo, 1.0));
    imageStore(out_depth, coord, vec4(depth));
    imageStore(out_hitid, coord, hitid);
    imageStore(out_mu1, coord, vec4(mu1, c_total));
    imageStore(out_mu2, coord, vec4(mu2, c_total));
}
