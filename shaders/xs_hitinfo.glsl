// SPDX-License-Identifier: MIT
/**
 * @file xs_hitinfo.glsl
 * @brief Rebuilds a surface point from (instance, primitive, barycentrics): world position,
 * normals, uv, triangle area and the material evaluated with its textures.
 *
 * Orientation conventions:
 * - "outside" of a triangle is the side its interpolated vertex normal points to (the winding
 *   is not used: the geometric normal is flipped to agree with the vertex normals);
 * - xs_surface_orient() then flips both normals to face the viewer (wo), and records whether wo
 *   is outside (used for the IOR ratio of glass and for one-sided emission).
 * Requires xs_bindings.glsl.
 */
#ifndef XS_HITINFO_GLSL
#define XS_HITINFO_GLSL

#include "xs_sampling.glsl"

struct xs_surface {
    vec3 p;        /* world position */
    vec3 ng;       /* unit geometric normal (outside, or facing wo after xs_surface_orient) */
    vec3 ns;       /* unit shading normal (same) */
    vec4 uv;       /* xy TEXCOORD_0, zw TEXCOORD_1 (xs_material.uv1_mask picks per texture) */
    float area;    /* world-space triangle area, m^2 */
    bool outside;  /* after xs_surface_orient: wo lies on the outside */
    uint material;
};

/** The material's values at uv (textures sampled at LOD 0). */
struct xs_mat {
    vec3 base;       /* linear base colour x texture */
    float metallic;
    float roughness; /* perceptual; GGX alpha = roughness^2 */
    float transmission;
    float ior;
    vec3 emission;   /* linear emitted radiance */
    bool double_sided;
    bool unlit;      /* KHR_materials_unlit: emission = base colour, nothing scattered */
    /* KHR_materials_specular / _clearcoat / _sheen / _volume (see xs_bsdf.glsl) */
    vec3 spec_color; /* specularColorFactor x texture (scales the dielectric F0) */
    float specular;  /* specularFactor x texture A: 1 = plain glTF, 0 = no dielectric specular */
    float clearcoat;
    float clearcoat_roughness;
    vec3 sheen_color;
    float sheen_roughness;
    bool thin;       /* transmission without KHR_materials_volume: thin-walled, no refraction */
    vec3 sigma_a;    /* Beer-Lambert absorption inside the volume, 1/m */
};

/** The uv set that texture `bit` (XS_TEX_* or XS_UV1_*) reads: uv.xy (TEXCOORD_0) or uv.zw
 *  (TEXCOORD_1, when its bit of the material's uv1_mask is set). */
vec2 xs_uv_set(uint uv1_mask, uint bit, vec4 uv)
{
    return (uv1_mask & (1u << bit)) != 0u ? uv.zw : uv.xy;
}

/** Texture t at its uv set (LOD 0), or `none` without one: the extension textures (no
 *  KHR_texture_transform). */
vec4 xs_tex_or(uint uv1_mask, uint t, uint bit, vec4 uv, vec4 none)
{
    return t == XS_NO_TEXTURE
               ? none
               : textureLod(textures[nonuniformEXT(t)], xs_uv_set(uv1_mask, bit, uv), 0.0);
}

