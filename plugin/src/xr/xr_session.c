// SPDX-License-Identifier: MIT
/**
 * @file xr_session.c
 * @brief OpenXR session: state machine, per-eye colour/depth swapchains, and the frame loop
 *        (wait, begin, locate views, render, stereo blend hook, copy, end with depth).
 */
#include "xr_internal.h"

#include "gpu_present.h"
#include "u_diag.h"
#include "xrsc_core_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/** xrsc_xr_session_options defaults (xrsc_xr.h); the same planes as the methods' projection. */
#define XR_DEFAULT_NEAR_M 0.05f
#define XR_DEFAULT_FAR_M 1000.0f
/** While the session does not run, a step sleeps this long after polling events. */
#define XR_IDLE_SLEEP_NS 1000000L
#define XR_MAX_SWAPCHAIN_IMAGES 8

typedef struct xr_swapchain {
    XrSwapchain handle;
    uint32_t count;
    XrSwapchainImageVulkan2KHR images[XR_MAX_SWAPCHAIN_IMAGES];
} xr_swapchain;

struct xrsc_xr_session {
    xrsc_xr *xr;
    xrsc_renderer *renderer;
    xrsc_xr_session_options opt;
    XrSession session;
    XrSpace space, view_space;
    XrSessionState state;
    bool running;
    uint32_t width, height;
    VkFormat color_format;
    bool depth_on;
    xr_swapchain color[2], depth[2];
    gpu_present present;
    float *depth_host; /**< one eye's renderer depth (distance along -Z) */
    bool anchored;     /**< space_in_scene is set (at frame 0, when anchoring) */
    XrPosef space_in_scene;
    uint32_t frames;            /**< frames waited for (xrWaitFrame) in this session */
    uint32_t rendered;          /**< of them, rendered */
    XrTime first_display_time;  /**< of the session's first waited frame */
};

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

/** Colour formats in order of preference: linear float first (bit-exact copies). */
static const VkFormat k_color_formats[] = {
    VK_FORMAT_R32G32B32A32_SFLOAT,
    VK_FORMAT_R16G16B16A16_SFLOAT,
    VK_FORMAT_R8G8B8A8_SRGB,
    VK_FORMAT_B8G8R8A8_SRGB,
};

static xrsc_result swapchain_create(xrsc_xr_session *s, VkFormat format, bool depth,
                                    xr_swapchain *out, xrsc_diag *diag)
{
    xrsc_result res = XRSC_OK;
    XrSwapchainCreateInfo ci = {
        .type = XR_TYPE_SWAPCHAIN_CREATE_INFO,
        .usageFlags = (depth ? XR_SWAPCHAIN_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT
                             : XR_SWAPCHAIN_USAGE_COLOR_ATTACHMENT_BIT) |
                      XR_SWAPCHAIN_USAGE_TRANSFER_DST_BIT,
        .format = (int64_t)format,
        .sampleCount = 1,
        .width = s->width,
        .height = s->height,
        .faceCount = 1,
        .arraySize = 1,
        .mipCount = 1,
    };
    XR_CHECK(res, s->xr->instance, diag, done, xrCreateSwapchain(s->session, &ci, &out->handle));
    uint32_t n = 0;
    XR_CHECK(res, s->xr->instance, diag, done,
             xrEnumerateSwapchainImages(out->handle, 0, &n, NULL));
    if (n == 0 || n > XR_MAX_SWAPCHAIN_IMAGES) {
        res = u_diag_set(diag, XRSC_ERROR_XR, "", 0, "xrEnumerateSwapchainImages",
                         "%u images (1..%d supported)", n, XR_MAX_SWAPCHAIN_IMAGES);
        goto done;
    }
    for (uint32_t i = 0; i < n; i++)
        out->images[i] = (XrSwapchainImageVulkan2KHR){.type = XR_TYPE_SWAPCHAIN_IMAGE_VULKAN2_KHR};
    XR_CHECK(res, s->xr->instance, diag, done,
             xrEnumerateSwapchainImages(out->handle, n, &n,
                                        (XrSwapchainImageBaseHeader *)out->images));
    out->count = n;
done:
    return res;
}

