// SPDX-License-Identifier: MIT
/**
 * @file hs_args.c
 * @brief Command-line helpers of the `xrsc` commands (hs_args.h).
 */
#include "hs_args.h"

#include "u_diag.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/** Longest path hs_make_dirs accepts, terminator included. */
#define HS_MAKE_DIRS_MAX 1024

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

xrsc_result hs_make_dirs(const char *path, const char *field, xrsc_diag *diag)
{
    char buf[HS_MAKE_DIRS_MAX];
    if (path[0] == '\0' || (size_t)snprintf(buf, sizeof(buf), "%s", path) >= sizeof(buf))
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, path, 0, field,
                          "output folder name is empty or too long");
    for (char *p = buf + 1; *p; p++) {
        if (*p != '/')
            continue;
        *p = '\0';
        if (mkdir(buf, 0777) != 0 && errno != EEXIST)
            return u_diag_set(diag, XRSC_ERROR_IO, buf, 0, field, "cannot create folder: %s",
                              strerror(errno));
        *p = '/';
    }
    if (mkdir(buf, 0777) != 0 && errno != EEXIST)
        return u_diag_set(diag, XRSC_ERROR_IO, buf, 0, field, "cannot create folder: %s",
                          strerror(errno));
    return XRSC_OK;
}
