// SPDX-License-Identifier: MIT
/**
 * @file xr_instance.c
 * @brief OpenXR instance, system, debug messenger, and the Vulkan instance/device made
 *        through the runtime (XR_KHR_vulkan_enable2) by the gpu layer's creation hooks.
 */
#include "xr_internal.h"

#include "u_diag.h"
#include "xrsc_core_internal.h"

#include <openxr/openxr_reflection.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/** The OpenXR version xrsc is written against (Debian 12's loader is 1.0.20). */
#define XR_APP_API_VERSION XR_MAKE_VERSION(1, 0, 0)

const char *xr_result_name(XrInstance instance, XrResult r, char buf[XR_MAX_RESULT_STRING_SIZE])
{
    (void)instance; /* the reflection list needs no instance (and works without a runtime) */
    switch (r) {
#define XR_X_RESULT(name, value)                                                                   \
    case name:                                                                                     \
        return #name;
        XR_LIST_ENUM_XrResult(XR_X_RESULT)
#undef XR_X_RESULT
    default:
        snprintf(buf, XR_MAX_RESULT_STRING_SIZE, "XrResult(%d)", (int)r);
        return buf;
    }
}

xrsc_result xr_error(xrsc_diag *diag, XrInstance instance, XrResult r, const char *call,
                     const char *file, int line)
{
    char buf[XR_MAX_RESULT_STRING_SIZE];
    const char *name = xr_result_name(instance, r, buf);
    bool lost = r == XR_ERROR_SESSION_LOST || r == XR_ERROR_INSTANCE_LOST;
    xrsc_result code = lost ? XRSC_ERROR_XR_SESSION_LOST : XRSC_ERROR_XR;
    U_LOG_E("%s:%d: %s failed: %s", file, line, call, name);
    return u_diag_set(diag, code, file, line, call, "%s failed: %s%s", call, name,
                      lost ? " (the runtime lost the session)" : "");
}

/* ---- XR_EXT_debug_utils: every message is logged and counted ---- */

static XrBool32 XRAPI_CALL debug_callback(XrDebugUtilsMessageSeverityFlagsEXT severity,
                                          XrDebugUtilsMessageTypeFlagsEXT types,
                                          const XrDebugUtilsMessengerCallbackDataEXT *data,
                                          void *user)
{
    xrsc_xr *xr = user;
    const char *fn = data && data->functionName ? data->functionName : "";
    const char *msg = data && data->message ? data->message : "";
    xr->messages++;
    if (types & XR_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT)
        xr->message_validation++;
    if (severity & XR_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) {
        xr->message_errors++;
        U_LOG_E("openxr: %s: %s", fn, msg);
    } else if (severity & XR_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) {
        xr->message_warnings++;
        U_LOG_W("openxr: %s: %s", fn, msg);
    } else {
        U_LOG_D("openxr: %s: %s", fn, msg);
    }
    return XR_FALSE;
}

/* ---- Vulkan through the runtime: the gpu layer's creation hooks ---- */

static VkResult hook_create_instance(void *user, const VkInstanceCreateInfo *info,
                                     VkInstance *out_instance)
{
    xrsc_xr *xr = user;
    XrVulkanInstanceCreateInfoKHR ci = {
        .type = XR_TYPE_VULKAN_INSTANCE_CREATE_INFO_KHR,
        .systemId = xr->system,
        .pfnGetInstanceProcAddr = vkGetInstanceProcAddr,
        .vulkanCreateInfo = info,
    };
    VkResult vr = VK_SUCCESS;
    XrResult r = xr->fn.CreateVulkanInstanceKHR(xr->instance, &ci, out_instance, &vr);
    if (XR_FAILED(r)) {
        char buf[XR_MAX_RESULT_STRING_SIZE];
        U_LOG_E("xrCreateVulkanInstanceKHR failed: %s", xr_result_name(xr->instance, r, buf));
        return vr != VK_SUCCESS ? vr : VK_ERROR_INITIALIZATION_FAILED;
    }
    return vr;
}