static void swapchain_destroy(xr_swapchain *sc)
{
    if (sc->handle)
        xrDestroySwapchain(sc->handle);
    memset(sc, 0, sizeof(*sc));
}

void xrsc_xr_session_destroy(xrsc_xr_session **psession)
{
    if (!psession || !*psession)
        return;
    xrsc_xr_session *s = *psession;
    gpu_context *gpu = xrsc_context_gpu(s->xr->ctx);
    if (gpu && gpu->device)
        vkDeviceWaitIdle(gpu->device);
    for (int e = 0; e < 2; e++) {
        swapchain_destroy(&s->color[e]);
        swapchain_destroy(&s->depth[e]);
    }
    if (gpu)
        gpu_present_destroy(gpu, &s->present);
    if (s->view_space)
        xrDestroySpace(s->view_space);
    if (s->space)
        xrDestroySpace(s->space);
    if (s->session)
        xrDestroySession(s->session);
    s->xr->session_alive = false;
    free(s->depth_host);
    free(s);
    *psession = NULL;
}

/** The renderer's per-eye size must fit both of the runtime's views. */
static xrsc_result resolution_check(const xrsc_xr_session *s, xrsc_diag *out_diag)
{
    const xrsc_xr *xr = s->xr;
    for (int e = 0; e < 2; e++) {
        if (s->width > xr->view_config[e].maxImageRectWidth ||
            s->height > xr->view_config[e].maxImageRectHeight)
            return u_diag_set(out_diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "resolution",
                              "%ux%u per eye is larger than the runtime's maximum %ux%u", s->width,
                              s->height, xr->view_config[e].maxImageRectWidth,
                              xr->view_config[e].maxImageRectHeight);
    }
    return XRSC_OK;
}

/** The XrSession on the context's Vulkan device, its reference space and the VIEW space. */
static xrsc_result session_and_spaces_create(xrsc_xr_session *s, xrsc_diag *out_diag)
{
    xrsc_xr *xr = s->xr;
    gpu_context *gpu = xrsc_context_gpu(xr->ctx);
    xrsc_result res = XRSC_OK;
    XrGraphicsBindingVulkan2KHR binding = {
        .type = XR_TYPE_GRAPHICS_BINDING_VULKAN2_KHR,
        .instance = gpu->instance,
        .physicalDevice = gpu->physical_device,
        .device = gpu->device,
        .queueFamilyIndex = gpu->queue_family,
        .queueIndex = 0,
    };
    XrSessionCreateInfo sci = {
        .type = XR_TYPE_SESSION_CREATE_INFO,
        .next = &binding,
        .systemId = xr->system,
    };
    XR_CHECK(res, xr->instance, out_diag, done, xrCreateSession(xr->instance, &sci, &s->session));
    XrReferenceSpaceCreateInfo rci = {
        .type = XR_TYPE_REFERENCE_SPACE_CREATE_INFO,
        .referenceSpaceType = s->opt.space,
        .poseInReferenceSpace = xrsc_pose_identity(),
    };
    XR_CHECK(res, xr->instance, out_diag, done,
             xrCreateReferenceSpace(s->session, &rci, &s->space));
    rci.referenceSpaceType = XR_REFERENCE_SPACE_TYPE_VIEW;
    XR_CHECK(res, xr->instance, out_diag, done,
             xrCreateReferenceSpace(s->session, &rci, &s->view_space));
done:
    return res;
}

