// SPDX-License-Identifier: MIT
/**
 * @file hs_light_args.h
 * @brief The lighting options of `xrsc replay` (environment map, sun and sky) and their
 *        rows of its option table (HS_LIGHT_OPTS), kept apart from hs_replay_cmd.c.
 */
#pragma once

#include "hs_opt.h"
#include "xrsc/xrsc.h"

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/** The table rows (hs_opt.h) of the lighting options, in --help's order (after --env); parse
 *  is the command's parser, which calls hs_light_parse with the row's name. */
#define HS_LIGHT_OPTS(parse)                                                                       \
    {"--env-map", "FILE",                                                                          \
     "equirectangular Radiance .hdr or OpenEXR .exr environment (centre = -Z,\n"                  \
     "top = +Y), importance-sampled; replaces --env and the scene's environment",                  \
     parse, 0, NULL},                                                                              \
        {"--env-intensity", "X", "scales --env-map, or --sky's sun and sky [1]", parse, 0, NULL},  \
        {"--env-rotation", "DEG",                                                                  \
         "turns the map or sky about +Y (counter-clockwise from above) [0]", parse, 0, NULL},      \
        {"--sky", NULL,                                                                            \
         "Preetham sun and sky (seed 000 section 5.1) as the environment;\n"                      \
         "its sun (a 0.53 deg disk) replaces the scene's directional light",                       \
         parse, 0, NULL},                                                                          \
        {"--sky-turbidity", "T", "--sky: atmospheric turbidity, 1.7..10 [3]", parse, 0, NULL},     \
        {"--sun-dir", "X,Y,Z", "--sky: towards the sun, y >= 0 [the scene's sun, else 0.5,0.707,0.5]", \
         parse, 0, NULL}

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
