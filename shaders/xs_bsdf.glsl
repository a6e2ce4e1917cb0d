// SPDX-License-Identifier: MIT
/**
 * @file xs_bsdf.glsl
 * @brief glTF 2.0 metal/rough + KHR_materials_transmission/ior/specular/clearcoat/sheen/volume
 *        BSDF: evaluation, sampling, pdf.
 *
 * The glTF material is a mix of components with weights that sum to 1 (glTF 2.0 Appendix B;
 * the KHR_materials_* extensions' layering: clearcoat over sheen over the base):
 *   coat        c Fc(N.V)                GGX reflection, white, alpha = clearcoatRoughness^2
 *   sheen       (1-cFc) s                sheen_color * Charlie sheen / s
 *   metal       (1-cFc)(1-s) m           F_schlick(base) * GGX specular
 *   opaque      (1-cFc)(1-s)(1-m)(1-tr)  Fs * GGX specular + (1 - max(Fs)) * base / pi
 *   glass       (1-cFc)(1-s)(1-m) tr     Fs * GGX reflection + (1 - Fs) * base * transmission
 * with Fc the exact Fresnel at IOR XS_CLEARCOAT_IOR of the view direction (KHR_materials_
 * clearcoat's fresnel_coat, which also attenuates everything below by 1 - c Fc), s =
 * min(max(sheen_color) E(N.V, sheenRoughness), 1) (KHR_materials_sheen's albedo scaling, E the
 * sheen lobe's directional albedo, XS_SHEEN_E), Fs the dielectric Fresnel scaled by
 * KHR_materials_specular (xs_spec_fresnel: min(F specularColor, 1) specular, so specular 0 has
 * no specular lobe at all). The path tracer picks ONE component per surface vertex with
 * probability equal to its weight (stochastic mixing, unbiased: the weight cancels against the
 * probability; every weight depends on wo only) and uses that component for both light sampling
 * and BSDF sampling, so MIS stays consistent. One uniform number picks the component, rescaled
 * after each layer, so materials without coat and sheen use it exactly as before.
 *
 * Glass is thin-walled unless the material has KHR_materials_volume (thicknessFactor > 0): the
 * transmission extension defines an infinitely thin surface, so light passes straight through
 * (smooth: wi = -wo; rough: the GGX reflection lobe mirrored through the surface) with the same
 * IOR on both sides and no radiance scaling. A volume refracts (Snell, Walter et al. 2007) and
 * absorbs inside with Beer-Lambert (xs_path.glsl).
 *
 * Dielectric Fresnel is the exact unpolarised formula with the material IOR (F0 = 0.04 at IOR
 * 1.5 as in glTF); metals use Schlick with F0 = base colour. An opaque dielectric with IOR 1
 * therefore has no specular lobe: a pure Lambertian (the white-furnace material).
 * GGX: D, height-correlated Smith G2 and G1 (Heitz 2014, "Understanding the Masking-Shadowing
 * Function", Eq. 72 and 99), visible-normal sampling (Heitz 2018, "Sampling the GGX
 * Distribution of Visible Normals", JCGT 7(4)). Rough transmission: Walter et al. 2007,
 * "Microfacet Models for Refraction through Rough Surfaces", Eq. 16-21.
 *
 * All directions are in the local shading frame (z = shading normal, facing wo; wo.z > 0).
 * Values are returned as f * |cos(theta_i)| ("fcos"); pdfs are per solid angle of wi.
 */
#ifndef XS_BSDF_GLSL
#define XS_BSDF_GLSL

#include "xs_sampling.glsl"

#define XS_BSDF_METAL 0u
#define XS_BSDF_OPAQUE 1u
#define XS_BSDF_GLASS 2u
#define XS_BSDF_SHEEN 3u

/* KHR_materials_clearcoat: the coat is a dielectric of IOR 1.5 (F0 = 0.04). */
#define XS_CLEARCOAT_IOR 1.5
/* Smallest Charlie sheen alpha (sheenRoughness^2): the lobe's sin^(1/alpha) stays finite; the
 * albedo table XS_SHEEN_E was integrated with the same clamp. */
#define XS_SHEEN_MIN_ALPHA 1e-2

