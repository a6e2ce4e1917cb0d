// SPDX-License-Identifier: MIT
/**
 * @file m_math.c
 * @brief Quaternion, pose, projection and simulated-headset math declared in xrsc_math.h.
 *
 * Plain C in double precision internally (results are floats, as in the OpenXR types), so the
 * functions have no hidden dependence on cglm's SIMD paths or its -Z/+Z conventions.
 */
#include "xrsc/xrsc_math.h"

#include <math.h>
#include <string.h>

/** Below this |q|^2, ::xrsc_quat_normalize returns the identity instead of dividing. */
#define M_QUAT_NORM_SQ_MIN 1e-30
/**
 * Above this |dot| = cos(theta) (theta the half angle: rotations less than ~3.6 deg apart)
 * slerp's 1/sin(theta) loses precision; normalised lerp differs from slerp there by less than
 * 1e-5 rad, below what the float pose inputs resolve at that scale.
 */
#define M_SLERP_NLERP_DOT 0.9995

/* Default simulated headset (xrsc_math.h): like a current consumer headset. */
#define M_DEFAULT_IPD_M 0.063f
#define M_DEFAULT_FOV_OUTER_DEG 52.0 /**< left eye's left edge, right eye's right edge */
#define M_DEFAULT_FOV_INNER_DEG 43.0 /**< towards the nose */
#define M_DEFAULT_FOV_UP_DEG 47.0
#define M_DEFAULT_FOV_DOWN_DEG 53.0
#define M_DEFAULT_WIDTH_PX 2064u
#define M_DEFAULT_HEIGHT_PX 2208u
#define M_DEFAULT_REFRESH_HZ 90.0f

/** pi/180; M_PI is not part of C11. */
#define M_RAD_PER_DEG (3.14159265358979323846 / 180.0)

static double deg_to_rad(double deg)
{
    return deg * M_RAD_PER_DEG;
}

XrPosef xrsc_pose_identity(void)
{
    XrPosef p;
    p.orientation.x = 0.0f;
    p.orientation.y = 0.0f;
    p.orientation.z = 0.0f;
    p.orientation.w = 1.0f;
    p.position.x = 0.0f;
    p.position.y = 0.0f;
    p.position.z = 0.0f;
    return p;
}

XrQuaternionf xrsc_quat_mul(XrQuaternionf a, XrQuaternionf b)
{
    /* Hamilton product. */
    XrQuaternionf r;
    r.w = a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z;
    r.x = a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y;
    r.y = a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x;
    r.z = a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w;
    return r;
}

XrQuaternionf xrsc_quat_conjugate(XrQuaternionf q)
{
    XrQuaternionf r = {-q.x, -q.y, -q.z, q.w};
    return r;
}

XrQuaternionf xrsc_quat_normalize(XrQuaternionf q)
{
    double n2 = (double)q.x * q.x + (double)q.y * q.y + (double)q.z * q.z + (double)q.w * q.w;
    if (!(n2 > M_QUAT_NORM_SQ_MIN) || !isfinite(n2)) {
        XrQuaternionf id = {0.0f, 0.0f, 0.0f, 1.0f};
        return id;
    }
    double inv = 1.0 / sqrt(n2);
    XrQuaternionf r = {(float)(q.x * inv), (float)(q.y * inv), (float)(q.z * inv),
                       (float)(q.w * inv)};
    return r;
}

XrVector3f xrsc_quat_rotate(XrQuaternionf q, XrVector3f v)
{
    /* v' = v + w t + u x t with t = 2 (u x v), u the vector part: q v q* for unit q. */
    double ux = q.x, uy = q.y, uz = q.z, w = q.w;
    double tx = 2.0 * (uy * v.z - uz * v.y);
    double ty = 2.0 * (uz * v.x - ux * v.z);
    double tz = 2.0 * (ux * v.y - uy * v.x);
    XrVector3f r;
    r.x = (float)(v.x + w * tx + (uy * tz - uz * ty));
    r.y = (float)(v.y + w * ty + (uz * tx - ux * tz));
    r.z = (float)(v.z + w * tz + (ux * ty - uy * tx));
    return r;
}

