// SPDX-License-Identifier: MIT
/**
 * @file me_error.c
 * @brief MSE, RMSE and relMSE of a test image against a reference.
 */
#include "me_internal.h"

#include <math.h>

uint64_t me_error_over(const float *test_rgba, const float *ref_rgba, size_t n,
                       const uint8_t *mask, uint8_t bit, double relmse_epsilon,
                       xrsc_error_metrics *out)
{
    /* Sums in double; the alpha channel is not part of the image (xrsc_metrics.h). */
    double sq = 0.0, rel = 0.0;
    uint64_t count = 0;
    for (size_t p = 0; p < n; p++) {
        if (mask && !(mask[p] & bit))
            continue;
        count++;
        for (int c = 0; c < 3; c++) {
            double r = ref_rgba[p * 4 + c];
            double d = (double)test_rgba[p * 4 + c] - r;
            sq += d * d;
            rel += d * d / (r * r + relmse_epsilon);
        }
    }
    double values = 3.0 * (double)count;
    out->mse = count ? sq / values : 0.0;
    out->rmse = sqrt(out->mse);
    out->relmse = count ? rel / values : 0.0;
    return count;
}

xrsc_result xrsc_metrics_error(const float *test_rgba, const float *ref_rgba, uint32_t width,
                               uint32_t height, const xrsc_metrics_options *options,
                               xrsc_error_metrics *out)
{
    if (!out)
        return XRSC_ERROR_INVALID_ARGUMENT;
    size_t n;
    xrsc_result res = me_check_pair(test_rgba, ref_rgba, width, height, &n);
    if (res != XRSC_OK)
        return res;
    me_error_over(test_rgba, ref_rgba, n, NULL, 0, me_options_fill(options).relmse_epsilon, out);
    return XRSC_OK;
}
