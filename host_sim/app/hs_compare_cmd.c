// SPDX-License-Identifier: MIT
/**
 * @file hs_compare_cmd.c
 * @brief `xrsc compare A B`: per frame a side-by-side image (A, B, |B - A| heat map with its
 *        scale, one row per eye; io/hs_compare_image.h draws it) and relMSE, RMSE, PSNR and SSIM
 *        of both eyes, B scored against A (io/hs_run_metrics.h), as a table and a CSV. This file
 *        is the command line, the frame loop and the output.
 */
#include "hs_compare_cmd.h"

#include "hs_args.h"
#include "hs_compare_image.h"
#include "hs_image.h"
#include "hs_opt.h"
#include "hs_run_dir.h"
#include "hs_run_metrics.h"
#include "u_diag.h"
#include "xrsc/xrsc_metrics.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PATH_MAX_LEN 4096
#define DEFAULT_OUT "out/compare"

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

/* Reads both eyes of frame f of A and B; 0, -1 when A has no such frame, or 1 after an error. */
static int read_pairs(const compare_args *a, hs_run_kind kind, uint32_t f, hs_frame_pair p[2])
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
        if (!hs_file_exists(pa))
            return e == 0 ? -1 : (fprintf(stderr, "xrsc compare: error: %s is missing\n", pa), 1);
        xrsc_diag diag = {0};
        char msg[1400];
        /* B is scored against A: A is the reference */
        if (hs_frame_pair_read(pa, pb, &p[e], &diag) != XRSC_OK) {
            fprintf(stderr, "xrsc compare: error: %s\n", xrsc_diag_format(&diag, msg, sizeof(msg)));
            return 1;
        }
        if (e == 1 && (p[1].w != p[0].w || p[1].h != p[0].h)) {
            fprintf(stderr, "xrsc compare: error: %s is %ux%u but %s is %ux%u\n", pb, p[1].w,
                    p[1].h, pa, p[0].w, p[0].h);
            return 1;
        }
    }
    return 0;
}

/* Composes and writes frame f's picture; scale in/out (0: pick it from this frame). */
static int write_picture(const compare_args *a, hs_run_kind kind, uint32_t f,
                         const hs_frame_pair p[2], const hs_pair_scores v[2], double *scale)
{
    hs_compare_frame fr = {.a = {p[0].ref, p[1].ref}, .b = {p[0].test, p[1].test},
                           .w = p[0].w, .h = p[0].h,
                           .relmse = {v[0].err.relmse, v[1].err.relmse}};
    char title[256];
    snprintf(title, sizeof(title), "FRAME %u   A %.40s   B %.40s", f, a->a_dir, a->b_dir);
    hs_compare_style style = {.title = title, .kind = kind, .exposure = a->exposure};
    bool auto_scale = *scale <= 0.0;
    uint8_t *rgb = NULL;
    uint32_t w = 0, h = 0;
    if (hs_compare_picture(&fr, &style, scale, &rgb, &w, &h) != XRSC_OK) {
        fprintf(stderr, "xrsc compare: error: out of memory\n");
        return 1;
    }
    if (auto_scale && !a->quiet)
        printf("heat map full scale: %.4g (RMS difference; --scale sets it)\n", *scale);
    char path[PATH_MAX_LEN];
    snprintf(path, sizeof(path), "%s/compare_%05u.png", a->out_dir, f);
    xrsc_diag diag = {0};
    char msg[1400];
    int rc = 0;
    if (hs_write_png(path, rgb, w, h, &diag) != XRSC_OK) {
        fprintf(stderr, "xrsc compare: error: %s\n", xrsc_diag_format(&diag, msg, sizeof(msg)));
        rc = 1;
    }
    free(rgb);
    return rc;
}

static int score(const compare_args *a, const hs_frame_pair p[2], hs_pair_scores v[2])
{
    for (int e = 0; e < 2; e++) {
        xrsc_result res = hs_frame_pair_score(&p[e], &a->mo, false, &v[e]);
        if (res != XRSC_OK) {
            fprintf(stderr, "xrsc compare: error: metrics: %s [%s]\n", xrsc_result_text(res),
                    xrsc_result_name(res));
            return 1;
        }
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
        hs_frame_pair p[2];
        hs_pair_scores v[2];
        int r = read_pairs(&a, kind, (uint32_t)f, p);
        if (r < 0 && count == 0)
            fprintf(stderr, "xrsc compare: error: frame %u of %s is missing\n", (uint32_t)f,
                    a.a_dir);
        if (r < 0 && (count == 0 || a.max_frames != 0))
            r = 1;
        if (r == 0 && (r = score(&a, p, v)) == 0)
            r = write_picture(&a, kind, (uint32_t)f, p, v, &scale);
        hs_frame_pair_free(&p[0]);
        hs_frame_pair_free(&p[1]);
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
