// SPDX-License-Identifier: MIT
/**
 * @file me_ssim.c
 * @brief Mean SSIM on luminance (Wang, Bovik, Sheikh, Simoncelli, IEEE TIP 13(4) 2004).
 */
#include "me_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define WIN XRSC_SSIM_WINDOW
#define HALF (XRSC_SSIM_WINDOW / 2)

/* The five local statistics of §III-B filtered by the window: x, y, x^2, y^2, x y. */
enum { S_X, S_Y, S_XX, S_YY, S_XY, S_COUNT };

static void gaussian_1d(double out_g[WIN])
{
    /* §III-C: circular-symmetric Gaussian, standard deviation 1.5 samples, normalised to unit
     * sum. It is separable: the 2-D window is the outer product of this 1-D one. */
    double sum = 0.0;
    for (int k = 0; k < WIN; k++) {
        double t = (double)(k - HALF);
        out_g[k] = exp(-t * t / (2.0 * XRSC_SSIM_SIGMA * XRSC_SSIM_SIGMA));
        sum += out_g[k];
    }
    for (int k = 0; k < WIN; k++)
        out_g[k] /= sum;
}

void xrsc_metrics_ssim_window(double out_w[XRSC_SSIM_WINDOW * XRSC_SSIM_WINDOW])
{
    double g[WIN];
    gaussian_1d(g);
    for (int r = 0; r < WIN; r++)
        for (int c = 0; c < WIN; c++)
            out_w[r * WIN + c] = g[r] * g[c];
}

xrsc_result xrsc_metrics_ssim(const float *test_rgba, const float *ref_rgba, uint32_t width,
                              uint32_t height, const xrsc_metrics_options *options,
                              double *out_mssim, float *out_map)
{
    if (!out_mssim)
        return XRSC_ERROR_INVALID_ARGUMENT;
    size_t n;
    xrsc_result res = me_check_pair(test_rgba, ref_rgba, width, height, &n);
    if (res != XRSC_OK)
        return res;
    if (width < WIN || height < WIN)
        return XRSC_ERROR_INVALID_ARGUMENT;
    const xrsc_metrics_options o = me_options_fill(options);

    const size_t ow = width - (WIN - 1), oh = height - (WIN - 1);
    /* Luminance of both images, then a ring of the last 11 horizontally filtered rows of the
     * five statistics, so memory stays O(w) beyond the two luminance planes. */
    double *lum = malloc(2 * n * sizeof(double));
    double *ring = malloc((size_t)WIN * S_COUNT * ow * sizeof(double));
    if (!lum || !ring) {
        free(lum);
        free(ring);
        return XRSC_ERROR_OUT_OF_MEMORY;
    }
    double *lx = lum, *ly = lum + n;
    for (size_t p = 0; p < n; p++) {
        lx[p] = me_display_luminance(test_rgba + p * 4, o.display_range);
        ly[p] = me_display_luminance(ref_rgba + p * 4, o.display_range);
    }

    double g[WIN];
    gaussian_1d(g);
    /* C1 = (K1 L)^2, C2 = (K2 L)^2 (Eq. 6-7) with the dynamic range L = 1 after division by
     * display_range. */
    const double c1 = (XRSC_SSIM_K1 * 1.0) * (XRSC_SSIM_K1 * 1.0);
    const double c2 = (XRSC_SSIM_K2 * 1.0) * (XRSC_SSIM_K2 * 1.0);

    double total = 0.0;
    for (size_t r = 0; r < height; r++) {
        double *slot = ring + (r % WIN) * S_COUNT * ow;
        const double *xr = lx + r * width, *yr = ly + r * width;
        for (size_t c = 0; c < ow; c++) {
            double s[S_COUNT] = {0};
            for (int k = 0; k < WIN; k++) {
                double a = xr[c + k], b = yr[c + k];
                s[S_X] += g[k] * a;
                s[S_Y] += g[k] * b;
                s[S_XX] += g[k] * a * a;
                s[S_YY] += g[k] * b * b;
                s[S_XY] += g[k] * a * b;
            }
            for (int i = 0; i < S_COUNT; i++)
                slot[i * ow + c] = s[i];
        }
        if (r < WIN - 1)
            continue;
        const size_t out_r = r - (WIN - 1);
        for (size_t c = 0; c < ow; c++) {
            double s[S_COUNT] = {0};
            for (int k = 0; k < WIN; k++) {
                const double *src = ring + ((out_r + k) % WIN) * S_COUNT * ow;
                for (int i = 0; i < S_COUNT; i++)
                    s[i] += g[k] * src[i * ow + c];
            }
            double mx = s[S_X], my = s[S_Y];
            /* Weighted mean, variances and covariance, Eq. (14)-(16); SSIM by Eq. (13). */
            double vx = s[S_XX] - mx * mx, vy = s[S_YY] - my * my, cxy = s[S_XY] - mx * my;
            double ssim = ((2.0 * mx * my + c1) * (2.0 * cxy + c2)) /
                          ((mx * mx + my * my + c1) * (vx + vy + c2));
            total += ssim;
            if (out_map)
                out_map[out_r * ow + c] = (float)ssim;
        }
    }
    free(lum);
    free(ring);
    /* Eq. (17): the mean over the map. */
    *out_mssim = total / ((double)ow * (double)oh);
    return XRSC_OK;
}
