// SPDX-License-Identifier: MIT
/**
 * @file test_stereo.c
 * @brief Stereo blends (seed 000 §3.6/§5.2, seed 004 §3-4): the beta formulas of xs_stereo.h
 *        on synthetic data (C build), the blend pass on synthetic images (device vs C), and
 *        stereo consistency on scenes/glossy.gltf against a converged reference: stereo
 *        discrepancy and relMSE for none, pfj23, moments R = 0 / 0.8 / 1.
 *
 * Glossy setup: 64 x 64 per eye, reference 256 spp `spp` (accumulated) of the view. The noisy
 * input the claims are about is the sample cache's (seed 000 §5.2: "the resulting image is used
 * as input for stereo blending"): `samplecache` with the fixed temporal alpha = 0.1 of §5.2,
 * defaults otherwise, after T_CACHE_FRAMES = 128 frames of the still stereo view (each pixel's
 * ~4 visibility samples shaded round robin, so every L_s has reached alpha's steady state; its
 * moments are Eq. 5-6 over those samples with their c_s). Printed for comparison, not asserted
 * beyond the per-pixel rules: the same on T_SPP_INPUTS 4-spp `spp` inputs (moments of 4 raw
 * path samples).
 * Every metric is the mean over both eyes and over T_CACHE_INPUTS (cache) or T_SPP_INPUTS
 * (`spp`) independent inputs (seeds), printed
 * with its standard error over the inputs, and each claimed comparison is printed as the paired
 * difference over the same inputs +- its standard error. All pixels are scored (relMSE: every
 * pixel of both eyes; discrepancy: xrsc_metrics_stereo_discrepancy's valid pixels). The scene is
 * in the regime of seed 000 §5.2: the converged reference's own stereo discrepancy (real view
 * dependence of the floor's glossy highlight, resampling at edges) must stay below 30 % of the
 * noisy input's, i.e. the input's discrepancy is not real view dependence (see
 * scenes/README.md for the earlier sun-streak scene where it was).
 *
 * Must hold: Eq. 8 from sample moments converges to Eq. 4's beta and a brute-force beta search
 * of the blend's MSE agrees with it; on the cache input: the scene's regime (above), moments
 * R = 0 lowers discrepancy and relMSE against none and pfj23, R = 0 beats R = 1 on relMSE by
 * more than 3 standard errors of the paired difference; on both inputs: disoccluded and
 * background pixels are untouched, swapping the eyes swaps the result, the renderer's in-frame
 * blend equals the pass run on the same inputs; zero validation errors.
 * Experiments (environment): T_INPUTS (<= 16), T_REF_FRAMES, T_CACHE_FRAMES, T_CACHE_YAW (head
 * turn per cache frame, rad, towards the scored view), T_PIXEL_MEAN (Eq. 8 of the pixel values: estimate
 * `mean`), T_NO_SPP, T_VAR_STATS (the estimates against the pixels' actual variance over the
 * inputs, and the blend with that variance and with the best fixed per-pixel beta: issue 12,
 * bench/results/issue12-fig15/). The estimate `mean` on the device equals xs_st_beta_eq8_mean,
 * and the renderer's blend_estimate reaches the pass (`samples`, the default, as before).
 * ctest runs it as two entries (issue 22): test_stereo_spp (the formulas, the synthetic pass and
 * the `spp` inputs' table; it renders the reference and writes it to T_REF_FILE_OUT) and
 * test_stereo (the claims on the cache inputs, reading the reference from T_REF_FILE_IN), so
 * that on a cold shader cache each process compiles only its own lavapipe pipelines. Without
 * those variables the program renders the reference itself, once for both.
 */
#include "st_blend.h"
#include "testing.h"
#include "xrsc/xrsc.h"
#include "xrsc/xrsc_metrics.h"
#include "xrsc_core_internal.h"
#include "xs_stereo.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define T_W 64u
#define T_H 64u
#define T_SPP 4u          /* noisy input */
#define T_INPUTS 16u      /* independent noisy inputs the glossy metrics are averaged over */
/* cache inputs by default (issue 22: 6 of 16, the test's cost was their 128 frames each; the
 * claims' paired differences at 6 (reference 256 spp) vs 8 vs 16 (reference 1024 spp):
 * R = 1 - R = 0 relMSE 16.0 vs 30.3 vs 28.5 standard errors, none - R = 0 discrepancy 10.9 vs
 * 13.3 vs 22.0, pfj23 - R = 0 discrepancy 5.3 vs 7.1 vs 12.9, pfj23 - R = 0 relMSE +1.4 vs
 * +1.7 vs +2.1: each sign as before, the asserted 3-standard-error margin unchanged;
 * T_INPUTS=16 in the environment runs all) */
#define T_CACHE_INPUTS 6u
/* `spp` inputs: their table is printed for comparison and only per-pixel rules are asserted on
 * them, which hold input by input; 4 keep a standard error in the table (issue 22: 16 cost
 * 12 renderers more for nothing asserted) */
#define T_SPP_INPUTS 4u
#define T_REF_SPP 256u    /* reference: T_REF_FRAMES x T_REF_SPP accumulated */
/* issue 22: 1 (was 4, ~20 s CPU): the regime check's reference discrepancy rose from 2.3 % to
 * 2.7 % of the input's (bound 30 %); T_REF_FRAMES in the environment overrides it */
#define T_REF_FRAMES 1u
#define T_IPD_M 0.063f
#define T_HALF_FOV_RAD 0.5f
#define T_GPU_TOL 1e-5f /* device float vs C float of the same formulas */
#define T_CACHE_FRAMES 128u /* cache input: frames of the view rendered before it is read */
#define T_INFRAME_FRAMES 4u /* cache: frames of the in-frame blend check */
#define T_CACHE_ALPHA 0.1f /* its fixed temporal alpha (seed 000 §5.2) */
#define T_CACHE_YAW 0.0f   /* head turn per frame (rad) */

static uint64_t rng_state = 0x9E3779B97F4A7C15ull;
static double rnd01(void)
{
    rng_state = rng_state * 6364136223846793005ull + 1442695040888963407ull;
    return ((rng_state >> 11) + 0.5) * (1.0 / 9007199254740992.0);
}
static double gauss(void)
{
    return sqrt(-2.0 * log(rnd01())) * cos(6.283185307179586 * rnd01());
}

/* ---- 1. formulas (C build of xs_stereo.h) ---- */

