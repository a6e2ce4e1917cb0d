// SPDX-License-Identifier: MIT
/**
 * @file sc_hdr.h
 * @brief Reader of Radiance `.hdr` pictures (RGBE) for equirectangular environment maps.
 *
 * The header and resolution line are read here; the scanlines are decoded by stb_image's
 * stbi_loadf_from_callbacks (Debian's libstb), guarded against its endless loops (sc_hdr.c).
 *
 * Accepted: the magic line `#?RADIANCE` or `#?RGBE`; header variables until an empty line
 * (`FORMAT=32-bit_rle_rgbe` when present, `EXPOSURE=x` divides the values, others ignored);
 * the resolution line `-Y H +X W` (rows top to bottom) or `+Y H +X W` (bottom to top);
 * scanlines flat or in the adaptive RLE of Radiance (2,2,hi,lo per scanline, four channel
 * runs; widths 8..32767), all scanlines alike. Values are mantissa x 2^(exponent - 136), as
 * stb_image decodes them (no +0.5). Old-style runs (1,1,1,n) are not recognised: stb_image
 * reads them as pixels. Refused with an error: XYZE pixels, other resolution orders (rotated
 * pictures), sides over ::SC_HDR_MAX_SIDE or more than ::SC_HDR_MAX_PIXELS pixels, pixel data
 * that ends early, runs that overrun a scanline, scanline widths that differ from the
 * resolution line.
 *
 * Errors fill diag: file = the name given, line = the header line (1-based) for header
 * errors, 0 for pixel data (stb_image does not say where), field = "magic", "header",
 * "FORMAT", "EXPOSURE", "resolution" or "pixels". Codes: XRSC_ERROR_EMPTY_FILE,
 * XRSC_ERROR_BAD_HEADER (magic, format, resolution, a side of 0), XRSC_ERROR_BAD_NUMBER
 * (EXPOSURE), XRSC_ERROR_FILE_TOO_LARGE (sides, pixel count, over 1 GiB),
 * XRSC_ERROR_TRUNCATED_LINE (the header or pixel data ends early, or stb_image finds the
 * pixel data corrupt: its reason is in the message), XRSC_ERROR_IO, XRSC_ERROR_OUT_OF_MEMORY.
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

/** Decodes a .hdr file held in memory (at most 1 GiB); name is used in messages. *out is
 *  zeroed on error. */
xrsc_result sc_hdr_decode(const char *name, const uint8_t *data, size_t size, sc_hdr_image *out,
                          xrsc_diag *diag);
/** Reads and decodes the file at path (files over 1 GiB are XRSC_ERROR_FILE_TOO_LARGE). */
xrsc_result sc_hdr_load(const char *path, sc_hdr_image *out, xrsc_diag *diag);
/** Frees the pixels and zeroes *img; accepts NULL. */
void sc_hdr_image_free(sc_hdr_image *img);

#ifdef __cplusplus
}
#endif
