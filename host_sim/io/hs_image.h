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

/**
 * Automatic exposure (the default of `xrsc replay`; --exposure X overrides it), from all the
 * pixels of a stereo frame (both eyes, so they get one exposure):
 *   exposure = min(HS_AUTO_KEY / log-average luminance,
 *                  HS_AUTO_WHITE / the HS_AUTO_PERCENTILE of max(r, g, b)),
 * i.e. the log-average ("key", Reinhard et al. 2002) becomes middle grey unless that would
 * push the brightest large areas past HS_AUTO_WHITE (ACES maps it to 0.62, sRGB 0.81): with
 * the key alone a closed room with a dark ceiling and noisy zeros was blown out. The log2 of
 * the exposure is smoothed over frames with weight HS_AUTO_ADAPT for the new frame, so a
 * replay does not flicker; the first frame is taken as it is. Clamped to [HS_AUTO_MIN,
 * HS_AUTO_MAX]. Zero-initialise the state; one state per stream of frames.
 */
typedef struct hs_autoexposure {
    int frames;          /**< frames seen */
    double log2_exposure; /**< smoothed */
} hs_autoexposure;
#define HS_AUTO_KEY 0.18      /**< middle grey: the target of the log-average luminance */
#define HS_AUTO_WHITE 0.5     /**< the target of the bright percentile */
#define HS_AUTO_PERCENTILE 0.97
#define HS_AUTO_ADAPT 0.15    /**< weight of the new frame (about 6 frames to adapt) */
#define HS_AUTO_DELTA 1e-4    /**< added to each luminance before the log (black pixels) */
#define HS_AUTO_MIN (1.0 / 1024.0)
#define HS_AUTO_MAX 1024.0
/**
 * Updates ae with count images of w*h RGBA floats (the eyes of one frame; non-finite pixels
 * skipped) and returns the exposure for this frame.
 */
float hs_autoexposure_update(hs_autoexposure *ae, const float *const *rgba, uint32_t count,
                             uint32_t w, uint32_t h);

/** The sRGB transfer function (IEC 61966-2-1) of a display value, clamped to [0, 1] (NaN to
 *  0) and quantised to 8 bits. */
uint8_t hs_srgb8(float linear);
/** The inverse of the sRGB transfer function: the linear value of display value c in [0, 1]. */
float hs_srgb_to_linear(float c);

/** Converts w*h RGBA float pixels to w*h RGB 8-bit sRGB pixels. */
void hs_tonemap_rgba(const hs_tonemap *tm, const float *rgba, uint32_t w, uint32_t h,
                     uint8_t *out_rgb);

/** Writes 8-bit RGB (rows top to bottom) as PNG, whole or not at all (hs_file.h). */
xrsc_result hs_write_png(const char *path, const uint8_t *rgb, uint32_t w, uint32_t h,
                         xrsc_diag *diag);
/**
 * Writes RGBA float pixels (rows top to bottom) as a colour PFM, whole or not at all
 * (hs_file.h) ("PF", the host's byte order
 * marked by the scale's sign, rows stored bottom to top as the format requires; alpha dropped).
 */
xrsc_result hs_write_pfm(const char *path, const float *rgba, uint32_t w, uint32_t h,
                         xrsc_diag *diag);
/** As hs_write_png / hs_write_pfm, for a frame set (hs_file.h): the file is written whole as
 *  PATH.tmp and left there for hs_frame_set_commit. Write errors name path and the errno text. */
xrsc_result hs_stage_png(const char *path, const uint8_t *rgb, uint32_t w, uint32_t h,
                         xrsc_diag *diag);
xrsc_result hs_stage_pfm(const char *path, const float *rgba, uint32_t w, uint32_t h,
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