static void test_beta_formulas(void)
{
    /* (E[X], sigma_X, E[Y], sigma_Y): unbiased, biased, noiseless X, large bias */
    static const double cases[][4] = {
        {1.0, 0.5, 1.0, 0.5}, {1.2, 0.3, 1.0, 0.6}, {0.5, 0.0, 0.6, 0.2}, {3.0, 0.2, 1.0, 0.4}};
    for (size_t k = 0; k < sizeof(cases) / sizeof(cases[0]); k++) {
        double mx = cases[k][0], sx = cases[k][1], my = cases[k][2], sy = cases[k][3];
        float b4 = xs_st_beta_eq4((float)(sx * sx), (float)(sy * sy), (float)((mx - my) * (mx - my)));
        /* Eq. 8 from K samples of each: the error shrinks with K */
        double err_prev = 1e9;
        for (uint32_t n = 100; n <= 1000000; n *= 100) {
            double s1x = 0, s2x = 0, s1y = 0, s2y = 0;
            for (uint32_t i = 0; i < n; i++) {
                double x = mx + sx * gauss(), y = my + sy * gauss();
                s1x += x, s2x += x * x, s1y += y, s2y += y * y;
            }
            float b8 = xs_st_beta_eq8((float)(s1x / n), (float)(s2x / n), (float)(s1y / n),
                                      (float)(s2y / n));
            double err = fabs((double)b8 - b4);
            printf("  case %zu: K = %7u samples: Eq. 8 beta %.4f vs Eq. 4 %.4f\n", k, n, b8, b4);
            if (n == 1000000)
                CHECK_MSG(err < 5e-3, "case %zu: |Eq.8 - Eq.4| = %g", k, err);
            CHECK(err <= err_prev + 2e-2);
            err_prev = err;
        }
        /* brute force: MSE of lerp(X, Y, beta) against E[Y] over M trials, beta on a grid */
        const uint32_t trials = 200000;
        double sxx = 0, syy = 0, sxy = 0; /* of X - E[Y], Y - E[Y] */
        for (uint32_t i = 0; i < trials; i++) {
            double x = mx + sx * gauss() - my, y = sy * gauss();
            sxx += x * x, syy += y * y, sxy += x * y;
        }
        double best = 0, best_mse = 1e300;
        for (int g = 0; g <= 1000; g++) {
            double b = g / 1000.0;
            double mse = ((1 - b) * (1 - b) * sxx + b * b * syy + 2 * b * (1 - b) * sxy) / trials;
            if (mse < best_mse)
                best_mse = mse, best = b;
        }
        printf("  case %zu: brute-force argmin beta %.3f, Eq. 4 %.4f\n", k, best, b4);
        CHECK_MSG(fabs(best - b4) < 0.01, "case %zu: brute force %g vs Eq. 4 %g", k, best, b4);
    }
    /* Dodgson: partition of unity for every r and offset, interpolating at r = 1 */
    for (int ri = 0; ri <= 10; ri++) {
        float r = ri / 10.0f;
        for (int oi = -5; oi <= 5; oi++) {
            float t = oi / 10.0f;
            float sum = xs_st_dodgson(t - 1.0f, r) + xs_st_dodgson(t, r) + xs_st_dodgson(t + 1.0f, r);
            CHECK_NEAR(sum, 1.0f, 1e-6f);
        }
    }
    CHECK_NEAR(xs_st_dodgson(0.0f, 1.0f), 1.0f, 1e-7f);
    CHECK_NEAR(xs_st_dodgson(1.0f, 1.0f), 0.0f, 1e-7f);
    /* PFJ23: a flat neighbourhood (no variance) keeps Y */
    CHECK_NEAR(xs_st_beta_pfj23(9.0f, 9.0f, 9.0f * 0.25f, 9.0f), 1.0f, 1e-7f);
}

/* ---- helpers ---- */

static void make_views(XrPosef head, xrsc_view views[2])
{
    for (int e = 0; e < 2; e++) {
        XrPosef off = xrsc_pose_identity();
        off.position.x = (e == 0 ? -0.5f : 0.5f) * T_IPD_M;
        views[e].pose = xrsc_pose_mul(head, off);
        views[e].fov = (XrFovf){-T_HALF_FOV_RAD, T_HALF_FOV_RAD, T_HALF_FOV_RAD, -T_HALF_FOV_RAD};
    }
}

typedef struct stereo_input {
    float *color, *depth, *mu1, *mu2; /* both eyes, eye 0 first */
} stereo_input;

static void input_free(stereo_input *in)
{
    free(in->color), free(in->depth), free(in->mu1), free(in->mu2);
    memset(in, 0, sizeof(*in));
}

static void read_outputs(xrsc_renderer *r, stereo_input *in)
{
    size_t px = (size_t)T_W * T_H;
    in->color = malloc(2 * px * 16), in->depth = malloc(2 * px * 4);
    in->mu1 = malloc(2 * px * 16), in->mu2 = malloc(2 * px * 16);
    for (uint32_t e = 0; e < 2; e++) {
        CHECK_EQ_INT(xrsc_renderer_read(r, e, XRSC_OUTPUT_COLOR, in->color + e * px * 4, px * 16), XRSC_OK);
        CHECK_EQ_INT(xrsc_renderer_read(r, e, XRSC_OUTPUT_DEPTH, in->depth + e * px, px * 4), XRSC_OK);
        CHECK_EQ_INT(xrsc_renderer_read(r, e, XRSC_OUTPUT_MU1, in->mu1 + e * px * 4, px * 16), XRSC_OK);
        CHECK_EQ_INT(xrsc_renderer_read(r, e, XRSC_OUTPUT_MU2, in->mu2 + e * px * 4, px * 16), XRSC_OK);
    }
}

static xrsc_metrics_view mview(const float *rgba, const float *depth, const xrsc_view *v)
{
    return (xrsc_metrics_view){rgba, depth, {v->pose, v->fov, T_W, T_H}};
}

/** Mean over both eyes of relMSE against ref, and of the stereo discrepancy (each eye against
 *  the other reprojected into it). */
static void measure(const float *rgba, const float *depth, const float *ref, const xrsc_view v[2],
                    double *out_relmse, double *out_disc)
{
    size_t px = (size_t)T_W * T_H;
    double rel = 0, disc = 0;
    for (int e = 0; e < 2; e++) {
        xrsc_error_metrics em;
        CHECK_EQ_INT(xrsc_metrics_error(rgba + e * px * 4, ref + e * px * 4, T_W, T_H, NULL, &em),
                     XRSC_OK);
        rel += em.relmse / 2;
        xrsc_metrics_view a = mview(rgba + e * px * 4, depth + e * px, &v[e]);
        xrsc_metrics_view b = mview(rgba + (1 - e) * px * 4, depth + (1 - e) * px, &v[1 - e]);
        xrsc_reproj_diff d;
        CHECK_EQ_INT(xrsc_metrics_stereo_discrepancy(&a, &b, NULL, &d, NULL, NULL), XRSC_OK);
        disc += d.mean_sq_diff / 2;
    }
    *out_relmse = rel;
    *out_disc = disc;
}

