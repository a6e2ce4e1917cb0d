// SPDX-License-Identifier: MIT
/**
 * @file hs_views_csv.h
 * @brief views.csv: each frame's eye poses, fields of view and image sizes, written by the
 *        replay beside frames.csv and read by `xrsc metrics --stereo` (also from other engines).
 *
 * Format (README.md, "views.csv"): a header line naming the columns, then one row per frame and
 * eye, comma-separated, numbers as C's strtod reads them ("#" lines are comments):
 *
 *     frame,eye,display_time_ns,px,py,pz,qx,qy,qz,qw,angle_left,angle_right,angle_up,angle_down,width,height
 *
 * - frame: the frame number of the image files (frame_NNNNN_left.exr); eye: left | right.
 * - display_time_ns: the frame's display time on the replay's clock (informational).
 * - px, py, pz (metres), qx, qy, qz, qw (unit quaternion): the eye's pose in world (scene)
 *   space as an OpenXR XrPosef (eye to world; the eye looks down its -Z, +Y up), the pose the
 *   frame was rendered with.
 * - angle_left, angle_right, angle_up, angle_down (radians): the eye's OpenXR XrFovf
 *   (left and down negative for a symmetric view).
 * - width, height (pixels): the eye's image size.
 *
 * Columns are found by name in any order; display_time_ns, width and height may be left out
 * (the reader then takes the image's size) and other columns are ignored. Floats are written
 * with 9 significant digits, so a written float reads back bit for bit.
 */
#pragma once

#include "xrsc/result.h"
#include "xrsc/xrsc_metrics.h"

#include <stdint.h>
#include <stdio.h>

#ifdef __cplusplus
extern "C" {
#endif

/** The file's name in a run folder. */
#define HS_VIEWS_CSV "views.csv"
/** The header the replay writes. */
#define HS_VIEWS_CSV_HEADER                                                                        \
    "frame,eye,display_time_ns,px,py,pz,qx,qy,qz,qw,angle_left,angle_right,angle_up,angle_down,"   \
    "width,height"
/** A quaternion whose length is off 1 by more than this is refused (XRSC_ERROR_QUAT_NOT_UNIT). */
#define HS_VIEWS_QUAT_TOLERANCE 1e-3
/** Most rows read (two per frame). */
#define HS_VIEWS_MAX_ROWS (1u << 22)

/** Writes the header line (HS_VIEWS_CSV_HEADER and a newline). */
void hs_views_csv_header(FILE *f);

/** Writes one row: frame number, eye (0 left, 1 right), display time, pose, fov, size. */
void hs_views_csv_row(FILE *f, uint32_t frame, uint32_t eye, int64_t display_time_ns,
                      const XrPosef *pose, const XrFovf *fov, uint32_t width, uint32_t height);

/** One view read back; width/height 0 when the file has no such columns. */
typedef struct hs_view_row {
    uint32_t frame, eye;
    xrsc_metrics_camera camera;
} hs_view_row;

/** The rows of a views.csv, sorted by frame then eye. */
typedef struct hs_views_table {
    hs_view_row *rows;
    uint32_t count;
} hs_views_table;

/**
 * Reads path. Errors name the file, line and column: XRSC_ERROR_IO (cannot be read),
 * XRSC_ERROR_EMPTY_FILE, XRSC_ERROR_UNKNOWN_COLUMN (a required column missing from the header),
 * XRSC_ERROR_TRUNCATED_LINE, XRSC_ERROR_BAD_NUMBER (a field that is not a number, an eye other
 * than left/right, a frame/size that is not a whole number), XRSC_ERROR_NAN,
 * XRSC_ERROR_QUAT_NOT_UNIT, XRSC_ERROR_INVALID_ARGUMENT (a field of view that is not a frustum:
 * each angle within +-90 degrees, left < right, down < up; a frame and eye given twice),
 * XRSC_ERROR_FILE_TOO_LARGE (more than HS_VIEWS_MAX_ROWS rows). On error *out is empty.
 */
xrsc_result hs_views_csv_read(const char *path, hs_views_table *out, xrsc_diag *diag);

/** The row of frame and eye, or NULL. */
const hs_view_row *hs_views_find(const hs_views_table *t, uint32_t frame, uint32_t eye);

/** Frees the rows (accepts an empty table). */
void hs_views_table_free(hs_views_table *t);

#ifdef __cplusplus
}
#endif
