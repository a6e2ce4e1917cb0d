// SPDX-License-Identifier: MIT
/**
 * @file hs_image.c
 * @brief PNG (libpng) and PFM writers, and the display tone mapping.
 */
#include "hs_image.h"

#include "hs_file.h"
#include "u_diag.h"

#include <errno.h>
#include <math.h>
#include <png.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ACES filmic tone curve, rational fit by K. Narkowicz, "ACES Filmic Tone Mapping Curve"
 * (2015): f(x) = x(ax + b) / (x(cx + d) + e). */
#define ACES_A 2.51f
#define ACES_B 0.03f
#define ACES_C 2.43f
#define ACES_D 0.59f
#define ACES_E 0.14f

/** Largest PFM side hs_read_pfm accepts. */
#define PFM_MAX_SIDE 65536u

static bool host_is_little_endian(void)
{
    const uint16_t one = 1;
    uint8_t first;
    memcpy(&first, &one, 1);
    return first == 1;
}

static float byte_swap_f32(float v)
{
    uint8_t b[4], t;
    memcpy(b, &v, 4);
    t = b[0], b[0] = b[3], b[3] = t;
    t = b[1], b[1] = b[2], b[2] = t;
    memcpy(&v, b, 4);
    return v;
}

static float aces(float x)
{
    if (!(x > 0.0f)) /* also maps NaN to 0 */
        return 0.0f;
    float y = (x * (ACES_A * x + ACES_B)) / (x * (ACES_C * x + ACES_D) + ACES_E);
    return y < 1.0f ? y : 1.0f;
}

uint8_t hs_srgb8(float c)
{
    if (!(c > 0.0f))
        return 0;
    if (c >= 1.0f)
        return 255;
    float s = c <= 0.0031308f ? 12.92f * c : 1.055f * powf(c, 1.0f / 2.4f) - 0.055f;
    return (uint8_t)lrintf(s * 255.0f);
}

float hs_srgb_to_linear(float c)
{
    return c <= 0.04045f ? c / 12.92f : powf((c + 0.055f) / 1.055f, 2.4f);
}

void hs_tonemap_rgba(const hs_tonemap *tm, const float *rgba, uint32_t w, uint32_t h,
                     uint8_t *out_rgb)
{
    float exposure = (tm && tm->exposure > 0.0f) ? tm->exposure : 1.0f;
    size_t n = (size_t)w * h;
    for (size_t i = 0; i < n; i++) {
        for (int c = 0; c < 3; c++)
            out_rgb[i * 3 + c] = hs_srgb8(aces(rgba[i * 4 + c] * exposure));
    }
}

/* Histogram of log2(max(r, g, b)) for the bright percentile of hs_autoexposure_update:
 * HS_AE_BINS bins over [HS_AE_LOG2_MIN, HS_AE_LOG2_MAX) (0.04 stops each, interpolated). */
#define HS_AE_BINS 1024
#define HS_AE_LOG2_MIN (-24.0)
#define HS_AE_LOG2_MAX (16.0)

/** The value below which fraction p of the histogram's count lies (log2, interpolated). */
static double histogram_percentile(const uint32_t *bins, size_t total, double p)
{
    double want = p * (double)total, acc = 0.0, width = (HS_AE_LOG2_MAX - HS_AE_LOG2_MIN) / HS_AE_BINS;
    for (int i = 0; i < HS_AE_BINS; i++) {
        if (bins[i] > 0 && acc + bins[i] >= want)
            return HS_AE_LOG2_MIN + width * (i + (want - acc) / bins[i]);
        acc += bins[i];
    }
    return HS_AE_LOG2_MAX;
}

