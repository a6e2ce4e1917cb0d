// SPDX-License-Identifier: MIT
/**
 * @file test_image.c
 * @brief Image output (hs_image.h): PFM round trip and orientation, PNG read back with libpng,
 *        the display tone curve, and the side-by-side layout.
 */
#include "hs_image.h"
#include "testing.h"

#include <float.h>
#include <math.h>
#include <png.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* ---- helpers ---- */

static void write_bytes(const char *path, const void *data, size_t size)
{
    FILE *f = fopen(path, "wb");
    if (f) {
        fwrite(data, 1, size, f);
        fclose(f);
    }
}

/* Independent reference of the documented tone curve (hs_image.h): ACES fit of Narkowicz
 * (2015) clamped to 1, then the sRGB OETF, in double precision. */
static double ref_tonemap(double x)
{
    if (!(x > 0.0))
        return 0.0;
    double y = x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14);
    if (y > 1.0)
        y = 1.0;
    double s = y <= 0.0031308 ? 12.92 * y : 1.055 * pow(y, 1.0 / 2.4) - 0.055;
    return s * 255.0;
}

/* Tone maps one grey value: returns the red channel's 8-bit output. */
static int tonemap1(float v, float exposure)
{
    float px[4] = {v, v, v, 1.0f};
    uint8_t out[3] = {0};
    hs_tonemap tm = {.exposure = exposure};
    hs_tonemap_rgba(&tm, px, 1, 1, out);
    return out[0];
}

/* ---- PFM ---- */

enum { PFM_W = 5, PFM_H = 3 };

static void fill_pfm_pattern(float *rgba)
{
    /* Values whose bits a lossy path would change: denormal, -0, huge, inf, NaN payload. */
    static const float special[] = {0.0f, -0.0f, 1e-40f, FLT_MAX, -3.5f, 0.1f, 1.0f / 3.0f};
    uint32_t nan_bits = 0x7fc01234u;
    float nan_payload;
    memcpy(&nan_payload, &nan_bits, 4);
    for (int i = 0; i < PFM_W * PFM_H; i++) {
        int x = i % PFM_W, y = i / PFM_W;
        rgba[i * 4 + 0] = (float)(100 * y + x) + 0.25f; /* encodes the position */
        rgba[i * 4 + 1] = special[i % 7];
        rgba[i * 4 + 2] = (float)i * 1.0e-3f;
        rgba[i * 4 + 3] = 0.5f; /* alpha is dropped by PFM */
    }
    rgba[4 * 4 + 2] = INFINITY;
    rgba[7 * 4 + 2] = nan_payload;
}

static void test_pfm_round_trip_bit_exact(void)
{
    float src[PFM_W * PFM_H * 4];
    fill_pfm_pattern(src);
    const char *path = t_temp_file("rt.pfm", "");
    xrsc_diag diag = {0};
    CHECK_EQ_INT(hs_write_pfm(path, src, PFM_W, PFM_H, &diag), XRSC_OK);
    float *back = NULL;
    uint32_t w = 0, h = 0;
    CHECK_EQ_INT(hs_read_pfm(path, &back, &w, &h, &diag), XRSC_OK);
    CHECK_EQ_INT(w, PFM_W);
    CHECK_EQ_INT(h, PFM_H);
    if (!back || w != PFM_W || h != PFM_H) {
        free(back);
        return;
    }
    for (int i = 0; i < PFM_W * PFM_H; i++) {
        CHECK_MSG(memcmp(&back[i * 4], &src[i * 4], 3 * sizeof(float)) == 0,
                  "pixel %d differs in its bits", i);
        CHECK(back[i * 4 + 3] == 1.0f);
    }
    /* The top row stays on top: pixel (x=2, y=0) still carries its position code. */
    CHECK(back[(0 * PFM_W + 2) * 4] == 2.25f);
    CHECK(back[(2 * PFM_W + 4) * 4] == 204.25f);
    free(back);
}

static void test_pfm_stores_rows_bottom_to_top(void)
{
    float src[PFM_W * PFM_H * 4];
    fill_pfm_pattern(src);
    const char *path = t_temp_file("order.pfm", "");
    CHECK_EQ_INT(hs_write_pfm(path, src, PFM_W, PFM_H, NULL), XRSC_OK);
    size_t size = 0;
    uint8_t *file = t_read_file(path, &size);
    static const char header[] = "PF\n5 3\n-1.0\n"; /* x86/ARM hosts are little-endian */
    size_t hl = sizeof(header) - 1;
    CHECK_EQ_INT(size, hl + (size_t)PFM_W * PFM_H * 3 * sizeof(float));
    if (!file || size < hl + 3 * sizeof(float)) {
        free(file);
        return;
    }
    CHECK(memcmp(file, header, hl) == 0);
    /* The first stored pixel is the bottom-left one (x=0, y=H-1), as the format requires. */
    float first[3];
    memcpy(first, file + hl, sizeof(first));
    CHECK(first[0] == 200.25f);
    CHECK(memcmp(first, &src[(2 * PFM_W + 0) * 4], sizeof(first)) == 0);
    free(file);
}

