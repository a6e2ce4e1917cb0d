// SPDX-License-Identifier: MIT
/**
 * @file hsrt_session.c
 * @brief The session state machine and its events, frame timing on a simulated clock,
 *        VIEW/LOCAL/STAGE reference spaces located from the replayed pose stream, xrLocateViews
 *        with the simulated headset's eyes, and an action system that accepts bindings and
 *        reports no input.
 *
 * States: xrCreateSession queues IDLE and READY; the first xrWaitFrame after xrBeginSession
 * queues SYNCHRONIZED, the first xrEndFrame VISIBLE and FOCUSED. An exit (the application's
 * xrRequestExitSession, or XRSC_RT_FRAMES frames ended) walks down to STOPPING; xrEndSession
 * then queues IDLE and EXITING. XRSC_RT_LOSE_AFTER frames queue LOSS_PENDING, after which the
 * session's functions return XR_ERROR_SESSION_LOST until it is destroyed.
 *
 * Spaces: the stream's coordinates are the tracking space. LOCAL's origin is the stream's
 * first pose turned only about +Y; STAGE's origin lies HSRT_EYE_HEIGHT_M below LOCAL's;
 * VIEW follows the head. Display time t maps to stream time t - (first predicted display
 * time), wrapping around at the stream's end.
 */
#include "hsrt_instance.h"

#include "u_diag.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

static hsrt_session *session_from(XrSession handle)
{
    return hsrt_handle_get(HSRT_VALUE(handle), HSRT_HANDLE_SESSION);
}

/*
 * Looks up the session, takes its instance's lock, and fails on a lost session (unless
 * allow_lost). Every path after a successful LOCK_SESSION must UNLOCK.
 */
#define LOCK_SESSION(var, handle, fn, allow_lost)                                                  \
    hsrt_session *var = session_from(handle);                                                      \
    if (!var)                                                                                      \
        return hsrt_fail(XR_ERROR_HANDLE_INVALID, fn, "not an XrSession of this runtime");         \
    pthread_mutex_lock(&var->instance->lock);                                                      \
    if (var->lost && !(allow_lost)) {                                                              \
        pthread_mutex_unlock(&var->instance->lock);                                                \
        return hsrt_fail(XR_ERROR_SESSION_LOST, fn, "the session was lost");                       \
    }
#define UNLOCK(var) pthread_mutex_unlock(&var->instance->lock)

static bool pose_valid(XrPosef p)
{
    XrQuaternionf q = p.orientation;
    float n = q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w;
    return isfinite(n) && fabsf(n - 1.0f) < 0.01f && isfinite(p.position.x) &&
           isfinite(p.position.y) && isfinite(p.position.z);
}

/* ---- poses ---- */

int64_t hsrt_stream_time(hsrt_session *s, XrTime time)
{
    const hs_pose_stream *ps = s->instance->poses;
    int64_t t = s->instance->cfg.start_ns + (s->first_display_time ? time - s->first_display_time
                                                                    : 0);
    int64_t dur = hs_pose_stream_duration_ns(ps);
    if (dur > 0) {
        t %= dur;
        if (t < 0)
            t += dur;
    } else {
        t = 0;
    }
    return t;
}

XrPosef hsrt_head_pose(hsrt_session *s, XrTime time)
{
    XrPosef head;
    hs_pose_stream_sample(s->instance->poses, hsrt_stream_time(s, time), &head);
    return head;
}

/** The pose of a space in the stream's coordinates; false for spaces that are never located. */
static bool space_pose(hsrt_session *s, const hsrt_space *sp, XrTime time, XrPosef *out)
{
    XrPosef origin;
    switch (sp->kind) {
    case HSRT_SPACE_VIEW:
        origin = hsrt_head_pose(s, time);
        break;
    case HSRT_SPACE_LOCAL:
        origin = s->instance->local_in_stream;
        break;
    case HSRT_SPACE_STAGE: {
        XrPosef down = xrsc_pose_identity();
        down.position.y = -HSRT_EYE_HEIGHT_M;
        origin = xrsc_pose_mul(s->instance->local_in_stream, down);
        break;
    }
    default:
        return false;
    }
    *out = xrsc_pose_mul(origin, sp->pose_in_ref);
    return true;
}

/* ---- session lifecycle ---- */

/* frames.csv: written as frames.csv.tmp and renamed into place when the session is destroyed
 * (hs_file.h), flushed row by row so that a process ended by a second signal keeps whole rows
 * (hs_run.h). */
static void csv_open(hsrt_session *s)
{
    const hsrt_config *cfg = &s->instance->cfg;
    if (!cfg->out_dir[0])
        return;
    if (mkdir(cfg->out_dir, 0777) != 0 && errno != EEXIST) {
        U_LOG_E("runtime: cannot create XRSC_RT_OUT folder %s: %s", cfg->out_dir, strerror(errno));
        return;
    }
    char path[1100], msg[1400];
    xrsc_diag diag = {0};
    snprintf(path, sizeof(path), "%s/frames.csv", cfg->out_dir);
    if (hs_out_open(&s->frames_csv, path, &diag) != XRSC_OK) {
        U_LOG_E("runtime: %s", xrsc_diag_format(&diag, msg, sizeof(msg)));
        return;
    }
    fprintf(s->frames_csv.f,
            "frame,display_time_ns,stream_time_ns,px,py,pz,qx,qy,qz,qw,layers\n");
}

/* Renames frames.csv into place (its rows are whole), or removes it when the session's writes
 * failed and the rename fails too (the folder is gone: that error was reported). */
static void csv_close(hsrt_session *s)
{
    xrsc_diag diag = {0};
    char msg[1400];
    if (hs_out_close(&s->frames_csv, true, &diag) != XRSC_OK && !s->write_failed)
        U_LOG_E("runtime: %s", xrsc_diag_format(&diag, msg, sizeof(msg)));
}

/**
 * The session cannot go on: a frame (or frames.csv) could not be written. The error goes to
 * XRSC_RT_ERROR_FD as one line "CODE\tFILE\tFIELD\tMESSAGE" (the application reports it),
 * else to stderr; the session is lost (LOSS_PENDING), so the application stops after this
 * frame instead of rendering frames that cannot be kept.
 */
static void fail_session(hsrt_session *s, const xrsc_diag *diag)
{
    if (s->write_failed)
        return;
    s->write_failed = true;
    int fd = s->instance->cfg.error_fd;
    char line[1400];
    if (fd >= 0) {
        int n = snprintf(line, sizeof(line), "%d\t%s\t%s\t%s\n", (int)diag->code, diag->file,
                         diag->field, diag->message);
        if (n > 0 && write(fd, line, (size_t)n < sizeof(line) ? (size_t)n : sizeof(line) - 1) > 0)
            fd = -2;
    }
    if (fd != -2)
        U_LOG_E("runtime: %s", xrsc_diag_format(diag, line, sizeof(line)));
    s->lost = true;
    hsrt_push_state(s, XR_SESSION_STATE_LOSS_PENDING);
}

/** Opens the preview window (XRSC_RT_PREVIEW=1); default size: 1280 wide, the eyes' aspect. */
static XrResult preview_open(hsrt_session *s)
{
    const hsrt_config *cfg = &s->instance->cfg;
    hsrt_preview_options opt = {.width = cfg->preview_w,
                                .height = cfg->preview_h,
                                .hold_frame = cfg->preview_hold_frame,
                                .swapped = cfg->preview_swapped,
                                .diff = cfg->preview_diff,
                                .autoclose = cfg->preview_autoclose,
                                .no_overlay = cfg->preview_no_overlay,
                                .info_fd = cfg->preview_info_fd,
                                .history = cfg->preview_history};
    snprintf(opt.device, sizeof(opt.device), "%s", cfg->preview_device);
    snprintf(opt.reference, sizeof(opt.reference), "%s", cfg->preview_reference);
    if (!opt.width || !opt.height) {
        opt.width = 1280;
        double h = 640.0 * cfg->headset.height_px / cfg->headset.width_px;
        opt.height = (uint32_t)lround(h < 16.0 ? 16.0 : h > 8192.0 ? 8192.0 : h);
    }
    return hsrt_preview_create(&opt, &s->preview);
}

