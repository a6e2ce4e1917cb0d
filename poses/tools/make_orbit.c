// SPDX-License-Identifier: MIT
/**
 * @file make_orbit.c
 * @brief Generates poses/orbit_cornell.xrpose: a seated user looking around a Cornell box.
 *
 * Usage: xrsc_make_orbit OUT.xrpose. The motion is specified in poses/README.md
 * ("orbit_cornell.xrpose"); every constant below is named there too.
 */
#include "hs_pose_stream.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#define ORBIT_RATE_HZ 90.0
#define ORBIT_SAMPLES 180
#define ORBIT_NS_PER_S 1e9
#define ORBIT_PI 3.14159265358979323846
#define ORBIT_DEG (ORBIT_PI / 180.0)

/* Yaw (about +Y, positive = look left): three eased segments, velocity zero at each joint. */
#define ORBIT_YAW_LOOK_LEFT_DEG (-20.0) /**< reached at ORBIT_TURN_START_S (negative = right) */
#define ORBIT_YAW_AFTER_TURN_DEG 22.0   /**< reached at ORBIT_TURN_END_S */
#define ORBIT_YAW_END_DEG 10.0          /**< reached at the last sample */
#define ORBIT_TURN_START_S 0.80
#define ORBIT_TURN_END_S 1.15 /**< 42 deg in 0.35 s: 120 deg/s mean, 188 deg/s peak */
/* Pitch (about +X, positive = look up) and roll (about -Z): slow sines, zero at t = 0. */
#define ORBIT_PITCH_AMPL_DEG 8.0
#define ORBIT_PITCH_PERIOD_S 1.8
#define ORBIT_ROLL_AMPL_DEG 2.0
#define ORBIT_ROLL_PERIOD_S 2.0
/* Head translation of a seated user, metres: sway, bob and lean, zero at t = 0. */
#define ORBIT_SWAY_X_M 0.03
#define ORBIT_SWAY_PERIOD_S 2.0
#define ORBIT_BOB_Y_M 0.01
#define ORBIT_BOB_PERIOD_S 1.0
#define ORBIT_LEAN_Z_M (-0.02)

/** Cosine ease from 0 to 1 over u in [0, 1], zero velocity at both ends. */
static double ease(double u)
{
    if (u <= 0.0)
        return 0.0;
    if (u >= 1.0)
        return 1.0;
    return 0.5 * (1.0 - cos(ORBIT_PI * u));
}

static double yaw_deg(double t, double t_end)
{
    if (t < ORBIT_TURN_START_S)
        return ORBIT_YAW_LOOK_LEFT_DEG * ease(t / ORBIT_TURN_START_S);
    if (t < ORBIT_TURN_END_S)
        return ORBIT_YAW_LOOK_LEFT_DEG +
               (ORBIT_YAW_AFTER_TURN_DEG - ORBIT_YAW_LOOK_LEFT_DEG) *
                   ease((t - ORBIT_TURN_START_S) / (ORBIT_TURN_END_S - ORBIT_TURN_START_S));
    return ORBIT_YAW_AFTER_TURN_DEG + (ORBIT_YAW_END_DEG - ORBIT_YAW_AFTER_TURN_DEG) *
                                          ease((t - ORBIT_TURN_END_S) / (t_end - ORBIT_TURN_END_S));
}

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: %s OUT.xrpose\n", argv[0]);
        return 2;
    }
    hs_pose_sample samples[ORBIT_SAMPLES];
    const double t_end = (ORBIT_SAMPLES - 1) / ORBIT_RATE_HZ;
    const XrVector3f axis_x = {1, 0, 0}, axis_y = {0, 1, 0}, axis_z = {0, 0, 1};
    for (int i = 0; i < ORBIT_SAMPLES; i++) {
        double t = i / ORBIT_RATE_HZ;
        double pitch = ORBIT_PITCH_AMPL_DEG * sin(2.0 * ORBIT_PI * t / ORBIT_PITCH_PERIOD_S);
        double roll = ORBIT_ROLL_AMPL_DEG * sin(2.0 * ORBIT_PI * t / ORBIT_ROLL_PERIOD_S);
        XrQuaternionf q = xrsc_quat_mul(
            xrsc_quat_from_axis_angle(axis_y, (float)(yaw_deg(t, t_end) * ORBIT_DEG)),
            xrsc_quat_mul(xrsc_quat_from_axis_angle(axis_x, (float)(pitch * ORBIT_DEG)),
                          xrsc_quat_from_axis_angle(axis_z, (float)(-roll * ORBIT_DEG))));
        samples[i].time_ns = (int64_t)llround(t * ORBIT_NS_PER_S);
        samples[i].pose.orientation = xrsc_quat_normalize(q);
        samples[i].pose.position.x =
            (float)(ORBIT_SWAY_X_M * sin(2.0 * ORBIT_PI * t / ORBIT_SWAY_PERIOD_S));
        samples[i].pose.position.y =
            (float)(ORBIT_BOB_Y_M * sin(2.0 * ORBIT_PI * t / ORBIT_BOB_PERIOD_S));
        /* + 0.0f turns -0 into 0 in the text. */
        samples[i].pose.position.z = (float)(ORBIT_LEAN_Z_M * ease(t / t_end)) + 0.0f;
    }
    hs_pose_stream stream = {.samples = samples,
                             .count = ORBIT_SAMPLES,
                             .orientation_only = false,
                             .format = HS_POSE_FORMAT_XRSC};
    xrsc_diag diag;
    if (hs_pose_stream_save(&stream, argv[1], &diag) != XRSC_OK) {
        char buf[1024];
        fprintf(stderr, "%s\n", xrsc_diag_format(&diag, buf, sizeof(buf)));
        return 1;
    }
    return 0;
}
