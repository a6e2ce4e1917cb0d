// SPDX-License-Identifier: MIT
/**
 * @file hs_view.c
 * @brief --viewpoint, --frame with eyes, the IPD of a tiny scene, first-frame hints (hs_view.h).
 */
#include "hs_view.h"

#include "u_diag.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define HS_VIEW_PI 3.14159265358979323846

static const char *const hint_names[] = {
#define HS_HINT_NAME(id, name) name,
    HS_HINT_LIST(HS_HINT_NAME)
#undef HS_HINT_NAME
};

const char *hs_hint_name(hs_hint hint)
{
    return hint >= 0 && hint < HS_HINT_COUNT ? hint_names[hint] : "?";
}

/** Parses all of s as a finite float. */
static bool parse_float(const char *s, const char *end, float *out)
{
    char buf[64];
    size_t n = (size_t)(end - s);
    if (n == 0 || n >= sizeof buf) return false;
    memcpy(buf, s, n);
    buf[n] = '\0';
    char *e;
    errno = 0;
    double v = strtod(buf, &e);
    if (*e || errno || !isfinite(v) || fabs(v) > 1e12) return false;
    *out = (float)v;
    return true;
}

static xrsc_result bad_viewpoint(xrsc_diag *diag, const char *text, const char *why)
{
    return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "--viewpoint", "'%s': %s", text,
                      why);
}

xrsc_result hs_viewpoint_parse(const char *text, hs_viewpoint *out, xrsc_diag *diag)
{
    memset(out, 0, sizeof(*out));
    if (!text || !*text)
        return bad_viewpoint(diag, text ? text : "", "expected camera:N, x,y,z[:yaw] or inside");
    if (!strcmp(text, "inside")) {
        out->kind = HS_VIEWPOINT_INSIDE;
        return XRSC_OK;
    }
    if (!strncmp(text, "camera:", 7)) {
        char *e;
        errno = 0;
        unsigned long n = strtoul(text + 7, &e, 10);
        if (text[7] < '0' || text[7] > '9' || *e || errno || n > UINT32_MAX)
            return bad_viewpoint(diag, text, "camera:N needs N, a camera index from 0");
        out->kind = HS_VIEWPOINT_CAMERA;
        out->camera = (uint32_t)n;
        return XRSC_OK;
    }
    const char *colon = strchr(text, ':'), *end = colon ? colon : text + strlen(text);
    const char *p = text;
    for (int a = 0; a < 3; a++) {
        const char *comma = a < 2 ? memchr(p, ',', (size_t)(end - p)) : end;
        if (!comma || !parse_float(p, comma, &out->position[a]))
            return bad_viewpoint(diag, text, "expected camera:N, x,y,z[:yaw] (metres, degrees) "
                                             "or inside");
        p = comma + 1;
    }
    if (colon && !parse_float(colon + 1, colon + strlen(colon), &out->yaw_deg))
        return bad_viewpoint(diag, text, "the yaw after ':' must be a number of degrees");
    out->kind = HS_VIEWPOINT_POSITION;
    return XRSC_OK;
}

XrPosef hs_view_at(const float p[3], float yaw_deg)
{
    double half = 0.5 * yaw_deg * HS_VIEW_PI / 180.0;
    XrPosef pose = {.orientation = {0.0f, (float)sin(half), 0.0f, (float)cos(half)},
                    .position = {p[0], p[1], p[2]}};
    return pose;
}

XrPosef hs_view_inside(const xrsc_scene_info *info)
{
    float c[3];
    for (int a = 0; a < 3; a++) c[a] = 0.5f * (info->bounds_min[a] + info->bounds_max[a]);
    return hs_view_at(c, 0.0f);
}

double hs_scene_width_m(const xrsc_scene_info *info)
{
    double w = 0.0;
    for (int a = 0; a < 3; a++) w = fmax(w, (double)info->bounds_max[a] - info->bounds_min[a]);
    return w;
}

