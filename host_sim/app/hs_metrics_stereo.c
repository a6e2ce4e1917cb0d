// SPDX-License-Identifier: MIT
/**
 * @file hs_metrics_stereo.c
 * @brief The stereo discrepancy and temporal difference of frames read from files
 *        (hs_metrics_stereo.h).
 */
#include "hs_metrics_stereo.h"

#include "hs_args.h"
#include "hs_exr.h"
#include "hs_run_dir.h"
#include "hs_views_csv.h"
#include "u_diag.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PATH_CHARS 4096
#define CMD "xrsc metrics --stereo"

/* One frame of both eyes as read. */
typedef struct stereo_frame {
    float *rgba[2], *depth[2];
    xrsc_metrics_camera camera[2];
} stereo_frame;

static void frame_free(stereo_frame *f)
{
    for (int e = 0; e < 2; e++) {
        free(f->rgba[e]);
        free(f->depth[e]);
    }
    memset(f, 0, sizeof(*f));
}

static int fail(const xrsc_diag *diag)
{
    char msg[1400];
    fprintf(stderr, CMD ": error: %s\n", xrsc_diag_format(diag, msg, sizeof(msg)));
    return 1;
}

/* Reads eye e of frame f: its EXR's colour and Z, its camera from views.csv. */
static int read_eye(const hs_frame_pattern *pat, const char *dir, const hs_views_table *views,
                    const char *views_path, uint32_t f, int e, stereo_frame *out)
{
    char path[PATH_CHARS];
    xrsc_diag diag = {0};
    uint32_t w = 0, h = 0;
    if (!hs_frame_pattern_path(dir, pat, f, path, sizeof(path))) {
        fprintf(stderr, CMD ": error: path too long\n");
        return 1;
    }
    if (hs_read_exr(path, &out->rgba[e], &out->depth[e], &w, &h, &diag) != XRSC_OK)
        return fail(&diag);
    if (!out->depth[e]) {
        u_diag_set(&diag, XRSC_ERROR_BAD_HEADER, path, 0, "Z",
                   "no Z (depth) channel: write the frames with --write exr");
        return fail(&diag);
    }
    const hs_view_row *row = hs_views_find(views, f, (uint32_t)e);
    if (!row) {
        u_diag_set(&diag, XRSC_ERROR_INVALID_ARGUMENT, views_path, 0, "frame",
                   "no row for frame %u, eye %s (needed by %s)", f, e ? "right" : "left", path);
        return fail(&diag);
    }
    out->camera[e] = row->camera;
    if (row->camera.width == 0 && row->camera.height == 0) {
        out->camera[e].width = w;
        out->camera[e].height = h;
    } else if (row->camera.width != w || row->camera.height != h) {
        u_diag_set(&diag, XRSC_ERROR_INVALID_ARGUMENT, views_path, 0, "width",
                   "frame %u, eye %s is %ux%u here but %s is %ux%u", f, e ? "right" : "left",
                   row->camera.width, row->camera.height, path, w, h);
        return fail(&diag);
    }
    return 0;
}

static xrsc_metrics_view view_of(const stereo_frame *f, int e)
{
    xrsc_metrics_view v = {.rgba = f->rgba[e], .depth_m = f->depth[e], .camera = f->camera[e]};
    return v;
}

/* Per-frame values: NaN where there is none (the bench's empty/nan cells). */
typedef struct frame_result {
    double temporal, stereo;
    uint64_t temporal_valid, stereo_valid;
} frame_result;

/* The bench's arithmetic (hs_bench.c put_temporal_columns / put_stereo_columns), so the values
 * agree to the last bit on the same images, cameras and depths. */
