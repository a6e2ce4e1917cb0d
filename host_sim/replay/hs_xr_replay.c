// SPDX-License-Identifier: MIT
/**
 * @file hs_xr_replay.c
 * @brief The OpenXR path of `xrsc replay`: configure the runtime, then run the plugin's
 *        OpenXR frame loop until the runtime ends the session.
 */
#define _GNU_SOURCE /* pipe2 */
#include "hs_xr_replay.h"

#include "hs_args.h"
#include "hs_outputs.h"
#include "hs_views.h"
#include "hs_preview_link.h"
#include "u_diag.h"
#include "xrsc/xrsc_xr.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#ifndef HS_XR_DEFAULT_MANIFEST
#define HS_XR_DEFAULT_MANIFEST ""
#endif

#define NS_PER_S 1e9
/** As hs_replay.c: renderer size 0 means 256 pixels; display refresh 0 means 90 Hz. */
#define DEFAULT_EYE_SIZE_PX 256u
#define DEFAULT_REFRESH_HZ 90.0
/** A session that renders nothing for this long has stalled (the runtime never started it). */
#define STALL_LIMIT_S 30.0

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

static bool file_exists(const char *path)
{
    struct stat st;
    return path && *path && stat(path, &st) == 0 && S_ISREG(st.st_mode);
}

static xrsc_result set_env(const char *name, const char *value, xrsc_diag *diag)
{
    if (setenv(name, value, 1) != 0)
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, name, "setenv failed: %s",
                          strerror(errno));
    return XRSC_OK;
}

/** Picks the runtime: XR_RUNTIME_JSON as given, else this build's manifest. */
static xrsc_result choose_runtime(xrsc_diag *diag)
{
    const char *json = getenv("XR_RUNTIME_JSON");
    if (json && *json) {
        if (!file_exists(json))
            return u_diag_set(diag, XRSC_ERROR_XR_RUNTIME_UNAVAILABLE, json, 0,
                              "XR_RUNTIME_JSON",
                              "XR_RUNTIME_JSON names no runtime manifest file ('%s'); unset it "
                              "to use this build's (%s), or run with --direct",
                              json, HS_XR_DEFAULT_MANIFEST);
        return XRSC_OK;
    }
    if (!file_exists(HS_XR_DEFAULT_MANIFEST))
        return u_diag_set(diag, XRSC_ERROR_XR_RUNTIME_UNAVAILABLE, HS_XR_DEFAULT_MANIFEST, 0,
                          "XR_RUNTIME_JSON",
                          "XR_RUNTIME_JSON is unset and this build's runtime manifest '%s' is "
                          "missing (build the target xrsc_runtime), or run with --direct",
                          HS_XR_DEFAULT_MANIFEST);
    return set_env("XR_RUNTIME_JSON", HS_XR_DEFAULT_MANIFEST, diag);
}

