// SPDX-License-Identifier: MIT
/**
 * @file test_metrics.c
 * @brief The metrics module (xrsc_metrics.h) on small images whose values are worked out by hand
 *        or by an independent brute-force computation here, and on analytically rendered views.
 */
#include "hs_image.h"
#include "hs_metrics_cmd.h"
#include "testing.h"
#include "xrsc/xrsc_metrics.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define PI 3.14159265358979323846

/* ---- helpers ---- */

static float *image_alloc(uint32_t w, uint32_t h, unsigned channels)
{
    return calloc((size_t)w * h * channels, sizeof(float));
}

static void set_px(float *rgba, uint32_t w, uint32_t x, uint32_t y, float r, float g, float b)
{
    float *p = rgba + ((size_t)y * w + x) * 4;
    p[0] = r;
    p[1] = g;
    p[2] = b;
    p[3] = 1.0f;
}

static void fill_grey(float *rgba, size_t pixels, float v)
{
    for (size_t p = 0; p < pixels; p++) {
        rgba[p * 4 + 0] = rgba[p * 4 + 1] = rgba[p * 4 + 2] = v;
        rgba[p * 4 + 3] = 1.0f;
    }
}

/* A deterministic pseudo-random number in [0, 1) (xorshift32), state passed explicitly. */
static float rnd(uint32_t *s)
{
    *s ^= *s << 13;
    *s ^= *s >> 17;
    *s ^= *s << 5;
    return (float)(*s >> 8) / 16777216.0f;
}

/* Gaussian blur (separable, clamp to edge, radius 4 sigma) of an RGBA image, in place. */
static void gaussian_blur(float *rgba, uint32_t w, uint32_t h, double sigma)
{
    int rad = (int)ceil(4.0 * sigma);
    double *k = malloc((size_t)(2 * rad + 1) * sizeof(double)), sum = 0.0;
    float *tmp = image_alloc(w, h, 4);
    for (int i = -rad; i <= rad; i++)
        sum += k[i + rad] = exp(-(double)i * i / (2.0 * sigma * sigma));
    for (int pass = 0; pass < 2; pass++) {
        const float *src = pass == 0 ? rgba : tmp;
        float *dst = pass == 0 ? tmp : rgba;
        for (uint32_t y = 0; y < h; y++) {
            for (uint32_t x = 0; x < w; x++) {
                for (int c = 0; c < 4; c++) {
                    double acc = 0.0;
                    for (int i = -rad; i <= rad; i++) {
                        long sx = pass == 0 ? (long)x + i : (long)x;
                        long sy = pass == 0 ? (long)y : (long)y + i;
                        sx = sx < 0 ? 0 : (sx >= (long)w ? (long)w - 1 : sx);
                        sy = sy < 0 ? 0 : (sy >= (long)h ? (long)h - 1 : sy);
                        acc += k[i + rad] * src[((size_t)sy * w + (size_t)sx) * 4 + c];
                    }
                    dst[((size_t)y * w + x) * 4 + c] = (float)(acc / sum);
                }
            }
        }
    }
    free(k);
    free(tmp);
}

/* ---- relMSE / RMSE ---- */

static void test_error_hand_2x2(void)
{
    /* Reference r and test x (R, G, B per pixel; alpha differs on purpose and must not count):
     *   pixel   r               x                x - r
     *   (0,0)   (1, 0, 0.5)     (1, 0.1, 0.5)    (0, 0.1, 0)
     *   (1,0)   (0, 0, 0)       (0.1, 0, 0)      (0.1, 0, 0)
     *   (0,1)   (0.2, 0.4, 0.6) (0.2, 0.4, 0.3)  (0, 0, -0.3)
     *   (1,1)   (2, 1, 0)       (1, 1, 0)        (-1, 0, 0)
     * N = 4 pixels x 3 channels = 12.
     * MSE = (0.01 + 0.01 + 0.09 + 1) / 12 = 1.11 / 12 = 0.0925; RMSE = sqrt(0.0925) = 0.3041381265.
     * relMSE with eps = 0.01, nonzero terms d^2 / (r^2 + eps):
     *   0.01 / (0 + 0.01) = 1;  0.01 / (0 + 0.01) = 1;  0.09 / (0.36 + 0.01) = 0.2432432432;
     *   1 / (4 + 0.01) = 0.2493765586;  sum = 2.4926198018;  / 12 = 0.2077183168. */
    float r[16], x[16];
    set_px(r, 2, 0, 0, 1.0f, 0.0f, 0.5f);
    set_px(r, 2, 1, 0, 0.0f, 0.0f, 0.0f);
    set_px(r, 2, 0, 1, 0.2f, 0.4f, 0.6f);
    set_px(r, 2, 1, 1, 2.0f, 1.0f, 0.0f);
    set_px(x, 2, 0, 0, 1.0f, 0.1f, 0.5f);
    set_px(x, 2, 1, 0, 0.1f, 0.0f, 0.0f);
    set_px(x, 2, 0, 1, 0.2f, 0.4f, 0.3f);
    set_px(x, 2, 1, 1, 1.0f, 1.0f, 0.0f);
    x[3] = 7.0f; /* alpha */
    xrsc_error_metrics e;
    CHECK_EQ_INT(xrsc_metrics_error(x, r, 2, 2, NULL, &e), XRSC_OK);
    CHECK_NEAR(e.mse, 0.0925, 1e-7);
    CHECK_NEAR(e.rmse, 0.3041381265, 1e-7);
    CHECK_NEAR(e.relmse, 0.2077183168, 1e-7);

    /* eps is an option: eps = 1 gives (0.01 + 0.01 + 0.09 / 1.36 + 1 / 5) / 12 = 0.0238480392. */
    xrsc_metrics_options o = {.relmse_epsilon = 1.0};
    CHECK_EQ_INT(xrsc_metrics_error(x, r, 2, 2, &o, &e), XRSC_OK);
    CHECK_NEAR(e.relmse, (0.01 + 0.01 + 0.09 / 1.36 + 1.0 / 5.0) / 12.0, 1e-7);

    /* Identical images: all zero. */
    CHECK_EQ_INT(xrsc_metrics_error(r, r, 2, 2, NULL, &e), XRSC_OK);
    CHECK(e.mse == 0.0 && e.rmse == 0.0 && e.relmse == 0.0);
}