/** Sets s->color_format (one the renderer's colour can be copied into) and s->depth_on. */
static xrsc_result formats_choose(xrsc_xr_session *s, xrsc_diag *out_diag)
{
    xrsc_xr *xr = s->xr;
    gpu_context *gpu = xrsc_context_gpu(xr->ctx);
    xrsc_result res = XRSC_OK;
    /* Formats: the runtime lists its preferred first; xrsc prefers linear float. */
    int64_t formats[64];
    uint32_t fc = 0;
    XR_CHECK(res, xr->instance, out_diag, done,
             xrEnumerateSwapchainFormats(s->session, 0, &fc, NULL));
    if (fc > 64)
        fc = 64;
    XR_CHECK(res, xr->instance, out_diag, done,
             xrEnumerateSwapchainFormats(s->session, fc, &fc, formats));
    s->color_format = VK_FORMAT_UNDEFINED;
    for (size_t k = 0; k < sizeof(k_color_formats) / sizeof(k_color_formats[0]); k++)
        for (uint32_t i = 0; i < fc && s->color_format == VK_FORMAT_UNDEFINED; i++)
            if (formats[i] == (int64_t)k_color_formats[k])
                s->color_format = k_color_formats[k];
    bool has_d32 = false;
    for (uint32_t i = 0; i < fc; i++)
        has_d32 = has_d32 || formats[i] == (int64_t)VK_FORMAT_D32_SFLOAT;
    if (s->color_format == VK_FORMAT_UNDEFINED)
        return u_diag_set(out_diag, XRSC_ERROR_XR, "", 0, "xrEnumerateSwapchainFormats",
                          "the runtime offers none of RGBA32F, RGBA16F, RGBA8/BGRA8 sRGB");
    const gpu_image *src = xrsc_renderer_output_image(s->renderer, XRSC_OUTPUT_COLOR);
    if (src ? !gpu_present_format_ok(gpu, src->format, s->color_format)
            : s->color_format != VK_FORMAT_R32G32B32A32_SFLOAT)
        return u_diag_set(out_diag, XRSC_ERROR_XR, "", 0, "swapchain format",
                          "cannot copy the renderer's colour into swapchain format %d",
                          (int)s->color_format);
    s->depth_on = xr->ext_depth && has_d32 && !s->opt.no_depth;
    if (xr->ext_depth && !has_d32 && !s->opt.no_depth)
        U_LOG_W("openxr: the runtime offers no D32_SFLOAT swapchains: frames go without depth");
done:
    return res;
}

/** Per eye a colour (and with depth on, a depth) swapchain; the copy's staging; depth_host. */
static xrsc_result swapchains_create(xrsc_xr_session *s, xrsc_diag *out_diag)
{
    gpu_context *gpu = xrsc_context_gpu(s->xr->ctx);
    xrsc_result res = XRSC_OK;
    for (int e = 0; e < 2; e++) {
        if ((res = swapchain_create(s, s->color_format, false, &s->color[e], out_diag)) != XRSC_OK)
            return res;
        if (s->depth_on &&
            (res = swapchain_create(s, VK_FORMAT_D32_SFLOAT, true, &s->depth[e], out_diag)) !=
                XRSC_OK)
            return res;
    }
    if ((res = gpu_present_create(gpu, s->width, s->height, &s->present, out_diag)) != XRSC_OK)
        return res;
    s->depth_host = malloc((size_t)s->width * s->height * sizeof(float));
    if (!s->depth_host)
        return u_diag_set(out_diag, XRSC_ERROR_OUT_OF_MEMORY, "", 0, "", "depth buffer");
    return XRSC_OK;
}

xrsc_result xrsc_xr_session_create(xrsc_xr *xr, xrsc_renderer *renderer,
                                   const xrsc_xr_session_options *options,
                                   xrsc_xr_session **out_session, xrsc_diag *out_diag)
{
    if (!out_session)
        return u_diag_set(out_diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "out_session", "NULL");
    *out_session = NULL;
    if (!xr || !renderer)
        return u_diag_set(out_diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, xr ? "renderer" : "xr",
                          "NULL");
    if (xr->session_alive)
        return u_diag_set(out_diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "xr",
                          "a session exists already: destroy it first (one at a time)");
    xrsc_xr_session *s = calloc(1, sizeof(*s));
    if (!s)
        return u_diag_set(out_diag, XRSC_ERROR_OUT_OF_MEMORY, "", 0, "", "out of memory");
    xr->session_alive = true;
    s->xr = xr;
    s->renderer = renderer;
    if (options)
        s->opt = *options;
    if (s->opt.space == 0)
        s->opt.space = XR_REFERENCE_SPACE_TYPE_LOCAL;
    if (s->opt.near_m <= 0.0f)
        s->opt.near_m = XR_DEFAULT_NEAR_M;
    if (s->opt.far_m <= 0.0f)
        s->opt.far_m = XR_DEFAULT_FAR_M;
    s->space_in_scene = xrsc_pose_identity();
    s->state = XR_SESSION_STATE_UNKNOWN;
    xrsc_renderer_size(renderer, &s->width, &s->height);
    xrsc_result res = XRSC_OK;
    if ((res = resolution_check(s, out_diag)) != XRSC_OK ||
        (res = session_and_spaces_create(s, out_diag)) != XRSC_OK ||
        (res = formats_choose(s, out_diag)) != XRSC_OK ||
        (res = swapchains_create(s, out_diag)) != XRSC_OK) {
        xrsc_xr_session_destroy(&s);
        return res;
    }
    *out_session = s;
    return XRSC_OK;
}