/** Sets the runtime's configuration from the options (hs_xr_replay.h). */
static xrsc_result configure_runtime(const hs_replay_options *opt, const hs_pose_stream *stream,
                                     uint32_t w, uint32_t h, double refresh_hz,
                                     uint32_t session_frames, xrsc_diag *diag)
{
    xrsc_result res;
    char buf[1100];
    if ((res = set_env("XRSC_RT_POSES", opt->poses_path, diag)) != XRSC_OK)
        return res;
    snprintf(buf, sizeof(buf), "%u", session_frames);
    if ((res = set_env("XRSC_RT_FRAMES", buf, diag)) != XRSC_OK)
        return res;
    /* --write exr alone: the runtime writes frames.csv only (the program writes the EXRs). */
    bool write = opt->out_dir &&
                 (opt->write_eyes || opt->write_sbs || opt->write_linear || opt->write_exr);
    if ((res = set_env("XRSC_RT_OUT", write ? opt->out_dir : "", diag)) != XRSC_OK)
        return res;
    snprintf(buf, sizeof(buf), "%s%s%s", opt->write_eyes ? "eyes," : "",
             opt->write_sbs ? "sbs," : "", opt->write_linear ? "linear," : "");
    if (buf[0])
        buf[strlen(buf) - 1] = '\0';
    else
        snprintf(buf, sizeof(buf), "none");
    if (write && (res = set_env("XRSC_RT_WRITE", buf, diag)) != XRSC_OK)
        return res;
    if (opt->exposure > 0.0f) /* else automatic (hs_image.h) */
        snprintf(buf, sizeof(buf), "%.9g", (double)opt->exposure);
    else
        snprintf(buf, sizeof(buf), "auto");
    if ((res = set_env("XRSC_RT_EXPOSURE", buf, diag)) != XRSC_OK)
        return res;
    snprintf(buf, sizeof(buf), "%ux%u", w, h);
    if ((res = set_env("XRSC_RT_EYE_SIZE", buf, diag)) != XRSC_OK)
        return res;
    snprintf(buf, sizeof(buf), "%.9g", refresh_hz);
    if ((res = set_env("XRSC_RT_REFRESH_HZ", buf, diag)) != XRSC_OK)
        return res;
    const char *dev = opt->context.device && *opt->context.device ? opt->context.device
                                                                   : getenv("XRSC_DEVICE");
    if (dev && *dev && (res = set_env("XRSC_RT_DEVICE", dev, diag)) != XRSC_OK)
        return res;
    /* --ipd and --start (always set, so a value left in the environment does not apply). */
    static const xrsc_headset zero;
    xrsc_headset hs = opt->headset;
    if (memcmp(&hs, &zero, sizeof(zero)) == 0) /* as hs_replay_run: all zero is the default */
        xrsc_headset_default(&hs);
    snprintf(buf, sizeof(buf), "%.9g", (double)hs.ipd_m * 1e3);
    if ((res = set_env("XRSC_RT_IPD_MM", buf, diag)) != XRSC_OK)
        return res;
    /* The per-eye FOVs (--headset), so xrLocateViews reports the direct path's frusta. */
    const double deg = 180.0 / 3.14159265358979323846;
    snprintf(buf, sizeof(buf), "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g",
             hs.fov[0].angleLeft * deg, hs.fov[0].angleRight * deg, hs.fov[0].angleUp * deg,
             hs.fov[0].angleDown * deg, hs.fov[1].angleLeft * deg, hs.fov[1].angleRight * deg,
             hs.fov[1].angleUp * deg, hs.fov[1].angleDown * deg);
    if ((res = set_env("XRSC_RT_FOV_DEG", buf, diag)) != XRSC_OK)
        return res;
    /* Round-trips the double, so the runtime's start (int64_t)(s * 1e9) is the direct path's
     * to the nanosecond, and so is the anchored time (frame 0's minus the start). */
    snprintf(buf, sizeof(buf), "%.17g", opt->start_s);
    if ((res = set_env("XRSC_RT_START_S", buf, diag)) != XRSC_OK)
        return res;
    /* --max-pose-bytes: the runtime reads the same file with the same limit. */
    snprintf(buf, sizeof(buf), "%llu", (unsigned long long)opt->max_pose_bytes);
    if ((res = set_env("XRSC_RT_MAX_POSE_BYTES", buf, diag)) != XRSC_OK)
        return res;
    const char *pace = getenv("XRSC_RT_PACE");
    if ((!pace || !*pace) && (res = set_env("XRSC_RT_PACE", "fast", diag)) != XRSC_OK)
        return res;
    (void)stream;
    return XRSC_OK;
}

/* The pose stream, read here too: a bad one is reported with file, line and field before any
 * runtime starts, and its duration gives the frame count. --pose-columns: the runtime reads
 * the canonical format, so it gets a converted copy (`imported`, *opt then points to conv).
 * The runtime reads a stream by format detection, so a forced format must be the detected. */
