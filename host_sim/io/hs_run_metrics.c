// SPDX-License-Identifier: MIT
/**
 * @file hs_run_metrics.c
 * @brief Metrics of run folders read back: frame pairs, a run's eyes, stereo frames
 *        (hs_run_metrics.h).
 */
#include "hs_run_metrics.h"

#include "hs_exr.h"
#include "u_diag.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PATH_CHARS 4096

void hs_frame_pair_free(hs_frame_pair *p)
{
    free(p->test);
    free(p->ref);
    memset(p, 0, sizeof(*p));
}

xrsc_result hs_frame_pair_read(const char *ref_path, const char *test_path, hs_frame_pair *out,
                               xrsc_diag *diag)
{
    memset(out, 0, sizeof(*out));
    uint32_t tw = 0, th = 0;
    xrsc_result r = hs_read_frame(ref_path, &out->ref, &out->w, &out->h, NULL, diag);
    if (r == XRSC_OK)
        r = hs_read_frame(test_path, &out->test, &tw, &th, NULL, diag);
    if (r == XRSC_OK && (tw != out->w || th != out->h)) {
        r = XRSC_ERROR_INVALID_ARGUMENT;
        u_diag_set(diag, r, "", 0, NULL, "%s is %ux%u but %s is %ux%u", test_path, tw, th,
                   ref_path, out->w, out->h);
    }
    if (r != XRSC_OK)
        hs_frame_pair_free(out);
    return r;
}

xrsc_result hs_frame_pair_score(const hs_frame_pair *p, const xrsc_metrics_options *mo,
                                bool with_cpbd, hs_pair_scores *out)
{
    memset(out, 0, sizeof(*out));
    xrsc_result r = xrsc_metrics_error(p->test, p->ref, p->w, p->h, mo, &out->err);
    if (r == XRSC_OK)
        r = xrsc_metrics_ssim(p->test, p->ref, p->w, p->h, mo, &out->ssim, NULL);
    if (r == XRSC_OK && with_cpbd)
        r = xrsc_metrics_cpbd(p->test, p->w, p->h, mo, &out->cpbd_test);
    if (r == XRSC_OK && with_cpbd)
        r = xrsc_metrics_cpbd(p->ref, p->w, p->h, mo, &out->cpbd_ref);
    out->psnr_db = out->err.mse > 0.0 ? -10.0 * log10(out->err.mse) : INFINITY;
    return r;
}

bool hs_file_exists(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return false;
    fclose(f);
    return true;
}

/* fmt with its first "left" as "right"; false if it has none or does not fit. */
static bool right_partner(const char *fmt, char *out, size_t size)
{
    const char *l = strstr(fmt, "left");
    if (!l || (size_t)(l - fmt) + strlen(fmt) + 2 >= size)
        return false;
    snprintf(out, size, "%.*sright%s", (int)(l - fmt), fmt, l + 4);
    return true;
}

bool hs_run_eyes_of(const char *fmt, const char *dir, uint32_t first, hs_run_eyes *out)
{
    memset(out, 0, sizeof(*out));
    if (!hs_frame_pattern_parse(fmt, &out->pat[0]))
        return false;
    out->count = 1;
    out->eye[0] = strstr(fmt, "left") ? "left" : "-";
    char right[1100], path[PATH_CHARS];
    if (right_partner(fmt, right, sizeof(right)) &&
        hs_frame_pattern_parse(right, &out->pat[1]) &&
        hs_frame_pattern_path(dir, &out->pat[1], first, path, sizeof(path)) &&
        hs_file_exists(path)) {
        out->count = 2;
        out->eye[1] = "right";
    }
    return true;
}

bool hs_stereo_patterns(const char *fmt, hs_frame_pattern out[2], const char **out_why)
{
    fmt = fmt ? fmt : "frame_%05u_left.exr";
    char right[1100];
    size_t n = strlen(fmt);
    if (!strstr(fmt, "left") || n < 4 || strcmp(fmt + n - 4, ".exr") != 0 ||
        !right_partner(fmt, right, sizeof(right))) {
        *out_why = "--stereo needs the left eye's EXR names (with \"left\", ending .exr)";
        return false;
    }
    if (!hs_frame_pattern_parse(fmt, &out[0]) || !hs_frame_pattern_parse(right, &out[1])) {
        *out_why = "expected one %u (e.g. frame_%05u_left.exr)";
        return false;
    }
    return true;
}

void hs_stereo_frame_free(hs_stereo_frame *f)
{
    for (int e = 0; e < 2; e++) {
        free(f->rgba[e]);
        free(f->depth[e]);
    }
    memset(f, 0, sizeof(*f));
}

/* Eye e of frame f: its EXR's colour and Z, its camera from views.csv. */
static xrsc_result read_eye(const hs_frame_pattern *pat, const char *dir,
                            const hs_views_table *views, const char *views_path, uint32_t f,
                            int e, hs_stereo_frame *out, xrsc_diag *diag)
{
    char path[PATH_CHARS];
    uint32_t w = 0, h = 0;
    const char *eye = e ? "right" : "left";
    if (!hs_frame_pattern_path(dir, pat, f, path, sizeof(path)))
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, dir, 0, NULL, "path too long");
    xrsc_result r = hs_read_exr(path, &out->rgba[e], &out->depth[e], &w, &h, diag);
    if (r != XRSC_OK)
        return r;
    if (!out->depth[e])
        return u_diag_set(diag, XRSC_ERROR_BAD_HEADER, path, 0, "Z",
                          "no Z (depth) channel: write the frames with --write exr");
    const hs_view_row *row = hs_views_find(views, f, (uint32_t)e);
    if (!row)
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, views_path, 0, "frame",
                          "no row for frame %u, eye %s (needed by %s)", f, eye, path);
    out->camera[e] = row->camera;
    if (row->camera.width == 0 && row->camera.height == 0) {
        out->camera[e].width = w;
        out->camera[e].height = h;
    } else if (row->camera.width != w || row->camera.height != h) {
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, views_path, 0, "width",
                          "frame %u, eye %s is %ux%u here but %s is %ux%u", f, eye,
                          row->camera.width, row->camera.height, path, w, h);
    }
    return XRSC_OK;
}

xrsc_result hs_stereo_frame_read(const hs_frame_pattern pat[2], const char *dir,
                                 const hs_views_table *views, const char *views_path, uint32_t f,
                                 hs_stereo_frame *out, xrsc_diag *diag)
{
    hs_stereo_frame_free(out);
    xrsc_result r = read_eye(&pat[0], dir, views, views_path, f, 0, out, diag);
    return r == XRSC_OK ? read_eye(&pat[1], dir, views, views_path, f, 1, out, diag) : r;
}

static xrsc_metrics_view view_of(const hs_stereo_frame *f, int e)
{
    xrsc_metrics_view v = {.rgba = f->rgba[e], .depth_m = f->depth[e], .camera = f->camera[e]};
    return v;
}

xrsc_result hs_stereo_frame_measure(const hs_stereo_frame *cur, const hs_stereo_frame *prev,
                                    const xrsc_metrics_options *mo, hs_stereo_values *out)
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
    if (res == XRSC_OK && prev && out->temporal_valid)
        out->temporal = sum / (double)out->temporal_valid;
    return res;
}
