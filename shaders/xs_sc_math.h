// SPDX-License-Identifier: MIT
/**
 * @file xs_sc_math.h
 * @brief The sample cache's scalar formulas, ONE source compiled as GLSL and as C: the first-hit
 *        packing of Listing 1, the slope Delta of Eq. 1, the edge test of Eq. 2 and the
 *        importance bucket of §3.5 (seed 000).
 *
 * Written in the common subset of C11 and GLSL 4.60 (scalars, ternaries, the XS_SCM_* math
 * macros), so the C build (unit tests, synthetic neighbourhoods) runs the shaders' own code;
 * sc_selftest.comp checks on the device that both builds agree (packing bit for bit, Eq. 1
 * within 1e-5 t; bit for bit on lavapipe).
 *
 * Listing 1 and its precision. The listing computes b = uint(round(clamp(bary, 0, 1) *
 * float(0xFFFFFFFF))) and stores (b & 0xFFFFFFFF) | (mat & 0xFF) << 24 in fh.x and
 * b.y | (mat & 0xFF00) << 16 in fh.y. Taken literally the material bytes are OR-ed over the top
 * 8 bits of a 32-bit barycentric (corrupting it), and float(0xFFFFFFFF) rounds to 2^32 so a
 * barycentric of 1 overflows. We keep the listing's layout (material bits 0..7 in the top byte
 * of x, bits 8..15 in the top byte of y: 16-bit material index; prim in z, instance in w) and
 * quantise each barycentric to the 24 bits left below: q = min(floor(b * 2^24 + 0.5), 2^24-1),
 * decoded as q * 2^-24 (both exact in float32). Error <= 2^-25, and 2^-24 for b > 1 - 2^-25;
 * a position error of at most 2^-24 of a triangle edge. fh is stored as uvec4 (the listing's
 * asfloat() bits) so no float NaN canonicalisation can touch it.
 */
#ifndef XS_SC_MATH_H
#define XS_SC_MATH_H

#include "xs_samplecache.h"

#ifdef XRSC_GLSL
#define XS_SCM_FN
#define XS_SCM_BOOL bool
#define XS_SCM_F2U(x) uint(x)
#define XS_SCM_U2F(x) float(x)
#define XS_SCM_FLOOR(x) floor(x)
#define XS_SCM_LOG(x) log(x)
#define XS_SCM_SQRT(x) sqrt(x)
#define XS_SCM_SIN(x) sin(x)
#define XS_SCM_COS(x) cos(x)
#define XS_SCM_FABS(x) abs(x)
#else
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#define XS_SCM_FN static inline
#define XS_SCM_BOOL bool
#define XS_SCM_F2U(x) ((uint32_t)(x))
#define XS_SCM_U2F(x) ((float)(x))
#define XS_SCM_FLOOR(x) floorf(x)
#define XS_SCM_LOG(x) logf(x)
#define XS_SCM_SQRT(x) sqrtf(x)
#define XS_SCM_SIN(x) sinf(x)
#define XS_SCM_COS(x) cosf(x)
#define XS_SCM_FABS(x) fabsf(x)
#endif

/* Listing 1 with 24-bit barycentrics (see the file comment). */
#define XS_SC_BARY_MAX 0xFFFFFFu
#define XS_SC_BARY_SCALE 16777216.0f                /* 2^24 */
#define XS_SC_BARY_INV_SCALE 5.9604644775390625e-8f /* 2^-24 */
#define XS_SC_MAT_BYTE 0xFFu
#define XS_SC_MAT_SHIFT 24u
#define XS_SC_MAX_MATERIALS 65536u

/** One barycentric quantised to 24 bits, one material byte on top (Listing 1, lines 3-5). */
XS_SCM_FN xs_uint xs_sc_pack_bary(xs_float b, xs_uint mat_byte)
{
    xs_float c = b > 0.0f ? (b < 1.0f ? b : 1.0f) : 0.0f; /* also maps NaN to 0 */
    xs_uint q = XS_SCM_F2U(XS_SCM_FLOOR(c * XS_SC_BARY_SCALE + 0.5f));
    q = q < XS_SC_BARY_MAX ? q : XS_SC_BARY_MAX;
    return q | ((mat_byte & XS_SC_MAT_BYTE) << XS_SC_MAT_SHIFT);
}

/** Word x of Listing 1: barycentric u and material bits 0..7. */
XS_SCM_FN xs_uint xs_sc_pack_x(xs_float u, xs_uint material)
{
    return xs_sc_pack_bary(u, material);
}

/** Word y of Listing 1: barycentric v and material bits 8..15. */
XS_SCM_FN xs_uint xs_sc_pack_y(xs_float v, xs_uint material)
{
    return xs_sc_pack_bary(v, material >> 8u);
}

