// SPDX-License-Identifier: MIT
/**
 * @file hs_pose_stats.h
 * @brief Angular-speed statistics of a pose stream: the peak speed between samples and the
 *        window of a given length with the fastest mean angular speed (issue 9: the
 *        `headturn-hololens` case takes the fastest one-second window of a real capture).
 */
#pragma once

#include "hs_pose_stream.h"

#ifdef __cplusplus
extern "C" {
#endif

/** The fastest window of a stream (all times relative to its first sample). */
typedef struct hs_pose_window {
    int64_t start_ns, end_ns;         /**< the window: a sample's time and start + window length */
    double mean_speed_rad_s;          /**< rotation angle summed over the sample steps inside the
                                       *   window, divided by the window length */
    double peak_speed_rad_s;          /**< fastest single step inside the window: angle / dt */
    int64_t peak_ns;                  /**< midpoint of that step */
    size_t first_sample, last_sample; /**< the samples inside the window */
} hs_pose_window;

/**
 * Finds, among the windows [t_i, t_i + window_ns] starting at a sample, the one with the
 * largest mean angular speed (rotation angle of each step between consecutive samples, summed
 * over the steps that lie inside the window). Ties keep the earliest window. A stream shorter
 * than the window is one window from its first sample. XRSC_ERROR_INVALID_ARGUMENT for a NULL
 * or empty stream or window_ns <= 0.
 */
xrsc_result hs_pose_stream_fastest_window(const hs_pose_stream *stream, int64_t window_ns,
                                          hs_pose_window *out);

#ifdef __cplusplus
}
#endif
