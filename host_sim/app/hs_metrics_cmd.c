// SPDX-License-Identifier: MIT
/**
 * @file hs_metrics_cmd.c
 * @brief `xrsc metrics`: compares a test run with a reference run frame by frame, both eyes,
 *        with the metrics of xrsc_metrics.h (read and scored by io/hs_run_metrics.h), and prints
 *        or writes the values; `--stereo DIR` scores one run's stereo and temporal consistency
 *        instead (hs_metrics_stereo.c). This file is the command line, the frame loop and the
 *        output.
 */
#include "hs_metrics_cmd.h"

#include "hs_args.h"
#include "hs_metrics_stereo.h"
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
#define MAX_SEQ 2 /* hs_run_eyes: one per eye */


static int bad_arg(const char *flag, const char *value, const char *why)
{
    return hs_bad_arg("xrsc metrics", flag, value, why);
}

/** The line of `xrsc bench --ref-floor`'s report that carries the floor (hs_bench_report.c). */
#define BENCH_FLOOR_TEXT "reference floor relMSE"

/* --floor: a relMSE, or a saved bench report whose two-reference floor is halved (a test image
 * equal to the truth scores about half of it against one reference). */
static bool parse_floor(const char *v, double *out)
{
    if (hs_parse_f(v, out))
        return *out > 0.0;
    FILE *f = fopen(v, "r");
    char line[1024];
    bool found = false;
    while (f && !found && fgets(line, sizeof(line), f)) {
        const char *p = strstr(line, BENCH_FLOOR_TEXT);
        if (!p)
            continue;
        for (p += strlen(BENCH_FLOOR_TEXT); *p && !(*p >= '0' && *p <= '9'); p++)
            ;
        char *end = NULL;
        double x = strtod(p, &end);
        found = end != p && x > 0.0;
        *out = 0.5 * x;
    }
    if (f)
        fclose(f);
    return found;
}

/* A number in (0, 1e30]. */
static bool parse_positive(const char *s, double *out)
{
    double v;
    if (!hs_parse_f(s, &v) || !(v > 0.0) || v > 1e30)
        return false;
    *out = v;
    return true;
}

/* Reads and scores one frame pair; returns 0, or 1 after printing the error. */
static int compare_frame(const char *ref_path, const char *test_path,
                         const xrsc_metrics_options *mo, hs_pair_scores *out)
{
    hs_frame_pair p;
    xrsc_diag diag = {0};
    char msg[1400];
    if (hs_frame_pair_read(ref_path, test_path, &p, &diag) != XRSC_OK) {
        fprintf(stderr, "xrsc metrics: error: %s\n", xrsc_diag_format(&diag, msg, sizeof(msg)));
        return 1;
    }
    xrsc_result res = hs_frame_pair_score(&p, mo, true, out);
    hs_frame_pair_free(&p);
    if (res != XRSC_OK) {
        fprintf(stderr, "xrsc metrics: error: %s vs %s: %s [%s]\n", test_path, ref_path,
                xrsc_result_text(res), xrsc_result_name(res));
        return 1;
    }
    return 0;
}

typedef struct sums {
    double rel, rmse, ssim, ct, cr;
    uint32_t count, below;
} sums;

static void print_mean(const char *eye, const sums *s)
{
    printf("%6s %5s %12.6g %12.6g %9.6f %7.4f %7.4f  (%u frames", "mean", eye, s->rel / s->count,
           s->rmse / s->count, s->ssim / s->count, s->ct / s->count, s->cr / s->count, s->count);
    if (s->below)
        printf(", %u below floor", s->below);
    printf(")\n");
}

typedef struct metrics_args {
    const char *ref_dir, *test_dir, *csv_path, *pattern;
    const char *stereo_dir, *views_path; /**< --stereo mode (hs_metrics_stereo.h) */
    uint32_t warmup;
    uint32_t first, max_frames;
    bool first_given, quiet;
    double floor_relmse; /**< 0: none */
    xrsc_metrics_options mo;
} metrics_args;

static int check_mode(const metrics_args *a);

#define A(a) ((metrics_args *)(a)->target)

static int parse_first(const hs_opt_arg *a)
{
    if (!hs_parse_u32(a->value, &A(a)->first))
        return bad_arg(a->opt->name, a->value, "expected a frame number");
    A(a)->first_given = true;
    return 0;
}

