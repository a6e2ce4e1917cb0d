// SPDX-License-Identifier: MIT
/**
 * @file test_math.c
 * @brief Unit tests of xrsc_math.h: quaternions, poses, slerp, projection, headset eye poses.
 */
#include "testing.h"
#include "xrsc/xrsc_math.h"

#include <cglm/cglm.h>
#include <math.h>
#include <string.h>

#define PI_D 3.14159265358979323846
#define DEG (PI_D / 180.0)
#define EPS 1e-5

static const XrVector3f AX = {1, 0, 0}, AY = {0, 1, 0}, AZ = {0, 0, 1};

static XrQuaternionf quat(float x, float y, float z, float w)
{
    XrQuaternionf q = {x, y, z, w};
    return q;
}

static XrVector3f vec(float x, float y, float z)
{
    XrVector3f v = {x, y, z};
    return v;
}

/** True when q and r are the same rotation (q == r or q == -r). */
static double quat_dist(XrQuaternionf q, XrQuaternionf r)
{
    double d1 = fabs(q.x - r.x) + fabs(q.y - r.y) + fabs(q.z - r.z) + fabs(q.w - r.w);
    double d2 = fabs(q.x + r.x) + fabs(q.y + r.y) + fabs(q.z + r.z) + fabs(q.w + r.w);
    return d1 < d2 ? d1 : d2;
}

static void check_vec(XrVector3f a, XrVector3f b, double tol)
{
    CHECK_NEAR(a.x, b.x, tol);
    CHECK_NEAR(a.y, b.y, tol);
    CHECK_NEAR(a.z, b.z, tol);
}

static void test_rotate_axes(void)
{
    /* +90 deg about +Y takes -Z (forward) to -X (left): right-handed rotation. */
    XrQuaternionf q = xrsc_quat_from_axis_angle(AY, (float)(90 * DEG));
    check_vec(xrsc_quat_rotate(q, vec(0, 0, -1)), vec(-1, 0, 0), EPS);
    /* +90 deg about +X takes -Z to +Y (looking up). */
    q = xrsc_quat_from_axis_angle(AX, (float)(90 * DEG));
    check_vec(xrsc_quat_rotate(q, vec(0, 0, -1)), vec(0, 1, 0), EPS);
    /* +90 deg about +Z takes +X to +Y. */
    q = xrsc_quat_from_axis_angle(AZ, (float)(90 * DEG));
    check_vec(xrsc_quat_rotate(q, vec(1, 0, 0)), vec(0, 1, 0), EPS);
    /* Against Rodrigues' formula for an arbitrary axis. */
    double n = sqrt(1.0 + 4.0 + 9.0);
    XrVector3f k = vec((float)(1 / n), (float)(2 / n), (float)(3 / n));
    double th = 1.1;
    XrVector3f v = vec(0.3f, -0.7f, 2.0f);
    double kv = k.x * v.x + k.y * v.y + k.z * v.z;
    double cx = k.y * v.z - k.z * v.y, cy = k.z * v.x - k.x * v.z, cz = k.x * v.y - k.y * v.x;
    XrVector3f expect = vec((float)(v.x * cos(th) + cx * sin(th) + k.x * kv * (1 - cos(th))),
                            (float)(v.y * cos(th) + cy * sin(th) + k.y * kv * (1 - cos(th))),
                            (float)(v.z * cos(th) + cz * sin(th) + k.z * kv * (1 - cos(th))));
    check_vec(xrsc_quat_rotate(xrsc_quat_from_axis_angle(k, (float)th), v), expect, EPS);
}

static void test_mul_conjugate_normalize(void)
{
    XrQuaternionf a = xrsc_quat_from_axis_angle(AY, 0.7f);
    XrQuaternionf b = xrsc_quat_from_axis_angle(AX, -0.4f);
    XrVector3f v = vec(0.2f, 0.5f, -1.0f);
    /* a*b applies b first, then a. */
    check_vec(xrsc_quat_rotate(xrsc_quat_mul(a, b), v), xrsc_quat_rotate(a, xrsc_quat_rotate(b, v)),
              EPS);
    /* Same-axis products add angles. */
    XrQuaternionf c = xrsc_quat_mul(a, xrsc_quat_from_axis_angle(AY, 0.3f));
    CHECK(quat_dist(c, xrsc_quat_from_axis_angle(AY, 1.0f)) < EPS);
    /* q * conj(q) = identity. */
    XrQuaternionf id = xrsc_quat_mul(xrsc_quat_mul(a, b), xrsc_quat_conjugate(xrsc_quat_mul(a, b)));
    CHECK(quat_dist(id, quat(0, 0, 0, 1)) < EPS);
    /* normalize */
    XrQuaternionf n = xrsc_quat_normalize(quat(0, 0, 3, 4));
    CHECK_NEAR(n.z, 0.6, 1e-7);
    CHECK_NEAR(n.w, 0.8, 1e-7);
    n = xrsc_quat_normalize(quat(0, 0, 0, 0));
    CHECK(quat_dist(n, quat(0, 0, 0, 1)) == 0.0);
}

