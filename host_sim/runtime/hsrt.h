// SPDX-License-Identifier: MIT
/**
 * @file hsrt.h
 * @brief host_sim as an OpenXR 1.0 runtime (internal): handles, configuration, and the
 *        functions the entry points of the other files share.
 *
 * The runtime is a shared library loaded by the Khronos loader through a manifest; it exports
 * only xrNegotiateLoaderRuntimeInterface (hsrt_entry.c). One head-mounted system with the
 * primary stereo view configuration, driven by a replayed pose stream and the simulated
 * headset of xrsc_math.h. Configuration is read from the environment at xrCreateInstance
 * (README.md in this folder lists the variables).
 *
 * Files: hsrt_entry.c (negotiation, xrGetInstanceProcAddr, instance, system, paths, events,
 * view configurations), hsrt_instance.c (the instance-level helpers that entry, session,
 * vulkan and preview share: hsrt_instance.h, the bottom of the runtime), hsrt_session.c (session state machine, frame timing, spaces, views,
 * actions), hsrt_vulkan.c (XR_KHR_vulkan_enable/enable2, swapchains, frame read-back),
 * hsrt_handle.c (the table of issued handles), hsrt_profiles.c (interaction profiles),
 * hsrt_capture.c (pixel conversion and writing of captured frames), hsrt_preview.c (the optional
 * GLFW/Vulkan preview window, XRSC_RT_PREVIEW=1), hsrt_preview_view.c (its picture: views,
 * heat maps, overlay).
 *
 * Locking: each instance has one mutex; every entry point that touches an instance or its
 * children takes it (xrWaitFrame drops it while sleeping).
 */
#pragma once

#define XR_USE_GRAPHICS_API_VULKAN
#include <vulkan/vulkan.h>
#include <openxr/openxr.h>
#include <openxr/openxr_platform.h>

#include "hs_file.h"
#include "hs_image.h"
#include "hs_pose_stream.h"
#include "xrsc/xrsc_math.h"

#include <pthread.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#define HSRT_RUNTIME_NAME "xrsc host_sim"
#define HSRT_SYSTEM_ID ((XrSystemId)1)
#define HSRT_EVENT_QUEUE 64
#define HSRT_MAX_SWAPCHAIN_IMAGES 3
/** Distinct top-level user paths (hsrt_profiles.c), so the most subaction paths an action has. */
#define HSRT_MAX_SUBACTION_PATHS 5
/** LOCAL's origin is this high above STAGE's (a standing user's eye height). */
#define HSRT_EYE_HEIGHT_M 1.6f
/** Half the side of the square STAGE bounds. */
#define HSRT_STAGE_HALF_M 2.0f

/** The types of handle the runtime issues (hsrt_handle.c): the low byte of each value. */
typedef enum hsrt_handle_type {
    HSRT_HANDLE_INSTANCE = 1,
    HSRT_HANDLE_SESSION,
    HSRT_HANDLE_SPACE,
    HSRT_HANDLE_SWAPCHAIN,
    HSRT_HANDLE_ACTION_SET,
    HSRT_HANDLE_ACTION,
} hsrt_handle_type;

/** An issued handle value as the OpenXR handle type T, and back. */
#define HSRT_XR(T, value) ((T)(uintptr_t)(value))
#define HSRT_VALUE(handle) ((uint64_t)(uintptr_t)(handle))

typedef enum hsrt_pace {
    HSRT_PACE_REALTIME, /**< xrWaitFrame sleeps to the next refresh of a monotonic clock (a
                             late call gets its frame at once while it can still be shown) */
    HSRT_PACE_FAST,     /**< no sleeping; display times advance one period per frame */
} hsrt_pace;