float hs_autoexposure_update(hs_autoexposure *ae, const float *const *rgba, uint32_t count,
                             uint32_t w, uint32_t h)
{
    static const double scale = HS_AE_BINS / (HS_AE_LOG2_MAX - HS_AE_LOG2_MIN);
    uint32_t *bins = calloc(HS_AE_BINS, sizeof(uint32_t));
    double sum = 0.0;
    size_t n = (size_t)w * h, used = 0;
    for (uint32_t e = 0; bins && e < count; e++) {
        for (size_t i = 0; i < n; i++) {
            const float *p = &rgba[e][i * 4];
            double y = 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
            double m = fmax(p[0], fmax(p[1], p[2]));
            if (!isfinite(y) || !isfinite(m)) continue;
            sum += log2(HS_AUTO_DELTA + (y > 0.0 ? y : 0.0));
            double b = m > 0.0 ? (log2(m) - HS_AE_LOG2_MIN) * scale : 0.0;
            bins[b < 0.0 ? 0 : b >= HS_AE_BINS ? HS_AE_BINS - 1 : (int)b]++;
            used++;
        }
    }
    if (used > 0) {
        double key = log2(HS_AUTO_KEY) - sum / (double)used;
        double white = log2(HS_AUTO_WHITE) - histogram_percentile(bins, used, HS_AUTO_PERCENTILE);
        double x = fmin(key, white);
        x = fmin(fmax(x, log2(HS_AUTO_MIN)), log2(HS_AUTO_MAX));
        ae->log2_exposure =
            ae->frames == 0 ? x : ae->log2_exposure + HS_AUTO_ADAPT * (x - ae->log2_exposure);
        ae->frames++;
    }
    free(bins);
    return ae->frames == 0 ? 1.0f : (float)exp2(ae->log2_exposure);
}

/* libpng's errors are reported by the caller (with errno), not printed by libpng. */
static void png_quiet_error(png_structp png, png_const_charp msg)
{
    (void)msg;
    png_longjmp(png, 1);
}

static void png_quiet_warning(png_structp png, png_const_charp msg)
{
    (void)png;
    (void)msg;
}

static xrsc_result write_png(const char *path, bool staged, const uint8_t *rgb, uint32_t w,
                             uint32_t h, xrsc_diag *diag)
{
    /* Written whole under a temporary name, then renamed (hs_file.h). */
    hs_out_file out;
    xrsc_result res = hs_out_open(&out, path, diag);
    if (res != XRSC_OK)
        return res;
    out.staged = staged;
    png_structp png =
        png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, png_quiet_error, png_quiet_warning);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    if (!png || !info) {
        png_destroy_write_struct(&png, &info);
        hs_out_close(&out, false, diag);
        return u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, path, 0, "", "libpng setup failed");
    }
    if (setjmp(png_jmpbuf(png))) {
        /* libpng's only error while writing rows to a FILE is a failed fwrite. */
        png_destroy_write_struct(&png, &info);
        return hs_out_close(&out, true, diag); /* names the file and the errno text */
    }
    png_init_io(png, out.f);
    png_set_IHDR(png, info, w, h, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_set_sRGB(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
    png_set_compression_level(png, 3);
    png_write_info(png, info);
    for (uint32_t y = 0; y < h; y++)
        png_write_row(png, (png_const_bytep)(rgb + (size_t)y * w * 3));
    png_write_end(png, NULL);
    png_destroy_write_struct(&png, &info);
    return hs_out_close(&out, true, diag);
}

xrsc_result hs_write_png(const char *path, const uint8_t *rgb, uint32_t w, uint32_t h,
                         xrsc_diag *diag)
{
    return write_png(path, false, rgb, w, h, diag);
}

xrsc_result hs_stage_png(const char *path, const uint8_t *rgb, uint32_t w, uint32_t h,
                         xrsc_diag *diag)
{
    return write_png(path, true, rgb, w, h, diag);
}

static xrsc_result write_pfm(const char *path, bool staged, const float *rgba, uint32_t w,
                             uint32_t h, xrsc_diag *diag)
{
    hs_out_file out; /* whole or nothing (hs_file.h) */
    xrsc_result res = hs_out_open(&out, path, diag);
    if (res != XRSC_OK)
        return res;
    out.staged = staged;
    FILE *f = out.f;
    /* The sign of the scale gives the byte order (negative: little-endian); the pixels are
     * written in the host's. PFM rows run bottom to top. */
    fprintf(f, "PF\n%u %u\n%s\n", w, h, host_is_little_endian() ? "-1.0" : "1.0");
    float *row = malloc((size_t)w * 3 * sizeof(float));
    if (!row) {
        hs_out_close(&out, false, diag);
        return u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, path, 0, "", "out of memory");
    }
    int ok = 1;
    for (uint32_t y = h; y-- > 0 && ok;) {
        const float *src = rgba + (size_t)y * w * 4;
        for (uint32_t x = 0; x < w; x++)
            memcpy(row + x * 3, src + x * 4, 3 * sizeof(float));
        ok = fwrite(row, sizeof(float) * 3, w, f) == w;
    }
    free(row);
    /* A failed fwrite sets the stream's error flag: the close names the file and errno. */
    return hs_out_close(&out, true, diag);
}