static xrsc_result load_stream(const hs_replay_options **opt, hs_replay_options *conv,
                               char *imported, size_t imported_size, hs_pose_stream **stream,
                               xrsc_diag *diag)
{
    const hs_replay_options *o = *opt;
    xrsc_result res;
    if (o->pose_columns.count > 0) {
        if ((res = hs_replay_load_poses(o, stream, diag)) != XRSC_OK)
            return res;
        const char *tmp = getenv("TMPDIR");
        snprintf(imported, imported_size, "%s/xrsc-poses-XXXXXX", tmp && *tmp ? tmp : "/tmp");
        int fd = mkstemp(imported);
        if (fd < 0) {
            imported[0] = '\0';
            return u_diag_set(diag, XRSC_ERROR_IO, "", 0, "--pose-columns",
                              "cannot create a temporary file: %s", strerror(errno));
        }
        close(fd);
        if ((res = hs_pose_stream_save(*stream, imported, diag)) != XRSC_OK)
            return res;
        *conv = *o;
        conv->poses_path = imported;
        conv->pose_format = HS_POSE_FORMAT_AUTO;
        *opt = o = conv;
    } else if ((res = hs_replay_load_poses(o, stream, diag)) != XRSC_OK) {
        return res;
    }
    if ((res = hs_check_start(o->poses_path, o->start_s, hs_pose_stream_duration_ns(*stream),
                              diag)) != XRSC_OK)
        return res;
    if (o->pose_format == HS_POSE_FORMAT_AUTO)
        return XRSC_OK;
    hs_pose_stream *probe = NULL;
    xrsc_diag pd = {0};
    const hs_pose_load_options auto_opt = {.max_bytes = o->max_pose_bytes};
    bool same = hs_pose_stream_load_with(o->poses_path, &auto_opt, &probe, &pd) == XRSC_OK &&
                probe->format == o->pose_format;
    hs_pose_stream_destroy(&probe);
    if (!same)
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, o->poses_path, 0, "--pose-format",
                          "the runtime detects the format itself and would not read this file "
                          "as %s; use --direct",
                          hs_pose_format_name(o->pose_format));
    return XRSC_OK;
}

/* --fov scene: the glTF camera's yfov and aspect for both eyes, read from the file before the
 * runtime starts and given to it as the headset's FOV (XRSC_RT_FOV_DEG), so that
 * xrLocateViews reports the frusta the direct path renders (*opt then points to copy). */
static xrsc_result use_scene_fov(const hs_replay_options **opt, hs_replay_options *copy,
                                 uint32_t w, uint32_t h, xrsc_diag *diag)
{
    xrsc_scene_info si;
    XrFovf f;
    xrsc_result res = xrsc_scene_inspect((*opt)->scene_path, &si, diag);
    if (res != XRSC_OK)
        return res;
    if (!hs_scene_fov(&si, w, h, &f))
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, (*opt)->scene_path, 0, "--fov",
                          "--fov scene: the scene has no perspective camera with a yfov");
    static const xrsc_headset zero;
    *copy = **opt;
    if (memcmp(&copy->headset, &zero, sizeof(zero)) == 0)
        xrsc_headset_default(&copy->headset);
    copy->headset.fov[0] = copy->headset.fov[1] = f;
    *opt = copy;
    return XRSC_OK;
}

/* XRSC_RT_ERROR_FD: a pipe on which host_sim's runtime sends the error that ended its session
 * (a frame it could not write), so that the run reports that error, once, instead of the lost
 * session it causes. fd[0] reads (non-blocking), fd[1] is the runtime's. */
static xrsc_result error_pipe_open(int fd[2], xrsc_diag *diag)
{
    char buf[32];
    if (pipe2(fd, O_CLOEXEC | O_NONBLOCK) != 0) {
        fd[0] = fd[1] = -1;
        return u_diag_set(diag, XRSC_ERROR_IO, "", 0, "XRSC_RT_ERROR_FD", "pipe: %s",
                          strerror(errno));
    }
    snprintf(buf, sizeof(buf), "%d", fd[1]);
    return set_env("XRSC_RT_ERROR_FD", buf, diag);
}

