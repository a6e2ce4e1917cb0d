// SPDX-License-Identifier: MIT
/**
 * @file u_exr_common.h
 * @brief What the OpenEXR reader (u_exr.c) and the host's writer (host_sim/io/hs_exr.c) share
 *        on OpenEXRCore: the error handler that keeps the library's last message, the
 *        diagnostic built from it, and a channel's plane in the caller's interleaved layout.
 *
 * Internal to xrsc_util_exr and its users; includes <openexr.h>, so only targets that link
 * OpenEXR (PkgConfig::OPENEXR) include it.
 */
#pragma once

#include "xrsc/result.h"

#include <openexr.h>

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** The library's last error message for one context. A context's user data must start with
 *  one (u_exr_on_error writes it there). */
typedef struct u_exr_msg {
    char text[512];
} u_exr_msg;

/** An OpenEXRCore error handler (exr_context_initializer_t.error_handler_fn): keeps "MESSAGE
 *  (CODE NAME)" in the u_exr_msg at the start of the context's user data. */
void u_exr_on_error(exr_const_context_t ctxt, exr_result_t code, const char *msg);

/** Fills diag with code, name as the file and field "exr": "WHAT: the library's last message"
 *  (msg's, else rv's default message); returns code. */
xrsc_result u_exr_fail(xrsc_diag *diag, xrsc_result code, const char *name, const char *what,
                       exr_result_t rv, const u_exr_msg *msg);

/** One channel's source or destination in the caller's interleaved layout. */
typedef struct u_exr_plane {
    const char *name;
    uint8_t *base;        /**< first pixel of row 0; NULL: the channel is not present */
    int32_t pixel_stride; /**< bytes */
    int32_t line_stride;  /**< bytes */
} u_exr_plane;

/** The plane of p[0..n) with that channel name and a base, or NULL. */
const u_exr_plane *u_exr_find_plane(const u_exr_plane *p, int n, const char *name);

#ifdef __cplusplus
}
#endif
