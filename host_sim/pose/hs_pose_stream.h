// SPDX-License-Identifier: MIT
/**
 * @file hs_pose_stream.h
 * @brief Head-pose streams: the canonical format (poses/README.md), importers for real
 *        captures, interpolation at display times, and anchoring into a scene.
 *
 * All poses are in OpenXR axes (right-handed, +Y up, -Z forward, metres) with timestamps in
 * nanoseconds relative to the stream's first sample (which is at t = 0).
 */
#pragma once

#include "xrsc/result.h"
#include "xrsc/xrsc_math.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Files (and buffers) larger than this are rejected with XRSC_ERROR_FILE_TOO_LARGE, unless
 *  hs_pose_load_options.max_bytes says otherwise (xrsc --max-pose-bytes). */
#define HS_POSE_MAX_FILE_BYTES (1ull << 30)
/** Longest line kept when a file is read line by line; the rest of a longer line is skipped
 *  (no valid line comes near it: fields are at most 64 characters). */
#define HS_POSE_MAX_LINE_CHARS 65536

typedef enum hs_pose_format {
    HS_POSE_FORMAT_AUTO = 0, /**< by header line / extension */
    HS_POSE_FORMAT_XRSC,     /**< canonical "xrsc-poses 1" text */
    HS_POSE_FORMAT_PRED6DOF, /**< HoloLens CSV: timestamp(.NET ticks),x,y,z,qx,qy,qz,qw; LH +Z fwd */
    HS_POSE_FORMAT_360VIDEO, /**< "timestamp viewpoint w x y z": seconds, orientation only */
    HS_POSE_FORMAT_LIBRNR,   /**< librnr's OpenXR trace: "t_ns type path ..." records; per-eye
                              *   views (`v`) with FOV, or head spaces (`s`) */
    HS_POSE_FORMAT_COLUMNS,  /**< a delimited file read with ::hs_pose_columns (never detected) */
} hs_pose_format;

typedef struct hs_pose_sample {
    int64_t time_ns;
    XrPosef pose;
} hs_pose_sample;

/**
 * The two eye views recorded with a head sample (librnr `v` records): eye poses in the
 * stream's coordinates and the per-eye field of view the recording runtime reported.
 */
typedef struct hs_view_sample {
    XrPosef pose[2]; /**< [0] left, [1] right */
    XrFovf fov[2];
} hs_view_sample;

typedef struct hs_pose_stream {
    hs_pose_sample *samples;
    /** NULL, or `count` entries parallel to samples: the recorded eye views. The head pose of
     *  such a sample is derived from them (poses/README.md, "Importer: librnr"). Not written
     *  by hs_pose_stream_save (the canonical format v1 has head poses only). */
    hs_view_sample *views;
    size_t count;
    bool orientation_only; /**< positions carry no information (3-DoF capture) */
    hs_pose_format format; /**< the format it was read from */
    uint32_t dropped_duplicates; /**< samples dropped because their timestamp repeated */
} hs_pose_stream;

/**
 * Column import for CSV/TSV exports of common tools (Unity, pandas, notebooks): which column
 * holds what, the time unit and the handedness. See poses/README.md, "Import by columns".
 * Zero-initialised means "not used".
 */
typedef enum hs_pose_time_unit {
    HS_POSE_TIME_S = 0, /**< seconds (decimal) — the default */
    HS_POSE_TIME_MS,
    HS_POSE_TIME_US,
    HS_POSE_TIME_NS,    /**< integer nanoseconds */
    HS_POSE_TIME_TICKS, /**< integer .NET ticks (100 ns) */
} hs_pose_time_unit;

typedef enum hs_pose_handedness {
    HS_POSE_RIGHT = 0,     /**< OpenXR/glTF axes: right-handed, +Y up, -Z forward */
    HS_POSE_LEFT_UNITY,    /**< Unity: left-handed, +Y up, +Z forward (z and qx, qy negated) */
} hs_pose_handedness;

/** Column roles; HS_POSE_COL_SKIP ignores a column. */
typedef enum hs_pose_col_role {
    HS_POSE_COL_SKIP = 0,
    HS_POSE_COL_T,
    HS_POSE_COL_X,
    HS_POSE_COL_Y,
    HS_POSE_COL_Z,
    HS_POSE_COL_QX,
    HS_POSE_COL_QY,
    HS_POSE_COL_QZ,
    HS_POSE_COL_QW,
    HS_POSE_COL_ROLE_COUNT
} hs_pose_col_role;

#define HS_POSE_MAX_COLUMNS 32

typedef struct hs_pose_columns {
    uint32_t count;                           /**< 0: column import not used */
    uint8_t role[HS_POSE_MAX_COLUMNS];        /**< hs_pose_col_role of file column i */
    hs_pose_time_unit time_unit;
    hs_pose_handedness handedness;
} hs_pose_columns;

/**
 * Parses a column list such as "t,x,y,z,qx,qy,qz,qw" (any order; names t|time, x|px, y|py,
 * z|pz, qx, qy, qz, qw; "_" or "skip" for a column to ignore) and the unit ("s", "ms", "us",
 * "ns", "ticks"; NULL = s) and handedness ("right", "left-unity"; NULL = right) flags.
 * Every role must appear exactly once (qx..qw are required; x, y, z may all be left out for an
 * orientation-only stream). Errors: XRSC_ERROR_INVALID_ARGUMENT with the flag as the field.
 */