/* The runtime's error, when it sent one, replaces diag's (res: the run's result so far). */
static xrsc_result error_pipe_read(const int fd[2], xrsc_result res, xrsc_diag *diag)
{
    char line[1400];
    ssize_t n = fd[0] >= 0 ? read(fd[0], line, sizeof(line) - 1) : -1;
    if (n <= 0)
        return res;
    line[n] = '\0';
    line[strcspn(line, "\n")] = '\0';
    char *field[4] = {line, NULL, NULL, NULL};
    for (int i = 1; i < 4; i++) {
        char *tab = field[i - 1] ? strchr(field[i - 1], '\t') : NULL;
        if (tab)
            *tab = '\0';
        field[i] = tab ? tab + 1 : NULL;
    }
    int code = atoi(field[0]);
    return u_diag_set(diag, code < 0 ? (xrsc_result)code : XRSC_ERROR_IO, field[1] ? field[1] : "",
                      0, field[2] ? field[2] : "", "%s", field[3] ? field[3] : field[0]);
}

static void error_pipe_close(int fd[2])
{
    for (int i = 0; i < 2; i++)
        if (fd[i] >= 0)
            close(fd[i]);
    fd[0] = fd[1] = -1;
    unsetenv("XRSC_RT_ERROR_FD");
}

/* One rendered frame of the session: statistics, the overlay's line, the app's own outputs. */
static xrsc_result count_frame(const hs_replay_options *opt, const xrsc_xr_frame_info *fi,
                               xrsc_renderer *r, hs_outputs *outs, hs_views *views,
                               hs_preview_link *plink, hs_replay_stats *st, xrsc_diag *diag)
{
    xrsc_frame frame = {.display_time_ns = fi->scene_time_ns, .frame_index = fi->frame_index};
    frame.views[0] = fi->views[0];
    frame.views[1] = fi->views[1];
    if (opt->on_frame)
        opt->on_frame(opt->on_frame_user, &frame);
    xrsc_pass_timing passes[XRSC_MAX_PASSES];
    uint32_t np;
    hs_replay_stats_add(st, r, fi->render_ms, passes, &np);
    hs_preview_link_frame(plink, fi->frame_index, fi->render_ms, passes, np);
    /* Numbered as the runtime numbers the PNG/PFM files of this frame. */
    xrsc_result res = hs_views_frame(views, &frame, fi->frame_index, diag);
    return res != XRSC_OK ? res : hs_outputs_frame(outs, r, fi->frame_index, NULL, diag);
}

/* Steps the session until the runtime ends it after `frames` shown frames (or a Ctrl-C,
 * opt->stop, asks it to: the frame in flight is finished and written, the session ends
 * cleanly); w x h per eye. st->frames may end at frames + 1 (a frame past the end, not
 * counted). */
static xrsc_result run_session(const hs_replay_options *opt, xrsc_xr_session *session,
                               xrsc_renderer *r, hs_outputs *outs, hs_views *views,
                               hs_preview_link *plink, uint32_t frames, uint32_t w, uint32_t h,
                               hs_replay_stats *st, xrsc_diag *diag)
{
    xrsc_result res;
    double last_progress = now_s();
    bool exit_requested = false;
    for (;;) {
        xrsc_xr_frame_info fi;
        if ((res = xrsc_xr_session_step(session, &fi, diag)) != XRSC_OK)
            return res;
        if (fi.status == XRSC_XR_EXITED)
            return XRSC_OK;
        if (fi.status == XRSC_XR_RENDERED && st->frames >= frames) {
            st->frames = frames + 1; /* past the end: not counted, only ends the session */
        } else if (fi.status == XRSC_XR_RENDERED) {
            last_progress = now_s();
            if (st->frames == 0)
                hs_warn_first_frame(opt, r, w, h, &st->scene, fi.views, st);
            if ((res = count_frame(opt, &fi, r, outs, views, plink, st, diag)) != XRSC_OK)
                return res;
            st->frames++;
            if (opt->progress && st->frames % 30 == 0)
                fprintf(stderr, "frame %u/%u\n", st->frames, frames);
        } else if (fi.status == XRSC_XR_WAITING && now_s() - last_progress > STALL_LIMIT_S) {
            return u_diag_set(diag, XRSC_ERROR_XR, "", 0, "session",
                              "the runtime did not run the session for %.0f s (state %d)",
                              STALL_LIMIT_S, (int)fi.state);
        }
        /* The runtime stops after XRSC_RT_FRAMES (its next state change is STOPPING); a
         * runtime that keeps going past them, or a Ctrl-C, asks it to end. */
        if (opt->stop && *opt->stop && !st->stopped_by)
            st->stopped_by = *opt->stop;
        if (st->stopped_by && fi.status == XRSC_XR_WAITING)
            return XRSC_OK; /* not running: nothing in flight to finish */
        if ((st->frames > frames || st->stopped_by) && !exit_requested) {
            if ((res = xrsc_xr_session_request_exit(session, diag)) != XRSC_OK)
                return res;
            exit_requested = true;
        }
    }
}

