// SPDX-License-Identifier: MIT
/**
 * @file make_stability_poses.c
 * @brief Generates the pose streams of the stability cases (issue 9): poses/strands.xrpose,
 *        headturn.xrpose, pan.xrpose, orbit_specular.xrpose, still.xrpose, sideways.xrpose.
 *
 * Usage: xrsc_make_stability_poses OUT_DIR (normally the repository's poses/ folder). Every
 * stream is sampled at 90 Hz (t = i / 90 s, rounded to ns), starts at the identity pose (a
 * replay anchors it at the scene's camera, so its motion is relative to that camera) and is
 * specified, with these constants, in poses/README.md ("Stability streams").
 */
#include "hs_pose_stream.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define SP_RATE_HZ 90.0
#define SP_PI 3.14159265358979323846
#define SP_DEG (SP_PI / 180.0)

/* strands: slow drift (flicker under small motion) */
#define DRIFT_DURATION_S 2.0
#define DRIFT_X_M_PER_S 0.02
#define DRIFT_YAW_DEG_PER_S 2.0
/* headturn: still, a 90 deg yaw to the left (cosine ease), still (seed 000 Fig. 12) */
#define TURN_START_S 1.0
#define TURN_DURATION_S 0.25
#define TURN_YAW_DEG 90.0
#define TURN_STILL_AFTER_S 1.0
/* pan: still, then a sideways (+X) translation accelerating to a constant speed */
#define PAN_START_S 0.2
#define PAN_RAMP_S 0.1
#define PAN_SPEED_M_PER_S 1.0
#define PAN_DURATION_S 1.4
/* orbit_specular: constant-speed orbit about the point ORBIT_RADIUS_M ahead of the start */
#define ORBIT_RADIUS_M 1.566 /**< camera to the point between the spheres of specular.gltf */
#define ORBIT_DEG_PER_S 45.0
#define ORBIT_DURATION_S 2.0
/* still */
#define STILL_DURATION_S 2.0
/* sideways: head sway along +X (disocclusion of the wall behind the box, one-eye pixels) */
#define SWAY_AMPL_M 0.15
#define SWAY_PERIOD_S 2.0
#define SWAY_DURATION_S 2.0

/** Cosine ease from 0 to 1 over u in [0, 1], zero velocity at both ends. */
static double ease(double u)
{
    if (u <= 0.0)
        return 0.0;
    if (u >= 1.0)
        return 1.0;
    return 0.5 * (1.0 - cos(SP_PI * u));
}

/** Yaw (deg, about +Y) and position (m) of one stream at time t. */
typedef void (*sp_motion)(double t, double *yaw_deg, double pos[3]);

static void m_drift(double t, double *yaw, double p[3])
{
    *yaw = DRIFT_YAW_DEG_PER_S * t;
    p[0] = DRIFT_X_M_PER_S * t;
}

static void m_headturn(double t, double *yaw, double p[3])
{
    (void)p;
    *yaw = TURN_YAW_DEG * ease((t - TURN_START_S) / TURN_DURATION_S);
}

static void m_pan(double t, double *yaw, double p[3])
{
    (void)yaw;
    double s = t - PAN_START_S;
    if (s <= 0.0)
        p[0] = 0.0;
    else if (s < PAN_RAMP_S) /* constant acceleration up to the speed */
        p[0] = PAN_SPEED_M_PER_S * s * s / (2.0 * PAN_RAMP_S);
    else
        p[0] = PAN_SPEED_M_PER_S * (0.5 * PAN_RAMP_S + (s - PAN_RAMP_S));
}

static void m_orbit(double t, double *yaw, double p[3])
{
    /* position = c + R_y(yaw) (0 - c) with c = (0, 0, -r), looking at c all the time */
    *yaw = ORBIT_DEG_PER_S * t;
    p[0] = ORBIT_RADIUS_M * sin(*yaw * SP_DEG);
    p[2] = ORBIT_RADIUS_M * (cos(*yaw * SP_DEG) - 1.0);
}

static void m_still(double t, double *yaw, double p[3])
{
    (void)t, (void)yaw, (void)p;
}

static void m_sideways(double t, double *yaw, double p[3])
{
    (void)yaw;
    p[0] = SWAY_AMPL_M * sin(2.0 * SP_PI * t / SWAY_PERIOD_S);
}

static int write_stream(const char *dir, const char *name, sp_motion motion, double duration_s)
{
    size_t n = (size_t)llround(duration_s * SP_RATE_HZ) + 1;
    hs_pose_sample *s = calloc(n, sizeof(*s));
    if (!s)
        return 1;
    const XrVector3f up = {0, 1, 0};
    for (size_t i = 0; i < n; i++) {
        double t = (double)i / SP_RATE_HZ, yaw = 0.0, p[3] = {0, 0, 0};
        motion(t, &yaw, p);
        s[i].time_ns = (int64_t)llround(t * 1e9);
        s[i].pose.orientation = xrsc_quat_from_axis_angle(up, (float)(yaw * SP_DEG));
        /* + 0.0f turns -0 into 0 in the text */
        s[i].pose.position =
            (XrVector3f){(float)p[0] + 0.0f, (float)p[1] + 0.0f, (float)p[2] + 0.0f};
    }
    hs_pose_stream stream = {.samples = s, .count = n, .format = HS_POSE_FORMAT_XRSC};
    char path[1024];
    snprintf(path, sizeof(path), "%s/%s.xrpose", dir, name);
    xrsc_diag diag;
    memset(&diag, 0, sizeof(diag));
    xrsc_result r = hs_pose_stream_save(&stream, path, &diag);
    free(s);
    if (r != XRSC_OK) {
        char buf[1024];
        fprintf(stderr, "%s\n", xrsc_diag_format(&diag, buf, sizeof(buf)));
        return 1;
    }
    printf("wrote %s (%zu samples)\n", path, n);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: %s OUT_DIR\n", argv[0]);
        return 2;
    }
    const char *d = argv[1];
    int fails = write_stream(d, "strands", m_drift, DRIFT_DURATION_S);
    fails += write_stream(d, "headturn", m_headturn,
                          TURN_START_S + TURN_DURATION_S + TURN_STILL_AFTER_S);
    fails += write_stream(d, "pan", m_pan, PAN_DURATION_S);
    fails += write_stream(d, "orbit_specular", m_orbit, ORBIT_DURATION_S);
    fails += write_stream(d, "still", m_still, STILL_DURATION_S);
    fails += write_stream(d, "sideways", m_sideways, SWAY_DURATION_S);
    return fails ? 1 : 0;
}
