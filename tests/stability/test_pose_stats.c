// SPDX-License-Identifier: MIT
/**
 * @file test_pose_stats.c
 * @brief hs_pose_stream_fastest_window (`xrsc poses stats --fastest`, which picks the window of
 *        the `headturn-hololens` case) on synthetic streams whose answer is known.
 */
#include "hs_pose_stats.h"
#include "testing.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define T_PI 3.14159265358979323846
#define T_RATE_HZ 100.0

/** A stream at 100 Hz whose yaw speed (deg/s) at time t is speed(t). */
static hs_pose_stream make_stream(hs_pose_sample *s, size_t n, double (*speed)(double))
{
    double yaw = 0.0;
    const XrVector3f up = {0, 1, 0};
    for (size_t i = 0; i < n; i++) {
        double t = (double)i / T_RATE_HZ;
        if (i)
            yaw += speed(t - 0.5 / T_RATE_HZ) / T_RATE_HZ; /* midpoint rule per step */
        memset(&s[i], 0, sizeof(s[i]));
        s[i].time_ns = (int64_t)llround(t * 1e9);
        s[i].pose.orientation = xrsc_quat_from_axis_angle(up, (float)(yaw * T_PI / 180.0));
    }
    hs_pose_stream st = {.samples = s, .count = n, .format = HS_POSE_FORMAT_XRSC};
    return st;
}

/* 10 deg/s everywhere, 100 deg/s over [3.0, 3.5) s, 60 deg/s over [6, 7.2) s: the fastest
 * one-second window lies inside the longer, slower burst (60 deg/s) rather than around the
 * short, fast one (0.5 x 100 + 0.5 x 10 = 55 deg/s); the fastest half second is the fast one. */
static double bursts(double t)
{
    if (t >= 3.0 && t < 3.5)
        return 100.0;
    if (t >= 6.0 && t < 7.2)
        return 60.0;
    return 10.0;
}

static void fastest_window_of_two_bursts(void)
{
    enum { N = 1001 }; /* 10 s */
    hs_pose_sample *s = malloc(sizeof(*s) * N);
    hs_pose_stream st = make_stream(s, N, bursts);
    hs_pose_window w;
    CHECK_EQ_INT(hs_pose_stream_fastest_window(&st, 1000000000LL, &w), XRSC_OK);
    const double deg = 180.0 / T_PI;
    /* every window starting in [6.0, 6.2] s lies in the 60 deg/s burst (they tie but for the
     * float rounding of the quaternions) */
    double t0 = (double)w.start_ns * 1e-9;
    CHECK_MSG(t0 > 6.0 - 1e-6 && t0 < 6.2 + 1e-6, "start %.3f s", t0);
    CHECK_NEAR((double)(w.end_ns - w.start_ns) * 1e-9, 1.0, 1e-9);
    CHECK_NEAR(w.mean_speed_rad_s * deg, 60.0, 0.01);
    CHECK_NEAR(w.peak_speed_rad_s * deg, 60.0, 0.01);
    CHECK(w.last_sample == w.first_sample + 100);
    /* a half-second window: the 100 deg/s burst wins */
    CHECK_EQ_INT(hs_pose_stream_fastest_window(&st, 500000000LL, &w), XRSC_OK);
    CHECK_NEAR((double)w.start_ns * 1e-9, 3.0, 1e-6);
    CHECK_NEAR(w.mean_speed_rad_s * deg, 100.0, 0.01);
    double tp = (double)w.peak_ns * 1e-9; /* the midpoint of a step of the burst */
    CHECK_MSG(tp > 3.0 && tp < 3.5, "peak at %.3f s", tp);
    /* the whole stream as one window: its mean and peak */
    CHECK_EQ_INT(hs_pose_stream_fastest_window(&st, 20000000000LL, &w), XRSC_OK);
    CHECK(w.start_ns == 0 && w.first_sample == 0 && w.last_sample == N - 1);
    double total = 10.0 * 10.0 + 0.5 * 90.0 + 1.2 * 50.0; /* degrees */
    CHECK_NEAR(w.mean_speed_rad_s * deg, total / 20.0, 0.01);
    CHECK_NEAR(w.peak_speed_rad_s * deg, 100.0, 0.01);
    free(s);
}

/* Rotation about any axis counts, in either direction and across the q / -q sign flip. */
static void angle_is_axis_and_sign_independent(void)
{
    hs_pose_sample s[4];
    memset(s, 0, sizeof(s));
    const XrVector3f axes[3] = {{1, 0, 0}, {0, 0, 1}, {0, 1, 0}};
    double angle_deg[4] = {0, 10, -10, 30};
    for (int i = 0; i < 4; i++) {
        s[i].time_ns = (int64_t)i * 100000000LL;
        XrQuaternionf q =
            xrsc_quat_from_axis_angle(axes[i % 3], (float)(angle_deg[i] * T_PI / 180.0));
        if (i == 3)
            q = (XrQuaternionf){-q.x, -q.y, -q.z, -q.w}; /* same rotation */
        s[i].pose.orientation = q;
    }
    hs_pose_stream st = {.samples = s, .count = 4};
    hs_pose_window w;
    CHECK_EQ_INT(hs_pose_stream_fastest_window(&st, 100000000LL, &w), XRSC_OK);
    /* steps: 10 deg (about Z), then from 10 deg about Z to -10 deg about Y, then to 30 deg
     * about X: the largest single step wins a window of one step */
    double deg = 180.0 / T_PI;
    CHECK(w.first_sample + 1 == w.last_sample);
    CHECK_NEAR(w.mean_speed_rad_s * 0.1 * deg, w.peak_speed_rad_s * 0.1 * deg, 1e-9);
    CHECK(w.peak_speed_rad_s * 0.1 * deg > 10.0);
}

static void bad_arguments(void)
{
    hs_pose_sample s[1];
    memset(s, 0, sizeof(s));
    s[0].pose.orientation.w = 1.0f;
    hs_pose_stream st = {.samples = s, .count = 1};
    hs_pose_window w;
    CHECK_EQ_INT(hs_pose_stream_fastest_window(NULL, 1, &w), XRSC_ERROR_INVALID_ARGUMENT);
    CHECK_EQ_INT(hs_pose_stream_fastest_window(&st, 0, &w), XRSC_ERROR_INVALID_ARGUMENT);
    /* one sample: one empty window, speed 0 */
    CHECK_EQ_INT(hs_pose_stream_fastest_window(&st, 1000, &w), XRSC_OK);
    CHECK(w.mean_speed_rad_s == 0.0 && w.peak_speed_rad_s == 0.0 && w.last_sample == 0);
}

int main(void)
{
    RUN(fastest_window_of_two_bursts);
    RUN(angle_is_axis_and_sign_independent);
    RUN(bad_arguments);
    return t_finish();
}
