// SPDX-License-Identifier: MIT
/**
 * @file hsrt_instance.c
 * @brief The runtime's instance-level helpers (hsrt_instance.h): failure logging, result
 *        names, the clock, XrInstance handles, the event queue and path strings. The bottom
 *        of the runtime: entry, session, vulkan and preview call it; it calls none of them.
 */
#include "hsrt_instance.h"

#include "u_diag.h"

#include <openxr/openxr_reflection.h>

#include <stdarg.h>
#include <string.h>
#include <time.h>

XrResult hsrt_fail(XrResult result, const char *function, const char *fmt, ...)
{
    char msg[768];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof(msg), fmt, ap);
    va_end(ap);
    U_LOG_E("runtime: %s: %s [%s]", function, msg, hsrt_result_name(result));
    return result;
}

const char *hsrt_result_name(XrResult result)
{
    switch (result) {
#define HSRT_X_RESULT(name, value)                                                                 \
    case name:                                                                                     \
        return #name;
        XR_LIST_ENUM_XrResult(HSRT_X_RESULT)
#undef HSRT_X_RESULT
    default:
        return NULL;
    }
}

XrTime hsrt_now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (XrTime)ts.tv_sec * 1000000000 + ts.tv_nsec;
}

hsrt_instance *hsrt_instance_from(XrInstance handle)
{
    return hsrt_handle_get(HSRT_VALUE(handle), HSRT_HANDLE_INSTANCE);
}

void hsrt_push_event(hsrt_instance *inst, const void *event, size_t size)
{
    if (inst->event_count == HSRT_EVENT_QUEUE) {
        U_LOG_W("runtime: event queue full, the oldest event is dropped");
        inst->event_head = (inst->event_head + 1) % HSRT_EVENT_QUEUE;
        inst->event_count--;
    }
    uint32_t slot = (inst->event_head + inst->event_count) % HSRT_EVENT_QUEUE;
    memset(&inst->events[slot], 0, sizeof(inst->events[slot]));
    memcpy(&inst->events[slot], event, size < sizeof(XrEventDataBuffer) ? size : sizeof(XrEventDataBuffer));
    inst->event_count++;
}

void hsrt_push_state(hsrt_session *s, XrSessionState state)
{
    s->state = state;
    XrEventDataSessionStateChanged ev = {.type = XR_TYPE_EVENT_DATA_SESSION_STATE_CHANGED,
                                         .session = HSRT_XR(XrSession, s->handle),
                                         .state = state,
                                         .time = hsrt_now_ns()};
    U_LOG_D("runtime: session state -> %d", (int)state);
    hsrt_push_event(s->instance, &ev, sizeof(ev));
}

const char *hsrt_path_string(hsrt_instance *inst, XrPath path)
{
    if (path == XR_NULL_PATH || path > inst->path_count)
        return NULL;
    return inst->paths[path - 1];
}