/** Mean and standard error of the mean of v[0..n-1]. */
static void mean_se(const double *v, uint32_t n, double *out_mean, double *out_se)
{
    double m = 0, ss = 0;
    for (uint32_t i = 0; i < n; i++)
        m += v[i] / n;
    for (uint32_t i = 0; i < n; i++)
        ss += (v[i] - m) * (v[i] - m);
    *out_mean = m;
    *out_se = n > 1 ? sqrt(ss / (n - 1) / n) : 0.0;
}

/* ---- 2. the pass on synthetic images: device vs the C formulas ---- */

static void test_blend_synthetic(void)
{
    xrsc_context_options co = {.validation = true};
    xrsc_context *ctx = NULL;
    CHECK_EQ_INT(xrsc_context_create(&co, &ctx, NULL), XRSC_OK);
    if (!ctx)
        return;
    gpu_context *gpu = xrsc_context_gpu(ctx);
    size_t px = (size_t)T_W * T_H;
    float *color = malloc(2 * px * 16), *depth = malloc(2 * px * 4);
    float *mu1 = malloc(2 * px * 16), *mu2 = malloc(2 * px * 16);
    float *out = malloc(2 * px * 16), *aux = malloc(2 * px * 16);
    /* Both eyes at the same pose: the reprojection is the identity. Eye e has colour and
     * moments constant per eye; the left half of eye 1 lies 3 x deeper (a disocclusion for
     * eye 0 there). */
    xrsc_view v[2];
    make_views(xrsc_pose_identity(), v);
    v[1] = v[0];
    const float m1[2] = {0.4f, 0.7f}, var[2] = {0.05f, 0.02f}, c[2] = {4.0f, 6.0f};
    for (uint32_t e = 0; e < 2; e++)
        for (size_t i = 0; i < px; i++) {
            for (int k = 0; k < 3; k++) {
                color[(e * px + i) * 4 + k] = m1[e];
                mu1[(e * px + i) * 4 + k] = m1[e];
                mu2[(e * px + i) * 4 + k] = m1[e] * m1[e] + var[e];
            }
            color[(e * px + i) * 4 + 3] = 1.0f;
            mu1[(e * px + i) * 4 + 3] = mu2[(e * px + i) * 4 + 3] = c[e];
            depth[e * px + i] = (e == 1 && i % T_W < T_W / 2) ? 6.0f : 2.0f;
        }
    static const float rs[] = {0.0f, 0.8f, 1.0f};
    for (size_t ri = 0; ri < 3; ri++) {
        st_settings set = {.blend = XRSC_BLEND_MOMENTS, .r = rs[ri]};
        CHECK_EQ_INT(st_blend_run_host(gpu, T_W, T_H, &set, v, color, depth, mu1, mu2, out, aux,
                                       NULL),
                     XRSC_OK);
        uint32_t rejected = 0, bad = 0;
        for (uint32_t e = 0; e < 2; e++) {
            uint32_t o = 1 - e;
            float beta = xs_st_beta_eq8(m1[o], m1[o] * m1[o] + var[o], m1[e], m1[e] * m1[e] + var[e]);
            float want = xs_st_lerp(m1[o], m1[e], beta);
            /* away from the depth step (the kernel and the 3 x 3 blur reach 2 pixels) */
            for (uint32_t y = 2; y < T_H - 2; y++)
                for (uint32_t x = 2; x < T_W - 2; x++) {
                    size_t i = e * px + (size_t)y * T_W + x;
                    bool deep = x < T_W / 2;
                    if (deep && e == 0) { /* eye 1 sees something else there */
                        rejected += aux[i * 4 + 3] == XS_ST_STATUS_REJECTED;
                        bad += memcmp(&out[i * 4], &color[i * 4], 16) != 0;
                    } else if (!deep || e == 1) {
                        if (e == 1 && deep)
                            continue; /* eye 0 is 3 x nearer there: rejected too */
                        if (x >= T_W / 2 - 2 && x <= T_W / 2 + 1)
                            continue;
                        bad += fabsf(out[i * 4] - want) > T_GPU_TOL ||
                               fabsf(aux[i * 4] - beta) > T_GPU_TOL;
                    }
                }
            if (ri == 0)
                printf("  eye %u: beta (Eq. 8, C) %.5f -> %.5f\n", e, beta, want);
        }
        printf("  R = %.1f: %u disoccluded pixels kept, %u mismatches\n", rs[ri], rejected, bad);
        CHECK(rejected == (T_H - 4) * (T_W / 2 - 2));
        CHECK_EQ_INT(bad, 0);
    }
    /* the `mean` estimate (pixel_mean): Eq. 8 of the pixel values' moments with the counts c
     * (one colour tap: n_x = c of the other eye), a different beta from the samples' one */
    st_settings pm = {.blend = XRSC_BLEND_MOMENTS, .pixel_mean = true};
    CHECK_EQ_INT(st_blend_run_host(gpu, T_W, T_H, &pm, v, color, depth, mu1, mu2, out, aux, NULL),
                 XRSC_OK);
    uint32_t bad_mean = 0;
    for (uint32_t e = 0; e < 2; e++) {
        uint32_t o = 1 - e;
        float b_s = xs_st_beta_eq8(m1[o], m1[o] * m1[o] + var[o], m1[e], m1[e] * m1[e] + var[e]);
        float b_m = xs_st_beta_eq8_mean(m1[o], m1[o] * m1[o] + var[o], c[o], m1[e],
                                        m1[e] * m1[e] + var[e], c[e]);
        CHECK_MSG(fabsf(b_m - b_s) > 0.05f, "eye %u: estimates must differ here", e);
        for (uint32_t y = 2; y < T_H - 2; y++)
            for (uint32_t x = T_W / 2 + 2; x < T_W - 2; x++) {
                size_t i = e * px + (size_t)y * T_W + x;
                bad_mean += fabsf(aux[i * 4] - b_m) > 1e-4f;
            }
        printf("  eye %u, estimate mean: beta (C) %.5f (samples: %.5f)\n", e, b_m, b_s);
    }
    printf("  estimate mean: %u mismatches\n", bad_mean);
    CHECK_EQ_INT(bad_mean, 0);
    free(color), free(depth), free(mu1), free(mu2), free(out), free(aux);
    CHECK_EQ_INT(xrsc_context_validation_errors(ctx), 0);
    xrsc_context_destroy(&ctx);
}