/** The extension values of xs_mat (xs_material_at). */
void xs_material_extensions(xs_material m, vec4 uv, inout xs_mat r)
{
    const vec4 one = vec4(1.0);
    uint mask = m.uv1_mask;
    r.transmission *= xs_tex_or(mask, m.transmission_tex, XS_UV1_TRANSMISSION, uv, one).r;
    r.specular = clamp(m.specular.w * xs_tex_or(mask, m.specular_tex, XS_UV1_SPECULAR, uv, one).a,
                       0.0, 1.0);
    vec4 spec_tex = xs_tex_or(mask, m.specular_color_tex, XS_UV1_SPECULAR_COLOR, uv, one);
    r.spec_color = max(m.specular.rgb * spec_tex.rgb, vec3(0.0));
    r.clearcoat = clamp(m.clearcoat * xs_tex_or(mask, m.clearcoat_tex, XS_UV1_CLEARCOAT, uv, one).r,
                        0.0, 1.0);
    r.clearcoat_roughness = clamp(
        m.clearcoat_roughness *
            xs_tex_or(mask, m.clearcoat_rough_tex, XS_UV1_CLEARCOAT_ROUGH, uv, one).g,
        0.0, 1.0);
    vec4 sheen_tex = xs_tex_or(mask, m.sheen_color_tex, XS_UV1_SHEEN_COLOR, uv, one);
    r.sheen_color = clamp(m.sheen.rgb * sheen_tex.rgb, vec3(0.0), vec3(1.0));
    r.sheen_roughness = clamp(
        m.sheen.w * xs_tex_or(mask, m.sheen_rough_tex, XS_UV1_SHEEN_ROUGH, uv, one).a, 0.0, 1.0);
    r.thin = !(m.attenuation.w > 0.0);
    r.sigma_a = max(m.attenuation.rgb, vec3(0.0));
}

/** KHR_texture_transform: the uv of texture slot XS_TEX_* of material m, from its uv set. */
vec2 xs_uv_slot(xs_material m, uint slot, vec4 uv)
{
    vec3 h = vec3(xs_uv_set(m.uv1_mask, slot, uv), 1.0);
    return vec2(dot(m.uv_rows[2u * slot].xyz, h), dot(m.uv_rows[2u * slot + 1u].xyz, h));
}

/**
 * Tangent-space normal mapping (glTF 2.0 §3.9.3): n = normalize(T x + B y + N z) with
 * (x, y, z) = (2 texel - 1) x (scale, scale, 1), T the vertex tangent made orthogonal to the
 * shading normal N, B = w cross(N, T) taken through the instance transform (so mirrored
 * instances keep the map's handedness). Returns ns unchanged without a normal map.
 */
vec3 xs_normal_map(xs_instance inst, xs_material m, vec3 ns, vec3 n_obj, vec4 t_obj, vec4 uv)
{
    if (m.normal_tex == XS_NO_TEXTURE)
        return ns;
    vec3 tex = textureLod(textures[nonuniformEXT(m.normal_tex)], xs_uv_slot(m, XS_TEX_NORMAL, uv),
                          0.0).xyz;
    vec3 c = tex * 2.0 - 1.0;
    c.xy *= m.normal_scale;
    vec3 t = mat3(inst.object_to_world) * t_obj.xyz;
    vec3 b = mat3(inst.object_to_world) * (cross(n_obj, t_obj.xyz) * (t_obj.w < 0.0 ? -1.0 : 1.0));
    t -= ns * dot(ns, t);
    b -= ns * dot(ns, b) + t * (dot(t, b) / max(dot(t, t), 1e-30));
    float tl = length(t), bl = length(b);
    if (!(tl > 1e-20) || !(bl > 1e-20))
        return ns;
    vec3 n = (t / tl) * c.x + (b / bl) * c.y + ns * c.z;
    float nl = length(n);
    return nl > 1e-20 && !isnan(nl) ? n / nl : ns;
}

