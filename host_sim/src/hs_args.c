// SPDX-License-Identifier: MIT
/**
 * @file hs_args.c
 * @brief Command-line helpers of the `xrsc` commands (hs_args.h).
 */
#include "hs_args.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int hs_bad_arg(const char *cmd, const char *flag, const char *value, const char *why)
{
    fprintf(stderr, "%s: error: %s%s%s: %s (see %s --help)\n", cmd, flag, value ? " " : "",
            value ? value : "", why, cmd);
    return HS_EXIT_BAD_ARGS;
}

bool hs_parse_u32(const char *s, uint32_t *out)
{
    char *end;
    errno = 0;
    unsigned long v = strtoul(s, &end, 10);
    if (errno || end == s || *end || v > 0xFFFFFFFFul || s[0] == '-')
        return false;
    *out = (uint32_t)v;
    return true;
}

bool hs_parse_f(const char *s, double *out)
{
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (errno || end == s || *end || v != v)
        return false;
    *out = v;
    return true;
}

bool hs_arg_in(const char *flag, const char *const *list, size_t count)
{
    for (size_t k = 0; k < count; k++)
        if (!strcmp(flag, list[k]))
            return true;
    return false;
}