xrsc_result hs_xr_replay_run(const hs_replay_options *opt, hs_replay_stats *out_stats,
                             xrsc_diag *diag)
{
    double t_start = now_s();
    hs_replay_stats local_stats;
    hs_replay_stats *st = out_stats ? out_stats : &local_stats;
    memset(st, 0, sizeof(*st));
    if (!opt || !opt->scene_path || !opt->poses_path)
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "",
                          "replay needs a scene and a pose stream");
    if (opt->out_dir && opt->out_dir[0] == '\0')
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "--out",
                          "output folder name is empty (NULL writes nothing)");
    xrsc_result res;
    hs_pose_stream *stream = NULL;
    xrsc_xr *xr = NULL;
    xrsc_scene *scene = NULL;
    xrsc_renderer *r = NULL;
    xrsc_xr_session *session = NULL;
    hs_outputs *outs = NULL; /* --write exr, --video: written here from the renderer */
    hs_views *views = NULL;  /* views.csv and the EXRs' depth (hs_views.h) */
    char imported[1100] = ""; /* --pose-columns: the canonical copy given to the runtime */
    hs_preview_link *plink = NULL; /* --preview: the overlay's information (hs_preview_link.h) */
    int rt_error[2] = {-1, -1};    /* the runtime's own error (error_pipe_open) */

    hs_replay_options conv;
    if ((res = load_stream(&opt, &conv, imported, sizeof(imported), &stream, diag)) != XRSC_OK)
        goto done;
    uint32_t w = opt->renderer.width ? opt->renderer.width : DEFAULT_EYE_SIZE_PX;
    uint32_t h = opt->renderer.height ? opt->renderer.height : DEFAULT_EYE_SIZE_PX;
    double refresh = opt->headset.refresh_hz > 0 ? opt->headset.refresh_hz : DEFAULT_REFRESH_HZ;
    double period_ns = NS_PER_S / refresh;
    int64_t span_ns = hs_pose_stream_duration_ns(stream) - (int64_t)(opt->start_s * NS_PER_S);
    /* A session's first frame is not shown (SYNCHRONIZED, shouldRender false): frame k >= 1
     * is rendered at stream time k / refresh, as the direct path's frame k. --frames N renders
     * frames 1..N (a session of N + 1); the whole stream renders frames 1..K-1 of the direct
     * path's 0..K-1 (the first sample's moment is the unshown frame). */
    uint32_t frames = opt->frames;
    uint32_t session_frames = frames + 1;
    if (frames == 0) {
        session_frames = span_ns > 0 ? (uint32_t)(span_ns / period_ns) + 1 : 2;
        frames = session_frames - 1;
    }
    hs_warn_frames_past_end(opt, hs_pose_stream_duration_ns(stream), period_ns, 1, frames);

    hs_replay_options scene_fov_opt;
    if (opt->fov_scene && (res = use_scene_fov(&opt, &scene_fov_opt, w, h, diag)) != XRSC_OK)
        goto done;
    if ((res = choose_runtime(diag)) != XRSC_OK)
        goto done;
    if ((res = configure_runtime(opt, stream, w, h, refresh, session_frames, diag)) != XRSC_OK)
        goto done;
    if ((res = hs_preview_link_open(opt, &plink, diag)) != XRSC_OK ||
        (res = error_pipe_open(rt_error, diag)) != XRSC_OK)
        goto done;
    if (opt->out_dir && (res = hs_make_dirs(opt->out_dir, "--out", diag)) != XRSC_OK)
        goto done;
    if ((res = hs_outputs_open(opt, w, h, refresh, &outs, diag)) != XRSC_OK)
        goto done;

    xrsc_xr_options xo = {.application_name = "xrsc replay", .context = opt->context};
    if ((res = xrsc_xr_create(&xo, &xr, diag)) != XRSC_OK)
        goto done;
    xrsc_context *ctx = xrsc_xr_context(xr);
    snprintf(st->device, sizeof(st->device), "%s", xrsc_context_device_name(ctx));
    if ((res = xrsc_scene_load(ctx, opt->scene_path, &opt->scene, &scene, diag)) != XRSC_OK)
        goto done;
    hs_replay_stats_scene(st, scene);
    xrsc_scene_info info;
    xrsc_scene_get_info(scene, &info);
    {
        /* the runtime already has the headset's IPD (XRSC_RT_IPD_MM): --frame keeps it */
        xrsc_headset hs = opt->headset;
        static const xrsc_headset zero_hs;
        if (memcmp(&hs, &zero_hs, sizeof(hs)) == 0)
            xrsc_headset_default(&hs);
        hs_warn_narrow_scene(&info, hs.ipd_m, hs.ipd_m);
        if ((res = hs_replay_viewpoint(opt, scene, &info, hs.fov, hs.ipd_m, &info.viewpoint,
                                       diag)) != XRSC_OK)
            goto done;
    }
    xrsc_renderer_options ropt = opt->renderer;
    ropt.width = w;
    ropt.height = h;
    if ((res = xrsc_renderer_create(ctx, scene, &ropt, &r, diag)) != XRSC_OK ||
        (res = hs_views_open(opt, ctx, scene, w, h, &views, diag)) != XRSC_OK)
        goto done;
    hs_outputs_set_depth(outs, hs_views_depth(views));
    /* Anchoring: the head at frame 0's display time minus the start is the stream's first
     * sample (the runtime's stream time start + (t - frame 0's)), the pose the direct path
     * anchors. */
    xrsc_xr_session_options so = {.anchor = !opt->no_anchor,
                                  .anchor_offset_ns = -(int64_t)(opt->start_s * NS_PER_S),
                                  .viewpoint = info.viewpoint};
    if ((res = xrsc_xr_session_create(xr, r, &so, &session, diag)) != XRSC_OK)
        goto done;
    st->load_s = now_s() - t_start;

    res = run_session(opt, session, r, outs, views, plink, frames, w, h, st, diag);
    if ((res = error_pipe_read(rt_error, res, diag)) != XRSC_OK)
        goto done;
    if (st->frames > frames)
        st->frames = frames;
    hs_replay_stats_average(st);
    res = XRSC_OK;