/* Smallest GGX alpha of reflective lobes: keeps D finite (D <= 1/(pi alpha^2) ~ 3e5). */
#define XS_MIN_ALPHA 1e-3
/* XS_GLASS_SMOOTH_ROUGHNESS (xrsc_shared.h): glass below it is smooth (delta lobes). */
/* Lower clamp of the probability of sampling the specular lobe of an opaque dielectric when
 * both lobes can contribute (keeps either lobe reachable by BSDF sampling). */
#define XS_MIN_LOBE_PROB 0.05
/* Relative IORs closer to 1 than this are index-matched: no reflection at all (exactly 0,
 * so an opaque dielectric with IOR 1 is a pure Lambertian and never samples its specular). */
#define XS_IOR_MATCH_EPS 1e-4
/* Cosines below this are treated as grazing (no contribution). */
#define XS_COS_EPS 1e-6

struct xs_bsdf {
    uint kind;   /* XS_BSDF_* */
    vec3 base;   /* metal: F0; opaque: diffuse albedo; glass: transmission tint; sheen: scale */
    float alpha; /* GGX alpha = roughness^2 (sheen: Charlie alpha) */
    float eta_o; /* IOR on the side of wo */
    float eta_i; /* IOR on the other side (for glass) */
    bool smooth_glass;
    bool thin;       /* glass: thin-walled (no refraction, same medium on both sides) */
    vec3 spec_color; /* KHR_materials_specular colour, (1, 1, 1) = plain glTF */
    float specular;  /* KHR_materials_specular weight, 1 = plain glTF */
};

/** The material parameters xs_bsdf_make reads (the path tracer fills it from xs_mat). */
struct xs_bsdf_in {
    vec3 base;
    float metallic, roughness, transmission, ior;
    vec3 spec_color;
    float specular;
    float clearcoat, clearcoat_roughness;
    vec3 sheen_color;
    float sheen_roughness;
    bool thin;
};

float xs_fresnel_dielectric(float cos_i, float eta);
float xs_sheen_albedo(float cos_o, float roughness);

/** Picks the coat (true) or rescales u for the layers below it (false). */
bool xs_pick_layer(float p, inout float u)
{
    if (!(p > 0.0))
        return false;
    if (u < p)
        return true;
    u = (u - p) / (1.0 - p);
    return false;
}

/** Picks the component for one vertex (u uniform in [0,1), wo_z the cosine of the view
 *  direction in the shading frame), see the file comment. */
xs_bsdf xs_bsdf_make(xs_bsdf_in m, float wo_z, bool outside, float u)
{
    xs_bsdf b;
    b.base = m.base;
    b.alpha = m.roughness * m.roughness;
    b.eta_o = outside ? 1.0 : m.ior;
    b.eta_i = outside ? m.ior : 1.0;
    b.smooth_glass = false;
    b.thin = false;
    b.spec_color = m.spec_color;
    b.specular = m.specular;
    float pc = m.clearcoat > 0.0 ? m.clearcoat * xs_fresnel_dielectric(wo_z, XS_CLEARCOAT_IOR)
                                 : 0.0;
    if (xs_pick_layer(pc, u)) {
        /* the coat's Fresnel is in its pick probability: a white GGX mirror lobe remains */
        b.kind = XS_BSDF_METAL;
        b.base = vec3(1.0);
        b.alpha = max(m.clearcoat_roughness * m.clearcoat_roughness, XS_MIN_ALPHA);
        return b;
    }
    float sc = xs_max3(m.sheen_color);
    float ps = sc > 0.0 ? min(sc * xs_sheen_albedo(wo_z, m.sheen_roughness), 1.0) : 0.0;
    if (xs_pick_layer(ps, u)) {
        b.kind = XS_BSDF_SHEEN;
        b.base = m.sheen_color / ps;
        b.alpha = max(m.sheen_roughness * m.sheen_roughness, XS_SHEEN_MIN_ALPHA);
        return b;
    }
    float metallic = m.metallic;
    float transmission = m.transmission;
    float roughness = m.roughness;
    if (u < metallic) {
        b.kind = XS_BSDF_METAL;
        b.alpha = max(b.alpha, XS_MIN_ALPHA);
    } else if ((u - metallic) < (1.0 - metallic) * transmission) {
        b.kind = XS_BSDF_GLASS;
        b.smooth_glass = roughness < XS_GLASS_SMOOTH_ROUGHNESS;
        b.alpha = max(b.alpha, XS_MIN_ALPHA);
        b.thin = m.thin;
        if (b.thin) {
            /* a thin wall has the outside medium on both sides */
            b.eta_o = 1.0;
            b.eta_i = m.ior;
        }
    } else {
        b.kind = XS_BSDF_OPAQUE;
        /* an opaque surface is seen from the outside medium on both sides */
        b.eta_o = 1.0;
        b.eta_i = m.ior;
        b.alpha = max(b.alpha, XS_MIN_ALPHA);
    }
    return b;
}

