// SPDX-License-Identifier: MIT
/**
 * @file u_exr.h
 * @brief OpenEXR reader of linear RGB(A) pictures (and a Z channel), through OpenEXR's C library
 *        (OpenEXRCore, libopenexr-dev): shared by the plugin (environment maps, sc_scene.c)
 *        and the host (hs_exr.h reads its frames back with it), which must not include the host.
 *
 * Read: a scanline EXR's first part; channels R, G, B (missing ones read 0), A (else 1) and,
 * when asked, Z; half, float and uint channels are converted to float; rows top to bottom from
 * the data window's first row. Refused: tiled or deep files, sides over ::U_EXR_MAX_SIDE.
 * Library target xrsc_util_exr (plugin/CMakeLists.txt), apart from xrsc_util so that only its
 * users link OpenEXR.
 */
#pragma once

#include "xrsc/result.h"

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Largest side accepted (pixels). */
#define U_EXR_MAX_SIDE 65536

/** A decoded picture. Arrays are malloc'ed (u_exr_image_free). */
typedef struct u_exr_image {
    uint32_t width, height;
    float *rgba;  /**< 4 floats per pixel, rows top to bottom */
    float *depth; /**< Z, 1 float per pixel; NULL when not asked for or the file has none */
} u_exr_image;

/** What to read. Zero-initialised: RGBA only, no pixel-count limit beyond the sides. */
typedef struct u_exr_options {
    int want_depth;      /**< nonzero: also read Z into u_exr_image.depth */
    uint64_t max_pixels; /**< 0: none; more: XRSC_ERROR_FILE_TOO_LARGE before any allocation */
} u_exr_options;

/**
 * Reads the EXR at path into *out (zeroed on error; nothing stays allocated). opt may be NULL.
 * Errors name path in diag (field "exr", the library's message): XRSC_ERROR_IO when the file
 * cannot be opened or its pixel data cannot be read (a truncated file), XRSC_ERROR_BAD_HEADER
 * for a file that is not an EXR, a tiled or deep one or sides out of range,
 * XRSC_ERROR_FILE_TOO_LARGE over opt->max_pixels, XRSC_ERROR_OUT_OF_MEMORY.
 */
xrsc_result u_exr_read(const char *path, const u_exr_options *opt, u_exr_image *out,
                       xrsc_diag *diag);
/** As u_exr_read, for a file held in memory; name is used in messages. */
xrsc_result u_exr_decode(const char *name, const uint8_t *data, size_t size,
                         const u_exr_options *opt, u_exr_image *out, xrsc_diag *diag);
/** Frees the arrays and zeroes *img; accepts NULL. */
void u_exr_image_free(u_exr_image *img);

#ifdef __cplusplus
}
#endif
