// SPDX-License-Identifier: MIT
/**
 * @file t_stab.h
 * @brief Helpers of the stability tests (issue 9): a case's scene and pose stream (anchored at
 *        the scene's camera, as the replay does), frames at 90 Hz, both eyes' colour, depth and
 *        first-hit ids, converged references and the region metrics of xrsc_metrics.h. Public
 *        API only; the validation layer is on and its error count is checked at the end.
 */
#pragma once

#include "hs_pose_stream.h"
#include "testing.h"
#include "xrsc/xrsc.h"
#include "xrsc/xrsc_math.h"
#include "xrsc/xrsc_metrics.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define TS_RATE_HZ 90.0
#define TS_MAX_INSTANCES 64

/** One case: context (validation on), scene, anchored pose stream, the default headset. */
typedef struct ts_rig {
    xrsc_context *ctx;
    xrsc_scene *scene;
    hs_pose_stream *poses;
    xrsc_headset hs;
    uint32_t w, h;
    uint8_t flags[TS_MAX_INSTANCES];
    uint32_t instance_count;
} ts_rig;

/** Both eyes of one rendered frame, as read back. */
typedef struct ts_views {
    xrsc_frame frame;
    float *rgba[2];
    float *depth[2];
    uint32_t *hit[2];
} ts_views;

/** Opens scene_rel (with scene options so, may be NULL) and poses_rel for w x w eyes. */
static inline bool ts_open_with(ts_rig *r, const char *scene_rel, const xrsc_scene_options *so,
                                const char *poses_rel, uint32_t w)
{
    memset(r, 0, sizeof(*r));
    r->w = r->h = w;
    xrsc_headset_default(&r->hs);
    xrsc_context_options co = {.validation = true};
    CHECK_EQ_INT(xrsc_context_create(&co, &r->ctx, NULL), XRSC_OK);
    if (!r->ctx)
        return false;
    CHECK_EQ_INT(xrsc_scene_load(r->ctx, t_source_path(scene_rel), so, &r->scene, NULL), XRSC_OK);
    xrsc_diag diag = {0};
    CHECK_EQ_INT(
        hs_pose_stream_load(t_source_path(poses_rel), HS_POSE_FORMAT_AUTO, &r->poses, &diag),
        XRSC_OK);
    if (!r->scene || !r->poses)
        return false;
    xrsc_scene_info info;
    xrsc_scene_get_info(r->scene, &info);
    CHECK(info.has_camera);
    hs_pose_stream_anchor(r->poses, info.viewpoint); /* as the replay: first pose = camera */
    r->instance_count = xrsc_scene_instance_flags(r->scene, r->flags, TS_MAX_INSTANCES);
    CHECK(r->instance_count <= TS_MAX_INSTANCES);
    return true;
}

static inline bool ts_open(ts_rig *r, const char *scene_rel, const char *poses_rel, uint32_t w)
{
    return ts_open_with(r, scene_rel, NULL, poses_rel, w);
}

static inline void ts_close(ts_rig *r)
{
    hs_pose_stream_destroy(&r->poses);
    xrsc_scene_destroy(&r->scene);
    if (r->ctx)
        CHECK_EQ_INT(xrsc_context_validation_errors(r->ctx), 0);
    xrsc_context_destroy(&r->ctx);
}

/** Display time of frame k at 90 Hz from the stream's start (also the scene's animation time). */
static inline int64_t ts_time_ns(uint32_t k)
{
    return (int64_t)llround((double)k * 1e9 / TS_RATE_HZ);
}

/** Frame k: the stream's head pose at its time, the headset's eyes, scene time = that time. */
static inline xrsc_frame ts_frame(const ts_rig *r, uint32_t k)
{
    XrPosef head, eyes[2];
    hs_pose_stream_sample(r->poses, ts_time_ns(k), &head);
    xrsc_headset_eye_poses(&r->hs, head, eyes);
    xrsc_frame f = {.display_time_ns = ts_time_ns(k), .frame_index = k};
    for (int e = 0; e < 2; e++) {
        f.views[e].pose = eyes[e];
        f.views[e].fov = r->hs.fov[e];
    }
    return f;
}

static inline xrsc_renderer *ts_renderer(ts_rig *r, xrsc_renderer_options ro)
{
    ro.width = r->w;
    ro.height = r->h;
    xrsc_renderer *rd = NULL;
    xrsc_diag diag = {0};
    xrsc_result res = xrsc_renderer_create(r->ctx, r->scene, &ro, &rd, &diag);
    CHECK_EQ_INT(res, XRSC_OK);
    if (res != XRSC_OK) {
        char msg[1400];
        fprintf(stderr, "%s\n", xrsc_diag_format(&diag, msg, sizeof(msg)));
    }
    return rd;
}

