// SPDX-License-Identifier: MIT
/**
 * @file t_frames.h
 * @brief The frames a replay hands to its on_frame callback, kept for checks, a pose
 *        comparison with a tolerance (tests of the direct and the OpenXR replay paths), and
 *        frames of one fixed view.
 */
#pragma once

#include "xrsc/xrsc.h"

#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <string.h>

#define T_CAPTURED_MAX 16

/** The first T_CAPTURED_MAX frames seen; count stops there. */
typedef struct t_captured {
    xrsc_frame frames[T_CAPTURED_MAX];
    uint32_t count;
} t_captured;

/** An on_frame callback (hs_replay_options): user is a t_captured. */
static inline void t_capture_frame(void *user, const xrsc_frame *frame)
{
    t_captured *c = user;
    if (c->count < T_CAPTURED_MAX)
        c->frames[c->count++] = *frame;
}

/** Whether every position and quaternion component of a and b differs by at most tol. */
static inline bool t_pose_near(XrPosef a, XrPosef b, double tol)
{
    return fabs(a.position.x - b.position.x) <= tol && fabs(a.position.y - b.position.y) <= tol &&
           fabs(a.position.z - b.position.z) <= tol &&
           fabs(a.orientation.x - b.orientation.x) <= tol &&
           fabs(a.orientation.y - b.orientation.y) <= tol &&
           fabs(a.orientation.z - b.orientation.z) <= tol &&
           fabs(a.orientation.w - b.orientation.w) <= tol;
}

/** A frame whose two eyes both sit at the identity pose (origin, looking down -Z) with the
 *  default headset's per-eye FOVs: for tests of what one fixed view shows. */
static inline void t_frame_identity(xrsc_frame *frame)
{
    xrsc_headset hs;
    xrsc_headset_default(&hs);
    memset(frame, 0, sizeof(*frame));
    for (int e = 0; e < 2; e++) {
        frame->views[e].pose = xrsc_pose_identity();
        frame->views[e].fov = hs.fov[e];
    }
}

/** A frame whose two eyes both sit at pos with orientation q (x, y, z, w), each eye's field of
 *  view half_fov_rad to every side: for tests of what one fixed view shows. */
static inline xrsc_frame t_frame_at(const float pos[3], const float q[4], float half_fov_rad)
{
    xrsc_frame f;
    memset(&f, 0, sizeof(f));
    for (int e = 0; e < 2; e++) {
        f.views[e].pose.orientation = (XrQuaternionf){q[0], q[1], q[2], q[3]};
        f.views[e].pose.position = (XrVector3f){pos[0], pos[1], pos[2]};
        f.views[e].fov.angleLeft = f.views[e].fov.angleDown = -half_fov_rad;
        f.views[e].fov.angleRight = f.views[e].fov.angleUp = half_fov_rad;
    }
    return f;
}