static void test_error_bad_input(void)
{
    float a[16] = {0}, b[16] = {0};
    xrsc_error_metrics e;
    CHECK_EQ_INT(xrsc_metrics_error(NULL, b, 2, 2, NULL, &e), XRSC_ERROR_INVALID_ARGUMENT);
    CHECK_EQ_INT(xrsc_metrics_error(a, b, 0, 2, NULL, &e), XRSC_ERROR_INVALID_ARGUMENT);
    CHECK_EQ_INT(xrsc_metrics_error(a, b, 2, 2, NULL, NULL), XRSC_ERROR_INVALID_ARGUMENT);
    a[5] = NAN;
    CHECK_EQ_INT(xrsc_metrics_error(a, b, 2, 2, NULL, &e), XRSC_ERROR_NAN);
    a[5] = 0.0f;
    b[14] = INFINITY;
    CHECK_EQ_INT(xrsc_metrics_error(a, b, 2, 2, NULL, &e), XRSC_ERROR_NAN);
}

/* ---- SSIM ---- */

static void test_ssim_window(void)
{
    /* 1-D Gaussian sigma 1.5 at offsets 0..5: exp(-k^2 / 4.5) = 1, 0.8007374029, 0.4111122905,
     * 0.1353352832, 0.0285655008, 0.0038659201; S = 1 + 2 (sum of the last five) = 3.7592327952.
     * The 2-D window is the outer product / S^2: centre 1 / S^2 = 0.0707622378, sum 1. */
    double w[XRSC_SSIM_WINDOW * XRSC_SSIM_WINDOW], sum = 0.0;
    xrsc_metrics_ssim_window(w);
    for (int i = 0; i < XRSC_SSIM_WINDOW * XRSC_SSIM_WINDOW; i++)
        sum += w[i];
    CHECK_NEAR(sum, 1.0, 1e-12);
    CHECK_NEAR(w[5 * 11 + 5], 0.0707622378, 1e-9);
    CHECK_NEAR(w[5 * 11 + 6], 0.0707622378 * 0.8007374029, 1e-9);
    CHECK_NEAR(w[0], 0.0038659201 * 0.0038659201 / (3.7592327952 * 3.7592327952), 1e-12);
    CHECK(w[2 * 11 + 7] == w[7 * 11 + 2]);
}

static void test_ssim_identical_and_constant(void)
{
    const uint32_t w = 24, h = 19;
    float *x = image_alloc(w, h, 4), *y = image_alloc(w, h, 4);
    uint32_t s = 12345u;
    for (size_t p = 0; p < (size_t)w * h; p++)
        set_px(x, w, (uint32_t)(p % w), (uint32_t)(p / w), rnd(&s), rnd(&s), rnd(&s));
    double m = 0.0;
    CHECK_EQ_INT(xrsc_metrics_ssim(x, x, w, h, NULL, &m, NULL), XRSC_OK);
    CHECK_NEAR(m, 1.0, 1e-12);

    /* Constant grey 0.5 vs 0.6 (luminance = the grey value, since 0.2126 + 0.7152 + 0.0722 = 1):
     * every window has mu_x = 0.5, mu_y = 0.6, sigma = 0, so with C1 = (0.01 * 1)^2 = 1e-4 and
     * C2 = (0.03 * 1)^2 = 9e-4, Eq. 13 gives
     *   (2 * 0.5 * 0.6 + 1e-4) / (0.25 + 0.36 + 1e-4) * (0 + C2) / (0 + C2)
     *   = 0.6001 / 0.6101 = 0.9836092444. */
    fill_grey(x, (size_t)w * h, 0.5f);
    fill_grey(y, (size_t)w * h, 0.6f);
    float *map = image_alloc(w - 10, h - 10, 1);
    map[0] = -5.0f;
    CHECK_EQ_INT(xrsc_metrics_ssim(x, y, w, h, NULL, &m, map), XRSC_OK);
    CHECK_NEAR(m, 0.9836092444, 1e-7);
    CHECK_NEAR(map[0], 0.9836092444, 1e-6);
    CHECK_NEAR(map[(w - 10) * (h - 10) - 1], 0.9836092444, 1e-6);

    /* HDR: 3.0 vs 1.0 both clamp to L = 1, so SSIM = 1. With L = 4 they become 0.75 and 0.25:
     * (2 * 0.75 * 0.25 + 1e-4) / (0.5625 + 0.0625 + 1e-4) = 0.3751 / 0.6251 = 0.6000639898. */
    fill_grey(x, (size_t)w * h, 3.0f);
    fill_grey(y, (size_t)w * h, 1.0f);
    CHECK_EQ_INT(xrsc_metrics_ssim(x, y, w, h, NULL, &m, NULL), XRSC_OK);
    CHECK_NEAR(m, 1.0, 1e-9);
    xrsc_metrics_options o = {.display_range = 4.0};
    CHECK_EQ_INT(xrsc_metrics_ssim(x, y, w, h, &o, &m, NULL), XRSC_OK);
    CHECK_NEAR(m, 0.6000639898, 1e-7);

    /* Too small for the window; NaN input. */
    CHECK_EQ_INT(xrsc_metrics_ssim(x, y, 10, 10, NULL, &m, NULL), XRSC_ERROR_INVALID_ARGUMENT);
    x[7] = NAN;
    CHECK_EQ_INT(xrsc_metrics_ssim(x, y, w, h, NULL, &m, NULL), XRSC_ERROR_NAN);
    free(x);
    free(y);
    free(map);
}

/* Independent SSIM: the 2-D window summed directly at every valid position (no separable
 * filtering, no ring buffer), each statistic from its definition (Wang et al. Eq. 14-16). */
static double ssim_brute(const float *x, const float *y, uint32_t w, uint32_t h, float *out_map)
{
    double win[11][11], ws = 0.0;
    for (int i = 0; i < 11; i++)
        for (int j = 0; j < 11; j++)
            ws += win[i][j] = exp(-((i - 5) * (i - 5) + (j - 5) * (j - 5)) / (2.0 * 1.5 * 1.5));
    double total = 0.0;
    for (uint32_t r = 0; r + 11 <= h; r++) {
        for (uint32_t c = 0; c + 11 <= w; c++) {
            double mx = 0, my = 0;
            for (int i = 0; i < 11; i++) {
                for (int j = 0; j < 11; j++) {
                    size_t p = ((r + i) * w + c + j) * 4;
                    double lx = 0.2126 * x[p] + 0.7152 * x[p + 1] + 0.0722 * x[p + 2];
                    double ly = 0.2126 * y[p] + 0.7152 * y[p + 1] + 0.0722 * y[p + 2];
                    mx += win[i][j] / ws * fmin(fmax(lx, 0.0), 1.0);
                    my += win[i][j] / ws * fmin(fmax(ly, 0.0), 1.0);
                }
            }
            double vx = 0, vy = 0, cxy = 0;
            for (int i = 0; i < 11; i++) {
                for (int j = 0; j < 11; j++) {
                    size_t p = ((r + i) * w + c + j) * 4;
                    double lx = 0.2126 * x[p] + 0.7152 * x[p + 1] + 0.0722 * x[p + 2];
                    double ly = 0.2126 * y[p] + 0.7152 * y[p + 1] + 0.0722 * y[p + 2];
                    lx = fmin(fmax(lx, 0.0), 1.0) - mx;
                    ly = fmin(fmax(ly, 0.0), 1.0) - my;
                    vx += win[i][j] / ws * lx * lx;
                    vy += win[i][j] / ws * ly * ly;
                    cxy += win[i][j] / ws * lx * ly;
                }
            }
            const double c1 = 1e-4, c2 = 9e-4;
            double s =
                (2 * mx * my + c1) * (2 * cxy + c2) / ((mx * mx + my * my + c1) * (vx + vy + c2));
            out_map[r * (w - 10) + c] = (float)s;
            total += s;
        }
    }
    return total / ((double)(w - 10) * (h - 10));
}

