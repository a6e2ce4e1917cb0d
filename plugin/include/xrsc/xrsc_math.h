// SPDX-License-Identifier: MIT
/**
 * @file xrsc_math.h
 * @brief Pose, quaternion and projection math in OpenXR conventions, shared by plugin and host.
 *
 * Conventions: right-handed, +Y up, -Z forward, metres, quaternions (x, y, z, w) as in
 * XrQuaternionf. Matrices are 4x4 column-major float[16] (m[col*4+row]), as cglm and GLSL.
 * Projection targets Vulkan clip space: x right, y DOWN, depth 0 (near) .. 1 (far).
 */
#pragma once

#include <openxr/openxr.h>
#include <stdbool.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Identity pose (no rotation, origin). */
XrPosef xrsc_pose_identity(void);

/** Quaternion product a*b (apply b first, then a). */
XrQuaternionf xrsc_quat_mul(XrQuaternionf a, XrQuaternionf b);
/** Conjugate (the inverse for unit quaternions). */
XrQuaternionf xrsc_quat_conjugate(XrQuaternionf q);
/** Returns q / |q|; identity if |q| == 0. */
XrQuaternionf xrsc_quat_normalize(XrQuaternionf q);
/** Rotates v by the unit quaternion q. */
XrVector3f xrsc_quat_rotate(XrQuaternionf q, XrVector3f v);
/** Quaternion from a unit axis and an angle in radians. */
XrQuaternionf xrsc_quat_from_axis_angle(XrVector3f axis, float angle_rad);
/** Angle in radians (0..pi) of the rotation that takes a to b. */
float xrsc_quat_angle_between(XrQuaternionf a, XrQuaternionf b);
/**
 * Spherical linear interpolation with a hemisphere check: if dot(a, b) < 0, -b is used so the
 * shorter arc is taken (q and -q are the same rotation). t in [0, 1]. Falls back to normalised
 * linear interpolation when a and b are nearly equal.
 */
XrQuaternionf xrsc_quat_slerp(XrQuaternionf a, XrQuaternionf b, float t);

/** Pose composition: result = a * b (b expressed in a's space). */
XrPosef xrsc_pose_mul(XrPosef a, XrPosef b);
/** Inverse of a rigid pose. */
XrPosef xrsc_pose_inverse(XrPosef p);
/** Transforms a point by a pose. */
XrVector3f xrsc_pose_transform_point(XrPosef p, XrVector3f v);
/** Interpolates position linearly and orientation with ::xrsc_quat_slerp. */
XrPosef xrsc_pose_interpolate(XrPosef a, XrPosef b, float t);

/** Model matrix of a pose (local → world). */
void xrsc_pose_to_matrix(XrPosef p, float out_m[16]);
/** View matrix (world → eye) of an eye at pose p; the inverse of ::xrsc_pose_to_matrix. */
void xrsc_pose_view_matrix(XrPosef p, float out_m[16]);
/**
 * Perspective projection for an asymmetric OpenXR field of view (angles in radians, left and
 * down negative), Vulkan clip space (y down, depth 0..1), near_m > 0, far_m > near_m. A point
 * on the view frustum's left edge maps to x_ndc = -1, on the top edge to y_ndc = -1.
 */
void xrsc_fov_projection(XrFovf fov, float near_m, float far_m, float out_m[16]);
/** out = a * b for column-major 4x4 matrices (out may alias neither input). */
void xrsc_mat4_mul(const float a[16], const float b[16], float out_m[16]);
/** out = m * (v, w) as a 4-vector. */
void xrsc_mat4_mul_vec4(const float m[16], const float v[4], float out_v[4]);

/**
 * A simulated headset. Defaults (xrsc_headset_default) are like a current consumer headset:
 * IPD 63 mm, asymmetric per-eye FOV (left eye: left -52 deg, right 43 deg, up 47 deg,
 * down -53 deg; right eye mirrored), 2064 x 2208 pixels per eye, 90 Hz.
 */
typedef struct xrsc_headset {
    float ipd_m;
    XrFovf fov[2]; /**< [0] left eye, [1] right eye */
    unsigned width_px, height_px;
    float refresh_hz;
} xrsc_headset;

/** Fills out with the documented defaults. */
void xrsc_headset_default(xrsc_headset *out);
/**
 * Eye poses for a head pose: each eye is offset by -+ipd/2 along the head's local +X axis
 * (left eye at -ipd/2), with the head's orientation.
 */
void xrsc_headset_eye_poses(const xrsc_headset *hs, XrPosef head, XrPosef out_eyes[2]);

#ifdef __cplusplus
}
#endif
