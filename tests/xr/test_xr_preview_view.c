// SPDX-License-Identifier: MIT
/**
 * @file test_xr_preview_view.c
 * @brief The preview window's CPU parts without a window: depth-layer texels decoded to
 *        metres (normal, reversed and 16-bit depth, background), and the stereo difference
 *        (right eye reprojected into the left by depth, background by direction) on eyes
 *        rendered here analytically: near zero with the true depth, large without
 *        compensation or with a wrong depth.
 */
#include "hsrt.h"
#include "hsrt_preview_view.h"
#include "testing.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define EYE 96
#define PLANE_M 2.0
#define NEAR_M 0.05f
#define FAR_M 1000.0f

/* The plugin's encoding (xr_session.c depth_to_ndc): d = f / (f - n) (1 - n / z), 1 where
 * nothing was hit. */
static float encode(double z)
{
    return z > 0.0 ? (float)(FAR_M / (FAR_M - NEAR_M) * (1.0 - NEAR_M / z)) : 1.0f;
}

static void depth_decoding(void)
{
    const double z[4] = {0.5, 2.0, 100.0, 0.0};
    float tex[4];
    for (int i = 0; i < 4; i++)
        tex[i] = encode(z[i]);
    XrCompositionLayerDepthInfoKHR info = {.type = XR_TYPE_COMPOSITION_LAYER_DEPTH_INFO_KHR,
                                           .minDepth = 0.0f,
                                           .maxDepth = 1.0f,
                                           .nearZ = NEAR_M,
                                           .farZ = FAR_M};
    float *m = hsrt_depth_to_metres(VK_FORMAT_D32_SFLOAT, tex, 4, 1, &info);
    CHECK(m != NULL);
    for (int i = 0; m && i < 3; i++)
        CHECK_MSG(fabs(m[i] - z[i]) < 2e-4 * z[i] * z[i] / NEAR_M + 1e-6, "z %g decoded %g", z[i],
                  (double)m[i]);
    CHECK(m && m[3] == 0.0f); /* background */
    free(m);
    /* reversed depth: minDepth at the far plane (nearZ > farZ), 0 where nothing was hit */
    info.nearZ = FAR_M;
    info.farZ = NEAR_M;
    for (int i = 0; i < 4; i++)
        tex[i] = 1.0f - encode(z[i]);
    m = hsrt_depth_to_metres(VK_FORMAT_D32_SFLOAT, tex, 4, 1, &info);
    CHECK(m != NULL);
    for (int i = 0; m && i < 3; i++)
        CHECK_MSG(fabs(m[i] - z[i]) < 2e-4 * z[i] * z[i] / NEAR_M + 1e-6, "reversed z %g -> %g",
                  z[i], (double)m[i]);
    CHECK(m && m[3] == 0.0f);
    free(m);
    /* 16-bit: a coarse but monotone decode; 65535 is background */
    info.nearZ = NEAR_M;
    info.farZ = FAR_M;
    uint16_t t16[2] = {(uint16_t)lrint(encode(0.5) * 65535.0), 65535};
    m = hsrt_depth_to_metres(VK_FORMAT_D16_UNORM, t16, 2, 1, &info);
    CHECK(m && fabs(m[0] - 0.5) < 0.01 && m[1] == 0.0f);
    free(m);
    CHECK(hsrt_depth_to_metres(VK_FORMAT_R8G8B8A8_UNORM, tex, 4, 1, &info) == NULL);
    CHECK(hsrt_depth_to_metres(VK_FORMAT_D32_SFLOAT, tex, 4, 1, NULL) == NULL);
}

/* A smooth colour of a point of the plane (x, y) or of a direction: what both eyes agree on. */
static void colour_at(double x, double y, float out[4])
{
    out[0] = (float)(0.5 + 0.4 * sin(3.0 * x + 0.5));
    out[1] = (float)(0.5 + 0.4 * sin(2.0 * y - 1.0));
    out[2] = (float)(0.5 + 0.3 * sin(2.0 * (x + y)));
    out[3] = 1.0f;
}

/**
 * Renders one eye looking down -Z from (x_m, 0, 0) with the headset's FOV: the plane z = -2 m
 * (depth 2, coloured by position) or, with background, nothing (depth 0, coloured by
 * direction). depth_scale multiplies the depth written (1: true).
 */