xrsc_result hs_pose_columns_parse(const char *spec, const char *time_unit,
                                  const char *handedness, hs_pose_columns *out,
                                  xrsc_diag *diag);

/**
 * Parses a delimited text file with the given columns: the delimiter is detected from the
 * first content line (tab, then ';', then ',', else runs of spaces); a first line with a
 * field that is not a number is a header and skipped; a file with exactly one column more
 * than `columns` names has its first column (a pandas/Unity row index) skipped. Lines starting
 * with '#' are comments. Errors name the file, line and column (e.g. "qx (column 5)").
 */
xrsc_result hs_pose_stream_parse_columns(const char *name, const char *data, size_t size,
                                         const hs_pose_columns *columns, hs_pose_stream **out,
                                         xrsc_diag *diag);
/** Reads a file (the checks of hs_pose_stream_load) and parses it with columns. */
xrsc_result hs_pose_stream_load_columns(const char *path, const hs_pose_columns *columns,
                                        hs_pose_stream **out, xrsc_diag *diag);

/** A short lower-case name of the format ("auto", "xrsc", "pred6dof", "360video", "librnr"). */
const char *hs_pose_format_name(hs_pose_format format);
/** The format named auto, xrsc, pred6dof, 360video or librnr (the --pose-format values);
 *  false for anything else (*out unchanged). */
bool hs_pose_format_from_name(const char *name, hs_pose_format *out);

/** How a file is loaded (zero: detected format, HS_POSE_MAX_FILE_BYTES). */
typedef struct hs_pose_load_options {
    hs_pose_format format;          /**< AUTO: detected from the first content line */
    const hs_pose_columns *columns; /**< non-NULL: read by these columns (format ignored) */
    uint64_t max_bytes;             /**< larger files: XRSC_ERROR_FILE_TOO_LARGE; 0: default */
} hs_pose_load_options;

/**
 * Loads a stream from a file, read line by line (never whole into memory): its size is checked
 * against the limit before anything is read, and its header (the first content line: the
 * format detected, or the forced format's header) before any other line, so a file that is not
 * a pose stream is refused after its first line however large it is.
 */
xrsc_result hs_pose_stream_load_with(const char *path, const hs_pose_load_options *opt,
                                     hs_pose_stream **out, xrsc_diag *diag);

/** Loads a stream; on error returns a negative result with file/line/field in diag. */
xrsc_result hs_pose_stream_load(const char *path, hs_pose_format format, hs_pose_stream **out,
                                xrsc_diag *diag);
/** Parses from memory (the same rules); name is used in diagnostics. */
xrsc_result hs_pose_stream_parse(const char *name, const char *data, size_t size,
                                 hs_pose_format format, hs_pose_stream **out, xrsc_diag *diag);
/** Writes the canonical format. */
xrsc_result hs_pose_stream_save(const hs_pose_stream *stream, const char *path, xrsc_diag *diag);
void hs_pose_stream_destroy(hs_pose_stream **stream);

/** Duration (last sample time) in ns. */
int64_t hs_pose_stream_duration_ns(const hs_pose_stream *stream);

/** How a lookup was answered (as Monado's relation history). */
typedef enum hs_lookup {
    HS_LOOKUP_EXACT,        /**< a sample at exactly that time */
    HS_LOOKUP_INTERPOLATED, /**< between two samples (lerp + slerp with hemisphere check) */
    HS_LOOKUP_CLAMPED,      /**< before the first or after the last sample: held */
} hs_lookup;

/** Head pose at time_ns. */
hs_lookup hs_pose_stream_sample(const hs_pose_stream *stream, int64_t time_ns, XrPosef *out_pose);

/**
 * Eye views at time_ns for a stream that carries them (stream->views != NULL): eye poses
 * interpolated as head poses are, FOV angles linearly; returns the lookup kind. For a stream
 * without views it returns HS_LOOKUP_CLAMPED and leaves the outputs untouched.
 */
hs_lookup hs_pose_stream_sample_views(const hs_pose_stream *stream, int64_t time_ns,
                                      hs_view_sample *out_views);

/**
 * The two eyes to render at time_ns, as the replay (hs_replay.c) and the runtime's
 * xrLocateViews (host_sim/runtime) both place them: a stream with recorded views
 * (stream->views) gives those (hs_pose_stream_sample_views: the recording headset's eye poses
 * and per-eye FOVs; the headset's IPD and FOVs are not used); any other stream gives the
 * headset's eyes (xrsc_headset_eye_poses: ±IPD/2 along the head's +X) at the interpolated head
 * pose with the headset's FOVs. Returns how the head pose was looked up.
 */
hs_lookup hs_pose_stream_eyes(const hs_pose_stream *stream, const xrsc_headset *headset,
                              int64_t time_ns, hs_view_sample *out_eyes);

/**
 * Re-anchors the stream in place so that its first pose becomes `viewpoint`:
 * every pose p becomes viewpoint * inverse(first) * p (recorded eye views too). For
 * orientation-only streams the position of every sample is set to viewpoint's position.
 */
void hs_pose_stream_anchor(hs_pose_stream *stream, XrPosef viewpoint);

#ifdef __cplusplus
}
#endif
