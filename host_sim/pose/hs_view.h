// SPDX-License-Identifier: MIT
/**
 * @file hs_view.h
 * @brief Where a replay's stream is placed in the scene (--viewpoint, --frame, the IPD of a
 *        tiny scene) and the hints a first frame that shows nothing gets, with their IDs.
 *
 * CPU only (the scene's xrsc_scene_info and numbers from the first frame), so that the rules
 * are unit-tested without a GPU; hs_replay.c applies them on both replay paths.
 */
#pragma once

#include "xrsc/xrsc.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* X(id, name): the warnings about the view. The name is printed in brackets at the start of
 * the warning ("warning [scene-too-small]: ..."), so scripts and tests match the ID, never
 * the text. */
#define HS_HINT_LIST(X)                                                                            \
    X(HS_HINT_NONE, "none")                                                                        \
    X(HS_HINT_VIEW_MISSES_SCENE, "view-misses-scene")                                              \
    X(HS_HINT_SCENE_TOO_SMALL, "scene-too-small")                                                  \
    X(HS_HINT_INSIDE_GEOMETRY, "inside-geometry")                                                  \
    X(HS_HINT_ENCLOSED_SCENE, "enclosed-scene")                                                    \
    X(HS_HINT_NO_LIGHT, "no-light")                                                                \
    X(HS_HINT_NARROWER_THAN_IPD, "narrower-than-ipd")

typedef enum hs_hint {
#define HS_HINT_ENUM(id, name) id,
    HS_HINT_LIST(HS_HINT_ENUM)
#undef HS_HINT_ENUM
        HS_HINT_COUNT
} hs_hint;

/** The hint's name (its ID in messages), "?" when out of range. */
const char *hs_hint_name(hs_hint hint);

/** --viewpoint: where the stream's first pose is placed (the default: the scene's viewpoint,
 *  i.e. its first camera or the documented default of xrsc_scene_info.viewpoint). */
typedef enum hs_viewpoint_kind {
    HS_VIEWPOINT_DEFAULT = 0,
    HS_VIEWPOINT_CAMERA,   /**< camera:N, the scene's N-th perspective camera (from 0) */
    HS_VIEWPOINT_POSITION, /**< x,y,z[:yaw]: there, looking down -Z turned by yaw */
    HS_VIEWPOINT_INSIDE,   /**< inside: ::hs_view_inside */
} hs_viewpoint_kind;

typedef struct hs_viewpoint {
    hs_viewpoint_kind kind;
    uint32_t camera;
    float position[3]; /**< metres, scene coordinates */
    float yaw_deg;     /**< about +Y, counter-clockwise seen from above; 0 looks down -Z */
} hs_viewpoint;

/**
 * Parses a --viewpoint value: "camera:N", "x,y,z", "x,y,z:yaw" (degrees) or "inside".
 * Errors: XRSC_ERROR_INVALID_ARGUMENT with field "--viewpoint" and what was expected.
 */
xrsc_result hs_viewpoint_parse(const char *text, hs_viewpoint *out, xrsc_diag *diag);

/** Looking down -Z turned by yaw_deg about +Y (counter-clockwise from above), at p. */
XrPosef hs_view_at(const float p[3], float yaw_deg);

/**
 * --viewpoint inside: the centre of the scene's bounds, looking down -Z (inside a room or a
 * sky box; a model there may need x,y,z instead).
 */
XrPosef hs_view_inside(const xrsc_scene_info *info);

/** The scene's width: the largest side of its bounds (m). */
double hs_scene_width_m(const xrsc_scene_info *info);

/**
 * --frame with eyes: the head looking down -Z at the bounds, at the nearest distance where
 * every corner of the bounds lies inside every side of both eyes' FOVs with the eyes ipd_m
 * apart (each eye ipd_m / 2 to the side of the head), so the bounds fill the view on at
 * least one side. The head is offset from the bounds' centre line so that the bounds'
 * middle is at the middle of the image, not on the eyes' axes (headset FOVs are asymmetric):
 * by h (t_a - t_b) / (t_a + t_b) per axis, h the half-extent and t_a, t_b the tangents of the
 * two sides' half-angles averaged over the eyes (left, right: x; down, up: y). With ipd_m 0
 * this is hs_frame_viewpoint (hs_replay.h).
 */
XrPosef hs_view_frame(const xrsc_scene_info *info, const XrFovf fov[2], double ipd_m);

/** IPD per metre of viewing distance that --frame gives a scene narrower than the IPD (the
 *  ratio of a 63 mm IPD at 0.63 m): its stereo then looks like a hand-held object's. */
#define HS_FRAME_IPD_PER_DISTANCE 0.1

/**
 * The IPD --frame uses: ipd_m, or, for a scene narrower than ipd_m (hs_scene_width_m), the
 * smaller of ipd_m and HS_FRAME_IPD_PER_DISTANCE x the distance hs_view_frame gives with
 * IPD 0 (the view of a 7 mm model would otherwise have each eye 31 mm to its side).
 */
double hs_frame_ipd_m(const xrsc_scene_info *info, const XrFovf fov[2], double ipd_m);

/** What the first frame showed and where it was seen from, for ::hs_first_frame_hint. */
typedef struct hs_first_frame {
    double background_fraction; /**< pixels of both eyes whose primary ray hit nothing */
    double black_fraction;      /**< pixels the 8-bit output rounds to 0 (hs_warn_if_black) */
    bool head_inside_bounds;    /**< the head was inside the scene's bounds */
    double scene_width_m;       /**< hs_scene_width_m */
    double distance_m;          /**< from the head to the bounds' centre */
    uint32_t camera_count;      /**< the scene's perspective cameras */
    bool viewpoint_inside;      /**< --viewpoint inside placed it (not suggested again) */
} hs_first_frame;

/** At least this fraction of background pixels is "almost all background". */
#define HS_HINT_BACKGROUND_MIN 0.95
/** At least this fraction of black pixels is a black frame (as hs_warn_if_black's). */
#define HS_HINT_BLACK_MIN 0.99
/** A scene narrower than this angle (width / distance, rad) seen from the head is too small
 *  (a few pixels) rather than out of view. */
#define HS_HINT_SMALL_ANGLE_RAD 0.05

/**
 * The hint for a first frame: almost all background → SCENE_TOO_SMALL (the scene spans less
 * than HS_HINT_SMALL_ANGLE_RAD: --frame) or VIEW_MISSES_SCENE (--frame); else black with
 * geometry filling the view → INSIDE_GEOMETRY (the head inside the bounds: --viewpoint
 * inside / camera:N / x,y,z) or ENCLOSED_SCENE (outside: the scene is wrapped in something
 * closed, a sky box or a room: --viewpoint inside); else black → NO_LIGHT; else NONE.
 */
hs_hint hs_first_frame_hint(const hs_first_frame *f);

/** The hint's message: what to try for this scene (no "warning" prefix, no ID), into buf. */
void hs_hint_message(hs_hint hint, const hs_first_frame *f, char *buf, size_t cap);

#ifdef __cplusplus
}
#endif
