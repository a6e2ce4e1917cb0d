// SPDX-License-Identifier: MIT
/**
 * @file hs_anim_args.h
 * @brief `--animation NAME|INDEX|first|all|none` (issue 21): the clip that plays, shared by
 *        `xrsc replay` (both paths) and `xrsc bench`, with its --help text.
 */
#pragma once

#include "xrsc/xrsc.h"

#ifdef __cplusplus
extern "C" {
#endif

/** The option's name, and its value that run.conf records when it is not given. */
#define HS_ANIM_FLAG "--animation"
#define HS_ANIM_DEFAULT "first"

/** The --help lines of --animation. */
#define HS_ANIM_USAGE                                                                              \
    "  --animation A       the clip that plays, looping at the display time: first (the file's\n"  \
    "                      first clip) | all (every clip at once) | none | a clip's name or\n"     \
    "                      index (xrsc scene info FILE lists them) [first]\n"

/**
 * Parses --animation's value into so->animation (the text is kept, not copied: it must outlive
 * the scene load). Which clips exist is checked when the scene loads
 * (XRSC_ERROR_ANIMATION_UNKNOWN). Returns -1 when flag is not --animation, 0 when parsed, else
 * the exit code of hs_bad_arg (an empty value).
 */
int hs_anim_parse(const char *cmd, const char *flag, const char *value, xrsc_scene_options *so);

#ifdef __cplusplus
}
#endif
