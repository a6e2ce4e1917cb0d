// SPDX-License-Identifier: MIT
/**
 * @file test_xr_app.c
 * @brief The plugin as an OpenXR application on host_sim's runtime: frames through OpenXR
 *        equal the direct path's bit for bit; zero messages from
 *        XR_APILAYER_LUNARG_core_validation and zero Vulkan validation errors; a bad pose
 *        stream, a missing manifest and a lost session end with clear errors and clean
 *        shutdowns; sessions end and start again on one instance.
 */
#include "hs_replay.h"
#include "hs_xr_replay.h"
#include "t_frames.h"
#include "t_xr_frames.h"
#include "testing.h"
#include "xrsc/xrsc_xr.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#define SCENE XRSC_SOURCE_DIR "/scenes/cornell.gltf"
#define POSES XRSC_SOURCE_DIR "/poses/orbit_cornell.xrpose"
#define EYE_PX 48u
/** Steps without a state change after which a test gives up (each step waits <= 1 frame). */
#define MAX_STEPS 400

static void runtime_env(void)
{
    setenv("XR_RUNTIME_JSON", XRSC_RUNTIME_JSON, 1);
    setenv("XRSC_RT_POSES", POSES, 1);
    setenv("XRSC_RT_PACE", "fast", 1);
    setenv("XRSC_RT_OUT", "", 1);
    unsetenv("XRSC_RT_FRAMES");
    unsetenv("XRSC_RT_LOSE_AFTER");
    char size[32];
    snprintf(size, sizeof(size), "%ux%u", EYE_PX, EYE_PX);
    setenv("XRSC_RT_EYE_SIZE", size, 1);
}

/* ---- the same poses and seed through OpenXR and directly: equal PFM files ---- */

static void test_pixel_identical(void)
{
    runtime_env();
    static const char *const dir_xr = XRSC_TEST_OUT "/app_identical_xr";
    static const char *const dir_direct = XRSC_TEST_OUT "/app_identical_direct";
    hs_replay_options opt = {
        .scene_path = SCENE,
        .poses_path = POSES,
        .write_linear = true,
        /* The stream starts at the origin facing -Z, so LOCAL (its first pose, yaw only) is
         * the stream's own frame: without anchoring both paths see the same eye poses. */
        .no_anchor = true,
        .renderer = {.method = XRSC_METHOD_SPP, .width = EYE_PX, .height = EYE_PX, .seed = 7,
                     .spp = {.samples_per_pixel = 2}},
    };
    xrsc_headset_default(&opt.headset);
    opt.headset.refresh_hz = 100.0f; /* a whole number of ns per frame on both clocks */
    opt.context.validation = true;

    const uint32_t frames = 3;
    hs_replay_stats st;
    xrsc_diag d = {0};
    opt.out_dir = dir_xr;
    opt.frames = frames; /* OpenXR: frames 1..3 (frame 0 is the unshown SYNCHRONIZED one) */
    xrsc_result r = hs_xr_replay_run(&opt, &st, &d);
    CHECK_MSG(r == XRSC_OK, "%s: %s", xrsc_result_name(r), d.message);
    CHECK_EQ_INT(st.frames, frames);
    CHECK_EQ_INT(st.validation_errors, 0);
    opt.out_dir = dir_direct;
    opt.frames = frames + 1; /* direct: frames 0..3 */
    r = hs_replay_run(&opt, &st, &d);
    CHECK_MSG(r == XRSC_OK, "%s: %s", xrsc_result_name(r), d.message);

    t_check_same_frames("identical", dir_xr, dir_direct, 1, frames,
                        (size_t)EYE_PX * EYE_PX * 12 /* RGB float32 PFM */);
}

/* ---- anchoring on (the default): the same eye poses and pixels on both paths ---- */

/*
 * A head that starts away from the origin, pitched and rolled (so the runtime's LOCAL, the
 * first pose turned about +Y only, is not the head) and keeps moving and turning: anchoring
 * has real work to do, and anchoring the wrong moment (a later frame's head, or the head at
 * --start) moves every view by far more than float rounding.
 */