/** The barycentric of word x or y. */
XS_SCM_FN xs_float xs_sc_unpack_bary(xs_uint word)
{
    return XS_SCM_U2F(word & XS_SC_BARY_MAX) * XS_SC_BARY_INV_SCALE;
}

/** The 16-bit material index of words x and y. */
XS_SCM_FN xs_uint xs_sc_unpack_material(xs_uint x, xs_uint y)
{
    return (x >> XS_SC_MAT_SHIFT) | ((y >> XS_SC_MAT_SHIFT) << 8u);
}

/**
 * Eq. 1: the expected distance extent within a pixel frustum, Delta_n = t |1 - cos(theta) /
 * cos(theta - phi)| (App. A), theta the angle between the normal and the direction to the
 * camera (cos_theta = |n . w_o|, clamped to [0, 1]), phi the angle subtended by the pixel's
 * diagonal. theta - phi < pi/2 keeps the denominator positive, so Delta is bounded.
 */
XS_SCM_FN xs_float xs_sc_slope(xs_float t, xs_float cos_theta, xs_float phi)
{
    /* cos(theta - phi) = cos(theta) cos(phi) + sin(theta) sin(phi): no acos (whose accuracy
     * on GPUs is loose, and which would make the device and C builds disagree by ~1e-3 t) */
    xs_float c = cos_theta > 0.0f ? (cos_theta < 1.0f ? cos_theta : 1.0f) : 0.0f;
    xs_float s = XS_SCM_SQRT(1.0f - c * c);
    return t * XS_SCM_FABS(1.0f - c / (c * XS_SCM_COS(phi) + s * XS_SCM_SIN(phi)));
}

/**
 * Eq. 2: true when the distances of a 3x3 neighbourhood are consistent with one flat smooth
 * surface, t_max < (1 + eps1)(t_min + 2 Delta_n), Delta_n the slope of the closest sample
 * (App. A: 2 Delta covers rays up to 2 phi apart). False means "likely an edge: trace all".
 */
XS_SCM_FN XS_SCM_BOOL xs_sc_consistent(xs_float t_min, xs_float t_max, xs_float delta,
                                       xs_float eps1)
{
    return t_max < (1.0f + eps1) * (t_min + 2.0f * delta);
}

/** §3.5: importance of a sample with count c, w = 1 / (1 + c). */
XS_SCM_FN xs_float xs_sc_importance(xs_float c)
{
    return 1.0f / (1.0f + c);
}

/* Variance-guided shading (XS_SC_SHADE_ADAPTIVE_VARIANCE). A pixel's visible surface samples
 * see nearly the same radiance, so the spread of their means L_s estimates the variance of one
 * observation: each L_s averages c_s of them, Var(L_s) = sigma^2 / c_s, so c_s (l_s - m)^2
 * has expectation sigma^2 (l = luminance, m the count-weighted mean). Relative to m^2, as
 * relMSE weighs errors. The estimate is shrunk towards XS_SC_VAR_PRIOR (the relative
 * variance of a single 1-sample estimate in a path-traced scene, order 1) as if the prior were
 * XS_SC_VAR_PRIOR_WEIGHT more degrees of freedom: a pixel whose few samples happen to agree
 * (all dark: no light path found yet) is not taken for converged and left unshaded, and a pixel
 * with fewer than two observed samples gets the prior. XS_SC_VAR_FLOOR keeps every importance
 * > 0 (log buckets). */
#define XS_SC_VAR_PRIOR 1.0f
#define XS_SC_VAR_PRIOR_WEIGHT 1.0f
#define XS_SC_VAR_FLOOR 1e-4f
#define XS_SC_VAR_MEAN_MIN 1e-4f

/** The relative variance of one observation from a pixel's sums over its k observed samples:
 *  sc = sum c_s, scl = sum c_s l_s, scl2 = sum c_s l_s^2. */
XS_SCM_FN xs_float xs_sc_pixel_variance(xs_float k, xs_float sc, xs_float scl, xs_float scl2)
{
    xs_float rel = 0.0f, dof = 0.0f;
    if (k >= 2.0f && sc > 0.0f) {
        xs_float m = scl / sc;
        xs_float spread = scl2 - sc * m * m; /* sum c_s (l_s - m)^2 */
        spread = spread > 0.0f ? spread : 0.0f;
        xs_float mm = m * m > XS_SC_VAR_MEAN_MIN ? m * m : XS_SC_VAR_MEAN_MIN;
        rel = spread / mm;
        dof = k - 1.0f;
    }
    return (rel + XS_SC_VAR_PRIOR * XS_SC_VAR_PRIOR_WEIGHT) / (dof + XS_SC_VAR_PRIOR_WEIGHT);
}

