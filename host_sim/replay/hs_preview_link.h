// SPDX-License-Identifier: MIT
/**
 * @file hs_preview_link.h
 * @brief The side channel from `xrsc replay` to the runtime's preview window: the run's method,
 *        blend and R, and each frame's timings, for the window's overlay.
 *
 * The runtime runs in this process (the OpenXR loader loads it), but the application reaches it
 * only through OpenXR calls, which carry no such information. The channel is a pipe: this side
 * keeps the write end (non-blocking: a preview that reads slowly or not at all never stalls the
 * frame loop; lines that do not fit are dropped), and XRSC_RT_PREVIEW_INFO_FD names the read end,
 * which the runtime reads at xrCreateInstance's configuration (hsrt_config.preview_info_fd).
 * Lines of space-separated words (host_sim/runtime/README.md, "Overlay information"):
 *
 *     run method=samplecache blend=moments r=0
 *     frame 12 ms=38.2 tlas=0.01 trace=20.5 ...
 *     autoclose
 *     stop
 *
 * frame N is the runtime's frame number (the numbering of the files it writes); ms is the wall
 * time of rendering the stereo frame, the other keys the GPU ms of each pass; autoclose asks the
 * window not to wait for the user when the session ends; stop (sent by a thread that watches the
 * run's Ctrl-C flag) also resumes a paused window, which holds the frame loop in xrWaitFrame.
 */
#pragma once

#include "hs_replay.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct hs_preview_link hs_preview_link;

/**
 * When the preview is on (opt->preview, or XRSC_RT_PREVIEW=1/on already in the environment):
 * sets XRSC_RT_PREVIEW=1 and, from the options, XRSC_RT_PREVIEW_AUTOCLOSE and
 * XRSC_RT_PREVIEW_REFERENCE, opens the pipe, sets XRSC_RT_PREVIEW_INFO_FD and sends the run
 * line. *out stays NULL when the preview is off. Call before the OpenXR instance is created.
 */
xrsc_result hs_preview_link_open(const hs_replay_options *opt, hs_preview_link **out,
                                 xrsc_diag *diag);
/** Sends frame `frame`'s timings (link NULL: nothing). */
void hs_preview_link_frame(hs_preview_link *link, uint64_t frame, double render_ms,
                           const xrsc_pass_timing *passes, uint32_t pass_count);
/** Asks the window to close when the session ends, as XRSC_RT_PREVIEW_AUTOCLOSE=1 (a run that
 *  was interrupted or failed does not wait for the user); link NULL: nothing. */
void hs_preview_link_autoclose(hs_preview_link *link);
/** Closes both ends and unsets XRSC_RT_PREVIEW_INFO_FD; accepts NULL, sets *link to NULL. */
void hs_preview_link_close(hs_preview_link **link);

#ifdef __cplusplus
}
#endif