static int measure(const stereo_frame *cur, const stereo_frame *prev,
                   const xrsc_metrics_options *mo, uint32_t f, frame_result *out)
{
    xrsc_reproj_diff d;
    xrsc_metrics_view vr = view_of(cur, 1), vl = view_of(cur, 0);
    xrsc_result res = xrsc_metrics_stereo_discrepancy(&vr, &vl, mo, &d, NULL, NULL);
    out->stereo = res == XRSC_OK && d.valid_count ? d.mean_sq_diff : NAN;
    out->stereo_valid = res == XRSC_OK ? d.valid_count : 0;
    out->temporal = NAN;
    out->temporal_valid = 0;
    double sum = 0.0;
    for (int e = 0; res == XRSC_OK && prev && e < 2; e++) {
        xrsc_metrics_view vc = view_of(cur, e), vp = view_of(prev, e);
        if ((res = xrsc_metrics_temporal_diff(&vc, &vp, mo, &d, NULL, NULL)) == XRSC_OK) {
            sum += d.mean_sq_diff * (double)d.valid_count;
            out->temporal_valid += d.valid_count;
        }
    }
    if (res != XRSC_OK) {
        fprintf(stderr, CMD ": error: frame %u: %s [%s]\n", f, xrsc_result_text(res),
                xrsc_result_name(res));
        return 1;
    }
    if (prev && out->temporal_valid)
        out->temporal = sum / (double)out->temporal_valid;
    return 0;
}

typedef struct means {
    double temporal, stereo;
    uint32_t temporal_n, stereo_n;
} means;

/* %.9g, or "-" where there is no value (so the bench's 6 digits can be checked). */
static const char *num(double v, char *buf, size_t cap)
{
    if (isfinite(v))
        snprintf(buf, cap, "%.9g", v);
    else
        snprintf(buf, cap, "-");
    return buf;
}

static void put_row(const hs_stereo_args *a, FILE *csv, uint32_t f, const frame_result *r,
                    bool warmup)
{
    char t[40], s[40];
    num(r->temporal, t, sizeof(t));
    num(r->stereo, s, sizeof(s));
    if (!a->quiet)
        printf("%6u %16s %9llu %16s %9llu%s\n", f, t, (unsigned long long)r->temporal_valid, s,
               (unsigned long long)r->stereo_valid, warmup ? "  warm-up" : "");
    if (csv) {
        fprintf(csv, "%u,%s,%llu,%s,%llu,%d\n", f, isfinite(r->temporal) ? t : "",
                (unsigned long long)r->temporal_valid, isfinite(r->stereo) ? s : "",
                (unsigned long long)r->stereo_valid, warmup ? 1 : 0);
    }
}

static void add_mean(means *m, const frame_result *r)
{
    if (isfinite(r->temporal)) {
        m->temporal += r->temporal;
        m->temporal_n++;
    }
    if (isfinite(r->stereo)) {
        m->stereo += r->stereo;
        m->stereo_n++;
    }
}

static void print_means(const means *m)
{
    char t[40], s[40];
    printf("mean temporal %s (%u frames)\n",
           num(m->temporal_n ? m->temporal / m->temporal_n : NAN, t, sizeof(t)), m->temporal_n);
    printf("mean stereo   %s (%u frames)\n",
           num(m->stereo_n ? m->stereo / m->stereo_n : NAN, s, sizeof(s)), m->stereo_n);
}

/* The left and right patterns; returns -1 to go on, else the exit code. */
static int patterns(const hs_stereo_args *a, hs_frame_pattern pat[2])
{
    const char *fmt = a->pattern ? a->pattern : "frame_%05u_left.exr";
    const char *l = strstr(fmt, "left");
    char right[1100];
    size_t n = strlen(fmt);
    if (!l || n < 4 || strcmp(fmt + n - 4, ".exr") != 0 || n + 2 >= sizeof(right))
        return hs_bad_arg("xrsc metrics", "--pattern", fmt,
                          "--stereo needs the left eye's EXR names (with \"left\", ending .exr)");
    snprintf(right, sizeof(right), "%.*sright%s", (int)(l - fmt), fmt, l + 4);
    if (!hs_frame_pattern_parse(fmt, &pat[0]) || !hs_frame_pattern_parse(right, &pat[1]))
        return hs_bad_arg("xrsc metrics", "--pattern", fmt,
                          "expected one %u (e.g. frame_%05u_left.exr)");
    return -1;
}

