// SPDX-License-Identifier: MIT
/**
 * @file hs_anim_args.c
 * @brief Parsing of --animation (hs_anim_args.h).
 */
#include "hs_anim_args.h"

#include "hs_args.h"

#include <string.h>

int hs_anim_parse(const char *cmd, const char *flag, const char *value, xrsc_scene_options *so)
{
    if (strcmp(flag, HS_ANIM_FLAG))
        return -1;
    if (!value || !value[0])
        return hs_bad_arg(cmd, flag, value, "expected first, all, none, a clip's name or index");
    so->animation = value;
    return 0;
}
