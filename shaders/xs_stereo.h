// SPDX-License-Identifier: MIT
/**
 * @file xs_stereo.h
 * @brief The stereo blends' layouts, bindings and scalar formulas, ONE source compiled as GLSL
 *        (stereo_blend.comp) and as C (plugin/src/stereo/, tests): the optimal blend factor of
 *        PFJ23 (seed 004 Eq. 4), its neighbourhood estimate (seed 004 Eq. 10-11), its raw-moment
 *        estimate (seed 000 Eq. 5-8) and Dodgson's quadratic resampling kernel [Dod97].
 *
 * Notation (seed 000 Eq. 3, seed 004 §3): Y is this eye's pixel (the one improved), X the other
 * eye's value reprojected onto it; the result is lerp(X, Y, beta) = (1 - beta) X + beta Y, so
 * beta = 1 keeps this eye's pixel unchanged.
 *
 * Written in the common subset of C11 and GLSL 4.60 (scalars, ternaries, XS_ST_* macros), as
 * xs_sc_math.h is for the sample cache.
 */
#ifndef XS_STEREO_H
#define XS_STEREO_H

#include "xrsc_shared.h"

#ifdef XRSC_GLSL
#define XS_ST_FN
#define XS_ST_FABS(x) abs(x)
#define XS_ST_MAX(a, b) max(a, b)
#define XS_ST_MIN(a, b) min(a, b)
#else
#include <math.h>
#include <stdbool.h>
#define XS_ST_FN static inline
#define XS_ST_FABS(x) fabsf(x)
#define XS_ST_MAX(a, b) fmaxf(a, b)
#define XS_ST_MIN(a, b) fminf(a, b)
#endif

/* ---- stereo_blend.comp: set 0 ---- */
#define XS_ST_BIND_PARAMS 0 /* uniform xs_st_params */
#define XS_ST_BIND_SRC 1    /* rgba32f image2DArray: both eyes' colour before the blend (input) */
#define XS_ST_BIND_DEPTH 2  /* r32f image2DArray: view-space depth along -Z, 0 = background */
#define XS_ST_BIND_MU1 3    /* rgba32f image2DArray: mu_1 (rgb), c_X (a) (seed 000 Eq. 5-6) */
#define XS_ST_BIND_MU2 4    /* rgba32f image2DArray: mu_2 (rgb), c_X (a) */
#define XS_ST_BIND_OUT 5    /* rgba32f image2DArray: blended colour (output) */
#define XS_ST_BIND_AUX 6    /* rgba32f image2DArray: beta (rgb), XS_ST_STATUS_* (a) (output) */
#define XS_ST_BIND_HITID 7  /* rgba32ui image2DArray: hit ids, instance in .x (instance_test) */

#define XS_ST_GROUP 8u /* local size x and y of stereo_blend.comp */

/* Blend modes (xrsc_blend values). */
#define XS_ST_MODE_NONE 0u
#define XS_ST_MODE_PFJ23 1u
#define XS_ST_MODE_MOMENTS 2u

/* Per-pixel outcome, written to the aux image's alpha. */
#define XS_ST_STATUS_BACKGROUND 0.0f /* no depth: left untouched */
#define XS_ST_STATUS_BLENDED 1.0f    /* blended with the other eye */
#define XS_ST_STATUS_REJECTED 2.0f   /* disoccluded / outside the other eye: left untouched */

/** Relative depth tolerance of the disocclusion test: a tap of the other eye is used when
 *  |d_tap - d_expected| <= tol * d_expected (the stereo metric's XRSC_METRICS_DEPTH_TOLERANCE). */
#define XS_ST_DEPTH_TOLERANCE 0.05f
/** A reprojection whose accepted taps carry less than this share of the kernel's weight
 *  (Dodgson's kernel and the bilinear tent sum to 1) counts as disoccluded. */
#define XS_ST_MIN_WEIGHT 0.5f
/** Denominators of beta at or below this (no variance and no difference at all) keep Y. */
#define XS_ST_TINY 1e-12f

XS_STRUCT(xs_st_params)
{
    xs_eye eyes[2];        /* view, view_inv, proj, tan_fov as in xs_frame */
    xs_uint width, height; /* per eye, pixels */
    xs_uint mode;          /* XS_ST_MODE_* */
    xs_uint pixel_mean;    /* 0: Eq. 8 on the per-sample moments as printed; 1: of the pixel values */
    xs_float r;               /* sharpness R in [0, 1] (moments) */
    xs_float depth_tolerance; /* XS_ST_DEPTH_TOLERANCE */
    xs_float min_weight;      /* XS_ST_MIN_WEIGHT */
    xs_uint instance_test;    /* 1: a tap must also show the pixel's instance (hit id) */
} XS_END(xs_st_params);

#ifndef XRSC_GLSL
_Static_assert(sizeof(xs_st_params) == 2 * 208 + 32, "xs_st_params layout");
#endif

/** Seed 004 Eq. 4 (= seed 000 Eq. 4): the MSE-optimal beta for lerp(X, Y, beta) as an estimate
 *  of E[Y], from the variances of X and Y and Bias^2 = (E[X] - E[Y])^2. */
