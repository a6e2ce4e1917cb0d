// SPDX-License-Identifier: MIT
/**
 * @file hs_file.c
 * @brief Whole-or-nothing output files (hs_file.h): temporary name, then rename(2), which
 *        POSIX makes atomic within one file system.
 */
#include "hs_file.h"

#include "u_diag.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>

bool hs_temp_path(const char *path, char *buf, size_t size)
{
    return (size_t)snprintf(buf, size, "%s%s", path, HS_TEMP_SUFFIX) < size;
}

xrsc_result hs_out_rename(const char *tmp, const char *path, xrsc_diag *diag)
{
    if (rename(tmp, path) == 0)
        return XRSC_OK;
    int err = errno;
    remove(tmp);
    return u_diag_set(diag, XRSC_ERROR_IO, path, 0, "", "cannot rename %s into place: %s", tmp,
                      strerror(err));
}

xrsc_result hs_out_open(hs_out_file *out, const char *path, xrsc_diag *diag)
{
    out->f = NULL;
    if ((size_t)snprintf(out->path, sizeof(out->path), "%s", path) >= sizeof(out->path) ||
        !hs_temp_path(path, out->tmp, sizeof(out->tmp)))
        return u_diag_set(diag, XRSC_ERROR_IO, path, 0, "", "path is too long");
    out->f = fopen(out->tmp, "wb");
    if (!out->f)
        return u_diag_set(diag, XRSC_ERROR_IO, path, 0, "", "cannot create %s: %s", out->tmp,
                          strerror(errno));
    return XRSC_OK;
}

xrsc_result hs_out_close(hs_out_file *out, bool ok, xrsc_diag *diag)
{
    if (!out->f)
        return XRSC_OK;
    bool written = !ferror(out->f);
    int err = 0;
    if (fclose(out->f) != 0) {
        written = false;
        err = errno;
    }
    out->f = NULL;
    if (!ok || !written) {
        remove(out->tmp);
        return ok ? u_diag_set(diag, XRSC_ERROR_IO, out->path, 0, "", "write failed%s%s",
                               err ? ": " : "", err ? strerror(err) : "")
                  : XRSC_OK;
    }
    return hs_out_rename(out->tmp, out->path, diag);
}
