// SPDX-License-Identifier: MIT
/**
 * @file xrsc_xr.h
 * @brief The plugin as an OpenXR application: instance, Vulkan through the runtime
 *        (XR_KHR_vulkan_enable2), session, swapchains and the frame loop that renders with an
 *        ::xrsc_renderer and submits a projection layer with depth (XR_KHR_composition_layer_depth).
 *
 * Use:
 *   xrsc_xr_create            -> instance, system, and the ::xrsc_context made through the
 *                                runtime (load scenes and create renderers on it);
 *   xrsc_xr_session_create    -> session, reference space, per-eye colour and depth swapchains
 *                                sized like the renderer;
 *   xrsc_xr_session_step      -> polls events, follows the session state (begins and ends the
 *                                session when the runtime says so) and, while running, does one
 *                                frame: xrWaitFrame, xrBeginFrame, xrLocateViews, render both
 *                                eyes, the stereo blend hook, copy into the swapchain images,
 *                                xrEndFrame;
 *   xrsc_xr_session_destroy   -> after XRSC_XR_EXITED / XRSC_XR_LOST, or at any time;
 *                                another session may then be created on the same xrsc_xr;
 *   destroy renderers and scenes, then xrsc_xr_destroy.
 *
 * The runtime is found by the Khronos loader (XR_RUNTIME_JSON, else the system's active
 * runtime). Thread rules: one thread at a time per xrsc_xr and its sessions.
 */
#pragma once

#include "xrsc/xrsc.h"

#include <openxr/openxr.h>
#include <stdbool.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct xrsc_xr xrsc_xr;
typedef struct xrsc_xr_session xrsc_xr_session;

/**
 * Options of the OpenXR front end.
 * - application_name: NULL means "xrsc".
 * - context: validation as ::xrsc_context_options (VK_LAYER_KHRONOS_validation on the instance
 *   created through the runtime, also with XRSC_VALIDATION=1). The runtime names the
 *   physical device (xrGetVulkanGraphicsDevice2KHR); `device` (else XRSC_DEVICE), when set,
 *   is checked against the devices of the instance made through the runtime before the
 *   runtime is asked: one that matches none is XRSC_ERROR_DEVICE_NOT_FOUND naming it (as
 *   without OpenXR), and the runtime's device must match it (else the same error). Give the
 *   runtime the same selector (host_sim's: XRSC_RT_DEVICE, which `xrsc replay` sets).
 * - The XR_EXT_debug_utils messenger (served by the loader) is always installed when the
 *   extension exists: its messages (API layers such as XR_APILAYER_LUNARG_core_validation,
 *   the loader, the runtime) are logged and counted, see ::xrsc_xr_debug_messages.
 */
typedef struct xrsc_xr_options {
    const char *application_name;
    xrsc_context_options context;
} xrsc_xr_options;

/**
 * Creates the XrInstance (XR_KHR_vulkan_enable2 required; XR_KHR_composition_layer_depth and
 * XR_EXT_debug_utils when offered), gets the head-mounted system, checks the primary stereo
 * view configuration, and creates the Vulkan instance and device through the runtime.
 * Errors: XRSC_ERROR_XR_RUNTIME_UNAVAILABLE (no runtime: the message names XR_RUNTIME_JSON
 * and its value), XRSC_ERROR_XR (a call failed or something required is missing: the message
 * names the call and the XrResult), the context's errors.
 */
xrsc_result xrsc_xr_create(const xrsc_xr_options *options, xrsc_xr **out_xr, xrsc_diag *out_diag);
/** Destroys the Vulkan context and the instance; sessions, renderers and scenes made on it
 *  must be destroyed first. Accepts NULL, sets *xr to NULL. */
void xrsc_xr_destroy(xrsc_xr **xr);
/** The Vulkan context made through the runtime (owned by xr). */
xrsc_context *xrsc_xr_context(xrsc_xr *xr);
/** The runtime's name, e.g. "xrsc host_sim". */
const char *xrsc_xr_runtime_name(const xrsc_xr *xr);
/** The runtime's recommended per-eye image size (primary stereo, view 0). */
void xrsc_xr_recommended_size(const xrsc_xr *xr, uint32_t *out_width, uint32_t *out_height);
/** Messages seen by the XR_EXT_debug_utils messenger so far, of all severities and types (the
 *  loader's informational ones included); the optional outputs count those of severity ERROR,
 *  of severity WARNING, and of type VALIDATION (what an API layer such as
 *  XR_APILAYER_LUNARG_core_validation reports). 0 when the extension is absent. */
uint32_t xrsc_xr_debug_messages(const xrsc_xr *xr, uint32_t *out_errors, uint32_t *out_warnings,
                                uint32_t *out_validation);