/* ---- events and states ---- */

static xrsc_result lost(xrsc_xr_session *s, xrsc_xr_frame_info *info, xrsc_diag *diag,
                        const char *why)
{
    info->status = XRSC_XR_LOST;
    s->running = false;
    return u_diag_set(diag, XRSC_ERROR_XR_SESSION_LOST, "", 0, "session",
                      "the OpenXR runtime %s after %u frames; the session must be destroyed",
                      why, s->frames);
}

/** Polls every event and follows the state changes; sets info->status for EXITING/LOST. */
static xrsc_result poll_events(xrsc_xr_session *s, xrsc_xr_frame_info *info, xrsc_diag *diag)
{
    xrsc_result res = XRSC_OK;
    xrsc_xr *xr = s->xr;
    for (;;) {
        XrEventDataBuffer ev = {.type = XR_TYPE_EVENT_DATA_BUFFER};
        XrResult r = xrPollEvent(xr->instance, &ev);
        if (r == XR_EVENT_UNAVAILABLE)
            return XRSC_OK;
        XR_CHECK(res, xr->instance, diag, done, r);
        if (ev.type == XR_TYPE_EVENT_DATA_INSTANCE_LOSS_PENDING)
            return lost(s, info, diag, "is losing the instance (INSTANCE_LOSS_PENDING)");
        if (ev.type != XR_TYPE_EVENT_DATA_SESSION_STATE_CHANGED)
            continue;
        const XrEventDataSessionStateChanged *sc = (const XrEventDataSessionStateChanged *)&ev;
        if (sc->session != s->session)
            continue;
        s->state = sc->state;
        switch (sc->state) {
        case XR_SESSION_STATE_READY: {
            XrSessionBeginInfo bi = {
                .type = XR_TYPE_SESSION_BEGIN_INFO,
                .primaryViewConfigurationType = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO,
            };
            XR_CHECK(res, xr->instance, diag, done, xrBeginSession(s->session, &bi));
            s->running = true;
            break;
        }
        case XR_SESSION_STATE_STOPPING:
            XR_CHECK(res, xr->instance, diag, done, xrEndSession(s->session));
            s->running = false;
            info->status = XRSC_XR_STOPPED;
            break;
        case XR_SESSION_STATE_EXITING:
            s->running = false;
            info->status = XRSC_XR_EXITED;
            return XRSC_OK;
        case XR_SESSION_STATE_LOSS_PENDING:
            return lost(s, info, diag, "lost the session (LOSS_PENDING)");
        default:
            break;
        }
    }
done:
    if (res == XRSC_ERROR_XR_SESSION_LOST)
        info->status = XRSC_XR_LOST;
    return res;
}

/* ---- the frame ---- */

/**
 * The stereo blend's place in the OpenXR frame: after both eyes are rendered, before anything
 * is copied into the swapchains and before xrEndFrame. The blend (plugin/src/stereo/: none,
 * PFJ23 neighbourhood, raw moments with R, seed 000 §3.6) is part of the renderer's frame:
 * xrsc_renderer_render records it into the frame's one command buffer right after the method's
 * reconstruction (pass "blend", the renderer's xrsc_renderer_options.blend), so when this hook
 * runs the colour image already holds the blended pair. Nothing is left to do here, which keeps
 * this path pixel-identical to the direct one (test_xr_app) and the frame at one submission.
 */