static void test_ssim_against_brute_force(void)
{
    /* A textured image against a noisy, offset, partly clamped (> 1) copy. */
    const uint32_t w = 29, h = 23;
    float *x = image_alloc(w, h, 4), *y = image_alloc(w, h, 4);
    float *map = image_alloc(w - 10, h - 10, 1), *ref = image_alloc(w - 10, h - 10, 1);
    uint32_t s = 777u;
    for (uint32_t j = 0; j < h; j++) {
        for (uint32_t i = 0; i < w; i++) {
            float v = 0.5f + 0.4f * (float)sin(i * 0.7) * (float)cos(j * 0.45);
            set_px(x, w, i, j, v, 0.8f * v, 1.1f * v);
            set_px(y, w, i, j, v + 0.6f * (rnd(&s) - 0.5f), 0.8f * v + 0.1f, 1.3f * v);
        }
    }
    double m = 0.0;
    CHECK_EQ_INT(xrsc_metrics_ssim(x, y, w, h, NULL, &m, map), XRSC_OK);
    double mb = ssim_brute(x, y, w, h, ref);
    CHECK_NEAR(m, mb, 1e-9);
    printf("  textured vs noisy copy: mean SSIM %.6f (brute force %.6f)\n", m, mb);
    CHECK(m < 0.99 && m > 0.0); /* a real difference, not the trivial 1 */
    float worst = 0.0f;
    for (uint32_t i = 0; i < (w - 10) * (h - 10); i++)
        worst = fmaxf(worst, fabsf(map[i] - ref[i]));
    CHECK_NEAR(worst, 0.0, 1e-6);
    free(x);
    free(y);
    free(map);
    free(ref);
}

/* ---- CPBD ---- */

/* A 64 x 64 image (one CPBD block) of grey levels (8-bit units with display_range 255 and
 * cpbd_linear): `lo` left of column 30, then the ramp levels, then `hi`. */
static float *ramp_image(float lo, const float *ramp, int ramp_len, float hi)
{
    const uint32_t n = 64;
    float *img = image_alloc(n, n, 4);
    for (uint32_t y = 0; y < n; y++) {
        for (uint32_t x = 0; x < n; x++) {
            float v = x < 30 ? lo : (x < 30u + (uint32_t)ramp_len ? ramp[x - 30] : hi);
            set_px(img, n, x, y, v, v, v);
        }
    }
    return img;
}

static double cpbd_levels(const float *img, xrsc_cpbd *out)
{
    xrsc_metrics_options o = {.display_range = 255.0, .cpbd_linear = true};
    CHECK_EQ_INT(xrsc_metrics_cpbd(img, 64, 64, &o, out), XRSC_OK);
    return out->cpbd;
}

static void test_cpbd_hand_widths(void)
{
    /* Each image has one vertical edge per row, so every interior row (62) gives one measured
     * edge pixel in the single 64 x 64 block (62 > 0.002 * 4096 = 8.2: an edge block).
     * Marziliano width = distance between the plateaus on either side of the ramp:
     * - 0 -> 255 as a step: width 1, contrast 255 > 50 so w_JNB = 3:
     *   P = 1 - exp(-(1/3)^3.6) = 0.019 <= 0.632: sharp, CPBD = 1.
     * - 0, 85, 170, 255 (plateau 0 at x = 29, 255 at x = 32): width 3 = w_JNB:
     *   P = 1 - exp(-1) = P_JNB exactly, counted as not blurred: CPBD = 1.
     * - 0, 64, 128, 192, 255: width 4: P = 1 - exp(-(4/3)^3.6) = 0.9402 > 0.632: CPBD = 0.
     * - 100 -> 140 in 5 steps of 8: width 5, contrast 40 <= 50 so w_JNB = 5: P = P_JNB: CPBD 1.
     * - 100 -> 140 in 6 steps: width 6: P = 1 - exp(-(6/5)^3.6) = 0.8545: CPBD 0.
     * - 0 -> 255 in 5 steps of 51: width 5 but contrast 255 so w_JNB = 3:
     *   P = 1 - exp(-(5/3)^3.6) = 0.9981: CPBD 0 (the same width is sharp at low contrast). */
    xrsc_cpbd r;
    const float step[] = {255.0f};
    const float r3[] = {85.0f, 170.0f, 255.0f};
    const float r4[] = {64.0f, 128.0f, 192.0f, 255.0f};
    const float r5lo[] = {108.0f, 116.0f, 124.0f, 132.0f, 140.0f};
    const float r6lo[] = {106.0f, 113.0f, 120.0f, 127.0f, 134.0f, 140.0f};
    const float r5hi[] = {51.0f, 102.0f, 153.0f, 204.0f, 255.0f};
    struct {
        float lo;
        const float *ramp;
        int len;
        float hi;
        double cpbd;
    } cases[] = {
        {0.0f, step, 1, 255.0f, 1.0},   {0.0f, r3, 3, 255.0f, 1.0},
        {0.0f, r4, 4, 255.0f, 0.0},     {100.0f, r5lo, 5, 140.0f, 1.0},
        {100.0f, r6lo, 6, 140.0f, 0.0}, {0.0f, r5hi, 5, 255.0f, 0.0},
    };
    for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); i++) {
        float *img = ramp_image(cases[i].lo, cases[i].ramp, cases[i].len, cases[i].hi);
        double c = cpbd_levels(img, &r);
        CHECK_MSG(c == cases[i].cpbd, "case %zu: cpbd %g, expected %g", i, c, cases[i].cpbd);
        CHECK_MSG(r.edge_count == 62, "case %zu: %llu edges", i, (unsigned long long)r.edge_count);
        CHECK_EQ_INT(r.edge_block_count, 1);
        CHECK_EQ_INT(r.block_count, 1);
        /* Mirrored (a falling edge) gives the same result. */
        for (uint32_t y = 0; y < 64; y++)
            for (uint32_t x = 0; x < 32; x++)
                for (int ch = 0; ch < 4; ch++) {
                    float *a = img + ((size_t)y * 64 + x) * 4 + ch;
                    float *b = img + ((size_t)y * 64 + 63 - x) * 4 + ch;
                    float t = *a;
                    *a = *b;
                    *b = t;
                }
        CHECK_MSG(cpbd_levels(img, &r) == cases[i].cpbd, "mirrored case %zu", i);
        free(img);
    }
}

