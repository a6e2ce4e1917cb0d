// SPDX-License-Identifier: MIT
/**
 * @file test_xr_replay.c
 * @brief Replay paths against each other: a librnr trace's recorded per-eye poses and
 *        asymmetric FOVs reach the renderer unchanged through the direct replay and through
 *        the runtime's xrLocateViews; the samplecache method through OpenXR (its colour image
 *        copied into the swapchains on the GPU) equals the same frames rendered directly, pixel
 *        for pixel.
 */
#include "hs_image.h"
#include "hs_pose_stream.h"
#include "hs_replay.h"
#include "t_frames.h"
#include "t_xr_frames.h"
#include "testing.h"
#include "xrsc_core_internal.h" /* xrsc_renderer_output_image */
#include "xrsc/xrsc_xr.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#define SCENE XRSC_SOURCE_DIR "/scenes/cornell.gltf"
#define EYE_PX 24u
/** A whole number of nanoseconds per frame, so frame k is at exactly k * 10 ms on both paths
 *  and lands on the trace's samples. */
#define REFRESH_HZ 100.0f
#define PERIOD_NS 10000000
#define FRAMES 4u
#define MAX_STEPS 400

static void runtime_env(const char *poses)
{
    setenv("XR_RUNTIME_JSON", XRSC_RUNTIME_JSON, 1);
    setenv("XRSC_RT_POSES", poses, 1);
    setenv("XRSC_RT_PACE", "fast", 1);
    setenv("XRSC_RT_OUT", "", 1);
    setenv("XRSC_RT_REFRESH_HZ", "100", 1);
    unsetenv("XRSC_RT_FRAMES");
    unsetenv("XRSC_RT_LOSE_AFTER");
    unsetenv("XRSC_RT_START_S");
    unsetenv("XRSC_RT_IPD_MM");
    char size[32];
    snprintf(size, sizeof(size), "%ux%u", EYE_PX, EYE_PX);
    setenv("XRSC_RT_EYE_SIZE", size, 1);
}

/*
 * A librnr trace (poses/README.md, "Importer: librnr"): view pairs every 10 ms, the eyes
 * 70 mm apart with a slight toe-in, each eye's FOV asymmetric and different from the other's
 * and from the simulated headset's, changing per sample. At t = 0 the head (the eyes' midpoint,
 * orientation halfway) is at the origin facing -Z, so the runtime's LOCAL space is the trace's
 * own frame and the unanchored paths see the same coordinates.
 */
static const char *write_trace(void)
{
    char text[4096];
    size_t len = 0;
    for (int k = 0; k <= 6; k++) {
        double z = -0.01 * k, yaw = 0.015; /* toe-in half angle (rad), as quaternion y */
        double s = 0.5 * yaw, c = 1.0 - 0.5 * s * s;
        /* up right down left (librnr's order), eye 0 then eye 1 */
        len += (size_t)snprintf(text + len, sizeof(text) - len,
                                "%d v XR_REFERENCE_SPACE_TYPE_LOCAL 0 %.9f 0 %.9f -0.035 0 %.3f "
                                "%.3f %.3f %.3f %.3f 2 0\n",
                                k * PERIOD_NS, -s, c, z, 0.61 + 0.01 * k, 0.52, -0.83, -0.97 + 0.01 * k);
        len += (size_t)snprintf(text + len, sizeof(text) - len,
                                "%d v XR_REFERENCE_SPACE_TYPE_LOCAL 0 %.9f 0 %.9f 0.035 0 %.3f "
                                "%.3f %.3f %.3f %.3f 2 1\n",
                                k * PERIOD_NS, s, c, z, 0.66, 0.91 - 0.01 * k, -0.74, -0.55);
    }
    return t_temp_file("views.librnr", text);
}

static bool fov_equal(XrFovf a, XrFovf b)
{
    return a.angleLeft == b.angleLeft && a.angleRight == b.angleRight &&
           a.angleUp == b.angleUp && a.angleDown == b.angleDown;
}

static void check_pose_near(XrPosef a, XrPosef b, double tol, const char *what, uint32_t k)
{
    CHECK_MSG(t_pose_near(a, b, tol),
              "%s frame %u: pose (%g %g %g | %g %g %g %g) vs (%g %g %g | %g %g %g %g)", what, k,
              a.position.x, a.position.y, a.position.z, a.orientation.x, a.orientation.y,
              a.orientation.z, a.orientation.w, b.position.x, b.position.y, b.position.z,
              b.orientation.x, b.orientation.y, b.orientation.z, b.orientation.w);
}

/* ---- recorded views: direct replay and the runtime's xrLocateViews ---- */

