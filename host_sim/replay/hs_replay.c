// SPDX-License-Identifier: MIT
/**
 * @file hs_replay.c
 * @brief Pose-stream replay: simulated display clock, interpolation, render, write.
 */
#include "hs_replay.h"

#include "hs_args.h"
#include "hs_file.h"
#include "hs_image.h"
#include "hs_outputs.h"
#include "hs_views.h"
#include "u_diag.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

#define NS_PER_S 1000000000.0
/** Progress appears only on runs that take longer than this. */
#define PROGRESS_AFTER_S 2.0
/** Without a terminal, one progress line per this many seconds. */
#define PROGRESS_LOG_PERIOD_S 10.0
/** xrsc.h: renderer width/height 0 mean 256 pixels. The replay sizes its buffers from the
 * resolved value, so it fills the default in itself rather than guess the library's. */
#define DEFAULT_EYE_SIZE_PX 256u
/** Display refresh rate when the headset's is 0 (xrsc_headset_default's). */
#define DEFAULT_REFRESH_HZ 90.0

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

typedef struct replay_buffers {
    float *color[2];
    uint8_t *ldr[2];
    uint8_t *sbs;
    hs_autoexposure autoexp; /**< exposure 0: automatic, over the replay's frames */
} replay_buffers;

static void buffers_free(replay_buffers *b)
{
    for (int e = 0; e < 2; e++) {
        free(b->color[e]);
        free(b->ldr[e]);
    }
    free(b->sbs);
    memset(b, 0, sizeof(*b));
}

/* Stages frame k's files (PNG eyes, PFM, side-by-side) into set (hs_file.h). */
static xrsc_result stage_frame(const hs_replay_options *opt, xrsc_renderer *r, uint32_t frame,
                               uint32_t w, uint32_t h, replay_buffers *b, hs_frame_set *set,
                               xrsc_diag *diag)
{
    static const char *const eye_name[2] = {"left", "right"};
    size_t bytes = (size_t)w * h * 4 * sizeof(float);
    if (xrsc_renderer_output_size(r, XRSC_OUTPUT_COLOR) != bytes)
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "output",
                          "colour output is %zu bytes, expected %u x %u RGBA float",
                          xrsc_renderer_output_size(r, XRSC_OUTPUT_COLOR), w, h);
    char path[HS_OUT_PATH_MAX];
    for (int e = 0; e < 2; e++) {
        xrsc_result res = xrsc_renderer_read(r, (uint32_t)e, XRSC_OUTPUT_COLOR, b->color[e], bytes);
        if (res != XRSC_OK)
            return u_diag_set(diag, res, "", 0, "output", "reading eye %d failed", e);
    }
    /* one exposure for both eyes: fixed, or automatic from the stereo frame (hs_image.h) */
    const float *const eyes[2] = {b->color[0], b->color[1]};
    hs_tonemap tm = {.exposure = opt->exposure > 0.0f
                                     ? opt->exposure
                                     : hs_autoexposure_update(&b->autoexp, eyes, 2, w, h)};
    for (int e = 0; e < 2; e++) {
        xrsc_result res;
        hs_tonemap_rgba(&tm, b->color[e], w, h, b->ldr[e]);
        if (opt->write_eyes) {
            snprintf(path, sizeof(path), "%s/frame_%05u_%s.png", opt->out_dir, frame, eye_name[e]);
            if ((res = hs_frame_set_add(set, path, diag)) != XRSC_OK ||
                (res = hs_stage_png(path, b->ldr[e], w, h, diag)) != XRSC_OK)
                return res;
        }
        if (opt->write_linear) {
            snprintf(path, sizeof(path), "%s/frame_%05u_%s.pfm", opt->out_dir, frame, eye_name[e]);
            if ((res = hs_frame_set_add(set, path, diag)) != XRSC_OK ||
                (res = hs_stage_pfm(path, b->color[e], w, h, diag)) != XRSC_OK)
                return res;
        }
    }
    if (opt->write_sbs) {
        hs_side_by_side(b->ldr[0], b->ldr[1], w, h, b->sbs);
        snprintf(path, sizeof(path), "%s/frame_%05u_sbs.png", opt->out_dir, frame);
        xrsc_result res = hs_frame_set_add(set, path, diag);
        return res != XRSC_OK ? res : hs_stage_png(path, b->sbs, 2 * w, h, diag);
    }
    return XRSC_OK;
}