static const char *write_tilted_stream(void)
{
    char text[8192];
    size_t len = (size_t)snprintf(text, sizeof(text),
                                  "xrsc-poses 1\ncolumns t_ns px py pz qx qy qz qw\n");
    const double ax = 0.3, ay = 0.9, az = 0.2, an = sqrt(ax * ax + ay * ay + az * az);
    for (int k = 0; k <= 60; k++) {
        double t = k * 0.01, half = 0.5 * (0.4 + 2.0 * t), sh = sin(half) / an;
        len += (size_t)snprintf(text + len, sizeof(text) - len,
                                "%d %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n", k * 10000000,
                                0.3 + 0.5 * t, 1.6 + 0.1 * t, -0.2 - 0.3 * t, ax * sh, ay * sh,
                                az * sh, cos(half));
    }
    return t_temp_file("tilted.xrpose", text);
}

/** Replays `frames` frames of `poses` through OpenXR (frames 1..frames) and directly (frames
 *  0..frames) with anchoring on; the same frames must have the same eye poses (1e-5), FOVs
 *  and scene times, and with `same_pixels` the same linear pixels. */
static void anchored_pair(const char *tag, const char *poses, xrsc_method method, double start_s,
                          bool same_pixels)
{
    runtime_env();
    char dir_xr[512], dir_direct[512];
    snprintf(dir_xr, sizeof(dir_xr), "%s/anchor_%s_xr", XRSC_TEST_OUT, tag);
    snprintf(dir_direct, sizeof(dir_direct), "%s/anchor_%s_direct", XRSC_TEST_OUT, tag);
    t_captured xr = {0}, direct = {0};
    hs_replay_options opt = {
        .scene_path = SCENE,
        .poses_path = poses,
        .write_linear = true,
        .start_s = start_s, /* no_anchor false: anchoring on, as `xrsc replay` by default */
        .renderer = {.method = method, .width = EYE_PX, .height = EYE_PX, .seed = 7,
                     .spp = {.samples_per_pixel = 2}},
        .on_frame = t_capture_frame,
    };
    xrsc_headset_default(&opt.headset);
    opt.headset.refresh_hz = 100.0f;
    opt.context.validation = true;
    const uint32_t frames = 4;
    hs_replay_stats st;
    xrsc_diag d = {0};
    opt.out_dir = dir_xr;
    opt.frames = frames;
    opt.on_frame_user = &xr;
    xrsc_result r = hs_xr_replay_run(&opt, &st, &d);
    CHECK_MSG(r == XRSC_OK, "%s OpenXR: %s: %s", tag, xrsc_result_name(r), d.message);
    CHECK_EQ_INT(st.validation_errors, 0);
    opt.out_dir = dir_direct;
    opt.frames = frames + 1;
    opt.on_frame_user = &direct;
    r = hs_replay_run(&opt, &st, &d);
    CHECK_MSG(r == XRSC_OK, "%s direct: %s: %s", tag, xrsc_result_name(r), d.message);
    CHECK_EQ_INT(xr.count, frames);
    CHECK_EQ_INT(direct.count, frames + 1);

    double worst = 0.0;
    for (uint32_t i = 0; i < xr.count; i++) {
        const xrsc_frame *a = &xr.frames[i];
        uint32_t k = a->frame_index;
        CHECK_MSG(k == i + 1, "%s: OpenXR frame %u is frame_index %u", tag, i, k);
        if (k >= direct.count)
            continue;
        const xrsc_frame *b = &direct.frames[k];
        CHECK_EQ_INT(b->frame_index, k);
        CHECK_EQ_INT(a->display_time_ns, b->display_time_ns);
        for (int e = 0; e < 2; e++) {
            CHECK(memcmp(&a->views[e].fov, &b->views[e].fov, sizeof(XrFovf)) == 0);
            XrPosef pa = a->views[e].pose, pb = b->views[e].pose;
            CHECK_MSG(t_pose_near(pa, pb, 1e-5),
                      "%s frame %u eye %d: OpenXR (%.7f %.7f %.7f | %.7f %.7f %.7f %.7f) vs "
                      "direct (%.7f %.7f %.7f | %.7f %.7f %.7f %.7f)",
                      tag, k, e, pa.position.x, pa.position.y, pa.position.z, pa.orientation.x,
                      pa.orientation.y, pa.orientation.z, pa.orientation.w, pb.position.x,
                      pb.position.y, pb.position.z, pb.orientation.x, pb.orientation.y,
                      pb.orientation.z, pb.orientation.w);
            const float *fa = &pa.position.x, *fb = &pb.position.x;
            for (int c = 0; c < 3; c++)
                worst = fmax(worst, fabs(fa[c] - fb[c]));
            fa = &pa.orientation.x;
            fb = &pb.orientation.x;
            for (int c = 0; c < 4; c++)
                worst = fmax(worst, fabs(fa[c] - fb[c]));
        }
    }
    fprintf(stderr, "  %s: largest eye-pose difference OpenXR vs direct %.3g\n", tag, worst);
    if (!same_pixels)
        return;
    t_check_same_frames(tag, dir_xr, dir_direct, 1, frames, (size_t)EYE_PX * EYE_PX * 12);
}