/* ---- 3. stereo consistency on the glossy scene ---- */

static void swap_eyes(const float *src, float *dst, size_t layer_floats)
{
    memcpy(dst, src + layer_floats, layer_floats * sizeof(float));
    memcpy(dst + layer_floats, src, layer_floats * sizeof(float));
}

static uint32_t env_u32(const char *name, uint32_t def)
{
    const char *v = getenv(name);
    return v && *v ? (uint32_t)strtoul(v, NULL, 10) : def;
}
static float env_f(const char *name, float def)
{
    const char *v = getenv(name);
    return v && *v ? strtof(v, NULL) : def;
}

/** The glossy scene, its stereo view and the converged reference of it. */
typedef struct glossy_rig {
    xrsc_context *ctx;
    gpu_context *gpu;
    xrsc_scene *scene;
    xrsc_frame frame;
    float *ref, *ref_depth;
    double ref_disc, ref_cpbd;
} glossy_rig;

typedef enum input_kind { INPUT_SPP, INPUT_CACHE } input_kind;

/** Options of noisy input k: `spp` at T_SPP, or `samplecache` with the fixed temporal alpha of
 *  seed 000 §5.2 (defaults otherwise); a different seed per input. */
static xrsc_renderer_options input_options(input_kind kind, uint32_t k)
{
    xrsc_renderer_options ro = {.width = T_W, .height = T_H, .seed = 3 + 7919 * k};
    if (kind == INPUT_SPP) {
        ro.method = XRSC_METHOD_SPP;
        ro.spp.samples_per_pixel = T_SPP;
    } else {
        ro.method = XRSC_METHOD_SAMPLECACHE;
        ro.samplecache.alpha = XRSC_SC_ALPHA_FIXED;
        ro.samplecache.alpha_fixed = T_CACHE_ALPHA;
    }
    return ro;
}

/** Renders one input: `spp` one frame of the view; `samplecache` `frames` frames (frame indices
 *  0, 1, ...), the head turning by T_CACHE_YAW per frame towards the view, which the last frame
 *  shows. */
static void render_input(glossy_rig *g, input_kind kind, uint32_t frames, xrsc_renderer *r)
{
    if (kind == INPUT_SPP) {
        CHECK_EQ_INT(xrsc_renderer_render(r, &g->frame), XRSC_OK);
        return;
    }
    float yaw = env_f("T_CACHE_YAW", T_CACHE_YAW);
    xrsc_scene_info info;
    xrsc_scene_get_info(g->scene, &info);
    for (uint32_t f = 0; f < frames; f++) {
        xrsc_frame fr = g->frame;
        fr.frame_index = f;
        XrPosef turn = xrsc_pose_identity();
        turn.orientation = xrsc_quat_from_axis_angle((XrVector3f){0, 1, 0},
                                                      yaw * (float)(frames - 1 - f));
        make_views(xrsc_pose_mul(info.viewpoint, turn), fr.views);
        CHECK_EQ_INT(xrsc_renderer_render(r, &fr), XRSC_OK);
    }
}

/* The glossy reference (both eyes' colour, then depth), rendered once per process: the cases
 * that compare against it share it (issue 22). */
static float *g_ref;

/** Renders the reference of g's view into g_ref: T_REF_FRAMES x T_REF_SPP accumulated. */
static bool reference_render(glossy_rig *g)
{
    size_t px = (size_t)T_W * T_H;
    xrsc_renderer_options ro = {.method = XRSC_METHOD_SPP, .width = T_W, .height = T_H, .seed = 99};
    ro.spp.samples_per_pixel = T_REF_SPP;
    ro.spp.accumulate = true;
    xrsc_renderer *r = NULL;
    CHECK_EQ_INT(xrsc_renderer_create(g->ctx, g->scene, &ro, &r, NULL), XRSC_OK);
    if (!r)
        return false;
    for (uint32_t f = 0; f < env_u32("T_REF_FRAMES", T_REF_FRAMES); f++) {
        xrsc_frame rf = g->frame;
        rf.frame_index = 1000 + f;
        CHECK_EQ_INT(xrsc_renderer_render(r, &rf), XRSC_OK);
    }
    for (uint32_t e = 0; e < 2; e++) {
        CHECK_EQ_INT(xrsc_renderer_read(r, e, XRSC_OUTPUT_COLOR, g_ref + e * px * 4, px * 16),
                     XRSC_OK);
        CHECK_EQ_INT(xrsc_renderer_read(r, e, XRSC_OUTPUT_DEPTH, g_ref + 8 * px + e * px, px * 4),
                     XRSC_OK);
    }
    xrsc_renderer_destroy(&r);
    return true;
}

/**
 * g_ref, made once: read from the file T_REF_FILE_IN names when it holds a reference of this
 * size (ctest's test_stereo, after test_stereo_spp wrote it: the two entries then compile
 * lavapipe's `spp` and sample-cache pipelines in different processes, issue 22), else rendered;
 * written to T_REF_FILE_OUT when that is set (test_stereo_spp).
 */
static bool reference_get(glossy_rig *g)
{
    size_t floats = (size_t)T_W * T_H * 10; /* colour RGBA and depth, both eyes */
    if (g_ref)
        return true;
    g_ref = malloc(floats * sizeof(float));
    const char *in = getenv("T_REF_FILE_IN"), *out = getenv("T_REF_FILE_OUT");
    FILE *f = in && *in ? fopen(in, "rb") : NULL;
    bool ok = f && fread(g_ref, sizeof(float), floats, f) == floats && fgetc(f) == EOF;
    if (f)
        fclose(f);
    if (ok) {
        printf("  reference read from %s\n", in);
        return true;
    }
    if (in && *in)
        printf("  no reference in %s: rendered here\n", in);
    if (!reference_render(g))
        return false;
    if (out && *out && (f = fopen(out, "wb"))) {
        CHECK(fwrite(g_ref, sizeof(float), floats, f) == floats);
        CHECK(fclose(f) == 0);
    }
    return true;
}