XrQuaternionf xrsc_quat_from_axis_angle(XrVector3f axis, float angle_rad)
{
    double s = sin(0.5 * angle_rad);
    XrQuaternionf q = {(float)(axis.x * s), (float)(axis.y * s), (float)(axis.z * s),
                       (float)cos(0.5 * angle_rad)};
    return q;
}

float xrsc_quat_angle_between(XrQuaternionf a, XrQuaternionf b)
{
    /* d = a* b is the rotation from a to b; its angle is 2 atan2(|vec(d)|, |w(d)|), which
     * stays accurate near 0 and pi where 2 acos(|dot|) does not. */
    XrQuaternionf d = xrsc_quat_mul(xrsc_quat_conjugate(a), b);
    double v = sqrt((double)d.x * d.x + (double)d.y * d.y + (double)d.z * d.z);
    return (float)(2.0 * atan2(v, fabs((double)d.w)));
}

XrQuaternionf xrsc_quat_slerp(XrQuaternionf a, XrQuaternionf b, float t)
{
    double dot = (double)a.x * b.x + (double)a.y * b.y + (double)a.z * b.z + (double)a.w * b.w;
    double bs = 1.0;
    if (dot < 0.0) { /* hemisphere check: -b is the same rotation, on a's side */
        dot = -dot;
        bs = -1.0;
    }
    double wa, wb;
    if (dot > M_SLERP_NLERP_DOT) {
        wa = 1.0 - t;
        wb = t;
    } else {
        double theta = acos(dot);
        double s = sin(theta);
        wa = sin((1.0 - t) * theta) / s;
        wb = sin(t * theta) / s;
    }
    wb *= bs;
    XrQuaternionf r = {(float)(wa * a.x + wb * b.x), (float)(wa * a.y + wb * b.y),
                       (float)(wa * a.z + wb * b.z), (float)(wa * a.w + wb * b.w)};
    return xrsc_quat_normalize(r);
}

XrPosef xrsc_pose_mul(XrPosef a, XrPosef b)
{
    XrPosef r;
    r.orientation = xrsc_quat_mul(a.orientation, b.orientation);
    XrVector3f p = xrsc_quat_rotate(a.orientation, b.position);
    r.position.x = p.x + a.position.x;
    r.position.y = p.y + a.position.y;
    r.position.z = p.z + a.position.z;
    return r;
}

XrPosef xrsc_pose_inverse(XrPosef p)
{
    XrPosef r;
    r.orientation = xrsc_quat_conjugate(p.orientation);
    XrVector3f t = xrsc_quat_rotate(r.orientation, p.position);
    r.position.x = -t.x;
    r.position.y = -t.y;
    r.position.z = -t.z;
    return r;
}

XrVector3f xrsc_pose_transform_point(XrPosef p, XrVector3f v)
{
    XrVector3f r = xrsc_quat_rotate(p.orientation, v);
    r.x += p.position.x;
    r.y += p.position.y;
    r.z += p.position.z;
    return r;
}

XrPosef xrsc_pose_interpolate(XrPosef a, XrPosef b, float t)
{
    XrPosef r;
    r.position.x = (float)(a.position.x + ((double)b.position.x - a.position.x) * t);
    r.position.y = (float)(a.position.y + ((double)b.position.y - a.position.y) * t);
    r.position.z = (float)(a.position.z + ((double)b.position.z - a.position.z) * t);
    r.orientation = xrsc_quat_slerp(a.orientation, b.orientation, t);
    return r;
}

void xrsc_pose_to_matrix(XrPosef p, float out_m[16])
{
    const XrQuaternionf q = p.orientation;
    double x = q.x, y = q.y, z = q.z, w = q.w;
    /* Columns are the images of the basis vectors (rotation matrix of a unit quaternion). */
    out_m[0] = (float)(1.0 - 2.0 * (y * y + z * z));
    out_m[1] = (float)(2.0 * (x * y + w * z));
    out_m[2] = (float)(2.0 * (x * z - w * y));
    out_m[3] = 0.0f;
    out_m[4] = (float)(2.0 * (x * y - w * z));
    out_m[5] = (float)(1.0 - 2.0 * (x * x + z * z));
    out_m[6] = (float)(2.0 * (y * z + w * x));
    out_m[7] = 0.0f;
    out_m[8] = (float)(2.0 * (x * z + w * y));
    out_m[9] = (float)(2.0 * (y * z - w * x));
    out_m[10] = (float)(1.0 - 2.0 * (x * x + y * y));
    out_m[11] = 0.0f;
    out_m[12] = p.position.x;
    out_m[13] = p.position.y;
    out_m[14] = p.position.z;
    out_m[15] = 1.0f;
}