static void test_cpbd_probability(void)
{
    /* 1 - exp(-(w / w_JNB)^3.6): (1/3)^3.6 = 0.0191586 -> 0.0189762; (2/3)^3.6 = 0.2323119
     * -> 0.2073012; 1 -> 1 - exp(-1) = 0.6321206; (4/3)^3.6 = 2.8169520 -> 0.9402121;
     * (6/5)^3.6 = 1.9277579 -> 0.8545260. */
    CHECK_NEAR(xrsc_metrics_cpbd_blur_probability(1, 3), 0.0189762, 1e-6);
    CHECK_NEAR(xrsc_metrics_cpbd_blur_probability(2, 3), 0.2073012, 1e-6);
    CHECK_NEAR(xrsc_metrics_cpbd_blur_probability(3, 3), 0.6321206, 1e-6);
    CHECK_NEAR(xrsc_metrics_cpbd_blur_probability(4, 3), 0.9402121, 1e-6);
    CHECK_NEAR(xrsc_metrics_cpbd_blur_probability(6, 5), 0.8545260, 1e-6);
}

static void test_cpbd_display_encoding(void)
{
    /* A 4-step ramp from linear 0.01 to 0.15. Linear 8-bit levels: 3 .. 38, contrast 35 <= 50,
     * w_JNB = 5, width 4 is sharp: CPBD 1 with cpbd_linear. sRGB-encoded (the default): levels
     * 25 (0.0998 x 255) .. 108 (0.4233 x 255), contrast 83 > 50, w_JNB = 3: blurred, CPBD 0. */
    const float ramp[] = {0.045f, 0.08f, 0.115f, 0.15f};
    float *img = ramp_image(0.01f, ramp, 4, 0.15f);
    xrsc_cpbd r;
    CHECK_EQ_INT(xrsc_metrics_cpbd(img, 64, 64, NULL, &r), XRSC_OK);
    CHECK(r.cpbd == 0.0 && r.edge_count == 62);
    xrsc_metrics_options lin = {.cpbd_linear = true};
    CHECK_EQ_INT(xrsc_metrics_cpbd(img, 64, 64, &lin, &r), XRSC_OK);
    CHECK(r.cpbd == 1.0 && r.edge_count == 62);
    free(img);
}

static void test_cpbd_blur_ranks_lower(void)
{
    /* Checkerboard of 32-pixel squares, linear 0.05 / 0.8 (sRGB 8-bit levels 63 / 231), and the
     * same blurred with Gaussians of growing sigma: CPBD must not rise, and must fall below the
     * sharp original once the blur is wider than the JNB width (sigma 0.5 widens a step to at
     * most 3 pixels, which is not yet perceivable, so it may stay at 1). */
    const uint32_t w = 128, h = 128;
    float *img = image_alloc(w, h, 4);
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++) {
            float v = ((x / 32) + (y / 32)) % 2 ? 0.8f : 0.05f;
            set_px(img, w, x, y, v, v, v);
        }
    xrsc_cpbd sharp, prev;
    CHECK_EQ_INT(xrsc_metrics_cpbd(img, w, h, NULL, &sharp), XRSC_OK);
    CHECK(sharp.edge_count > 100);
    CHECK_NEAR(sharp.cpbd, 1.0, 1e-12); /* step edges: width 1 everywhere */
    CHECK_EQ_INT(sharp.block_count, 4);
    prev = sharp;
    const double sigmas[] = {0.5, 1.0, 1.5, 2.5};
    float *b = image_alloc(w, h, 4);
    for (size_t i = 0; i < 4; i++) {
        memcpy(b, img, (size_t)w * h * 4 * sizeof(float));
        gaussian_blur(b, w, h, sigmas[i]);
        xrsc_cpbd r;
        CHECK_EQ_INT(xrsc_metrics_cpbd(b, w, h, NULL, &r), XRSC_OK);
        printf("  checkerboard blurred sigma %.1f: CPBD %.4f (%llu edges), sharp %.4f\n", sigmas[i],
               r.cpbd, (unsigned long long)r.edge_count, sharp.cpbd);
        CHECK(r.edge_count > 0);
        CHECK(r.cpbd <= prev.cpbd);
        if (sigmas[i] >= 1.0)
            CHECK(r.cpbd < sharp.cpbd);
        prev = r;
    }
    CHECK(prev.cpbd < 0.1);

    /* Half sharp, half blurred (sigma 1.5 right of column 64): CPBD in between, near the
     * share of the sharp half's edges. */
    memcpy(b, img, (size_t)w * h * 4 * sizeof(float));
    gaussian_blur(b, w, h, 1.5);
    for (uint32_t y = 0; y < h; y++)
        memcpy(b + ((size_t)y * w) * 4, img + ((size_t)y * w) * 4, 64 * 4 * sizeof(float));
    xrsc_cpbd half;
    CHECK_EQ_INT(xrsc_metrics_cpbd(b, w, h, NULL, &half), XRSC_OK);
    printf("  checkerboard half blurred: CPBD %.4f (%llu edges)\n", half.cpbd,
           (unsigned long long)half.edge_count);
    CHECK(half.cpbd > 0.25 && half.cpbd < 0.75);
    free(img);
    free(b);
}

static void test_cpbd_constant_and_sizes(void)
{
    /* No gradient, no edge: CPBD 0 with edge_count 0 (documented). */
    float *img = image_alloc(100, 70, 4);
    fill_grey(img, 100 * 70, 0.3f);
    xrsc_cpbd r = {.cpbd = -1.0};
    CHECK_EQ_INT(xrsc_metrics_cpbd(img, 100, 70, NULL, &r), XRSC_OK);
    CHECK(r.cpbd == 0.0);
    CHECK_EQ_INT(r.edge_count, 0);
    CHECK_EQ_INT(r.edge_block_count, 0);
    CHECK_EQ_INT(r.block_count, 4); /* ceil(100/64) x ceil(70/64), partial blocks included */
    /* Tiny images are fine (no interior gradient). */
    CHECK_EQ_INT(xrsc_metrics_cpbd(img, 2, 2, NULL, &r), XRSC_OK);
    CHECK(r.cpbd == 0.0);
    img[9] = NAN;
    CHECK_EQ_INT(xrsc_metrics_cpbd(img, 100, 70, NULL, &r), XRSC_ERROR_NAN);
    free(img);
}

/* ---- reprojection: an independent CPU "renderer" of analytic scenes ---- */

