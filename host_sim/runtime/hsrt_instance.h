// SPDX-License-Identifier: MIT
/**
 * @file hsrt_instance.h
 * @brief The runtime's instance-level helpers (hsrt_instance.c), the one file that hsrt_entry.c,
 *        hsrt_session.c, hsrt_vulkan.c and hsrt_preview.c all use, so that none of them needs
 *        another's: entry dispatches to session and vulkan, session drives vulkan and the
 *        preview, and every one logs, reads the clock and queues events through here.
 */
#pragma once

#include "hsrt.h"

#include <stddef.h>

/** One row {"xrNAME", hsrt_xrNAME} of a table of OpenXR functions (xrGetInstanceProcAddr), for
 *  an X-macro list such as HSRT_SESSION_FUNCS. */
#define HSRT_X_PROC(n) {"xr" #n, (PFN_xrVoidFunction)hsrt_xr##n},

/** Logs "xrsc runtime: <function>: <message>" as an error and returns result. */
XrResult hsrt_fail(XrResult result, const char *function, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;
const char *hsrt_result_name(XrResult result);
/** Validates an XrInstance handle (not locked). */
hsrt_instance *hsrt_instance_from(XrInstance handle);
/** Queues a session state change (locked by the caller). */
void hsrt_push_state(hsrt_session *s, XrSessionState state);
/** Queues an event (locked by the caller); the oldest is dropped when the queue is full. */
void hsrt_push_event(hsrt_instance *inst, const void *event, size_t size);
/** The string of a path, NULL if the path is not one of this instance's. */
const char *hsrt_path_string(hsrt_instance *inst, XrPath path);
/** Monotonic clock in ns. */
XrTime hsrt_now_ns(void);
