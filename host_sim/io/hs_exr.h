// SPDX-License-Identifier: MIT
/**
 * @file hs_exr.h
 * @brief OpenEXR output of linear frames (RGB and depth as the standard Z channel) and a reader
 *        for them, through OpenEXR's C library (OpenEXRCore, libopenexr-dev); the reader is
 *        u_exr.h's (plugin/src/util, shared with the plugin's environment maps).
 *
 * Files are single-part scanline EXRs with 32-bit float channels B, G, R and, when depth is
 * given, Z (the channel names tev, Blender and Nuke read as colour and depth), ZIP compressed
 * (lossless), rows top to bottom (INCREASING_Y), data window (0,0)-(w-1,h-1). Float rather
 * than half so the values are the renderer's bit for bit (the PFM's), and depth keeps its
 * precision far from the eye.
 */
#pragma once

#include "xrsc/result.h"

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/**
 * Writes w*h RGBA float pixels (rows top to bottom; alpha dropped) as R, G, B and, when depth
 * is not NULL, w*h float depth values as Z (xrsc.h's XRSC_OUTPUT_DEPTH: view-space distance
 * along -Z in metres, 0 where the ray missed, written as given). The file is written as
 * PATH.tmp and renamed over path only when everything was written (hs_file.h), so an
 * interrupted run leaves no partial EXR. XRSC_ERROR_IO names path and the library's message.
 */
xrsc_result hs_write_exr(const char *path, const float *rgba, const float *depth, uint32_t w,
                         uint32_t h, xrsc_diag *diag);
/** As hs_write_exr, for a frame set (hs_file.h): written whole as PATH.tmp and left there for
 *  hs_frame_set_commit. */
xrsc_result hs_stage_exr(const char *path, const float *rgba, const float *depth, uint32_t w,
                         uint32_t h, xrsc_diag *diag);

/**
 * Reads a scanline EXR's first part: R, G, B (missing channels read 0) into malloc'ed RGBA
 * floats (alpha from A, else 1) and, when out_depth is not NULL, Z into malloc'ed floats
 * (*out_depth NULL when the file has no Z). Half and uint channels are converted to float.
 * XRSC_ERROR_BAD_HEADER for a file that is not an EXR, a tiled or deep one, or sides over
 * 65536; XRSC_ERROR_IO when it cannot be read. On error nothing is allocated.
 */
xrsc_result hs_read_exr(const char *path, float **out_rgba, float **out_depth, uint32_t *out_w,
                        uint32_t *out_h, xrsc_diag *diag);

#ifdef __cplusplus
}
#endif
