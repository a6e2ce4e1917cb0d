// SPDX-License-Identifier: MIT
/**
 * @file hs_compare_cmd.c
 * @brief `xrsc compare A B`: per frame a side-by-side image (A, B, |B - A| heat map with its
 *        scale, one row per eye, labelled with the bitmap font of hs_font.h) and relMSE, RMSE,
 *        PSNR and SSIM of both eyes, B scored against A, as a table and a CSV.
 */
#include "hs_compare_cmd.h"

#include "hs_args.h"
#include "hs_font.h"
#include "hs_image.h"
#include "hs_opt.h"
#include "hs_run_dir.h"
#include "u_diag.h"
#include "xrsc/xrsc_metrics.h"

#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PATH_MAX_LEN 4096
#define DEFAULT_OUT "out/compare"
/** Pixels between panels, and around the labels. */
#define GAP_PX 4
/** The heat map's full scale when none is given: this quantile of the first frame's values. */
#define AUTO_SCALE_QUANTILE 0.99
/** Smallest automatic full scale (identical runs still get a valid scale bar). */
#define MIN_SCALE 1e-6
/** Height of the colour scale bar, pixels (times the text scale). */
#define SCALE_BAR_PX 8

static int bad_arg(const char *flag, const char *value, const char *why)
{
    return hs_bad_arg("xrsc compare", flag, value, why);
}

typedef struct compare_args {
    const char *a_dir, *b_dir, *out_dir;
    uint32_t first, max_frames;
    bool first_given, quiet;
    double scale, exposure;
    xrsc_metrics_options mo;
} compare_args;

#define C(a) ((compare_args *)(a)->target)

/* The run folders A and B, in order. */
static int parse_folder(const hs_opt_arg *a)
{
    if (!C(a)->a_dir)
        C(a)->a_dir = a->value;
    else if (!C(a)->b_dir)
        C(a)->b_dir = a->value;
    else
        return bad_arg(a->value, NULL, "unexpected argument (two run folders: A B)");
    return 0;
}

static int parse_first(const hs_opt_arg *a)
{
    if (!hs_parse_u32(a->value, &C(a)->first))
        return bad_arg(a->opt->name, a->value, "expected a frame number");
    C(a)->first_given = true;
    return 0;
}

/* A double field in (0, 1e30]. */
static int parse_positive(const hs_opt_arg *a)
{
    double d;
    if (!hs_parse_f(a->value, &d) || !(d > 0.0) || d > 1e30)
        return bad_arg(a->opt->name, a->value, "expected a positive number");
    *(double *)a->field = d;
    return 0;
}

#define F(field) offsetof(compare_args, field)
#define TEXT(s) {NULL, NULL, s, NULL, 0, NULL}

/* Every option of `xrsc compare` once, in --help's order; the text row with a parser takes A
 * and B. */
static const hs_opt k_compare_opts[] = {
    {NULL, NULL,
     "usage: xrsc compare A B [options]\n"
     "\n"
     "A/B comparison of two run folders (as `xrsc replay` writes them; linear PFM, else EXR frames\n"
     "when both have them, else PNGs with a warning that they are tone-mapped). Frames are matched\n"
     "by number from the lowest one in A. Per frame it writes OUT/compare_NNNNN.png: one row per\n"
     "eye with A, B and the heat map of |B - A| (RMS over R, G, B; black = equal), each labelled,\n"
     "and the heat map's colour scale; and it prints relMSE, RMSE, PSNR and SSIM of B against A for\n"
     "both eyes (also written to OUT/compare.csv).\n"
     "\n",
     parse_folder, 0, NULL},
    {"--out", "DIR", "output folder (created)          [" DEFAULT_OUT "]", NULL, F(out_dir), NULL},
    {"--first", "N", "first frame number               [the lowest in A]", parse_first, 0, NULL},
    {"--frames", "N", "N frames (0 = until a frame of A is missing)  [0]", hs_opt_u32,
     F(max_frames), &(const hs_opt_num){0, UINT32_MAX, "expected a count"}},
    {"--scale", "X",
     "heat map full scale (RMS difference shown white) [the 99th\n"
     "percentile of the first frame's differences]",
     parse_positive, F(scale), NULL},
    {"--exposure", "X", "tone-mapping exposure of linear frames in the images [1]",
     parse_positive, F(exposure), NULL},
    {"--relmse-eps", "E", "relMSE epsilon                   [0.01]", parse_positive,
     F(mo.relmse_epsilon), NULL},
    {"--quiet", NULL, "print only the mean lines", NULL, F(quiet), NULL},
    TEXT("  -h, --help          this help\n"
         "\n"
         "PSNR is 10 log10(1 / MSE): the peak is 1, the display white of linear frames.\n"),
};
#define COMPARE_OPT_COUNT (sizeof(k_compare_opts) / sizeof(k_compare_opts[0]))