static bool glossy_open(glossy_rig *g)
{
    memset(g, 0, sizeof(*g));
    xrsc_context_options co = {.validation = true};
    CHECK_EQ_INT(xrsc_context_create(&co, &g->ctx, NULL), XRSC_OK);
    if (!g->ctx)
        return false;
    g->gpu = xrsc_context_gpu(g->ctx);
    xrsc_diag diag = {0};
    CHECK_EQ_INT(xrsc_scene_load(g->ctx, t_source_path("scenes/glossy.gltf"), NULL, &g->scene, &diag),
                 XRSC_OK);
    if (!g->scene) {
        xrsc_context_destroy(&g->ctx);
        return false;
    }
    xrsc_scene_info info;
    xrsc_scene_get_info(g->scene, &info);
    g->frame = (xrsc_frame){.frame_index = 7};
    make_views(info.viewpoint, g->frame.views);
    size_t px = (size_t)T_W * T_H;
    if (!reference_get(g)) {
        xrsc_scene_destroy(&g->scene);
        xrsc_context_destroy(&g->ctx);
        return false;
    }
    g->ref = g_ref, g->ref_depth = g_ref + 8 * px;
    double ref_relmse;
    measure(g->ref, g->ref_depth, g->ref, g->frame.views, &ref_relmse, &g->ref_disc);
    for (uint32_t e = 0; e < 2; e++) {
        xrsc_cpbd cp;
        CHECK_EQ_INT(xrsc_metrics_cpbd(g->ref + e * px * 4, T_W, T_H, NULL, &cp), XRSC_OK);
        g->ref_cpbd += cp.cpbd / 2;
    }
    return true;
}

static void glossy_close(glossy_rig *g)
{
    xrsc_scene_destroy(&g->scene);
    CHECK_EQ_INT(xrsc_context_validation_errors(g->ctx), 0);
    xrsc_context_destroy(&g->ctx);
}

/**
 * Experiment T_VAR_STATS (issue 12): what the moments blend's variance estimates are worth.
 * Per foreground pixel and channel, over the n independent inputs of the same view: V, the
 * pixel value's actual variance (sample variance of Y over the inputs), against the mean over
 * the inputs of the estimates Eq. 8 takes for it: `samples` S = mu_2 - mu_1^2 (Eq. 5-7 as
 * printed), `mean` S / c_X. Printed: sum S / sum V, sum (S / c_X) / sum V and the medians of
 * the per-pixel ratios (1 = unbiased; above 1 the estimate inflates both variances of Eq. 4
 * against the bias term, i.e. trusts the other eye too much, below 1 too little).
 */
static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static void variance_stats(const stereo_input *ins, uint32_t n, float *v_out)
{
    size_t px = (size_t)T_W * T_H, m = 0, fg = 0;
    double *rs = malloc(2 * px * 3 * sizeof(double)), *rm = malloc(2 * px * 3 * sizeof(double));
    double sv = 0, ss = 0, sm = 0, cx = 0;
    for (size_t i = 0; i < 2 * px; i++) {
        if (!(ins[0].depth[i] > 0.0f))
            continue;
        fg++;
        for (int c = 0; c < 3; c++) {
            double y1 = 0, y2 = 0, es = 0, em = 0, cm = 0;
            for (uint32_t k = 0; k < n; k++) {
                double y = ins[k].color[i * 4 + c], a = ins[k].mu1[i * 4 + c];
                double spread = fmax(ins[k].mu2[i * 4 + c] - a * a, 0.0);
                double cnt = fmax(ins[k].mu1[i * 4 + 3], 1e-6);
                y1 += y / n, y2 += y * y / n, es += spread / n, em += spread / cnt / n;
                cm += cnt / n;
            }
            double v = fmax(y2 - y1 * y1, 0.0) * n / (n - 1);
            v_out[i * 4 + c] = (float)v;
            sv += v, ss += es, sm += em, cx += cm / 3;
            if (v > 1e-10)
                rs[m] = es / v, rm[m] = em / v, m++;
        }
    }
    qsort(rs, m, sizeof(double), cmp_double);
    qsort(rm, m, sizeof(double), cmp_double);
    printf("  T_VAR_STATS: %zu pixel channels; estimate / actual variance of the pixel: samples "
           "%.3f (median %.3f), mean %.4f (median %.4f); mean c_X %.2f\n",
           m, ss / sv, m ? rs[m / 2] : 0.0, sm / sv, m ? rm[m / 2] : 0.0,
           fg ? cx / (double)fg : 0.0);
    free(rs), free(rm);
}

/** T_VAR_STATS: X, the other eye's colour as the blend resamples it onto each pixel (both eyes),
 *  via the moments pass with a huge variance in the eye being improved (beta = 0 there);
 *  status (aux alpha) per pixel in st. */
static void other_eye_colour(glossy_rig *g, const stereo_input *in, float *x, float *st)
{
    size_t px = (size_t)T_W * T_H;
    float *mu2 = malloc(2 * px * 16), *out = malloc(2 * px * 16), *aux = malloc(2 * px * 16);
    st_settings set = {.blend = XRSC_BLEND_MOMENTS, .r = 1.0f};
    for (uint32_t e = 0; e < 2; e++) {
        for (size_t i = 0; i < 2 * px * 4; i++) {
            float m = in->mu1[i];
            mu2[i] = i % 4 == 3 ? in->mu2[i] : m * m + (i / 4 / px == e ? 1e8f : 0.0f);
        }
        CHECK_EQ_INT(st_blend_run_host(g->gpu, T_W, T_H, &set, g->frame.views, in->color, in->depth,
                                       in->mu1, mu2, out, aux, NULL),
                     XRSC_OK);
        memcpy(x + e * px * 4, out + e * px * 4, px * 16);
        for (size_t i = 0; i < px; i++)
            st[e * px + i] = aux[(e * px + i) * 4 + 3];
    }
    free(mu2), free(out), free(aux);
}

/** T_VAR_STATS: the per-pixel, per-channel beta that minimises the squared error against the
 *  reference over the n inputs (fitted on them, so slightly optimistic): the best any per-pixel
 *  lerp(X, Y, beta) can do; its relMSE, discrepancy, CPBD and mean beta over blended pixels. */