/** True when every direction this component returns is a delta (no light sampling). */
bool xs_bsdf_is_delta(xs_bsdf b)
{
    return b.kind == XS_BSDF_GLASS && b.smooth_glass;
}

/** Exact unpolarised Fresnel reflectance for cos_i > 0 on the incident side and
 *  eta = eta_transmitted / eta_incident; 1 under total internal reflection. */
float xs_fresnel_dielectric(float cos_i, float eta)
{
    if (abs(eta - 1.0) < XS_IOR_MATCH_EPS)
        return 0.0;
    cos_i = clamp(cos_i, 0.0, 1.0);
    float sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    if (sin2_t >= 1.0)
        return 1.0;
    float cos_t = sqrt(1.0 - sin2_t);
    float rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    float rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    return 0.5 * (rs * rs + rp * rp);
}

vec3 xs_fresnel_schlick(vec3 f0, float cos_i)
{
    float m = clamp(1.0 - cos_i, 0.0, 1.0);
    float m2 = m * m;
    return f0 + (1.0 - f0) * (m2 * m2 * m);
}

/** GGX normal distribution D(h), h.z > 0 (Walter et al. 2007 Eq. 33). */
float xs_ggx_d(vec3 h, float alpha)
{
    float a2 = alpha * alpha;
    float c2 = h.z * h.z;
    float d = c2 * (a2 - 1.0) + 1.0;
    return a2 / (XS_PI * d * d);
}

/** Smith Lambda of GGX (Heitz 2014 Eq. 72). */
float xs_ggx_lambda(vec3 w, float alpha)
{
    float c2 = w.z * w.z;
    float s2 = max(0.0, 1.0 - c2);
    if (c2 <= 0.0)
        return 1e30;
    float tan2 = s2 / c2;
    return 0.5 * (-1.0 + sqrt(1.0 + alpha * alpha * tan2));
}

float xs_ggx_g1(vec3 w, float alpha)
{
    return 1.0 / (1.0 + xs_ggx_lambda(w, alpha));
}

/** Height-correlated masking-shadowing (Heitz 2014 Eq. 99). */
float xs_ggx_g2(vec3 wo, vec3 wi, float alpha)
{
    return 1.0 / (1.0 + xs_ggx_lambda(wo, alpha) + xs_ggx_lambda(wi, alpha));
}

/** Pdf of a visible normal h seen from wo (Heitz 2018 Eq. 3): G1(wo) max(0, wo.h) D(h) / wo.z. */
float xs_ggx_vndf_pdf(vec3 wo, vec3 h, float alpha)
{
    return xs_ggx_g1(wo, alpha) * max(0.0, dot(wo, h)) * xs_ggx_d(h, alpha) / wo.z;
}

/** Samples a visible normal (Heitz 2018, §3-4: stretch, sample the projected hemisphere, unstretch). */
vec3 xs_ggx_sample_vndf(vec3 wo, float alpha, vec2 u)
{
    vec3 v = normalize(vec3(alpha * wo.x, alpha * wo.y, wo.z));
    float len2 = v.x * v.x + v.y * v.y;
    vec3 t1 = len2 > 0.0 ? vec3(-v.y, v.x, 0.0) * inversesqrt(len2) : vec3(1.0, 0.0, 0.0);
    vec3 t2 = cross(v, t1);
    float r = sqrt(u.x);
    float phi = XS_TWO_PI * u.y;
    float a = r * cos(phi);
    float b = r * sin(phi);
    float s = 0.5 * (1.0 + v.z);
    b = (1.0 - s) * sqrt(max(0.0, 1.0 - a * a)) + s * b;
    vec3 nh = a * t1 + b * t2 + sqrt(max(0.0, 1.0 - a * a - b * b)) * v;
    return normalize(vec3(alpha * nh.x, alpha * nh.y, max(1e-7, nh.z)));
}