static XrResult XRAPI_CALL hsrt_xrCreateSession(XrInstance instance,
                                                const XrSessionCreateInfo *createInfo,
                                                XrSession *session)
{
    const char *fn = "xrCreateSession";
    hsrt_instance *inst = hsrt_instance_from(instance);
    if (!inst)
        return hsrt_fail(XR_ERROR_HANDLE_INVALID, fn, "not an XrInstance of this runtime");
    if (!createInfo || !session || createInfo->type != XR_TYPE_SESSION_CREATE_INFO)
        return hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn, "bad createInfo");
    if (createInfo->systemId != HSRT_SYSTEM_ID)
        return hsrt_fail(XR_ERROR_SYSTEM_INVALID, fn, "systemId %llu",
                         (unsigned long long)createInfo->systemId);
    const XrGraphicsBindingVulkanKHR *binding = NULL;
    for (const XrBaseInStructure *n = createInfo->next; n; n = n->next) {
        if (n->type == XR_TYPE_GRAPHICS_BINDING_VULKAN_KHR)
            binding = (const XrGraphicsBindingVulkanKHR *)n;
    }
    if (!binding)
        return hsrt_fail(XR_ERROR_GRAPHICS_DEVICE_INVALID, fn,
                         "no XrGraphicsBindingVulkanKHR (this runtime serves Vulkan only)");
    pthread_mutex_lock(&inst->lock);
    XrResult r = XR_SUCCESS;
    hsrt_session *s = NULL;
    if (!inst->graphics_requirements_queried) {
        r = hsrt_fail(XR_ERROR_GRAPHICS_REQUIREMENTS_CALL_MISSING, fn,
                      "xrGetVulkanGraphicsRequirements(2)KHR was not called");
        goto out;
    }
    if (inst->session) {
        r = hsrt_fail(XR_ERROR_LIMIT_REACHED, fn, "one session at a time");
        goto out;
    }
    s = calloc(1, sizeof(*s));
    if (!s) {
        r = hsrt_fail(XR_ERROR_OUT_OF_MEMORY, fn, "session");
        goto out;
    }
    s->instance = inst;
    s->period_ns = (int64_t)llround(1e9 / (double)inst->cfg.headset.refresh_hz);
    r = hsrt_vk_session_init(s, binding);
    if (XR_FAILED(r)) {
        free(s);
        s = NULL;
        goto out;
    }
    if (inst->cfg.preview) {
        r = preview_open(s);
        if (XR_FAILED(r)) {
            hsrt_vk_session_fini(s);
            free(s);
            s = NULL;
            goto out;
        }
    }
    s->handle = hsrt_handle_issue(s, HSRT_HANDLE_SESSION);
    if (!s->handle) {
        hsrt_preview_destroy(&s->preview);
        hsrt_vk_session_fini(s);
        free(s);
        r = hsrt_fail(XR_ERROR_OUT_OF_MEMORY, fn, "handle table");
        goto out;
    }
    inst->session = s;
    csv_open(s);
    hsrt_push_state(s, XR_SESSION_STATE_IDLE);
    hsrt_push_state(s, XR_SESSION_STATE_READY);
    *session = HSRT_XR(XrSession, s->handle);
out:
    pthread_mutex_unlock(&inst->lock);
    return r;
}

static XrResult XRAPI_CALL hsrt_xrDestroySession(XrSession session)
{
    LOCK_SESSION(s, session, "xrDestroySession", true);
    hsrt_instance *inst = s->instance;
    while (s->spaces) {
        hsrt_space *sp = s->spaces;
        s->spaces = sp->next_in_session;
        hsrt_handle_revoke(sp->handle);
        free(sp);
    }
    hsrt_preview_destroy(&s->preview);
    hsrt_vk_session_fini(s);
    csv_close(s);
    /* Events of this session that were not polled would name a dead handle: drop them. */
    uint32_t kept = 0;
    XrEventDataBuffer tmp[HSRT_EVENT_QUEUE];
    for (uint32_t i = 0; i < inst->event_count; i++) {
        const XrEventDataBuffer *ev = &inst->events[(inst->event_head + i) % HSRT_EVENT_QUEUE];
        if (ev->type == XR_TYPE_EVENT_DATA_SESSION_STATE_CHANGED &&
            ((const XrEventDataSessionStateChanged *)ev)->session == session)
            continue;
        tmp[kept++] = *ev;
    }
    memcpy(inst->events, tmp, kept * sizeof(tmp[0]));
    inst->event_head = 0;
    inst->event_count = kept;
    inst->session = NULL;
    hsrt_handle_revoke(s->handle);
    free(s);
    pthread_mutex_unlock(&inst->lock);
    return XR_SUCCESS;
}

static XrResult XRAPI_CALL hsrt_xrBeginSession(XrSession session, const XrSessionBeginInfo *beginInfo)
{
    const char *fn = "xrBeginSession";
    LOCK_SESSION(s, session, fn, false);
    XrResult r = XR_SUCCESS;
    if (!beginInfo || beginInfo->type != XR_TYPE_SESSION_BEGIN_INFO)
        r = hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn, "bad beginInfo");
    else if (beginInfo->primaryViewConfigurationType != XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO)
        r = hsrt_fail(XR_ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED, fn, "type %d",
                      (int)beginInfo->primaryViewConfigurationType);
    else if (s->running)
        r = hsrt_fail(XR_ERROR_SESSION_RUNNING, fn, "already running");
    else if (s->state != XR_SESSION_STATE_READY)
        r = hsrt_fail(XR_ERROR_SESSION_NOT_READY, fn, "state is %d, not READY", (int)s->state);
    if (XR_SUCCEEDED(r)) {
        s->running = true;
        s->clock_start = hsrt_now_ns();
        s->last_display_time = 0;
        s->first_display_time = 0;
        s->waits_pending = 0;
        s->frame_begun = false;
        s->frames_ended = 0;
    }
    UNLOCK(s);
    return r;
}

/** Walks the state down to STOPPING (locked). */
static void stop_session(hsrt_session *s)
{
    s->exit_requested = true;
    if (s->state == XR_SESSION_STATE_FOCUSED)
        hsrt_push_state(s, XR_SESSION_STATE_VISIBLE);
    if (s->state == XR_SESSION_STATE_VISIBLE || s->state == XR_SESSION_STATE_READY)
        hsrt_push_state(s, XR_SESSION_STATE_SYNCHRONIZED);
    if (s->state == XR_SESSION_STATE_SYNCHRONIZED)
        hsrt_push_state(s, XR_SESSION_STATE_STOPPING);
}

static XrResult XRAPI_CALL hsrt_xrEndSession(XrSession session)
{
    const char *fn = "xrEndSession";
    LOCK_SESSION(s, session, fn, false);
    XrResult r = XR_SUCCESS;
    if (!s->running)
        r = hsrt_fail(XR_ERROR_SESSION_NOT_RUNNING, fn, "not running");
    else if (s->state != XR_SESSION_STATE_STOPPING)
        r = hsrt_fail(XR_ERROR_SESSION_NOT_STOPPING, fn, "state is %d, not STOPPING",
                      (int)s->state);
    if (XR_SUCCEEDED(r)) {
        s->running = false;
        hsrt_push_state(s, XR_SESSION_STATE_IDLE);
        if (s->exit_requested)
            hsrt_push_state(s, XR_SESSION_STATE_EXITING);
        else
            hsrt_push_state(s, XR_SESSION_STATE_READY);
    }
    UNLOCK(s);
    return r;
}

static XrResult XRAPI_CALL hsrt_xrRequestExitSession(XrSession session)
{
    const char *fn = "xrRequestExitSession";
    LOCK_SESSION(s, session, fn, false);
    XrResult r = XR_SUCCESS;
    if (!s->running)
        r = hsrt_fail(XR_ERROR_SESSION_NOT_RUNNING, fn, "not running");
    else
        stop_session(s);
    UNLOCK(s);
    return r;
}

/* ---- spaces ---- */

static hsrt_space *space_from(XrSpace handle)
{
    return hsrt_handle_get(HSRT_VALUE(handle), HSRT_HANDLE_SPACE);
}

static const XrReferenceSpaceType k_ref_spaces[] = {
    XR_REFERENCE_SPACE_TYPE_VIEW, XR_REFERENCE_SPACE_TYPE_LOCAL, XR_REFERENCE_SPACE_TYPE_STAGE};

static XrResult XRAPI_CALL hsrt_xrEnumerateReferenceSpaces(XrSession session,
                                                           uint32_t spaceCapacityInput,
                                                           uint32_t *spaceCountOutput,
                                                           XrReferenceSpaceType *spaces)
{
    const char *fn = "xrEnumerateReferenceSpaces";
    LOCK_SESSION(s, session, fn, false);
    XrResult r = XR_SUCCESS;
    if (!spaceCountOutput) {
        r = hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn, "NULL count");
    } else {
        *spaceCountOutput = 3;
        if (spaceCapacityInput) {
            if (spaceCapacityInput < 3 || !spaces)
                r = XR_ERROR_SIZE_INSUFFICIENT;
            else
                memcpy(spaces, k_ref_spaces, sizeof(k_ref_spaces));
        }
    }
    UNLOCK(s);
    return r;
}

