// SPDX-License-Identifier: MIT
/**
 * @file xr_internal.h
 * @brief The OpenXR front end's shared state: the instance bundle (xr_instance.c) that
 *        sessions (xr_session.c) use, and the error helper for XrResults.
 */
#pragma once

#define XR_USE_GRAPHICS_API_VULKAN
#include <vulkan/vulkan.h>
#include <openxr/openxr.h>
#include <openxr/openxr_platform.h>

#include "xrsc/xrsc_xr.h"

#include "gpu_context.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Extension functions, looked up with xrGetInstanceProcAddr. */
typedef struct xr_functions {
    PFN_xrGetVulkanGraphicsRequirements2KHR GetVulkanGraphicsRequirements2KHR;
    PFN_xrCreateVulkanInstanceKHR CreateVulkanInstanceKHR;
    PFN_xrGetVulkanGraphicsDevice2KHR GetVulkanGraphicsDevice2KHR;
    PFN_xrCreateVulkanDeviceKHR CreateVulkanDeviceKHR;
    PFN_xrCreateDebugUtilsMessengerEXT CreateDebugUtilsMessengerEXT;
    PFN_xrDestroyDebugUtilsMessengerEXT DestroyDebugUtilsMessengerEXT;
} xr_functions;

struct xrsc_xr {
    XrInstance instance;
    XrSystemId system;
    XrDebugUtilsMessengerEXT messenger;
    xr_functions fn;
    bool ext_depth;       /**< XR_KHR_composition_layer_depth enabled */
    bool ext_debug_utils; /**< XR_EXT_debug_utils enabled */
    char runtime_name[XR_MAX_RUNTIME_NAME_SIZE];
    XrViewConfigurationView view_config[2];
    XrEnvironmentBlendMode blend_mode;
    xrsc_context *ctx;
    bool session_alive; /**< one session at a time */
    uint32_t messages, message_errors, message_warnings, message_validation;
};

/** "XR_ERROR_SESSION_LOST" etc. (the instance may be XR_NULL_HANDLE). */
const char *xr_result_name(XrInstance instance, XrResult r, char buf[XR_MAX_RESULT_STRING_SIZE]);

/** Logs a failed OpenXR call with its name and XrResult, fills diag (XRSC_ERROR_XR_SESSION_LOST
 *  for the loss results, XRSC_ERROR_XR for others) and returns that code. */
xrsc_result xr_error(xrsc_diag *diag, XrInstance instance, XrResult r, const char *call,
                     const char *file, int line);

/** Runs `call`; on failure fills diag via xr_error and jumps to `label` with `res` set. */
#define XR_CHECK(res, inst, diag, label, call)                                                     \
    do {                                                                                           \
        XrResult xr_check_r_ = (call);                                                             \
        if (XR_FAILED(xr_check_r_)) {                                                              \
            (res) = xr_error((diag), (inst), xr_check_r_, #call, __FILE__, __LINE__);              \
            goto label;                                                                            \
        }                                                                                          \
    } while (0)

#ifdef __cplusplus
}
#endif