static void test_anchored_same_views(void)
{
    const char *tilted = write_tilted_stream();
    /* primary is deterministic: the same poses give the same pixels */
    anchored_pair("primary", tilted, XRSC_METHOD_PRIMARY, 0.0, true);
    /* --start: both paths anchor the stream's first sample, not the head at the start */
    anchored_pair("primary_start", tilted, XRSC_METHOD_PRIMARY, 0.25, true);
    anchored_pair("spp", POSES, XRSC_METHOD_SPP, 0.0, false);
    anchored_pair("spp_start", tilted, XRSC_METHOD_SPP, 0.1, false);
}

/* ---- sessions on one instance; validation layers ---- */

typedef struct app {
    xrsc_xr *xr;
    xrsc_scene *scene;
    xrsc_renderer *renderer;
} app;

static bool app_create(app *a, xrsc_diag *d)
{
    memset(a, 0, sizeof(*a));
    xrsc_xr_options xo = {.application_name = "test_xr_app", .context = {.validation = true}};
    xrsc_result r = xrsc_xr_create(&xo, &a->xr, d);
    CHECK_MSG(r == XRSC_OK, "%s: %s", xrsc_result_name(r), d->message);
    if (r != XRSC_OK)
        return false;
    r = xrsc_scene_load(xrsc_xr_context(a->xr), SCENE, NULL, &a->scene, d);
    CHECK(r == XRSC_OK);
    xrsc_renderer_options ro = {.method = XRSC_METHOD_PRIMARY, .width = EYE_PX, .height = EYE_PX};
    if (r == XRSC_OK)
        r = xrsc_renderer_create(xrsc_xr_context(a->xr), a->scene, &ro, &a->renderer, d);
    CHECK(r == XRSC_OK);
    return r == XRSC_OK;
}

/** Destroys everything; returns the Vulkan validation errors seen. */
static uint32_t app_destroy(app *a)
{
    xrsc_renderer_destroy(&a->renderer);
    xrsc_scene_destroy(&a->scene);
    uint32_t errors = xrsc_context_validation_errors(xrsc_xr_context(a->xr));
    xrsc_xr_destroy(&a->xr);
    CHECK(a->xr == NULL);
    return errors;
}

/** Steps until EXITED/LOST or an error; counts rendered frames; asks for exit after
 *  exit_after rendered frames (0: never). */