static XrResult add_space(hsrt_session *s, hsrt_space_kind kind, XrPosef pose, XrSpace *out)
{
    hsrt_space *sp = calloc(1, sizeof(*sp));
    if (!sp)
        return XR_ERROR_OUT_OF_MEMORY;
    sp->handle = hsrt_handle_issue(sp, HSRT_HANDLE_SPACE);
    if (!sp->handle) {
        free(sp);
        return XR_ERROR_OUT_OF_MEMORY;
    }
    sp->session = s;
    sp->kind = kind;
    sp->pose_in_ref = pose;
    sp->next_in_session = s->spaces;
    s->spaces = sp;
    *out = HSRT_XR(XrSpace, sp->handle);
    return XR_SUCCESS;
}

static XrResult XRAPI_CALL hsrt_xrCreateReferenceSpace(XrSession session,
                                                       const XrReferenceSpaceCreateInfo *createInfo,
                                                       XrSpace *space)
{
    const char *fn = "xrCreateReferenceSpace";
    LOCK_SESSION(s, session, fn, false);
    XrResult r = XR_SUCCESS;
    if (!createInfo || !space || createInfo->type != XR_TYPE_REFERENCE_SPACE_CREATE_INFO) {
        r = hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn, "bad createInfo");
    } else if (!pose_valid(createInfo->poseInReferenceSpace)) {
        r = hsrt_fail(XR_ERROR_POSE_INVALID, fn, "poseInReferenceSpace is not a rigid pose");
    } else {
        hsrt_space_kind kind;
        switch (createInfo->referenceSpaceType) {
        case XR_REFERENCE_SPACE_TYPE_VIEW: kind = HSRT_SPACE_VIEW; break;
        case XR_REFERENCE_SPACE_TYPE_LOCAL: kind = HSRT_SPACE_LOCAL; break;
        case XR_REFERENCE_SPACE_TYPE_STAGE: kind = HSRT_SPACE_STAGE; break;
        default:
            r = hsrt_fail(XR_ERROR_REFERENCE_SPACE_UNSUPPORTED, fn, "type %d",
                          (int)createInfo->referenceSpaceType);
            UNLOCK(s);
            return r;
        }
        r = add_space(s, kind, createInfo->poseInReferenceSpace, space);
        if (XR_FAILED(r))
            hsrt_fail(r, fn, "space");
    }
    UNLOCK(s);
    return r;
}

static XrResult XRAPI_CALL hsrt_xrGetReferenceSpaceBoundsRect(XrSession session,
                                                              XrReferenceSpaceType referenceSpaceType,
                                                              XrExtent2Df *bounds)
{
    const char *fn = "xrGetReferenceSpaceBoundsRect";
    LOCK_SESSION(s, session, fn, false);
    XrResult r = XR_SUCCESS;
    if (!bounds) {
        r = hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn, "NULL bounds");
    } else if (referenceSpaceType == XR_REFERENCE_SPACE_TYPE_STAGE) {
        bounds->width = bounds->height = 2.0f * HSRT_STAGE_HALF_M;
    } else if (referenceSpaceType == XR_REFERENCE_SPACE_TYPE_VIEW ||
               referenceSpaceType == XR_REFERENCE_SPACE_TYPE_LOCAL) {
        bounds->width = bounds->height = 0.0f;
        r = XR_SPACE_BOUNDS_UNAVAILABLE;
    } else {
        r = hsrt_fail(XR_ERROR_REFERENCE_SPACE_UNSUPPORTED, fn, "type %d", (int)referenceSpaceType);
    }
    UNLOCK(s);
    return r;
}

static hsrt_action *action_from(XrAction handle)
{
    return hsrt_handle_get(HSRT_VALUE(handle), HSRT_HANDLE_ACTION);
}

/** A subaction path given to a query of action a: none, or one a was created with. */
static XrResult check_subaction(hsrt_instance *inst, const hsrt_action *a, XrPath path,
                                const char *fn)
{
    if (path == XR_NULL_PATH)
        return XR_SUCCESS;
    if (!hsrt_path_string(inst, path))
        return hsrt_fail(XR_ERROR_PATH_INVALID, fn, "subactionPath %llu is not a path",
                         (unsigned long long)path);
    for (uint32_t i = 0; i < a->subaction_count; i++) {
        if (a->subaction_paths[i] == path)
            return XR_SUCCESS;
    }
    return hsrt_fail(XR_ERROR_PATH_UNSUPPORTED, fn, "action '%s' has no subaction path %s", a->name,
                     hsrt_path_string(inst, path));
}

static XrResult XRAPI_CALL hsrt_xrCreateActionSpace(XrSession session,
                                                    const XrActionSpaceCreateInfo *createInfo,
                                                    XrSpace *space)
{
    const char *fn = "xrCreateActionSpace";
    LOCK_SESSION(s, session, fn, false);
    XrResult r = XR_SUCCESS;
    hsrt_action *a = createInfo ? action_from(createInfo->action) : NULL;
    if (!createInfo || !space || createInfo->type != XR_TYPE_ACTION_SPACE_CREATE_INFO)
        r = hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn, "bad createInfo");
    else if (!a)
        r = hsrt_fail(XR_ERROR_HANDLE_INVALID, fn, "not an XrAction");
    else if (a->type != XR_ACTION_TYPE_POSE_INPUT)
        r = hsrt_fail(XR_ERROR_ACTION_TYPE_MISMATCH, fn, "action '%s' is not a pose", a->name);
    else
        r = check_subaction(s->instance, a, createInfo->subactionPath, fn);
    if (XR_SUCCEEDED(r) && !pose_valid(createInfo->poseInActionSpace))
        r = hsrt_fail(XR_ERROR_POSE_INVALID, fn, "poseInActionSpace is not a rigid pose");
    if (XR_SUCCEEDED(r) &&
        XR_FAILED(r = add_space(s, HSRT_SPACE_ACTION, createInfo->poseInActionSpace, space)))
        hsrt_fail(r, fn, "space");
    UNLOCK(s);
    return r;
}

static XrResult XRAPI_CALL hsrt_xrLocateSpace(XrSpace space, XrSpace baseSpace, XrTime time,
                                              XrSpaceLocation *location)
{
    const char *fn = "xrLocateSpace";
    hsrt_space *sp = space_from(space), *base = space_from(baseSpace);
    if (!sp || !base)
        return hsrt_fail(XR_ERROR_HANDLE_INVALID, fn, "not an XrSpace of this runtime");
    if (sp->session != base->session)
        return hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn, "spaces of different sessions");
    LOCK_SESSION(s, HSRT_XR(XrSession, sp->session->handle), fn, false);
    XrResult r = XR_SUCCESS;
    if (!location || location->type != XR_TYPE_SPACE_LOCATION) {
        r = hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn, "bad location");
    } else if (time <= 0) {
        r = hsrt_fail(XR_ERROR_TIME_INVALID, fn, "time %lld", (long long)time);
    } else {
        XrPosef a, b;
        if (space_pose(s, sp, time, &a) && space_pose(s, base, time, &b)) {
            location->pose = xrsc_pose_mul(xrsc_pose_inverse(b), a);
            location->locationFlags =
                XR_SPACE_LOCATION_ORIENTATION_VALID_BIT | XR_SPACE_LOCATION_POSITION_VALID_BIT |
                XR_SPACE_LOCATION_ORIENTATION_TRACKED_BIT | XR_SPACE_LOCATION_POSITION_TRACKED_BIT;
        } else {
            location->pose = xrsc_pose_identity();
            location->locationFlags = 0;
        }
        for (XrBaseOutStructure *n = location->next; n; n = n->next) {
            if (n->type == XR_TYPE_SPACE_VELOCITY) {
                XrSpaceVelocity *v = (XrSpaceVelocity *)n;
                v->velocityFlags = 0;
                memset(&v->linearVelocity, 0, sizeof(v->linearVelocity));
                memset(&v->angularVelocity, 0, sizeof(v->angularVelocity));
            }
        }
    }
    UNLOCK(s);
    return r;
}

static XrResult XRAPI_CALL hsrt_xrDestroySpace(XrSpace space)
{
    hsrt_space *sp = space_from(space);
    if (!sp)
        return hsrt_fail(XR_ERROR_HANDLE_INVALID, "xrDestroySpace", "not an XrSpace");
    LOCK_SESSION(s, HSRT_XR(XrSession, sp->session->handle), "xrDestroySpace", true);
    for (hsrt_space **p = &s->spaces; *p; p = &(*p)->next_in_session) {
        if (*p == sp) {
            *p = sp->next_in_session;
            break;
        }
    }
    hsrt_handle_revoke(sp->handle);
    free(sp);
    UNLOCK(s);
    return XR_SUCCESS;
}

/* ---- frame loop ---- */

static void sleep_until(XrTime t)
{
    struct timespec ts = {.tv_sec = (time_t)(t / 1000000000), .tv_nsec = (long)(t % 1000000000)};
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL) == EINTR) {
    }
}

