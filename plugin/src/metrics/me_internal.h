// SPDX-License-Identifier: MIT
/**
 * @file me_internal.h
 * @brief Helpers shared by the metrics files: option defaults and input checks.
 */
#pragma once

#include "xrsc/xrsc_metrics.h"

#include <stddef.h>

/** A copy of options (NULL allowed) with zero fields replaced by the documented defaults. */
xrsc_metrics_options me_options_fill(const xrsc_metrics_options *options);

/**
 * Checks a w*h image of `channels` floats per pixel: non-NULL, non-zero size whose element
 * count fits size_t, every value finite. Writes the pixel count to out_pixels.
 */
xrsc_result me_check_image(const float *data, uint32_t width, uint32_t height, unsigned channels,
                           size_t *out_pixels);

/** relMSE / MSE / RMSE over the pixels p < n whose mask[p] has bit (mask NULL: every pixel)
 *  into out (all 0 when none counts); returns the number of pixels counted. */
uint64_t me_error_over(const float *test_rgba, const float *ref_rgba, size_t n,
                       const uint8_t *mask, uint8_t bit, double relmse_epsilon,
                       xrsc_error_metrics *out);
/** me_check_image of a test and a reference RGBA image of the same size (the test's first). */
xrsc_result me_check_pair(const float *test_rgba, const float *ref_rgba, uint32_t width,
                          uint32_t height, size_t *out_pixels);

/** Luminance clamped to [0, L] and divided by L (L = options->display_range). */
double me_display_luminance(const float rgba[4], double display_range);