/* Writes frame k's files (hs_replay.h's and hs_outputs.h's) as one set (hs_file.h). */
static xrsc_result write_frame(const hs_replay_options *opt, xrsc_renderer *r, uint32_t frame,
                               uint32_t w, uint32_t h, replay_buffers *b, hs_outputs *outs,
                               xrsc_diag *diag)
{
    hs_frame_set set = {0};
    xrsc_result res = XRSC_OK;
    if (opt->out_dir && (opt->write_eyes || opt->write_sbs || opt->write_linear))
        res = stage_frame(opt, r, frame, w, h, b, &set, diag);
    if (res == XRSC_OK)
        res = hs_outputs_frame(outs, r, frame, &set, diag);
    if (res != XRSC_OK) {
        hs_frame_set_abort(&set);
        return res;
    }
    return hs_frame_set_commit(&set, diag);
}

static void show_progress(const hs_replay_options *opt, uint32_t done, uint32_t total,
                          double started, double *last_print, bool final)
{
    if (!opt->progress)
        return;
    double t = now_s(), elapsed = t - started;
    if (elapsed < PROGRESS_AFTER_S && !(final && *last_print > 0.0))
        return;
    bool tty = isatty(STDERR_FILENO);
    if (!final && !tty && t - *last_print < PROGRESS_LOG_PERIOD_S && *last_print > 0.0)
        return;
    if (!final && tty && t - *last_print < 0.1)
        return;
    *last_print = t;
    double per = done ? elapsed / done : 0.0;
    double eta = per * (total - done);
    fprintf(stderr, "%sframe %u/%u  %.0f%%  %.2f s/frame  elapsed %.0f s  left ~%.0f s%s",
            tty ? "\r" : "", done, total, 100.0 * done / (total ? total : 1), per, elapsed, eta,
            tty ? (final ? "\n" : "   ") : "\n");
    fflush(stderr);
}

/* True when the caller left the headset zero-initialised (never filled it). */
static bool headset_is_zero(const xrsc_headset *hs)
{
    static const xrsc_headset zero;
    return memcmp(hs, &zero, sizeof(zero)) == 0;
}

/* A pixel counts as black when its linear value x exposure rounds to 0 in the 8-bit sRGB
 * PNG: 12.92 x 255 x v < 0.5 (sRGB's linear segment). */
#define BLACK_LINEAR_MAX (0.5 / (12.92 * 255.0))
#define HS_PI 3.14159265358979323846

XrPosef hs_frame_viewpoint(const xrsc_scene_info *info, const XrFovf fov[2])
{
    return hs_view_frame(info, fov, 0.0);
}

bool hs_scene_fov(const xrsc_scene_info *info, uint32_t width, uint32_t height, XrFovf *out)
{
    if (!info->has_camera || !(info->camera_yfov_rad > 0.0f) ||
        !(info->camera_yfov_rad < (float)HS_PI))
        return false;
    double aspect = info->camera_aspect_ratio > 0.0f ? info->camera_aspect_ratio
                                                     : (double)width / (height ? height : 1);
    double ty = tan(0.5 * info->camera_yfov_rad), tx = aspect * ty;
    out->angleUp = (float)atan(ty);
    out->angleDown = -out->angleUp;
    out->angleRight = (float)atan(tx);
    out->angleLeft = -out->angleRight;
    return true;
}