/**
 * Realtime pace (locked): when xrWaitFrame wakes, and the display time it predicts. Frames are
 * slots on the refresh grid (clock_start + k * period), each woken one period before it is
 * displayed. The slot after the last one predicted is next; a call that comes after that
 * slot's wake time but before its display time gets it at once (the application was late, the
 * frame can still be shown, as a compositor takes a late frame until its deadline), so a frame
 * loop that needs less than a period on average keeps the display rate through scheduling
 * jitter. A call after the slot's display time starts again at the next wake on the grid.
 */
static void realtime_wait_times(hsrt_session *s, XrTime *out_wake, XrTime *out_predicted)
{
    XrTime now = hsrt_now_ns();
    XrTime wake = s->last_display_time; /* the next slot's wake: the last display time */
    if (!s->last_display_time || now >= wake + s->period_ns) {
        int64_t k = (now - s->clock_start) / s->period_ns + 1;
        wake = s->clock_start + k * s->period_ns;
    }
    *out_predicted = wake + s->period_ns;
    *out_wake = wake > now ? wake : 0; /* 0: no sleeping */
}

static XrResult XRAPI_CALL hsrt_xrWaitFrame(XrSession session, const XrFrameWaitInfo *frameWaitInfo,
                                            XrFrameState *frameState)
{
    const char *fn = "xrWaitFrame";
    LOCK_SESSION(s, session, fn, false);
    XrResult r = XR_SUCCESS;
    if ((frameWaitInfo && frameWaitInfo->type != XR_TYPE_FRAME_WAIT_INFO) || !frameState ||
        frameState->type != XR_TYPE_FRAME_STATE) {
        r = hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn, "bad frameWaitInfo or frameState");
        UNLOCK(s);
        return r;
    }
    if (!s->running) {
        UNLOCK(s);
        return hsrt_fail(XR_ERROR_SESSION_NOT_RUNNING, fn, "not running");
    }
    if (s->preview) {
        /* The preview's pause holds the frame loop here. The stream's clock stands still
         * meanwhile (realtime pace), so a step moves the head by one refresh period. */
        hsrt_preview *pv = s->preview;
        UNLOCK(s);
        int64_t blocked_ns = hsrt_preview_wait(pv);
        pthread_mutex_lock(&s->instance->lock);
        if (s->first_display_time && s->instance->cfg.pace == HSRT_PACE_REALTIME)
            s->first_display_time += blocked_ns / s->period_ns * s->period_ns; /* on the grid */
        if (hsrt_preview_take_exit(pv) && s->running && !s->exit_requested) {
            U_LOG_I("runtime: the preview asked to exit: stopping the session");
            stop_session(s);
        }
        if (s->lost || !s->running) {
            UNLOCK(s);
            return hsrt_fail(s->lost ? XR_ERROR_SESSION_LOST : XR_ERROR_SESSION_NOT_RUNNING, fn,
                             "the session stopped while xrWaitFrame waited");
        }
    }
    XrTime predicted, wake = 0;
    if (s->instance->cfg.pace == HSRT_PACE_FAST) {
        predicted = (s->last_display_time ? s->last_display_time : s->clock_start) + s->period_ns;
    } else {
        realtime_wait_times(s, &wake, &predicted);
    }
    s->last_display_time = predicted;
    if (!s->first_display_time)
        s->first_display_time = predicted;
    s->waits_pending++;
    if (s->state == XR_SESSION_STATE_READY && !s->exit_requested)
        hsrt_push_state(s, XR_SESSION_STATE_SYNCHRONIZED);
    frameState->predictedDisplayTime = predicted;
    frameState->predictedDisplayPeriod = s->period_ns;
    frameState->shouldRender =
        (s->state == XR_SESSION_STATE_VISIBLE || s->state == XR_SESSION_STATE_FOCUSED) ? XR_TRUE
                                                                                       : XR_FALSE;
    UNLOCK(s);
    if (wake)
        sleep_until(wake);
    return XR_SUCCESS;
}

static XrResult XRAPI_CALL hsrt_xrBeginFrame(XrSession session, const XrFrameBeginInfo *frameBeginInfo)
{
    const char *fn = "xrBeginFrame";
    LOCK_SESSION(s, session, fn, false);
    XrResult r = XR_SUCCESS;
    if (frameBeginInfo && frameBeginInfo->type != XR_TYPE_FRAME_BEGIN_INFO)
        r = hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn, "bad frameBeginInfo");
    else if (!s->running)
        r = hsrt_fail(XR_ERROR_SESSION_NOT_RUNNING, fn, "not running");
    else if (!s->waits_pending)
        r = hsrt_fail(XR_ERROR_CALL_ORDER_INVALID, fn, "no xrWaitFrame before it");
    if (XR_SUCCEEDED(r)) {
        s->waits_pending--;
        if (s->frame_begun)
            r = XR_FRAME_DISCARDED;
        s->frame_begun = true;
    }
    UNLOCK(s);
    return r;
}

static hsrt_swapchain *swapchain_of(XrSwapchain handle)
{
    return hsrt_handle_get(HSRT_VALUE(handle), HSRT_HANDLE_SWAPCHAIN);
}

/**
 * A layer's sub-image (spec 10.5.1 and xrEndFrame's valid usage): a swapchain of this session
 * with a released image (else XR_ERROR_LAYER_INVALID), imageRect inside it (else
 * XR_ERROR_SWAPCHAIN_RECT_INVALID), imageArrayIndex below its arraySize (else
 * XR_ERROR_VALIDATION_FAILURE). what names the layer part in the message.
 */
static XrResult check_sub_image(hsrt_session *s, const XrSwapchainSubImage *si, const char *what)
{
    const char *fn = "xrEndFrame";
    hsrt_swapchain *sc = swapchain_of(si->swapchain);
    if (!sc || sc->session != s)
        return hsrt_fail(XR_ERROR_HANDLE_INVALID, fn, "%s: swapchain", what);
    if (sc->last_released < 0)
        return hsrt_fail(XR_ERROR_LAYER_INVALID, fn, "%s: no image of the swapchain was released",
                         what);
    const XrRect2Di *rc = &si->imageRect;
    if (rc->offset.x < 0 || rc->offset.y < 0 || rc->extent.width <= 0 || rc->extent.height <= 0 ||
        (uint64_t)rc->offset.x + (uint64_t)rc->extent.width > sc->info.width ||
        (uint64_t)rc->offset.y + (uint64_t)rc->extent.height > sc->info.height)
        return hsrt_fail(XR_ERROR_SWAPCHAIN_RECT_INVALID, fn,
                         "%s: rect is outside the %ux%u swapchain", what, sc->info.width,
                         sc->info.height);
    if (si->imageArrayIndex >= sc->info.arraySize)
        return hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn, "%s: imageArrayIndex %u of %u layers",
                         what, si->imageArrayIndex, sc->info.arraySize);
    return XR_SUCCESS;
}

static XrResult check_quad(hsrt_session *s, const XrCompositionLayerQuad *q, uint32_t i)
{
    char what[32];
    snprintf(what, sizeof(what), "layers[%u]", i);
    if (q->eyeVisibility != XR_EYE_VISIBILITY_BOTH && q->eyeVisibility != XR_EYE_VISIBILITY_LEFT &&
        q->eyeVisibility != XR_EYE_VISIBILITY_RIGHT)
        return hsrt_fail(XR_ERROR_VALIDATION_FAILURE, "xrEndFrame", "%s: eyeVisibility %d", what,
                         (int)q->eyeVisibility);
    XrResult r = check_sub_image(s, &q->subImage, what);
    if (XR_FAILED(r))
        return r;
    if (!pose_valid(q->pose))
        return hsrt_fail(XR_ERROR_POSE_INVALID, "xrEndFrame", "%s.pose", what);
    return XR_SUCCESS;
}