static void test_pfm_reads_big_endian(void)
{
    /* 2x1 big-endian PFM (positive scale) written by hand. */
    const float vals[6] = {1.5f, -2.0f, 0.25f, 1024.0f, 3.0f, -0.125f};
    static const char header[] = "PF\n2 1\n1.0\n";
    uint8_t data[sizeof(header) - 1 + sizeof(vals)];
    memcpy(data, header, sizeof(header) - 1);
    for (int i = 0; i < 6; i++) {
        uint32_t u;
        memcpy(&u, &vals[i], 4);
        uint8_t *d = data + sizeof(header) - 1 + i * 4;
        d[0] = (uint8_t)(u >> 24), d[1] = (uint8_t)(u >> 16), d[2] = (uint8_t)(u >> 8),
        d[3] = (uint8_t)u;
    }
    const char *path = t_temp_file("be.pfm", "");
    write_bytes(path, data, sizeof(data));
    float *back = NULL;
    uint32_t w = 0, h = 0;
    CHECK_EQ_INT(hs_read_pfm(path, &back, &w, &h, NULL), XRSC_OK);
    if (back && w == 2 && h == 1) {
        for (int i = 0; i < 2; i++)
            for (int c = 0; c < 3; c++)
                CHECK(back[i * 4 + c] == vals[i * 3 + c]);
    }
    free(back);
}

static void test_pfm_rejects_bad_files(void)
{
    float *img = (float *)(uintptr_t)1; /* must be reset to NULL on failure */
    uint32_t w = 7, h = 7;
    xrsc_diag diag = {0};

    CHECK_EQ_INT(hs_read_pfm(t_source_path("no/such/file.pfm"), &img, &w, &h, &diag),
                 XRSC_ERROR_IO);
    CHECK(img == NULL);
    CHECK_EQ_INT(diag.code, XRSC_ERROR_IO);

    /* Grey PFM ("Pf"), a PPM, zero and oversized sides, zero scale: header errors. */
    static const char *const bad_headers[] = {
        "Pf\n1 1\n-1.0\n0000", "P6\n1 1\n255\n000", "PF\n0 1\n-1.0\n", "PF\n1 0\n-1.0\n",
        "PF\n65537 1\n-1.0\n", "PF\n1 1\n0\n000000000000", "PF\n1 1\n-1.0",
        "",
    };
    for (size_t i = 0; i < sizeof(bad_headers) / sizeof(bad_headers[0]); i++) {
        const char *path = t_temp_file("bad.pfm", bad_headers[i]);
        CHECK_MSG(hs_read_pfm(path, &img, &w, &h, &diag) == XRSC_ERROR_BAD_HEADER,
                  "header %zu", i);
        CHECK(img == NULL);
    }

    /* Pixels missing: one float short, and a huge header over a few bytes (must fail before
     * allocating 64 GiB). */
    CHECK_EQ_INT(hs_read_pfm(t_temp_file("short.pfm", "PF\n1 1\n-1.0\n12345678"), &img, &w,
                             &h, &diag),
                 XRSC_ERROR_TRUNCATED_LINE);
    CHECK(img == NULL);
    CHECK_EQ_INT(hs_read_pfm(t_temp_file("huge.pfm", "PF\n65536 65536\n-1.0\n123456789012"),
                             &img, &w, &h, &diag),
                 XRSC_ERROR_TRUNCATED_LINE);
    CHECK(img == NULL);
    CHECK_EQ_INT(diag.code, XRSC_ERROR_TRUNCATED_LINE);
}

static void test_pfm_write_to_missing_folder_is_io_error(void)
{
    float px[4] = {1, 2, 3, 4};
    xrsc_diag diag = {0};
    CHECK_EQ_INT(hs_write_pfm("/nonexistent-xrsc-dir/a.pfm", px, 1, 1, &diag), XRSC_ERROR_IO);
    CHECK_EQ_INT(diag.code, XRSC_ERROR_IO);
    CHECK(strstr(diag.file, "a.pfm") != NULL);
}