xrsc_result hs_replay_load_poses(const hs_replay_options *opt, hs_pose_stream **out,
                                 xrsc_diag *diag)
{
    const hs_pose_load_options lo = {
        .format = opt->pose_format,
        .columns = opt->pose_columns.count > 0 ? &opt->pose_columns : NULL,
        .max_bytes = opt->max_pose_bytes,
    };
    return hs_pose_stream_load_with(opt->poses_path, &lo, out, diag);
}

xrsc_result hs_check_start(const char *poses_path, double start_s, int64_t duration_ns,
                           xrsc_diag *diag)
{
    if (start_s * NS_PER_S <= (double)duration_ns)
        return XRSC_OK;
    return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, poses_path, 0, "--start",
                      "%.9g s is past the end of the stream, which lasts %.9g s", start_s,
                      (double)duration_ns / NS_PER_S);
}

uint32_t hs_warn_frames_past_end(const hs_replay_options *opt, int64_t duration_ns,
                                 double period_ns, uint32_t first, uint32_t last)
{
    /* As the frame counts of both paths: the span from --start in whole nanoseconds. Frame k
     * is at k periods from --start; the last within the stream is floor(span / period). */
    double span_ns = (double)(duration_ns - (int64_t)(opt->start_s * NS_PER_S));
    double inside = span_ns >= 0.0 ? floor(span_ns / period_ns) : -1.0;
    if (last <= inside || last < first)
        return 0;
    uint32_t held = inside < first ? last - first + 1 : (uint32_t)(last - inside);
    if (opt->hold_last)
        return held;
    xrsc_diag d = {0};
    char msg[1400];
    u_diag_set(&d, XRSC_WARN_FRAMES_PAST_END, opt->poses_path, 0, "--frames",
               "%u frames at %.6g Hz last %.6g s, but the stream lasts %.6g s from --start %.6g "
               "s: the last %u frames hold its last pose (--hold-last asks for that without "
               "this warning)",
               last - first + 1, NS_PER_S / period_ns, (last - first + 1) * period_ns / NS_PER_S,
               span_ns > 0.0 ? span_ns / NS_PER_S : 0.0, opt->start_s, held);
    U_LOG_W("%s", xrsc_diag_format(&d, msg, sizeof(msg)));
    return held;
}

/** Fraction of pixels of both eyes that are black (colour) or background (depth 0); -1 when
 *  the output cannot be read. */
static double eye_fraction(xrsc_renderer *r, xrsc_output out, uint32_t w, uint32_t h,
                           double exposure)
{
    size_t n = (size_t)w * h, count = 0;
    bool color = out == XRSC_OUTPUT_COLOR;
    float *px = malloc(n * (color ? 4 : 1) * sizeof(float));
    if (!px)
        return -1.0;
    for (uint32_t e = 0; e < 2; e++) {
        if (xrsc_renderer_read(r, e, out, px, n * (color ? 4 : 1) * sizeof(float)) != XRSC_OK) {
            free(px);
            return -1.0;
        }
        for (size_t i = 0; i < n; i++) {
            if (!color) {
                count += !(px[i] > 0.0f);
                continue;
            }
            float m = fmaxf(px[4 * i], fmaxf(px[4 * i + 1], px[4 * i + 2]));
            count += !(m * exposure >= BLACK_LINEAR_MAX);
        }
    }
    free(px);
    return (double)count / (double)(2 * n);
}