static xrsc_result run_session(xrsc_xr_session *s, uint32_t exit_after, uint32_t *out_rendered,
                               xrsc_xr_status *out_last, xrsc_diag *d)
{
    uint32_t rendered = 0;
    xrsc_result r = XRSC_OK;
    xrsc_xr_frame_info fi = {0};
    for (int i = 0; i < MAX_STEPS; i++) {
        r = xrsc_xr_session_step(s, &fi, d);
        if (r != XRSC_OK || fi.status == XRSC_XR_EXITED)
            break;
        if (fi.status == XRSC_XR_RENDERED) {
            rendered++;
            CHECK_EQ_INT(fi.scene_time_ns, (int64_t)fi.frame_index * 11111111);
        }
        if (exit_after && rendered == exit_after) {
            CHECK(xrsc_xr_session_request_exit(s, d) == XRSC_OK);
            exit_after = 0;
        }
    }
    *out_rendered = rendered;
    *out_last = fi.status;
    return r;
}

static void test_sessions_and_validation(void)
{
    runtime_env();
    setenv("XR_ENABLE_API_LAYERS", "XR_APILAYER_LUNARG_core_validation", 1);
    app a;
    xrsc_diag d = {0};
    if (!app_create(&a, &d)) {
        unsetenv("XR_ENABLE_API_LAYERS");
        return;
    }
    /* Two sessions, one after the other: each ends on request and a new one starts. */
    for (int round = 0; round < 2; round++) {
        xrsc_xr_session *s = NULL;
        xrsc_xr_session_options so = {.anchor = true};
        xrsc_scene_info info;
        xrsc_scene_get_info(a.scene, &info);
        so.viewpoint = info.viewpoint;
        xrsc_result r = xrsc_xr_session_create(a.xr, a.renderer, &so, &s, &d);
        CHECK_MSG(r == XRSC_OK, "round %d: %s: %s", round, xrsc_result_name(r), d.message);
        if (r != XRSC_OK)
            break;
        uint32_t rendered = 0;
        xrsc_xr_status last;
        r = run_session(s, 4, &rendered, &last, &d);
        CHECK_MSG(r == XRSC_OK, "round %d: %s", round, d.message);
        CHECK_EQ_INT(last, XRSC_XR_EXITED);
        CHECK_EQ_INT(rendered, 4);
        xrsc_xr_session_destroy(&s);
        CHECK(s == NULL);
    }
    uint32_t errors = 0, warnings = 0, validation = 0;
    uint32_t all = xrsc_xr_debug_messages(a.xr, &errors, &warnings, &validation);
    fprintf(stderr, "  OpenXR debug messages: %u (errors %u, warnings %u, validation %u)\n", all,
            errors, warnings, validation);
    CHECK_EQ_INT(errors, 0);
    CHECK_EQ_INT(warnings, 0);
    CHECK_EQ_INT(validation, 0);
    CHECK_EQ_INT(app_destroy(&a), 0);
    unsetenv("XR_ENABLE_API_LAYERS");
}

/* ---- failures end cleanly ---- */

static void test_lost_session(void)
{
    runtime_env();
    setenv("XRSC_RT_LOSE_AFTER", "3", 1);
    app a;
    xrsc_diag d = {0};
    if (!app_create(&a, &d))
        return;
    for (int round = 0; round < 2; round++) {
        xrsc_xr_session *s = NULL;
        xrsc_result r = xrsc_xr_session_create(a.xr, a.renderer, NULL, &s, &d);
        CHECK_MSG(r == XRSC_OK, "%s", d.message);
        if (r != XRSC_OK)
            break;
        uint32_t rendered = 0;
        xrsc_xr_status last;
        r = run_session(s, 0, &rendered, &last, &d);
        CHECK_EQ_INT(r, XRSC_ERROR_XR_SESSION_LOST);
        CHECK_EQ_INT(last, XRSC_XR_LOST);
        CHECK(rendered >= 1);
        CHECK(strstr(d.message, "lost") != NULL);
        xrsc_xr_session_destroy(&s); /* and a new session works after a lost one */
    }
    CHECK_EQ_INT(app_destroy(&a), 0);
    unsetenv("XRSC_RT_LOSE_AFTER");
}