/** Variance-guided importance of a sample with count c in a pixel of relative variance v:
 *  the relative variance of its mean after one more observation, (v + floor) / (1 + c). */
XS_SCM_FN xs_float xs_sc_variance_importance(xs_float v, xs_float c)
{
    return (v + XS_SC_VAR_FLOOR) / (1.0f + c);
}

/**
 * §3.5: bucket 0..XS_SC_BUCKETS-1 of importance w among XS_SC_BUCKETS logarithmically sized
 * buckets spanning [w_min, w_max] (the previous frame's bounds); the top bucket holds the most
 * important samples. Out-of-range w clamp to the end buckets; an empty or single-valued range
 * puts everything into the top bucket.
 */
XS_SCM_FN xs_uint xs_sc_bucket(xs_float w, xs_float w_min, xs_float w_max)
{
    if (!(w_max > w_min) || !(w_min > 0.0f))
        return XS_SC_BUCKETS - 1u;
    xs_float x = XS_SCM_LOG(w / w_min) / XS_SCM_LOG(w_max / w_min);
    xs_float b = XS_SCM_FLOOR(x * XS_SCM_U2F(XS_SC_BUCKETS));
    xs_float top = XS_SCM_U2F(XS_SC_BUCKETS - 1u);
    b = b > 0.0f ? (b < top ? b : top) : 0.0f;
    return XS_SCM_F2U(b);
}

/** App. C: the smallest temporal blend factor of a surface with GGX alpha a_ggx. */
XS_SCM_FN xs_float xs_sc_alpha_min(xs_float a_ggx)
{
    return (1.0f - a_ggx) * XS_SC_ALPHA_MIN_SMOOTH + a_ggx * XS_SC_ALPHA_MIN_ROUGH;
}

/**
 * App. C's clamp of a material: xs_sc_alpha_min of its GGX alpha (roughness^2) scaled by the
 * weight of its view-dependent lobes, metallic + (1 - metallic) transmission (1 for metal and
 * glass, 0 for diffuse surfaces: no clamp). The hash cache reuses it to decide which surfaces
 * it does not serve (xs_hashcache.h: XS_HC_VIEW_DEP_ALPHA_MIN).
 */
XS_SCM_FN xs_float xs_sc_alpha_min_material(xs_float metallic, xs_float transmission,
                                            xs_float roughness)
{
    xs_float view_dep = metallic + (1.0f - metallic) * transmission;
    return view_dep * xs_sc_alpha_min(roughness * roughness);
}

/**
 * The share of App. C's clamp that applies when the view of a sample turned by angle_rad since
 * the previous frame, for a pixel diagonal of phi_rad: angle / (XS_SC_VIEW_MOTION_PIXELS phi)
 * clamped to [0, 1] (1 without a pixel size). Scales the transmission's part of the clamp
 * (xs_sc_alpha_min_glass).
 */
XS_SCM_FN xs_float xs_sc_view_motion(xs_float angle_rad, xs_float phi_rad)
{
    if (!(phi_rad > 0.0f))
        return 1.0f;
    xs_float x = angle_rad / (XS_SC_VIEW_MOTION_PIXELS * phi_rad);
    return x < 1.0f ? (x > 0.0f ? x : 0.0f) : 1.0f;
}

/**
 * The clamp sc_shade.rgen applies: xs_sc_alpha_min_material with the transmission's weight
 * scaled by view_motion (xs_sc_view_motion; 1 = App. C as it is). Glass only: metal keeps App.
 * C's clamp whatever the view does, so images of scenes without transmission are unchanged
 * (the same argument would hold for metal; not applied there yet).
 */
XS_SCM_FN xs_float xs_sc_alpha_min_glass(xs_float metallic, xs_float transmission,
                                         xs_float roughness, xs_float view_motion)
{
    xs_float view_dep = metallic + (1.0f - metallic) * transmission * view_motion;
    return view_dep * xs_sc_alpha_min(roughness * roughness);
}

/**
 * Cross-eye reuse: true when a sample's radiance differs between the eyes, so it is shaded per
 * eye only (xs_samplecache.h, XS_SC_CROSS_EYE_*): metal and glass (App. C's view-dependent
 * weight), and dielectrics with a specular layer (ior != 1) smoother than the threshold.
 */
XS_SCM_FN xs_uint xs_sc_eye_specific(xs_float metallic, xs_float transmission, xs_float roughness,
                                     xs_float ior)
{
    xs_float view_dep = metallic + (1.0f - metallic) * transmission;
    xs_uint specular = ior != 1.0f && roughness < XS_SC_CROSS_EYE_ROUGHNESS ? 1u : 0u;
    return view_dep > XS_SC_CROSS_EYE_VIEW_DEP || specular != 0u ? 1u : 0u;
}

#endif /* XS_SC_MATH_H */