static inline void ts_views_alloc(const ts_rig *r, ts_views *v)
{
    size_t n = (size_t)r->w * r->h;
    for (int e = 0; e < 2; e++) {
        v->rgba[e] = calloc(n, 16);
        v->depth[e] = calloc(n, 4);
        v->hit[e] = calloc(n, 16);
    }
}

static inline void ts_views_free(ts_views *v)
{
    for (int e = 0; e < 2; e++) {
        free(v->rgba[e]);
        free(v->depth[e]);
        free(v->hit[e]);
    }
    memset(v, 0, sizeof(*v));
}

/** Renders frame f and reads both eyes' colour, depth and first-hit ids into v. */
static inline bool ts_render(const ts_rig *r, xrsc_renderer *rd, const xrsc_frame *f, ts_views *v)
{
    size_t n = (size_t)r->w * r->h;
    bool ok = xrsc_renderer_render(rd, f) == XRSC_OK;
    for (uint32_t e = 0; ok && e < 2; e++)
        ok = xrsc_renderer_read(rd, e, XRSC_OUTPUT_COLOR, v->rgba[e], n * 16) == XRSC_OK &&
             xrsc_renderer_read(rd, e, XRSC_OUTPUT_DEPTH, v->depth[e], n * 4) == XRSC_OK &&
             xrsc_renderer_read(rd, e, XRSC_OUTPUT_HIT_ID, v->hit[e], n * 16) == XRSC_OK;
    CHECK(ok);
    v->frame = *f;
    return ok;
}

/** Renders a converged reference of frame f (the renderer is `spp` with many samples per
 *  frame; `accumulated` frames of it at the same view and time are averaged). */
static inline bool ts_reference(const ts_rig *r, xrsc_renderer *ref, const xrsc_frame *f,
                                uint32_t accumulated, ts_views *v)
{
    bool ok = true;
    for (uint32_t k = 0; ok && k < accumulated; k++) {
        xrsc_frame fk = *f;
        fk.frame_index = 1000000u + k; /* a random stream of its own */
        ok = ts_render(r, ref, &fk, v);
    }
    return ok;
}

static inline xrsc_metrics_camera ts_camera(const ts_rig *r, const xrsc_frame *f, uint32_t eye)
{
    xrsc_metrics_camera c = {
        .pose = f->views[eye].pose, .fov = f->views[eye].fov, .width = r->w, .height = r->h};
    return c;
}

/** Region mask of one eye of `cur` (prev: the last frame, NULL for no UNCOVERED region). */
static inline void ts_regions(const ts_rig *r, const ts_views *cur, const ts_views *prev,
                              uint32_t eye, uint8_t *mask)
{
    xrsc_region_input in = {.width = r->w,
                            .height = r->h,
                            .hit_id = cur->hit[eye],
                            .depth_m = cur->depth[eye],
                            .camera = ts_camera(r, &cur->frame, eye),
                            .other_depth_m = cur->depth[1 - eye],
                            .other_hit_id = cur->hit[1 - eye],
                            .other_camera = ts_camera(r, &cur->frame, 1 - eye),
                            .instance_flags = r->flags,
                            .instance_count = r->instance_count};
    if (prev) {
        in.prev_hit_id = prev->hit[eye];
        in.prev_depth_m = prev->depth[eye];
        in.prev_camera = ts_camera(r, &prev->frame, eye);
    }
    CHECK_EQ_INT(xrsc_metrics_regions(&in, NULL, mask), XRSC_OK);
}

/** relMSE of img against ref over the region's pixels; *count their number. */
static inline double ts_region_relmse(const ts_rig *r, const float *img, const float *ref,
                                      const uint8_t *mask, xrsc_region region, uint64_t *count)
{
    xrsc_error_metrics em = {0};
    CHECK_EQ_INT(xrsc_metrics_region_error(img, ref, mask, region, r->w, r->h, NULL, &em, count),
                 XRSC_OK);
    return em.relmse;
}

/** Mean and standard error of the mean of x[0..n). */
static inline void ts_mean_se(const double *x, uint32_t n, double *mean, double *se)
{
    double s = 0.0, s2 = 0.0;
    for (uint32_t i = 0; i < n; i++)
        s += x[i];
    *mean = n ? s / n : 0.0;
    for (uint32_t i = 0; i < n; i++)
        s2 += (x[i] - *mean) * (x[i] - *mean);
    *se = n > 1 ? sqrt(s2 / (n - 1) / n) : 0.0;
}

/** Pixels of one eye's region. */
static inline uint64_t ts_region_count(const ts_rig *r, const uint8_t *mask, xrsc_region region)
{
    uint64_t c = 0;
    for (size_t i = 0; i < (size_t)r->w * r->h; i++)
        c += (mask[i] >> region) & 1u;
    return c;
}
