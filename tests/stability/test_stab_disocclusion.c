// SPDX-License-Identifier: MIT
/**
 * @file test_stab_disocclusion.c
 * @brief Stability case `disocclusion` (issue 9): a box sliding at 2.4 m/s in front of a
 *        checker-textured wall (scenes/disocclusion.gltf) under a sideways head sway
 *        (poses/sideways.xrpose). Pixels the box uncovers have no history: they must hold a
 *        valid value (finite, not black) the frame they appear, and reach the error of the rest
 *        of the image within K = T_K frames.
 *
 * Uncovered pixels (XRSC_REGION_UNCOVERED of the reference's first hits and depth, this frame
 * against the last) that show the wall (not the flagged moving box, whose leading edge also
 * counts as uncovered) start an age of 0; the relative squared error (relMSE's terms,
 * eps = XRSC_METRICS_RELMSE_EPSILON) of the sample cache against a converged reference is
 * pooled by age over all scored frames and both eyes, and compared with that of the rest of
 * the wall (pixels not uncovered in the last T_AGES frames). K is the first age whose error is
 * within T_FACTOR x the rest's (the "1.2 x" of issue 9's recovery frames).
 */
#include "t_stab.h"

#define T_RES 96u
#define T_FIRST 8u /**< first frame whose uncovered pixels are tracked (the cache is filled) */
#define T_LAST 36u /**< last scored frame */
#define T_AGES 12u /**< ages 0 .. T_AGES - 1 are pooled */
#define T_K 10u    /**< asserted: within T_FACTOR x the rest's error by this age (measured: 8) */
#define T_FACTOR 1.2
#define T_REF_SPP 32u
#define T_BLACK 1e-3 /**< luminance below this is "black" (the darkest lit cell is ~0.01) */

typedef struct ages {
    double err[T_AGES], rest;
    uint64_t n[T_AGES], rest_n, invalid, appeared;
} ages;

/** Relative squared error of one pixel (mean over R, G, B), as relMSE sums it. */
static double pixel_rel(const float *x, const float *r)
{
    double s = 0.0;
    for (int c = 0; c < 3; c++) {
        double d = (double)x[c] - r[c];
        s += d * d / ((double)r[c] * r[c] + XRSC_METRICS_RELMSE_EPSILON);
    }
    return s / 3.0;
}

/** Updates the ages of one eye at frame k and pools its errors. */
static void score_eye(const ts_rig *r, uint32_t k, const float *img, const ts_views *ref,
                      const uint8_t *mask, uint32_t eye, uint32_t *born, ages *a)
{
    for (size_t i = 0; i < (size_t)r->w * r->h; i++) {
        uint32_t inst = ref->hit[eye][4 * i];
        bool wall = (mask[i] & XRSC_REGION_BIT(XRSC_REGION_ALL)) &&
                    !(mask[i] & XRSC_REGION_BIT(XRSC_REGION_OBJECT)) && inst != UINT32_MAX;
        if (!wall)
            continue;
        const float *x = img + 4 * i;
        if (mask[i] & XRSC_REGION_BIT(XRSC_REGION_UNCOVERED)) {
            born[i] = k;
            a->appeared++;
            bool finite = isfinite(x[0]) && isfinite(x[1]) && isfinite(x[2]);
            if (!finite || xrsc_metrics_luminance(x) < T_BLACK)
                a->invalid++;
        }
        uint32_t age = born[i] == UINT32_MAX ? UINT32_MAX : k - born[i];
        double e = pixel_rel(x, ref->rgba[eye] + 4 * i);
        if (age < T_AGES) {
            a->err[age] += e;
            a->n[age]++;
        } else {
            a->rest += e;
            a->rest_n++;
        }
    }
}