/* Camera with yaw (about +Y) and pitch (about the yawed +X) so the rotation is written out here
 * with sines and cosines rather than through xrsc_math. */
typedef struct cam {
    double pos[3];
    double yaw, pitch;     /* radians */
    double tl, tr, tu, td; /* tangents of the fov angles */
    uint32_t w, h;
} cam;

static cam make_cam(double x, double y, double z, double yaw_deg, double pitch_deg, uint32_t w,
                    uint32_t h)
{
    cam c = {{x, y, z},
             yaw_deg * PI / 180.0,
             pitch_deg * PI / 180.0,
             tan(-50.0 * PI / 180.0),
             tan(40.0 * PI / 180.0),
             tan(45.0 * PI / 180.0),
             tan(-48.0 * PI / 180.0),
             w,
             h};
    return c;
}

/* Eye-to-world rotation R = R_yaw(Y) * R_pitch(X) applied to v. */
static void cam_rotate(const cam *c, const double v[3], double out[3])
{
    double cp = cos(c->pitch), sp = sin(c->pitch), cy = cos(c->yaw), sy = sin(c->yaw);
    double a[3] = {v[0], cp * v[1] - sp * v[2], sp * v[1] + cp * v[2]}; /* pitch about X */
    out[0] = cy * a[0] + sy * a[2];                                     /* yaw about Y */
    out[1] = a[1];
    out[2] = -sy * a[0] + cy * a[2];
}

/* The same camera for the metrics: quaternion q = q_yaw * q_pitch. */
static xrsc_metrics_camera to_metrics(const cam *c)
{
    XrQuaternionf qy = {0.0f, (float)sin(c->yaw / 2), 0.0f, (float)cos(c->yaw / 2)};
    XrQuaternionf qp = {(float)sin(c->pitch / 2), 0.0f, 0.0f, (float)cos(c->pitch / 2)};
    XrQuaternionf q = {qy.w * qp.x + qy.x * qp.w + qy.y * qp.z - qy.z * qp.y,
                       qy.w * qp.y - qy.x * qp.z + qy.y * qp.w + qy.z * qp.x,
                       qy.w * qp.z + qy.x * qp.y - qy.y * qp.x + qy.z * qp.w,
                       qy.w * qp.w - qy.x * qp.x - qy.y * qp.y - qy.z * qp.z};
    xrsc_metrics_camera m = {
        .pose = {q, {(float)c->pos[0], (float)c->pos[1], (float)c->pos[2]}},
        .fov = {(float)atan(c->tl), (float)atan(c->tr), (float)atan(c->tu), (float)atan(c->td)},
        .width = c->w,
        .height = c->h,
    };
    return m;
}

/* The renderer's ray (xs_camera.glsl): eye direction (mix(tl, tr, u), mix(tu, td, v), -1) at
 * the pixel centre, v = 0 on the top row; flip_v renders with v = 0 at the bottom instead. */
static void cam_ray(const cam *c, uint32_t x, uint32_t y, bool flip_v, double out_dir[3])
{
    double u = (x + 0.5) / c->w, v = (y + 0.5) / c->h;
    if (flip_v)
        v = 1.0 - v;
    double d[3] = {c->tl + (c->tr - c->tl) * u, c->tu + (c->td - c->tu) * v, -1.0};
    cam_rotate(c, d, out_dir);
}

/* Smooth textures (periods of a metre or more, so bilinear reads are accurate). */
static void tex_plane(const double p[3], double out[3])
{
    out[0] = 0.5 + 0.3 * sin(2 * PI * p[0] / 1.5);
    out[1] = 0.5 + 0.3 * sin(2 * PI * p[1] / 1.2 + 1.0);
    out[2] = 0.5 + 0.3 * cos(2 * PI * (p[0] + p[1]) / 1.7);
}

/* Scene A: the tilted plane n . X = c with n = (-0.2, -0.3, 1), c = -3 (z = -3 + 0.2 x + 0.3 y),
 * textured. depth = t for the unnormalised eye direction (its eye z is -1). */
static void render_plane(const cam *c, bool flip_v, float *rgba, float *depth)
{
    const double n[3] = {-0.2, -0.3, 1.0}, pc = -3.0;
    for (uint32_t y = 0; y < c->h; y++) {
        for (uint32_t x = 0; x < c->w; x++) {
            double d[3], col[3] = {0, 0, 0}, t = 0.0;
            cam_ray(c, x, y, flip_v, d);
            double nd = n[0] * d[0] + n[1] * d[1] + n[2] * d[2];
            double no = n[0] * c->pos[0] + n[1] * c->pos[1] + n[2] * c->pos[2];
            if (fabs(nd) > 1e-9 && (pc - no) / nd > 0.0) {
                t = (pc - no) / nd;
                double p[3] = {c->pos[0] + t * d[0], c->pos[1] + t * d[1], c->pos[2] + t * d[2]};
                tex_plane(p, col);
            }
            size_t i = (size_t)y * c->w + x;
            set_px(rgba, c->w, x, y, (float)col[0], (float)col[1], (float)col[2]);
            depth[i] = (float)t;
        }
    }
}

static void test_reproject_conventions(void)
{
    /* Identity camera: the point d * (tanL, tanU, -1) is the top-left image corner (0, 0), and
     * d * (tanR, tanD, -1) the bottom-right corner (w, h): v = 0 is the TOP row, and depth is the
     * distance along -Z. */
    cam c = make_cam(0, 0, 0, 0, 0, 64, 48);
    xrsc_metrics_camera m = to_metrics(&c);
    double x, y, d;
    CHECK(xrsc_metrics_reproject(&m, 0.0, 0.0, 2.0, &m, &x, &y, &d));
    CHECK_NEAR(x, 0.0, 1e-4);
    CHECK_NEAR(y, 0.0, 1e-4);
    CHECK_NEAR(d, 2.0, 1e-5);
    CHECK(xrsc_metrics_reproject(&m, 10.5, 20.5, 3.0, &m, &x, &y, &d));
    CHECK_NEAR(x, 10.5, 1e-4);
    CHECK_NEAR(y, 20.5, 1e-4);
    CHECK_NEAR(d, 3.0, 1e-5);

    /* A point 2 m straight ahead (0, 0, -2) seen from a camera 1 m to its right, yawed 10 deg to
     * the left (towards the point). In that camera's eye space (inverse rotation of the offset
     * (-1, 0, -2)): x_e = cos(10) * -1 - sin(10) * -2 = -0.637511, z_e = sin(10) * -1 +
     * cos(10) * -2 = -2.143264; depth 2.143264; u = (x_e / -z_e - tanL) / (tanR - tanL) with
     * x_e / -z_e = -0.297449, tanL = -1.191754, tanR = 0.839100: u = 0.440359 -> 28.1830 px;
     * y_e = 0 -> v = tanU / (tanU - tanD) = 1 / 2.110613 = 0.473796 -> 22.7422 px of 48. */
    cam a = make_cam(0, 0, 0, 0, 0, 64, 48), b = make_cam(1, 0, 0, 10, 0, 64, 48);
    xrsc_metrics_camera ma = to_metrics(&a), mb = to_metrics(&b);
    /* (0, 0, -2) in camera a is at u = -tanL / (tanR - tanL), v = tanU / (tanU - tanD). */
    double ua = -a.tl / (a.tr - a.tl) * 64.0, va = a.tu / (a.tu - a.td) * 48.0;
    CHECK(xrsc_metrics_reproject(&ma, ua, va, 2.0, &mb, &x, &y, &d));
    CHECK_NEAR(d, 2.143264, 1e-5);
    CHECK_NEAR(x, 28.1830, 2e-3);
    CHECK_NEAR(y, 22.7422, 2e-3);
    /* ... and back. */
    double x2, y2, d2;
    CHECK(xrsc_metrics_reproject(&mb, x, y, d, &ma, &x2, &y2, &d2));
    CHECK_NEAR(x2, ua, 1e-3);
    CHECK_NEAR(y2, va, 1e-3);
    CHECK_NEAR(d2, 2.0, 1e-5);
    /* Behind the target camera: no position. */
    cam behind = make_cam(0, 0, -5, 0, 0, 64, 48);
    xrsc_metrics_camera mbh = to_metrics(&behind);
    CHECK(!xrsc_metrics_reproject(&ma, ua, va, 2.0, &mbh, &x, &y, &d));
}

