// SPDX-License-Identifier: MIT
/**
 * @file xs_bsdf.glsl
 * @brief glTF 2.0 metal/rough + KHR_materials_transmission/ior BSDF: evaluation, sampling, pdf.
 *
 * The glTF material is a mix of three components with weights that sum to 1 (glTF 2.0
 * Appendix B; KHR_materials_transmission):
 *   metal       weight m            F_schlick(base) * GGX specular
 *   opaque      (1-m)(1-tr)         F * GGX specular + (1 - F) * base / pi      (fresnel_mix)
 *   glass       (1-m) tr            F * GGX reflection + (1 - F) * base * GGX transmission
 * The path tracer picks ONE component per surface vertex with probability equal to its weight
 * (stochastic mixing, unbiased: the weight cancels against the probability) and uses that
 * component for both light sampling and BSDF sampling, so MIS stays consistent.
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

/* Smallest GGX alpha of reflective lobes: keeps D finite (D <= 1/(pi alpha^2) ~ 3e5). */
#define XS_MIN_ALPHA 1e-3
/* Glass with perceptual roughness below this is treated as perfectly smooth (delta lobes). */
#define XS_GLASS_SMOOTH_ROUGHNESS 0.05
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
    vec3 base;
    float alpha; /* GGX alpha = roughness^2 */
    float eta_o; /* IOR on the side of wo */
    float eta_i; /* IOR on the other side (for glass) */
    bool smooth_glass;
};

/** Picks the component for one vertex (u uniform in [0,1)), see the file comment. */
xs_bsdf xs_bsdf_make(vec3 base, float metallic, float roughness, float transmission, float ior,
                     bool outside, float u)
{
    xs_bsdf b;
    b.base = base;
    b.alpha = roughness * roughness;
    b.eta_o = outside ? 1.0 : ior;
    b.eta_i = outside ? ior : 1.0;
    b.smooth_glass = false;
    if (u < metallic) {
        b.kind = XS_BSDF_METAL;
        b.alpha = max(b.alpha, XS_MIN_ALPHA);
    } else if ((u - metallic) < (1.0 - metallic) * transmission) {
        b.kind = XS_BSDF_GLASS;
        b.smooth_glass = roughness < XS_GLASS_SMOOTH_ROUGHNESS;
        b.alpha = max(b.alpha, XS_MIN_ALPHA);
    } else {
        b.kind = XS_BSDF_OPAQUE;
        /* an opaque surface is seen from the outside medium on both sides */
        b.eta_o = 1.0;
        b.eta_i = ior;
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

/** Probability that the opaque component samples its specular lobe. */
float xs_opaque_spec_prob(xs_bsdf b, vec3 wo)
{
    float f = xs_fresnel_dielectric(wo.z, b.eta_i / b.eta_o);
    float d = (1.0 - f) * xs_luminance(b.base);
    if (f <= 0.0)
        return 0.0;
    if (d <= 0.0)
        return 1.0;
    return clamp(f / (f + d), XS_MIN_LOBE_PROB, 1.0 - XS_MIN_LOBE_PROB);
}

/** f * |cos(theta_i)| and the solid-angle pdf of sampling wi with xs_bsdf_sample. Delta lobes
 *  (smooth glass) return 0. */
vec3 xs_bsdf_eval(xs_bsdf b, vec3 wo, vec3 wi, out float pdf)
{
    pdf = 0.0;
    if (wo.z < XS_COS_EPS || abs(wi.z) < XS_COS_EPS || xs_bsdf_is_delta(b))
        return vec3(0.0);

    if (b.kind != XS_BSDF_GLASS) {
        if (wi.z <= 0.0)
            return vec3(0.0);
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
        float f = xs_fresnel_dielectric(dot(wo, h), b.eta_i / b.eta_o);
        float ps = xs_opaque_spec_prob(b, wo);
        pdf = ps * spec_pdf + (1.0 - ps) * wi.z * XS_INV_PI;
        return vec3(f * spec) + (1.0 - f) * b.base * (wi.z * XS_INV_PI);
    }

    /* rough glass */
    if (wi.z > 0.0) {
        vec3 h = normalize(wo + wi);
        float f = xs_fresnel_dielectric(dot(wo, h), b.eta_i / b.eta_o);
        float d = xs_ggx_d(h, b.alpha);
        pdf = f * xs_ggx_vndf_pdf(wo, h, b.alpha) / (4.0 * dot(wo, h));
        return vec3(f * d * xs_ggx_g2(wo, wi, b.alpha) / (4.0 * wo.z));
    }
    /* transmission: generalised half vector (Walter et al. 2007 Eq. 16), towards +z */
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
    float f = xs_fresnel_dielectric(wo_h, b.eta_i / b.eta_o);
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
        float eta = b.eta_i / b.eta_o;
        float f = xs_fresnel_dielectric(wo.z, eta);
        if (u.z < f) {
            wi = vec3(-wo.x, -wo.y, wo.z);
            weight = vec3(1.0);
            pdf = f;
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

    if (b.kind == XS_BSDF_METAL) {
        vec3 h = xs_ggx_sample_vndf(wo, b.alpha, u.xy);
        wi = reflect(-wo, h);
    } else if (b.kind == XS_BSDF_OPAQUE) {
        if (u.z < xs_opaque_spec_prob(b, wo)) {
            vec3 h = xs_ggx_sample_vndf(wo, b.alpha, u.xy);
            wi = reflect(-wo, h);
        } else {
            wi = xs_sample_cosine_hemisphere(u.xy);
        }
    } else {
        vec3 h = xs_ggx_sample_vndf(wo, b.alpha, u.xy);
        float f = xs_fresnel_dielectric(dot(wo, h), b.eta_i / b.eta_o);
        if (u.z < f)
            wi = reflect(-wo, h);
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
