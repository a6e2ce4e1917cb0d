// SPDX-License-Identifier: MIT
/**
 * @file hs_file.c
 * @brief Whole-or-nothing output files (hs_file.h): temporary name, then rename(2), which
 *        POSIX makes atomic within one file system.
 */
#include "hs_file.h"

#include "u_diag.h"

#include <errno.h>
#include <pthread.h>
#include <signal.h>
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
    out->staged = false;
    if ((size_t)snprintf(out->path, sizeof(out->path), "%s", path) >= sizeof(out->path) ||
        !hs_temp_path(path, out->tmp, sizeof(out->tmp)))
        return u_diag_set(diag, XRSC_ERROR_IO, path, 0, "", "path is too long");
    out->f = fopen(out->tmp, "wb");
    if (!out->f)
        return u_diag_set(diag, XRSC_ERROR_IO, path, 0, "", "cannot create %s: %s", out->tmp,
                          strerror(errno));
    return XRSC_OK;
}

const char *hs_write_error_text(FILE *f, int saved_errno)
{
    /* stdio keeps the error flag but not the reason: a second flush of the data still
     * buffered fails again and sets errno, else the errno of the failed call stands. */
    errno = 0;
    if (f && fflush(f) != 0 && errno)
        return strerror(errno);
    return saved_errno ? strerror(saved_errno) : "write error";
}

xrsc_result hs_out_close(hs_out_file *out, bool ok, xrsc_diag *diag)
{
    if (!out->f)
        return XRSC_OK;
    int saved = errno;
    bool written = !ferror(out->f);
    const char *why = written ? NULL : hs_write_error_text(out->f, saved);
    if (written && fflush(out->f) != 0) {
        written = false;
        why = strerror(errno);
    }
    if (fclose(out->f) != 0 && written) {
        written = false;
        why = strerror(errno);
    }
    out->f = NULL;
    if (!ok || !written) {
        remove(out->tmp);
        return ok ? u_diag_set(diag, XRSC_ERROR_IO, out->path, 0, "", "cannot write %s: %s",
                               out->tmp, why)
                  : XRSC_OK;
    }
    if (out->staged)
        return XRSC_OK;
    return hs_out_rename(out->tmp, out->path, diag);
}

xrsc_result hs_frame_set_add(hs_frame_set *set, const char *path, xrsc_diag *diag)
{
    if (set->count >= HS_FRAME_SET_MAX ||
        (size_t)snprintf(set->path[set->count], HS_OUT_PATH_MAX, "%s", path) >= HS_OUT_PATH_MAX)
        return u_diag_set(diag, XRSC_ERROR_IO, path, 0, "",
                          "path too long, or more than %d files in one frame", HS_FRAME_SET_MAX);
    set->count++;
    return XRSC_OK;
}

/* Removes the temporary files of members [from, count). */
static void remove_temps(const hs_frame_set *set, uint32_t from)
{
    char tmp[HS_OUT_PATH_MAX + sizeof(HS_TEMP_SUFFIX)];
    for (uint32_t i = from; i < set->count; i++)
        if (hs_temp_path(set->path[i], tmp, sizeof(tmp)))
            remove(tmp);
}

xrsc_result hs_frame_set_commit(hs_frame_set *set, xrsc_diag *diag)
{
    char tmp[HS_OUT_PATH_MAX + sizeof(HS_TEMP_SUFFIX)];
    xrsc_result res = XRSC_OK;
    /* The signals that end a run (hs_run.h) wait until the set is renamed: a handler that
     * ends the process at once then finds the set whole or still all temporary. */
    sigset_t stop, old;
    sigemptyset(&stop);
    sigaddset(&stop, SIGINT);
    sigaddset(&stop, SIGTERM);
    sigaddset(&stop, SIGHUP);
    pthread_sigmask(SIG_BLOCK, &stop, &old);
    for (uint32_t i = 0; i < set->count; i++) {
        hs_temp_path(set->path[i], tmp, sizeof(tmp));
        if (rename(tmp, set->path[i]) == 0)
            continue;
        res = u_diag_set(diag, XRSC_ERROR_IO, set->path[i], 0, "",
                         "cannot rename %s into place: %s", tmp, strerror(errno));
        /* Roll back: the frame's files go together or not at all. */
        for (uint32_t j = 0; j < i; j++)
            remove(set->path[j]);
        remove_temps(set, i);
        break;
    }
    pthread_sigmask(SIG_SETMASK, &old, NULL);
    set->count = 0;
    return res;
}

void hs_frame_set_abort(hs_frame_set *set)
{
    if (!set)
        return;
    remove_temps(set, 0);
    set->count = 0;
}
