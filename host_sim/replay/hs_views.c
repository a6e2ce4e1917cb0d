// SPDX-License-Identifier: MIT
/**
 * @file hs_views.c
 * @brief views.csv and the pixel-centre depth of a replay's frames (hs_views.h).
 */
#include "hs_views.h"

#include "hs_file.h"
#include "hs_views_csv.h"
#include "u_diag.h"

#include <stdio.h>
#include <stdlib.h>

struct hs_views {
    hs_out_file csv;
    uint32_t w, h;
    xrsc_renderer *depth_r; /**< `primary`, with --write exr */
};

xrsc_result hs_views_open(const hs_replay_options *opt, xrsc_context *ctx, xrsc_scene *scene,
                          uint32_t w, uint32_t h, hs_views **out, xrsc_diag *diag)
{
    *out = NULL;
    if (!opt->out_dir)
        return XRSC_OK;
    hs_views *v = calloc(1, sizeof(*v));
    if (!v)
        return u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, "", 0, "", "views");
    v->w = w;
    v->h = h;
    char path[HS_OUT_PATH_MAX];
    snprintf(path, sizeof(path), "%s/" HS_VIEWS_CSV, opt->out_dir);
    xrsc_result res = hs_out_open(&v->csv, path, diag);
    if (res == XRSC_OK && opt->write_exr) {
        /* Depth at pixel centres, as `xrsc bench` reprojects by (hs_views.h). */
        xrsc_renderer_options dro = {.method = XRSC_METHOD_PRIMARY, .width = w, .height = h};
        res = xrsc_renderer_create(ctx, scene, &dro, &v->depth_r, diag);
    }
    if (res != XRSC_OK) {
        hs_views_close(&v, false, NULL);
        return res;
    }
    hs_views_csv_header(v->csv.f);
    *out = v;
    return XRSC_OK;
}

xrsc_result hs_views_frame(hs_views *v, const xrsc_frame *frame, uint32_t number, xrsc_diag *diag)
{
    if (!v)
        return XRSC_OK;
    for (uint32_t e = 0; e < 2; e++)
        hs_views_csv_row(v->csv.f, number, e, frame->display_time_ns, &frame->views[e].pose,
                         &frame->views[e].fov, v->w, v->h);
    xrsc_result res = v->depth_r ? xrsc_renderer_render(v->depth_r, frame) : XRSC_OK;
    if (res != XRSC_OK)
        return u_diag_set(diag, res, "", 0, "--write exr", "rendering frame %u's depth failed",
                          number);
    return XRSC_OK;
}

xrsc_renderer *hs_views_depth(hs_views *v)
{
    return v ? v->depth_r : NULL;
}

xrsc_result hs_views_close(hs_views **pv, bool keep, xrsc_diag *diag)
{
    hs_views *v = pv ? *pv : NULL;
    if (!v)
        return XRSC_OK;
    *pv = NULL;
    xrsc_result res = v->csv.f ? hs_out_close(&v->csv, keep, diag) : XRSC_OK;
    xrsc_renderer_destroy(&v->depth_r);
    free(v);
    return res;
}
