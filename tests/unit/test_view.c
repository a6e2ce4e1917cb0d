// SPDX-License-Identifier: MIT
/**
 * @file test_view.c
 * @brief Issue 18 (viewpoint), CPU side: --viewpoint parsing and its errors (field
 *        "--viewpoint"), yaw, --viewpoint inside, --frame with eyes (every corner of the bounds
 *        inside every side of both eyes' frusta, tightly on one; a flat box centred in an
 *        asymmetric view and touching both its edges), the IPD --frame gives a scene narrower than the IPD,
 *        and which hint ID each kind of first frame gets.
 */
#include "hs_view.h"
#include "testing.h"

#include <math.h>
#include <string.h>

#define T_PI 3.14159265358979323846

static void test_parse(void)
{
    hs_viewpoint v;
    xrsc_diag d;
    CHECK_EQ_INT(hs_viewpoint_parse("camera:2", &v, &d), XRSC_OK);
    CHECK_EQ_INT(v.kind, HS_VIEWPOINT_CAMERA);
    CHECK_EQ_INT(v.camera, 2);
    CHECK_EQ_INT(hs_viewpoint_parse("inside", &v, &d), XRSC_OK);
    CHECK_EQ_INT(v.kind, HS_VIEWPOINT_INSIDE);
    CHECK_EQ_INT(hs_viewpoint_parse("1.5,-2,3e-3", &v, &d), XRSC_OK);
    CHECK_EQ_INT(v.kind, HS_VIEWPOINT_POSITION);
    CHECK_NEAR(v.position[0], 1.5, 0.0);
    CHECK_NEAR(v.position[1], -2.0, 0.0);
    CHECK_NEAR(v.position[2], 3e-3, 1e-9);
    CHECK_NEAR(v.yaw_deg, 0.0, 0.0);
    CHECK_EQ_INT(hs_viewpoint_parse("0,1.6,0:90", &v, &d), XRSC_OK);
    CHECK_NEAR(v.yaw_deg, 90.0, 0.0);
    static const char *const bad[] = {"",        "camera:",   "camera:x", "camera:-1",
                                      "1,2",     "1,2,3,4",   "1,,3",     "a,b,c",
                                      "1,2,3:",  "1,2,3:up",  "inside2",  "camera:1.5",
                                      "nan,0,0", "1,2,3:1:2"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        memset(&d, 0, sizeof d);
        CHECK_MSG(hs_viewpoint_parse(bad[i], &v, &d) == XRSC_ERROR_INVALID_ARGUMENT, "'%s'",
                  bad[i]);
        CHECK_MSG(!strcmp(d.field, "--viewpoint"), "'%s': field '%s'", bad[i], d.field);
    }
}

