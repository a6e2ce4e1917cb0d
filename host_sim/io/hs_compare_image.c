// SPDX-License-Identifier: MIT
/**
 * @file hs_compare_image.c
 * @brief The labelled A | B | heat-map picture of one compared frame (hs_compare_image.h).
 */
#include "hs_compare_image.h"

#include "hs_font.h"
#include "hs_image.h"

#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/** Pixels between panels, and around the labels. */
#define GAP_PX 4
/** The heat map's full scale when none is given: this quantile of the first frame's values. */
#define AUTO_SCALE_QUANTILE 0.99
/** Smallest automatic full scale (identical runs still get a valid scale bar). */
#define MIN_SCALE 1e-6
/** Height of the colour scale bar, pixels (times the text scale). */
#define SCALE_BAR_PX 8

/* The display picture of a frame: linear frames tone-mapped, PNG frames re-encoded as read. */
static void display(const float *rgba, uint32_t w, uint32_t h, hs_run_kind kind, double exposure,
                    uint8_t *out_rgb)
{
    if (kind != HS_RUN_PNG) {
        hs_tonemap tm = {.exposure = (float)exposure};
        hs_tonemap_rgba(&tm, rgba, w, h, out_rgb);
        return;
    }
    for (size_t i = 0; i < (size_t)w * h; i++)
        for (int c = 0; c < 3; c++)
            out_rgb[i * 3 + c] = hs_srgb8(rgba[i * 4 + c]);
}

/* RMS over R, G, B of b - a per pixel. */
static void rms_diff(const float *a, const float *b, size_t n, float *out)
{
    for (size_t i = 0; i < n; i++) {
        double s = 0.0;
        for (int c = 0; c < 3; c++) {
            double d = (double)b[i * 4 + c] - a[i * 4 + c];
            s += d * d;
        }
        out[i] = (float)sqrt(s / 3.0);
    }
}

static int cmp_float(const void *x, const void *y)
{
    float a = *(const float *)x, b = *(const float *)y;
    return (a > b) - (a < b);
}

static double quantile(const float *v, size_t n, double q)
{
    float *s = malloc(n * sizeof(float));
    if (!s || n == 0) {
        free(s);
        return 0.0;
    }
    memcpy(s, v, n * sizeof(float));
    qsort(s, n, sizeof(float), cmp_float);
    double r = s[(size_t)(q * (double)(n - 1))];
    free(s);
    return r;
}

/** The composed picture: a title line, then per eye a row of three panels, then the scale. */
typedef struct canvas {
    uint8_t *rgb;
    uint32_t w, h, text_scale, panel_w, panel_h, title_h, label_h;
} canvas;

static void blit(canvas *cv, const uint8_t *rgb, uint32_t x0, uint32_t y0)
{
    for (uint32_t y = 0; y < cv->panel_h; y++)
        memcpy(cv->rgb + ((size_t)(y0 + y) * cv->w + x0) * 3, rgb + (size_t)y * cv->panel_w * 3,
               (size_t)cv->panel_w * 3);
}

static void label(canvas *cv, int32_t x, int32_t y, const char *text)
{
    static const uint8_t white[3] = {255, 255, 255}, dark[3] = {24, 24, 24};
    uint32_t s = cv->text_scale;
    hs_font_fill(cv->rgb, cv->w, cv->h, 3, x, y, hs_font_text_width(text, s) + 2 * s,
                 (HS_FONT_H + 2) * s, dark);
    hs_font_draw(cv->rgb, cv->w, cv->h, 3, x + (int32_t)s, y + (int32_t)s, s, text, white);
}

static bool canvas_init(canvas *cv, uint32_t w, uint32_t h)
{
    memset(cv, 0, sizeof(*cv));
    cv->panel_w = w;
    cv->panel_h = h;
    cv->text_scale = w >= 256 ? 2 : 1;
    cv->title_h = (HS_FONT_LINE + 2) * cv->text_scale + GAP_PX;
    cv->label_h = (HS_FONT_LINE + 2) * cv->text_scale;
    cv->w = 3 * w + 4 * GAP_PX;
    cv->h =
        cv->title_h + 2 * (h + GAP_PX) + SCALE_BAR_PX * cv->text_scale + cv->label_h + 2 * GAP_PX;
    cv->rgb = calloc((size_t)cv->w * cv->h, 3);
    return cv->rgb != NULL;
}