static void render_eye(hsrt_preview_frame *f, int e, double x_m, bool background,
                       double depth_scale)
{
    xrsc_headset hs;
    xrsc_headset_default(&hs);
    f->fov[e] = hs.fov[e];
    f->pose[e] = xrsc_pose_identity();
    f->pose[e].position.x = (float)x_m;
    hsrt_eye_image *img = &f->eyes[e];
    img->w = img->h = EYE;
    img->rgba = malloc((size_t)EYE * EYE * 4 * sizeof(float));
    f->depth_m[e] = malloc((size_t)EYE * EYE * sizeof(float));
    double tl = tan(hs.fov[e].angleLeft), tr = tan(hs.fov[e].angleRight);
    double tu = tan(hs.fov[e].angleUp), td = tan(hs.fov[e].angleDown);
    for (int y = 0; y < EYE; y++) {
        for (int x = 0; x < EYE; x++) {
            double dx = tl + (tr - tl) * (x + 0.5) / EYE, dy = tu + (td - tu) * (y + 0.5) / EYE;
            size_t i = (size_t)y * EYE + x;
            if (background)
                colour_at(dx, -dy, img->rgba + i * 4);
            else
                colour_at(x_m + PLANE_M * dx, -PLANE_M * dy, img->rgba + i * 4);
            f->depth_m[e][i] = background ? 0.0f : (float)(PLANE_M * depth_scale);
        }
    }
}

/* Mean RMS of |left - right| over all pixels (no compensation). */
static double raw_diff(const hsrt_preview_frame *f)
{
    double s = 0.0;
    for (size_t i = 0; i < (size_t)EYE * EYE; i++) {
        double q = 0.0;
        for (int c = 0; c < 3; c++) {
            double d = (double)f->eyes[0].rgba[i * 4 + c] - f->eyes[1].rgba[i * 4 + c];
            q += d * d;
        }
        s += sqrt(q / 3.0);
    }
    return s / (EYE * EYE);
}

static void stereo_case(bool background, double depth_scale, double *out_mean, double *out_valid,
                        double *out_raw)
{
    hsrt_preview_frame f = {.frame = 1};
    const double half_ipd = 0.0315;
    render_eye(&f, 0, -half_ipd, background, depth_scale);
    render_eye(&f, 1, half_ipd, background, depth_scale);
    float *rms = malloc((size_t)EYE * EYE * sizeof(float));
    CHECK(hsrt_view_stereo_diff(&f, rms, out_mean, out_valid));
    *out_raw = raw_diff(&f);
    free(rms);
    hsrt_preview_frame_free(&f);
}

static void stereo_difference(void)
{
    double mean, valid, raw;
    stereo_case(false, 1.0, &mean, &valid, &raw);
    printf("  plane at 2 m: compensated %.5f (%.0f%% compared), raw %.4f\n", mean, valid * 100,
           raw);
    CHECK(valid > 0.7);
    CHECK(raw > 0.05);
    CHECK_MSG(mean < 0.05 * raw, "compensated %.5f vs raw %.5f", mean, raw);
    double wrong_mean, wrong_valid;
    stereo_case(false, 1.5, &wrong_mean, &wrong_valid, &raw);
    printf("  plane, depth x1.5: compensated %.5f (%.0f%% compared)\n", wrong_mean,
           wrong_valid * 100);
    CHECK_MSG(wrong_mean > 5.0 * mean, "a wrong depth %.5f is not worse than the true %.5f",
              wrong_mean, mean);
    stereo_case(true, 1.0, &mean, &valid, &raw);
    printf("  background (by direction): compensated %.5f (%.0f%% compared), raw %.4f\n", mean,
           valid * 100, raw);
    CHECK(valid > 0.7);
    CHECK(raw > 0.05);
    CHECK_MSG(mean < 0.05 * raw, "compensated %.5f vs raw %.5f", mean, raw);
    /* without depth there is nothing to compensate with */
    hsrt_preview_frame f = {.frame = 1};
    render_eye(&f, 0, -0.03, false, 1.0);
    render_eye(&f, 1, 0.03, false, 1.0);
    free(f.depth_m[1]);
    f.depth_m[1] = NULL;
    float *rms = malloc((size_t)EYE * EYE * sizeof(float));
    CHECK(!hsrt_view_stereo_diff(&f, rms, &mean, &valid));
    free(rms);
    hsrt_preview_frame_free(&f);
}

int main(void)
{
    RUN(depth_decoding);
    RUN(stereo_difference);
    return t_finish();
}