static void test_missing_manifest(void)
{
    runtime_env();
    setenv("XR_RUNTIME_JSON", XRSC_TEST_OUT "/no_such_runtime.json", 1);
    xrsc_xr *xr = NULL;
    xrsc_diag d = {0};
    xrsc_result r = xrsc_xr_create(NULL, &xr, &d);
    CHECK_EQ_INT(r, XRSC_ERROR_XR_RUNTIME_UNAVAILABLE);
    CHECK(xr == NULL);
    CHECK(strstr(d.message, "XR_RUNTIME_JSON") != NULL);
    CHECK(strcmp(d.field, "XR_RUNTIME_JSON") == 0);

    hs_replay_options opt = {.scene_path = SCENE, .poses_path = POSES, .frames = 1};
    r = hs_xr_replay_run(&opt, NULL, &d);
    CHECK_EQ_INT(r, XRSC_ERROR_XR_RUNTIME_UNAVAILABLE);
    CHECK(strstr(d.message, "XR_RUNTIME_JSON") != NULL);
    runtime_env();
}

static void test_bad_pose_stream(void)
{
    runtime_env();
    const char *bad = t_temp_file("bad.xrpose",
                                  "xrsc-poses 1\ncolumns t_ns px py pz qx qy qz qw\n"
                                  "0 0 0 0 0 0 0 1\n10 0 0 0 0 0 nan 1\n");
    /* The replay reads the stream first: file, line and field, no runtime started. */
    hs_replay_options opt = {.scene_path = SCENE, .poses_path = bad, .frames = 1};
    xrsc_diag d = {0};
    xrsc_result r = hs_xr_replay_run(&opt, NULL, &d);
    CHECK_EQ_INT(r, XRSC_ERROR_NAN);
    CHECK_EQ_INT(d.line, 4);
    CHECK(strcmp(d.field, "qz") == 0);
    /* The runtime given the bad stream itself refuses the instance: a clean XR error. */
    setenv("XRSC_RT_POSES", bad, 1);
    xrsc_xr *xr = NULL;
    r = xrsc_xr_create(NULL, &xr, &d);
    CHECK(r == XRSC_ERROR_XR || r == XRSC_ERROR_XR_RUNTIME_UNAVAILABLE);
    CHECK(xr == NULL);
    runtime_env();
}

/* A device selector that matches nothing is XRSC_ERROR_DEVICE_NOT_FOUND naming it, as
 * without OpenXR: checked against the runtime-made instance's devices before the runtime is
 * asked for its device (given the same selector, host_sim's would only fail). */
static void test_device_not_found(void)
{
    runtime_env();
    for (int rt_too = 0; rt_too < 2; rt_too++) {
        if (rt_too)
            setenv("XRSC_RT_DEVICE", "nosuch-device", 1);
        else
            unsetenv("XRSC_RT_DEVICE");
        xrsc_xr_options xo = {.application_name = "test_xr_app",
                              .context = {.device = "nosuch-device"}};
        xrsc_xr *xr = NULL;
        xrsc_diag d = {0};
        xrsc_result r = xrsc_xr_create(&xo, &xr, &d);
        CHECK_MSG(r == XRSC_ERROR_DEVICE_NOT_FOUND, "runtime selector %s: %s: %s",
                  rt_too ? "too" : "unset", xrsc_result_name(r), d.message);
        CHECK(xr == NULL);
        CHECK(strstr(d.message, "\"nosuch-device\"") != NULL);
        CHECK(strcmp(d.field, "device") == 0);
    }
    unsetenv("XRSC_RT_DEVICE");
}

int main(void)
{
    mkdir(XRSC_TEST_OUT, 0777);
    RUN(test_missing_manifest);
    RUN(test_bad_pose_stream);
    RUN(test_device_not_found);
    RUN(test_lost_session);
    RUN(test_sessions_and_validation);
    RUN(test_pixel_identical);
    RUN(test_anchored_same_views);
    return t_finish();
}