static xrsc_result xr_stereo_blend_hook(xrsc_xr_session *s, const xrsc_frame *frame,
                                        xrsc_diag *diag)
{
    (void)s;
    (void)frame;
    (void)diag;
    return XRSC_OK;
}

/** Renderer depth (distance along -Z, 0 = background) -> the projection's [0, 1] depth,
 *  d = far (z - near) / (z (far - near)), background and anything beyond far at 1. */
static void depth_to_ndc(const float *z, float *out, size_t n, float near_m, float far_m)
{
    double a = (double)far_m / ((double)far_m - (double)near_m);
    for (size_t i = 0; i < n; i++) {
        double d = z[i] > 0.0f ? a * (1.0 - (double)near_m / (double)z[i]) : 1.0;
        out[i] = d < 0.0 ? 0.0f : d > 1.0 ? 1.0f : (float)d;
    }
}

static xrsc_result acquire(xrsc_xr_session *s, xr_swapchain *sc, uint32_t *out_index,
                           xrsc_diag *diag)
{
    xrsc_result res = XRSC_OK;
    XrSwapchainImageAcquireInfo ai = {.type = XR_TYPE_SWAPCHAIN_IMAGE_ACQUIRE_INFO};
    XR_CHECK(res, s->xr->instance, diag, done, xrAcquireSwapchainImage(sc->handle, &ai, out_index));
    XrSwapchainImageWaitInfo wi = {.type = XR_TYPE_SWAPCHAIN_IMAGE_WAIT_INFO,
                                   .timeout = XR_INFINITE_DURATION};
    XR_CHECK(res, s->xr->instance, diag, done, xrWaitSwapchainImage(sc->handle, &wi));
done:
    return res;
}

/**
 * Anchoring (xrsc_xr.h): locates the head (VIEW in the session's space) at `time` and maps it
 * onto the viewpoint. A head the runtime cannot locate then (flags not valid, or
 * XR_ERROR_TIME_INVALID for a time it keeps no poses for) leaves the session unanchored, so a
 * later frame is tried; other failures are errors.
 */
static xrsc_result anchor_at(xrsc_xr_session *s, XrTime time, xrsc_diag *diag)
{
    xrsc_xr *xr = s->xr;
    if (time <= 0)
        return XRSC_OK;
    XrSpaceLocation loc = {.type = XR_TYPE_SPACE_LOCATION};
    XrResult r = xrLocateSpace(s->view_space, s->space, time, &loc);
    if (r == XR_ERROR_TIME_INVALID) {
        U_LOG_D("openxr: the head cannot be located at %lld for anchoring", (long long)time);
        return XRSC_OK;
    }
    if (XR_FAILED(r))
        return xr_error(diag, xr->instance, r, "xrLocateSpace", __FILE__, __LINE__);
    const XrSpaceLocationFlags need =
        XR_SPACE_LOCATION_ORIENTATION_VALID_BIT | XR_SPACE_LOCATION_POSITION_VALID_BIT;
    if ((loc.locationFlags & need) == need) {
        s->space_in_scene = xrsc_pose_mul(s->opt.viewpoint, xrsc_pose_inverse(loc.pose));
        s->anchored = true;
    }
    return XRSC_OK;
}

/** Renders the located views (mapped into the scene when anchored) and runs the blend hook;
 *  out_frame is what was rendered, out_render_ms the renderer's time for it. */
