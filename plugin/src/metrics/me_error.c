// SPDX-License-Identifier: MIT
/**
 * @file me_error.c
 * @brief MSE, RMSE and relMSE of a test image against a reference.
 */
#include "me_internal.h"

#include <math.h>

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
    const xrsc_metrics_options o = me_options_fill(options);

    /* Sums in double; the alpha channel is not part of the image (xrsc_metrics.h). */
    double sq = 0.0, rel = 0.0;
    for (size_t p = 0; p < n; p++) {
        for (int c = 0; c < 3; c++) {
            double r = ref_rgba[p * 4 + c];
            double d = (double)test_rgba[p * 4 + c] - r;
            sq += d * d;
            rel += d * d / (r * r + o.relmse_epsilon);
        }
    }
    double count = 3.0 * (double)n;
    out->mse = sq / count;
    out->rmse = sqrt(out->mse);
    out->relmse = rel / count;
    return XRSC_OK;
}
