// SPDX-License-Identifier: MIT
/**
 * @file hs_image.h
 * @brief Writing per-eye and side-by-side images: tone-mapped 8-bit PNG and linear float PFM.
 */
#pragma once

#include "xrsc/result.h"

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/**
 * Tone mapping for display: linear radiance x exposure, then the ACES filmic curve fit of
 * Narkowicz (2015), then the sRGB transfer function, quantised to 8 bits.
 */
typedef struct hs_tonemap {
    float exposure; /**< 0 means 1.0 */
} hs_tonemap;

/** Converts w*h RGBA float pixels to w*h RGB 8-bit sRGB pixels. */
void hs_tonemap_rgba(const hs_tonemap *tm, const float *rgba, uint32_t w, uint32_t h,
                     uint8_t *out_rgb);

/** Writes 8-bit RGB (rows top to bottom) as PNG. */
xrsc_result hs_write_png(const char *path, const uint8_t *rgb, uint32_t w, uint32_t h,
                         xrsc_diag *diag);
/**
 * Writes RGBA float pixels (rows top to bottom) as a colour PFM ("PF", the host's byte order
 * marked by the scale's sign, rows stored bottom to top as the format requires; alpha dropped).
 */
xrsc_result hs_write_pfm(const char *path, const float *rgba, uint32_t w, uint32_t h,
                         xrsc_diag *diag);
/**
 * Reads a colour PFM (either byte order) back into RGBA floats, rows top to bottom, alpha 1;
 * *out_rgba is malloc'ed. XRSC_ERROR_BAD_HEADER for anything but "PF" with sides 1..65536,
 * XRSC_ERROR_TRUNCATED_LINE when the file is shorter than its header says.
 */
xrsc_result hs_read_pfm(const char *path, float **out_rgba, uint32_t *out_w, uint32_t *out_h,
                        xrsc_diag *diag);

/** Places two w*h RGB images side by side into a (2w)*h RGB image (left eye on the left). */
void hs_side_by_side(const uint8_t *left, const uint8_t *right, uint32_t w, uint32_t h,
                     uint8_t *out_rgb);

#ifdef __cplusplus
}
#endif