void hs_warn_first_frame(const hs_replay_options *opt, xrsc_renderer *r, uint32_t w, uint32_t h,
                         const xrsc_scene_info *info, const xrsc_view views[2],
                         hs_replay_stats *st)
{
    double exposure = opt->exposure > 0.0f ? opt->exposure : 1.0;
    hs_first_frame f = {.black_fraction = eye_fraction(r, XRSC_OUTPUT_COLOR, w, h, exposure),
                        .background_fraction = eye_fraction(r, XRSC_OUTPUT_DEPTH, w, h, 1.0),
                        .scene_width_m = hs_scene_width_m(info),
                        .camera_count = info->camera_count,
                        .viewpoint_inside = opt->viewpoint.kind == HS_VIEWPOINT_INSIDE,
                        .head_inside_bounds = true};
    double head[3] = {0.5 * ((double)views[0].pose.position.x + views[1].pose.position.x),
                      0.5 * ((double)views[0].pose.position.y + views[1].pose.position.y),
                      0.5 * ((double)views[0].pose.position.z + views[1].pose.position.z)};
    double d2 = 0.0;
    for (int a = 0; a < 3; a++) {
        double c = 0.5 * ((double)info->bounds_min[a] + info->bounds_max[a]);
        d2 += (head[a] - c) * (head[a] - c);
        f.head_inside_bounds &= head[a] >= info->bounds_min[a] && head[a] <= info->bounds_max[a];
    }
    f.distance_m = sqrt(d2);
    if (f.background_fraction < 0.0) /* no depth output: the black frame alone */
        f.background_fraction = 0.5;
    hs_hint hint = f.black_fraction < 0.0 ? HS_HINT_NONE : hs_first_frame_hint(&f);
    if (st) {
        st->first_frame_hint = hint;
        st->first_frame_background = f.background_fraction;
    }
    if (hint == HS_HINT_NONE)
        return;
    char msg[512];
    hs_hint_message(hint, &f, msg, sizeof msg);
    U_LOG_W("[%s] %s", hs_hint_name(hint), msg);
}

xrsc_result hs_replay_viewpoint(const hs_replay_options *opt, const xrsc_scene *scene,
                                const xrsc_scene_info *info, const XrFovf fov[2], double ipd_m,
                                XrPosef *out, xrsc_diag *diag)
{
    const hs_viewpoint *v = &opt->viewpoint;
    *out = info->viewpoint;
    switch (v->kind) {
    case HS_VIEWPOINT_CAMERA: {
        xrsc_result r = xrsc_scene_camera(scene, v->camera, out, NULL, diag);
        if (r != XRSC_OK && diag)
            snprintf(diag->field, sizeof diag->field, "%s", "--viewpoint");
        return r;
    }
    case HS_VIEWPOINT_POSITION:
        *out = hs_view_at(v->position, v->yaw_deg);
        return XRSC_OK;
    case HS_VIEWPOINT_INSIDE:
        *out = hs_view_inside(info);
        return XRSC_OK;
    default:
        if (opt->frame_bounds)
            *out = hs_view_frame(info, fov, ipd_m);
        return XRSC_OK;
    }
}

void hs_warn_narrow_scene(const xrsc_scene_info *info, double ipd_m, double used_ipd_m)
{
    double width = hs_scene_width_m(info);
    if (!(width < ipd_m))
        return;
    if (used_ipd_m < ipd_m)
        U_LOG_W("[%s] the scene is %.3g mm across, narrower than the IPD (%.3g mm): --frame "
                "uses an IPD of %.3g mm (a tenth of its viewing distance); --ipd sets another",
                hs_hint_name(HS_HINT_NARROWER_THAN_IPD), width * 1e3, ipd_m * 1e3,
                used_ipd_m * 1e3);
    else
        U_LOG_W("[%s] the scene is %.3g mm across, narrower than the IPD (%.3g mm): each eye "
                "sees it from far to its side; try --frame --direct (scales the IPD with the "
                "distance) or --ipd %.2g",
                hs_hint_name(HS_HINT_NARROWER_THAN_IPD), width * 1e3, ipd_m * 1e3,
                fmax(width * 1e3 / 4.0, 0.01));
}

void hs_replay_stats_scene(hs_replay_stats *st, const xrsc_scene *scene)
{
    xrsc_scene_get_info(scene, &st->scene);
    struct rusage ru;
    st->load_peak_rss_kib = getrusage(RUSAGE_SELF, &ru) == 0 ? ru.ru_maxrss : 0;
}