/** KHR_materials_specular on the dielectric Fresnel f (exact, at the material IOR):
 *  min(f specularColor, 1) specular, which is exactly f for the plain glTF values (1, 1); total
 *  internal reflection (f = 1) stays total. */
vec3 xs_spec_fresnel(xs_bsdf b, float f)
{
    return f >= 1.0 ? vec3(1.0) : min(f * b.spec_color, vec3(1.0)) * b.specular;
}

/** Glass's scalar reflection probability (xs_spec_fresnel with the colour's maximum) and its
 *  reflection tint (the colour over its maximum: 1 for plain glTF). */
float xs_glass_fresnel(xs_bsdf b, float f, out vec3 tint)
{
    float cmax = xs_max3(b.spec_color);
    tint = cmax > 0.0 ? b.spec_color / cmax : vec3(1.0);
    return f >= 1.0 ? 1.0 : min(f * cmax, 1.0) * b.specular;
}

/* ---- KHR_materials_sheen: Charlie distribution (Estevez and Kulla 2017, "Production Friendly
 * Microfacet Sheen BRDF", Eq. 2) with their fitted masking (Table 1, interpolated in
 * (1 - alpha)^2 as the glTF Sample Viewer does) ---- */
float xs_sheen_d(float cos_h, float alpha)
{
    float sin2 = max(0.0, 1.0 - cos_h * cos_h);
    float inv = 1.0 / alpha;
    return (2.0 + inv) * pow(sin2, 0.5 * inv) / XS_TWO_PI;
}

float xs_sheen_l(float x, float alpha)
{
    float t = (1.0 - alpha) * (1.0 - alpha);
    float a = mix(21.5473, 25.3245, t);
    float b = mix(3.82987, 3.32435, t);
    float c = mix(0.19823, 0.16801, t);
    float d = mix(-1.97760, -1.27393, t);
    float e = mix(-4.32054, -4.85967, t);
    return a / (1.0 + b * pow(max(x, 0.0), c)) + d * x + e;
}

float xs_sheen_lambda(float cos_t, float alpha)
{
    return cos_t < 0.5 ? exp(xs_sheen_l(cos_t, alpha))
                       : exp(2.0 * xs_sheen_l(0.5, alpha) - xs_sheen_l(1.0 - cos_t, alpha));
}

/** The sheen lobe f cos for wo, wi above the surface (without sheen colour). */
float xs_sheen_fcos(vec3 wo, vec3 wi, float alpha)
{
    vec3 h = normalize(wo + wi);
    float v = 1.0 / ((1.0 + xs_sheen_lambda(wo.z, alpha) + xs_sheen_lambda(wi.z, alpha)) *
                     (4.0 * wo.z * wi.z));
    return xs_sheen_d(h.z, alpha) * clamp(v, 0.0, 1.0) * wi.z;
}

/* Directional albedo E of xs_sheen_fcos: rows sheenRoughness = 0, 1/7, .., 1; columns
 * cos(theta_o) = (k/15)^2, k = 0..15 (k = 0 at 1e-3). Integrated numerically here (midpoint
 * rule, 192 x 96 directions per entry, alpha clamped to XS_SHEEN_MIN_ALPHA). Values above 1 at
 * grazing angles are the fitted masking's. */