done:
    {
        xrsc_result out_res = hs_outputs_close(&outs, res == XRSC_OK, res == XRSC_OK ? diag : NULL);
        if (res == XRSC_OK)
            res = out_res;
        out_res = hs_views_close(&views, true, res == XRSC_OK ? diag : NULL); /* rows whole */
        if (res == XRSC_OK)
            res = out_res;
    }
    if (res != XRSC_OK || st->stopped_by) /* no waiting for the window after Ctrl-C or errors */
        hs_preview_link_autoclose(plink);
    xrsc_xr_session_destroy(&session);
    xrsc_renderer_destroy(&r);
    xrsc_scene_destroy(&scene);
    st->validation_errors = xrsc_context_validation_errors(xrsc_xr_context(xr));
    if (st->validation_errors > 0)
        U_LOG_W("the Vulkan validation layer reported %u errors", st->validation_errors);
    uint32_t xr_errors = 0;
    xrsc_xr_debug_messages(xr, &xr_errors, NULL, NULL);
    if (xr_errors > 0)
        U_LOG_W("OpenXR reported %u error messages", xr_errors);
    xrsc_xr_destroy(&xr);
    error_pipe_close(rt_error);
    hs_preview_link_close(&plink);
    hs_pose_stream_destroy(&stream);
    if (imported[0])
        unlink(imported);
    st->total_s = now_s() - t_start;
    return res;
}