void hs_replay_stats_average(hs_replay_stats *st)
{
    if (st->frames) {
        st->render_ms_mean /= st->frames;
        st->rays_per_frame /= st->frames;
        for (uint32_t p = 0; p < st->pass_count; p++)
            st->pass_mean[p].gpu_ms /= st->frames;
    }
}

void hs_replay_stats_add(hs_replay_stats *st, xrsc_renderer *r, double render_ms,
                         xrsc_pass_timing passes[XRSC_MAX_PASSES], uint32_t *out_np)
{
    st->render_ms_mean += render_ms;
    if (render_ms > st->render_ms_max)
        st->render_ms_max = render_ms;
    uint32_t np = xrsc_renderer_timings(r, passes, XRSC_MAX_PASSES);
    if (st->frames == 0) {
        st->pass_count = np;
        for (uint32_t p = 0; p < np; p++)
            st->pass_mean[p].name = passes[p].name;
    }
    for (uint32_t p = 0; p < np && p < st->pass_count; p++)
        st->pass_mean[p].gpu_ms += passes[p].gpu_ms;
    st->rays_per_frame += (double)xrsc_renderer_rays_last_frame(r);
    *out_np = np;
}

/* What the direct replay's frames share (hs_replay_run sets it up). */
typedef struct replay_loop {
    const hs_replay_options *opt;
    xrsc_renderer *r;
    const hs_pose_stream *stream;
    xrsc_headset headset;
    XrFovf scene_fov;      /* --fov scene: both eyes' */
    uint32_t w, h, frames; /* eye size; frames to render */
    double period_ns;      /* frame spacing on the simulated clock */
    int64_t start_ns;      /* --start */
    replay_buffers buf;
    hs_outputs *outs;
    hs_views *views;            /* views.csv and the EXRs' depth (hs_views.h), or NULL */
    FILE *csv;                  /* frames.csv, or NULL */
    const hs_out_file *csv_out; /* its names */
    bool csv_header_done;
} replay_loop;

/* frames.csv: the pass columns' names after the first frame, then one row per frame. */
static void csv_row(replay_loop *L, uint32_t k, int64_t t_ns, hs_lookup lookup, double ms,
                    const xrsc_pass_timing *passes, uint32_t np)
{
    static const char *const lookup_name[] = {"exact", "interpolated", "clamped"};
    if (k == 0) {
        for (uint32_t p = 0; L->csv && p < np; p++)
            fprintf(L->csv, ",%s_gpu_ms", passes[p].name);
        if (L->csv)
            fputc('\n', L->csv);
        L->csv_header_done = true;
    }
    if (!L->csv)
        return;
    fprintf(L->csv, "%u,%lld,%s,%.3f,%llu", k, (long long)t_ns, lookup_name[lookup], ms,
            (unsigned long long)xrsc_renderer_rays_last_frame(L->r));
    for (uint32_t p = 0; p < np; p++)
        fprintf(L->csv, ",%.4f", passes[p].gpu_ms);
    fputc('\n', L->csv);
    /* Whole rows on disk after each frame: a second Ctrl-C keeps them (hs_run.h). */
    fflush(L->csv);
}