static int parse_args(int argc, char **argv, compare_args *a)
{
    int r = hs_opt_parse("xrsc compare", k_compare_opts, COMPARE_OPT_COUNT, argc, argv, 1, a);
    if (r == HS_OPT_HELP) {
        hs_opt_print_help(stdout, k_compare_opts, COMPARE_OPT_COUNT);
        return 0;
    }
    if (r != HS_ARG_NEXT)
        return r;
    if (!a->a_dir || !a->b_dir)
        return bad_arg(a->a_dir ? "B" : "A", NULL, "two run folders are required: A B");
    return -1;
}

/* ---- the picture ---- */

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

/* ---- per frame ---- */

typedef struct eye_pair {
    float *a, *b;
    uint32_t w, h;
} eye_pair;

static void pair_free(eye_pair p[2])
{
    for (int e = 0; e < 2; e++) {
        free(p[e].a);
        free(p[e].b);
        p[e].a = p[e].b = NULL;
    }
}

/* Reads both eyes of frame f of A and B; 0, -1 when A has no such frame, or 1 after an error. */
static int read_pairs(const compare_args *a, hs_run_kind kind, uint32_t f, eye_pair p[2])
{
    memset(p, 0, 2 * sizeof(*p));
    for (int e = 0; e < 2; e++) {
        hs_frame_pattern pat;
        char pa[PATH_MAX_LEN], pb[PATH_MAX_LEN];
        hs_frame_pattern_parse(hs_run_pattern(kind, e), &pat);
        if (!hs_frame_pattern_path(a->a_dir, &pat, f, pa, sizeof(pa)) ||
            !hs_frame_pattern_path(a->b_dir, &pat, f, pb, sizeof(pb))) {
            fprintf(stderr, "xrsc compare: error: path too long\n");
            return 1;
        }
        FILE *probe = fopen(pa, "rb");
        if (!probe)
            return e == 0 ? -1 : (fprintf(stderr, "xrsc compare: error: %s is missing\n", pa), 1);
        fclose(probe);
        xrsc_diag diag = {0};
        char msg[1400];
        uint32_t bw = 0, bh = 0;
        if (hs_read_frame(pa, &p[e].a, &p[e].w, &p[e].h, NULL, &diag) != XRSC_OK ||
            hs_read_frame(pb, &p[e].b, &bw, &bh, NULL, &diag) != XRSC_OK) {
            fprintf(stderr, "xrsc compare: error: %s\n", xrsc_diag_format(&diag, msg, sizeof(msg)));
            return 1;
        }
        if (bw != p[e].w || bh != p[e].h || (e == 1 && p[1].w != p[0].w) ||
            (e == 1 && p[1].h != p[0].h)) {
            fprintf(stderr, "xrsc compare: error: %s is %ux%u but %s is %ux%u\n", pb, bw, bh, pa,
                    p[e].w, p[e].h);
            return 1;
        }
    }
    return 0;
}

typedef struct eye_values {
    xrsc_error_metrics err;
    double psnr_db, ssim;
} eye_values;

