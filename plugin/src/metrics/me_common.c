// SPDX-License-Identifier: MIT
/**
 * @file me_common.c
 * @brief Option defaults, input checks and luminance for the metrics module.
 */
#include "me_internal.h"

#include <math.h>

xrsc_metrics_options me_options_fill(const xrsc_metrics_options *options)
{
    xrsc_metrics_options o = {0};
    if (options)
        o = *options;
    if (!(o.relmse_epsilon > 0.0))
        o.relmse_epsilon = XRSC_METRICS_RELMSE_EPSILON;
    if (!(o.display_range > 0.0))
        o.display_range = XRSC_METRICS_DISPLAY_RANGE;
    if (!(o.depth_tolerance > 0.0))
        o.depth_tolerance = XRSC_METRICS_DEPTH_TOLERANCE;
    return o;
}

xrsc_result me_check_image(const float *data, uint32_t width, uint32_t height, unsigned channels,
                           size_t *out_pixels)
{
    if (!data || width == 0 || height == 0 || channels == 0)
        return XRSC_ERROR_INVALID_ARGUMENT;
    size_t pixels = (size_t)width * height;
    if (pixels / width != height || pixels > SIZE_MAX / sizeof(float) / channels)
        return XRSC_ERROR_INVALID_ARGUMENT;
    size_t n = pixels * channels;
    for (size_t i = 0; i < n; i++)
        if (!isfinite(data[i]))
            return XRSC_ERROR_NAN;
    *out_pixels = pixels;
    return XRSC_OK;
}

xrsc_result me_check_pair(const float *test_rgba, const float *ref_rgba, uint32_t width,
                          uint32_t height, size_t *out_pixels)
{
    xrsc_result res = me_check_image(test_rgba, width, height, 4, out_pixels);
    if (res == XRSC_OK)
        res = me_check_image(ref_rgba, width, height, 4, out_pixels);
    return res;
}

/* Rec. 709 luminance weights of linear sRGB primaries (ITU-R BT.709-6, item 3.2). */
double xrsc_metrics_luminance(const float rgba[4])
{
    return 0.2126 * rgba[0] + 0.7152 * rgba[1] + 0.0722 * rgba[2];
}

double me_display_luminance(const float rgba[4], double display_range)
{
    double y = xrsc_metrics_luminance(rgba) / display_range;
    return y < 0.0 ? 0.0 : (y > 1.0 ? 1.0 : y);
}