#define XS_SHEEN_E_COLS 16
#define XS_SHEEN_E_ROWS 8
const float XS_SHEEN_E[XS_SHEEN_E_ROWS * XS_SHEEN_E_COLS] = float[](
    1.390, 1.411, 1.267, 1.012, 0.719, 0.445, 0.235, 0.106, 0.040, 0.012, 0.002, 0.000, 0.000, 0.000, 0.000, 0.000,
    1.130, 1.168, 1.088, 0.919, 0.712, 0.503, 0.321, 0.188, 0.099, 0.045, 0.018, 0.005, 0.001, 0.000, 0.000, 0.000,
    0.750, 0.795, 0.779, 0.708, 0.614, 0.509, 0.404, 0.308, 0.227, 0.160, 0.106, 0.065, 0.036, 0.017, 0.006, 0.001,
    0.646, 0.694, 0.694, 0.652, 0.590, 0.519, 0.444, 0.369, 0.301, 0.239, 0.183, 0.135, 0.095, 0.062, 0.034, 0.013,
    0.639, 0.689, 0.697, 0.665, 0.617, 0.560, 0.497, 0.432, 0.369, 0.309, 0.253, 0.202, 0.157, 0.117, 0.080, 0.046,
    0.670, 0.721, 0.733, 0.706, 0.663, 0.612, 0.556, 0.497, 0.435, 0.375, 0.317, 0.263, 0.215, 0.171, 0.130, 0.090,
    0.703, 0.754, 0.766, 0.740, 0.701, 0.653, 0.601, 0.545, 0.486, 0.425, 0.367, 0.312, 0.262, 0.217, 0.174, 0.132,
    0.701, 0.750, 0.762, 0.738, 0.701, 0.657, 0.609, 0.557, 0.502, 0.445, 0.389, 0.336, 0.289, 0.245, 0.204, 0.164);

/** E(cos_o, sheenRoughness), bilinear in the table's coordinates. */
float xs_sheen_albedo(float cos_o, float roughness)
{
    float x = sqrt(clamp(cos_o, 0.0, 1.0)) * float(XS_SHEEN_E_COLS - 1);
    float y = clamp(roughness, 0.0, 1.0) * float(XS_SHEEN_E_ROWS - 1);
    int x0 = min(int(x), XS_SHEEN_E_COLS - 2), y0 = min(int(y), XS_SHEEN_E_ROWS - 2);
    float fx = x - float(x0), fy = y - float(y0);
    int i = y0 * XS_SHEEN_E_COLS + x0;
    float top = mix(XS_SHEEN_E[i], XS_SHEEN_E[i + 1], fx);
    float bottom = mix(XS_SHEEN_E[i + XS_SHEEN_E_COLS], XS_SHEEN_E[i + XS_SHEEN_E_COLS + 1], fx);
    return mix(top, bottom, fy);
}

/**
 * What a smooth thin wall lets through at cosine cos_o (a shadow ray passing it straight,
 * xs_path.glsl): the expected weight of a path's delta transmission there (wi = -wo), i.e.
 * the pick probability of the glass component in xs_bsdf_make ((1 - c Fc)(1 - s)(1 -
 * metallic) transmission) times xs_bsdf_sample_delta's transmission (1 - F) base. 0 where the
 * point is not smooth thin glass (a volume refracts, so no straight line passes it; rough or
 * metal: no delta transmission).
 */
vec3 xs_glass_pass(xs_bsdf_in m, float cos_o)
{
    if (!m.thin || !(m.transmission > 0.0) || m.metallic >= 1.0 ||
        m.roughness >= XS_GLASS_SMOOTH_ROUGHNESS)
        return vec3(0.0);
    float w = (1.0 - m.metallic) * m.transmission;
    if (m.clearcoat > 0.0)
        w *= 1.0 - m.clearcoat * xs_fresnel_dielectric(cos_o, XS_CLEARCOAT_IOR);
    float sc = xs_max3(m.sheen_color);
    if (sc > 0.0)
        w *= 1.0 - min(sc * xs_sheen_albedo(cos_o, m.sheen_roughness), 1.0);
    xs_bsdf b;
    b.spec_color = m.spec_color;
    b.specular = m.specular;
    vec3 tint;
    float f = xs_glass_fresnel(b, xs_fresnel_dielectric(cos_o, m.ior), tint);
    return m.base * (w * (1.0 - f));
}

/** Probability that the opaque component samples its specular lobe. */
float xs_opaque_spec_prob(xs_bsdf b, vec3 wo)
{
    float f = xs_max3(xs_spec_fresnel(b, xs_fresnel_dielectric(wo.z, b.eta_i / b.eta_o)));
    float d = (1.0 - f) * xs_luminance(b.base);
    if (f <= 0.0)
        return 0.0;
    if (d <= 0.0)
        return 1.0;
    return clamp(f / (f + d), XS_MIN_LOBE_PROB, 1.0 - XS_MIN_LOBE_PROB);
}