/* Composes and writes frame f's picture; scale in/out (0: pick it from this frame). */
static int write_picture(const compare_args *a, hs_run_kind kind, uint32_t f, eye_pair p[2],
                         const eye_values v[2], double *scale)
{
    uint32_t w = p[0].w, h = p[0].h;
    size_t n = (size_t)w * h;
    float *heat = malloc(2 * n * sizeof(float));
    uint8_t *tmp = malloc(n * 3);
    canvas cv;
    bool ok = heat && tmp && canvas_init(&cv, w, h);
    if (!ok) {
        free(heat);
        free(tmp);
        fprintf(stderr, "xrsc compare: error: out of memory\n");
        return 1;
    }
    for (int e = 0; e < 2; e++)
        rms_diff(p[e].a, p[e].b, n, heat + e * n);
    if (*scale <= 0.0) {
        *scale = fmax(quantile(heat, 2 * n, AUTO_SCALE_QUANTILE), MIN_SCALE);
        if (!a->quiet)
            printf("heat map full scale: %.4g (RMS difference; --scale sets it)\n", *scale);
    }
    char t[256];
    snprintf(t, sizeof(t), "FRAME %u   A %.40s   B %.40s", f, a->a_dir, a->b_dir);
    label(&cv, GAP_PX, GAP_PX / 2, t);
    static const char *const eyes[2] = {"LEFT", "RIGHT"};
    for (int e = 0; e < 2; e++) {
        uint32_t y0 = cv.title_h + (uint32_t)e * (h + GAP_PX);
        display(p[e].a, w, h, kind, a->exposure, tmp);
        blit(&cv, tmp, GAP_PX, y0);
        display(p[e].b, w, h, kind, a->exposure, tmp);
        blit(&cv, tmp, 2 * GAP_PX + w, y0);
        for (size_t i = 0; i < n; i++)
            hs_heat_colour((float)(heat[e * n + i] / *scale), tmp + i * 3);
        blit(&cv, tmp, 3 * GAP_PX + 2 * w, y0);
        snprintf(t, sizeof(t), "A %s", eyes[e]);
        label(&cv, GAP_PX, (int32_t)y0, t);
        snprintf(t, sizeof(t), "B %s", eyes[e]);
        label(&cv, 2 * GAP_PX + (int32_t)w, (int32_t)y0, t);
        snprintf(t, sizeof(t), "B-A %s RELMSE %.3g", eyes[e], v[e].err.relmse);
        label(&cv, 3 * GAP_PX + 2 * (int32_t)w, (int32_t)y0, t);
    }
    scale_bar(&cv, *scale);
    char path[PATH_MAX_LEN];
    snprintf(path, sizeof(path), "%s/compare_%05u.png", a->out_dir, f);
    xrsc_diag diag = {0};
    char msg[1400];
    int rc = 0;
    if (hs_write_png(path, cv.rgb, cv.w, cv.h, &diag) != XRSC_OK) {
        fprintf(stderr, "xrsc compare: error: %s\n", xrsc_diag_format(&diag, msg, sizeof(msg)));
        rc = 1;
    }
    free(cv.rgb);
    free(heat);
    free(tmp);
    return rc;
}

static int score(const compare_args *a, const eye_pair p[2], eye_values v[2])
{
    for (int e = 0; e < 2; e++) {
        xrsc_result res = xrsc_metrics_error(p[e].b, p[e].a, p[e].w, p[e].h, &a->mo, &v[e].err);
        if (res == XRSC_OK)
            res = xrsc_metrics_ssim(p[e].b, p[e].a, p[e].w, p[e].h, &a->mo, &v[e].ssim, NULL);
        if (res != XRSC_OK) {
            fprintf(stderr, "xrsc compare: error: metrics: %s [%s]\n", xrsc_result_text(res),
                    xrsc_result_name(res));
            return 1;
        }
        v[e].psnr_db = v[e].err.mse > 0.0 ? -10.0 * log10(v[e].err.mse) : INFINITY;
    }
    return 0;
}