static void oracle_beta_row(glossy_rig *g, const stereo_input *ins, uint32_t n)
{
    size_t px = (size_t)T_W * T_H, nf = 2 * px * 4;
    float *x = malloc(n * nf * sizeof(float)), *st = malloc(n * 2 * px * sizeof(float));
    float *out = malloc(nf * sizeof(float));
    for (uint32_t k = 0; k < n; k++)
        other_eye_colour(g, &ins[k], x + k * nf, st + k * 2 * px);
    float *beta = malloc(nf * sizeof(float));
    double bsum = 0, bn = 0;
    for (size_t i = 0; i < nf; i++) {
        double num = 0, den = 0;
        for (uint32_t k = 0; k < n; k++) {
            if (i % 4 == 3 || st[k * 2 * px + i / 4] != XS_ST_STATUS_BLENDED)
                continue;
            double a = x[k * nf + i] - g->ref[i], b = ins[k].color[i] - g->ref[i];
            num -= a * (b - a), den += (b - a) * (b - a);
        }
        beta[i] = den > 0 ? (float)fmin(fmax(num / den, 0.0), 1.0) : 1.0f;
        if (den > 0)
            bsum += beta[i], bn += 1;
    }
    double rel[T_INPUTS], disc[T_INPUTS], rm, rse, dm, dse, cpbd = 0;
    for (uint32_t k = 0; k < n; k++) {
        for (size_t i = 0; i < nf; i++) {
            bool bl = i % 4 != 3 && st[k * 2 * px + i / 4] == XS_ST_STATUS_BLENDED;
            out[i] = bl ? xs_st_lerp(x[k * nf + i], ins[k].color[i], beta[i]) : ins[k].color[i];
        }
        measure(out, ins[k].depth, g->ref, g->frame.views, &rel[k], &disc[k]);
        for (uint32_t e = 0; e < 2; e++) {
            xrsc_cpbd cp;
            CHECK_EQ_INT(xrsc_metrics_cpbd(out + e * px * 4, T_W, T_H, NULL, &cp), XRSC_OK);
            cpbd += cp.cpbd / (2 * n);
        }
    }
    mean_se(rel, n, &rm, &rse);
    mean_se(disc, n, &dm, &dse);
    printf("  oracle beta    %10.6f +- %7.6f %12.6f +- %8.6f %8.4f %17s %6.3f\n", rm, rse, dm, dse,
           cpbd, "", bn > 0 ? bsum / bn : 1.0);
    free(x), free(st), free(out), free(beta);
}

/** T_VAR_STATS, continued: the moments blend with the pixels' actual variances v (from
 *  variance_stats) in place of an estimate: mu_2 replaced by mu_1^2 + v c_X under the `mean`
 *  estimate, so Eq. 8 sees Var(Y) = v. What an exact per-pixel variance (e.g. per-sample second
 *  moments in the shading cache) could give at best; printed as the table's rows. */
static void oracle_rows(glossy_rig *g, const stereo_input *ins, uint32_t n, const float *v)
{
    size_t px = (size_t)T_W * T_H;
    float *mu2 = malloc(2 * px * 16), *out = malloc(2 * px * 16);
    static const float rs[] = {0.0f, 0.8f, 1.0f};
    for (int ri = 0; ri < 3; ri++) {
        double rel[T_INPUTS], disc[T_INPUTS], rm, rse, dm, dse, cpbd = 0;
        st_settings set = {.blend = XRSC_BLEND_MOMENTS, .r = rs[ri], .pixel_mean = true};
        for (uint32_t k = 0; k < n; k++) {
            for (size_t i = 0; i < 2 * px; i++) {
                float a = ins[k].mu1[i * 4 + 3];
                for (int c = 0; c < 4; c++)
                    mu2[i * 4 + c] =
                        c < 3 && a > 0.0f
                            ? ins[k].mu1[i * 4 + c] * ins[k].mu1[i * 4 + c] + v[i * 4 + c] * a
                            : ins[k].mu2[i * 4 + c];
            }
            CHECK_EQ_INT(st_blend_run_host(g->gpu, T_W, T_H, &set, g->frame.views, ins[k].color,
                                           ins[k].depth, ins[k].mu1, mu2, out, NULL, NULL),
                         XRSC_OK);
            measure(out, ins[k].depth, g->ref, g->frame.views, &rel[k], &disc[k]);
            for (uint32_t e = 0; e < 2; e++) {
                xrsc_cpbd cp;
                CHECK_EQ_INT(xrsc_metrics_cpbd(out + e * px * 4, T_W, T_H, NULL, &cp), XRSC_OK);
                cpbd += cp.cpbd / (2 * n);
            }
        }
        mean_se(rel, n, &rm, &rse);
        mean_se(disc, n, &dm, &dse);
        printf("  oracle var R=%.1f %10.6f +- %7.6f %12.6f +- %8.6f %8.4f\n", rs[ri], rm, rse, dm,
               dse, cpbd);
    }
    free(mu2), free(out);
}

/**
 * The blends on T_INPUTS independent inputs of one kind against the reference: the table, the
 * paired differences, and (claims) the claims asserted; always asserted: disoccluded and
 * background pixels untouched, swapping the eyes swaps the result, the renderer's in-frame blend
 * equals the pass on the same inputs.
 */