static void disocclusion_uncovered_pixels_valid_and_recover(void)
{
    ts_rig r;
    if (!ts_open(&r, "scenes/disocclusion.gltf", "poses/sideways.xrpose", T_RES)) {
        ts_close(&r);
        return;
    }
    CHECK(r.instance_count >= 2 && (r.flags[0] | r.flags[1]) & XRSC_INSTANCE_FLAG_OBJECT);
    xrsc_renderer_options o_sc = {
        .method = XRSC_METHOD_SAMPLECACHE, .seed = 17, .samplecache = {.max_bounces = 1}};
    xrsc_renderer_options o_ref = {.method = XRSC_METHOD_SPP,
                                   .seed = 4,
                                   .spp = {.samples_per_pixel = T_REF_SPP, .max_bounces = 1}};
    xrsc_renderer *sc = ts_renderer(&r, o_sc), *ref = ts_renderer(&r, o_ref);
    ts_views v, vr[2];
    ts_views_alloc(&r, &v);
    ts_views_alloc(&r, &vr[0]);
    ts_views_alloc(&r, &vr[1]);
    size_t n = (size_t)T_RES * T_RES;
    uint8_t *mask = malloc(n);
    uint32_t *born[2] = {malloc(n * 4), malloc(n * 4)};
    for (size_t i = 0; i < n; i++)
        born[0][i] = born[1][i] = UINT32_MAX;
    ages a;
    memset(&a, 0, sizeof(a));
    for (uint32_t k = 0; sc && ref && k <= T_LAST; k++) {
        xrsc_frame f = ts_frame(&r, k);
        ts_render(&r, sc, &f, &v);
        if (k + 1 < T_FIRST)
            continue;
        ts_views *cur = &vr[k & 1], *prev = &vr[(k + 1) & 1];
        ts_reference(&r, ref, &f, 1, cur);
        if (k < T_FIRST)
            continue;
        for (uint32_t e = 0; e < 2; e++) {
            ts_regions(&r, cur, prev, e, mask);
            score_eye(&r, k, v.rgba[e], cur, mask, e, born[e], &a);
        }
    }
    double rest = a.rest_n ? a.rest / (double)a.rest_n : 0.0;
    uint32_t k_reached = UINT32_MAX;
    printf("  uncovered wall pixels: %llu appeared, %llu invalid (non-finite or black) the frame "
           "they appeared\n",
           (unsigned long long)a.appeared, (unsigned long long)a.invalid);
    printf("  relative squared error by age (frames since uncovered), rest of the wall %.4f:\n   ",
           rest);
    for (uint32_t g = 0; g < T_AGES; g++) {
        double e = a.n[g] ? a.err[g] / (double)a.n[g] : 0.0;
        printf(" %u: %.4f (%llu)", g, e, (unsigned long long)a.n[g]);
        if (k_reached == UINT32_MAX && a.n[g] && e <= T_FACTOR * rest)
            k_reached = g;
    }
    printf("\n  within %.1f x the rest at age %u (K = %u asserted)\n", T_FACTOR, k_reached, T_K);
    CHECK(a.appeared > 300 && a.rest_n > 1000);
    CHECK_EQ_INT((int)a.invalid, 0);
    /* the case must show a disocclusion at all: fresh pixels start worse than the rest */
    CHECK_MSG(a.n[0] && a.err[0] / (double)a.n[0] > T_FACTOR * rest, "age 0 %.4f vs rest %.4f",
              a.n[0] ? a.err[0] / (double)a.n[0] : 0.0, rest);
    CHECK_MSG(k_reached <= T_K, "uncovered pixels reach the rest's error at age %u", k_reached);
    ts_views_free(&v);
    ts_views_free(&vr[0]);
    ts_views_free(&vr[1]);
    free(mask);
    free(born[0]);
    free(born[1]);
    xrsc_renderer_destroy(&sc);
    xrsc_renderer_destroy(&ref);
    ts_close(&r);
}

int main(void)
{
    RUN(disocclusion_uncovered_pixels_valid_and_recover);
    return t_finish();
}