/* Renders, counts and writes frame k. */
static xrsc_result replay_frame(replay_loop *L, uint32_t k, hs_replay_stats *st,
                                xrsc_diag *diag)
{
    const hs_replay_options *opt = L->opt;
    /* Predicted display time of frame k on the simulated clock. */
    int64_t t_ns = L->start_ns + (int64_t)(k * L->period_ns + 0.5);
    /* Recorded eye views (librnr) when the stream has them, else the headset's eyes. */
    hs_view_sample eyes;
    hs_lookup lookup = hs_pose_stream_eyes(L->stream, &L->headset, t_ns, &eyes);
    xrsc_frame frame = {.display_time_ns = t_ns - L->start_ns, .frame_index = k};
    for (int e = 0; e < 2; e++) {
        frame.views[e].pose = eyes.pose[e];
        frame.views[e].fov = opt->fov_scene ? L->scene_fov : eyes.fov[e];
    }
    if (opt->on_frame)
        opt->on_frame(opt->on_frame_user, &frame);
    double t0 = now_s();
    xrsc_result res = xrsc_renderer_render(L->r, &frame);
    if (res != XRSC_OK)
        return u_diag_set(diag, res, opt->poses_path, 0, "", "rendering frame %u failed", k);
    double ms = (now_s() - t0) * 1e3;
    xrsc_pass_timing passes[XRSC_MAX_PASSES];
    uint32_t np;
    hs_replay_stats_add(st, L->r, ms, passes, &np);
    csv_row(L, k, t_ns, lookup, ms, passes, np);
    if (L->csv && ferror(L->csv)) /* the first failed write ends the run */
        return u_diag_set(diag, XRSC_ERROR_IO, L->csv_out->path, 0, "", "cannot write %s: %s",
                          L->csv_out->tmp, hs_write_error_text(L->csv, errno));
    if (k == 0)
        hs_warn_first_frame(opt, L->r, L->w, L->h, &st->scene, frame.views, st);
    if ((res = hs_views_frame(L->views, &frame, k, diag)) != XRSC_OK)
        return res;
    return write_frame(opt, L->r, k, L->w, L->h, &L->buf, L->outs, diag);
}

/* The scene's view: --fov scene's FOV, --viewpoint's or --frame's viewpoint (a scene narrower
 * than the IPD gets --frame's IPD), the stream anchored to it. */
static xrsc_result scene_view(const hs_replay_options *opt, xrsc_scene *scene,
                              replay_loop *L, hs_pose_stream *stream, xrsc_diag *diag)
{
    xrsc_scene_info info;
    xrsc_scene_get_info(scene, &info);
    if (opt->fov_scene && !hs_scene_fov(&info, L->w, L->h, &L->scene_fov))
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, opt->scene_path, 0, "--fov",
                          "--fov scene: the scene has no perspective camera with a yfov");
    XrFovf f[2] = {L->headset.fov[0], L->headset.fov[1]};
    if (opt->fov_scene)
        f[0] = f[1] = L->scene_fov;
    double ipd = L->headset.ipd_m;
    if (opt->frame_bounds && !opt->frame_keep_ipd && opt->viewpoint.kind == HS_VIEWPOINT_DEFAULT)
        L->headset.ipd_m = (float)hs_frame_ipd_m(&info, f, ipd);
    hs_warn_narrow_scene(&info, ipd, L->headset.ipd_m);
    xrsc_result res = hs_replay_viewpoint(opt, scene, &info, f, L->headset.ipd_m,
                                          &info.viewpoint, diag);
    if (res == XRSC_OK && !opt->no_anchor)
        hs_pose_stream_anchor(stream, info.viewpoint);
    return res;
}