static void glossy_compare(glossy_rig *g, input_kind kind, bool claims)
{
    size_t px = (size_t)T_W * T_H;
    uint32_t n_def = kind == INPUT_CACHE ? T_CACHE_INPUTS : T_SPP_INPUTS;
    uint32_t n_in = env_u32("T_INPUTS", n_def);
    if (n_in > T_INPUTS || n_in < 2)
        n_in = n_def;
    stereo_input ins[T_INPUTS] = {{0}};
    xrsc_renderer *r = NULL;
    for (uint32_t k = 0; k < n_in; k++) {
        xrsc_renderer_options rk = input_options(kind, k);
        CHECK_EQ_INT(xrsc_renderer_create(g->ctx, g->scene, &rk, &r, NULL), XRSC_OK);
        if (!r)
            return;
        render_input(g, kind, env_u32("T_CACHE_FRAMES", T_CACHE_FRAMES), r);
        read_outputs(r, &ins[k]);
        xrsc_renderer_destroy(&r);
    }
    const xrsc_view *views = g->frame.views;
    float *var_px = getenv("T_VAR_STATS") ? calloc(2 * px * 4, sizeof(float)) : NULL;
    if (var_px)
        variance_stats(ins, n_in, var_px);
    float *out = malloc(2 * px * 16), *aux = malloc(2 * px * 16);
    struct {
        const char *name;
        xrsc_blend blend;
        float r;
        double relmse, relmse_se, disc, disc_se, cpbd, beta; /* beta: mean over blended */
        double rel_n[T_INPUTS], disc_n[T_INPUTS]; /* per input */
    } runs[] = {{.name = "none", .blend = XRSC_BLEND_NONE},
                {.name = "pfj23", .blend = XRSC_BLEND_PFJ23},
                {.name = "moments R=0", .blend = XRSC_BLEND_MOMENTS, .r = 0.0f},
                {.name = "moments R=0.8", .blend = XRSC_BLEND_MOMENTS, .r = 0.8f},
                {.name = "moments R=1", .blend = XRSC_BLEND_MOMENTS, .r = 1.0f}};
    enum { NONE, PFJ, M0, M08, M1, NRUNS };
    float *keep_m0 = malloc(2 * px * 16);
    if (kind == INPUT_SPP)
        printf("  glossy %ux%u, input `spp` %u spp", T_W, T_H, T_SPP);
    else
        printf("  glossy %ux%u, input `samplecache` (alpha fixed %.2f, defaults otherwise) after "
               "%u frames, head turning %.4f rad/frame",
               T_W, T_H, T_CACHE_ALPHA, env_u32("T_CACHE_FRAMES", T_CACHE_FRAMES),
               env_f("T_CACHE_YAW", T_CACHE_YAW));
    printf("; reference %u spp; means over both eyes and %u inputs (+- standard error over the "
           "inputs)\n",
           T_REF_SPP * env_u32("T_REF_FRAMES", T_REF_FRAMES), n_in);
    printf("  %-14s %21s %24s %8s %8s %8s %6s\n", "blend", "relMSE", "discrepancy", "CPBD",
           "blended", "kept", "beta");
    printf("  %-14s %21s %24.6f %8.4f   (the converged images' own)\n", "reference", "-",
           g->ref_disc, g->ref_cpbd);
    const char *ps_env = getenv("T_PIXEL_MEAN"); /* experiment: the other estimate */
    for (int k = 0; k < NRUNS; k++) {
        st_settings set = {.blend = runs[k].blend, .r = runs[k].r, .pixel_mean = ps_env != NULL};
        uint32_t blended = 0, kept = 0, touched = 0, rejected = 0;
        for (uint32_t n = 0; n < n_in; n++) {
            const stereo_input *ik = &ins[n];
            CHECK_EQ_INT(st_blend_run_host(g->gpu, T_W, T_H, &set, views, ik->color, ik->depth,
                                           ik->mu1, ik->mu2, out, aux, NULL),
                         XRSC_OK);
            measure(out, ik->depth, g->ref, views, &runs[k].rel_n[n], &runs[k].disc_n[n]);
            for (uint32_t e = 0; e < 2; e++) {
                xrsc_cpbd cp;
                CHECK_EQ_INT(xrsc_metrics_cpbd(out + e * px * 4, T_W, T_H, NULL, &cp), XRSC_OK);
                runs[k].cpbd += cp.cpbd / (2 * n_in);
            }
            for (size_t i = 0; i < 2 * px; i++) {
                if (aux[i * 4 + 3] == XS_ST_STATUS_BLENDED) {
                    blended++;
                    runs[k].beta += (aux[i * 4] + aux[i * 4 + 1] + aux[i * 4 + 2]) / 3;
                } else {
                    kept++;
                    touched += memcmp(&out[i * 4], &ik->color[i * 4], 16) != 0;
                }
                rejected += aux[i * 4 + 3] == XS_ST_STATUS_REJECTED;
            }
            if (k == M0 && n == 0)
                memcpy(keep_m0, out, 2 * px * 16);
        }
        mean_se(runs[k].rel_n, n_in, &runs[k].relmse, &runs[k].relmse_se);
        mean_se(runs[k].disc_n, n_in, &runs[k].disc, &runs[k].disc_se);
        printf("  %-14s %10.6f +- %7.6f %12.6f +- %8.6f %8.4f %8u %8u %6.3f\n", runs[k].name,
               runs[k].relmse, runs[k].relmse_se, runs[k].disc, runs[k].disc_se, runs[k].cpbd,
               blended / n_in, kept / n_in, blended ? runs[k].beta / blended : 1.0);
        CHECK_EQ_INT(touched, 0); /* disoccluded and background pixels untouched */
        if (k != NONE) {
            CHECK(blended / n_in > px); /* most foreground pixels find the other eye */
            CHECK(rejected > 0);        /* the objects' sides seen by one eye only */
        }
    }
    if (var_px) {
        oracle_rows(g, ins, n_in, var_px);
        oracle_beta_row(g, ins, n_in);
    }
    free(var_px);
    printf("  reference discrepancy / noisy input's: %.1f %%\n",
           100.0 * g->ref_disc / runs[NONE].disc);
    /* paired differences over the same inputs: margin +- its standard error */
    static const struct { int a, b; bool relmse; } cmp[] = {
        {NONE, M0, false}, {PFJ, M0, false}, {NONE, M0, true}, {PFJ, M0, true}, {M1, M0, true}};
    double m1_m0 = 0, m1_m0_se = 0;
    for (size_t c = 0; c < sizeof(cmp) / sizeof(cmp[0]); c++) {
        double d[T_INPUTS], m, se;
        for (uint32_t n = 0; n < n_in; n++)
            d[n] = cmp[c].relmse ? runs[cmp[c].a].rel_n[n] - runs[cmp[c].b].rel_n[n]
                                 : runs[cmp[c].a].disc_n[n] - runs[cmp[c].b].disc_n[n];
        mean_se(d, n_in, &m, &se);
        printf("  %-12s: %-13s - %-13s = %+.6f +- %.6f (%.1f standard errors)\n",
               cmp[c].relmse ? "relMSE" : "discrepancy", runs[cmp[c].a].name, runs[cmp[c].b].name,
               m, se, se > 0 ? m / se : 0.0);
        if (cmp[c].a == M1)
            m1_m0 = m, m1_m0_se = se;
    }
    if (claims) {
        /* the regime: discrepancy mostly noise, not real view dependence */
        CHECK_MSG(g->ref_disc < 0.3 * runs[NONE].disc, "reference discrepancy %g vs input %g",
                  g->ref_disc, runs[NONE].disc);
        CHECK(runs[M0].disc < runs[NONE].disc && runs[M0].disc < runs[PFJ].disc);
        CHECK(runs[M0].relmse < runs[NONE].relmse && runs[M0].relmse < runs[PFJ].relmse);
        CHECK(runs[M0].relmse < runs[M1].relmse);
        CHECK_MSG(m1_m0 > 3 * m1_m0_se, "R = 1 - R = 0 relMSE %g +- %g: not resolved", m1_m0,
                  m1_m0_se);
    }

    /* swapping the eyes swaps the result (bit for bit) */
    stereo_input in = ins[0];
    {
        stereo_input sw = {malloc(2 * px * 16), malloc(2 * px * 4), malloc(2 * px * 16),
                           malloc(2 * px * 16)};
        swap_eyes(in.color, sw.color, px * 4);
        swap_eyes(in.depth, sw.depth, px);
        swap_eyes(in.mu1, sw.mu1, px * 4);
        swap_eyes(in.mu2, sw.mu2, px * 4);
        xrsc_view sv[2] = {views[1], views[0]};
        st_settings set = {.blend = XRSC_BLEND_MOMENTS, .r = 0.0f, .pixel_mean = ps_env != NULL};
        CHECK_EQ_INT(st_blend_run_host(g->gpu, T_W, T_H, &set, sv, sw.color, sw.depth, sw.mu1,
                                       sw.mu2, out, NULL, NULL),
                     XRSC_OK);
        bool same = memcmp(out, keep_m0 + px * 4, px * 16) == 0 &&
                    memcmp(out + px * 4, keep_m0, px * 16) == 0;
        printf("  eyes swapped: result swapped %s\n", same ? "bit for bit" : "NOT");
        CHECK(same);
        input_free(&sw);
    }

    /* the renderer's in-frame blend: the same pixels as the pass on the same inputs (`spp`:
     * input 0 again; `samplecache`: input 0's options over T_INFRAME_FRAMES frames, rendered
     * without and with the blend), pass "blend" last; the second frame's timings (pipelines
     * warm). `samplecache` also with blend_estimate `mean`: it reaches the pass (pixel_mean)
     * and changes the image, while the default `samples` is the pass as before. */
    float *prev_est = NULL;
    for (int est = 0; est < (kind == INPUT_CACHE ? 2 : 1); est++) {
        const float *want = keep_m0;
        float *want_sc = NULL;
        xrsc_renderer_options ro = input_options(kind, 0);
        if (kind == INPUT_CACHE) {
            stereo_input sc = {0};
            CHECK_EQ_INT(xrsc_renderer_create(g->ctx, g->scene, &ro, &r, NULL), XRSC_OK);
            render_input(g, kind, T_INFRAME_FRAMES, r);
            read_outputs(r, &sc);
            xrsc_renderer_destroy(&r);
            want = want_sc = malloc(2 * px * 16);
            st_settings set = {.blend = XRSC_BLEND_MOMENTS, .r = 0.0f, .pixel_mean = est == 1};
            CHECK_EQ_INT(st_blend_run_host(g->gpu, T_W, T_H, &set, views, sc.color, sc.depth,
                                           sc.mu1, sc.mu2, want_sc, NULL, NULL),
                         XRSC_OK);
            input_free(&sc);
        }
        ro.blend = XRSC_BLEND_MOMENTS;
        ro.blend_r = 0.0f;
        ro.blend_estimate = (xrsc_blend_estimate)est;
        CHECK_EQ_INT(xrsc_renderer_create(g->ctx, g->scene, &ro, &r, NULL), XRSC_OK);
        double blend_ms = 0, total_ms = 0;
        for (int rep = 0; rep < (kind == INPUT_SPP ? 2 : 1); rep++) {
            render_input(g, kind, T_INFRAME_FRAMES, r);
            xrsc_pass_timing tm[XRSC_MAX_PASSES];
            uint32_t n = xrsc_renderer_timings(r, tm, XRSC_MAX_PASSES);
            CHECK(n >= 3 && !strcmp(tm[n - 1].name, "blend"));
            blend_ms = total_ms = 0;
            for (uint32_t i = 0; i < n; i++) {
                total_ms += tm[i].gpu_ms;
                if (!strcmp(tm[i].name, "blend"))
                    blend_ms = tm[i].gpu_ms;
            }
        }
        float *rc = malloc(px * 16);
        bool same = true;
        for (uint32_t e = 0; e < 2; e++) {
            CHECK_EQ_INT(xrsc_renderer_read(r, e, XRSC_OUTPUT_COLOR, rc, px * 16), XRSC_OK);
            same = same && memcmp(rc, want + e * px * 4, px * 16) == 0;
        }
        printf("  renderer --blend moments --blend-estimate %s: %s the pass on its inputs; blend "
               "%.3f ms of %.3f ms GPU frame (%.1f %%, %s)\n",
               xrsc_blend_estimate_name((xrsc_blend_estimate)est),
               same ? "equal to" : "DIFFERENT from", blend_ms, total_ms,
               100.0 * blend_ms / (total_ms > 0 ? total_ms : 1), xrsc_context_device_name(g->ctx));
        CHECK(same);
        free(rc);
        if (prev_est) { /* `mean` vs `samples` on the same frames */
            size_t differ = 0;
            for (size_t i = 0; i < 2 * px * 4; i++)
                differ += want_sc[i] != prev_est[i];
            printf("  estimates mean vs samples: %zu of %zu values differ\n", differ, 2 * px * 4);
            CHECK(differ > px / 10);
        }
        free(prev_est);
        prev_est = want_sc;
        xrsc_renderer_destroy(&r);
    }
    free(prev_est);
    free(out), free(aux), free(keep_m0);
    for (uint32_t k = 0; k < n_in; k++)
        input_free(&ins[k]);
}