static xrsc_result views_render(xrsc_xr_session *s, XrTime display_time, const XrView views[2],
                                xrsc_frame *out_frame, double *out_render_ms, xrsc_diag *diag)
{
    xrsc_result res = XRSC_OK;
    /* Normally anchored at frame 0 (xrsc_xr_session_step); a runtime that could not locate
     * the head then has it anchored at the first rendered frame. */
    if (s->opt.anchor && !s->anchored && (res = anchor_at(s, display_time, diag)) != XRSC_OK)
        return res;
    xrsc_frame frame = {
        .display_time_ns = display_time - s->first_display_time,
        .frame_index = s->frames,
    };
    for (int e = 0; e < 2; e++) {
        /* Without anchoring the reference space is scene space: the poses pass unchanged. */
        frame.views[e].pose = s->anchored ? xrsc_pose_mul(s->space_in_scene, views[e].pose)
                                          : views[e].pose;
        frame.views[e].fov = views[e].fov;
    }
    double t0 = now_ms();
    if ((res = xrsc_renderer_render(s->renderer, &frame)) != XRSC_OK) {
        u_diag_set(diag, res, "", 0, "render", "rendering frame %u failed: %s", s->frames,
                   xrsc_result_name(res));
        return res;
    }
    double t1 = now_ms();
    if ((res = xr_stereo_blend_hook(s, &frame, diag)) != XRSC_OK)
        return res;
    *out_frame = frame;
    *out_render_ms = t1 - t0;
    return XRSC_OK;
}

/** Into the swapchains: acquire, copy (one submission), release. */
static xrsc_result swapchains_fill(xrsc_xr_session *s, xrsc_diag *diag)
{
    xrsc_xr *xr = s->xr;
    gpu_context *gpu = xrsc_context_gpu(xr->ctx);
    xrsc_result res = XRSC_OK;
    uint32_t ci[2] = {0, 0}, dix[2] = {0, 0};
    gpu_present_eye pe[2];
    const gpu_image *src = xrsc_renderer_output_image(s->renderer, XRSC_OUTPUT_COLOR);
    size_t px = (size_t)s->width * s->height;
    for (uint32_t e = 0; e < 2; e++) {
        if ((res = acquire(s, &s->color[e], &ci[e], diag)) != XRSC_OK)
            goto done;
        pe[e] = (gpu_present_eye){
            .color_src = src,
            .color_layer = e,
            .color_dst = s->color[e].images[ci[e]].image,
            .color_format = s->color_format,
        };
        if (!src && (res = xrsc_renderer_read(s->renderer, e, XRSC_OUTPUT_COLOR,
                                              gpu_present_color_staging(&s->present, e),
                                              px * 4 * sizeof(float))) != XRSC_OK) {
            u_diag_set(diag, res, "", 0, "colour", "reading eye %u failed", e);
            goto done;
        }
        if (!s->depth_on)
            continue;
        if ((res = acquire(s, &s->depth[e], &dix[e], diag)) != XRSC_OK)
            goto done;
        pe[e].depth_dst = s->depth[e].images[dix[e]].image;
        if ((res = xrsc_renderer_read(s->renderer, e, XRSC_OUTPUT_DEPTH, s->depth_host,
                                      px * sizeof(float))) != XRSC_OK) {
            u_diag_set(diag, res, "", 0, "depth", "reading eye %u failed", e);
            goto done;
        }
        depth_to_ndc(s->depth_host, gpu_present_depth_staging(&s->present, e), px, s->opt.near_m,
                     s->opt.far_m);
    }
    if ((res = gpu_present_submit(gpu, &s->present, pe, diag)) != XRSC_OK)
        goto done;
    XrSwapchainImageReleaseInfo ri = {.type = XR_TYPE_SWAPCHAIN_IMAGE_RELEASE_INFO};
    for (uint32_t e = 0; e < 2; e++) {
        XR_CHECK(res, xr->instance, diag, done, xrReleaseSwapchainImage(s->color[e].handle, &ri));
        if (s->depth_on)
            XR_CHECK(res, xr->instance, diag, done,
                     xrReleaseSwapchainImage(s->depth[e].handle, &ri));
    }
done:
    return res;
}