xrsc_result hs_replay_run(const hs_replay_options *opt, hs_replay_stats *out_stats,
                          xrsc_diag *diag)
{
    double t_start = now_s();
    hs_replay_stats local_stats;
    hs_replay_stats *st = out_stats ? out_stats : &local_stats;
    memset(st, 0, sizeof(*st));
    xrsc_context *ctx = NULL;
    xrsc_scene *scene = NULL;
    hs_pose_stream *stream = NULL;
    replay_loop L = {.opt = opt};
    hs_out_file csv_file = {0}; /* frames.csv, renamed into place at the end (hs_file.h) */
    xrsc_result res;

    if (!opt || !opt->scene_path || !opt->poses_path)
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "",
                          "replay needs a scene and a pose stream");
    if (opt->out_dir && opt->out_dir[0] == '\0')
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "--out",
                          "output folder name is empty (NULL writes nothing)");
    L.headset = opt->headset;
    if (headset_is_zero(&L.headset))
        xrsc_headset_default(&L.headset);
    xrsc_renderer_options ropt = opt->renderer;
    if (ropt.width == 0)
        ropt.width = DEFAULT_EYE_SIZE_PX;
    if (ropt.height == 0)
        ropt.height = DEFAULT_EYE_SIZE_PX;
    L.w = ropt.width;
    L.h = ropt.height;

    res = hs_replay_load_poses(opt, &stream, diag);
    if (res != XRSC_OK ||
        (res = hs_check_start(opt->poses_path, opt->start_s, hs_pose_stream_duration_ns(stream),
                              diag)) != XRSC_OK ||
        (res = xrsc_context_create(&opt->context, &ctx, diag)) != XRSC_OK)
        goto done;
    snprintf(st->device, sizeof(st->device), "%s", xrsc_context_device_name(ctx));
    if ((res = xrsc_scene_load(ctx, opt->scene_path, &opt->scene, &scene, diag)) != XRSC_OK)
        goto done;
    hs_replay_stats_scene(st, scene);
    if ((res = scene_view(opt, scene, &L, stream, diag)) != XRSC_OK ||
        (res = xrsc_renderer_create(ctx, scene, &ropt, &L.r, diag)) != XRSC_OK)
        goto done;
    L.stream = stream;
    st->load_s = now_s() - t_start;

    size_t n = (size_t)L.w * L.h;
    for (int e = 0; e < 2; e++) {
        L.buf.color[e] = malloc(n * 4 * sizeof(float));
        L.buf.ldr[e] = malloc(n * 3);
    }
    L.buf.sbs = malloc(n * 6);
    if (!L.buf.color[0] || !L.buf.color[1] || !L.buf.ldr[0] || !L.buf.ldr[1] || !L.buf.sbs) {
        res = u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, "", 0, "", "image buffers");
        goto done;
    }
    L.period_ns = NS_PER_S / (L.headset.refresh_hz > 0 ? L.headset.refresh_hz : DEFAULT_REFRESH_HZ);
    L.start_ns = (int64_t)(opt->start_s * NS_PER_S);
    int64_t span_ns = hs_pose_stream_duration_ns(stream) - L.start_ns;
    L.frames = opt->frames;
    if (L.frames == 0)
        L.frames = span_ns > 0 ? (uint32_t)(span_ns / L.period_ns) + 1 : 1;
    hs_warn_frames_past_end(opt, hs_pose_stream_duration_ns(stream), L.period_ns, 0,
                            L.frames - 1);

    if (opt->out_dir) {
        if ((res = hs_make_dirs(opt->out_dir, "--out", diag)) != XRSC_OK)
            goto done;
        char path[1100];
        snprintf(path, sizeof(path), "%s/frames.csv", opt->out_dir);
        if ((res = hs_out_open(&csv_file, path, diag)) != XRSC_OK)
            goto done;
        L.csv = csv_file.f;
        L.csv_out = &csv_file;
        fprintf(L.csv, "frame,display_time_ns,lookup,render_wall_ms,rays");
    }
    if ((res = hs_outputs_open(opt, L.w, L.h, NS_PER_S / L.period_ns, &L.outs, diag)) != XRSC_OK ||
        (res = hs_views_open(opt, ctx, scene, L.w, L.h, &L.views, diag)) != XRSC_OK)
        goto done;
    hs_outputs_set_depth(L.outs, hs_views_depth(L.views));

    double started = now_s(), last_print = 0.0;
    for (uint32_t k = 0; k < L.frames; k++) {
        if (opt->stop && *opt->stop) { /* Ctrl-C: the frames so far are complete */
            st->stopped_by = *opt->stop;
            break;
        }
        if ((res = replay_frame(&L, k, st, diag)) != XRSC_OK)
            goto done;
        st->frames = k + 1;
        show_progress(opt, k + 1, L.frames, started, &last_print, k + 1 == L.frames);
    }
    hs_replay_stats_average(st);
    res = XRSC_OK;