/* The claims, on the sample cache's inputs; and bad blend options. */
static void test_glossy_consistency(void)
{
    glossy_rig g;
    if (!glossy_open(&g))
        return;
    glossy_compare(&g, INPUT_CACHE, true);
    /* moments need moments: `primary` has none; R outside [0, 1] */
    xrsc_renderer_options ro = input_options(INPUT_SPP, 0);
    ro.blend = XRSC_BLEND_MOMENTS;
    ro.method = XRSC_METHOD_PRIMARY;
    xrsc_renderer *r = NULL;
    CHECK_EQ_INT(xrsc_renderer_create(g.ctx, g.scene, &ro, &r, NULL), XRSC_ERROR_INVALID_ARGUMENT);
    ro.method = XRSC_METHOD_SPP;
    ro.blend_r = 1.5f;
    CHECK_EQ_INT(xrsc_renderer_create(g.ctx, g.scene, &ro, &r, NULL), XRSC_ERROR_INVALID_ARGUMENT);
    ro.blend_r = 0.0f;
    ro.blend_estimate = (xrsc_blend_estimate)2;
    CHECK_EQ_INT(xrsc_renderer_create(g.ctx, g.scene, &ro, &r, NULL), XRSC_ERROR_INVALID_ARGUMENT);
    glossy_close(&g);
}

/* The same table on `spp` inputs (printed; the per-pixel rules asserted), unless T_NO_SPP. Run
 * first, it renders the reference (and, for ctest, writes it: T_REF_FILE_OUT). */
static void test_glossy_spp(void)
{
    glossy_rig g;
    if (!glossy_open(&g))
        return;
    if (!getenv("T_NO_SPP"))
        glossy_compare(&g, INPUT_SPP, false);
    glossy_close(&g);
}

int main(void)
{
    RUN(test_beta_formulas);
    RUN(test_blend_synthetic);
    RUN(test_glossy_spp);
    RUN(test_glossy_consistency);
    free(g_ref);
    return t_finish();
}