int hs_compare_main(int argc, char **argv)
{
    compare_args a = {.out_dir = DEFAULT_OUT, .exposure = 1.0};
    int rc = parse_args(argc, argv, &a);
    if (rc >= 0)
        return rc;
    xrsc_diag diag = {0};
    char msg[1400];
    hs_run_kind kind = hs_run_common_kind(a.a_dir, a.b_dir, &diag);
    if (kind == HS_RUN_NONE) {
        fprintf(stderr, "xrsc compare: error: %s\n", xrsc_diag_format(&diag, msg, sizeof(msg)));
        return 1;
    }
    if (kind == HS_RUN_PNG)
        fprintf(stderr, "xrsc compare: warning: no linear (PFM) frames in both runs: comparing "
                        "the PNGs, which are tone-mapped and 8-bit (display-referred values); "
                        "write both runs with --write linear for linear metrics\n");
    hs_frame_pattern pat;
    hs_frame_pattern_parse(hs_run_pattern(kind, 0), &pat);
    if (!a.first_given)
        hs_frame_pattern_first(a.a_dir, &pat, &a.first);
    if (hs_make_dirs(a.out_dir, "--out", &diag) != XRSC_OK) {
        fprintf(stderr, "xrsc compare: error: %s\n", xrsc_diag_format(&diag, msg, sizeof(msg)));
        return 1;
    }
    char csv_path[PATH_MAX_LEN];
    snprintf(csv_path, sizeof(csv_path), "%s/compare.csv", a.out_dir);
    FILE *csv = fopen(csv_path, "w");
    if (!csv) {
        fprintf(stderr, "xrsc compare: error: cannot write %s\n", csv_path);
        return 1;
    }
    fprintf(csv, "frame,eye,relmse,rmse,mse,psnr_db,ssim\n");
    if (!a.quiet)
        printf("%6s %5s %12s %12s %9s %9s\n", "frame", "eye", "relMSE", "RMSE", "PSNR dB", "SSIM");
    static const char *const eyes[2] = {"left", "right"};
    double sum[2][4] = {{0}};
    uint32_t count = 0;
    double scale = a.scale;
    for (uint64_t f = a.first; rc < 0 && (a.max_frames == 0 || count < a.max_frames); f++) {
        eye_pair p[2];
        eye_values v[2];
        int r = read_pairs(&a, kind, (uint32_t)f, p);
        if (r < 0 && count == 0)
            fprintf(stderr, "xrsc compare: error: frame %u of %s is missing\n", (uint32_t)f,
                    a.a_dir);
        if (r < 0 && (count == 0 || a.max_frames != 0))
            r = 1;
        if (r == 0 && (r = score(&a, p, v)) == 0)
            r = write_picture(&a, kind, (uint32_t)f, p, v, &scale);
        pair_free(p);
        if (r != 0) {
            rc = r < 0 ? 0 : r;
            break;
        }
        for (int e = 0; e < 2; e++) {
            if (!a.quiet)
                printf("%6u %5s %12.6g %12.6g %9.3f %9.6f\n", (uint32_t)f, eyes[e], v[e].err.relmse,
                       v[e].err.rmse, v[e].psnr_db, v[e].ssim);
            fprintf(csv, "%u,%s,%.9g,%.9g,%.9g,%.9g,%.9g\n", (uint32_t)f, eyes[e], v[e].err.relmse,
                    v[e].err.rmse, v[e].err.mse, v[e].psnr_db, v[e].ssim);
            sum[e][0] += v[e].err.relmse;
            sum[e][1] += v[e].err.rmse;
            sum[e][2] += v[e].psnr_db;
            sum[e][3] += v[e].ssim;
        }
        count++;
    }
    if (rc < 0)
        rc = 0;
    if (fclose(csv) != 0 && rc == 0) {
        fprintf(stderr, "xrsc compare: error: cannot write %s\n", csv_path);
        rc = 1;
    }
    for (int e = 0; rc == 0 && e < 2 && count > 0; e++)
        printf("%6s %5s %12.6g %12.6g %9.3f %9.6f  (%u frames)\n", "mean", eyes[e],
               sum[e][0] / count, sum[e][1] / count, sum[e][2] / count, sum[e][3] / count, count);
    if (rc == 0 && !a.quiet)
        printf("images: %s/compare_NNNNN.png, values: %s\n", a.out_dir, csv_path);
    return rc;
}