/* ---- PNG ---- */

static void test_png_read_back_with_libpng(void)
{
    enum { W = 7, H = 5 };
    uint8_t rgb[W * H * 3];
    uint32_t s = 12345u;
    for (size_t i = 0; i < sizeof(rgb); i++) {
        s = s * 1664525u + 1013904223u; /* LCG: every byte value pattern, no structure */
        rgb[i] = (uint8_t)(s >> 24);
    }
    rgb[0] = 0, rgb[1] = 255; /* both ends of the range */
    const char *path = t_temp_file("rt.png", "");
    CHECK_EQ_INT(hs_write_png(path, rgb, W, H, NULL), XRSC_OK);

    png_image img;
    memset(&img, 0, sizeof(img));
    img.version = PNG_IMAGE_VERSION;
    CHECK(png_image_begin_read_from_file(&img, path) != 0);
    CHECK_EQ_INT(img.width, W);
    CHECK_EQ_INT(img.height, H);
    /* 8-bit RGB on disk, no alpha. */
    CHECK(!(img.format & PNG_FORMAT_FLAG_ALPHA));
    CHECK(img.format & PNG_FORMAT_FLAG_COLOR);
    if (img.width != W || img.height != H) {
        png_image_free(&img);
        return;
    }
    img.format = PNG_FORMAT_RGB;
    uint8_t back[W * H * 3];
    memset(back, 0xAA, sizeof(back));
    CHECK(png_image_finish_read(&img, NULL, back, W * 3, NULL) != 0);
    CHECK(memcmp(back, rgb, sizeof(rgb)) == 0);
    /* Row order: the first row written is the top one. */
    CHECK(back[0] == 0 && back[1] == 255);
}

static void test_png_write_to_missing_folder_is_io_error(void)
{
    uint8_t px[3] = {1, 2, 3};
    xrsc_diag diag = {0};
    CHECK_EQ_INT(hs_write_png("/nonexistent-xrsc-dir/a.png", px, 1, 1, &diag), XRSC_ERROR_IO);
    CHECK_EQ_INT(diag.code, XRSC_ERROR_IO);
}

/* ---- tone mapping ---- */

static void test_tonemap_black_is_zero(void)
{
    CHECK_EQ_INT(tonemap1(0.0f, 1.0f), 0);
    CHECK_EQ_INT(tonemap1(-0.0f, 1.0f), 0);
    CHECK_EQ_INT(tonemap1(-5.0f, 1.0f), 0);
    CHECK_EQ_INT(tonemap1(-INFINITY, 1.0f), 0);
    CHECK_EQ_INT(tonemap1(0.0f, 100.0f), 0);
}

static void test_tonemap_nan_is_zero(void)
{
    CHECK_EQ_INT(tonemap1(NAN, 1.0f), 0);
    CHECK_EQ_INT(tonemap1(-NAN, 1.0f), 0);
    /* A NaN in one channel does not leak into the others. */
    float px[4] = {NAN, 0.5f, 1e6f, NAN};
    uint8_t out[3];
    hs_tonemap_rgba(NULL, px, 1, 1, out);
    CHECK_EQ_INT(out[0], 0);
    CHECK_EQ_INT(out[1], tonemap1(0.5f, 1.0f));
    CHECK_EQ_INT(out[2], 255);
}

static void test_tonemap_monotonic(void)
{
    int prev = 0, distinct = 0;
    for (int i = 0; i <= 4000; i++) {
        float x = 1e-4f * powf(1.005f, (float)i) - 1e-4f; /* 0 .. ~5e4, dense near 0 */
        int v = tonemap1(x, 1.0f);
        CHECK_MSG(v >= prev, "x = %g maps to %d after %d", (double)x, v, prev);
        distinct += v != prev;
        prev = v;
    }
    /* It is a ramp, not a step: nearly every 8-bit level is reached. */
    CHECK_MSG(distinct > 200, "only %d distinct levels", distinct);
}

static void test_tonemap_saturates_at_255(void)
{
    CHECK_EQ_INT(tonemap1(20.0f, 1.0f), 255);
    CHECK_EQ_INT(tonemap1(1e6f, 1.0f), 255);
    CHECK_EQ_INT(tonemap1(FLT_MAX, 1.0f), 255);
    CHECK_EQ_INT(tonemap1(INFINITY, 1.0f), 255);
    CHECK(tonemap1(1.0f, 1.0f) < 255); /* white paper is not yet clipped */
}