xs_surface xs_surface_at(uint instance, uint primitive, vec2 bary)
{
    xs_instance inst = instances[instance];
    uint base = inst.first_index + 3u * primitive;
    xs_vertex v0 = vertices[indices[base]];
    xs_vertex v1 = vertices[indices[base + 1u]];
    xs_vertex v2 = vertices[indices[base + 2u]];
    vec3 w = vec3(1.0 - bary.x - bary.y, bary.x, bary.y);

    vec3 p0 = (inst.object_to_world * vec4(v0.position_u.xyz, 1.0)).xyz;
    vec3 p1 = (inst.object_to_world * vec4(v1.position_u.xyz, 1.0)).xyz;
    vec3 p2 = (inst.object_to_world * vec4(v2.position_u.xyz, 1.0)).xyz;

    xs_surface s;
    s.p = w.x * p0 + w.y * p1 + w.z * p2;
    vec3 cr = cross(p1 - p0, p2 - p0);
    float cr_len = length(cr);
    s.area = 0.5 * cr_len;
    vec3 ng = cr_len > 0.0 ? cr / cr_len : vec3(0.0, 0.0, 1.0);

    vec3 n_obj = w.x * v0.normal_v.xyz + w.y * v1.normal_v.xyz + w.z * v2.normal_v.xyz;
    vec3 ns = (inst.normal_to_world * vec4(n_obj, 0.0)).xyz;
    float ns_len = length(ns);
    ns = ns_len > 1e-20 && !isnan(ns_len) ? ns / ns_len : ng;
    /* Outside = where the vertex normals point (before normal mapping). */
    if (dot(ng, ns) < 0.0)
        ng = -ng;
    s.uv.xy = w.x * vec2(v0.position_u.w, v0.normal_v.w) +
              w.y * vec2(v1.position_u.w, v1.normal_v.w) +
              w.z * vec2(v2.position_u.w, v2.normal_v.w);
    s.uv.zw = w.x * v0.uv1.xy + w.y * v1.uv1.xy + w.z * v2.uv1.xy;
    vec4 t_obj = w.x * v0.tangent + w.y * v1.tangent + w.z * v2.tangent;
    t_obj.w = v0.tangent.w;
    ns = xs_normal_map(inst, materials[inst.material], ns, n_obj, t_obj, s.uv);
    s.ng = ng;
    s.ns = ns;
    s.outside = true;
    s.material = inst.material;
    return s;
}

/** glTF alpha (base colour factor alpha x base colour texture alpha) of material m at the
 *  point (bary) of triangle `primitive` of `instance`: only the uv is rebuilt (hit.rahit). */
float xs_alpha_at(xs_material m, uint instance, uint primitive, vec2 bary)
{
    float a = m.base_color.a;
    if (m.base_color_tex == XS_NO_TEXTURE)
        return a;
    uint base = instances[instance].first_index + 3u * primitive;
    xs_vertex v0 = vertices[indices[base]];
    xs_vertex v1 = vertices[indices[base + 1u]];
    xs_vertex v2 = vertices[indices[base + 2u]];
    vec3 w = vec3(1.0 - bary.x - bary.y, bary.x, bary.y);
    vec4 uv;
    uv.xy = w.x * vec2(v0.position_u.w, v0.normal_v.w) +
            w.y * vec2(v1.position_u.w, v1.normal_v.w) + w.z * vec2(v2.position_u.w, v2.normal_v.w);
    uv.zw = w.x * v0.uv1.xy + w.y * v1.uv1.xy + w.z * v2.uv1.xy;
    return a * textureLod(textures[nonuniformEXT(m.base_color_tex)], xs_uv_slot(m, XS_TEX_BASE, uv),
                          0.0).a;
}

/** Flips the normals to face wo (unit, pointing away from the surface). The shading normal
 *  falls back to the geometric one when wo is below it (silhouettes of smooth meshes). */
void xs_surface_orient(inout xs_surface s, vec3 wo)
{
    s.outside = dot(wo, s.ng) >= 0.0;
    if (!s.outside) {
        s.ng = -s.ng;
        s.ns = -s.ns;
    }
    if (dot(wo, s.ns) <= 0.0)
        s.ns = s.ng;
}