void xrsc_pose_view_matrix(XrPosef p, float out_m[16])
{
    xrsc_pose_to_matrix(xrsc_pose_inverse(p), out_m);
}

void xrsc_fov_projection(XrFovf fov, float near_m, float far_m, float out_m[16])
{
    /* For a view-space point (x, y, z) with z < 0, w_clip = -z. x/(-z) = tan(angleLeft) must
     * give x_ndc = -1 and tan(angleRight) +1; y/(-z) = tan(angleUp) gives y_ndc = -1 (Vulkan
     * y down); z = -near gives depth 0 and z = -far depth 1. */
    double l = tan((double)fov.angleLeft), r = tan((double)fov.angleRight);
    double u = tan((double)fov.angleUp), d = tan((double)fov.angleDown);
    double n = near_m, f = far_m;
    memset(out_m, 0, 16 * sizeof(float));
    out_m[0] = (float)(2.0 / (r - l));
    out_m[8] = (float)((r + l) / (r - l));
    out_m[5] = (float)(-2.0 / (u - d));
    out_m[9] = (float)(-(u + d) / (u - d));
    out_m[10] = (float)(-f / (f - n));
    out_m[14] = (float)(-f * n / (f - n));
    out_m[11] = -1.0f;
}

void xrsc_mat4_mul(const float a[16], const float b[16], float out_m[16])
{
    for (int c = 0; c < 4; c++) {
        for (int r = 0; r < 4; r++) {
            double s = 0.0;
            for (int k = 0; k < 4; k++)
                s += (double)a[k * 4 + r] * b[c * 4 + k];
            out_m[c * 4 + r] = (float)s;
        }
    }
}

void xrsc_mat4_mul_vec4(const float m[16], const float v[4], float out_v[4])
{
    for (int r = 0; r < 4; r++) {
        double s = 0.0;
        for (int k = 0; k < 4; k++)
            s += (double)m[k * 4 + r] * v[k];
        out_v[r] = (float)s;
    }
}

void xrsc_headset_default(xrsc_headset *out)
{
    if (!out)
        return;
    memset(out, 0, sizeof(*out));
    out->ipd_m = M_DEFAULT_IPD_M;
    /* Left eye: wider towards the temple (left), narrower towards the nose; right mirrored. */
    out->fov[0].angleLeft = (float)-deg_to_rad(M_DEFAULT_FOV_OUTER_DEG);
    out->fov[0].angleRight = (float)deg_to_rad(M_DEFAULT_FOV_INNER_DEG);
    out->fov[0].angleUp = (float)deg_to_rad(M_DEFAULT_FOV_UP_DEG);
    out->fov[0].angleDown = (float)-deg_to_rad(M_DEFAULT_FOV_DOWN_DEG);
    out->fov[1].angleLeft = (float)-deg_to_rad(M_DEFAULT_FOV_INNER_DEG);
    out->fov[1].angleRight = (float)deg_to_rad(M_DEFAULT_FOV_OUTER_DEG);
    out->fov[1].angleUp = out->fov[0].angleUp;
    out->fov[1].angleDown = out->fov[0].angleDown;
    out->width_px = M_DEFAULT_WIDTH_PX;
    out->height_px = M_DEFAULT_HEIGHT_PX;
    out->refresh_hz = M_DEFAULT_REFRESH_HZ;
}

void xrsc_headset_eye_poses(const xrsc_headset *hs, XrPosef head, XrPosef out_eyes[2])
{
    float half = hs ? 0.5f * hs->ipd_m : 0.5f * M_DEFAULT_IPD_M;
    for (int eye = 0; eye < 2; eye++) {
        XrPosef offset = xrsc_pose_identity();
        offset.position.x = eye == 0 ? -half : half;
        out_eyes[eye] = xrsc_pose_mul(head, offset);
    }
}