/**
 * Session options. Zero means the documented default.
 * - space: the reference space views are located in; 0 means XR_REFERENCE_SPACE_TYPE_LOCAL.
 * - anchor: when true, the head pose (the VIEW space located in `space`) at the predicted
 *   display time of the session's first frame (frame 0, located although that frame is
 *   usually not rendered) plus anchor_offset_ns is mapped onto `viewpoint` (the scene's,
 *   xrsc_scene_info.viewpoint), as the direct replay anchors a stream's first pose; when false
 *   `space` is scene space itself. A runtime that cannot locate the head then (flags not
 *   valid, XR_ERROR_TIME_INVALID) has the head of the first rendered frame anchored instead.
 * - anchor_offset_ns: added to frame 0's predicted display time for anchoring (0: that
 *   time). `xrsc replay` passes -start, so the stream's first sample is anchored on both of
 *   its paths whatever --start is.
 * - near_m / far_m: the projection the depth layer is expressed in (D32 values
 *   far (z - near) / (z (far - near)), 1 for background), handed to the compositor in
 *   XrCompositionLayerDepthInfoKHR; 0 means 0.05 m / 1000 m.
 * - no_depth: submit no depth even when XR_KHR_composition_layer_depth is enabled.
 */
typedef struct xrsc_xr_session_options {
    XrReferenceSpaceType space;
    bool anchor;
    int64_t anchor_offset_ns;
    XrPosef viewpoint;
    float near_m, far_m;
    bool no_depth;
} xrsc_xr_session_options;

/**
 * Creates the session (graphics binding: the context's Vulkan objects), its reference and VIEW
 * spaces and one colour and one depth swapchain per eye of the renderer's size. Colour format:
 * the first of R32G32B32A32_SFLOAT (a bit-exact copy of the renderer's linear colour),
 * R16G16B16A16_SFLOAT, R8G8B8A8_SRGB, B8G8R8A8_SRGB the runtime offers; depth D32_SFLOAT.
 * The renderer is borrowed and must outlive the session.
 */
xrsc_result xrsc_xr_session_create(xrsc_xr *xr, xrsc_renderer *renderer,
                                   const xrsc_xr_session_options *options,
                                   xrsc_xr_session **out_session, xrsc_diag *out_diag);
/** Destroys swapchains, spaces and the session (ending it first if it runs). Accepts NULL. */
void xrsc_xr_session_destroy(xrsc_xr_session **session);

/** Where a session is after a step. */
typedef enum xrsc_xr_status {
    XRSC_XR_WAITING,  /**< not running yet (IDLE, or READY being handled): step again */
    XRSC_XR_RENDERED, /**< a frame was rendered and submitted */
    XRSC_XR_SKIPPED,  /**< a frame was waited for and ended without layers (shouldRender false
                       *   or views not valid) */
    XRSC_XR_STOPPED,  /**< the runtime stopped the session (xrEndSession done); step on to
                       *   reach XRSC_XR_EXITED, or wait for it to become READY again */
    XRSC_XR_EXITED,   /**< EXITING: destroy the session (another may be created) */
    XRSC_XR_LOST,     /**< LOSS_PENDING or instance loss: destroy the session */
} xrsc_xr_status;

/** What a step did. */
typedef struct xrsc_xr_frame_info {
    xrsc_xr_status status;
    XrSessionState state;       /**< the session state after the step */
    /** The frame's number in the session, counting every xrWaitFrame (0 for the first,
     *  which is usually not shown: SYNCHRONIZED, shouldRender false); the renderer's
     *  xrsc_frame.frame_index (the random stream). */
    uint32_t frame_index;
    XrTime display_time;        /**< predicted display time of the frame (runtime clock) */
    int64_t scene_time_ns;      /**< display time minus the session's first frame's */
    xrsc_view views[2];         /**< the rendered views in scene space */
    double render_ms;           /**< wall time of xrsc_renderer_render */
    double submit_ms;           /**< wall time of the swapchain copies and xrEndFrame */
} xrsc_xr_frame_info;

/**
 * One step (see the file comment). Blocks in xrWaitFrame while running (the runtime paces).
 * Returns XRSC_OK with out_info->status set, XRSC_ERROR_XR_SESSION_LOST when the runtime
 * lost the session (status XRSC_XR_LOST: destroy the session; a new one may work), or another
 * error (an OpenXR or Vulkan call failed, named in the diag). out_info may be NULL.
 */
xrsc_result xrsc_xr_session_step(xrsc_xr_session *session, xrsc_xr_frame_info *out_info,
                                 xrsc_diag *out_diag);
/** Asks the runtime to end the session (xrRequestExitSession) when it runs; stepping on then
 *  reaches XRSC_XR_EXITED. */
xrsc_result xrsc_xr_session_request_exit(xrsc_xr_session *session, xrsc_diag *out_diag);

#ifdef __cplusplus
}
#endif