xrsc_result hs_write_pfm(const char *path, const float *rgba, uint32_t w, uint32_t h,
                         xrsc_diag *diag)
{
    return write_pfm(path, false, rgba, w, h, diag);
}

xrsc_result hs_stage_pfm(const char *path, const float *rgba, uint32_t w, uint32_t h,
                         xrsc_diag *diag)
{
    return write_pfm(path, true, rgba, w, h, diag);
}

xrsc_result hs_read_pfm(const char *path, float **out_rgba, uint32_t *out_w, uint32_t *out_h,
                        xrsc_diag *diag)
{
    *out_rgba = NULL;
    FILE *f = fopen(path, "rb");
    if (!f)
        return u_diag_set(diag, XRSC_ERROR_IO, path, 0, "", "cannot open: %s", strerror(errno));
    char magic[3] = {0};
    unsigned w = 0, h = 0;
    float scale = 0.0f;
    /* The header ends with exactly one whitespace character after the scale. */
    if (fscanf(f, "%2s %u %u %f", magic, &w, &h, &scale) != 4 || strcmp(magic, "PF") != 0 ||
        w == 0 || h == 0 || w > PFM_MAX_SIDE || h > PFM_MAX_SIDE || scale == 0.0f ||
        scale != scale || fgetc(f) == EOF) {
        fclose(f);
        return u_diag_set(diag, XRSC_ERROR_BAD_HEADER, path, 1, "header", "not a colour PFM");
    }
    bool swap = (scale < 0.0f) != host_is_little_endian();
    /* Check the size before allocating, so a short file with a huge header costs nothing. */
    long header_end = ftell(f);
    if (header_end < 0 || fseek(f, 0, SEEK_END) != 0) {
        fclose(f);
        return u_diag_set(diag, XRSC_ERROR_IO, path, 0, "", "cannot seek");
    }
    long file_end = ftell(f);
    uint64_t need = (uint64_t)w * h * 3 * sizeof(float);
    if (file_end < header_end || (uint64_t)(file_end - header_end) < need ||
        fseek(f, header_end, SEEK_SET) != 0) {
        fclose(f);
        return u_diag_set(diag, XRSC_ERROR_TRUNCATED_LINE, path, 0, "pixels",
                          "file ends before %u x %u pixels", w, h);
    }
    float *rgba = malloc((size_t)w * h * 4 * sizeof(float));
    float *row = malloc((size_t)w * 3 * sizeof(float));
    if (!rgba || !row) {
        free(rgba);
        free(row);
        fclose(f);
        return u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, path, 0, "", "out of memory");
    }
    for (uint32_t y = h; y-- > 0;) {
        if (fread(row, sizeof(float) * 3, w, f) != w) {
            free(rgba);
            free(row);
            fclose(f);
            return u_diag_set(diag, XRSC_ERROR_TRUNCATED_LINE, path, 0, "pixels",
                              "file ends before %u x %u pixels", w, h);
        }
        for (uint32_t x = 0; x < w; x++) {
            float *d = rgba + ((size_t)y * w + x) * 4;
            for (int c = 0; c < 3; c++)
                d[c] = swap ? byte_swap_f32(row[x * 3 + c]) : row[x * 3 + c];
            d[3] = 1.0f;
        }
    }
    free(row);
    fclose(f);
    *out_rgba = rgba;
    *out_w = w;
    *out_h = h;
    return XRSC_OK;
}

void hs_side_by_side(const uint8_t *left, const uint8_t *right, uint32_t w, uint32_t h,
                     uint8_t *out_rgb)
{
    size_t row = (size_t)w * 3;
    for (uint32_t y = 0; y < h; y++) {
        memcpy(out_rgb + y * row * 2, left + y * row, row);
        memcpy(out_rgb + y * row * 2 + row, right + y * row, row);
    }
}