static void test_temporal_static_is_zero(void)
{
    cam c = make_cam(0.3, 1.2, 0.5, 20, -10, 96, 80);
    float *rgba = image_alloc(c.w, c.h, 4), *depth = image_alloc(c.w, c.h, 1);
    render_plane(&c, false, rgba, depth);
    /* Some background (no depth) pixels to check they are skipped. */
    for (uint32_t x = 0; x < 10; x++)
        depth[x] = 0.0f;
    size_t bg = 0;
    for (size_t i = 0; i < (size_t)c.w * c.h; i++)
        bg += depth[i] == 0.0f;
    xrsc_metrics_view v = {rgba, depth, to_metrics(&c)};
    uint8_t *status = calloc((size_t)c.w * c.h, 1);
    xrsc_reproj_diff r;
    CHECK_EQ_INT(xrsc_metrics_temporal_diff(&v, &v, NULL, &r, status, NULL), XRSC_OK);
    CHECK(r.mean_sq_diff == 0.0);
    CHECK_EQ_INT(r.foreground_count, (uint64_t)c.w * c.h - bg);
    /* Each foreground pixel reads exactly itself: all valid. */
    CHECK_EQ_INT(r.valid_count, r.foreground_count);
    CHECK_EQ_INT(status[0], XRSC_REPROJ_BACKGROUND);
    CHECK_EQ_INT(status[c.w * c.h - 1], XRSC_REPROJ_VALID);
    free(rgba);
    free(depth);
    free(status);
}

static void test_temporal_plane_two_poses(void)
{
    /* Frame t-1 and frame t of a textured tilted plane rendered analytically from two poses
     * (5 cm / 3 cm / 8 cm move, 3 deg yaw, 2 deg pitch). Reprojection by depth must explain the
     * change: the difference is only bilinear interpolation error (~1e-5), whereas a previous
     * frame rendered with v flipped (wrong convention) or compared without reprojection is far
     * off. */
    cam c1 = make_cam(0.0, 0.0, 0.0, 0, 0, 128, 112);
    cam c2 = make_cam(0.05, 0.03, -0.08, 3, 2, 128, 112);
    size_t n = (size_t)128 * 112;
    float *rgb1 = image_alloc(128, 112, 4), *dep1 = image_alloc(128, 112, 1);
    float *rgb2 = image_alloc(128, 112, 4), *dep2 = image_alloc(128, 112, 1);
    float *rgbf = image_alloc(128, 112, 4), *depf = image_alloc(128, 112, 1);
    float *sq = image_alloc(128, 112, 1);
    uint8_t *status = calloc(n, 1);
    render_plane(&c1, false, rgb1, dep1);
    render_plane(&c2, false, rgb2, dep2);
    render_plane(&c1, true, rgbf, depf);
    xrsc_metrics_view prev = {rgb1, dep1, to_metrics(&c1)}, cur = {rgb2, dep2, to_metrics(&c2)};
    xrsc_metrics_view flipped = {rgbf, depf, to_metrics(&c1)};
    xrsc_reproj_diff r, rf, rn;
    CHECK_EQ_INT(xrsc_metrics_temporal_diff(&cur, &prev, NULL, &r, status, sq), XRSC_OK);
    CHECK_EQ_INT(xrsc_metrics_temporal_diff(&cur, &flipped, NULL, &rf, NULL, NULL), XRSC_OK);
    /* No reprojection: the previous frame as if rendered from the current pose. */
    xrsc_metrics_view naive = {rgb1, dep1, to_metrics(&c2)};
    CHECK_EQ_INT(xrsc_metrics_temporal_diff(&cur, &naive, NULL, &rn, NULL, NULL), XRSC_OK);
    printf("  plane, two poses: reprojected %.3g over %llu px; v flipped %.3g over %llu px; "
           "not reprojected %.3g\n",
           r.mean_sq_diff, (unsigned long long)r.valid_count, rf.mean_sq_diff,
           (unsigned long long)rf.valid_count, rn.mean_sq_diff);
    CHECK(r.valid_count > n * 8 / 10);
    CHECK(r.mean_sq_diff < 1e-4);
    CHECK(rf.mean_sq_diff > 100.0 * r.mean_sq_diff);
    CHECK(rn.mean_sq_diff > 100.0 * r.mean_sq_diff);
    /* Status and per-pixel output agree with the counts. */
    uint64_t valid = 0;
    double sum = 0.0;
    bool zero_where_invalid = true;
    for (size_t i = 0; i < n; i++) {
        if (status[i] == XRSC_REPROJ_VALID) {
            valid++;
            sum += sq[i];
        } else if (sq[i] != 0.0f) {
            zero_where_invalid = false;
        }
    }
    CHECK_EQ_INT(valid, r.valid_count);
    CHECK_NEAR(sum / (double)valid, r.mean_sq_diff, 1e-9);
    CHECK(zero_where_invalid);
    free(rgb1);
    free(dep1);
    free(rgb2);
    free(dep2);
    free(rgbf);
    free(depf);
    free(sq);
    free(status);
}

/* Scene B: background plane z = -4 (blue-ish texture) and a foreground square |x|, |y| <= 0.5
 * at z = -2 (red-ish texture), facing +Z. */