/** Everything the environment configures (README.md). */
typedef struct hsrt_config {
    char poses_path[1024];
    char out_dir[1024]; /**< "" = write nothing */
    uint64_t frames;    /**< 0 = run until the application stops */
    uint64_t lose_after; /**< 0 = never; else the session is lost after this many frames */
    uint64_t max_pose_bytes; /**< XRSC_RT_MAX_POSE_BYTES; 0 = HS_POSE_MAX_FILE_BYTES */
    hsrt_pace pace;
    bool write_eyes, write_sbs, write_linear;
    /** XRSC_RT_ERROR_FD: write end of a pipe that gets the error which ended the session (a
     *  frame that could not be written), one line; -1 = none (the error goes to stderr). */
    int error_fd;
    float exposure;     /**< XRSC_RT_EXPOSURE: > 0 fixed, 0 = "auto" (hs_autoexposure) */
    char device[256];   /**< XRSC_RT_DEVICE, else XRSC_DEVICE: selector of u_device.h, "" = any */
    int64_t start_ns;   /**< XRSC_RT_START_S: stream time of the session's first display time */
    xrsc_headset headset; /**< ipd_m from XRSC_RT_IPD_MM, size, refresh */
    /* the preview window (hsrt_preview.c); off unless XRSC_RT_PREVIEW=1 */
    bool preview;
    uint32_t preview_w, preview_h;      /**< XRSC_RT_PREVIEW_SIZE; 0 = from the eyes' aspect */
    int64_t preview_hold_frame;         /**< XRSC_RT_PREVIEW_HOLD_FRAME; -1 = none */
    bool preview_swapped, preview_diff; /**< XRSC_RT_PREVIEW_VIEW: swap / diff at start */
    char preview_device[256];           /**< XRSC_RT_PREVIEW_DEVICE; "" = CPU device first */
    bool preview_autoclose;  /**< XRSC_RT_PREVIEW_AUTOCLOSE=1: close when the session ends */
    bool preview_no_overlay; /**< XRSC_RT_PREVIEW_OVERLAY=0: the eyes only, no text */
    int preview_info_fd;     /**< XRSC_RT_PREVIEW_INFO_FD; -1 = none (hs_preview_link.h) */
    uint32_t preview_history; /**< XRSC_RT_PREVIEW_HISTORY: frames kept to step back through */
    char preview_reference[1024]; /**< XRSC_RT_PREVIEW_REFERENCE: linear frames; "" = none */
} hsrt_config;

typedef struct hsrt_preview hsrt_preview;

typedef struct hsrt_instance hsrt_instance;
typedef struct hsrt_session hsrt_session;
typedef struct hsrt_swapchain hsrt_swapchain;

/** Loaded Vulkan entry points of the application's device (one bundle, see STYLE.md). */
typedef struct hsrt_vk {
    VkInstance instance;
    VkPhysicalDevice physical;
    VkDevice device;
    VkQueue queue;
    uint32_t queue_family;
    VkCommandPool pool;
    VkCommandBuffer cmd;
    VkFence fence;
    VkBuffer readback;
    VkDeviceMemory readback_mem;
    VkDeviceSize readback_size;
    void *readback_map;
    VkPhysicalDeviceMemoryProperties mem_props;
    PFN_vkGetDeviceProcAddr GetDeviceProcAddr;
#define HSRT_VK_DEVICE_FUNCS(X)                                                                    \
    X(GetDeviceQueue) X(CreateCommandPool) X(DestroyCommandPool) X(AllocateCommandBuffers)         \
    X(FreeCommandBuffers) X(BeginCommandBuffer) X(EndCommandBuffer) X(ResetCommandBuffer)          \
    X(CmdPipelineBarrier) X(CmdCopyImageToBuffer) X(QueueSubmit) X(CreateFence) X(DestroyFence)    \
    X(WaitForFences) X(ResetFences) X(CreateImage) X(DestroyImage) X(GetImageMemoryRequirements)   \
    X(AllocateMemory) X(FreeMemory) X(BindImageMemory) X(CreateBuffer) X(DestroyBuffer)           \
    X(GetBufferMemoryRequirements) X(BindBufferMemory) X(MapMemory) X(UnmapMemory)                \
    X(InvalidateMappedMemoryRanges) X(DeviceWaitIdle) X(GetFenceStatus)
#define HSRT_X_DECL(name) PFN_vk##name name;
    HSRT_VK_DEVICE_FUNCS(HSRT_X_DECL)
#undef HSRT_X_DECL
} hsrt_vk;

