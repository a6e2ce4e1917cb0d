// SPDX-License-Identifier: MIT
/**
 * @file me_reproject.c
 * @brief Depth-based backward reprojection between two views and the reprojected squared
 *        difference behind the temporal (seed 000 Fig. 10) and stereo (seed 004 Fig. 2) metrics.
 */
#include "me_internal.h"

#include <math.h>

/* Near/far of the projection used for reprojection: only x/w, y/w and w = -z_eye are read, so
 * the planes do not affect the result; they only have to be a valid frustum. */
#define REPROJ_NEAR_M 0.01f
#define REPROJ_FAR_M 1000.0f
/* A source position this close (pixels) to a pixel centre reads that pixel alone, so a view
 * reprojected onto itself reads exactly its own pixels despite float rounding. */
#define CENTRE_SNAP_PX 1e-3

/* Matrix taking a point in `from`'s eye space to `to`'s clip space: P_to * V_to * M_from. */
static void eye_to_clip(const xrsc_metrics_camera *from, const xrsc_metrics_camera *to,
                        float out_m[16])
{
    float model[16], view[16], proj[16], vm[16];
    xrsc_pose_to_matrix(from->pose, model);
    xrsc_pose_view_matrix(to->pose, view);
    xrsc_fov_projection(to->fov, REPROJ_NEAR_M, REPROJ_FAR_M, proj);
    xrsc_mat4_mul(view, model, vm);
    xrsc_mat4_mul(proj, vm, out_m);
}

/* Tangents of a camera's fov angles (xrsc_shared.h's tan_fov), computed once per image. */
typedef struct tangents {
    double l, r, u, d;
} tangents;

static tangents fov_tangents(const xrsc_metrics_camera *cam)
{
    tangents t = {tan((double)cam->fov.angleLeft), tan((double)cam->fov.angleRight),
                  tan((double)cam->fov.angleUp), tan((double)cam->fov.angleDown)};
    return t;
}

/* Eye-space point seen at image position (x, y) at depth d (xs_camera.glsl's ray times d). */
static void eye_point(const xrsc_metrics_camera *cam, const tangents *t, double x_px, double y_px,
                      double depth_m, double out_p[3])
{
    double u = x_px / cam->width, v = y_px / cam->height;
    out_p[0] = depth_m * (t->l + (t->r - t->l) * u);
    out_p[1] = depth_m * (t->u + (t->d - t->u) * v);
    out_p[2] = -depth_m;
}

/* Clip space to image position: Vulkan NDC x right, y down, both -1..1 across the image. */
static bool clip_to_image(const float m[16], const double p[3], const xrsc_metrics_camera *to,
                          double *out_x, double *out_y, double *out_depth)
{
    float v[4] = {(float)p[0], (float)p[1], (float)p[2], 1.0f}, c[4];
    xrsc_mat4_mul_vec4(m, v, c);
    if (!(c[3] > 0.0f)) /* w_clip = -z_eye of `to`: not in front of the camera */
        return false;
    *out_x = ((double)c[0] / c[3] + 1.0) * 0.5 * to->width;
    *out_y = ((double)c[1] / c[3] + 1.0) * 0.5 * to->height;
    *out_depth = c[3];
    return true;
}

bool xrsc_metrics_reproject(const xrsc_metrics_camera *from, double x_px, double y_px,
                            double depth_m, const xrsc_metrics_camera *to, double *out_x_px,
                            double *out_y_px, double *out_depth_m)
{
    if (!from || !to || from->width == 0 || from->height == 0)
        return false;
    float m[16];
    eye_to_clip(from, to, m);
    double p[3];
    const tangents t = fov_tangents(from);
    eye_point(from, &t, x_px, y_px, depth_m, p);
    return clip_to_image(m, p, to, out_x_px, out_y_px, out_depth_m);
}

/* Tap columns/rows and weights of a bilinear read at continuous position pos (pixel centres at
 * k + 0.5), clamped to [0, size - 1]. Returns how many taps (1 or 2) carry weight. */
static int taps(double pos, uint32_t size, uint32_t out_i[2], double out_w[2])
{
    double f = pos - 0.5, base = floor(f), frac = f - base;
    if (frac < CENTRE_SNAP_PX || frac > 1.0 - CENTRE_SNAP_PX) {
        double k = frac < 0.5 ? base : base + 1.0;
        k = k < 0.0 ? 0.0 : (k > size - 1.0 ? size - 1.0 : k);
        out_i[0] = (uint32_t)k;
        out_w[0] = 1.0;
        return 1;
    }
    double k0 = base < 0.0 ? 0.0 : (base > size - 1.0 ? size - 1.0 : base);
    double k1 = base + 1.0 > size - 1.0 ? size - 1.0 : (base + 1.0 < 0.0 ? 0.0 : base + 1.0);
    out_i[0] = (uint32_t)k0;
    out_i[1] = (uint32_t)k1;
    out_w[0] = 1.0 - frac;
    out_w[1] = frac;
    return 2;
}

