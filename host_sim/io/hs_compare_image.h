// SPDX-License-Identifier: MIT
/**
 * @file hs_compare_image.h
 * @brief The picture of `xrsc compare A B` for one frame (issue 22 item 1: below the command):
 *        a title line, one row per eye with A, B and the heat map of |B - A| (RMS over R, G, B;
 *        black = equal), each labelled with the bitmap font (hs_font.h), and the heat map's
 *        colour scale.
 */
#pragma once

#include "hs_run_dir.h"

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** One frame of both eyes of runs A and B (RGBA floats, w x h each, rows top to bottom). */
typedef struct hs_compare_frame {
    const float *a[2], *b[2]; /**< [0] left, [1] right */
    uint32_t w, h;
    double relmse[2]; /**< B against A, printed in the heat maps' labels */
} hs_compare_frame;

/** How to draw it; zero fields are the defaults. */
typedef struct hs_compare_style {
    const char *title;  /**< the first line */
    hs_run_kind kind;   /**< HS_RUN_PNG: frames are re-encoded as read, else tone-mapped */
    double exposure;    /**< tone-mapping exposure of linear frames; 0: 1 */
} hs_compare_style;

/**
 * Composes the picture into *out_rgb (malloc'ed, *out_w x *out_h RGB8). *scale is the heat
 * map's full scale (RMS difference drawn white); when it is <= 0 it is set to the 99th
 * percentile of this frame's differences (at least 1e-6). Returns XRSC_ERROR_OUT_OF_MEMORY or
 * XRSC_OK.
 */
xrsc_result hs_compare_picture(const hs_compare_frame *fr, const hs_compare_style *style,
                               double *scale, uint8_t **out_rgb, uint32_t *out_w,
                               uint32_t *out_h);

#ifdef __cplusplus
}
#endif
