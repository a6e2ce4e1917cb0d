// SPDX-License-Identifier: MIT
/**
 * @file hs_outputs.h
 * @brief Per-frame outputs both replay paths write from the renderer itself: OpenEXR frames
 *        (`--write exr`) and the side-by-side video (`--video FILE`, through ffmpeg).
 *
 * They are written by the program from the renderer's outputs after each rendered frame, on
 * the direct path and through OpenXR alike: colour is XRSC_OUTPUT_COLOR after the stereo blend
 * (the pixels the OpenXR path submits in its R32G32B32A32 swapchains, so an EXR equals the
 * runtime's PFM of the same frame), depth is XRSC_OUTPUT_DEPTH in metres (the runtime only
 * sees it as [0, 1] window depth) of hs_outputs_set_depth's renderer: the replay sets the one
 * of hs_views.h, so Z is the depth at each pixel's centre. Frame numbers are the replay's: those of the PNG/PFM files.
 *
 * Video: the side-by-side frames (tone-mapped as the _sbs.png) are piped as raw RGB24 to
 * `ffmpeg -f rawvideo ... -pix_fmt yuv420p FILE` at the display refresh rate; ffmpeg picks the
 * codec from FILE's extension. ffmpeg is found on PATH (XRSC_FFMPEG names another program with
 * ffmpeg's arguments). When it is not there the run goes on without a video, with a warning.
 * ffmpeg writes FILE with ".partial" before the extension, renamed to FILE when it succeeded.
 * ffmpeg runs in a process group of its own, so a Ctrl-C at the terminal stops only xrsc, which
 * ends the stream after its last frame and keeps the video (a whole file, fewer frames).
 */
#pragma once

#include "hs_file.h"
#include "hs_replay.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct hs_outputs hs_outputs;

/**
 * Prepares the outputs opt asks for (write_exr with an out_dir, video_path) for w x h eyes
 * shown at fps; *out is NULL when there is nothing to do (also when ffmpeg is missing).
 * XRSC_ERROR_IO when ffmpeg cannot be started.
 */
xrsc_result hs_outputs_open(const hs_replay_options *opt, uint32_t w, uint32_t h, double fps,
                            hs_outputs **out, xrsc_diag *diag);

/**
 * Writes frame number `frame` from the renderer's current outputs; accepts o == NULL. The EXR
 * files join set (hs_file.h: staged, renamed with the frame's other files by the caller's
 * hs_frame_set_commit); set NULL: they form a set of their own, committed here.
 */
xrsc_result hs_outputs_frame(hs_outputs *o, xrsc_renderer *r, uint32_t frame, hs_frame_set *set,
                             xrsc_diag *diag);

/**
 * The renderer whose XRSC_OUTPUT_DEPTH the EXRs' Z is read from (hs_views.h: depth at pixel
 * centres), rendered with the same views before each hs_outputs_frame; NULL: the frame's own
 * renderer. Accepts o == NULL.
 */
void hs_outputs_set_depth(hs_outputs *o, xrsc_renderer *depth);

/**
 * Ends the outputs and frees them (accepts NULL, sets *o to NULL). With keep, waits for ffmpeg
 * and renames the video into place (XRSC_ERROR_IO when ffmpeg failed); without (a failed run),
 * the partial video is removed.
 */
xrsc_result hs_outputs_close(hs_outputs **o, bool keep, xrsc_diag *diag);

#ifdef __cplusplus
}
#endif