/** The two projection views on the whole swapchain images, chained to depth infos if on. */
static void projection_views_fill(const xrsc_xr_session *s, const XrView views[2],
                                  XrCompositionLayerProjectionView pv[2],
                                  XrCompositionLayerDepthInfoKHR di[2])
{
    const XrRect2Di rect = {{0, 0}, {(int32_t)s->width, (int32_t)s->height}};
    for (uint32_t e = 0; e < 2; e++) {
        di[e] = (XrCompositionLayerDepthInfoKHR){
            .type = XR_TYPE_COMPOSITION_LAYER_DEPTH_INFO_KHR,
            .subImage = {s->depth[e].handle, rect, 0},
            .minDepth = 0.0f,
            .maxDepth = 1.0f,
            .nearZ = s->opt.near_m,
            .farZ = s->opt.far_m,
        };
        pv[e] = (XrCompositionLayerProjectionView){
            .type = XR_TYPE_COMPOSITION_LAYER_PROJECTION_VIEW,
            .next = s->depth_on ? &di[e] : NULL,
            .pose = views[e].pose,
            .fov = views[e].fov,
            .subImage = {s->color[e].handle, rect, 0},
        };
    }
}

/** Renders the located views and fills the two projection views (with depth infos). */
static xrsc_result render_frame(xrsc_xr_session *s, XrTime display_time, const XrView views[2],
                                XrCompositionLayerProjectionView pv[2],
                                XrCompositionLayerDepthInfoKHR di[2], xrsc_xr_frame_info *info,
                                xrsc_diag *diag)
{
    xrsc_frame frame;
    double render_ms = 0.0;
    xrsc_result res = views_render(s, display_time, views, &frame, &render_ms, diag);
    if (res != XRSC_OK || (res = swapchains_fill(s, diag)) != XRSC_OK)
        return res;
    projection_views_fill(s, views, pv, di);
    info->frame_index = s->frames;
    info->scene_time_ns = frame.display_time_ns;
    info->views[0] = frame.views[0];
    info->views[1] = frame.views[1];
    info->render_ms = render_ms;
    s->rendered++;
    return XRSC_OK;
}

/** xrWaitFrame, the session's first display time and anchor (frame 0), xrBeginFrame. */
static xrsc_result frame_begin(xrsc_xr_session *s, XrFrameState *fs, xrsc_diag *out_diag)
{
    xrsc_xr *xr = s->xr;
    xrsc_result res = XRSC_OK;
    XrFrameWaitInfo wi = {.type = XR_TYPE_FRAME_WAIT_INFO};
    XR_CHECK(res, xr->instance, out_diag, fail, xrWaitFrame(s->session, &wi, fs));
    /* Frame numbers and scene time count from the session's first frame, shown or not (the
     * first is usually not: SYNCHRONIZED, shouldRender false), as the runtime's clock does. */
    if (s->frames == 0)
        s->first_display_time = fs->predictedDisplayTime;
    /* Anchoring (xrsc_xr.h): the head at frame 0's display time (plus the offset), located
     * whether or not that frame is rendered; with `xrsc replay`'s offset (-start) it is the
     * stream's first sample, the pose the direct replay anchors. */
    if (s->frames == 0 && s->opt.anchor && !s->anchored &&
        (res = anchor_at(s, fs->predictedDisplayTime + s->opt.anchor_offset_ns, out_diag)) !=
            XRSC_OK)
        return res;
    XrFrameBeginInfo bi = {.type = XR_TYPE_FRAME_BEGIN_INFO};
    XR_CHECK(res, xr->instance, out_diag, fail, xrBeginFrame(s->session, &bi));
fail:
    return res;
}

/** When the runtime wants the frame and both views are located: renders it into pv / di and
 *  sets *out_layer_count to 1 (else 0, the frame ends without layers). */