static VkResult hook_physical_device(void *user, VkInstance instance, VkPhysicalDevice *out)
{
    xrsc_xr *xr = user;
    XrVulkanGraphicsDeviceGetInfoKHR gi = {
        .type = XR_TYPE_VULKAN_GRAPHICS_DEVICE_GET_INFO_KHR,
        .systemId = xr->system,
        .vulkanInstance = instance,
    };
    XrResult r = xr->fn.GetVulkanGraphicsDevice2KHR(xr->instance, &gi, out);
    if (XR_FAILED(r)) {
        char buf[XR_MAX_RESULT_STRING_SIZE];
        U_LOG_E("xrGetVulkanGraphicsDevice2KHR failed: %s", xr_result_name(xr->instance, r, buf));
        return VK_ERROR_INITIALIZATION_FAILED;
    }
    return VK_SUCCESS;
}

static VkResult hook_create_device(void *user, VkPhysicalDevice physical_device,
                                   const VkDeviceCreateInfo *info, VkDevice *out_device)
{
    xrsc_xr *xr = user;
    XrVulkanDeviceCreateInfoKHR ci = {
        .type = XR_TYPE_VULKAN_DEVICE_CREATE_INFO_KHR,
        .systemId = xr->system,
        .pfnGetInstanceProcAddr = vkGetInstanceProcAddr,
        .vulkanPhysicalDevice = physical_device,
        .vulkanCreateInfo = info,
    };
    VkResult vr = VK_SUCCESS;
    XrResult r = xr->fn.CreateVulkanDeviceKHR(xr->instance, &ci, out_device, &vr);
    if (XR_FAILED(r)) {
        char buf[XR_MAX_RESULT_STRING_SIZE];
        U_LOG_E("xrCreateVulkanDeviceKHR failed: %s", xr_result_name(xr->instance, r, buf));
        return vr != VK_SUCCESS ? vr : VK_ERROR_INITIALIZATION_FAILED;
    }
    return vr;
}

/* ---- instance ---- */

static bool has_extension(const XrExtensionProperties *props, uint32_t n, const char *name)
{
    for (uint32_t i = 0; i < n; i++)
        if (!strcmp(props[i].extensionName, name))
            return true;
    return false;
}

/** The loader's answer when it finds no runtime, with where it looked. */
static xrsc_result runtime_unavailable(xrsc_diag *diag, XrResult r, const char *call)
{
    char buf[XR_MAX_RESULT_STRING_SIZE];
    const char *json = getenv("XR_RUNTIME_JSON");
    return u_diag_set(diag, XRSC_ERROR_XR_RUNTIME_UNAVAILABLE, json ? json : "", 0,
                      "XR_RUNTIME_JSON",
                      "no OpenXR runtime could be loaded (%s: %s); XR_RUNTIME_JSON is %s%s%s: "
                      "set it to a runtime manifest such as the build tree's "
                      "host_sim/runtime/xrsc_runtime.json",
                      call, xr_result_name(XR_NULL_HANDLE, r, buf), json ? "'" : "unset",
                      json ? json : "", json ? "'" : "");
}