struct hsrt_swapchain {
    uint64_t handle; /**< the value issued by hsrt_handle_issue, 0 before */
    hsrt_session *session;
    hsrt_swapchain *next_in_session;
    XrSwapchainCreateInfo info;
    VkImageLayout layout; /**< the layout images are in while the application holds them */
    uint32_t image_count;
    VkImage images[HSRT_MAX_SWAPCHAIN_IMAGES];
    VkDeviceMemory memory[HSRT_MAX_SWAPCHAIN_IMAGES];
    uint32_t next_acquire;    /**< round robin */
    uint32_t acquired;        /**< number acquired and not yet released */
    uint32_t acquired_order[HSRT_MAX_SWAPCHAIN_IMAGES]; /**< FIFO of acquired indices */
    bool waited;              /**< the oldest acquired image has been waited on */
    int32_t last_released;    /**< -1 before the first release */
    /** Set once destroyed: signals when the queue has finished all work submitted before, so
     *  the images can be freed (hsrt_session.retired). */
    VkFence retire_fence;
};

typedef enum hsrt_space_kind {
    HSRT_SPACE_VIEW,
    HSRT_SPACE_LOCAL,
    HSRT_SPACE_STAGE,
    HSRT_SPACE_ACTION, /**< never located: the runtime reports no input */
} hsrt_space_kind;

typedef struct hsrt_space {
    uint64_t handle; /**< the value issued by hsrt_handle_issue, 0 before */
    hsrt_session *session;
    struct hsrt_space *next_in_session;
    hsrt_space_kind kind;
    XrPosef pose_in_ref;
} hsrt_space;

typedef struct hsrt_action_set hsrt_action_set;

typedef struct hsrt_action {
    uint64_t handle; /**< the value issued by hsrt_handle_issue, 0 before */
    hsrt_action_set *set;
    struct hsrt_action *next_in_set;
    char name[XR_MAX_ACTION_NAME_SIZE];
    char localized_name[XR_MAX_LOCALIZED_ACTION_NAME_SIZE];
    XrActionType type;
    uint32_t subaction_count; /**< the top-level user paths given at creation (at most 5) */
    XrPath subaction_paths[HSRT_MAX_SUBACTION_PATHS];
} hsrt_action;

struct hsrt_action_set {
    uint64_t handle; /**< the value issued by hsrt_handle_issue, 0 before */
    hsrt_instance *instance;
    hsrt_action_set *next_in_instance;
    char name[XR_MAX_ACTION_SET_NAME_SIZE];
    char localized_name[XR_MAX_LOCALIZED_ACTION_SET_NAME_SIZE];
    hsrt_action *actions;
    bool attached; /**< attached to a session: immutable from then on */
};

struct hsrt_session {
    uint64_t handle; /**< the value issued by hsrt_handle_issue, 0 before */
    hsrt_instance *instance;
    XrSessionState state;
    bool running;          /**< between xrBeginSession and xrEndSession */
    bool exit_requested;   /**< EXITING follows IDLE after xrEndSession */
    bool lost;             /**< LOSS_PENDING has been queued */
    bool actions_attached;
    hsrt_vk vk;
    hsrt_space *spaces;
    hsrt_swapchain *swapchains;
    hsrt_swapchain *retired; /**< destroyed by the application, freed once their fence signals */
    /* frame loop */
    int64_t period_ns;
    XrTime clock_start;        /**< display times are start + k * period */
    XrTime last_display_time;  /**< the last one xrWaitFrame returned, 0 before */
    XrTime first_display_time; /**< stream time 0, set at the first xrWaitFrame */
    uint32_t waits_pending;    /**< xrWaitFrame calls not yet followed by xrBeginFrame */
    bool frame_begun;
    uint64_t frames_ended;
    hs_out_file frames_csv; /**< frames.csv, written as frames.csv.tmp until xrDestroySession */
    bool write_failed;      /**< a frame or row could not be written: the session was lost */
    hsrt_preview *preview; /**< NULL unless XRSC_RT_PREVIEW=1 */
    hs_autoexposure autoexp; /**< cfg.exposure 0: automatic over the captured frames */
};