/** Rotates v by unit quaternion q. */
static void rotate(XrQuaternionf q, const double v[3], double out[3])
{
    double u[3] = {q.x, q.y, q.z}, s = q.w;
    double uv = u[0] * v[0] + u[1] * v[1] + u[2] * v[2], uu = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
    double c[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    for (int a = 0; a < 3; a++) out[a] = 2.0 * uv * u[a] + (s * s - uu) * v[a] + 2.0 * s * c[a];
}

static void test_at_and_inside(void)
{
    const float p[3] = {1, 2, 3};
    XrPosef pose = hs_view_at(p, 90.0f);
    CHECK_NEAR(pose.position.x, 1.0, 0.0);
    CHECK_NEAR(pose.position.z, 3.0, 0.0);
    const double fwd[3] = {0, 0, -1};
    double f[3];
    rotate(pose.orientation, fwd, f); /* 90 degrees counter-clockwise from above: -Z -> -X */
    CHECK_NEAR(f[0], -1.0, 1e-6);
    CHECK_NEAR(f[2], 0.0, 1e-6);
    xrsc_scene_info info = {.bounds_min = {-2, 0, -3}, .bounds_max = {4, 3, 1}};
    XrPosef in = hs_view_inside(&info);
    CHECK_NEAR(in.position.x, 1.0, 0.0);
    CHECK_NEAR(in.position.y, 1.5, 0.0);
    CHECK_NEAR(in.position.z, -1.0, 0.0);
    CHECK_NEAR(in.orientation.w, 1.0, 0.0);
}

/** Signed distance of the sphere (centre c, eye at e looking down -Z) inside each side of the
 *  eye's frustum, minus r: >= 0 when it fits; returns the smallest over the sides. */
static double fit_margin(const double c[3], double r, const double e[3], XrFovf fov)
{
    double x = c[0] - e[0], y = c[1] - e[1], depth = e[2] - c[2];
    const double ang[4] = {fov.angleRight, -fov.angleLeft, fov.angleUp, -fov.angleDown};
    const double off[4] = {x, -x, y, -y};
    double m = 1e30;
    for (int k = 0; k < 4; k++) m = fmin(m, depth * sin(ang[k]) - off[k] * cos(ang[k]) - r);
    return m;
}

static void test_frame_with_eyes(void)
{
    XrFovf fov[2] = {{-0.9f, 0.7f, 0.8f, -0.8f}, {-0.7f, 0.9f, 0.8f, -0.8f}};
    /* a 7 mm model, a 1 m one and a 10 km one, eyes 63 mm apart: every corner of the
     * bounds fits every side of both eyes, tightly on one of them */
    const double sizes[3] = {0.007, 1.0, 1e4};
    for (int s = 0; s < 3; s++) {
        double h = 0.5 * sizes[s];
        xrsc_scene_info info = {.bounds_min = {(float)(5 - h), (float)-h, (float)-h},
                                .bounds_max = {(float)(5 + h), (float)h, (float)h}};
        double ipd = 0.063, r = sqrt(3.0) * h;
        XrPosef p = hs_view_frame(&info, fov, ipd);
        /* the eyes' FOVs mirror each other: no sideways or vertical offset */
        CHECK_NEAR(p.position.x, 5.0, 1e-6 * fmax(1.0, sizes[s]));
        CHECK_NEAR(p.position.y, 0.0, 1e-6 * fmax(1.0, sizes[s]));
        CHECK_NEAR(p.orientation.w, 1.0, 0.0);
        double m = 1e30;
        for (int e = 0; e < 2; e++) {
            double eye[3] = {p.position.x + (e ? 0.5 : -0.5) * ipd, p.position.y, p.position.z};
            for (int k = 0; k < 8; k++) {
                double corner[3] = {5 + (k & 1 ? h : -h), k & 2 ? h : -h, k & 4 ? h : -h};
                m = fmin(m, fit_margin(corner, 0.0, eye, fov[e]));
            }
        }
        double tol = 1e-5 * fmax(1.0, sizes[s]); /* float bounds and positions */
        CHECK_MSG(m >= -tol && m <= tol + 1e-4 * r, "size %g: margin %g", sizes[s], m);
        /* ipd 0: the front corners in the narrowest half-angle (hs_frame_viewpoint) */
        XrPosef q = hs_view_frame(&info, fov, 0.0);
        CHECK_NEAR(q.position.z, h + h / tan(0.7), 1e-5 * fmax(1.0, sizes[s]));
    }
    /* the IPD --frame uses: a tenth of the distance for the 7 mm model, unchanged for 1 m */
    xrsc_scene_info tiny = {.bounds_min = {-0.0035f, -0.0035f, -0.0001f},
                            .bounds_max = {0.0035f, 0.0035f, 0.0001f}};
    double d = hs_view_frame(&tiny, fov, 0.0).position.z;
    CHECK_NEAR(hs_frame_ipd_m(&tiny, fov, 0.063), 0.1 * d, 1e-9);
    CHECK(hs_frame_ipd_m(&tiny, fov, 0.063) < 0.002);
    xrsc_scene_info metre = {.bounds_min = {-0.5f, -0.5f, -0.5f}, .bounds_max = {0.5f, 0.5f, 0.5f}};
    CHECK_NEAR(hs_frame_ipd_m(&metre, fov, 0.063), 0.063, 0.0);
    CHECK_NEAR(hs_scene_width_m(&tiny), 0.007, 1e-7);
}

/** A 7 mm tall flat box in a view wider downwards than upwards: --frame centres it in the
 *  image (not on the view axis) and it touches the top and the bottom edge. */
static void test_frame_centred(void)
{
    XrFovf fov[2] = {{-0.9f, 0.9f, 0.6f, -0.9f}, {-0.9f, 0.9f, 0.6f, -0.9f}};
    const double hx = 0.001, hy = 0.0035, hz = 0.0001, cy = 0.02;
    xrsc_scene_info info = {.bounds_min = {(float)-hx, (float)(cy - hy), (float)-hz},
                            .bounds_max = {(float)hx, (float)(cy + hy), (float)hz}};
    XrPosef p = hs_view_frame(&info, fov, 0.0);
    double depth = p.position.z - hz; /* to the front face */
    double top = (cy + hy - p.position.y) / depth, bottom = (p.position.y - (cy - hy)) / depth;
    printf("flat box: top edge at tan %.6f (view %.6f), bottom at %.6f (view %.6f)\n", top,
           tan(0.6), bottom, tan(0.9));
    CHECK_NEAR(top, tan(0.6), 1e-4);
    CHECK_NEAR(bottom, tan(0.9), 1e-4);
    CHECK(p.position.y > cy); /* above the box's centre: the box sits low, where the view is wide */
    CHECK_NEAR(p.position.x, 0.0, 1e-9);
}

static void test_hints(void)
{
    hs_first_frame f = {.background_fraction = 0.99, .black_fraction = 0.0,
                        .scene_width_m = 0.007, .distance_m = 2.0};
    CHECK_EQ_INT(hs_first_frame_hint(&f), HS_HINT_SCENE_TOO_SMALL);
    f.scene_width_m = 1.0; /* big enough: the view looks elsewhere */
    CHECK_EQ_INT(hs_first_frame_hint(&f), HS_HINT_VIEW_MISSES_SCENE);
    f.background_fraction = 1.0, f.black_fraction = 1.0; /* black background: still a miss */
    CHECK_EQ_INT(hs_first_frame_hint(&f), HS_HINT_VIEW_MISSES_SCENE);
    f.background_fraction = 0.0; /* black and filled with geometry */
    f.head_inside_bounds = true;
    CHECK_EQ_INT(hs_first_frame_hint(&f), HS_HINT_INSIDE_GEOMETRY);
    f.head_inside_bounds = false;
    CHECK_EQ_INT(hs_first_frame_hint(&f), HS_HINT_ENCLOSED_SCENE);
    f.background_fraction = 0.5; /* black, half background: no light */
    CHECK_EQ_INT(hs_first_frame_hint(&f), HS_HINT_NO_LIGHT);
    f.black_fraction = 0.5; /* a frame that shows something */
    CHECK_EQ_INT(hs_first_frame_hint(&f), HS_HINT_NONE);
    /* names are the IDs printed in brackets; the messages name what to try */
    CHECK(!strcmp(hs_hint_name(HS_HINT_SCENE_TOO_SMALL), "scene-too-small"));
    CHECK(!strcmp(hs_hint_name(HS_HINT_NARROWER_THAN_IPD), "narrower-than-ipd"));
    CHECK(!strcmp(hs_hint_name(HS_HINT_COUNT), "?"));
    char msg[512];
    f.camera_count = 2;
    hs_hint_message(HS_HINT_INSIDE_GEOMETRY, &f, msg, sizeof msg);
    CHECK(strstr(msg, "--viewpoint inside") && strstr(msg, "camera:0..1"));
    hs_hint_message(HS_HINT_SCENE_TOO_SMALL, &f, msg, sizeof msg);
    CHECK(strstr(msg, "--frame") != NULL);
    hs_hint_message(HS_HINT_NONE, &f, msg, sizeof msg);
    CHECK(msg[0] == '\0');
}

int main(void)
{
    RUN(test_parse);
    RUN(test_at_and_inside);
    RUN(test_frame_with_eyes);
    RUN(test_frame_centred);
    RUN(test_hints);
    return t_finish();
}