static void test_tonemap_matches_reference_curve(void)
{
    static const float xs[] = {1e-4f, 1e-3f, 0.01f, 0.05f, 0.18f, 0.5f, 1.0f, 2.0f, 4.0f};
    for (size_t i = 0; i < sizeof(xs) / sizeof(xs[0]); i++) {
        double ref = ref_tonemap(xs[i]);
        CHECK_MSG(fabs(tonemap1(xs[i], 1.0f) - ref) <= 0.51, "x = %g: %d vs %.2f",
                  (double)xs[i], tonemap1(xs[i], 1.0f), ref);
    }
    /* Middle grey (18%) lands near the middle of the range. */
    CHECK_EQ_INT(tonemap1(0.18f, 1.0f), 141);
}

static void test_tonemap_exposure_scales(void)
{
    static const float xs[] = {0.01f, 0.05f, 0.1f, 0.3f, 0.7f};
    for (size_t i = 0; i < sizeof(xs) / sizeof(xs[0]); i++) {
        CHECK_EQ_INT(tonemap1(xs[i], 2.0f), tonemap1(2.0f * xs[i], 1.0f));
        CHECK_EQ_INT(tonemap1(xs[i], 0.25f), tonemap1(0.25f * xs[i], 1.0f));
        CHECK(tonemap1(xs[i], 4.0f) > tonemap1(xs[i], 1.0f));
        /* 0 and negative exposures mean the default 1. */
        CHECK_EQ_INT(tonemap1(xs[i], 0.0f), tonemap1(xs[i], 1.0f));
        CHECK_EQ_INT(tonemap1(xs[i], -3.0f), tonemap1(xs[i], 1.0f));
    }
}

static void test_tonemap_layout_rgba_to_rgb(void)
{
    enum { W = 3, H = 2 };
    float rgba[W * H * 4];
    for (int i = 0; i < W * H; i++) {
        rgba[i * 4 + 0] = 0.01f * (float)(i + 1);
        rgba[i * 4 + 1] = 0.0f;
        rgba[i * 4 + 2] = 100.0f;
        rgba[i * 4 + 3] = 0.0f; /* alpha ignored */
    }
    uint8_t out[W * H * 3 + 1];
    out[W * H * 3] = 0x5A; /* guard byte */
    hs_tonemap_rgba(NULL, rgba, W, H, out);
    for (int i = 0; i < W * H; i++) {
        CHECK_EQ_INT(out[i * 3 + 0], tonemap1(0.01f * (float)(i + 1), 1.0f));
        CHECK_EQ_INT(out[i * 3 + 1], 0);
        CHECK_EQ_INT(out[i * 3 + 2], 255);
    }
    CHECK_EQ_INT(out[W * H * 3], 0x5A);
}

/* ---- side by side ---- */

static void test_side_by_side_layout(void)
{
    enum { W = 4, H = 3 };
    uint8_t left[W * H * 3], right[W * H * 3], sbs[2 * W * H * 3 + 1];
    for (int i = 0; i < W * H * 3; i++) {
        left[i] = (uint8_t)i;
        right[i] = (uint8_t)(200 - i);
    }
    sbs[2 * W * H * 3] = 0x5A; /* guard byte */
    hs_side_by_side(left, right, W, H, sbs);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            for (int c = 0; c < 3; c++) {
                CHECK(sbs[(y * 2 * W + x) * 3 + c] == left[(y * W + x) * 3 + c]);
                CHECK(sbs[(y * 2 * W + W + x) * 3 + c] == right[(y * W + x) * 3 + c]);
            }
    CHECK_EQ_INT(sbs[2 * W * H * 3], 0x5A);
}

int main(void)
{
    RUN(test_pfm_round_trip_bit_exact);
    RUN(test_pfm_stores_rows_bottom_to_top);
    RUN(test_pfm_reads_big_endian);
    RUN(test_pfm_rejects_bad_files);
    RUN(test_pfm_write_to_missing_folder_is_io_error);
    RUN(test_png_read_back_with_libpng);
    RUN(test_png_write_to_missing_folder_is_io_error);
    RUN(test_tonemap_black_is_zero);
    RUN(test_tonemap_nan_is_zero);
    RUN(test_tonemap_monotonic);
    RUN(test_tonemap_saturates_at_255);
    RUN(test_tonemap_matches_reference_curve);
    RUN(test_tonemap_exposure_scales);
    RUN(test_tonemap_layout_rgba_to_rgb);
    RUN(test_side_by_side_layout);
    return t_finish();
}
