// SPDX-License-Identifier: MIT
/**
 * @file test_autoexposure.c
 * @brief Issue 11: automatic exposure (hs_autoexposure, hs_image.h) maps a dark and a bright
 *        frame to similar mean tone-mapped brightness (a fixed exposure does not), is
 *        proportional to 1 / scene scale, keeps large bright areas below white, skips
 *        non-finite pixels, and adapts over frames without jumping (a replay does not
 *        flicker).
 */
#include "hs_image.h"
#include "testing.h"

#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdlib.h>

#define T_W 48u
#define T_H 32u

/** A frame with a spread of values (a gradient and a few bright spots), scaled by k. */
static void make_frame(float *rgba, float k)
{
    for (uint32_t y = 0; y < T_H; y++)
        for (uint32_t x = 0; x < T_W; x++) {
            float *p = &rgba[(y * T_W + x) * 4];
            float v = 0.05f + 0.5f * (float)x / T_W + 0.2f * (float)y / T_H;
            if ((x * 13 + y * 7) % 97 == 0) v = 8.0f; /* highlights */
            p[0] = k * v;
            p[1] = k * v * 0.9f;
            p[2] = k * v * 0.7f;
            p[3] = 1.0f;
        }
}

static double mean8(const float *rgba, float exposure)
{
    static uint8_t rgb[T_W * T_H * 3];
    hs_tonemap tm = {.exposure = exposure};
    hs_tonemap_rgba(&tm, rgba, T_W, T_H, rgb);
    double s = 0.0;
    for (uint32_t i = 0; i < T_W * T_H * 3; i++) s += rgb[i];
    return s / (T_W * T_H * 3.0);
}

static float auto_of(const float *rgba)
{
    hs_autoexposure ae = {0};
    const float *eyes[2] = {rgba, rgba};
    return hs_autoexposure_update(&ae, eyes, 2, T_W, T_H);
}

static void test_dark_and_bright_similar(void)
{
    static float dark[T_W * T_H * 4], bright[T_W * T_H * 4];
    make_frame(dark, 0.01f);
    make_frame(bright, 50.0f);
    double d = mean8(dark, auto_of(dark)), b = mean8(bright, auto_of(bright));
    double d1 = mean8(dark, 1.0f), b1 = mean8(bright, 1.0f);
    printf("  mean 8-bit value: dark %.1f, bright %.1f (auto); %.1f, %.1f (exposure 1)\n", d, b,
           d1, b1);
    CHECK_MSG(fabs(d - b) < 0.03 * (d + b) / 2, "auto: dark %.1f vs bright %.1f", d, b);
    CHECK(d > 60.0 && d < 200.0);                /* mid-tones, neither black nor white */
    CHECK(d1 < 20.0 && b1 > 240.0);              /* a fixed exposure cannot do both */
    /* exposure ~ 1 / scale (the log average is scale-equivariant up to HS_AUTO_DELTA, which
     * the dark frame's darkest pixels, 3.5e-4, come near) */
    CHECK_NEAR(auto_of(dark) * 0.01, auto_of(bright) * 50.0, 0.05 * auto_of(bright) * 50.0);
}

/** Half the frame very dark, half bright: the key alone would push the bright half to white;
 *  the bright percentile keeps it at HS_AUTO_WHITE. */
static void test_bright_area_not_blown(void)
{
    static float f[T_W * T_H * 4];
    for (uint32_t i = 0; i < T_W * T_H; i++)
        for (int c = 0; c < 4; c++) f[i * 4 + c] = c == 3 ? 1.0f : (i % T_W < T_W / 2 ? 1e-3f : 1.0f);
    float e = auto_of(f);
    CHECK_NEAR(e, HS_AUTO_WHITE, 0.03 * HS_AUTO_WHITE); /* the bright half (1.0) at 0.5 */
    static uint8_t rgb[T_W * T_H * 3];
    hs_tonemap tm = {.exposure = e};
    hs_tonemap_rgba(&tm, f, T_W, T_H, rgb);
    printf("  half dark, half bright: exposure %.3f (key alone: %.1f), bright half at %u\n", e,
           HS_AUTO_KEY / sqrt(1e-3 * 1.0), rgb[(T_W - 1) * 3]);
    CHECK(rgb[(T_W - 1) * 3] > 180 && rgb[(T_W - 1) * 3] < 230);
}

static void test_non_finite_skipped(void)
{
    static float f[T_W * T_H * 4];
    make_frame(f, 1.0f);
    float e = auto_of(f);
    f[0] = NAN;
    f[5] = INFINITY;
    float e2 = auto_of(f);
    CHECK(isfinite(e2));
    CHECK_NEAR(e2, e, 0.02 * e);
    /* an all-black frame: the largest exposure, finite */
    for (uint32_t i = 0; i < T_W * T_H * 4; i++) f[i] = 0.0f;
    CHECK_NEAR(auto_of(f), HS_AUTO_MAX, 0.0);
}

static void test_temporal_smoothing(void)
{
    static float dark[T_W * T_H * 4], bright[T_W * T_H * 4];
    make_frame(dark, 0.1f);
    make_frame(bright, 10.0f);
    const float *d2[2] = {dark, dark}, *b2[2] = {bright, bright};
    hs_autoexposure ae = {0};
    float e_dark = 0.0f;
    for (int i = 0; i < 40; i++) e_dark = hs_autoexposure_update(&ae, d2, 2, T_W, T_H);
    CHECK_NEAR(e_dark, auto_of(dark), 1e-3 * e_dark);
    /* a step to a 100x brighter frame: each frame's exposure moves by at most the factor
     * 100^HS_AUTO_ADAPT (no jump), monotonically, and settles on the bright frame's */
    float prev = e_dark, max_step = 0.0f;
    bool monotone = true;
    for (int i = 0; i < 60; i++) {
        float e = hs_autoexposure_update(&ae, b2, 2, T_W, T_H);
        monotone &= e <= prev;
        max_step = fmaxf(max_step, prev / e);
        prev = e;
    }
    printf("  step x100: largest frame-to-frame exposure change x%.3f, settled at %.4f "
           "(fresh %.4f)\n", max_step, prev, auto_of(bright));
    CHECK(monotone);
    CHECK(max_step <= powf(100.0f, (float)HS_AUTO_ADAPT) * 1.01f);
    CHECK_NEAR(prev, auto_of(bright), 0.01 * prev);
}

int main(void)
{
    RUN(test_dark_and_bright_similar);
    RUN(test_bright_area_not_blown);
    RUN(test_non_finite_skipped);
    RUN(test_temporal_smoothing);
    return t_finish();
}
