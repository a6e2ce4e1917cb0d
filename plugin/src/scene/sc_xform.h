// SPDX-License-Identifier: MIT
/**
 * @file sc_xform.h
 * @brief Internal: the few column-major 4x4 / quaternion helpers the scene module needs.
 *
 * Matrices are float[16], m[col * 4 + row], as glTF, cglm and GLSL. Quaternions are x, y, z, w.
 */
#pragma once

#include <math.h>
#include <string.h>

static inline void sc_mat4_identity(float m[16])
{
    memset(m, 0, 16 * sizeof(float));
    m[0] = m[5] = m[10] = m[15] = 1.0f;
}

/** out = a * b (out may not alias a or b). */
static inline void sc_mat4_mul(const float a[16], const float b[16], float out[16])
{
    for (int c = 0; c < 4; c++)
        for (int r = 0; r < 4; r++) {
            float s = 0.0f;
            for (int k = 0; k < 4; k++) s += a[k * 4 + r] * b[c * 4 + k];
            out[c * 4 + r] = s;
        }
}

/** Transforms a point (w = 1). */
static inline void sc_mat4_point(const float m[16], const float p[3], float out[3])
{
    for (int r = 0; r < 3; r++) out[r] = m[r] * p[0] + m[4 + r] * p[1] + m[8 + r] * p[2] + m[12 + r];
}

static inline void sc_quat_normalize(float q[4])
{
    float n = sqrtf(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    if (n > 0.0f && isfinite(n)) {
        for (int i = 0; i < 4; i++) q[i] /= n;
    } else {
        q[0] = q[1] = q[2] = 0.0f;
        q[3] = 1.0f;
    }
}

/** M = T * R * S (glTF node local transform). q need not be normalised. */
static inline void sc_mat4_from_trs(const float t[3], const float q_in[4], const float s[3],
                                    float m[16])
{
    float q[4] = {q_in[0], q_in[1], q_in[2], q_in[3]};
    sc_quat_normalize(q);
    float x = q[0], y = q[1], z = q[2], w = q[3];
    float r[9] = {
        1 - 2 * (y * y + z * z), 2 * (x * y + z * w),     2 * (x * z - y * w), /* column 0 */
        2 * (x * y - z * w),     1 - 2 * (x * x + z * z), 2 * (y * z + x * w), /* column 1 */
        2 * (x * z + y * w),     2 * (y * z - x * w),     1 - 2 * (x * x + y * y), /* column 2 */
    };
    for (int c = 0; c < 3; c++) {
        for (int k = 0; k < 3; k++) m[c * 4 + k] = r[c * 3 + k] * s[c];
        m[c * 4 + 3] = 0.0f;
    }
    m[12] = t[0];
    m[13] = t[1];
    m[14] = t[2];
    m[15] = 1.0f;
}

/** Quaternion of a pure rotation matrix given as three unit columns (Shepperd's method). */
static inline void sc_quat_from_columns(const float c0[3], const float c1[3], const float c2[3],
                                        float q[4])
{
    float m00 = c0[0], m10 = c0[1], m20 = c0[2];
    float m01 = c1[0], m11 = c1[1], m21 = c1[2];
    float m02 = c2[0], m12 = c2[1], m22 = c2[2];
    float tr = m00 + m11 + m22;
    if (tr > 0.0f) {
        float s = sqrtf(tr + 1.0f) * 2.0f;
        q[3] = 0.25f * s;
        q[0] = (m21 - m12) / s;
        q[1] = (m02 - m20) / s;
        q[2] = (m10 - m01) / s;
    } else if (m00 > m11 && m00 > m22) {
        float s = sqrtf(1.0f + m00 - m11 - m22) * 2.0f;
        q[3] = (m21 - m12) / s;
        q[0] = 0.25f * s;
        q[1] = (m01 + m10) / s;
        q[2] = (m02 + m20) / s;
    } else if (m11 > m22) {
        float s = sqrtf(1.0f + m11 - m00 - m22) * 2.0f;
        q[3] = (m02 - m20) / s;
        q[0] = (m01 + m10) / s;
        q[1] = 0.25f * s;
        q[2] = (m12 + m21) / s;
    } else {
        float s = sqrtf(1.0f + m22 - m00 - m11) * 2.0f;
        q[3] = (m10 - m01) / s;
        q[0] = (m02 + m20) / s;
        q[1] = (m12 + m21) / s;
        q[2] = 0.25f * s;
    }
    sc_quat_normalize(q);
}

/**
 * Splits an affine matrix into translation, rotation and scale (M = T R S); exact for
 * matrices built that way, an approximation for sheared ones. A negative determinant is
 * carried by a negative x scale.
 */
static inline void sc_mat4_decompose(const float m[16], float t[3], float q[4], float s[3])
{
    float c[3][3];
    for (int i = 0; i < 3; i++) {
        for (int k = 0; k < 3; k++) c[i][k] = m[i * 4 + k];
        s[i] = sqrtf(c[i][0] * c[i][0] + c[i][1] * c[i][1] + c[i][2] * c[i][2]);
    }
    float det = c[0][0] * (c[1][1] * c[2][2] - c[2][1] * c[1][2]) -
                c[1][0] * (c[0][1] * c[2][2] - c[2][1] * c[0][2]) +
                c[2][0] * (c[0][1] * c[1][2] - c[1][1] * c[0][2]);
    if (det < 0.0f) s[0] = -s[0];
    for (int i = 0; i < 3; i++)
        for (int k = 0; k < 3; k++) c[i][k] = s[i] != 0.0f ? c[i][k] / s[i] : (i == k);
    sc_quat_from_columns(c[0], c[1], c[2], q);
    t[0] = m[12];
    t[1] = m[13];
    t[2] = m[14];
}

/** Spherical linear interpolation with a hemisphere check; nlerp when nearly parallel. */
static inline void sc_quat_slerp(const float a[4], const float b_in[4], float t, float out[4])
{
    float b[4] = {b_in[0], b_in[1], b_in[2], b_in[3]};
    float d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
    if (d < 0.0f) {
        d = -d;
        for (int i = 0; i < 4; i++) b[i] = -b[i];
    }
    float wa, wb;
    if (d > 0.9995f) {
        wa = 1.0f - t;
        wb = t;
    } else {
        float theta = acosf(d), st = sinf(theta);
        wa = sinf((1.0f - t) * theta) / st;
        wb = sinf(t * theta) / st;
    }
    for (int i = 0; i < 4; i++) out[i] = wa * a[i] + wb * b[i];
    sc_quat_normalize(out);
}