/** Metal, coat and opaque dielectric (wi above the surface). */
vec3 xs_reflective_eval(xs_bsdf b, vec3 wo, vec3 wi, out float pdf)
{
    vec3 h = normalize(wo + wi);
    float d = xs_ggx_d(h, b.alpha);
    float g2 = xs_ggx_g2(wo, wi, b.alpha);
    float spec_pdf = xs_ggx_vndf_pdf(wo, h, b.alpha) / (4.0 * dot(wo, h));
    /* specular f cos = F D G2 / (4 wo.z) (Walter et al. 2007 Eq. 20 times wi.z) */
    float spec = d * g2 / (4.0 * wo.z);
    if (b.kind == XS_BSDF_METAL) {
        pdf = spec_pdf;
        return xs_fresnel_schlick(b.base, dot(wo, h)) * spec;
    }
    vec3 f = xs_spec_fresnel(b, xs_fresnel_dielectric(dot(wo, h), b.eta_i / b.eta_o));
    float ps = xs_opaque_spec_prob(b, wo);
    pdf = ps * spec_pdf + (1.0 - ps) * wi.z * XS_INV_PI;
    return f * spec + (1.0 - xs_max3(f)) * b.base * (wi.z * XS_INV_PI);
}

/** Glass reflection (wi.z > 0), and a thin wall's transmission: the same GGX lobe mirrored
 *  through the surface (wi.z < 0), weighted 1 - F and tinted by the base colour. */
vec3 xs_glass_reflect_eval(xs_bsdf b, vec3 wo, vec3 wi, out float pdf)
{
    bool through = wi.z < 0.0;
    vec3 wr = vec3(wi.xy, abs(wi.z));
    vec3 h = normalize(wo + wr);
    vec3 tint;
    float f = xs_glass_fresnel(b, xs_fresnel_dielectric(dot(wo, h), b.eta_i / b.eta_o), tint);
    float w = through ? 1.0 - f : f;
    float d = xs_ggx_d(h, b.alpha);
    pdf = w * xs_ggx_vndf_pdf(wo, h, b.alpha) / (4.0 * dot(wo, h));
    return (through ? b.base : tint) * (w * d * xs_ggx_g2(wo, wr, b.alpha) / (4.0 * wo.z));
}

/** Rough refraction into or out of a volume (wi.z < 0). */
vec3 xs_glass_refract_eval(xs_bsdf b, vec3 wo, vec3 wi, out float pdf)
{
    /* generalised half vector (Walter et al. 2007 Eq. 16), towards +z */
    vec3 h = -(b.eta_i * wi + b.eta_o * wo);
    float hl = length(h);
    if (hl <= 0.0)
        return vec3(0.0);
    h /= hl;
    if (h.z < 0.0)
        h = -h;
    float wo_h = dot(wo, h);
    float wi_h = dot(wi, h);
    if (wo_h <= 0.0 || wi_h >= 0.0)
        return vec3(0.0);
    vec3 tint;
    float f = xs_glass_fresnel(b, xs_fresnel_dielectric(wo_h, b.eta_i / b.eta_o), tint);
    float denom = b.eta_o * wo_h + b.eta_i * wi_h;
    denom *= denom;
    if (denom <= 0.0)
        return vec3(0.0);
    float d = xs_ggx_d(h, b.alpha);
    float g2 = xs_ggx_g2(wo, wi, b.alpha);
    /* Walter Eq. 17: |dh/dwi| = eta_i^2 |wi.h| / (eta_o wo.h + eta_i wi.h)^2 */
    pdf = (1.0 - f) * xs_ggx_vndf_pdf(wo, h, b.alpha) * b.eta_i * b.eta_i * abs(wi_h) / denom;
    /* Walter Eq. 21 (radiance form, light flows from wi's side to wo's), times |wi.z| */
    float ft = abs(wi_h) * wo_h * b.eta_o * b.eta_o * (1.0 - f) * g2 * d / (wo.z * denom);
    return b.base * ft;
}

/** f * |cos(theta_i)| and the solid-angle pdf of sampling wi with xs_bsdf_sample. Delta lobes
 *  (smooth glass) return 0. */