struct hsrt_instance {
    uint64_t handle; /**< the value issued by hsrt_handle_issue, 0 before */
    pthread_mutex_t lock;
    hsrt_config cfg;
    hs_pose_stream *poses;
    XrPosef local_in_stream; /**< LOCAL's origin in the stream's coordinates */
    bool ext_vulkan, ext_vulkan2, ext_depth;
    char app_name[XR_MAX_APPLICATION_NAME_SIZE];
    /* paths: XrPath k (k >= 1) is paths[k - 1] */
    char **paths;
    uint32_t path_count, path_cap;
    /* event queue (ring) */
    XrEventDataBuffer events[HSRT_EVENT_QUEUE];
    uint32_t event_head, event_count;
    hsrt_session *session; /**< at most one at a time */
    hsrt_action_set *action_sets;
    bool graphics_requirements_queried;
    PFN_vkGetInstanceProcAddr vk_gipa; /**< from xrCreateVulkanInstanceKHR, else libvulkan's */
    VkInstance vk_instance;            /**< the last one created or asked about */
    VkPhysicalDevice vk_physical;      /**< the one xrGetVulkanGraphicsDevice(2)KHR chose */
};

/* ---- hsrt_handle.c ---- */
/** Issues a new handle value for object (never reused); 0 when out of memory. */
uint64_t hsrt_handle_issue(void *object, hsrt_handle_type type);
/** The object of an issued, not revoked value of that type; NULL for any other value. */
void *hsrt_handle_get(uint64_t value, hsrt_handle_type type);
/** Forgets a value (its object is being freed); accepts 0 and unknown values. */
void hsrt_handle_revoke(uint64_t value);

/* ---- hsrt_profiles.c ---- */
typedef struct hsrt_profile hsrt_profile;
/** The interaction profile at path that this instance offers, NULL if none. */
const hsrt_profile *hsrt_profile_find(const hsrt_instance *inst, const char *path);
/** Whether binding (a full input/output path) is one of the profile's. */
bool hsrt_profile_has_binding(const hsrt_profile *p, const char *binding);
/** Whether path is a top-level user path (/user/hand/left, /user/head, …). */
bool hsrt_top_level_path(const char *path);

/* ---- hsrt_session.c: the core entry points implemented there ---- */
#define HSRT_SESSION_FUNCS(X)                                                                      \
    X(CreateSession) X(DestroySession) X(BeginSession) X(EndSession) X(RequestExitSession)         \
    X(EnumerateReferenceSpaces) X(CreateReferenceSpace) X(GetReferenceSpaceBoundsRect)             \
    X(CreateActionSpace) X(LocateSpace) X(DestroySpace) X(WaitFrame) X(BeginFrame) X(EndFrame)      \
    X(LocateViews) X(CreateActionSet) X(DestroyActionSet) X(CreateAction) X(DestroyAction)          \
    X(SuggestInteractionProfileBindings) X(AttachSessionActionSets)                                \
    X(GetCurrentInteractionProfile) X(GetActionStateBoolean) X(GetActionStateFloat)                \
    X(GetActionStateVector2f) X(GetActionStatePose) X(SyncActions)                                 \
    X(EnumerateBoundSourcesForAction) X(GetInputSourceLocalizedName) X(ApplyHapticFeedback)        \
    X(StopHapticFeedback)
/** The core function `name` implemented in hsrt_session.c, NULL if it is not one of them. */
PFN_xrVoidFunction hsrt_session_proc(const char *name);
/** Frees the action sets of an instance (at xrDestroyInstance). */
void hsrt_action_sets_free(hsrt_instance *inst);
/** Stream time at an XrTime: XRSC_RT_START_S + (time − the session's first display time),
 *  wrapped at the stream's end. */
int64_t hsrt_stream_time(hsrt_session *s, XrTime time);
/** Head pose in the stream's coordinates at an XrTime. */
XrPosef hsrt_head_pose(hsrt_session *s, XrTime time);