static bool exists(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (f)
        fclose(f);
    return f != NULL;
}

/* The frames from a->first on: rows, CSV and means. */
static int score(const hs_stereo_args *a, const hs_frame_pattern pat[2],
                 const hs_views_table *views, const char *views_path, FILE *csv, means *m)
{
    stereo_frame fr[2];
    memset(fr, 0, sizeof(fr));
    int rc = 0;
    uint32_t count = 0;
    char path[PATH_CHARS];
    for (uint64_t f = a->first; f <= UINT32_MAX && (a->max_frames == 0 || count < a->max_frames);
         f++, count++) {
        stereo_frame *cur = &fr[count & 1], *prev = count ? &fr[(count + 1) & 1] : NULL;
        if (!hs_frame_pattern_path(a->dir, &pat[0], (uint32_t)f, path, sizeof(path)) ||
            !exists(path)) {
            if (count == 0 || a->max_frames != 0) {
                fprintf(stderr, CMD ": error: frame %s is missing\n", path);
                rc = 1;
            }
            break;
        }
        frame_free(cur);
        frame_result r;
        if ((rc = read_eye(&pat[0], a->dir, views, views_path, (uint32_t)f, 0, cur)) != 0 ||
            (rc = read_eye(&pat[1], a->dir, views, views_path, (uint32_t)f, 1, cur)) != 0 ||
            (rc = measure(cur, prev, &a->mo, (uint32_t)f, &r)) != 0)
            break;
        bool warmup = count < a->warmup;
        put_row(a, csv, (uint32_t)f, &r, warmup);
        if (!warmup)
            add_mean(m, &r);
    }
    frame_free(&fr[0]);
    frame_free(&fr[1]);
    return rc;
}

int hs_metrics_stereo_run(const hs_stereo_args *a)
{
    hs_frame_pattern pat[2];
    int rc = patterns(a, pat);
    if (rc >= 0)
        return rc;
    uint32_t first = a->first;
    if (!a->first_given && !hs_frame_pattern_first(a->dir, &pat[0], &first)) {
        fprintf(stderr, CMD ": error: no frame named like %s%%u%s in %s\n", pat[0].prefix,
                pat[0].suffix, a->dir);
        return 1;
    }
    char views_path[PATH_CHARS];
    snprintf(views_path, sizeof(views_path), "%s", a->views_path ? a->views_path : "");
    if (!a->views_path)
        snprintf(views_path, sizeof(views_path), "%s/" HS_VIEWS_CSV, a->dir);
    hs_views_table views;
    xrsc_diag diag = {0};
    if (hs_views_csv_read(views_path, &views, &diag) != XRSC_OK)
        return fail(&diag);
    FILE *csv = a->csv_path ? fopen(a->csv_path, "w") : NULL;
    if (a->csv_path && !csv) {
        fprintf(stderr, CMD ": error: cannot write %s\n", a->csv_path);
        hs_views_table_free(&views);
        return 1;
    }
    if (csv)
        fprintf(csv, "frame,temporal_msd,temporal_valid,stereo_msd,stereo_valid,warmup\n");
    if (!a->quiet)
        printf("%6s %16s %9s %16s %9s\n", "frame", "temporal", "valid", "stereo", "valid");
    hs_stereo_args from = *a;
    from.first = first;
    means m = {0};
    rc = score(&from, pat, &views, views_path, csv, &m);
    if (csv && fclose(csv) != 0 && rc == 0) {
        fprintf(stderr, CMD ": error: cannot write %s\n", a->csv_path);
        rc = 1;
    }
    if (rc == 0)
        print_means(&m);
    hs_views_table_free(&views);
    return rc;
}
