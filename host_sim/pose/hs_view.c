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

/**
 * Distance along +Z from the centre at which a sphere of radius r fits one side of an eye's
 * frustum: the side's plane through the eye at half-angle ang (towards the side), the centre
 * offset by x towards that side from the eye's axis: D sin(ang) - x cos(ang) >= r.
 */
static double side_distance(double r, double x, double ang)
{
    return (r + x * cos(ang)) / sin(ang);
}

XrPosef hs_view_frame(const xrsc_scene_info *info, const XrFovf fov[2], double ipd_m)
{
    double c[3], r = bounds_sphere(info, c), dist = 0.0;
    for (int e = 0; e < 2; e++) {
        /* the left eye (0) sits at -ipd/2: the centre is ipd/2 to its right */
        double x = e == 0 ? 0.5 * ipd_m : -0.5 * ipd_m;
        const double ang[4] = {-fov[e].angleLeft, fov[e].angleRight, fov[e].angleUp,
                               -fov[e].angleDown};
        const double off[4] = {-x, x, 0.0, 0.0};
        for (int k = 0; k < 4; k++)
            if (ang[k] > 0.0) /* as hs_frame_viewpoint: wider than 90 degrees counts as 90 */
                dist = fmax(dist, side_distance(r, off[k], fmin(ang[k], 0.5 * HS_VIEW_PI)));
    }
    if (!(r > 0.0)) dist = 1.0;
    float p[3] = {(float)c[0], (float)c[1], (float)(c[2] + dist)};
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