static xrsc_result check_view(const xrsc_metrics_view *v)
{
    if (!v)
        return XRSC_ERROR_INVALID_ARGUMENT;
    size_t n;
    xrsc_result res = me_check_image(v->rgba, v->camera.width, v->camera.height, 4, &n);
    if (res == XRSC_OK)
        res = me_check_image(v->depth_m, v->camera.width, v->camera.height, 1, &n);
    return res;
}

xrsc_result xrsc_metrics_reprojected_diff(const xrsc_metrics_view *target,
                                          const xrsc_metrics_view *source,
                                          const xrsc_metrics_options *options,
                                          xrsc_reproj_diff *out, uint8_t *out_status,
                                          float *out_sq_diff)
{
    if (!out)
        return XRSC_ERROR_INVALID_ARGUMENT;
    xrsc_result res = check_view(target);
    if (res == XRSC_OK)
        res = check_view(source);
    if (res != XRSC_OK)
        return res;
    const xrsc_metrics_options o = me_options_fill(options);
    const xrsc_metrics_camera *tc = &target->camera, *sc = &source->camera;
    const uint32_t tw = tc->width, th = tc->height, sw = sc->width, sh = sc->height;

    float m[16];
    eye_to_clip(tc, sc, m);
    const tangents tt = fov_tangents(tc);
    double sum = 0.0;
    uint64_t valid = 0, foreground = 0;
    for (uint32_t y = 0; y < th; y++) {
        for (uint32_t x = 0; x < tw; x++) {
            const size_t tp = (size_t)y * tw + x;
            uint8_t status = XRSC_REPROJ_BACKGROUND;
            float sq = 0.0f;
            const double d = target->depth_m[tp];
            if (d > 0.0) {
                foreground++;
                status = XRSC_REPROJ_OUTSIDE;
                double p[3], sx, sy, sd;
                eye_point(tc, &tt, x + 0.5, y + 0.5, d, p);
                if (clip_to_image(m, p, sc, &sx, &sy, &sd) && sx >= 0.0 && sx <= sw && sy >= 0.0 &&
                    sy <= sh) {
                    uint32_t ix[2], iy[2];
                    double wx[2], wy[2];
                    int nx = taps(sx, sw, ix, wx), ny = taps(sy, sh, iy, wy);
                    double col[3] = {0.0, 0.0, 0.0};
                    status = XRSC_REPROJ_VALID;
                    for (int j = 0; j < ny && status == XRSC_REPROJ_VALID; j++) {
                        for (int i = 0; i < nx; i++) {
                            const size_t sp = (size_t)iy[j] * sw + ix[i];
                            const double sdepth = source->depth_m[sp];
                            /* Depth test of every tap: background or another surface (a
                             * disocclusion in the target) invalidates the pixel. */
                            if (!(sdepth > 0.0) || fabs(sdepth - sd) > o.depth_tolerance * sd) {
                                status = XRSC_REPROJ_DEPTH_MISMATCH;
                                break;
                            }
                            for (int c = 0; c < 3; c++)
                                col[c] += wx[i] * wy[j] * source->rgba[sp * 4 + c];
                        }
                    }
                    if (status == XRSC_REPROJ_VALID) {
                        double s = 0.0;
                        for (int c = 0; c < 3; c++) {
                            double diff = target->rgba[tp * 4 + c] - col[c];
                            s += diff * diff;
                        }
                        sum += s;
                        sq = (float)(s / 3.0);
                        valid++;
                    }
                }
            }
            if (out_status)
                out_status[tp] = status;
            if (out_sq_diff)
                out_sq_diff[tp] = sq;
        }
    }
    out->mean_sq_diff = valid ? sum / (3.0 * (double)valid) : 0.0;
    out->valid_count = valid;
    out->foreground_count = foreground;
    return XRSC_OK;
}

xrsc_result xrsc_metrics_temporal_diff(const xrsc_metrics_view *current,
                                       const xrsc_metrics_view *previous,
                                       const xrsc_metrics_options *options, xrsc_reproj_diff *out,
                                       uint8_t *out_status, float *out_sq_diff)
{
    return xrsc_metrics_reprojected_diff(current, previous, options, out, out_status, out_sq_diff);
}

xrsc_result xrsc_metrics_stereo_discrepancy(const xrsc_metrics_view *eye,
                                            const xrsc_metrics_view *other_eye,
                                            const xrsc_metrics_options *options,
                                            xrsc_reproj_diff *out, uint8_t *out_status,
                                            float *out_sq_diff)
{
    return xrsc_metrics_reprojected_diff(eye, other_eye, options, out, out_status, out_sq_diff);
}