#define FG_Z (-2.0)
#define FG_HALF 0.5
#define BG_Z (-4.0)

/* Does the ray o + t d hit the square of half side `half` at z = FG_Z? */
static bool hits_square(const double o[3], const double d[3], double half, double *out_t)
{
    if (d[2] >= 0.0)
        return false;
    double t = (FG_Z - o[2]) / d[2];
    double x = o[0] + t * d[0], y = o[1] + t * d[1];
    if (t <= 0.0 || fabs(x) > half || fabs(y) > half)
        return false;
    *out_t = t;
    return true;
}

static bool hits_fg(const double o[3], const double d[3], double *out_t)
{
    return hits_square(o, d, FG_HALF, out_t);
}

static void render_step(const cam *c, float *rgba, float *depth)
{
    for (uint32_t y = 0; y < c->h; y++) {
        for (uint32_t x = 0; x < c->w; x++) {
            double d[3], t, col[3];
            cam_ray(c, x, y, false, d);
            bool fg = hits_fg(c->pos, d, &t);
            if (!fg)
                t = (BG_Z - c->pos[2]) / d[2];
            double p[3] = {c->pos[0] + t * d[0], c->pos[1] + t * d[1], c->pos[2] + t * d[2]};
            tex_plane(p, col);
            if (fg)
                set_px(rgba, c->w, x, y, (float)(0.6 + 0.4 * col[0]), (float)(0.2 * col[1]),
                       (float)(0.1 * col[2]));
            else
                set_px(rgba, c->w, x, y, (float)(0.1 * col[0]), (float)(0.3 * col[1]),
                       (float)(0.5 + 0.4 * col[2]));
            depth[(size_t)y * c->w + x] = (float)t;
        }
    }
}

static void test_stereo_excludes_disocclusion(void)
{
    /* Two eyes 0.5 m apart (a wide baseline so the disoccluded strips beside the square are
     * several pixels wide at 96 x 96), both looking down -Z. A background point seen by the
     * right eye is occluded for the left eye when the segment from the left eye to it crosses
     * the square: those pixels must be excluded; the rest must agree (discrepancy ~0). */
    const uint32_t w = 96, h = 96;
    const size_t n = (size_t)w * h;
    cam left = make_cam(-0.25, 0, 0, 0, 0, w, h), right = make_cam(0.25, 0, 0, 0, 0, w, h);
    float *rl = image_alloc(w, h, 4), *dl = image_alloc(w, h, 1);
    float *rr = image_alloc(w, h, 4), *dr = image_alloc(w, h, 1);
    uint8_t *status = calloc(n, 1);
    render_step(&left, rl, dl);
    render_step(&right, rr, dr);
    xrsc_metrics_view vl = {rl, dl, to_metrics(&left)}, vr = {rr, dr, to_metrics(&right)};
    xrsc_reproj_diff r, loose;
    /* Seed 000 Fig. 15: the left eye reprojected onto the right view. */
    CHECK_EQ_INT(xrsc_metrics_stereo_discrepancy(&vr, &vl, NULL, &r, status, NULL), XRSC_OK);
    xrsc_metrics_options no_depth_test = {.depth_tolerance = 1e9};
    CHECK_EQ_INT(xrsc_metrics_stereo_discrepancy(&vr, &vl, &no_depth_test, &loose, NULL, NULL),
                 XRSC_OK);

    size_t occluded = 0, occluded_excluded = 0, visible_far = 0, visible_far_valid = 0;
    for (uint32_t y = 0; y < h; y++) {
        for (uint32_t x = 0; x < w; x++) {
            double d[3], t;
            cam_ray(&right, x, y, false, d);
            if (hits_fg(right.pos, d, &t))
                continue; /* foreground: seen by both eyes */
            t = (BG_Z - right.pos[2]) / d[2];
            double p[3] = {right.pos[0] + t * d[0], right.pos[1] + t * d[1], BG_Z};
            double to_p[3] = {p[0] - left.pos[0], p[1] - left.pos[1], p[2] - left.pos[2]}, tf;
            size_t i = (size_t)y * w + x;
            if (hits_fg(left.pos, to_p, &tf) && tf < 1.0) {
                occluded++;
                occluded_excluded += status[i] == XRSC_REPROJ_DEPTH_MISMATCH;
            } else if (x > 20 && x < w - 20 && y > 4 && y < h - 4 && dr[i] > 3.0f &&
                       !(hits_square(left.pos, to_p, FG_HALF + 0.15, &tf) && tf < 1.0)) {
                /* visible background away from the image border and from the square's edge in
                 * both eyes (0.15 m at 2 m is about 3.5 pixels in the left eye; in the right eye
                 * its 5 x 5 neighbourhood is background) */
                bool near_edge = false;
                for (uint32_t yy = y - 2; yy <= y + 2; yy++)
                    for (uint32_t xx = x - 2; xx <= x + 2; xx++)
                        near_edge |= dr[(size_t)yy * w + xx] < 3.0f;
                if (!near_edge) {
                    visible_far++;
                    visible_far_valid += status[i] == XRSC_REPROJ_VALID;
                }
            }
        }
    }
    printf("  stereo step: %zu occluded px (%zu excluded), discrepancy %.3g over %llu px; "
           "without depth test %.3g over %llu px\n",
           occluded, occluded_excluded, r.mean_sq_diff, (unsigned long long)r.valid_count,
           loose.mean_sq_diff, (unsigned long long)loose.valid_count);
    /* The strip exists: disparity difference 0.5 m x 47 px x (1/2 - 1/4 m^-1) = 5.9 px, the
     * square 23 rows tall (f = 96 / (tan 50 + tan 40) = 47.3 px; 96 / (tan 45 + tan 48) = 45.5). */
    CHECK(occluded > 100);
    CHECK_EQ_INT(occluded_excluded, occluded);
    CHECK_EQ_INT(visible_far_valid, visible_far);
    CHECK(visible_far > n / 3);
    CHECK(r.mean_sq_diff < 1e-4);
    CHECK(loose.valid_count > r.valid_count + occluded / 2);
    CHECK(loose.mean_sq_diff > 100.0 * r.mean_sq_diff);
    free(rl);
    free(dl);
    free(rr);
    free(dr);
    free(status);
}

