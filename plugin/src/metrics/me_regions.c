// SPDX-License-Identifier: MIT
/**
 * @file me_regions.c
 * @brief Region masks from first-hit ids and depth (edges, moving object, uncovered, specular,
 *        one eye only), error over a region, and recovery frames after an event (issue 9: the
 *        places seed 000 names where caches fail, Figs. 7, 8, 12, 18, 19).
 */
#include "me_internal.h"

#include <math.h>
#include <stddef.h>

#define MISS_ID UINT32_MAX
/* Landing points this close (pixels) to a pixel centre test that pixel alone (seen_in). */
#define CENTRE_SNAP_PX 1e-3

const char *xrsc_region_name(xrsc_region region)
{
    static const char *const names[XRSC_REGION_COUNT] = {"all",       "edge",     "object",
                                                         "uncovered", "specular", "one_eye"};
    return (unsigned)region < XRSC_REGION_COUNT ? names[region] : "?";
}

static bool camera_matches(const xrsc_metrics_camera *c, uint32_t w, uint32_t h)
{
    return c->width == w && c->height == h;
}

static xrsc_result check_input(const xrsc_region_input *in, size_t *out_n)
{
    if (!in || !in->hit_id || !camera_matches(&in->camera, in->width, in->height))
        return XRSC_ERROR_INVALID_ARGUMENT;
    xrsc_result res = me_check_image(in->depth_m, in->width, in->height, 1, out_n);
    if (res == XRSC_OK && in->prev_hit_id) {
        if (!camera_matches(&in->prev_camera, in->width, in->height))
            return XRSC_ERROR_INVALID_ARGUMENT;
        res = me_check_image(in->prev_depth_m, in->width, in->height, 1, out_n);
    }
    if (res == XRSC_OK && in->other_depth_m) {
        if (!camera_matches(&in->other_camera, in->width, in->height))
            return XRSC_ERROR_INVALID_ARGUMENT;
        res = me_check_image(in->other_depth_m, in->width, in->height, 1, out_n);
    }
    return res;
}

static bool is_foreground(const uint32_t *hit_id, const float *depth_m, size_t p)
{
    return hit_id[p * 4] != MISS_ID && depth_m[p] > 0.0f;
}

/* Edge (3x3): another instance (a miss counts as one) or a depth jump beyond the ratio. */
static bool is_edge(const xrsc_region_input *in, uint32_t x, uint32_t y)
{
    const uint32_t w = in->width, h = in->height;
    const size_t p = (size_t)y * w + x;
    const uint32_t id = in->hit_id[p * 4];
    const double d = in->depth_m[p] > 0.0f ? in->depth_m[p] : 0.0;
    for (int dy = -1; dy <= 1; dy++)
        for (int dx = -1; dx <= 1; dx++) {
            int nx = (int)x + dx, ny = (int)y + dy;
            if (nx < 0 || ny < 0 || nx >= (int)w || ny >= (int)h)
                continue;
            const size_t q = (size_t)ny * w + (size_t)nx;
            const double dq = in->depth_m[q] > 0.0f ? in->depth_m[q] : 0.0;
            if (in->hit_id[q * 4] != id)
                return true;
            if (fabs(dq - d) > XRSC_REGION_EDGE_DEPTH_RATIO * fmax(d, dq))
                return true;
        }
    return false;
}

/*
 * Is the surface seen at pixel (x, y) of `in` also seen in view `to`? Reprojected by depth
 * (static scene), it must land inside to's image and one of the 2x2 pixels nearest to the
 * landing point must show it: depth within the tolerance and, when to_hit_id is given, the same
 * instance. Any of the (up to) four pixels whose centres lie less than a pixel away on both axes
 * rather than the nearest: the landing point is sub-pixel, so at a silhouette the nearest pixel
 * may lie just across it without anything being disoccluded. A landing point on a centre (within
 * CENTRE_SNAP_PX) has that pixel alone, so an unmoved view tests each pixel against itself.
 */
static bool seen_in(const xrsc_region_input *in, uint32_t x, uint32_t y,
                    const xrsc_metrics_camera *to, const float *to_depth, const uint32_t *to_hit_id,
                    double tolerance)
{
    const size_t p = (size_t)y * in->width + x;
    double tx, ty, td;
    if (!xrsc_metrics_reproject(&in->camera, x + 0.5, y + 0.5, in->depth_m[p], to, &tx, &ty, &td))
        return false;
    if (!(tx >= 0.0 && ty >= 0.0 && tx <= to->width && ty <= to->height))
        return false;
    const int x0 = (int)floor(tx - 0.5), y0 = (int)floor(ty - 0.5);
    for (int j = 0; j <= 1; j++)
        for (int i = 0; i <= 1; i++) {
            int sx = x0 + i, sy = y0 + j;
            if (sx < 0 || sy < 0 || sx >= (int)to->width || sy >= (int)to->height ||
                fabs(sx + 0.5 - tx) >= 1.0 - CENTRE_SNAP_PX ||
                fabs(sy + 0.5 - ty) >= 1.0 - CENTRE_SNAP_PX)
                continue;
            const size_t q = (size_t)sy * to->width + (size_t)sx;
            const double dq = to_depth[q];
            if (!(dq > 0.0) || fabs(dq - td) > tolerance * td)
                continue;
            if (to_hit_id && to_hit_id[q * 4] != in->hit_id[p * 4])
                continue;
            return true;
        }
    return false;
}