XS_ST_FN float xs_st_beta_eq4(float var_x, float var_y, float bias2)
{
    float den = bias2 + var_x + var_y;
    return den > XS_ST_TINY ? XS_ST_MIN(XS_ST_MAX(1.0f - var_y / den, 0.0f), 1.0f) : 1.0f;
}

/** Seed 000 Eq. 8: Eq. 4 in raw moments, sigma^2 = mu_2 - mu_1^2 (Eq. 7) and
 *  E[(X - Y)^2] = mu_2(X) + mu_2(Y) - 2 mu_1(X) mu_1(Y) for independent X, Y. */
XS_ST_FN float xs_st_beta_eq8(float mu1_x, float mu2_x, float mu1_y, float mu2_y)
{
    float var_y = XS_ST_MAX(mu2_y - mu1_y * mu1_y, 0.0f);
    float den = mu2_x + mu2_y - 2.0f * mu1_x * mu1_y;
    return den > XS_ST_TINY ? XS_ST_MIN(XS_ST_MAX(1.0f - var_y / den, 0.0f), 1.0f) : 1.0f;
}

/** Seed 000 Eq. 8 for the pixel values rather than single samples: a pixel value averages its
 *  samples, so its raw moments are mu_1 and mu_1^2 + (mu_2 - mu_1^2) / n with n its effective
 *  sample count (seed 004 §3.1: Var = sigma^2 / N); Eq. 8 of those (n = 1: Eq. 8 as printed). */
XS_ST_FN float xs_st_beta_eq8_mean(float mu1_x, float mu2_x, float n_x, float mu1_y, float mu2_y,
                                   float n_y)
{
    float m2x = mu1_x * mu1_x + XS_ST_MAX(mu2_x - mu1_x * mu1_x, 0.0f) / n_x;
    float m2y = mu1_y * mu1_y + XS_ST_MAX(mu2_y - mu1_y * mu1_y, 0.0f) / n_y;
    return xs_st_beta_eq8(mu1_x, m2x, mu1_y, m2y);
}

/** Seed 004 Eq. 10-11 (PFJ23's neighbourhood estimate) from sums over the n pixels Y_i of the
 *  3x3 neighbourhood: sum_y = sum Y_i, sum_y2 = sum Y_i^2, sum_d2 = sum (X - Y_i)^2.
 *  Eq. 10 as printed, (1/|N|) (sum Y_i^2 - (sum Y_i)^2), is not a variance (it mixes a sum of
 *  squares with a squared sum); we use the variance it means, (1/n) sum Y_i^2 - ((1/n) sum Y_i)^2,
 *  the variance-clipping estimate [Sal16] it cites. */
XS_ST_FN float xs_st_beta_pfj23(float sum_y, float sum_y2, float sum_d2, float n)
{
    float mean = sum_y / n;
    float var_y = XS_ST_MAX(sum_y2 / n - mean * mean, 0.0f);
    float msd = sum_d2 / n; /* E[(X - Y)^2], Eq. 11 */
    return msd > XS_ST_TINY ? XS_ST_MIN(XS_ST_MAX(1.0f - var_y / msd, 0.0f), 1.0f) : 1.0f;
}

/** Seed 000 Eq. 3: lerp(X, Y, beta) = (1 - beta) X + beta Y. */
XS_ST_FN float xs_st_lerp(float x, float y, float beta) { return (1.0f - beta) * x + beta * y; }

/** Dodgson's quadratic kernel [Dod97, Eq. 11] with spline parameter r at distance s (pixels):
 *  -2r s^2 + (r + 1)/2 for |s| <= 1/2, r s^2 - (2r + 1/2)|s| + 3(r + 1)/4 for 1/2 < |s| <= 3/2,
 *  0 beyond. r = 1 interpolates (h(0) = 1, h(+-1) = 0), r = 1/2 is the C1 approximating one,
 *  smaller r blur more; the weights of the three taps around any position sum to 1. */
XS_ST_FN float xs_st_dodgson(float s, float r)
{
    float a = XS_ST_FABS(s);
    if (a <= 0.5f)
        return -2.0f * r * a * a + 0.5f * (r + 1.0f);
    if (a <= 1.5f)
        return r * a * a - (2.0f * r + 0.5f) * a + 0.75f * (r + 1.0f);
    return 0.0f;
}

/** Weight of a neighbour in the 3x3 blur of this eye's moments (seed 000 §5.2): 1 at the
 *  centre, 1 - R off centre. */
XS_ST_FN float xs_st_blur_weight(int dx, int dy, float r)
{
    return (dx == 0 && dy == 0) ? 1.0f : 1.0f - r;
}

/** The disocclusion test: a tap at depth d_tap may stand for a point expected at d_exp. */
XS_ST_FN bool xs_st_depth_ok(float d_tap, float d_exp, float tol)
{
    return d_tap > 0.0f && d_exp > 0.0f && XS_ST_FABS(d_tap - d_exp) <= tol * d_exp;
}

#endif /* XS_STEREO_H */