/** Radius of the bounds' enclosing sphere and its centre. */
static double bounds_sphere(const xrsc_scene_info *info, double c[3])
{
    double r2 = 0.0;
    for (int a = 0; a < 3; a++) {
        c[a] = 0.5 * ((double)info->bounds_min[a] + info->bounds_max[a]);
        double h = 0.5 * ((double)info->bounds_max[a] - info->bounds_min[a]);
        r2 += h * h;
    }
    return sqrt(r2);
}

/** Half-angles of a side of the view are clamped to this (a side at 90 degrees or wider
 *  would never bound the scene): tan(89 degrees). */
#define HS_FRAME_MAX_TAN 57.29
/** The nearest corner of the bounds stays at least this fraction of the bounds' radius in
 *  front of the eyes. */
#define HS_FRAME_MIN_DEPTH 0.05

/** tan of a side's half-angle towards that side, 0 for a side on the far side of the axis. */
static double side_tan(double ang)
{
    return ang > 0.0 ? fmin(tan(fmin(ang, 0.5 * HS_VIEW_PI)), HS_FRAME_MAX_TAN) : 0.0;
}

/**
 * The head's offset (x, y) from the bounds' centre that puts the bounds' middle at the middle
 * of the image rather than on the view axis: the views of headsets are asymmetric (wider
 * towards the temple and downwards), so a box of half-extents h on the axis would sit off the
 * image's centre. A flat box fills both sides equally when (h - s) / t_near = (h + s) / t_far,
 * i.e. s = h (t_a - t_b) / (t_a + t_b), with the tangents averaged over the two eyes.
 */
static void frame_offset(const XrFovf fov[2], const double h[3], double s[2])
{
    double tl = 0.0, tr = 0.0, tu = 0.0, td = 0.0;
    for (int e = 0; e < 2; e++) {
        tl += 0.5 * side_tan(-fov[e].angleLeft), tr += 0.5 * side_tan(fov[e].angleRight);
        tu += 0.5 * side_tan(fov[e].angleUp), td += 0.5 * side_tan(-fov[e].angleDown);
    }
    s[0] = tl + tr > 0.0 ? h[0] * (tl - tr) / (tl + tr) : 0.0;
    s[1] = tu + td > 0.0 ? h[1] * (td - tu) / (tu + td) : 0.0;
}

/**
 * Distance along +Z from the centre's plane at which every corner of the bounds (half-extents
 * h about the centre) lies inside every side of both eyes' frustums, the head at offset s
 * from the centre and the eyes ipd_m apart: a corner at depth d and at l beyond the eye's
 * axis towards a side of half-angle tangent t is inside when d t >= l.
 */
static double frame_distance(const XrFovf fov[2], const double h[3], const double s[2],
                             double ipd_m)
{
    double r = sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
    double dist = h[2] + HS_FRAME_MIN_DEPTH * r;
    for (int e = 0; e < 2; e++) {
        double ex = s[0] + (e == 0 ? -0.5 : 0.5) * ipd_m; /* the eye, from the centre */
        const double t[4] = {side_tan(-fov[e].angleLeft), side_tan(fov[e].angleRight),
                             side_tan(fov[e].angleUp), side_tan(-fov[e].angleDown)};
        for (int k = 0; k < 8; k++) {
            double x = (k & 1 ? h[0] : -h[0]) - ex, y = (k & 2 ? h[1] : -h[1]) - s[1];
            double z = k & 4 ? h[2] : -h[2];
            const double beyond[4] = {-x, x, y, -y};
            for (int side = 0; side < 4; side++)
                if (t[side] > 0.0) dist = fmax(dist, z + beyond[side] / t[side]);
        }
    }
    return dist;
}

XrPosef hs_view_frame(const xrsc_scene_info *info, const XrFovf fov[2], double ipd_m)
{
    double c[3], h[3], s[2];
    double r = bounds_sphere(info, c);
    for (int a = 0; a < 3; a++) h[a] = 0.5 * ((double)info->bounds_max[a] - info->bounds_min[a]);
    frame_offset(fov, h, s);
    double dist = r > 0.0 ? frame_distance(fov, h, s, ipd_m) : 1.0;
    if (!(r > 0.0)) s[0] = s[1] = 0.0;
    float p[3] = {(float)(c[0] + s[0]), (float)(c[1] + s[1]), (float)(c[2] + dist)};
    return hs_view_at(p, 0.0f);
}

