// SPDX-License-Identifier: MIT
/**
 * @file hs_xr_replay.h
 * @brief `xrsc replay` through OpenXR: the plugin's OpenXR front end (xrsc_xr.h) as the
 *        application, host_sim's runtime (or any runtime) replaying the pose stream.
 *
 * The runtime is configured through its environment variables (host_sim/runtime/
 * README.md), set from the replay options before the instance is created: XRSC_RT_POSES,
 * XRSC_RT_FRAMES, XRSC_RT_OUT, XRSC_RT_WRITE, XRSC_RT_EXPOSURE, XRSC_RT_EYE_SIZE,
 * XRSC_RT_REFRESH_HZ, XRSC_RT_IPD_MM (--ipd), XRSC_RT_FOV_DEG (the headset's per-eye FOVs,
 * --headset), XRSC_RT_START_S (--start), XRSC_RT_DEVICE
 * (--device, else XRSC_DEVICE: the same selector), and XRSC_RT_PACE=fast unless already set. The runtime
 * writes the frames (PNG/PFM) and frames.csv; the replay reports timing like hs_replay_run.
 *
 * Which runtime: XR_RUNTIME_JSON when set (it must name an existing file), else this build's
 * host_sim runtime manifest (HS_XR_DEFAULT_MANIFEST, set into XR_RUNTIME_JSON for the loader).
 */
#pragma once

#include "hs_replay.h"

#ifdef __cplusplus
extern "C" {
#endif

/**
 * Runs the replay through OpenXR. A forced pose format the runtime would read differently is
 * XRSC_ERROR_INVALID_ARGUMENT naming --pose-format (the direct path, hs_replay_run, has it).
 * Anchoring places the same pose on the viewpoint as the direct path, the stream's first
 * sample: the plugin locates the head at frame 0's predicted display time minus --start
 * (xrsc_xr_session_options.anchor_offset_ns; frame 0 itself is not rendered), which the
 * runtime maps to stream time 0. So frame k's eye poses equal the direct path's frame k's
 * (within float rounding), anchored or not. opt->on_frame is called after each rendered frame
 * with the views it was rendered with (frame_index k >= 1, scene time k / refresh).
 * A missing runtime is XRSC_ERROR_XR_RUNTIME_UNAVAILABLE naming XR_RUNTIME_JSON; a lost
 * session XRSC_ERROR_XR_SESSION_LOST. Everything made is destroyed on every path.
 */
xrsc_result hs_xr_replay_run(const hs_replay_options *opt, hs_replay_stats *out_stats,
                             xrsc_diag *diag);

#ifdef __cplusplus
}
#endif