static int parse_floor_opt(const hs_opt_arg *a)
{
    if (!parse_floor(a->value, &A(a)->floor_relmse))
        return bad_arg(a->opt->name, a->value,
                       "expected a positive relMSE, or a file with `xrsc bench "
                       "--ref-floor`'s \"" BENCH_FLOOR_TEXT "\"");
    return 0;
}

/* A double field in (0, 1e30]. */
static int parse_positive_opt(const hs_opt_arg *a)
{
    if (!parse_positive(a->value, (double *)a->field))
        return bad_arg(a->opt->name, a->value, "expected a positive number");
    return 0;
}

#define F(field) offsetof(metrics_args, field)
#define COUNT (&(const hs_opt_num){0, UINT32_MAX, "expected a count"})
#define TEXT(s) {NULL, NULL, s, NULL, 0, NULL}

/* Every option of `xrsc metrics` once, in --help's order. */
static const hs_opt k_metrics_opts[] = {
    TEXT("usage: xrsc metrics --ref DIR --test DIR [options]\n"
         "       xrsc metrics --stereo DIR [--views FILE] [options]\n"
         "\n"
         "Compares two runs frame by frame, both eyes: linear colour PFM files as `xrsc replay\n"
         "--write linear` writes them, else EXR files (--write exr), else the PNGs of runs that have\n"
         "only PNGs (a warning: those are tone-mapped and 8-bit, so the values are display-referred).\n"
         "Per frame and eye: relMSE, RMSE and mean SSIM of the test frame against the reference\n"
         "frame, and the CPBD sharpness of both; then the means over the sequence, per eye. The first\n"
         "frame is the lowest number present in the reference folder (OpenXR runs start at 1, --direct\n"
         "runs at 0).\n"
         "\n"),
    {"--ref", "DIR", "reference frames (e.g. `spp` with many samples per pixel)", NULL, F(ref_dir),
     NULL},
    {"--test", "DIR", "frames to evaluate (same names and sizes)", NULL, F(test_dir), NULL},
    {"--pattern", "FMT",
     "one sequence's file name with one %u, zero padding allowed; a name\n"
     "with \"left\" also scores the \"right\" one  [frame_%05u_left.pfm,\n"
     ".exr or .png]",
     NULL, F(pattern), NULL},
    {"--first", "N", "first frame number          [the lowest in --ref]", parse_first, 0, NULL},
    {"--frames", "N",
     "N frames, an error if fewer exist (0 = until a reference frame is\n"
     "missing)                    [0]",
     hs_opt_u32, F(max_frames), COUNT},
    {"--floor", "X|FILE",
     "the reference's noise floor as a relMSE: rows whose relMSE is below it\n"
     "are marked \"below floor\" (their difference cannot be told from the\n"
     "reference's own noise). FILE: the saved output of `xrsc bench\n"
     "--ref-floor`, whose \"reference floor relMSE\" is measured between two\n"
     "independent references; half of it is one reference's noise, used here",
     parse_floor_opt, 0, NULL},
    {"--csv", "PATH", "also write the per-frame values as CSV (one row per frame and eye)", NULL,
     F(csv_path), NULL},
    {"--relmse-eps", "E", "relMSE epsilon: (x - r)^2 / (r^2 + E)           [0.01]",
     parse_positive_opt, F(mo.relmse_epsilon), NULL},
    {"--range", "L", "display range: luminance clamped to [0, L] for SSIM and CPBD [1]",
     parse_positive_opt, F(mo.display_range), NULL},
    {"--cpbd-linear", NULL, "CPBD on linear instead of sRGB-encoded luminance", NULL,
     F(mo.cpbd_linear), NULL},
    {"--quiet", NULL, "print only the mean lines", NULL, F(quiet), NULL},
    TEXT("  -h, --help          this help\n"
         "\n"
         "--stereo DIR scores one run's stereo frames, as `xrsc bench` does (its temporal_msd and\n"
         "stereo_msd): per frame the stereo discrepancy (the left eye reprojected into the right by\n"
         "depth, disocclusions excluded; mean squared RGB difference over the valid pixels) and the\n"
         "temporal difference (each eye against the previous frame reprojected into it, both eyes'\n"
         "means weighted by their valid pixels), then their means. Input: frame_NNNNN_left.exr and\n"
         "_right.exr with colour R, G, B and depth Z (metres along -Z at the pixel centre, 0 = no hit;\n"
         "`xrsc replay --write exr` writes them) and views.csv (each frame's eye poses, FOVs and\n"
         "sizes; the replay writes it; README.md, \"views.csv\"), so frames of any renderer can be\n"
         "scored. --pattern (with \"left\", ending .exr), --first, --frames, --csv and --quiet apply.\n"),
    {"--stereo", "DIR", "the run to score (instead of --ref/--test)", NULL, F(stereo_dir), NULL},
    {"--views", "FILE", "the eye poses and FOVs               [DIR/views.csv]", NULL,
     F(views_path), NULL},
    {"--warmup", "N",
     "the first N frames are listed but left out of the means (as\n"
     "`xrsc bench --warmup`)                [0]",
     hs_opt_u32, F(warmup), COUNT},
    {"--depth-tolerance", "X", "relative depth test of the reprojection [0.05]",
     parse_positive_opt, F(mo.depth_tolerance), NULL},
};
#define METRICS_OPT_COUNT (sizeof(k_metrics_opts) / sizeof(k_metrics_opts[0]))