double hs_frame_ipd_m(const xrsc_scene_info *info, const XrFovf fov[2], double ipd_m)
{
    if (!(hs_scene_width_m(info) < ipd_m)) return ipd_m;
    double c[3];
    bounds_sphere(info, c);
    XrPosef p = hs_view_frame(info, fov, 0.0);
    double d = (double)p.position.z - c[2];
    return fmin(ipd_m, HS_FRAME_IPD_PER_DISTANCE * d);
}

hs_hint hs_first_frame_hint(const hs_first_frame *f)
{
    if (f->background_fraction >= HS_HINT_BACKGROUND_MIN) {
        bool small = f->distance_m > 0.0 && f->scene_width_m / f->distance_m < HS_HINT_SMALL_ANGLE_RAD;
        return small ? HS_HINT_SCENE_TOO_SMALL : HS_HINT_VIEW_MISSES_SCENE;
    }
    if (f->black_fraction < HS_HINT_BLACK_MIN) return HS_HINT_NONE;
    if (f->background_fraction <= 1.0 - HS_HINT_BACKGROUND_MIN)
        return f->head_inside_bounds ? HS_HINT_INSIDE_GEOMETRY : HS_HINT_ENCLOSED_SCENE;
    return HS_HINT_NO_LIGHT;
}

/** "camera:0..N-1" advice when the scene has cameras, else "". */
static void camera_advice(const hs_first_frame *f, char *buf, size_t cap)
{
    if (f->camera_count == 1)
        snprintf(buf, cap, ", --viewpoint camera:0 (its camera)");
    else if (f->camera_count > 1)
        snprintf(buf, cap, ", --viewpoint camera:0..%u (its cameras)", f->camera_count - 1);
    else
        buf[0] = '\0';
}

void hs_hint_message(hs_hint hint, const hs_first_frame *f, char *buf, size_t cap)
{
    char cams[96];
    camera_advice(f, cams, sizeof cams);
    double pct = 100.0 * f->background_fraction;
    switch (hint) {
    case HS_HINT_SCENE_TOO_SMALL:
        snprintf(buf, cap,
                 "frame 0 is %.1f %% background: the scene is %.3g m across, seen from %.3g m "
                 "it is a few pixels; try --frame (it fits the scene to the view at any size)",
                 pct, f->scene_width_m, f->distance_m);
        break;
    case HS_HINT_VIEW_MISSES_SCENE:
        snprintf(buf, cap,
                 "frame 0 is %.1f %% background: the view misses the scene (%.3g m across, "
                 "its centre %.3g m away); try --frame%s, or --viewpoint x,y,z[:yaw]",
                 pct, f->scene_width_m, f->distance_m, cams);
        break;
    case HS_HINT_INSIDE_GEOMETRY:
        snprintf(buf, cap,
                 "frame 0 is black and filled with geometry: the view starts inside something "
                 "closed that no light reaches; try %s--viewpoint x,y,z[:yaw]%s, light inside "
                 "it (an emissive material or a light), or --frame to see it from outside",
                 f->viewpoint_inside ? "" : "--viewpoint inside (the centre of the scene), ",
                 cams);
        break;
    case HS_HINT_ENCLOSED_SCENE:
        snprintf(buf, cap,
                 "frame 0 is black and filled with geometry seen from outside: the scene is "
                 "wrapped in something closed (a sky box or a room); try --viewpoint inside%s "
                 "or --viewpoint x,y,z[:yaw]",
                 cams);
        break;
    case HS_HINT_NO_LIGHT:
        snprintf(buf, cap,
                 "frame 0 is %.1f %% black: no light reaches the view; try --env 0.8,0.8,0.8, "
                 "--sky or --env-map FILE (a file's sun turns the default studio light off), "
                 "or --exposure",
                 100.0 * f->black_fraction);
        break;
    default:
        snprintf(buf, cap, "%s", "");
        break;
    }
}