done:
    if (L.csv && !L.csv_header_done)
        fputc('\n', L.csv); /* the header waits for the first frame's pass names */
    if (L.csv) { /* its rows so far are whole, also after an error */
        xrsc_result closed = hs_out_close(&csv_file, true, res == XRSC_OK ? diag : NULL);
        if (res == XRSC_OK)
            res = closed;
    }
    xrsc_result out_res = hs_outputs_close(&L.outs, res == XRSC_OK, res == XRSC_OK ? diag : NULL);
    if (res == XRSC_OK)
        res = out_res;
    out_res = hs_views_close(&L.views, true, res == XRSC_OK ? diag : NULL); /* rows whole */
    if (res == XRSC_OK)
        res = out_res;
    buffers_free(&L.buf);
    xrsc_renderer_destroy(&L.r);
    xrsc_scene_destroy(&scene);
    /* Counted after the renderer and scene are gone, so errors at their destruction count. */
    st->validation_errors = xrsc_context_validation_errors(ctx);
    if (st->validation_errors > 0)
        U_LOG_W("the Vulkan validation layer reported %u errors", st->validation_errors);
    xrsc_context_destroy(&ctx);
    hs_pose_stream_destroy(&stream);
    st->total_s = now_s() - t_start;
    return res;
}

xrsc_blend hs_replay_default_blend(xrsc_method method)
{
    return method == XRSC_METHOD_SAMPLECACHE || method == XRSC_METHOD_ISRT ||
                   method == XRSC_METHOD_HYBRID
               ? XRSC_BLEND_MOMENTS
               : XRSC_BLEND_NONE;
}

xrsc_taa_mode hs_replay_default_taa(xrsc_method method)
{
    return method == XRSC_METHOD_SAMPLECACHE ? XRSC_TAA_ON : XRSC_TAA_DEFAULT;
}

void hs_replay_default_shading(xrsc_renderer_options *o, bool shade_given, bool rate_given)
{
    bool product = o->method == XRSC_METHOD_SAMPLECACHE && !shade_given;
    if (!shade_given)
        o->samplecache.shade = product ? XRSC_SC_SHADE_ADAPTIVE_VARIANCE : XRSC_SC_SHADE_DEFAULT;
    if (!rate_given)
        o->samplecache.shade_rate = product ? HS_REPLAY_DEFAULT_SHADE_RATE : 0.0f;
}

void hs_replay_default_rules(xrsc_renderer_options *o, hs_replay_given given)
{
    bool product = o->method == XRSC_METHOD_SAMPLECACHE;
    if (!given.taa_motion)
        o->taa.motion = product ? XRSC_TAA_MOTION_EDGES : XRSC_TAA_MOTION_DEFAULT;
    if (!given.blend_instances)
        o->blend_instance_test = product;
    if (!given.moving)
        o->samplecache.moving = product;
    if (!given.cover)
        o->samplecache.cover = product;
}

void hs_replay_default_renderer(xrsc_renderer_options *out)
{
    *out = (xrsc_renderer_options){.method = XRSC_METHOD_SAMPLECACHE,
                                   .width = HS_REPLAY_DEFAULT_SIZE_PX,
                                   .height = HS_REPLAY_DEFAULT_SIZE_PX,
                                   .spp = {.samples_per_pixel = HS_REPLAY_DEFAULT_SPP}};
    out->blend = hs_replay_default_blend(out->method);
    out->taa.mode = hs_replay_default_taa(out->method);
    hs_replay_default_shading(out, false, false);
    hs_replay_default_rules(out, (hs_replay_given){0});
}
