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
} hs_out_file;

/** Opens path + HS_TEMP_SUFFIX for writing (binary). XRSC_ERROR_IO naming path on failure. */
xrsc_result hs_out_open(hs_out_file *out, const char *path, xrsc_diag *diag);

/**
 * Closes the file; when ok and every write and the close succeeded, renames it onto its final
 * path (replacing an older file), else removes the temporary file. A failed write, close or
 * rename is XRSC_ERROR_IO naming the final path (unless ok was false: then the caller's error
 * stands and XRSC_OK is returned). Accepts a file whose open failed (f NULL).
 */
xrsc_result hs_out_close(hs_out_file *out, bool ok, xrsc_diag *diag);

/**
 * For writers that take a file name (libraries that open the file themselves): the temporary
 * name of path (path + HS_TEMP_SUFFIX) into buf; false when it does not fit.
 */
bool hs_temp_path(const char *path, char *buf, size_t size);

/** Renames tmp onto path (XRSC_ERROR_IO naming path, tmp removed, on failure). */
xrsc_result hs_out_rename(const char *tmp, const char *path, xrsc_diag *diag);

#ifdef __cplusplus
}
#endif
