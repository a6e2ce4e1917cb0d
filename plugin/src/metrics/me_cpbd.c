// SPDX-License-Identifier: MIT
/**
 * @file me_cpbd.c
 * @brief CPBD no-reference sharpness (Narvekar & Karam, IEEE TIP 20(9) 2011), written from the
 *        paper's description; the steps are listed at xrsc_metrics_cpbd in xrsc_metrics.h.
 */
#include "me_internal.h"

#include <math.h>
#include <stdlib.h>

/* A vertical edge: gradient within 22.5 deg of horizontal, i.e. the gradient angle quantised to
 * 45 deg is 0 or 180 (the paper measures widths along rows only). tan(pi / 8). */
#define VERTICAL_EDGE_TAN 0.41421356237309503

/* sRGB OETF (IEC 61966-2-1), for the display encoding the JNB experiments were run on. */
static double srgb_encode(double y)
{
    return y <= 0.0031308 ? 12.92 * y : 1.055 * pow(y, 1.0 / 2.4) - 0.055;
}

/* Marziliano's width along row `row` at column c: the distance between the nearest local
 * extrema on either side, walking while the profile stays strictly monotone in the edge's sense
 * (rising when gx > 0). */
static int edge_width(const uint8_t *row, uint32_t width, uint32_t c, bool rising)
{
    uint32_t l = c, r = c;
    if (rising) {
        while (l > 0 && row[l - 1] < row[l])
            l--;
        while (r + 1 < width && row[r + 1] > row[r])
            r++;
    } else {
        while (l > 0 && row[l - 1] > row[l])
            l--;
        while (r + 1 < width && row[r + 1] < row[r])
            r++;
    }
    return (int)(r - l);
}

double xrsc_metrics_cpbd_blur_probability(double width_px, double w_jnb_px)
{
    return 1.0 - exp(-pow(fabs(width_px / w_jnb_px), XRSC_CPBD_BETA));
}

xrsc_result xrsc_metrics_cpbd(const float *rgba, uint32_t width, uint32_t height,
                              const xrsc_metrics_options *options, xrsc_cpbd *out)
{
    if (!out)
        return XRSC_ERROR_INVALID_ARGUMENT;
    size_t n;
    xrsc_result res = me_check_image(rgba, width, height, 4, &n);
    if (res != XRSC_OK)
        return res;
    const xrsc_metrics_options o = me_options_fill(options);

    uint8_t *img = malloc(n);
    uint8_t *edge = calloc(n, 1);
    int32_t *gx = calloc(n, sizeof(int32_t));
    int32_t *gy = calloc(n, sizeof(int32_t));
    double *mag2 = calloc(n, sizeof(double));
    if (!img || !edge || !gx || !gy || !mag2) {
        free(img);
        free(edge);
        free(gx);
        free(gy);
        free(mag2);
        return XRSC_ERROR_OUT_OF_MEMORY;
    }

    /* 8-bit luminance levels: the paper's JNB widths and contrast split are in 8-bit units. */
    for (size_t p = 0; p < n; p++) {
        double y = me_display_luminance(rgba + p * 4, o.display_range);
        if (!o.cpbd_linear)
            y = srgb_encode(y);
        img[p] = (uint8_t)lround(255.0 * y);
    }

    /* Sobel gradients on interior pixels (border gradients stay 0). */
    double mean_mag2 = 0.0;
    if (width >= 3 && height >= 3) {
        double sum = 0.0;
        for (uint32_t y = 1; y + 1 < height; y++) {
            for (uint32_t x = 1; x + 1 < width; x++) {
                const uint8_t *a = img + (size_t)(y - 1) * width + x; /* row above */
                const uint8_t *m = a + width, *b = m + width;
                int32_t sx = (a[1] + 2 * m[1] + b[1]) - (a[-1] + 2 * m[-1] + b[-1]);
                int32_t sy = (b[-1] + 2 * b[0] + b[1]) - (a[-1] + 2 * a[0] + a[1]);
                size_t p = (size_t)y * width + x;
                gx[p] = sx;
                gy[p] = sy;
                mag2[p] = (double)sx * sx + (double)sy * sy;
                sum += mag2[p];
            }
        }
        mean_mag2 = sum / ((double)(width - 2) * (double)(height - 2));
    }
    /* Edge pixels: above the threshold and a local maximum along the dominant axis (thinning;
     * ties go to the right/lower pixel of a pair so a one-step edge gives one edge pixel). */
    const double threshold = XRSC_CPBD_SOBEL_THRESHOLD_SCALE * mean_mag2;
    for (uint32_t y = 1; y + 1 < height; y++) {
        for (uint32_t x = 1; x + 1 < width; x++) {
            size_t p = (size_t)y * width + x;
            if (!(mag2[p] > threshold))
                continue;
            size_t step = abs(gx[p]) >= abs(gy[p]) ? 1 : width;
            if (mag2[p] >= mag2[p - step] && mag2[p] > mag2[p + step])
                edge[p] = 1;
        }
    }

    const double p_jnb = 1.0 - exp(-1.0); /* P at w = w_JNB: the paper's 63 % */
    uint64_t measured = 0, sharp = 0;
    uint32_t blocks = 0, edge_blocks = 0;
    for (uint32_t by = 0; by < height; by += XRSC_CPBD_BLOCK) {
        for (uint32_t bx = 0; bx < width; bx += XRSC_CPBD_BLOCK) {
            uint32_t ey = by + XRSC_CPBD_BLOCK < height ? by + XRSC_CPBD_BLOCK : height;
            uint32_t ex = bx + XRSC_CPBD_BLOCK < width ? bx + XRSC_CPBD_BLOCK : width;
            blocks++;
            uint32_t count = 0;
            int lo = 255, hi = 0;
            for (uint32_t y = by; y < ey; y++) {
                for (uint32_t x = bx; x < ex; x++) {
                    size_t p = (size_t)y * width + x;
                    count += edge[p];
                    lo = img[p] < lo ? img[p] : lo;
                    hi = img[p] > hi ? img[p] : hi;
                }
            }
            double block_pixels = (double)(ey - by) * (double)(ex - bx);
            if (!((double)count > XRSC_CPBD_EDGE_BLOCK_FRACTION * block_pixels))
                continue;
            edge_blocks++;
            double w_jnb =
                hi - lo > XRSC_CPBD_CONTRAST_SPLIT ? XRSC_CPBD_WJNB_HIGH : XRSC_CPBD_WJNB_LOW;
            for (uint32_t y = by; y < ey; y++) {
                for (uint32_t x = bx; x < ex; x++) {
                    size_t p = (size_t)y * width + x;
                    if (!edge[p] || gx[p] == 0)
                        continue;
                    if (abs(gy[p]) > VERTICAL_EDGE_TAN * abs(gx[p]))
                        continue;
                    int w = edge_width(img + (size_t)y * width, width, x, gx[p] > 0);
                    if (w == 0) /* no monotone profile along the row: not measurable */
                        continue;
                    double prob = xrsc_metrics_cpbd_blur_probability(w, w_jnb);
                    measured++;
                    sharp += prob <= p_jnb;
                }
            }
        }
    }
    free(img);
    free(edge);
    free(gx);
    free(gy);
    free(mag2);

    out->cpbd = measured ? (double)sharp / (double)measured : 0.0;
    out->edge_count = measured;
    out->edge_block_count = edge_blocks;
    out->block_count = blocks;
    return XRSC_OK;
}