/* ---- hsrt_vulkan.c ---- */
#define HSRT_VULKAN_FUNCS(X)                                                                       \
    X(GetVulkanInstanceExtensionsKHR) X(GetVulkanDeviceExtensionsKHR)                              \
    X(GetVulkanGraphicsDeviceKHR) X(GetVulkanGraphicsRequirementsKHR)
#define HSRT_VULKAN2_FUNCS(X)                                                                      \
    X(CreateVulkanInstanceKHR) X(CreateVulkanDeviceKHR) X(GetVulkanGraphicsDevice2KHR)             \
    X(GetVulkanGraphicsRequirements2KHR)
#define HSRT_SWAPCHAIN_FUNCS(X)                                                                    \
    X(EnumerateSwapchainFormats) X(CreateSwapchain) X(DestroySwapchain)                            \
    X(EnumerateSwapchainImages) X(AcquireSwapchainImage) X(WaitSwapchainImage)                     \
    X(ReleaseSwapchainImage)
/**
 * A function implemented in hsrt_vulkan.c (the swapchain core functions and those of the two
 * Vulkan extensions), NULL if none; *out_ext says 0 core, 1 XR_KHR_vulkan_enable,
 * 2 XR_KHR_vulkan_enable2.
 */
PFN_xrVoidFunction hsrt_vulkan_proc(const char *name, int *out_ext);
/** Sets up s->vk from the session's graphics binding (command pool, fence, queue). */
XrResult hsrt_vk_session_init(hsrt_session *s, const XrGraphicsBindingVulkanKHR *binding);
/** Destroys the session's swapchains and Vulkan objects (not the application's device). */
void hsrt_vk_session_fini(hsrt_session *s);
void hsrt_swapchain_free(hsrt_swapchain *sc);
/**
 * Destroys a swapchain the application gave up (locked): its handle at once, its images once
 * the session's queue has finished the work submitted before (the application may still be
 * rendering into them: a fence on an empty submission marks that point).
 */
void hsrt_swapchain_retire(hsrt_session *s, hsrt_swapchain *sc);
/** Frees retired swapchains whose fence has signalled; wait: wait for every one. */
void hsrt_swapchains_reap(hsrt_session *s, bool wait);

/** One eye's captured pixels. */
typedef struct hsrt_eye_image {
    uint32_t w, h;
    float *rgba;   /**< linear, w*h*4 */
    uint8_t *rgb;  /**< display-referred sRGB, w*h*3 */
} hsrt_eye_image;
/**
 * Reads back the released image of each view of a projection layer (at most 2) into
 * out_eyes, and, when out_depth_m is given, each view's depth (XR_KHR_composition_layer_depth)
 * as metres into out_depth_m[v] (malloc'ed; left NULL for a view without a depth info of its
 * colour region's size); frees nothing on failure beyond what it allocated itself.
 */
XrResult hsrt_vk_capture(hsrt_session *s, const XrCompositionLayerProjection *layer,
                         hsrt_eye_image out_eyes[2], float *out_depth_m[2]);

/* ---- hsrt_capture.c ---- */
/** Bytes per texel of a supported swapchain format, 0 for others. */
uint32_t hsrt_format_size(VkFormat format);
bool hsrt_format_is_depth(VkFormat format);
/** The formats offered, colour first in order of preference. */
extern const VkFormat hsrt_formats[];
extern const uint32_t hsrt_format_count;
/**
 * Converts read-back texels (rows top to bottom, row pitch w*size) into linear floats and
 * display sRGB bytes: 8-bit sRGB formats are decoded/kept; UNORM is linear [0,1]; float
 * formats are linear HDR and tone-mapped with hs_tonemap (ACES + sRGB, exposure).
 */
bool hsrt_convert(VkFormat format, const void *texels, uint32_t w, uint32_t h, float exposure,
                  hsrt_eye_image *out);