static void test_reproj_bad_input(void)
{
    float rgba[4 * 4] = {0}, depth[4] = {1, 1, 1, 1};
    cam c = make_cam(0, 0, 0, 0, 0, 2, 2);
    xrsc_metrics_view v = {rgba, depth, to_metrics(&c)};
    xrsc_reproj_diff r;
    CHECK_EQ_INT(xrsc_metrics_temporal_diff(&v, NULL, NULL, &r, NULL, NULL),
                 XRSC_ERROR_INVALID_ARGUMENT);
    CHECK_EQ_INT(xrsc_metrics_temporal_diff(&v, &v, NULL, NULL, NULL, NULL),
                 XRSC_ERROR_INVALID_ARGUMENT);
    xrsc_metrics_view nodepth = {rgba, NULL, to_metrics(&c)};
    CHECK_EQ_INT(xrsc_metrics_temporal_diff(&v, &nodepth, NULL, &r, NULL, NULL),
                 XRSC_ERROR_INVALID_ARGUMENT);
    depth[2] = NAN;
    CHECK_EQ_INT(xrsc_metrics_stereo_discrepancy(&v, &v, NULL, &r, NULL, NULL), XRSC_ERROR_NAN);
    /* All background: nothing valid, mean 0. */
    memset(depth, 0, sizeof(depth));
    CHECK_EQ_INT(xrsc_metrics_temporal_diff(&v, &v, NULL, &r, NULL, NULL), XRSC_OK);
    CHECK(r.valid_count == 0 && r.foreground_count == 0 && r.mean_sq_diff == 0.0);
}

/* ---- the `xrsc metrics` subcommand ---- */

static int run_cmd(int argc, const char **argv)
{
    return hs_metrics_main(argc, (char **)argv);
}

static void test_cli(void)
{
    char ref_dir[] = "/tmp/xrsc-metrics-ref-XXXXXX", test_dir[] = "/tmp/xrsc-metrics-test-XXXXXX";
    CHECK(mkdtemp(ref_dir) != NULL);
    CHECK(mkdtemp(test_dir) != NULL);
    const uint32_t w = 16, h = 12;
    float *r = image_alloc(w, h, 4), *t = image_alloc(w, h, 4);
    uint32_t st = 99u;
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++)
            set_px(r, w, x, y, rnd(&st), rnd(&st), rnd(&st));
    char path[4][512];
    snprintf(path[0], sizeof(path[0]), "%s/f_000.pfm", ref_dir);
    snprintf(path[1], sizeof(path[1]), "%s/f_001.pfm", ref_dir);
    snprintf(path[2], sizeof(path[2]), "%s/f_000.pfm", test_dir);
    snprintf(path[3], sizeof(path[3]), "%s/f_001.pfm", test_dir);
    /* Frame 0 identical, frame 1 the reference + 0.1 in every channel. */
    CHECK_EQ_INT(hs_write_pfm(path[0], r, w, h, NULL), XRSC_OK);
    CHECK_EQ_INT(hs_write_pfm(path[1], r, w, h, NULL), XRSC_OK);
    CHECK_EQ_INT(hs_write_pfm(path[2], r, w, h, NULL), XRSC_OK);
    memcpy(t, r, (size_t)w * h * 4 * sizeof(float));
    for (size_t i = 0; i < (size_t)w * h * 4; i++)
        t[i] += 0.1f;
    CHECK_EQ_INT(hs_write_pfm(path[3], t, w, h, NULL), XRSC_OK);
    xrsc_error_metrics e1;
    double ssim1;
    CHECK_EQ_INT(xrsc_metrics_error(t, r, w, h, NULL, &e1), XRSC_OK);
    CHECK_EQ_INT(xrsc_metrics_ssim(t, r, w, h, NULL, &ssim1, NULL), XRSC_OK);

    const char *csv = t_temp_file("metrics.csv", "");
    const char *ok[] = {"metrics",   "--ref",      ref_dir, "--test", test_dir,
                        "--pattern", "f_%03u.pfm", "--csv", csv,      "--quiet"};
    CHECK_EQ_INT(run_cmd(10, ok), 0);
    FILE *f = fopen(csv, "r");
    CHECK(f != NULL);
    if (f) {
        char line[512];
        unsigned frame[2] = {9, 9};
        double v[2][6] = {{0}};
        CHECK(fgets(line, sizeof(line), f) && !strncmp(line, "frame,relmse,rmse,mse,ssim", 26));
        for (int k = 0; k < 2; k++)
            CHECK(fscanf(f, "%u,%lf,%lf,%lf,%lf,%lf,%lf,%*u,%*u,-,0\n", &frame[k], &v[k][0],
                         &v[k][1], &v[k][2], &v[k][3], &v[k][4], &v[k][5]) == 7);
        CHECK(fgets(line, sizeof(line), f) == NULL); /* exactly two frames */
        fclose(f);
        CHECK(frame[0] == 0 && frame[1] == 1);
        CHECK(v[0][0] == 0.0 && v[0][1] == 0.0 && v[0][3] == 1.0);
        CHECK_NEAR(v[1][0], e1.relmse, 1e-8);
        CHECK_NEAR(v[1][1], 0.1, 1e-6);
        CHECK_NEAR(v[1][3], ssim1, 1e-8);
    }

    /* Errors: a pattern without exactly one %u, a missing option, a frame count the reference
     * does not have, mismatched sizes. */
    const char *bad_pattern[] = {"metrics", "--ref",     ref_dir,   "--test",
                                 test_dir,  "--pattern", "f_%s.pfm"};
    CHECK_EQ_INT(run_cmd(7, bad_pattern), 2);
    const char *two[] = {"metrics", "--ref",     ref_dir,        "--test",
                         test_dir,  "--pattern", "f_%03u_%u.pfm"};
    CHECK_EQ_INT(run_cmd(7, two), 2);
    const char *no_test[] = {"metrics", "--ref", ref_dir};
    CHECK_EQ_INT(run_cmd(3, no_test), 2);
    const char *three[] = {"metrics",   "--ref",      ref_dir,    "--test", test_dir,
                           "--pattern", "f_%03u.pfm", "--frames", "3",      "--quiet"};
    CHECK_EQ_INT(run_cmd(10, three), 1);
    CHECK_EQ_INT(hs_write_pfm(path[3], t, w, h - 1, NULL), XRSC_OK);
    CHECK_EQ_INT(run_cmd(10, ok), 1);

    for (int k = 0; k < 4; k++)
        remove(path[k]);
    remove(csv);
    rmdir(ref_dir);
    rmdir(test_dir);
    free(r);
    free(t);
}

int main(void)
{
    RUN(test_error_hand_2x2);
    RUN(test_error_bad_input);
    RUN(test_ssim_window);
    RUN(test_ssim_identical_and_constant);
    RUN(test_ssim_against_brute_force);
    RUN(test_cpbd_hand_widths);
    RUN(test_cpbd_probability);
    RUN(test_cpbd_display_encoding);
    RUN(test_cpbd_blur_ranks_lower);
    RUN(test_cpbd_constant_and_sizes);
    RUN(test_reproject_conventions);
    RUN(test_temporal_static_is_zero);
    RUN(test_temporal_plane_two_poses);
    RUN(test_stereo_excludes_disocclusion);
    RUN(test_reproj_bad_input);
    RUN(test_cli);
    return t_finish();
}