static void test_recorded_views(void)
{
    const char *trace = write_trace();
    hs_pose_stream *stream = NULL;
    xrsc_diag d = {0};
    CHECK(hs_pose_stream_load(trace, HS_POSE_FORMAT_AUTO, &stream, &d) == XRSC_OK);
    if (!stream)
        return;
    CHECK(stream->views != NULL);
    CHECK_EQ_INT(stream->count, 7);
    xrsc_headset def;
    xrsc_headset_default(&def);

    /* Direct: frame k at 10 k ms = sample k: exactly the recorded views, not the headset's. */
    t_captured direct = {0};
    hs_replay_options opt = {
        .scene_path = SCENE,
        .poses_path = trace,
        .no_anchor = true,
        .frames = FRAMES + 1,
        .renderer = {.method = XRSC_METHOD_PRIMARY, .width = EYE_PX, .height = EYE_PX},
        .on_frame = t_capture_frame,
        .on_frame_user = &direct,
    };
    xrsc_headset_default(&opt.headset);
    opt.headset.refresh_hz = REFRESH_HZ;
    opt.context.validation = true;
    hs_replay_stats st;
    xrsc_result r = hs_replay_run(&opt, &st, &d);
    CHECK_MSG(r == XRSC_OK, "%s: %s", xrsc_result_name(r), d.message);
    CHECK_EQ_INT(st.validation_errors, 0);
    CHECK_EQ_INT(direct.count, FRAMES + 1);
    for (uint32_t k = 0; k < direct.count; k++) {
        for (int e = 0; e < 2; e++) {
            const xrsc_view *v = &direct.frames[k].views[e];
            CHECK_MSG(fov_equal(v->fov, stream->views[k].fov[e]), "direct frame %u eye %d FOV", k,
                      e);
            CHECK(!fov_equal(v->fov, def.fov[e]));
            CHECK(memcmp(&v->pose, &stream->views[k].pose[e], sizeof(XrPosef)) == 0);
        }
        /* the file's numbers: left eye's left angle and right eye's right angle */
        CHECK_NEAR(direct.frames[k].views[0].fov.angleLeft, -0.97 + 0.01 * k, 1e-6);
        CHECK_NEAR(direct.frames[k].views[0].fov.angleUp, 0.61 + 0.01 * k, 1e-6);
        CHECK_NEAR(direct.frames[k].views[1].fov.angleRight, 0.91 - 0.01 * k, 1e-6);
        CHECK_NEAR(direct.frames[k].views[1].fov.angleLeft, -0.55, 1e-6);
        CHECK_NEAR(direct.frames[k].views[1].pose.position.x -
                       direct.frames[k].views[0].pose.position.x,
                   0.070, 1e-6); /* the recording's 70 mm, not the headset's 63 */
    }

    /* OpenXR: the runtime locates the recorded views; the plugin renders them unanchored. */
    runtime_env(trace);
    xrsc_xr *xr = NULL;
    xrsc_scene *scene = NULL;
    xrsc_renderer *ren = NULL;
    xrsc_xr_session *s = NULL;
    xrsc_xr_options xo = {.application_name = "test_xr_replay", .context = {.validation = true}};
    r = xrsc_xr_create(&xo, &xr, &d);
    CHECK_MSG(r == XRSC_OK, "%s: %s", xrsc_result_name(r), d.message);
    if (r == XRSC_OK)
        r = xrsc_scene_load(xrsc_xr_context(xr), SCENE, NULL, &scene, &d);
    xrsc_renderer_options ro = {.method = XRSC_METHOD_PRIMARY, .width = EYE_PX, .height = EYE_PX};
    if (r == XRSC_OK)
        r = xrsc_renderer_create(xrsc_xr_context(xr), scene, &ro, &ren, &d);
    xrsc_xr_session_options so = {.anchor = false};
    if (r == XRSC_OK)
        r = xrsc_xr_session_create(xr, ren, &so, &s, &d);
    CHECK_MSG(r == XRSC_OK, "%s: %s", xrsc_result_name(r), d.message);
    uint32_t rendered = 0;
    for (int i = 0; r == XRSC_OK && i < MAX_STEPS && rendered < FRAMES; i++) {
        xrsc_xr_frame_info fi;
        r = xrsc_xr_session_step(s, &fi, &d);
        if (r != XRSC_OK || fi.status != XRSC_XR_RENDERED)
            continue;
        uint32_t k = fi.frame_index;
        CHECK_EQ_INT(fi.scene_time_ns, (int64_t)k * PERIOD_NS);
        if (k >= direct.count)
            break;
        rendered++;
        for (int e = 0; e < 2; e++) {
            CHECK_MSG(fov_equal(fi.views[e].fov, direct.frames[k].views[e].fov),
                      "OpenXR frame %u eye %d: FOV (%g %g %g %g) is not the recorded one", k, e,
                      fi.views[e].fov.angleLeft, fi.views[e].fov.angleRight,
                      fi.views[e].fov.angleUp, fi.views[e].fov.angleDown);
            check_pose_near(fi.views[e].pose, direct.frames[k].views[e].pose, 1e-5, "OpenXR", k);
        }
    }
    CHECK_MSG(r == XRSC_OK, "%s: %s", xrsc_result_name(r), d.message);
    CHECK_EQ_INT(rendered, FRAMES);
    xrsc_xr_session_destroy(&s);
    xrsc_renderer_destroy(&ren);
    xrsc_scene_destroy(&scene);
    CHECK_EQ_INT(xrsc_context_validation_errors(xrsc_xr_context(xr)), 0);
    xrsc_xr_destroy(&xr);
    hs_pose_stream_destroy(&stream);
}