void hsrt_eye_image_free(hsrt_eye_image *img);
/**
 * Depth texels (D32_SFLOAT or D16_UNORM, w*h) to view-space depth in metres (-z of the eye;
 * the convention of xrsc_metrics_view.depth_m), 0 for background: the value at the far end
 * of the range (nothing hit). The mapping is the perspective one the depth info describes:
 * t = (d - minDepth) / (maxDepth - minDepth), z = nearZ farZ / (farZ - t (farZ - nearZ)), which
 * covers reversed depth (nearZ > farZ) and an infinite farZ. NULL when out of memory.
 */
float *hsrt_depth_to_metres(VkFormat format, const void *texels, uint32_t w, uint32_t h,
                            const XrCompositionLayerDepthInfoKHR *info);
/**
 * Writes frame_NNNNN_{left,right}.png/.pfm and _sbs.png as the configuration says, as one set
 * (hs_file.h: all renamed into place, or none). On the first failure the rest is not written
 * and diag names the file and the errno text.
 */
xrsc_result hsrt_write_frame(const hsrt_config *cfg, uint64_t frame, hsrt_eye_image eyes[2],
                             xrsc_diag *diag);

/* ---- hsrt_preview.c ---- */
/** Frames the preview keeps to step back through, by default and at most (XRSC_RT_PREVIEW_HISTORY). */
#define HSRT_PREVIEW_HISTORY_DEFAULT 32u
#define HSRT_PREVIEW_HISTORY_MAX 1024u
/** The history never holds more than this many bytes of pixels: the oldest frames go first. */
#define HSRT_PREVIEW_HISTORY_BYTES (512ull << 20)

/** What the preview window starts with (from hsrt_config). */
typedef struct hsrt_preview_options {
    uint32_t width, height; /**< window size in screen coordinates */
    int64_t hold_frame;     /**< pause once this frame is submitted; -1 = never */
    bool swapped, diff;     /**< initial view */
    char device[256];       /**< Vulkan device for the window: cpu, gpu, index, name part, "" */
    bool autoclose;         /**< close when the session ends (else stay open until closed) */
    bool no_overlay;        /**< start without the text overlay */
    int info_fd;            /**< the overlay's information channel (hs_preview_link.h); -1 none */
    uint32_t history;       /**< frames kept to step back through (0: the default) */
    char reference[1024];   /**< folder of linear reference frames; "" = none */
} hsrt_preview_options;

/** One submitted frame as the preview keeps it. */
typedef struct hsrt_preview_frame {
    uint64_t frame;         /**< the runtime's frame number (that of the files it writes) */
    int64_t stream_time_ns; /**< the pose stream's time at the frame's display time */
    hsrt_eye_image eyes[2];
    float *depth_m[2]; /**< view depth per pixel, 0 background; NULL without a depth layer */
    XrPosef pose[2];   /**< the views' poses in the layer's space */
    XrFovf fov[2];
} hsrt_preview_frame;
/** Frees a frame's pixels and zeroes it; accepts NULL (in hsrt_capture.c). */
void hsrt_preview_frame_free(hsrt_preview_frame *f);

/**
 * Opens the preview window on a thread of its own and waits until it is up. *out stays NULL
 * (with XR_SUCCESS) when another session of the process already shows one. Fails with an
 * error logged when the window cannot open (no X server, no Vulkan device that presents).
 */
XrResult hsrt_preview_create(const hsrt_preview_options *opt, hsrt_preview **out);
/**
 * Closes the window and joins its thread; accepts NULL and sets *p to NULL. Unless the options
 * say autoclose (or the window already asked to exit), it first waits until the user closes
 * the window, which says so (the end of a run stays on screen).
 */
void hsrt_preview_destroy(hsrt_preview **p);
/** Hands over a frame (its buffers are taken; *frame is zeroed). */
void hsrt_preview_submit(hsrt_preview *p, hsrt_preview_frame *frame);
/**
 * Blocks while the preview is paused (until resumed, a single step, an exit request or the
 * window closing); returns the nanoseconds it blocked. Call without the instance's lock.
 */
int64_t hsrt_preview_wait(hsrt_preview *p);
/** True once after Esc/Q or closing the window: the session should walk down to STOPPING. */
bool hsrt_preview_take_exit(hsrt_preview *p);