static XrResult check_layer(hsrt_session *s, const XrCompositionLayerBaseHeader *l, uint32_t i)
{
    const char *fn = "xrEndFrame";
    if (!l)
        return hsrt_fail(XR_ERROR_LAYER_INVALID, fn, "layers[%u] is NULL", i);
    if (!space_from(l->space) || space_from(l->space)->session != s)
        return hsrt_fail(XR_ERROR_HANDLE_INVALID, fn, "layers[%u].space", i);
    if (l->type == XR_TYPE_COMPOSITION_LAYER_QUAD)
        return check_quad(s, (const XrCompositionLayerQuad *)l, i);
    if (l->type != XR_TYPE_COMPOSITION_LAYER_PROJECTION)
        return hsrt_fail(XR_ERROR_LAYER_INVALID, fn, "layers[%u] type %d is not supported", i,
                         (int)l->type);
    const XrCompositionLayerProjection *p = (const XrCompositionLayerProjection *)l;
    if (p->viewCount != 2 || !p->views)
        return hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn, "layers[%u] has %u views, not 2", i,
                         p->viewCount);
    for (uint32_t v = 0; v < 2; v++) {
        const XrCompositionLayerProjectionView *pv = &p->views[v];
        if (pv->type != XR_TYPE_COMPOSITION_LAYER_PROJECTION_VIEW)
            return hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn, "layers[%u].views[%u].type", i, v);
        char what[48];
        snprintf(what, sizeof(what), "layers[%u].views[%u]", i, v);
        XrResult r = check_sub_image(s, &pv->subImage, what);
        if (XR_FAILED(r))
            return r;
        if (!pose_valid(pv->pose))
            return hsrt_fail(XR_ERROR_POSE_INVALID, fn, "layers[%u].views[%u].pose", i, v);
        for (const XrBaseInStructure *n = pv->next; n; n = n->next) {
            if (n->type != XR_TYPE_COMPOSITION_LAYER_DEPTH_INFO_KHR)
                continue;
            const XrCompositionLayerDepthInfoKHR *d = (const XrCompositionLayerDepthInfoKHR *)n;
            if (!s->instance->ext_depth)
                return hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn,
                                 "depth info without XR_KHR_composition_layer_depth");
            hsrt_swapchain *dsc = swapchain_of(d->subImage.swapchain);
            if (!dsc || dsc->session != s || dsc->last_released < 0)
                return hsrt_fail(XR_ERROR_LAYER_INVALID, fn,
                                 "layers[%u].views[%u] depth swapchain", i, v);
            if (!(d->minDepth >= 0.0f && d->maxDepth <= 1.0f && d->minDepth <= d->maxDepth))
                return hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn,
                                 "layers[%u].views[%u] depth range", i, v);
        }
    }
    return XR_SUCCESS;
}

/**
 * Reads the layer's views back; writes them (XRSC_RT_OUT) and hands them to the preview, with
 * their depth (when the layer has it) and cameras for its stereo-difference view.
 */
static void capture_frame(hsrt_session *s, const XrCompositionLayerProjection *layer,
                          XrTime display_time, bool write)
{
    hsrt_preview_frame f = {.frame = s->frames_ended};
    XrResult r = hsrt_vk_capture(s, layer, f.eyes, s->preview ? f.depth_m : NULL);
    xrsc_diag diag = {0};
    if (XR_SUCCEEDED(r) && write &&
        hsrt_write_frame(&s->instance->cfg, s->frames_ended, f.eyes, &diag) != XRSC_OK)
        fail_session(s, &diag);
    if (XR_SUCCEEDED(r) && s->preview) {
        f.stream_time_ns = hsrt_stream_time(s, display_time);
        for (int v = 0; v < 2; v++) {
            f.pose[v] = layer->views[v].pose;
            f.fov[v] = layer->views[v].fov;
        }
        hsrt_preview_submit(s->preview, &f); /* takes the pixels */
    }
    hsrt_preview_frame_free(&f);
}

static XrResult XRAPI_CALL hsrt_xrEndFrame(XrSession session, const XrFrameEndInfo *frameEndInfo)
{
    const char *fn = "xrEndFrame";
    LOCK_SESSION(s, session, fn, false);
    XrResult r = XR_SUCCESS;
    if (!frameEndInfo || frameEndInfo->type != XR_TYPE_FRAME_END_INFO)
        r = hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn, "bad frameEndInfo");
    else if (!s->running)
        r = hsrt_fail(XR_ERROR_SESSION_NOT_RUNNING, fn, "not running");
    else if (!s->frame_begun)
        r = hsrt_fail(XR_ERROR_CALL_ORDER_INVALID, fn, "no xrBeginFrame before it");
    else if (frameEndInfo->displayTime <= 0)
        r = hsrt_fail(XR_ERROR_TIME_INVALID, fn, "displayTime %lld",
                      (long long)frameEndInfo->displayTime);
    else if (frameEndInfo->environmentBlendMode != XR_ENVIRONMENT_BLEND_MODE_OPAQUE)
        r = hsrt_fail(XR_ERROR_ENVIRONMENT_BLEND_MODE_UNSUPPORTED, fn, "blend mode %d",
                      (int)frameEndInfo->environmentBlendMode);
    else if (frameEndInfo->layerCount > XR_MIN_COMPOSITION_LAYERS_SUPPORTED)
        r = hsrt_fail(XR_ERROR_LAYER_LIMIT_EXCEEDED, fn, "%u layers",
                      frameEndInfo->layerCount);
    else if (frameEndInfo->layerCount && !frameEndInfo->layers)
        r = hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn, "layers is NULL");
    for (uint32_t i = 0; XR_SUCCEEDED(r) && i < frameEndInfo->layerCount; i++)
        r = check_layer(s, frameEndInfo->layers[i], i);
    if (XR_FAILED(r)) {
        UNLOCK(s);
        return r;
    }
    s->frame_begun = false;
    const XrCompositionLayerProjection *proj = NULL;
    for (uint32_t i = 0; i < frameEndInfo->layerCount && !proj; i++) {
        if (frameEndInfo->layers[i]->type == XR_TYPE_COMPOSITION_LAYER_PROJECTION)
            proj = (const XrCompositionLayerProjection *)frameEndInfo->layers[i];
    }
    const hsrt_config *cfg = &s->instance->cfg;
    bool write = cfg->out_dir[0] && (cfg->write_eyes || cfg->write_sbs || cfg->write_linear);
    if (proj && (write || s->preview))
        capture_frame(s, proj, frameEndInfo->displayTime, write);
    if (s->frames_csv.f && !s->write_failed) {
        XrPosef h = hsrt_head_pose(s, frameEndInfo->displayTime);
        fprintf(s->frames_csv.f, "%llu,%lld,%lld,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%u\n",
                (unsigned long long)s->frames_ended, (long long)frameEndInfo->displayTime,
                (long long)(cfg->start_ns + frameEndInfo->displayTime - s->first_display_time),
                (double)h.position.x, (double)h.position.y, (double)h.position.z,
                (double)h.orientation.x, (double)h.orientation.y, (double)h.orientation.z,
                (double)h.orientation.w, frameEndInfo->layerCount);
        if (fflush(s->frames_csv.f) != 0 || ferror(s->frames_csv.f)) {
            xrsc_diag diag = {0};
            u_diag_set(&diag, XRSC_ERROR_IO, s->frames_csv.path, 0, "", "cannot write %s: %s",
                       s->frames_csv.tmp, hs_write_error_text(s->frames_csv.f, errno));
            fail_session(s, &diag);
        }
    }
    s->frames_ended++;
    if (s->state == XR_SESSION_STATE_SYNCHRONIZED && !s->exit_requested && !s->lost) {
        hsrt_push_state(s, XR_SESSION_STATE_VISIBLE);
        hsrt_push_state(s, XR_SESSION_STATE_FOCUSED);
    }
    if (s->lost) { /* a frame could not be written (fail_session): nothing more to change */
    } else if (cfg->lose_after && s->frames_ended == cfg->lose_after) {
        U_LOG_W("runtime: XRSC_RT_LOSE_AFTER=%llu frames reached: the session is lost",
                (unsigned long long)cfg->lose_after);
        s->lost = true;
        hsrt_push_state(s, XR_SESSION_STATE_LOSS_PENDING);
    } else if (cfg->frames && s->frames_ended == cfg->frames && !s->exit_requested) {
        U_LOG_I("runtime: XRSC_RT_FRAMES=%llu frames ended: stopping the session",
                (unsigned long long)cfg->frames);
        stop_session(s);
    }
    if (s->preview && !s->lost && hsrt_preview_take_exit(s->preview) && !s->exit_requested) {
        U_LOG_I("runtime: the preview asked to exit: stopping the session");
        stop_session(s);
    }
    UNLOCK(s);
    return XR_SUCCESS;
}

