// SPDX-License-Identifier: MIT
/**
 * @file hs_font.h
 * @brief A 5x7 bitmap font for labels drawn into images: the preview window's overlay, the
 *        panels of `xrsc compare`, and the tests that read those labels back pixel by pixel.
 *
 * Glyphs cover ASCII 32..95 (space, digits, upper-case letters, punctuation); lower-case
 * letters are drawn as upper case and every other character as '?'. A glyph is HS_FONT_W x
 * HS_FONT_H pixels; text advances HS_FONT_ADVANCE pixels per character (one blank column) and
 * is scaled by an integer factor (each font pixel a scale x scale square).
 */
#pragma once

#include <stdbool.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define HS_FONT_W 5u
#define HS_FONT_H 7u
#define HS_FONT_ADVANCE 6u
/** Line height in font pixels (two blank rows between lines). */
#define HS_FONT_LINE 9u

/** Whether pixel (x, y) of character c's glyph is set (x < HS_FONT_W, y < HS_FONT_H). */
bool hs_font_pixel(char c, uint32_t x, uint32_t y);

/** Width in image pixels of text drawn at `scale` (the last character's blank column
 *  excluded); 0 for "". */
uint32_t hs_font_text_width(const char *text, uint32_t scale);

/**
 * Draws text with its top-left corner at (x, y) into a w x h image of `channels` bytes per
 * pixel (3 or 4), writing colour[0..2] to the first three bytes of each set pixel (so the
 * caller orders the colour as the image does: RGB or BGR). Pixels outside the image are
 * skipped; unset glyph pixels are left as they are.
 */
void hs_font_draw(uint8_t *image, uint32_t w, uint32_t h, uint32_t channels, int32_t x, int32_t y,
                  uint32_t scale, const char *text, const uint8_t colour[3]);

/** Fills a rectangle (clipped to the image) with colour, as hs_font_draw writes pixels. */
void hs_font_fill(uint8_t *image, uint32_t w, uint32_t h, uint32_t channels, int32_t x, int32_t y,
                  uint32_t rw, uint32_t rh, const uint8_t colour[3]);

/**
 * The heat-map colour of t in [0, 1] (clamped): black, blue, magenta, orange, yellow, white,
 * increasing in luminance, so that 0 is black and the scale reads without a legend's help.
 */
void hs_heat_colour(float t, uint8_t out_rgb[3]);

#ifdef __cplusplus
}
#endif