static void test_angle_between(void)
{
    XrQuaternionf a = xrsc_quat_from_axis_angle(AY, 0.2f);
    XrQuaternionf b = xrsc_quat_from_axis_angle(AY, 1.3f);
    CHECK_NEAR(xrsc_quat_angle_between(a, b), 1.1, 1e-5);
    /* -b is the same rotation: the angle must not change. */
    XrQuaternionf nb = quat(-b.x, -b.y, -b.z, -b.w);
    CHECK_NEAR(xrsc_quat_angle_between(a, nb), 1.1, 1e-5);
    CHECK_NEAR(xrsc_quat_angle_between(a, a), 0.0, 1e-6);
    XrQuaternionf c = xrsc_quat_from_axis_angle(AX, (float)PI_D);
    CHECK_NEAR(xrsc_quat_angle_between(quat(0, 0, 0, 1), c), PI_D, 1e-5);
}

static void test_slerp(void)
{
    XrQuaternionf a = xrsc_quat_from_axis_angle(AY, 0.0f);
    XrQuaternionf b = xrsc_quat_from_axis_angle(AY, (float)(90 * DEG));
    CHECK(quat_dist(xrsc_quat_slerp(a, b, 0.0f), a) < EPS);
    CHECK(quat_dist(xrsc_quat_slerp(a, b, 1.0f), b) < EPS);
    for (int i = 1; i < 10; i++) {
        float t = i / 10.0f;
        XrQuaternionf q = xrsc_quat_slerp(a, b, t);
        /* Constant angular velocity along the arc. */
        CHECK_NEAR(xrsc_quat_angle_between(a, q), t * 90 * DEG, 1e-5);
        CHECK(quat_dist(q, xrsc_quat_from_axis_angle(AY, (float)(t * 90 * DEG))) < EPS);
    }
    /* Hemisphere check: b flipped in sign is the same rotation, so slerp must take the same
     * 45-degree midpoint, not the long way round (which would be 135 deg). */
    XrQuaternionf nb = quat(-b.x, -b.y, -b.z, -b.w);
    XrQuaternionf mid = xrsc_quat_slerp(a, nb, 0.5f);
    CHECK(quat_dist(mid, xrsc_quat_from_axis_angle(AY, (float)(45 * DEG))) < EPS);
    CHECK_NEAR(xrsc_quat_angle_between(a, mid), 45 * DEG, 1e-5);
    /* A 170-degree pair: each quarter step is 42.5 degrees. */
    XrQuaternionf c = xrsc_quat_from_axis_angle(AX, (float)(170 * DEG));
    CHECK_NEAR(xrsc_quat_angle_between(a, xrsc_quat_slerp(a, c, 0.25f)), 42.5 * DEG, 1e-4);
    /* Nearly equal quaternions (the nlerp branch) stay unit and in between. */
    XrQuaternionf d = xrsc_quat_from_axis_angle(AZ, 1e-4f);
    XrQuaternionf m = xrsc_quat_slerp(a, d, 0.5f);
    double len = sqrt(m.x * m.x + m.y * m.y + m.z * m.z + m.w * m.w);
    CHECK_NEAR(len, 1.0, 1e-6);
    CHECK_NEAR(xrsc_quat_angle_between(a, m), 0.5e-4, 1e-6);
}

static XrPosef pose(XrQuaternionf q, XrVector3f p)
{
    XrPosef r = {q, p};
    return r;
}