/* The colour scale under the heat-map column: the ramp, then "0" and the full scale. */
static void scale_bar(canvas *cv, double full)
{
    int32_t x0 = (int32_t)(3 * GAP_PX + 2 * cv->panel_w);
    int32_t y0 = (int32_t)(cv->title_h + 2 * (cv->panel_h + GAP_PX));
    for (uint32_t x = 0; x < cv->panel_w; x++) {
        uint8_t c[3];
        hs_heat_colour((float)x / (float)(cv->panel_w - 1), c);
        hs_font_fill(cv->rgb, cv->w, cv->h, 3, x0 + (int32_t)x, y0, 1,
                     SCALE_BAR_PX * cv->text_scale, c);
    }
    char t[64];
    int32_t ty = y0 + (int32_t)(SCALE_BAR_PX * cv->text_scale) + GAP_PX / 2;
    label(cv, x0, ty, "0");
    snprintf(t, sizeof(t), "%.3g", full);
    label(cv,
          x0 + (int32_t)cv->panel_w -
              (int32_t)(hs_font_text_width(t, cv->text_scale) + 2 * cv->text_scale),
          ty, t);
    label(cv, x0 - (int32_t)(hs_font_text_width("RMS", cv->text_scale) + 3 * cv->text_scale), ty,
          "RMS");
}

/* Eye e's row: A, B and the heat map, labelled. */
static void eye_row(canvas *cv, const hs_compare_frame *fr, const hs_compare_style *st,
                    double exposure, int e, const float *heat, double scale, uint8_t *tmp)
{
    static const char *const eyes[2] = {"LEFT", "RIGHT"};
    uint32_t w = fr->w, h = fr->h;
    uint32_t y0 = cv->title_h + (uint32_t)e * (h + GAP_PX);
    char t[256];
    display(fr->a[e], w, h, st->kind, exposure, tmp);
    blit(cv, tmp, GAP_PX, y0);
    display(fr->b[e], w, h, st->kind, exposure, tmp);
    blit(cv, tmp, 2 * GAP_PX + w, y0);
    for (size_t i = 0; i < (size_t)w * h; i++)
        hs_heat_colour((float)(heat[i] / scale), tmp + i * 3);
    blit(cv, tmp, 3 * GAP_PX + 2 * w, y0);
    snprintf(t, sizeof(t), "A %s", eyes[e]);
    label(cv, GAP_PX, (int32_t)y0, t);
    snprintf(t, sizeof(t), "B %s", eyes[e]);
    label(cv, 2 * GAP_PX + (int32_t)w, (int32_t)y0, t);
    snprintf(t, sizeof(t), "B-A %s RELMSE %.3g", eyes[e], fr->relmse[e]);
    label(cv, 3 * GAP_PX + 2 * (int32_t)w, (int32_t)y0, t);
}

xrsc_result hs_compare_picture(const hs_compare_frame *fr, const hs_compare_style *style,
                               double *scale, uint8_t **out_rgb, uint32_t *out_w,
                               uint32_t *out_h)
{
    size_t n = (size_t)fr->w * fr->h;
    float *heat = malloc(2 * n * sizeof(float));
    uint8_t *tmp = malloc(n * 3);
    canvas cv;
    if (!heat || !tmp || !canvas_init(&cv, fr->w, fr->h)) {
        free(heat);
        free(tmp);
        return XRSC_ERROR_OUT_OF_MEMORY;
    }
    for (int e = 0; e < 2; e++)
        rms_diff(fr->a[e], fr->b[e], n, heat + e * n);
    if (*scale <= 0.0)
        *scale = fmax(quantile(heat, 2 * n, AUTO_SCALE_QUANTILE), MIN_SCALE);
    label(&cv, GAP_PX, GAP_PX / 2, style->title ? style->title : "");
    double exposure = style->exposure > 0.0 ? style->exposure : 1.0;
    for (int e = 0; e < 2; e++)
        eye_row(&cv, fr, style, exposure, e, heat + e * n, *scale, tmp);
    scale_bar(&cv, *scale);
    free(heat);
    free(tmp);
    *out_rgb = cv.rgb;
    *out_w = cv.w;
    *out_h = cv.h;
    return XRSC_OK;
}
