// SPDX-License-Identifier: MIT
/**
 * @file hs_pose_stats.c
 * @brief The fastest window of a pose stream by mean angular speed (two pointers, O(n)).
 */
#include "hs_pose_stats.h"

#include <string.h>

/** Rotation angle (rad) of the step from sample i to sample i + 1. */
static double step_angle(const hs_pose_stream *s, size_t i)
{
    return (double)xrsc_quat_angle_between(s->samples[i].pose.orientation,
                                           s->samples[i + 1].pose.orientation);
}

/** Peak step speed inside samples [first, last] into out. */
static void find_peak(const hs_pose_stream *s, hs_pose_window *out)
{
    out->peak_speed_rad_s = 0.0;
    out->peak_ns = s->samples[out->first_sample].time_ns;
    for (size_t i = out->first_sample; i < out->last_sample; i++) {
        int64_t dt = s->samples[i + 1].time_ns - s->samples[i].time_ns;
        if (dt <= 0)
            continue;
        double speed = step_angle(s, i) / ((double)dt * 1e-9);
        if (speed > out->peak_speed_rad_s) {
            out->peak_speed_rad_s = speed;
            out->peak_ns = s->samples[i].time_ns + dt / 2;
        }
    }
}

xrsc_result hs_pose_stream_fastest_window(const hs_pose_stream *stream, int64_t window_ns,
                                          hs_pose_window *out)
{
    if (!stream || !stream->samples || stream->count == 0 || window_ns <= 0 || !out)
        return XRSC_ERROR_INVALID_ARGUMENT;
    memset(out, 0, sizeof(*out));
    const hs_pose_sample *s = stream->samples;
    size_t n = stream->count, end = 0; /* end: last sample inside the current window */
    double sum = 0.0, best = -1.0;     /* sum: angle of the steps from i to end */
    for (size_t i = 0; i < n; i++) {
        if (end < i) {
            end = i;
            sum = 0.0;
        }
        while (end + 1 < n && s[end + 1].time_ns - s[i].time_ns <= window_ns) {
            sum += step_angle(stream, end);
            end++;
        }
        if (sum > best) {
            best = sum;
            out->start_ns = s[i].time_ns;
            out->first_sample = i;
            out->last_sample = end;
        }
        if (end == n - 1 && i + 1 < n && s[i].time_ns + window_ns >= s[n - 1].time_ns)
            break; /* later windows only lose steps */
        if (end > i)
            sum -= step_angle(stream, i); /* slide: drop the step leaving the window */
    }
    out->end_ns = out->start_ns + window_ns;
    out->mean_speed_rad_s = best / ((double)window_ns * 1e-9);
    find_peak(stream, out);
    return XRSC_OK;
}
