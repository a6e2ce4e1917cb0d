// SPDX-License-Identifier: MIT
/**
 * @file sc_hdr.h
 * @brief Reader of Radiance `.hdr` pictures (RGBE) for equirectangular environment maps.
 *
 * Accepted: the magic line `#?RADIANCE` or `#?RGBE`; header variables until an empty line
 * (`FORMAT=32-bit_rle_rgbe` when present, `EXPOSURE=x` divides the values, others ignored);
 * the resolution line `-Y H +X W` (rows top to bottom) or `+Y H +X W` (bottom to top);
 * scanlines flat, old-style run-length (1,1,1,n) or the adaptive RLE of Radiance
 * (2,2,hi,lo per scanline, four channel runs). Refused with an error: XYZE pixels, other
 * resolution orders (rotated pictures), sides over ::SC_HDR_MAX_SIDE or more than
 * ::SC_HDR_MAX_PIXELS pixels, scanlines that overrun or end early.
 *
 * Errors fill diag: file = the name given, line = the header line (1-based) for header
 * errors, or the scanline (1-based, in file order) for pixel data, field = "magic",
 * "FORMAT", "EXPOSURE", "resolution" or "scanline". Codes: XRSC_ERROR_EMPTY_FILE,
 * XRSC_ERROR_BAD_HEADER (magic, format, resolution, a side of 0), XRSC_ERROR_BAD_NUMBER
 * (EXPOSURE),
 * XRSC_ERROR_FILE_TOO_LARGE (sides or pixel count), XRSC_ERROR_TRUNCATED_LINE (data ends
 * or a run overruns its scanline), XRSC_ERROR_IO, XRSC_ERROR_OUT_OF_MEMORY.
 *
 * Why not stb_image's stbi_loadf (issue 22 asked for it): the stb_image in Debian's libstb-dev
 * (2.27) loops forever on a zero count in an adaptive-RLE scanline or on a file cut inside one
 * (CVE-2021-42715, fixed upstream in 2.28; tests/scene/test_hdr_env.c holds both files), reads
 * missing pixel data as zeros instead of failing, refuses bottom-up (+Y) pictures and files
 * without a FORMAT line, ignores EXPOSURE, does not know old-style runs, decodes without
 * Radiance's +0.5 (mantissa + 0.5) and names no line. A guard that made it safe would walk every
 * scanline as this reader does.
 */
#pragma once

#include "xrsc/result.h"

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Largest side accepted (pixels). */
#define SC_HDR_MAX_SIDE 32768u
/** Largest pixel count accepted (16 Mpixel: 192 MB of floats). */
#define SC_HDR_MAX_PIXELS (1u << 24)

/** A decoded picture: linear RGB floats, 3 per pixel, rows top to bottom. */
typedef struct sc_hdr_image {
    uint32_t width, height;
    float *rgb; /**< malloc'ed; sc_hdr_image_free */
} sc_hdr_image;

/** Decodes a .hdr file held in memory; name is used in messages. *out is zeroed on error. */
xrsc_result sc_hdr_decode(const char *name, const uint8_t *data, size_t size, sc_hdr_image *out,
                          xrsc_diag *diag);
/** Reads and decodes the file at path (files over 1 GiB are XRSC_ERROR_FILE_TOO_LARGE). */
xrsc_result sc_hdr_load(const char *path, sc_hdr_image *out, xrsc_diag *diag);
/** Frees the pixels and zeroes *img; accepts NULL. */
void sc_hdr_image_free(sc_hdr_image *img);

#ifdef __cplusplus
}
#endif