static uint8_t instance_bits(const xrsc_region_input *in, uint32_t id)
{
    if (!in->instance_flags || id >= in->instance_count)
        return 0;
    const uint8_t f = in->instance_flags[id];
    return (
        uint8_t)(((f & XRSC_INSTANCE_FLAG_OBJECT) ? XRSC_REGION_BIT(XRSC_REGION_OBJECT) : 0u) |
                 ((f & XRSC_INSTANCE_FLAG_SPECULAR) ? XRSC_REGION_BIT(XRSC_REGION_SPECULAR) : 0u));
}

xrsc_result xrsc_metrics_regions(const xrsc_region_input *in, const xrsc_metrics_options *options,
                                 uint8_t *out_mask)
{
    size_t n;
    xrsc_result res = out_mask ? check_input(in, &n) : XRSC_ERROR_INVALID_ARGUMENT;
    if (res != XRSC_OK)
        return res;
    const xrsc_metrics_options o = me_options_fill(options);
    for (uint32_t y = 0; y < in->height; y++)
        for (uint32_t x = 0; x < in->width; x++) {
            const size_t p = (size_t)y * in->width + x;
            uint8_t m = is_edge(in, x, y) ? (uint8_t)XRSC_REGION_BIT(XRSC_REGION_EDGE) : 0u;
            if (is_foreground(in->hit_id, in->depth_m, p)) {
                m |= (uint8_t)XRSC_REGION_BIT(XRSC_REGION_ALL);
                m |= instance_bits(in, in->hit_id[p * 4]);
                if (in->prev_hit_id && !seen_in(in, x, y, &in->prev_camera, in->prev_depth_m,
                                                in->prev_hit_id, o.depth_tolerance))
                    m |= (uint8_t)XRSC_REGION_BIT(XRSC_REGION_UNCOVERED);
                if (in->other_depth_m && !seen_in(in, x, y, &in->other_camera, in->other_depth_m,
                                                  in->other_hit_id, o.depth_tolerance))
                    m |= (uint8_t)XRSC_REGION_BIT(XRSC_REGION_ONE_EYE);
            }
            out_mask[p] = m;
        }
    return XRSC_OK;
}

xrsc_result xrsc_metrics_region_error(const float *test_rgba, const float *ref_rgba,
                                      const uint8_t *mask, xrsc_region region, uint32_t width,
                                      uint32_t height, const xrsc_metrics_options *options,
                                      xrsc_error_metrics *out, uint64_t *out_count)
{
    if (!out || !mask || (unsigned)region >= XRSC_REGION_COUNT)
        return XRSC_ERROR_INVALID_ARGUMENT;
    size_t n;
    xrsc_result res = me_check_pair(test_rgba, ref_rgba, width, height, &n);
    if (res != XRSC_OK)
        return res;
    const uint8_t bit = (uint8_t)XRSC_REGION_BIT(region);
    uint64_t count = me_error_over(test_rgba, ref_rgba, n, mask, bit,
                                   me_options_fill(options).relmse_epsilon, out);
    if (out_count)
        *out_count = count;
    return XRSC_OK;
}

/* Mean of the finite err[first .. end) (NaN when none). */
static double finite_mean(const double *err, uint32_t first, uint32_t end)
{
    double sum = 0.0;
    uint32_t used = 0;
    for (uint32_t k = first; k < end; k++)
        if (isfinite(err[k])) {
            sum += err[k];
            used++;
        }
    return used ? sum / used : NAN;
}

uint32_t xrsc_metrics_recovery_frames_after(const double *err, uint32_t count, uint32_t event_frame,
                                            uint32_t pre_frames, uint32_t end_frame, double factor)
{
    if (!err || event_frame == 0 || end_frame < event_frame || end_frame >= count)
        return UINT32_MAX;
    const uint32_t first = pre_frames && pre_frames < event_frame ? event_frame - pre_frames : 0;
    const double baseline = finite_mean(err, first, event_frame);
    if (!isfinite(baseline))
        return UINT32_MAX;
    const double limit = factor * baseline;
    /* The spike: the largest error from the event on, so that a slow rise (a turn that
     * accelerates) does not count as being back. */
    uint32_t peak = UINT32_MAX;
    for (uint32_t k = event_frame; k < count; k++)
        if (isfinite(err[k]) && (peak == UINT32_MAX || err[k] > err[peak]))
            peak = k;
    if (peak == UINT32_MAX)
        return UINT32_MAX;
    if (err[peak] <= limit) /* the error never left the band */
        return 0;
    const uint32_t from = peak > end_frame ? peak : end_frame;
    for (uint32_t k = from; k < count; k++)
        if (isfinite(err[k]) && err[k] <= limit)
            return k - end_frame;
    return UINT32_MAX;
}

uint32_t xrsc_metrics_recovery_frames(const double *err, uint32_t count, uint32_t event_frame,
                                      uint32_t pre_frames, double factor)
{
    return xrsc_metrics_recovery_frames_after(err, count, event_frame, pre_frames, event_frame,
                                              factor);
}