/* Parses the command line; returns -1 to go on, else the exit code. */
static int parse_args(int argc, char **argv, metrics_args *a)
{
    int r = hs_opt_parse("xrsc metrics", k_metrics_opts, METRICS_OPT_COUNT, argc, argv, 1, a);
    if (r == HS_OPT_HELP) {
        hs_opt_print_help(stdout, k_metrics_opts, METRICS_OPT_COUNT);
        return 0;
    }
    if (r != HS_ARG_NEXT)
        return r;
    return check_mode(a);
}

/* --stereo excludes --ref/--test (and their options); else both are required. */
static int check_mode(const metrics_args *a)
{
    if (a->stereo_dir) {
        if (a->ref_dir || a->test_dir)
            return bad_arg(a->ref_dir ? "--ref" : "--test", NULL,
                           "scores two runs; --stereo scores one (run them separately)");
        if (a->floor_relmse > 0.0)
            return bad_arg("--floor", NULL, "applies to --ref/--test, not --stereo");
        return -1;
    }
    if (a->views_path || a->warmup || a->mo.depth_tolerance > 0.0)
        return bad_arg(a->views_path ? "--views" : a->warmup ? "--warmup" : "--depth-tolerance",
                       NULL, "applies to --stereo only");
    if (!a->ref_dir || !a->test_dir)
        return bad_arg(a->ref_dir ? "--test" : "--ref", NULL, "is required");
    return -1;
}

/* The sequences and first frame; returns -1 to go on, else the exit code. */
static int pick_sequences(metrics_args *a, hs_run_eyes *seq)
{
    char fmt[1100];
    if (a->pattern) {
        snprintf(fmt, sizeof(fmt), "%s", a->pattern);
    } else {
        xrsc_diag diag = {0};
        char msg[1400];
        hs_run_kind kind = hs_run_common_kind(a->ref_dir, a->test_dir, &diag);
        if (kind == HS_RUN_NONE) {
            fprintf(stderr, "xrsc metrics: error: %s\n", xrsc_diag_format(&diag, msg, sizeof(msg)));
            return 1;
        }
        if (kind == HS_RUN_PNG)
            fprintf(stderr, "xrsc metrics: warning: no linear (PFM) frames in both runs: scoring "
                            "the PNGs, which are tone-mapped and 8-bit (display-referred values, "
                            "not radiance); write both runs with --write linear for linear "
                            "metrics\n");
        snprintf(fmt, sizeof(fmt), "%s", hs_run_pattern(kind, 0));
    }
    hs_frame_pattern pat;
    if (!hs_frame_pattern_parse(fmt, &pat))
        return bad_arg("--pattern", fmt, "expected one %u (e.g. frame_%05u_left.pfm)");
    if (!a->first_given && !hs_frame_pattern_first(a->ref_dir, &pat, &a->first)) {
        fprintf(stderr, "xrsc metrics: error: no frame named like %s in %s\n", fmt, a->ref_dir);
        return 1;
    }
    hs_run_eyes_of(fmt, a->ref_dir, a->first, seq);
    return -1;
}