/** The material's values at a point with uv sets uv.xy (TEXCOORD_0) and uv.zw (TEXCOORD_1). */
xs_mat xs_material_at(uint material, vec4 uv)
{
    xs_material m = materials[material];
    xs_mat r;
    r.base = m.base_color.rgb;
    if (m.base_color_tex != XS_NO_TEXTURE)
        r.base *= textureLod(textures[nonuniformEXT(m.base_color_tex)],
                             xs_uv_slot(m, XS_TEX_BASE, uv), 0.0).rgb;
    r.metallic = m.metallic;
    r.roughness = m.roughness;
    if (m.metal_rough_tex != XS_NO_TEXTURE) {
        /* glTF 2.0 §3.9.2: G = roughness, B = metallic. */
        vec4 mr = textureLod(textures[nonuniformEXT(m.metal_rough_tex)],
                             xs_uv_slot(m, XS_TEX_METAL_ROUGH, uv), 0.0);
        r.roughness *= mr.g;
        r.metallic *= mr.b;
    }
    r.metallic = clamp(r.metallic, 0.0, 1.0);
    r.roughness = clamp(r.roughness, 0.0, 1.0);
    r.transmission = clamp(m.transmission, 0.0, 1.0);
    r.ior = max(m.ior, 1.0);
    r.emission = m.emission.rgb;
    if (m.emission_tex != XS_NO_TEXTURE)
        r.emission *= textureLod(textures[nonuniformEXT(m.emission_tex)],
                                 xs_uv_slot(m, XS_TEX_EMISSION, uv), 0.0).rgb;
    r.double_sided = (m.flags & XS_MAT_DOUBLE_SIDED) != 0u;
    r.unlit = (m.flags & XS_MAT_UNLIT) != 0u;
    xs_material_extensions(m, uv, r);
    if (r.unlit) {
        /* KHR_materials_unlit: the base colour is the radiance seen, on both sides; a black,
         * index-matched (IOR 1) opaque dielectric scatters nothing (xs_bsdf.glsl). */
        r.emission = r.base;
        r.base = vec3(0.0);
        r.metallic = 0.0;
        r.transmission = 0.0;
        r.ior = 1.0;
        r.double_sided = true;
        r.clearcoat = 0.0;
        r.sheen_color = vec3(0.0);
    }
    return r;
}

/** xs_material_at with TEXCOORD_1 = TEXCOORD_0, for callers that hold one uv set. */
xs_mat xs_material_at(uint material, vec2 uv)
{
    return xs_material_at(material, vec4(uv, uv));
}

/** Emitted radiance towards the viewer: one-sided (outside only) unless double-sided. */
vec3 xs_emitted(xs_mat m, bool outside)
{
    return (outside || m.double_sided) ? m.emission : vec3(0.0);
}

/**
 * The demodulation albedo written to XS_BIND_OUT_ALBEDO: the base colour (diffuse albedo of
 * dielectrics, F0 of metals: glTF uses the same base colour for both), blended towards 1 by
 * the transmission of the dielectric part (clear glass = 1). Background = 1.
 */
vec3 xs_demod_albedo(xs_mat m)
{
    if (m.unlit)
        return m.emission; /* the unlit colour (what `primary` shows) */
    return mix(m.base, vec3(1.0), m.transmission * (1.0 - m.metallic));
}

/* Albedo channels below this are not divided out (nor multiplied back): black base colours
 * can still reflect specularly. */
#define XS_DEMOD_MIN 1e-3
/** The factor radiance is demodulated by / remodulated with (seed 000 §3.3): the albedo of
 *  xs_demod_albedo, 1 in channels below XS_DEMOD_MIN. The sample and hash caches store
 *  radiance divided by it. */
vec3 xs_demod(vec3 albedo)
{
    return mix(vec3(1.0), albedo, greaterThanEqual(albedo, vec3(XS_DEMOD_MIN)));
}

/** Ray origin offset off a surface to the side of n, against self-intersection: a fixed
 *  number of float ULPs away from the world origin, a small absolute step near it (Wächter and
 *  Binder 2019, "A Fast and Robust Method for Avoiding Self-Intersection", Ray Tracing Gems
 *  ch. 6). */
#define XS_OFFSET_ORIGIN_BAND (1.0 / 32.0)
#define XS_OFFSET_FLOAT_STEP (1.0 / 65536.0)
#define XS_OFFSET_INT_ULPS 256.0
vec3 xs_offset_ray(vec3 p, vec3 n)
{
    ivec3 ulps = ivec3(XS_OFFSET_INT_ULPS * n);
    vec3 far_off;
    for (int i = 0; i < 3; i++)
        far_off[i] = intBitsToFloat(floatBitsToInt(p[i]) + (p[i] < 0.0 ? -ulps[i] : ulps[i]));
    vec3 near_off = p + XS_OFFSET_FLOAT_STEP * n;
    return mix(far_off, near_off, lessThan(abs(p), vec3(XS_OFFSET_ORIGIN_BAND)));
}

#endif
