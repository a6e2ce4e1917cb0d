// SPDX-License-Identifier: MIT
/**
 * @file hs_metrics_stereo.c
 * @brief `xrsc metrics --stereo`: the frame loop and its rows, CSV and means
 *        (hs_metrics_stereo.h); the frames are read and measured by io/hs_run_metrics.h.
 */
#include "hs_metrics_stereo.h"

#include "hs_args.h"
#include "hs_run_dir.h"
#include "hs_run_metrics.h"
#include "hs_views_csv.h"
#include "u_diag.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PATH_CHARS 4096
#define CMD "xrsc metrics --stereo"

static int fail(const xrsc_diag *diag)
{
    char msg[1400];
    fprintf(stderr, CMD ": error: %s\n", xrsc_diag_format(diag, msg, sizeof(msg)));
    return 1;
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

static void put_row(const hs_stereo_args *a, FILE *csv, uint32_t f, const hs_stereo_values *r,
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

static void add_mean(means *m, const hs_stereo_values *r)
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
    const char *why = NULL;
    if (!hs_stereo_patterns(a->pattern, pat, &why))
        return hs_bad_arg("xrsc metrics", "--pattern",
                          a->pattern ? a->pattern : "frame_%05u_left.exr", why);
    return -1;
}

/* The frames from a->first on: rows, CSV and means. */
static int score(const hs_stereo_args *a, const hs_frame_pattern pat[2],
                 const hs_views_table *views, const char *views_path, FILE *csv, means *m)
{
    hs_stereo_frame fr[2];
    memset(fr, 0, sizeof(fr));
    int rc = 0;
    uint32_t count = 0;
    char path[PATH_CHARS];
    for (uint64_t f = a->first; f <= UINT32_MAX && (a->max_frames == 0 || count < a->max_frames);
         f++, count++) {
        hs_stereo_frame *cur = &fr[count & 1], *prev = count ? &fr[(count + 1) & 1] : NULL;
        if (!hs_frame_pattern_path(a->dir, &pat[0], (uint32_t)f, path, sizeof(path)) ||
            !hs_file_exists(path)) {
            if (count == 0 || a->max_frames != 0) {
                fprintf(stderr, CMD ": error: frame %s is missing\n", path);
                rc = 1;
            }
            break;
        }
        hs_stereo_values r;
        xrsc_diag diag = {0};
        if (hs_stereo_frame_read(pat, a->dir, views, views_path, (uint32_t)f, cur, &diag) !=
            XRSC_OK) {
            rc = fail(&diag);
            break;
        }
        xrsc_result res = hs_stereo_frame_measure(cur, prev, &a->mo, &r);
        if (res != XRSC_OK) {
            fprintf(stderr, CMD ": error: frame %u: %s [%s]\n", (uint32_t)f,
                    xrsc_result_text(res), xrsc_result_name(res));
            rc = 1;
            break;
        }
        bool warmup = count < a->warmup;
        put_row(a, csv, (uint32_t)f, &r, warmup);
        if (!warmup)
            add_mean(m, &r);
    }
    hs_stereo_frame_free(&fr[0]);
    hs_stereo_frame_free(&fr[1]);
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