static void test_pose_ops(void)
{
    XrPosef a = pose(xrsc_quat_from_axis_angle(AY, 0.5f), vec(1, 2, 3));
    XrPosef b = pose(xrsc_quat_from_axis_angle(AX, -0.3f), vec(-0.5f, 0.25f, 4));
    XrVector3f v = vec(0.1f, -0.2f, 0.3f);
    /* (a*b)(v) = a(b(v)) */
    check_vec(xrsc_pose_transform_point(xrsc_pose_mul(a, b), v),
              xrsc_pose_transform_point(a, xrsc_pose_transform_point(b, v)), EPS);
    /* a * inverse(a) = identity, both ways. */
    XrPosef i1 = xrsc_pose_mul(a, xrsc_pose_inverse(a));
    XrPosef i2 = xrsc_pose_mul(xrsc_pose_inverse(a), a);
    CHECK(quat_dist(i1.orientation, quat(0, 0, 0, 1)) < EPS);
    check_vec(i1.position, vec(0, 0, 0), EPS);
    CHECK(quat_dist(i2.orientation, quat(0, 0, 0, 1)) < EPS);
    check_vec(i2.position, vec(0, 0, 0), EPS);
    /* transform of a point, by hand: rotate then translate. */
    XrPosef c = pose(xrsc_quat_from_axis_angle(AY, (float)(90 * DEG)), vec(1, 0, 0));
    check_vec(xrsc_pose_transform_point(c, vec(0, 0, -1)), vec(0, 0, 0), EPS);
    /* interpolate: midpoint position and 45-degree orientation. */
    XrPosef p0 = pose(quat(0, 0, 0, 1), vec(0, 0, 0));
    XrPosef p1 = pose(xrsc_quat_from_axis_angle(AY, (float)(90 * DEG)), vec(2, -4, 6));
    XrPosef m = xrsc_pose_interpolate(p0, p1, 0.5f);
    check_vec(m.position, vec(1, -2, 3), EPS);
    CHECK_NEAR(xrsc_quat_angle_between(p0.orientation, m.orientation), 45 * DEG, 1e-5);
    /* identity */
    XrPosef id = xrsc_pose_identity();
    CHECK(id.orientation.w == 1.0f && id.orientation.x == 0.0f && id.position.z == 0.0f);
}

static void test_matrices(void)
{
    XrPosef a = pose(xrsc_quat_normalize(quat(0.1f, -0.4f, 0.2f, 0.9f)), vec(1, -2, 0.5f));
    float m[16], v[16], mv[16];
    xrsc_pose_to_matrix(a, m);
    xrsc_pose_view_matrix(a, v);
    XrVector3f p = vec(0.3f, 0.7f, -1.1f);
    float p4[4] = {p.x, p.y, p.z, 1}, out[4];
    xrsc_mat4_mul_vec4(m, p4, out);
    check_vec(vec(out[0], out[1], out[2]), xrsc_pose_transform_point(a, p), EPS);
    CHECK_NEAR(out[3], 1.0, 1e-7);
    /* Column-major: translation in m[12..14]. */
    CHECK_NEAR(m[12], 1.0, 0);
    CHECK_NEAR(m[13], -2.0, 0);
    /* view * model = identity */
    xrsc_mat4_mul(v, m, mv);
    for (int i = 0; i < 16; i++)
        CHECK_NEAR(mv[i], (i % 5 == 0) ? 1.0 : 0.0, 1e-5);
    /* mat4_mul against cglm (an independent implementation). */
    mat4 ga, gb, gc;
    memcpy(ga, m, sizeof(ga));
    memcpy(gb, v, sizeof(gb));
    ga[1][3] = 0.25f; /* make it non-affine */
    float am[16], bm[16], cm[16];
    memcpy(am, ga, sizeof(am));
    memcpy(bm, gb, sizeof(bm));
    glm_mat4_mul(ga, gb, gc);
    xrsc_mat4_mul(am, bm, cm);
    for (int c = 0; c < 4; c++)
        for (int r = 0; r < 4; r++)
            CHECK_NEAR(cm[c * 4 + r], gc[c][r], 1e-5);
}

static void project(const float m[16], double x, double y, double z, double out_ndc[3])
{
    float v[4] = {(float)x, (float)y, (float)z, 1}, c[4];
    xrsc_mat4_mul_vec4(m, v, c);
    out_ndc[0] = c[0] / c[3];
    out_ndc[1] = c[1] / c[3];
    out_ndc[2] = c[2] / c[3];
}