static XrResult XRAPI_CALL hsrt_xrLocateViews(XrSession session, const XrViewLocateInfo *viewLocateInfo,
                                              XrViewState *viewState, uint32_t viewCapacityInput,
                                              uint32_t *viewCountOutput, XrView *views)
{
    const char *fn = "xrLocateViews";
    LOCK_SESSION(s, session, fn, false);
    XrResult r = XR_SUCCESS;
    hsrt_space *base = viewLocateInfo ? space_from(viewLocateInfo->space) : NULL;
    if (!viewLocateInfo || viewLocateInfo->type != XR_TYPE_VIEW_LOCATE_INFO || !viewState ||
        viewState->type != XR_TYPE_VIEW_STATE || !viewCountOutput)
        r = hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn, "bad arguments");
    else if (viewLocateInfo->viewConfigurationType != XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO)
        r = hsrt_fail(XR_ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED, fn, "type %d",
                      (int)viewLocateInfo->viewConfigurationType);
    else if (!base || base->session != s)
        r = hsrt_fail(XR_ERROR_HANDLE_INVALID, fn, "space");
    else if (viewLocateInfo->displayTime <= 0)
        r = hsrt_fail(XR_ERROR_TIME_INVALID, fn, "displayTime %lld",
                      (long long)viewLocateInfo->displayTime);
    if (XR_FAILED(r)) {
        UNLOCK(s);
        return r;
    }
    *viewCountOutput = 2;
    if (!viewCapacityInput) {
        UNLOCK(s);
        return XR_SUCCESS;
    }
    if (viewCapacityInput < 2 || !views) {
        UNLOCK(s);
        return XR_ERROR_SIZE_INSUFFICIENT;
    }
    XrPosef base_pose;
    bool located = space_pose(s, base, viewLocateInfo->displayTime, &base_pose);
    /* The recorded eye views and FOVs of a stream that has them (librnr `v` records), else
     * the simulated headset's eyes (IPD along the head's +X) and FOVs: hs_pose_stream_eyes,
     * as the direct replay places them. */
    hs_view_sample eyes;
    hs_pose_stream_eyes(s->instance->poses, &s->instance->cfg.headset,
                        hsrt_stream_time(s, viewLocateInfo->displayTime), &eyes);
    viewState->viewStateFlags =
        located ? (XR_VIEW_STATE_ORIENTATION_VALID_BIT | XR_VIEW_STATE_POSITION_VALID_BIT |
                   XR_VIEW_STATE_ORIENTATION_TRACKED_BIT | XR_VIEW_STATE_POSITION_TRACKED_BIT)
                : 0;
    for (int i = 0; i < 2; i++) {
        if (views[i].type != XR_TYPE_VIEW) {
            UNLOCK(s);
            return hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn, "views[%d].type", i);
        }
        views[i].pose = located ? xrsc_pose_mul(xrsc_pose_inverse(base_pose), eyes.pose[i])
                                : xrsc_pose_identity();
        views[i].fov = eyes.fov[i];
    }
    UNLOCK(s);
    return XR_SUCCESS;
}

/* ---- actions: bindings are accepted, no input is ever reported ---- */

static hsrt_action_set *action_set_from(XrActionSet handle)
{
    return hsrt_handle_get(HSRT_VALUE(handle), HSRT_HANDLE_ACTION_SET);
}

static bool name_well_formed(const char *s, size_t max)
{
    size_t n = strnlen(s, max);
    if (!n || n == max)
        return false;
    for (size_t i = 0; i < n; i++) {
        char c = s[i];
        if (!((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '-' || c == '_' || c == '.'))
            return false;
    }
    return true;
}

/**
 * The naming rules of xrCreateActionSet / xrCreateAction (spec 11.2, 11.3): an empty name is
 * XR_ERROR_NAME_INVALID, one that is not a well-formed path component
 * XR_ERROR_PATH_FORMAT_INVALID, an empty (or unterminated) localized name
 * XR_ERROR_LOCALIZED_NAME_INVALID.
 */
static XrResult check_names(const char *name, size_t max, const char *localized,
                            size_t localized_max, const char *fn)
{
    if (!name[0])
        return hsrt_fail(XR_ERROR_NAME_INVALID, fn, "empty name");
    if (!name_well_formed(name, max))
        return hsrt_fail(XR_ERROR_PATH_FORMAT_INVALID, fn, "name '%.64s' is not a path component",
                         name);
    size_t n = strnlen(localized, localized_max);
    if (!n || n == localized_max)
        return hsrt_fail(XR_ERROR_LOCALIZED_NAME_INVALID, fn, "localized name of '%s'", name);
    return XR_SUCCESS;
}

static void action_set_free(hsrt_action_set *set)
{
    while (set->actions) {
        hsrt_action *a = set->actions;
        set->actions = a->next_in_set;
        hsrt_handle_revoke(a->handle);
        free(a);
    }
    hsrt_handle_revoke(set->handle);
    free(set);
}

void hsrt_action_sets_free(hsrt_instance *inst)
{
    while (inst->action_sets) {
        hsrt_action_set *set = inst->action_sets;
        inst->action_sets = set->next_in_instance;
        action_set_free(set);
    }
}

static XrResult XRAPI_CALL hsrt_xrCreateActionSet(XrInstance instance,
                                                  const XrActionSetCreateInfo *createInfo,
                                                  XrActionSet *actionSet)
{
    const char *fn = "xrCreateActionSet";
    hsrt_instance *inst = hsrt_instance_from(instance);
    if (!inst)
        return hsrt_fail(XR_ERROR_HANDLE_INVALID, fn, "not an XrInstance");
    if (!createInfo || !actionSet || createInfo->type != XR_TYPE_ACTION_SET_CREATE_INFO)
        return hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn, "bad createInfo");
    XrResult r =
        check_names(createInfo->actionSetName, XR_MAX_ACTION_SET_NAME_SIZE,
                    createInfo->localizedActionSetName, XR_MAX_LOCALIZED_ACTION_SET_NAME_SIZE, fn);
    if (XR_FAILED(r))
        return r;
    pthread_mutex_lock(&inst->lock);
    for (hsrt_action_set *o = inst->action_sets; o; o = o->next_in_instance) {
        if (!strcmp(o->name, createInfo->actionSetName)) {
            r = hsrt_fail(XR_ERROR_NAME_DUPLICATED, fn, "'%s'", o->name);
            goto out;
        }
        if (!strcmp(o->localized_name, createInfo->localizedActionSetName)) {
            r = hsrt_fail(XR_ERROR_LOCALIZED_NAME_DUPLICATED, fn, "'%s'", o->localized_name);
            goto out;
        }
    }
    hsrt_action_set *set = calloc(1, sizeof(*set));
    if (!set) {
        r = hsrt_fail(XR_ERROR_OUT_OF_MEMORY, fn, "action set");
        goto out;
    }
    set->handle = hsrt_handle_issue(set, HSRT_HANDLE_ACTION_SET);
    if (!set->handle) {
        free(set);
        r = hsrt_fail(XR_ERROR_OUT_OF_MEMORY, fn, "handle table");
        goto out;
    }
    set->instance = inst;
    snprintf(set->name, sizeof(set->name), "%s", createInfo->actionSetName);
    snprintf(set->localized_name, sizeof(set->localized_name), "%s",
             createInfo->localizedActionSetName);
    set->next_in_instance = inst->action_sets;
    inst->action_sets = set;
    *actionSet = HSRT_XR(XrActionSet, set->handle);
out:
    pthread_mutex_unlock(&inst->lock);
    return r;
}

static XrResult XRAPI_CALL hsrt_xrDestroyActionSet(XrActionSet actionSet)
{
    hsrt_action_set *set = action_set_from(actionSet);
    if (!set)
        return hsrt_fail(XR_ERROR_HANDLE_INVALID, "xrDestroyActionSet", "not an XrActionSet");
    hsrt_instance *inst = set->instance;
    pthread_mutex_lock(&inst->lock);
    for (hsrt_action_set **p = &inst->action_sets; *p; p = &(*p)->next_in_instance) {
        if (*p == set) {
            *p = set->next_in_instance;
            break;
        }
    }
    action_set_free(set);
    pthread_mutex_unlock(&inst->lock);
    return XR_SUCCESS;
}

/**
 * An action's subaction paths (locked): each a path of this instance (else
 * XR_ERROR_PATH_INVALID), a top-level user path and given once (else XR_ERROR_PATH_UNSUPPORTED).
 */
static XrResult check_subaction_paths(hsrt_instance *inst, const XrActionCreateInfo *ci,
                                      const char *fn)
{
    for (uint32_t i = 0; i < ci->countSubactionPaths; i++) {
        const char *p = hsrt_path_string(inst, ci->subactionPaths[i]);
        if (!p)
            return hsrt_fail(XR_ERROR_PATH_INVALID, fn, "subactionPaths[%u] is not a path", i);
        if (!hsrt_top_level_path(p))
            return hsrt_fail(XR_ERROR_PATH_UNSUPPORTED, fn,
                             "subactionPaths[%u] %s is not a top-level user path", i, p);
        for (uint32_t j = 0; j < i; j++) {
            if (ci->subactionPaths[j] == ci->subactionPaths[i])
                return hsrt_fail(XR_ERROR_PATH_UNSUPPORTED, fn,
                                 "subactionPaths[%u] %s is given twice", i, p);
        }
    }
    return XR_SUCCESS;
}