int hs_metrics_main(int argc, char **argv)
{
    metrics_args a = {.pattern = NULL};
    int rc = parse_args(argc, argv, &a);
    if (rc >= 0)
        return rc;
    if (a.stereo_dir) {
        hs_stereo_args sa = {.dir = a.stereo_dir, .views_path = a.views_path,
                             .pattern = a.pattern, .csv_path = a.csv_path, .first = a.first,
                             .max_frames = a.max_frames, .warmup = a.warmup,
                             .first_given = a.first_given, .quiet = a.quiet, .mo = a.mo};
        return hs_metrics_stereo_run(&sa);
    }
    hs_run_eyes seq;
    if ((rc = pick_sequences(&a, &seq)) >= 0)
        return rc;
    rc = 0;

    FILE *csv = NULL;
    if (a.csv_path) {
        csv = fopen(a.csv_path, "w");
        if (!csv) {
            fprintf(stderr, "xrsc metrics: error: cannot write %s\n", a.csv_path);
            return 1;
        }
        fprintf(csv, "frame,relmse,rmse,mse,ssim,cpbd_test,cpbd_ref,cpbd_test_edges,"
                     "cpbd_ref_edges,eye,below_floor\n");
    }
    if (!a.quiet)
        printf("%6s %5s %12s %12s %9s %7s %7s\n", "frame", "eye", "relMSE", "RMSE", "SSIM", "CPBD",
               "CPBDref");

    sums s[MAX_SEQ];
    memset(s, 0, sizeof(s));
    uint32_t count = 0;
    char ref_path[PATH_MAX_LEN], test_path[PATH_MAX_LEN];
    for (uint64_t f = a.first;
         rc == 0 && f <= UINT32_MAX && (a.max_frames == 0 || count < a.max_frames); f++) {
        for (uint32_t e = 0; e < seq.count && rc == 0; e++) {
            if (!hs_frame_pattern_path(a.ref_dir, &seq.pat[e], (uint32_t)f, ref_path,
                                       sizeof(ref_path)) ||
                !hs_frame_pattern_path(a.test_dir, &seq.pat[e], (uint32_t)f, test_path,
                                       sizeof(test_path))) {
                fprintf(stderr, "xrsc metrics: error: path too long\n");
                rc = 1;
                break;
            }
            if (!hs_file_exists(ref_path)) {
                if (count == 0 || a.max_frames != 0 || e > 0) {
                    fprintf(stderr, "xrsc metrics: error: reference frame %s is missing\n",
                            ref_path);
                    rc = 1;
                }
                rc = rc ? rc : -1; /* the end of the sequence */
                break;
            }
            hs_pair_scores fv;
            if ((rc = compare_frame(ref_path, test_path, &a.mo, &fv)) != 0)
                break;
            bool below = a.floor_relmse > 0.0 && fv.err.relmse < a.floor_relmse;
            if (!a.quiet)
                printf("%6u %5s %12.6g %12.6g %9.6f %7.4f %7.4f%s\n", (uint32_t)f, seq.eye[e],
                       fv.err.relmse, fv.err.rmse, fv.ssim, fv.cpbd_test.cpbd, fv.cpbd_ref.cpbd,
                       below ? "  below floor" : "");
            if (csv)
                fprintf(csv, "%u,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%llu,%llu,%s,%d\n", (uint32_t)f,
                        fv.err.relmse, fv.err.rmse, fv.err.mse, fv.ssim, fv.cpbd_test.cpbd,
                        fv.cpbd_ref.cpbd, (unsigned long long)fv.cpbd_test.edge_count,
                        (unsigned long long)fv.cpbd_ref.edge_count, seq.eye[e], below ? 1 : 0);
            s[e].rel += fv.err.relmse;
            s[e].rmse += fv.err.rmse;
            s[e].ssim += fv.ssim;
            s[e].ct += fv.cpbd_test.cpbd;
            s[e].cr += fv.cpbd_ref.cpbd;
            s[e].count++;
            s[e].below += below ? 1u : 0u;
        }
        if (rc == 0)
            count++;
    }
    if (rc < 0)
        rc = 0;
    if (csv && fclose(csv) != 0 && rc == 0) {
        fprintf(stderr, "xrsc metrics: error: cannot write %s\n", a.csv_path);
        rc = 1;
    }
    for (uint32_t e = 0; rc == 0 && e < seq.count; e++) {
        if (s[e].count > 0)
            print_mean(seq.eye[e], &s[e]);
    }
    if (rc == 0 && a.floor_relmse > 0.0 && !a.quiet)
        printf("floor: relMSE %.6g (rows below it differ by no more than reference noise)\n",
               a.floor_relmse);
    return rc;
}