static void test_projection(void)
{
    XrFovf fov = {(float)(-52 * DEG), (float)(43 * DEG), (float)(47 * DEG), (float)(-53 * DEG)};
    const float n = 0.05f, f = 100.0f;
    float m[16];
    xrsc_fov_projection(fov, n, f, m);
    double ndc[3];
    const double d = 3.0; /* any depth in front of the eye */
    project(m, tan(fov.angleLeft) * d, 0, -d, ndc);
    CHECK_NEAR(ndc[0], -1.0, 1e-5);
    project(m, tan(fov.angleRight) * d, 0, -d, ndc);
    CHECK_NEAR(ndc[0], 1.0, 1e-5);
    /* y down: the top edge is -1, the bottom edge +1. */
    project(m, 0, tan(fov.angleUp) * d, -d, ndc);
    CHECK_NEAR(ndc[1], -1.0, 1e-5);
    project(m, 0, tan(fov.angleDown) * d, -d, ndc);
    CHECK_NEAR(ndc[1], 1.0, 1e-5);
    /* depth 0 at near, 1 at far, increasing in between. */
    project(m, 0, 0, -n, ndc);
    CHECK_NEAR(ndc[2], 0.0, 1e-6);
    project(m, 0, 0, -f, ndc);
    CHECK_NEAR(ndc[2], 1.0, 1e-5);
    double prev = -1;
    for (double z = n; z < f; z *= 2) {
        project(m, 0.1, 0.1, -z, ndc);
        CHECK(ndc[2] > prev);
        prev = ndc[2];
    }
    /* Independent computation: cglm's OpenGL frustum (y up, depth -1..1) on the near plane's
     * rectangle, then the fixed Vulkan correction (flip y, depth z' = (z + w) / 2). */
    mat4 gl;
    glm_frustum_rh_no((float)(tan(fov.angleLeft) * n), (float)(tan(fov.angleRight) * n),
                      (float)(tan(fov.angleDown) * n), (float)(tan(fov.angleUp) * n), n, f, gl);
    for (int c = 0; c < 4; c++) {
        double vk[4] = {gl[c][0], -gl[c][1], 0.5 * (gl[c][2] + gl[c][3]), gl[c][3]};
        for (int r = 0; r < 4; r++)
            CHECK_NEAR(m[c * 4 + r], vk[r], 1e-4 * (1 + fabs(vk[r])));
    }
}

static void test_headset(void)
{
    xrsc_headset hs;
    xrsc_headset_default(&hs);
    CHECK_NEAR(hs.ipd_m, 0.063, 1e-7);
    CHECK_NEAR(hs.refresh_hz, 90, 0);
    CHECK_EQ_INT(hs.width_px, 2064);
    CHECK_EQ_INT(hs.height_px, 2208);
    CHECK_NEAR(hs.fov[0].angleLeft, -52 * DEG, 1e-6);
    CHECK_NEAR(hs.fov[0].angleRight, 43 * DEG, 1e-6);
    CHECK_NEAR(hs.fov[0].angleUp, 47 * DEG, 1e-6);
    CHECK_NEAR(hs.fov[0].angleDown, -53 * DEG, 1e-6);
    /* right eye mirrored */
    CHECK_NEAR(hs.fov[1].angleLeft, -hs.fov[0].angleRight, 1e-7);
    CHECK_NEAR(hs.fov[1].angleRight, -hs.fov[0].angleLeft, 1e-7);
    CHECK_NEAR(hs.fov[1].angleUp, hs.fov[0].angleUp, 0);

    /* Head turned 90 deg left (about +Y): its +X axis points to world -Z. */
    XrPosef head = pose(xrsc_quat_from_axis_angle(AY, (float)(90 * DEG)), vec(1, 1.6f, 2));
    XrPosef eyes[2];
    xrsc_headset_eye_poses(&hs, head, eyes);
    check_vec(eyes[0].position, vec(1, 1.6f, 2 + 0.0315f), 1e-6);
    check_vec(eyes[1].position, vec(1, 1.6f, 2 - 0.0315f), 1e-6);
    for (int e = 0; e < 2; e++)
        CHECK(quat_dist(eyes[e].orientation, head.orientation) < 1e-7);
    double dx = eyes[1].position.x - eyes[0].position.x,
           dy = eyes[1].position.y - eyes[0].position.y,
           dz = eyes[1].position.z - eyes[0].position.z;
    CHECK_NEAR(sqrt(dx * dx + dy * dy + dz * dz), hs.ipd_m, 1e-6);
    /* Another IPD. */
    hs.ipd_m = 0.07f;
    xrsc_headset_eye_poses(&hs, xrsc_pose_identity(), eyes);
    CHECK_NEAR(eyes[0].position.x, -0.035, 1e-7);
    CHECK_NEAR(eyes[1].position.x, 0.035, 1e-7);
}

int main(void)
{
    RUN(test_rotate_axes);
    RUN(test_mul_conjugate_normalize);
    RUN(test_angle_between);
    RUN(test_slerp);
    RUN(test_pose_ops);
    RUN(test_matrices);
    RUN(test_projection);
    RUN(test_headset);
    return t_finish();
}