/* ---- samplecache through OpenXR = the same frames rendered directly ---- */

static void test_samplecache_identity(void)
{
    static const char *const dir_xr = XRSC_TEST_OUT "/replay_sc_xr";
    static const char *const dir_direct = XRSC_TEST_OUT "/replay_sc_direct";
    mkdir(dir_xr, 0777);
    mkdir(dir_direct, 0777);
    runtime_env(XRSC_SOURCE_DIR "/poses/orbit_cornell.xrpose");
    setenv("XRSC_RT_OUT", dir_xr, 1);
    setenv("XRSC_RT_WRITE", "linear", 1);

    xrsc_xr *xr = NULL;
    xrsc_scene *scene = NULL;
    xrsc_renderer *ren = NULL, *ref = NULL;
    xrsc_xr_session *s = NULL;
    xrsc_diag d = {0};
    xrsc_xr_options xo = {.application_name = "test_xr_replay", .context = {.validation = true}};
    xrsc_result r = xrsc_xr_create(&xo, &xr, &d);
    CHECK_MSG(r == XRSC_OK, "%s: %s", xrsc_result_name(r), d.message);
    if (r == XRSC_OK)
        r = xrsc_scene_load(xrsc_xr_context(xr), SCENE, NULL, &scene, &d);
    xrsc_renderer_options ro = {.method = XRSC_METHOD_SAMPLECACHE, .width = EYE_PX,
                                .height = EYE_PX, .seed = 3};
    /* Two renderers with the same options: one feeds the swapchains, the other renders the
     * frames the first rendered, read back as the direct path reads them. */
    if (r == XRSC_OK)
        r = xrsc_renderer_create(xrsc_xr_context(xr), scene, &ro, &ren, &d);
    if (r == XRSC_OK)
        r = xrsc_renderer_create(xrsc_xr_context(xr), scene, &ro, &ref, &d);
    /* The method offers its colour image: the OpenXR path copies it on the GPU. */
    CHECK(ren && xrsc_renderer_output_image(ren, XRSC_OUTPUT_COLOR) != NULL);
    xrsc_scene_info info = {0};
    if (scene)
        xrsc_scene_get_info(scene, &info);
    xrsc_xr_session_options so = {.anchor = true, .viewpoint = info.viewpoint};
    if (r == XRSC_OK)
        r = xrsc_xr_session_create(xr, ren, &so, &s, &d);
    CHECK_MSG(r == XRSC_OK, "%s: %s", xrsc_result_name(r), d.message);

    size_t px = (size_t)EYE_PX * EYE_PX;
    float *rgba = malloc(px * 4 * sizeof(float));
    uint32_t rendered = 0, first = 0;
    for (int i = 0; r == XRSC_OK && rgba && i < MAX_STEPS && rendered < FRAMES; i++) {
        xrsc_xr_frame_info fi;
        r = xrsc_xr_session_step(s, &fi, &d);
        if (r != XRSC_OK || fi.status != XRSC_XR_RENDERED)
            continue;
        if (!rendered)
            first = fi.frame_index;
        rendered++;
        xrsc_frame frame = {.display_time_ns = fi.scene_time_ns, .frame_index = fi.frame_index};
        frame.views[0] = fi.views[0];
        frame.views[1] = fi.views[1];
        r = xrsc_renderer_render(ref, &frame);
        CHECK_MSG(r == XRSC_OK, "reference frame %u: %s", fi.frame_index, xrsc_result_name(r));
        for (uint32_t e = 0; r == XRSC_OK && e < 2; e++) {
            char path[512];
            snprintf(path, sizeof(path), "%s/frame_%05u_%s.pfm", dir_direct, fi.frame_index,
                     e ? "right" : "left");
            r = xrsc_renderer_read(ref, e, XRSC_OUTPUT_COLOR, rgba, px * 4 * sizeof(float));
            if (r == XRSC_OK)
                r = hs_write_pfm(path, rgba, EYE_PX, EYE_PX, &d);
        }
    }
    free(rgba);
    CHECK_MSG(r == XRSC_OK, "%s: %s", xrsc_result_name(r), d.message);
    CHECK_EQ_INT(rendered, FRAMES);
    xrsc_xr_session_destroy(&s); /* the runtime has written every submitted frame */
    xrsc_renderer_destroy(&ref);
    xrsc_renderer_destroy(&ren);
    xrsc_scene_destroy(&scene);
    CHECK_EQ_INT(xrsc_context_validation_errors(xrsc_xr_context(xr)), 0);
    xrsc_xr_destroy(&xr);

    t_check_same_frames("samplecache", dir_xr, dir_direct, first, rendered, px * 12);
    unsetenv("XRSC_RT_WRITE");
}

int main(void)
{
    mkdir(XRSC_TEST_OUT, 0777);
    RUN(test_recorded_views);
    RUN(test_samplecache_identity);
    return t_finish();
}
