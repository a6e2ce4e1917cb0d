// SPDX-License-Identifier: MIT
/**
 * @file hs_file.h
 * @brief Whole-or-nothing output files: written under a temporary name in the same folder and
 *        renamed into place, so a reader (or a run stopped by Ctrl-C) never sees a truncated or
 *        empty file under the final name.
 */
#pragma once

#include "xrsc/result.h"

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Appended to the final name for the temporary one (same folder, so rename is atomic). */
#define HS_TEMP_SUFFIX ".tmp"
/** Longest final path, terminator included. */
#define HS_OUT_PATH_MAX 1200

/** A file being written: f writes PATH.tmp until hs_out_close. */
typedef struct hs_out_file {
    FILE *f;
    char path[HS_OUT_PATH_MAX];
    char tmp[HS_OUT_PATH_MAX + sizeof(HS_TEMP_SUFFIX)];
    /** Set after hs_out_open: a successful hs_out_close leaves PATH.tmp for a frame set
     *  (hs_frame_set_commit renames it) instead of renaming it itself. */
    bool staged;
} hs_out_file;

/** Opens path + HS_TEMP_SUFFIX for writing (binary). XRSC_ERROR_IO naming path on failure. */
xrsc_result hs_out_open(hs_out_file *out, const char *path, xrsc_diag *diag);

/**
 * Closes the file; when ok and every write and the close succeeded, renames it onto its final
 * path (replacing an older file; staged: leaves it for the frame set), else removes the
 * temporary file. A failed write, close or rename is XRSC_ERROR_IO naming the final path and
 * the errno text (unless ok was false: then the caller's error stands and XRSC_OK is
 * returned). Accepts a file whose open failed (f NULL).
 */
xrsc_result hs_out_close(hs_out_file *out, bool ok, xrsc_diag *diag);

/**
 * For writers that take a file name (libraries that open the file themselves): the temporary
 * name of path (path + HS_TEMP_SUFFIX) into buf; false when it does not fit.
 */
bool hs_temp_path(const char *path, char *buf, size_t size);

/** Renames tmp onto path (XRSC_ERROR_IO naming path, tmp removed, on failure). */
xrsc_result hs_out_rename(const char *tmp, const char *path, xrsc_diag *diag);

/** The errno text of a failed write on f (its error flag set): flushing again gives the
 *  reason (ENOSPC, EFBIG, EIO, ...); "write error" when the system says nothing. */
const char *hs_write_error_text(FILE *f, int saved_errno);

/** Most files one frame writes: PNG, PFM and EXR of both eyes, and the side-by-side PNG. */
#define HS_FRAME_SET_MAX 8

/**
 * The files of one frame, written as a set so that a reader (or a run that ends, however it
 * ends) never finds a frame with only some of its files: each file is written whole under its
 * temporary name (the writers' hs_stage_* forms: PATH.tmp, left there), then
 * hs_frame_set_commit renames them all into place, or hs_frame_set_abort removes them all.
 * Zero-initialise; paths are added before their files are written.
 */
typedef struct hs_frame_set {
    uint32_t count;
    char path[HS_FRAME_SET_MAX][HS_OUT_PATH_MAX];
} hs_frame_set;

/** Records path as a member of the set (XRSC_ERROR_IO naming it when the set is full or the
 *  path too long). */
xrsc_result hs_frame_set_add(hs_frame_set *set, const char *path, xrsc_diag *diag);

/**
 * Renames every member's temporary file onto its path, in the order added, with SIGINT,
 * SIGTERM and SIGHUP blocked meanwhile (their handler may end the process: hs_run.h). When one rename
 * fails (the folder removed), the members already renamed and the temporary files left are
 * removed, and the error (XRSC_ERROR_IO) names that path and the errno text. Empties the set.
 */
xrsc_result hs_frame_set_commit(hs_frame_set *set, xrsc_diag *diag);

/** Removes every member's temporary file (a member that failed, or the run ended); empties
 *  the set. Accepts NULL. */
void hs_frame_set_abort(hs_frame_set *set);

#ifdef __cplusplus
}
#endif
