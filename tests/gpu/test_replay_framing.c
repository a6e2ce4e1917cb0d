// SPDX-License-Identifier: MIT
/**
 * @file test_replay_framing.c
 * @brief Issue 13 in the replay: --frame (hs_frame_viewpoint), --fov scene (hs_scene_fov and
 *        the FOV every rendered frame gets), --start past the stream's end (both paths' check),
 *        and --pose-columns through hs_replay_run.
 */
#include "hs_replay.h"
#include "testing.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define T_PI 3.14159265358979323846

static void test_frame_viewpoint(void)
{
    xrsc_scene_info info = {0};
    for (int a = 0; a < 3; a++) {
        info.bounds_min[a] = -1.0f;
        info.bounds_max[a] = 1.0f;
    }
    info.bounds_min[0] = 3.0f, info.bounds_max[0] = 5.0f; /* centre (4, 0, 0), radius sqrt 3 */
    /* asymmetric FOVs: the head is offset by h (t_a - t_b) / (t_a + t_b) per axis (tangents
     * averaged over the eyes, h = 1) and backs off until every front corner (z = 1) is inside
     * every side; the narrowest side (30 deg, right eye's left) decides */
    XrFovf fov[2] = {{-0.8f, 0.7f, 0.9f, -0.75f}, {(float)(-T_PI / 6.0), 0.8f, 0.9f, -0.9f}};
    XrPosef p = hs_frame_viewpoint(&info, fov);
    double tl = 0.5 * (tan(0.8) + tan(T_PI / 6.0)), tr = 0.5 * (tan(0.7) + tan(0.8));
    double tu = tan(0.9), td = 0.5 * (tan(0.75) + tan(0.9));
    double sx = (tl - tr) / (tl + tr), sy = (td - tu) / (tu + td);
    CHECK_NEAR(p.position.x, 4.0 + sx, 1e-6);
    CHECK_NEAR(p.position.y, sy, 1e-6);
    CHECK_NEAR(p.position.z, 1.0 + (1.0 + sx) / tan(T_PI / 6.0), 1e-5); /* centre z = 0 */
    CHECK_NEAR(p.orientation.w, 1.0, 0.0);
}

static void test_scene_fov(void)
{
    xrsc_scene_info info = {0};
    XrFovf f;
    CHECK(!hs_scene_fov(&info, 64, 32, &f)); /* no camera */
    info.has_camera = true;
    info.camera_yfov_rad = 0.5f;
    CHECK(hs_scene_fov(&info, 64, 32, &f)); /* no aspectRatio: width / height = 2 */
    CHECK_NEAR(f.angleUp, 0.25, 1e-6);
    CHECK_NEAR(f.angleDown, -0.25, 1e-6);
    CHECK_NEAR(tan(f.angleRight), 2.0 * tan(0.25), 1e-6);
    CHECK_NEAR(f.angleLeft, -f.angleRight, 0.0);
    info.camera_aspect_ratio = 1.0f;
    CHECK(hs_scene_fov(&info, 64, 32, &f));
    CHECK_NEAR(f.angleRight, 0.25, 1e-6);
}

static void test_start_past_end(void)
{
    xrsc_diag d;
    CHECK_EQ_INT(hs_check_start("p", 1.0, 1000000000, &d), XRSC_OK);
    CHECK_EQ_INT(hs_check_start("p", 1.5, 1000000000, &d), XRSC_ERROR_INVALID_ARGUMENT);
    CHECK(!strcmp(d.field, "--start"));
    CHECK(strstr(d.message, "lasts 1 s") != NULL);
    /* through hs_replay_run: refused before anything is rendered */
    hs_replay_options opt = {.scene_path = t_source_path("scenes/cornell.gltf"),
                             .poses_path = t_source_path("poses/orbit_cornell.xrpose"),
                             .start_s = 1000.0};
    opt.context.validation = true;
    CHECK_EQ_INT(hs_replay_run(&opt, NULL, &d), XRSC_ERROR_INVALID_ARGUMENT);
    CHECK(!strcmp(d.field, "--start"));
}

typedef struct seen_frames {
    uint32_t count;
    XrFovf fov[2];
    XrPosef pose;
} seen_frames;

static void on_frame(void *user, const xrsc_frame *frame)
{
    seen_frames *s = user;
    if (s->count++ == 0) {
        s->fov[0] = frame->views[0].fov;
        s->fov[1] = frame->views[1].fov;
        s->pose = frame->views[0].pose;
    }
}

static void test_replay_fov_scene_frame_columns(void)
{
    /* cornell.gltf's camera: yfov 1 rad; eye 32 x 16 (no aspectRatio in the file: 2) */
    const char *csv = t_temp_file("frame.csv", ",time,x,y,z,qw,qx,qy,qz\n0,0,0,0,0,1,0,0,0\n"
                                               "1,0.05,0,0,0,1,0,0,0\n");
    hs_pose_columns cols;
    xrsc_diag d;
    CHECK_EQ_INT(hs_pose_columns_parse("t,x,y,z,qw,qx,qy,qz", NULL, NULL, &cols, &d), XRSC_OK);
    seen_frames seen = {0};
    hs_replay_options opt = {.scene_path = t_source_path("scenes/cornell.gltf"),
                             .poses_path = csv,
                             .pose_columns = cols,
                             .fov_scene = true,
                             .frame_bounds = true,
                             .frames = 2,
                             .on_frame = on_frame,
                             .on_frame_user = &seen};
    opt.context.validation = true;
    opt.renderer.method = XRSC_METHOD_PRIMARY;
    opt.renderer.width = 32;
    opt.renderer.height = 16;
    hs_replay_stats st;
    char buf[1024];
    xrsc_result r = hs_replay_run(&opt, &st, &d);
    CHECK_MSG(r == XRSC_OK, "%s", xrsc_diag_format(&d, buf, sizeof buf));
    CHECK_EQ_INT(seen.count, 2);
    for (int e = 0; e < 2; e++) {
        CHECK_NEAR(seen.fov[e].angleUp, 0.5, 1e-6);
        CHECK_NEAR(tan(seen.fov[e].angleRight), 2.0 * tan(0.5), 1e-5);
    }
    /* --frame: the viewpoint backs off along +Z from the bounds' centre (cornell: x, z in
     * [-1, 1], y in [0, 2]) until the front corners (z = 1) fit the narrowest half-angle
     * (0.5 rad, up and down: symmetric, so no vertical offset) */
    CHECK_NEAR(seen.pose.position.y, 1.0, 1e-3);
    CHECK_NEAR(seen.pose.position.z, 1.0 + 1.0 / tan(0.5), 1e-3);
    CHECK_EQ_INT(st.validation_errors, 0);
}

int main(void)
{
    RUN(test_frame_viewpoint);
    RUN(test_scene_fov);
    RUN(test_start_past_end);
    RUN(test_replay_fov_scene_frame_columns);
    return t_finish();
}