static XrResult XRAPI_CALL hsrt_xrCreateAction(XrActionSet actionSet,
                                               const XrActionCreateInfo *createInfo, XrAction *action)
{
    const char *fn = "xrCreateAction";
    hsrt_action_set *set = action_set_from(actionSet);
    if (!set)
        return hsrt_fail(XR_ERROR_HANDLE_INVALID, fn, "not an XrActionSet");
    if (!createInfo || !action || createInfo->type != XR_TYPE_ACTION_CREATE_INFO)
        return hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn, "bad createInfo");
    XrResult r =
        check_names(createInfo->actionName, XR_MAX_ACTION_NAME_SIZE,
                    createInfo->localizedActionName, XR_MAX_LOCALIZED_ACTION_NAME_SIZE, fn);
    if (XR_FAILED(r))
        return r;
    if (createInfo->countSubactionPaths && !createInfo->subactionPaths)
        return hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn, "subactionPaths is NULL");
    switch (createInfo->actionType) {
    case XR_ACTION_TYPE_BOOLEAN_INPUT:
    case XR_ACTION_TYPE_FLOAT_INPUT:
    case XR_ACTION_TYPE_VECTOR2F_INPUT:
    case XR_ACTION_TYPE_POSE_INPUT:
    case XR_ACTION_TYPE_VIBRATION_OUTPUT:
        break;
    default:
        return hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn, "actionType %d",
                         (int)createInfo->actionType);
    }
    hsrt_instance *inst = set->instance;
    pthread_mutex_lock(&inst->lock);
    if (set->attached) {
        r = hsrt_fail(XR_ERROR_ACTIONSETS_ALREADY_ATTACHED, fn, "set '%s'", set->name);
        goto out;
    }
    r = check_subaction_paths(inst, createInfo, fn);
    if (XR_FAILED(r))
        goto out;
    for (hsrt_action *o = set->actions; o; o = o->next_in_set) {
        if (!strcmp(o->name, createInfo->actionName)) {
            r = hsrt_fail(XR_ERROR_NAME_DUPLICATED, fn, "'%s'", o->name);
            goto out;
        }
        if (!strcmp(o->localized_name, createInfo->localizedActionName)) {
            r = hsrt_fail(XR_ERROR_LOCALIZED_NAME_DUPLICATED, fn, "'%s'", o->localized_name);
            goto out;
        }
    }
    hsrt_action *a = calloc(1, sizeof(*a));
    if (!a) {
        r = hsrt_fail(XR_ERROR_OUT_OF_MEMORY, fn, "action");
        goto out;
    }
    a->handle = hsrt_handle_issue(a, HSRT_HANDLE_ACTION);
    if (!a->handle) {
        free(a);
        r = hsrt_fail(XR_ERROR_OUT_OF_MEMORY, fn, "handle table");
        goto out;
    }
    a->set = set;
    a->type = createInfo->actionType;
    snprintf(a->name, sizeof(a->name), "%s", createInfo->actionName);
    snprintf(a->localized_name, sizeof(a->localized_name), "%s", createInfo->localizedActionName);
    a->subaction_count = createInfo->countSubactionPaths;
    if (a->subaction_count) /* subactionPaths may be NULL when there are none */
        memcpy(a->subaction_paths, createInfo->subactionPaths,
               a->subaction_count * sizeof(a->subaction_paths[0]));
    a->next_in_set = set->actions;
    set->actions = a;
    *action = HSRT_XR(XrAction, a->handle);
out:
    pthread_mutex_unlock(&inst->lock);
    return r;
}

static XrResult XRAPI_CALL hsrt_xrDestroyAction(XrAction action)
{
    hsrt_action *a = action_from(action);
    if (!a)
        return hsrt_fail(XR_ERROR_HANDLE_INVALID, "xrDestroyAction", "not an XrAction");
    hsrt_instance *inst = a->set->instance;
    pthread_mutex_lock(&inst->lock);
    for (hsrt_action **p = &a->set->actions; *p; p = &(*p)->next_in_set) {
        if (*p == a) {
            *p = a->next_in_set;
            break;
        }
    }
    hsrt_handle_revoke(a->handle);
    free(a);
    pthread_mutex_unlock(&inst->lock);
    return XR_SUCCESS;
}

static XrResult XRAPI_CALL hsrt_xrSuggestInteractionProfileBindings(
    XrInstance instance, const XrInteractionProfileSuggestedBinding *suggestedBindings)
{
    const char *fn = "xrSuggestInteractionProfileBindings";
    hsrt_instance *inst = hsrt_instance_from(instance);
    if (!inst)
        return hsrt_fail(XR_ERROR_HANDLE_INVALID, fn, "not an XrInstance");
    if (!suggestedBindings ||
        suggestedBindings->type != XR_TYPE_INTERACTION_PROFILE_SUGGESTED_BINDING ||
        !suggestedBindings->countSuggestedBindings || !suggestedBindings->suggestedBindings)
        return hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn, "bad suggestedBindings");
    pthread_mutex_lock(&inst->lock);
    XrResult r = XR_SUCCESS;
    const char *profile = hsrt_path_string(inst, suggestedBindings->interactionProfile);
    const hsrt_profile *prof = profile ? hsrt_profile_find(inst, profile) : NULL;
    if (!profile) {
        r = hsrt_fail(XR_ERROR_PATH_INVALID, fn, "interactionProfile is not a path");
        goto out;
    }
    if (!prof) {
        r = hsrt_fail(XR_ERROR_PATH_UNSUPPORTED, fn, "%s is not an interaction profile offered",
                      profile);
        goto out;
    }
    for (uint32_t i = 0; i < suggestedBindings->countSuggestedBindings; i++) {
        const XrActionSuggestedBinding *b = &suggestedBindings->suggestedBindings[i];
        hsrt_action *a = action_from(b->action);
        if (!a || a->set->instance != inst) {
            r = hsrt_fail(XR_ERROR_HANDLE_INVALID, fn, "suggestedBindings[%u].action", i);
            goto out;
        }
        if (a->set->attached) {
            r = hsrt_fail(XR_ERROR_ACTIONSETS_ALREADY_ATTACHED, fn, "action '%s'", a->name);
            goto out;
        }
        const char *bp = hsrt_path_string(inst, b->binding);
        if (!bp) {
            r = hsrt_fail(XR_ERROR_PATH_INVALID, fn, "suggestedBindings[%u].binding", i);
            goto out;
        }
        if (!hsrt_profile_has_binding(prof, bp)) {
            r = hsrt_fail(XR_ERROR_PATH_UNSUPPORTED, fn, "suggestedBindings[%u]: %s has no %s", i,
                          profile, bp);
            goto out;
        }
    }
    U_LOG_D("runtime: %u bindings for %s accepted (no input is reported)",
            suggestedBindings->countSuggestedBindings, profile);
out:
    pthread_mutex_unlock(&inst->lock);
    return r;
}

static XrResult XRAPI_CALL hsrt_xrAttachSessionActionSets(XrSession session,
                                                          const XrSessionActionSetsAttachInfo *attachInfo)
{
    const char *fn = "xrAttachSessionActionSets";
    LOCK_SESSION(s, session, fn, false);
    XrResult r = XR_SUCCESS;
    if (!attachInfo || attachInfo->type != XR_TYPE_SESSION_ACTION_SETS_ATTACH_INFO ||
        !attachInfo->countActionSets || !attachInfo->actionSets)
        r = hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn, "bad attachInfo");
    else if (s->actions_attached)
        r = hsrt_fail(XR_ERROR_ACTIONSETS_ALREADY_ATTACHED, fn, "already attached");
    for (uint32_t i = 0; XR_SUCCEEDED(r) && i < attachInfo->countActionSets; i++) {
        if (!action_set_from(attachInfo->actionSets[i]))
            r = hsrt_fail(XR_ERROR_HANDLE_INVALID, fn, "actionSets[%u]", i);
    }
    if (XR_SUCCEEDED(r)) {
        for (uint32_t i = 0; i < attachInfo->countActionSets; i++)
            action_set_from(attachInfo->actionSets[i])->attached = true;
        s->actions_attached = true;
    }
    UNLOCK(s);
    return r;
}

static XrResult XRAPI_CALL hsrt_xrGetCurrentInteractionProfile(
    XrSession session, XrPath topLevelUserPath, XrInteractionProfileState *interactionProfile)
{
    const char *fn = "xrGetCurrentInteractionProfile";
    LOCK_SESSION(s, session, fn, false);
    XrResult r = XR_SUCCESS;
    if (!interactionProfile || interactionProfile->type != XR_TYPE_INTERACTION_PROFILE_STATE)
        r = hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn, "bad interactionProfile");
    else if (!hsrt_path_string(s->instance, topLevelUserPath))
        r = hsrt_fail(XR_ERROR_PATH_INVALID, fn, "topLevelUserPath");
    else if (!hsrt_top_level_path(hsrt_path_string(s->instance, topLevelUserPath)))
        r = hsrt_fail(XR_ERROR_PATH_UNSUPPORTED, fn, "%s is not a top-level user path",
                      hsrt_path_string(s->instance, topLevelUserPath));
    else if (!s->actions_attached)
        r = hsrt_fail(XR_ERROR_ACTIONSET_NOT_ATTACHED, fn, "no action sets attached");
    else
        interactionProfile->interactionProfile = XR_NULL_PATH;
    UNLOCK(s);
    return r;
}