#define XR_LOAD(xr, name)                                                                          \
    xrGetInstanceProcAddr((xr)->instance, "xr" #name, (PFN_xrVoidFunction *)&(xr)->fn.name)

/** The instance extensions xrsc enables: enable2 always, depth and debug utils if offered. */
typedef struct xr_extension_list {
    const char *names[3];
    uint32_t count;
} xr_extension_list;

/** Fails unless the runtime offers XR_KHR_vulkan_enable2; sets xr->ext_depth and
 *  xr->ext_debug_utils and lists the extensions to enable. */
static xrsc_result extensions_choose(xrsc_xr *xr, xr_extension_list *out_exts, xrsc_diag *out_diag)
{
    xrsc_result res = XRSC_OK;
    uint32_t n = 0;
    XrResult r = xrEnumerateInstanceExtensionProperties(NULL, 0, &n, NULL);
    if (XR_FAILED(r))
        return runtime_unavailable(out_diag, r, "xrEnumerateInstanceExtensionProperties");
    XrExtensionProperties *props = calloc(n ? n : 1, sizeof(*props));
    if (!props)
        return u_diag_set(out_diag, XRSC_ERROR_OUT_OF_MEMORY, "", 0, "", "out of memory");
    for (uint32_t i = 0; i < n; i++)
        props[i].type = XR_TYPE_EXTENSION_PROPERTIES;
    XR_CHECK(res, XR_NULL_HANDLE, out_diag, done,
             xrEnumerateInstanceExtensionProperties(NULL, n, &n, props));
    if (!has_extension(props, n, XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME)) {
        res = u_diag_set(out_diag, XRSC_ERROR_XR, "", 0, XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME,
                         "the OpenXR runtime does not offer %s, which xrsc renders through",
                         XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME);
        goto done;
    }
    out_exts->count = 0;
    out_exts->names[out_exts->count++] = XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME;
    xr->ext_depth = has_extension(props, n, XR_KHR_COMPOSITION_LAYER_DEPTH_EXTENSION_NAME);
    if (xr->ext_depth)
        out_exts->names[out_exts->count++] = XR_KHR_COMPOSITION_LAYER_DEPTH_EXTENSION_NAME;
    xr->ext_debug_utils = has_extension(props, n, XR_EXT_DEBUG_UTILS_EXTENSION_NAME);
    if (xr->ext_debug_utils)
        out_exts->names[out_exts->count++] = XR_EXT_DEBUG_UTILS_EXTENSION_NAME;
done:
    free(props);
    return res;
}

/** xrCreateInstance, then the debug messenger and the extension functions. */
static xrsc_result instance_create(xrsc_xr *xr, const char *application_name,
                                   const xr_extension_list *exts, xrsc_diag *out_diag)
{
    xrsc_result res = XRSC_OK;
    XrDebugUtilsMessengerCreateInfoEXT mci = {
        .type = XR_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT,
        .messageSeverities = XR_DEBUG_UTILS_MESSAGE_SEVERITY_VERBOSE_BIT_EXT |
                             XR_DEBUG_UTILS_MESSAGE_SEVERITY_INFO_BIT_EXT |
                             XR_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                             XR_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT,
        .messageTypes = XR_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                        XR_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                        XR_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT |
                        XR_DEBUG_UTILS_MESSAGE_TYPE_CONFORMANCE_BIT_EXT,
        .userCallback = debug_callback,
        .userData = xr,
    };
    XrInstanceCreateInfo ici = {
        .type = XR_TYPE_INSTANCE_CREATE_INFO,
        /* also catches messages from xrCreateInstance / xrDestroyInstance */
        .next = xr->ext_debug_utils ? &mci : NULL,
        .applicationInfo = {.applicationVersion = 1,
                            .engineVersion = 1,
                            .apiVersion = XR_APP_API_VERSION},
        .enabledExtensionCount = exts->count,
        .enabledExtensionNames = exts->names,
    };
    snprintf(ici.applicationInfo.applicationName, XR_MAX_APPLICATION_NAME_SIZE, "%s",
             application_name ? application_name : "xrsc");
    snprintf(ici.applicationInfo.engineName, XR_MAX_ENGINE_NAME_SIZE, "xrsc");
    XrResult r = xrCreateInstance(&ici, &xr->instance);
    if (r == XR_ERROR_RUNTIME_UNAVAILABLE || r == XR_ERROR_RUNTIME_FAILURE)
        return runtime_unavailable(out_diag, r, "xrCreateInstance");
    XR_CHECK(res, XR_NULL_HANDLE, out_diag, done, r);
    if (xr->ext_debug_utils) {
        XR_CHECK(res, xr->instance, out_diag, done, XR_LOAD(xr, CreateDebugUtilsMessengerEXT));
        XR_CHECK(res, xr->instance, out_diag, done, XR_LOAD(xr, DestroyDebugUtilsMessengerEXT));
        XR_CHECK(res, xr->instance, out_diag, done,
                 xr->fn.CreateDebugUtilsMessengerEXT(xr->instance, &mci, &xr->messenger));
    }
    XR_CHECK(res, xr->instance, out_diag, done, XR_LOAD(xr, GetVulkanGraphicsRequirements2KHR));
    XR_CHECK(res, xr->instance, out_diag, done, XR_LOAD(xr, CreateVulkanInstanceKHR));
    XR_CHECK(res, xr->instance, out_diag, done, XR_LOAD(xr, GetVulkanGraphicsDevice2KHR));
    XR_CHECK(res, xr->instance, out_diag, done, XR_LOAD(xr, CreateVulkanDeviceKHR));
done:
    return res;
}

/** The runtime's name, the HMD system, its two stereo views and its preferred blend mode. */
static xrsc_result system_get(xrsc_xr *xr, xrsc_diag *out_diag)
{
    xrsc_result res = XRSC_OK;
    XrInstanceProperties ip = {.type = XR_TYPE_INSTANCE_PROPERTIES};
    XR_CHECK(res, xr->instance, out_diag, done, xrGetInstanceProperties(xr->instance, &ip));
    snprintf(xr->runtime_name, sizeof(xr->runtime_name), "%s", ip.runtimeName);

    XrSystemGetInfo sgi = {.type = XR_TYPE_SYSTEM_GET_INFO,
                           .formFactor = XR_FORM_FACTOR_HEAD_MOUNTED_DISPLAY};
    XR_CHECK(res, xr->instance, out_diag, done, xrGetSystem(xr->instance, &sgi, &xr->system));

    /* Primary stereo with two views, and a blend mode for it. */
    uint32_t vc = 0;
    XR_CHECK(res, xr->instance, out_diag, done,
             xrEnumerateViewConfigurationViews(xr->instance, xr->system,
                                               XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO, 0, &vc,
                                               NULL));
    if (vc != 2)
        return u_diag_set(out_diag, XRSC_ERROR_XR, "", 0, "xrEnumerateViewConfigurationViews",
                          "the primary stereo view configuration has %u views, not 2", vc);
    xr->view_config[0].type = xr->view_config[1].type = XR_TYPE_VIEW_CONFIGURATION_VIEW;
    XR_CHECK(res, xr->instance, out_diag, done,
             xrEnumerateViewConfigurationViews(xr->instance, xr->system,
                                               XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO, 2, &vc,
                                               xr->view_config));
    XrEnvironmentBlendMode modes[8];
    uint32_t mc = 0;
    XR_CHECK(res, xr->instance, out_diag, done,
             xrEnumerateEnvironmentBlendModes(xr->instance, xr->system,
                                              XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO, 0, &mc,
                                              NULL));
    if (mc == 0 || mc > 8)
        return u_diag_set(out_diag, XRSC_ERROR_XR, "", 0, "xrEnumerateEnvironmentBlendModes",
                          "%u environment blend modes", mc);
    XR_CHECK(res, xr->instance, out_diag, done,
             xrEnumerateEnvironmentBlendModes(xr->instance, xr->system,
                                              XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO, mc, &mc,
                                              modes));
    xr->blend_mode = modes[0]; /* the runtime's preferred one */
done:
    return res;
}

/** XR_KHR_vulkan_enable2: the requirements must be queried before the device is made. */
static xrsc_result vulkan_requirements_check(xrsc_xr *xr, xrsc_diag *out_diag)
{
    xrsc_result res = XRSC_OK;
    XrGraphicsRequirementsVulkan2KHR req = {.type = XR_TYPE_GRAPHICS_REQUIREMENTS_VULKAN2_KHR};
    XR_CHECK(res, xr->instance, out_diag, done,
             xr->fn.GetVulkanGraphicsRequirements2KHR(xr->instance, xr->system, &req));
    if (XR_VERSION_MAJOR(req.minApiVersionSupported) > 1 ||
        (XR_VERSION_MAJOR(req.minApiVersionSupported) == 1 &&
         XR_VERSION_MINOR(req.minApiVersionSupported) > 3)) {
        res = u_diag_set(out_diag, XRSC_ERROR_XR, "", 0, "xrGetVulkanGraphicsRequirements2KHR",
                         "the runtime needs Vulkan %u.%u or later; xrsc uses 1.3",
                         (unsigned)XR_VERSION_MAJOR(req.minApiVersionSupported),
                         (unsigned)XR_VERSION_MINOR(req.minApiVersionSupported));
    }
done:
    return res;
}

xrsc_result xrsc_xr_create(const xrsc_xr_options *options, xrsc_xr **out_xr, xrsc_diag *out_diag)
{
    if (!out_xr)
        return u_diag_set(out_diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "out_xr", "NULL");
    *out_xr = NULL;
    xrsc_xr_options opt = {0};
    if (options)
        opt = *options;
    xrsc_result res = XRSC_OK;
    xrsc_xr *xr = calloc(1, sizeof(*xr));
    if (!xr)
        return u_diag_set(out_diag, XRSC_ERROR_OUT_OF_MEMORY, "", 0, "", "out of memory");

    xr_extension_list exts = {0};
    if ((res = extensions_choose(xr, &exts, out_diag)) != XRSC_OK ||
        (res = instance_create(xr, opt.application_name, &exts, out_diag)) != XRSC_OK ||
        (res = system_get(xr, out_diag)) != XRSC_OK ||
        (res = vulkan_requirements_check(xr, out_diag)) != XRSC_OK)
        goto fail;

    gpu_context_hooks hooks = {
        .user = xr,
        .create_instance = hook_create_instance,
        .physical_device = hook_physical_device,
        .create_device = hook_create_device,
    };
    res = xrsc_context_create_hooked(&opt.context, &hooks, &xr->ctx, out_diag);
    if (res != XRSC_OK)
        goto fail;
    U_LOG_D("openxr: runtime '%s', %ux%u recommended per eye, depth layers %s", xr->runtime_name,
            xr->view_config[0].recommendedImageRectWidth,
            xr->view_config[0].recommendedImageRectHeight, xr->ext_depth ? "on" : "off");
    *out_xr = xr;
    return XRSC_OK;

fail:
    xrsc_xr_destroy(&xr);
    return res;
}

void xrsc_xr_destroy(xrsc_xr **pxr)
{
    if (!pxr || !*pxr)
        return;
    xrsc_xr *xr = *pxr;
    /* The application owns the Vulkan objects made through the runtime: they go first, the
     * instance that made them last. */
    xrsc_context_destroy(&xr->ctx);
    if (xr->messenger && xr->fn.DestroyDebugUtilsMessengerEXT)
        xr->fn.DestroyDebugUtilsMessengerEXT(xr->messenger);
    if (xr->instance)
        xrDestroyInstance(xr->instance);
    free(xr);
    *pxr = NULL;
}

xrsc_context *xrsc_xr_context(xrsc_xr *xr) { return xr ? xr->ctx : NULL; }

const char *xrsc_xr_runtime_name(const xrsc_xr *xr) { return xr ? xr->runtime_name : ""; }

void xrsc_xr_recommended_size(const xrsc_xr *xr, uint32_t *out_width, uint32_t *out_height)
{
    if (out_width)
        *out_width = xr ? xr->view_config[0].recommendedImageRectWidth : 0;
    if (out_height)
        *out_height = xr ? xr->view_config[0].recommendedImageRectHeight : 0;
}

uint32_t xrsc_xr_debug_messages(const xrsc_xr *xr, uint32_t *out_errors, uint32_t *out_warnings,
                                uint32_t *out_validation)
{
    if (out_validation)
        *out_validation = xr ? xr->message_validation : 0;
    if (out_errors)
        *out_errors = xr ? xr->message_errors : 0;
    if (out_warnings)
        *out_warnings = xr ? xr->message_warnings : 0;
    return xr ? xr->messages : 0;
}
