// SPDX-License-Identifier: MIT
/**
 * @file hs_light_args.h
 * @brief The lighting options of `xrsc replay` (environment map, sun and sky) and their
 *        --help text, kept apart from main.c's parse loop.
 */
#pragma once

#include "xrsc/xrsc.h"

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Lighting options that take a value (for the command's value-option list). */
extern const char *const hs_light_value_options[];
extern const size_t hs_light_value_option_count;

/** The --help lines of the lighting options (right after the --env line). */
#define HS_LIGHT_USAGE                                                                             \
    "                      (a scene without one and without a directional light: the built-in\n" \
    "                      studio environment, emissive materials notwithstanding; 1,1,1 is\n" \
    "                      the grey of earlier versions)\n"                                  \
    "  --env-map FILE      equirectangular Radiance .hdr environment (centre = -Z, top = +Y),\n" \
    "                      importance-sampled; replaces --env and the scene's environment\n"     \
    "  --env-intensity X   scales --env-map, or --sky's sun and sky [1]\n"                     \
    "  --env-rotation DEG  turns the map or sky about +Y (counter-clockwise from above) [0]\n"    \
    "  --sky               Preetham sun and sky (seed 000 section 5.1) as the environment;\n"    \
    "                      its sun (a 0.53 deg disk) replaces the scene's directional light\n"   \
    "  --sky-turbidity T   --sky: atmospheric turbidity, 1.7..10 [3]\n"                           \
    "  --sun-dir X,Y,Z     --sky: towards the sun, y >= 0 [the scene's sun, else 0.5,0.707,0.5]\n"

/** Flags (no value) of the lighting options. */
#define HS_LIGHT_FLAG_SKY "--sky"

/**
 * Parses one lighting option (flag as typed, value NULL for --sky) into so. Returns -1 when
 * flag is not a lighting option, 0 when parsed, else the exit code of hs_bad_arg (printed as
 * cmd's error).
 */
int hs_light_parse(const char *cmd, const char *flag, const char *value, xrsc_scene_options *so);

#ifdef __cplusplus
}
#endif
