// SPDX-License-Identifier: MIT
/**
 * @file hs_light_args.c
 * @brief Parsing of the lighting options (hs_light_args.h).
 */
#include "hs_light_args.h"

#include "hs_args.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/** Largest accepted --env-intensity. */
#define HS_LIGHT_MAX_INTENSITY 1e6

int hs_light_parse(const char *cmd, const char *flag, const char *value, xrsc_scene_options *so)
{
    double d;
    if (!strcmp(flag, HS_LIGHT_FLAG_SKY)) {
        so->sky = true;
    } else if (!strcmp(flag, "--env-map")) {
        if (!value || !*value)
            return hs_bad_arg(cmd, flag, value, "expected a .hdr file");
        so->env_map_path = value;
    } else if (!strcmp(flag, "--env-intensity")) {
        if (!value || !hs_parse_f(value, &d) || !(d > 0.0) || d > HS_LIGHT_MAX_INTENSITY)
            return hs_bad_arg(cmd, flag, value, "expected a number in (0, 1e6]");
        so->env_intensity = (float)d;
    } else if (!strcmp(flag, "--env-rotation")) {
        if (!value || !hs_parse_f(value, &d) || !(fabs(d) <= 3600.0))
            return hs_bad_arg(cmd, flag, value, "expected degrees in [-3600, 3600]");
        so->env_rotation_deg = (float)d;
    } else if (!strcmp(flag, "--sky-turbidity")) {
        if (!value || !hs_parse_f(value, &d) || !(d >= 1.7 && d <= 10.0))
            return hs_bad_arg(cmd, flag, value, "expected 1.7..10");
        so->sky_turbidity = (float)d;
    } else if (!strcmp(flag, "--sun-dir")) {
        float x, y, z;
        char tail;
        if (!value || sscanf(value, "%f,%f,%f%c", &x, &y, &z, &tail) != 3 || !isfinite(x) ||
            !isfinite(y) || !isfinite(z) || y < 0.0f || x * x + y * y + z * z < 1e-12f)
            return hs_bad_arg(cmd, flag, value, "expected X,Y,Z (not zero, Y >= 0)");
        so->sun_direction_set = true;
        so->sun_direction[0] = x;
        so->sun_direction[1] = y;
        so->sun_direction[2] = z;
    } else {
        return -1;
    }
    return 0;
}