vec3 xs_bsdf_eval(xs_bsdf b, vec3 wo, vec3 wi, out float pdf)
{
    pdf = 0.0;
    if (wo.z < XS_COS_EPS || abs(wi.z) < XS_COS_EPS || xs_bsdf_is_delta(b))
        return vec3(0.0);
    if (b.kind == XS_BSDF_SHEEN) {
        if (wi.z <= 0.0)
            return vec3(0.0);
        pdf = wi.z * XS_INV_PI;
        return b.base * xs_sheen_fcos(wo, wi, b.alpha);
    }
    if (b.kind != XS_BSDF_GLASS)
        return wi.z > 0.0 ? xs_reflective_eval(b, wo, wi, pdf) : vec3(0.0);
    if (wi.z > 0.0 || b.thin)
        return xs_glass_reflect_eval(b, wo, wi, pdf);
    return xs_glass_refract_eval(b, wo, wi, pdf);
}

/** Smooth glass: mirror reflection, refraction (volume) or straight through (thin wall). */
bool xs_bsdf_sample_delta(xs_bsdf b, vec3 wo, float u, out vec3 wi, out vec3 weight,
                          out float pdf)
{
    float eta = b.eta_i / b.eta_o;
    vec3 tint;
    float f = xs_glass_fresnel(b, xs_fresnel_dielectric(wo.z, eta), tint);
    if (u < f) {
        wi = vec3(-wo.x, -wo.y, wo.z);
        weight = tint;
        pdf = f;
    } else if (b.thin) {
        wi = -wo;
        weight = b.base;
        pdf = 1.0 - f;
    } else {
        wi = refract(-wo, vec3(0.0, 0.0, 1.0), 1.0 / eta);
        if (wi.z >= 0.0)
            return false;
        /* radiance scales by (eta_o / eta_i)^2 across the interface (Veach 1997 §5.2) */
        weight = b.base * (b.eta_o * b.eta_o) / (b.eta_i * b.eta_i);
        pdf = 1.0 - f;
    }
    return pdf > 0.0;
}

/**
 * Samples wi. Returns false when no direction was produced. weight = f |cos| / pdf; pdf is
 * the solid-angle pdf (for delta lobes: the discrete probability of the chosen lobe, and
 * delta = true).
 */
bool xs_bsdf_sample(xs_bsdf b, vec3 wo, vec3 u, out vec3 wi, out vec3 weight, out float pdf,
                    out bool delta)
{
    wi = vec3(0.0, 0.0, 1.0);
    weight = vec3(0.0);
    pdf = 0.0;
    delta = false;
    if (wo.z < XS_COS_EPS)
        return false;

    if (xs_bsdf_is_delta(b)) {
        delta = true;
        return xs_bsdf_sample_delta(b, wo, u.z, wi, weight, pdf);
    }

    if (b.kind == XS_BSDF_METAL) {
        vec3 h = xs_ggx_sample_vndf(wo, b.alpha, u.xy);
        wi = reflect(-wo, h);
    } else if (b.kind == XS_BSDF_SHEEN) {
        wi = xs_sample_cosine_hemisphere(u.xy);
    } else if (b.kind == XS_BSDF_OPAQUE) {
        if (u.z < xs_opaque_spec_prob(b, wo)) {
            vec3 h = xs_ggx_sample_vndf(wo, b.alpha, u.xy);
            wi = reflect(-wo, h);
        } else {
            wi = xs_sample_cosine_hemisphere(u.xy);
        }
    } else {
        vec3 h = xs_ggx_sample_vndf(wo, b.alpha, u.xy);
        vec3 tint;
        float f = xs_glass_fresnel(b, xs_fresnel_dielectric(dot(wo, h), b.eta_i / b.eta_o), tint);
        if (u.z < f)
            wi = reflect(-wo, h);
        else if (b.thin)
            wi = reflect(-wo, h) * vec3(1.0, 1.0, -1.0); /* mirrored through the wall */
        else
            wi = refract(-wo, h, b.eta_o / b.eta_i);
    }
    if (dot(wi, wi) < 0.5)
        return false; /* refract() returned 0: total internal reflection on this normal */
    vec3 fc = xs_bsdf_eval(b, wo, wi, pdf);
    if (!(pdf > 0.0) || !xs_finite(fc))
        return false;
    weight = fc / pdf;
    return xs_finite(weight);
}

#endif