static xrsc_result frame_views(xrsc_xr_session *s, const XrFrameState *fs,
                               XrCompositionLayerProjectionView pv[2],
                               XrCompositionLayerDepthInfoKHR di[2], xrsc_xr_frame_info *info,
                               uint32_t *out_layer_count, xrsc_diag *out_diag)
{
    xrsc_result res = XRSC_OK;
    *out_layer_count = 0;
    if (!fs->shouldRender)
        return XRSC_OK;
    XrViewLocateInfo li = {
        .type = XR_TYPE_VIEW_LOCATE_INFO,
        .viewConfigurationType = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO,
        .displayTime = fs->predictedDisplayTime,
        .space = s->space,
    };
    XrViewState vs = {.type = XR_TYPE_VIEW_STATE};
    XrView views[2] = {{.type = XR_TYPE_VIEW}, {.type = XR_TYPE_VIEW}};
    uint32_t vc = 0;
    XR_CHECK(res, s->xr->instance, out_diag, fail,
             xrLocateViews(s->session, &li, &vs, 2, &vc, views));
    const XrViewStateFlags need =
        XR_VIEW_STATE_ORIENTATION_VALID_BIT | XR_VIEW_STATE_POSITION_VALID_BIT;
    if (vc == 2 && (vs.viewStateFlags & need) == need) {
        if ((res = render_frame(s, fs->predictedDisplayTime, views, pv, di, info, out_diag)) !=
            XRSC_OK)
            return res;
        *out_layer_count = 1;
        info->status = XRSC_XR_RENDERED;
    }
fail:
    return res;
}

/** One frame: wait, begin, render the views when wanted, end (with the projection layer when
 *  rendered); session loss is reported as XRSC_XR_LOST. */
static xrsc_result frame_run(xrsc_xr_session *s, xrsc_xr_frame_info *info, xrsc_diag *out_diag)
{
    xrsc_xr *xr = s->xr;
    XrFrameState fs = {.type = XR_TYPE_FRAME_STATE};
    xrsc_result res = frame_begin(s, &fs, out_diag);
    if (res != XRSC_OK)
        return res;
    info->display_time = fs.predictedDisplayTime;

    XrCompositionLayerProjectionView pv[2];
    XrCompositionLayerDepthInfoKHR di[2];
    XrCompositionLayerProjection layer = {
        .type = XR_TYPE_COMPOSITION_LAYER_PROJECTION,
        .space = s->space,
        .viewCount = 2,
        .views = pv,
    };
    const XrCompositionLayerBaseHeader *layers[1] = {(const XrCompositionLayerBaseHeader *)&layer};
    uint32_t layer_count = 0;
    info->status = XRSC_XR_SKIPPED;
    if ((res = frame_views(s, &fs, pv, di, info, &layer_count, out_diag)) != XRSC_OK)
        return res;
    double t0 = now_ms();
    XrFrameEndInfo ei = {
        .type = XR_TYPE_FRAME_END_INFO,
        .displayTime = fs.predictedDisplayTime,
        .environmentBlendMode = xr->blend_mode,
        .layerCount = layer_count,
        .layers = layers,
    };
    XR_CHECK(res, xr->instance, out_diag, fail, xrEndFrame(s->session, &ei));
    info->submit_ms = now_ms() - t0;
    s->frames++;
fail:
    return res;
}

xrsc_result xrsc_xr_session_step(xrsc_xr_session *s, xrsc_xr_frame_info *out_info,
                                 xrsc_diag *out_diag)
{
    xrsc_xr_frame_info local;
    xrsc_xr_frame_info *info = out_info ? out_info : &local;
    memset(info, 0, sizeof(*info));
    info->status = XRSC_XR_WAITING;
    if (!s)
        return u_diag_set(out_diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "session", "NULL");
    xrsc_result res = poll_events(s, info, out_diag);
    info->state = s->state;
    if (res != XRSC_OK || info->status == XRSC_XR_EXITED || info->status == XRSC_XR_LOST)
        return res;
    if (!s->running) {
        struct timespec ts = {0, XR_IDLE_SLEEP_NS};
        nanosleep(&ts, NULL);
        return XRSC_OK;
    }
    res = frame_run(s, info, out_diag);
    if (res == XRSC_ERROR_XR_SESSION_LOST) {
        info->status = XRSC_XR_LOST;
        s->running = false;
    }
    info->state = s->state;
    return res;
}

xrsc_result xrsc_xr_session_request_exit(xrsc_xr_session *s, xrsc_diag *out_diag)
{
    if (!s)
        return u_diag_set(out_diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "session", "NULL");
    if (!s->running)
        return XRSC_OK;
    xrsc_result res = XRSC_OK;
    XR_CHECK(res, s->xr->instance, out_diag, done, xrRequestExitSession(s->session));
done:
    return res;
}