/** Checks an action query (locked). */
static XrResult check_action(hsrt_session *s, const XrActionStateGetInfo *info, XrActionType type,
                             const char *fn)
{
    if (!info || info->type != XR_TYPE_ACTION_STATE_GET_INFO)
        return hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn, "bad getInfo");
    hsrt_action *a = action_from(info->action);
    if (!a)
        return hsrt_fail(XR_ERROR_HANDLE_INVALID, fn, "not an XrAction");
    if (!a->set->attached || !s->actions_attached)
        return hsrt_fail(XR_ERROR_ACTIONSET_NOT_ATTACHED, fn, "action '%s'", a->name);
    if (a->type != type)
        return hsrt_fail(XR_ERROR_ACTION_TYPE_MISMATCH, fn, "action '%s'", a->name);
    return check_subaction(s->instance, a, info->subactionPath, fn);
}

#define ACTION_STATE_FN(Name, StateT, stype, atype)                                                \
    static XrResult XRAPI_CALL hsrt_xrGetActionState##Name(                                        \
        XrSession session, const XrActionStateGetInfo *getInfo, StateT *state)                     \
    {                                                                                              \
        const char *fn = "xrGetActionState" #Name;                                                 \
        LOCK_SESSION(s, session, fn, false);                                                       \
        XrResult r = check_action(s, getInfo, atype, fn);                                          \
        if (XR_SUCCEEDED(r) && (!state || state->type != stype))                                   \
            r = hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn, "bad state");                           \
        if (XR_SUCCEEDED(r)) {                                                                     \
            void *next = state->next;                                                              \
            memset(state, 0, sizeof(*state));                                                      \
            state->type = stype;                                                                   \
            state->next = next;                                                                    \
        }                                                                                          \
        UNLOCK(s);                                                                                 \
        return r;                                                                                  \
    }
ACTION_STATE_FN(Boolean, XrActionStateBoolean, XR_TYPE_ACTION_STATE_BOOLEAN,
                XR_ACTION_TYPE_BOOLEAN_INPUT)
ACTION_STATE_FN(Float, XrActionStateFloat, XR_TYPE_ACTION_STATE_FLOAT, XR_ACTION_TYPE_FLOAT_INPUT)
ACTION_STATE_FN(Vector2f, XrActionStateVector2f, XR_TYPE_ACTION_STATE_VECTOR2F,
                XR_ACTION_TYPE_VECTOR2F_INPUT)
ACTION_STATE_FN(Pose, XrActionStatePose, XR_TYPE_ACTION_STATE_POSE, XR_ACTION_TYPE_POSE_INPUT)

static XrResult XRAPI_CALL hsrt_xrSyncActions(XrSession session, const XrActionsSyncInfo *syncInfo)
{
    const char *fn = "xrSyncActions";
    LOCK_SESSION(s, session, fn, false);
    XrResult r = XR_SUCCESS;
    if (!syncInfo || syncInfo->type != XR_TYPE_ACTIONS_SYNC_INFO ||
        (syncInfo->countActiveActionSets && !syncInfo->activeActionSets))
        r = hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn, "bad syncInfo");
    for (uint32_t i = 0; XR_SUCCEEDED(r) && i < syncInfo->countActiveActionSets; i++) {
        hsrt_action_set *set = action_set_from(syncInfo->activeActionSets[i].actionSet);
        if (!set)
            r = hsrt_fail(XR_ERROR_HANDLE_INVALID, fn, "activeActionSets[%u]", i);
        else if (!set->attached || !s->actions_attached)
            r = hsrt_fail(XR_ERROR_ACTIONSET_NOT_ATTACHED, fn, "set '%s'", set->name);
    }
    if (XR_SUCCEEDED(r) && s->state != XR_SESSION_STATE_FOCUSED)
        r = XR_SESSION_NOT_FOCUSED;
    UNLOCK(s);
    return r;
}

static XrResult XRAPI_CALL hsrt_xrEnumerateBoundSourcesForAction(
    XrSession session, const XrBoundSourcesForActionEnumerateInfo *enumerateInfo,
    uint32_t sourceCapacityInput, uint32_t *sourceCountOutput, XrPath *sources)
{
    const char *fn = "xrEnumerateBoundSourcesForAction";
    (void)sourceCapacityInput;
    (void)sources;
    LOCK_SESSION(s, session, fn, false);
    XrResult r = XR_SUCCESS;
    hsrt_action *a = enumerateInfo ? action_from(enumerateInfo->action) : NULL;
    if (!enumerateInfo || enumerateInfo->type != XR_TYPE_BOUND_SOURCES_FOR_ACTION_ENUMERATE_INFO ||
        !sourceCountOutput)
        r = hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn, "bad arguments");
    else if (!a)
        r = hsrt_fail(XR_ERROR_HANDLE_INVALID, fn, "not an XrAction");
    else if (!a->set->attached || !s->actions_attached)
        r = hsrt_fail(XR_ERROR_ACTIONSET_NOT_ATTACHED, fn, "action '%s'", a->name);
    else
        *sourceCountOutput = 0;
    UNLOCK(s);
    return r;
}

static XrResult XRAPI_CALL hsrt_xrGetInputSourceLocalizedName(
    XrSession session, const XrInputSourceLocalizedNameGetInfo *getInfo,
    uint32_t bufferCapacityInput, uint32_t *bufferCountOutput, char *buffer)
{
    const char *fn = "xrGetInputSourceLocalizedName";
    (void)bufferCapacityInput;
    (void)bufferCountOutput;
    (void)buffer;
    LOCK_SESSION(s, session, fn, false);
    XrResult r;
    if (!getInfo || getInfo->type != XR_TYPE_INPUT_SOURCE_LOCALIZED_NAME_GET_INFO)
        r = hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn, "bad getInfo");
    else if (!s->actions_attached)
        r = hsrt_fail(XR_ERROR_ACTIONSET_NOT_ATTACHED, fn, "no action sets attached");
    else /* no source is ever bound, so no path names one */
        r = hsrt_fail(XR_ERROR_PATH_UNSUPPORTED, fn, "this runtime binds no input sources");
    UNLOCK(s);
    return r;
}

static XrResult haptic_check(XrSession session, const XrHapticActionInfo *info, const char *fn)
{
    LOCK_SESSION(s, session, fn, false);
    XrResult r = XR_SUCCESS;
    hsrt_action *a = info ? action_from(info->action) : NULL;
    if (!info || info->type != XR_TYPE_HAPTIC_ACTION_INFO)
        r = hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn, "bad hapticActionInfo");
    else if (!a)
        r = hsrt_fail(XR_ERROR_HANDLE_INVALID, fn, "not an XrAction");
    else if (!a->set->attached || !s->actions_attached)
        r = hsrt_fail(XR_ERROR_ACTIONSET_NOT_ATTACHED, fn, "action '%s'", a->name);
    else if (a->type != XR_ACTION_TYPE_VIBRATION_OUTPUT)
        r = hsrt_fail(XR_ERROR_ACTION_TYPE_MISMATCH, fn, "action '%s'", a->name);
    else
        r = check_subaction(s->instance, a, info->subactionPath, fn);
    if (XR_SUCCEEDED(r) && s->state != XR_SESSION_STATE_FOCUSED)
        r = XR_SESSION_NOT_FOCUSED;
    UNLOCK(s);
    return r;
}

static XrResult XRAPI_CALL hsrt_xrApplyHapticFeedback(XrSession session,
                                                      const XrHapticActionInfo *hapticActionInfo,
                                                      const XrHapticBaseHeader *hapticFeedback)
{
    if (!hapticFeedback)
        return hsrt_fail(XR_ERROR_VALIDATION_FAILURE, "xrApplyHapticFeedback", "NULL feedback");
    return haptic_check(session, hapticActionInfo, "xrApplyHapticFeedback");
}

static XrResult XRAPI_CALL hsrt_xrStopHapticFeedback(XrSession session,
                                                     const XrHapticActionInfo *hapticActionInfo)
{
    return haptic_check(session, hapticActionInfo, "xrStopHapticFeedback");
}

/* ---- lookup ---- */

PFN_xrVoidFunction hsrt_session_proc(const char *name)
{
    static const struct {
        const char *name;
        PFN_xrVoidFunction fn;
    } procs[] = {
        HSRT_SESSION_FUNCS(HSRT_X_PROC)
    };
    for (size_t i = 0; i < sizeof(procs) / sizeof(procs[0]); i++) {
        if (!strcmp(procs[i].name, name))
            return procs[i].fn;
    }
    return NULL;
}
