// SPDX-License-Identifier: MIT
/**
 * @file test_xr_runtime.c
 * @brief The host_sim runtime as an application sees it through the Khronos loader, and as
 *        the loader sees it (the library on its own).
 *
 * - the library exports only the negotiation entry point and serves every OpenXR 1.0 core
 *   function (the loader calls them without checking);
 * - a session on a Vulkan device made through XR_KHR_vulkan_enable2 goes through
 *   IDLE, READY, SYNCHRONIZED, VISIBLE, FOCUSED, VISIBLE, SYNCHRONIZED, STOPPING, IDLE, EXITING,
 *   twice on one instance (XRSC_RT_FRAMES, then xrRequestExitSession); what it submitted is
 *   captured exactly (HDR clear colours read back from the PFM files);
 * - spaces and views follow the pose stream and the simulated headset; frame times advance
 *   one refresh period per frame on the fast clock;
 * - a lost session (XRSC_RT_LOSE_AFTER) reports LOSS_PENDING and XR_ERROR_SESSION_LOST, and a
 *   new session on the same instance works.
 * With XRSC_VALIDATION=1 the Vulkan validation layer watches the runtime's Vulkan use.
 */
#define _GNU_SOURCE /* dladdr */
#include "testing.h"

#define XR_USE_GRAPHICS_API_VULKAN
#include <vulkan/vulkan.h>
#include <openxr/openxr.h>
#include <openxr/openxr_platform.h>
#include <openxr/openxr_reflection.h>

#include "hs_image.h"

#include <dlfcn.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static const char *const k_core_functions[] = {
    "xrGetInstanceProcAddr", "xrEnumerateApiLayerProperties",
    "xrEnumerateInstanceExtensionProperties", "xrCreateInstance", "xrDestroyInstance",
    "xrGetInstanceProperties", "xrPollEvent", "xrResultToString", "xrStructureTypeToString",
    "xrGetSystem", "xrGetSystemProperties", "xrEnumerateEnvironmentBlendModes", "xrCreateSession",
    "xrDestroySession", "xrEnumerateReferenceSpaces", "xrCreateReferenceSpace",
    "xrGetReferenceSpaceBoundsRect", "xrCreateActionSpace", "xrLocateSpace", "xrDestroySpace",
    "xrEnumerateViewConfigurations", "xrGetViewConfigurationProperties",
    "xrEnumerateViewConfigurationViews", "xrEnumerateSwapchainFormats", "xrCreateSwapchain",
    "xrDestroySwapchain", "xrEnumerateSwapchainImages", "xrAcquireSwapchainImage",
    "xrWaitSwapchainImage", "xrReleaseSwapchainImage", "xrBeginSession", "xrEndSession",
    "xrRequestExitSession", "xrWaitFrame", "xrBeginFrame", "xrEndFrame", "xrLocateViews",
    "xrStringToPath", "xrPathToString", "xrCreateActionSet", "xrDestroyActionSet",
    "xrCreateAction", "xrDestroyAction", "xrSuggestInteractionProfileBindings",
    "xrAttachSessionActionSets", "xrGetCurrentInteractionProfile", "xrGetActionStateBoolean",
    "xrGetActionStateFloat", "xrGetActionStateVector2f", "xrGetActionStatePose", "xrSyncActions",
    "xrEnumerateBoundSourcesForAction", "xrGetInputSourceLocalizedName", "xrApplyHapticFeedback",
    "xrStopHapticFeedback"};
#define CORE_COUNT (sizeof(k_core_functions) / sizeof(k_core_functions[0]))

static const char *result_name(XrResult r)
{
    switch (r) {
#define T_X(name, value)                                                                           \
    case name:                                                                                     \
        return #name;
        XR_LIST_ENUM_XrResult(T_X)
#undef T_X
    default:
        return "?";
    }
}

#define XR_CHECK(call)                                                                             \
    do {                                                                                           \
        XrResult r_ = (call);                                                                      \
        CHECK_MSG(XR_SUCCEEDED(r_), "%s -> %s", #call, result_name(r_));                           \
    } while (0)
#define XR_EXPECT(call, want)                                                                      \
    do {                                                                                           \
        XrResult r_ = (call);                                                                      \
        CHECK_MSG(r_ == (want), "%s -> %s, expected %s", #call, result_name(r_),                   \
                  result_name(want));                                                              \
    } while (0)
#define VK_CHECK(call)                                                                             \
    do {                                                                                           \
        VkResult v_ = (call);                                                                      \
        CHECK_MSG(v_ == VK_SUCCESS, "%s -> VkResult %d", #call, (int)v_);                          \
    } while (0)

/* ---- the runtime library on its own (as the loader sees it) ---- */

typedef enum {
    T_LOADER_INFO = 1,
    T_RUNTIME_REQUEST = 3,
} t_struct_type;
typedef struct {
    int structType;
    uint32_t structVersion;
    size_t structSize;
    uint32_t minInterfaceVersion, maxInterfaceVersion;
    XrVersion minApiVersion, maxApiVersion;
} t_loader_info;
typedef struct {
    int structType;
    uint32_t structVersion;
    size_t structSize;
    uint32_t runtimeInterfaceVersion;
    XrVersion runtimeApiVersion;
    PFN_xrGetInstanceProcAddr getInstanceProcAddr;
} t_runtime_request;
typedef XrResult (*t_negotiate_fn)(const t_loader_info *, t_runtime_request *);

static void library_serves_every_core_function(void)
{
    void *lib = dlopen(XRSC_RUNTIME_LIB, RTLD_NOW | RTLD_LOCAL);
    CHECK_MSG(lib != NULL, "%s", dlerror());
    if (!lib)
        return;
    t_negotiate_fn negotiate = (t_negotiate_fn)dlsym(lib, "xrNegotiateLoaderRuntimeInterface");
    CHECK(negotiate != NULL);
    /* nothing else is exported (a name found may only come from another library, e.g. the
     * loader this test links) */
    const char *hidden[] = {"xrCreateInstance", "xrGetInstanceProcAddr", "hs_pose_stream_load",
                            "hsrt_fail", "xrsc_pose_mul", "u_log"};
    for (size_t i = 0; i < sizeof(hidden) / sizeof(hidden[0]); i++) {
        void *sym = dlsym(lib, hidden[i]);
        Dl_info info = {0};
        CHECK_MSG(!sym || !dladdr(sym, &info) || !info.dli_fname ||
                      !strstr(info.dli_fname, "libxrsc_runtime"),
                  "the runtime exports %s", hidden[i]);
    }
    t_loader_info li = {T_LOADER_INFO, 1, sizeof(li), 1, 1, XR_MAKE_VERSION(1, 0, 0),
                        XR_MAKE_VERSION(1, 0, 0xffff)};
    t_runtime_request rq = {T_RUNTIME_REQUEST, 1, sizeof(rq), 0, 0, NULL};
    t_loader_info bad = li;
    bad.minInterfaceVersion = bad.maxInterfaceVersion = 2;
    XR_EXPECT(negotiate(&bad, &rq), XR_ERROR_INITIALIZATION_FAILED);
    XR_CHECK(negotiate(&li, &rq));
    CHECK_EQ_INT(rq.runtimeInterfaceVersion, 1);
    PFN_xrGetInstanceProcAddr gipa = rq.getInstanceProcAddr;
    CHECK(gipa != NULL);
    if (!gipa) {
        dlclose(lib);
        return;
    }
    PFN_xrCreateInstance create = NULL;
    PFN_xrVoidFunction fn = NULL;
    XR_CHECK(gipa(XR_NULL_HANDLE, "xrCreateInstance", (PFN_xrVoidFunction *)&create));
    XR_EXPECT(gipa(XR_NULL_HANDLE, "xrPollEvent", &fn), XR_ERROR_HANDLE_INVALID);
    unsetenv("XRSC_RT_POSES"); /* the bundled orbit */
    XrInstanceCreateInfo ci = {.type = XR_TYPE_INSTANCE_CREATE_INFO};
    snprintf(ci.applicationInfo.applicationName, sizeof(ci.applicationInfo.applicationName), "t");
    ci.applicationInfo.apiVersion = XR_MAKE_VERSION(1, 0, 0);
    XrInstance inst = XR_NULL_HANDLE;
    XR_CHECK(create(&ci, &inst));
    if (inst) {
        for (size_t i = 0; i < CORE_COUNT; i++) {
            fn = NULL;
            XrResult r = gipa(inst, k_core_functions[i], &fn);
            CHECK_MSG(r == XR_SUCCESS && fn, "%s -> %s", k_core_functions[i], result_name(r));
        }
        /* extension functions only when the extension is enabled */
        XR_EXPECT(gipa(inst, "xrCreateVulkanInstanceKHR", &fn), XR_ERROR_FUNCTION_UNSUPPORTED);
        XR_EXPECT(gipa(inst, "xrGetVulkanGraphicsDeviceKHR", &fn), XR_ERROR_FUNCTION_UNSUPPORTED);
        XR_EXPECT(gipa(inst, "xrNoSuchFunction", &fn), XR_ERROR_FUNCTION_UNSUPPORTED);
        CHECK(fn == NULL);
        PFN_xrDestroyInstance destroy = NULL;
        XR_CHECK(gipa(inst, "xrDestroyInstance", (PFN_xrVoidFunction *)&destroy));
        if (destroy)
            XR_CHECK(destroy(inst));
    }
    /* a second API version or an unknown extension is refused */
    ci.applicationInfo.apiVersion = XR_MAKE_VERSION(2, 0, 0);
    XR_EXPECT(create(&ci, &inst), XR_ERROR_API_VERSION_UNSUPPORTED);
    ci.applicationInfo.apiVersion = XR_MAKE_VERSION(1, 0, 0);
    const char *ext = "XR_KHR_no_such_extension";
    ci.enabledExtensionCount = 1;
    ci.enabledExtensionNames = &ext;
    XR_EXPECT(create(&ci, &inst), XR_ERROR_EXTENSION_NOT_PRESENT);
    dlclose(lib);
}

/* ---- issue 20: the conformance rules, called on the library directly (no loader in between,
 * so made-up handles reach the runtime) ---- */

typedef struct t_direct {
    void *lib;
    PFN_xrGetInstanceProcAddr gipa;
    XrInstance inst;
} t_direct;

/** Negotiates with the library and creates an instance with an API layer name passed through. */
static bool direct_open(t_direct *d)
{
    memset(d, 0, sizeof(*d));
    d->lib = dlopen(XRSC_RUNTIME_LIB, RTLD_NOW | RTLD_LOCAL);
    t_negotiate_fn negotiate =
        d->lib ? (t_negotiate_fn)dlsym(d->lib, "xrNegotiateLoaderRuntimeInterface") : NULL;
    t_loader_info li = {T_LOADER_INFO, 1, sizeof(li), 1, 1, XR_MAKE_VERSION(1, 0, 0),
                        XR_MAKE_VERSION(1, 0, 0xffff)};
    t_runtime_request rq = {T_RUNTIME_REQUEST, 1, sizeof(rq), 0, 0, NULL};
    CHECK(negotiate && negotiate(&li, &rq) == XR_SUCCESS && rq.getInstanceProcAddr);
    if (!negotiate || !rq.getInstanceProcAddr)
        return false;
    d->gipa = rq.getInstanceProcAddr;
    PFN_xrCreateInstance create = NULL;
    XR_CHECK(d->gipa(XR_NULL_HANDLE, "xrCreateInstance", (PFN_xrVoidFunction *)&create));
    XrInstanceCreateInfo ci = {.type = XR_TYPE_INSTANCE_CREATE_INFO};
    snprintf(ci.applicationInfo.applicationName, sizeof(ci.applicationInfo.applicationName), "t");
    ci.applicationInfo.apiVersion = XR_MAKE_VERSION(1, 0, 0);
    /* the loader passes the application's layer names through: they are ignored */
    const char *layer = "XR_APILAYER_LUNARG_core_validation";
    ci.enabledApiLayerCount = 1;
    ci.enabledApiLayerNames = &layer;
    XR_CHECK(create(&ci, &d->inst));
    return d->inst != XR_NULL_HANDLE;
}

/** Declares PFN_xr<name> <name>, looked up on d's instance. */
#define T_PROC(d, name)                                                                            \
    PFN_xr##name name = NULL;                                                                      \
    XR_CHECK((d)->gipa((d)->inst, "xr" #name, (PFN_xrVoidFunction *)&name))

static XrPath t_path(t_direct *d, const char *s)
{
    T_PROC(d, StringToPath);
    XrPath p = XR_NULL_PATH;
    XR_CHECK(StringToPath(d->inst, s, &p));
    return p;
}

/** xrSuggestInteractionProfileBindings of one binding: the result. */
static XrResult t_suggest(t_direct *d, const char *profile, XrAction action, const char *binding)
{
    T_PROC(d, SuggestInteractionProfileBindings);
    XrActionSuggestedBinding sb = {action, t_path(d, binding)};
    XrInteractionProfileSuggestedBinding isb = {.type =
                                                    XR_TYPE_INTERACTION_PROFILE_SUGGESTED_BINDING,
                                                .interactionProfile = t_path(d, profile),
                                                .countSuggestedBindings = 1,
                                                .suggestedBindings = &sb};
    return SuggestInteractionProfileBindings(d->inst, &isb);
}

static void runtime_applies_the_conformance_rules(void)
{
    t_direct d;
    if (!direct_open(&d)) {
        if (d.lib)
            dlclose(d.lib);
        return;
    }
    T_PROC(&d, GetSystem);
    T_PROC(&d, CreateActionSet);
    T_PROC(&d, DestroyActionSet);
    T_PROC(&d, CreateAction);
    T_PROC(&d, DestroyAction);
    T_PROC(&d, DestroyInstance);
    /* any form factor but HMD: FORM_FACTOR_UNSUPPORTED, also one no version defines */
    XrSystemGetInfo gi = {.type = XR_TYPE_SYSTEM_GET_INFO, .formFactor = (XrFormFactor)0x7fff};
    XrSystemId sys = XR_NULL_SYSTEM_ID;
    XR_EXPECT(GetSystem(d.inst, &gi, &sys), XR_ERROR_FORM_FACTOR_UNSUPPORTED);
    /* names: empty, localized empty, localized duplicated */
    XrActionSetCreateInfo asci = {.type = XR_TYPE_ACTION_SET_CREATE_INFO};
    snprintf(asci.localizedActionSetName, sizeof(asci.localizedActionSetName), "Set");
    XrActionSet set = XR_NULL_HANDLE, set2 = XR_NULL_HANDLE;
    XR_EXPECT(CreateActionSet(d.inst, &asci, &set), XR_ERROR_NAME_INVALID);
    snprintf(asci.actionSetName, sizeof(asci.actionSetName), "set");
    XR_CHECK(CreateActionSet(d.inst, &asci, &set));
    snprintf(asci.actionSetName, sizeof(asci.actionSetName), "set2");
    XR_EXPECT(CreateActionSet(d.inst, &asci, &set2), XR_ERROR_LOCALIZED_NAME_DUPLICATED);
    asci.localizedActionSetName[0] = '\0';
    XR_EXPECT(CreateActionSet(d.inst, &asci, &set2), XR_ERROR_LOCALIZED_NAME_INVALID);
    XrActionCreateInfo aci = {.type = XR_TYPE_ACTION_CREATE_INFO,
                              .actionType = XR_ACTION_TYPE_BOOLEAN_INPUT};
    snprintf(aci.actionName, sizeof(aci.actionName), "click");
    snprintf(aci.localizedActionName, sizeof(aci.localizedActionName), "Click");
    /* subaction paths: top-level user paths, each once */
    XrPath subs[2] = {t_path(&d, "/user/head"), t_path(&d, "/user/head")};
    aci.countSubactionPaths = 2;
    aci.subactionPaths = subs;
    XrAction a = XR_NULL_HANDLE, a2 = XR_NULL_HANDLE;
    XR_EXPECT(CreateAction(set, &aci, &a), XR_ERROR_PATH_UNSUPPORTED);
    subs[1] = t_path(&d, "/user/invalid");
    XR_EXPECT(CreateAction(set, &aci, &a), XR_ERROR_PATH_UNSUPPORTED);
    subs[1] = t_path(&d, "/user/hand/left");
    XR_CHECK(CreateAction(set, &aci, &a));
    snprintf(aci.actionName, sizeof(aci.actionName), "click2");
    XR_EXPECT(CreateAction(set, &aci, &a2), XR_ERROR_LOCALIZED_NAME_DUPLICATED);
    /* the interaction-profile table */
    const char *simple = "/interaction_profiles/khr/simple_controller";
    const char *touch = "/interaction_profiles/oculus/touch_controller";
    XR_CHECK(t_suggest(&d, simple, a, "/user/hand/left/input/select/click"));
    XR_CHECK(t_suggest(&d, simple, a, "/user/hand/right/input/select")); /* identifier alone */
    XR_CHECK(t_suggest(&d, touch, a, "/user/hand/left/input/x/click"));
    XR_EXPECT(t_suggest(&d, simple, a, "/user/hand/left/input/trigger/value"),
              XR_ERROR_PATH_UNSUPPORTED);
    XR_EXPECT(t_suggest(&d, touch, a, "/user/hand/right/input/x/click"), XR_ERROR_PATH_UNSUPPORTED);
    XR_EXPECT(t_suggest(&d, touch, a, "/user/head/input/x/click"), XR_ERROR_PATH_UNSUPPORTED);
    XR_EXPECT(t_suggest(&d, "/interaction_profiles/xrsc/no_such_controller", a,
                        "/user/hand/left/input/select/click"),
              XR_ERROR_PATH_UNSUPPORTED);
    /* handles: made-up and destroyed values are HANDLE_INVALID, not dereferenced */
    XR_EXPECT(CreateActionSet((XrInstance)(uintptr_t)0x1234, &asci, &set2),
              XR_ERROR_HANDLE_INVALID);
    XR_CHECK(DestroyActionSet(set)); /* destroys its action too */
    XR_EXPECT(DestroyAction(a), XR_ERROR_HANDLE_INVALID);
    XR_EXPECT(DestroyActionSet(set), XR_ERROR_HANDLE_INVALID);
    XR_CHECK(DestroyInstance(d.inst));
    XR_EXPECT(DestroyInstance(d.inst), XR_ERROR_HANDLE_INVALID);
    PFN_xrVoidFunction fn = NULL;
    XR_EXPECT(d.gipa(d.inst, "xrGetSystem", &fn), XR_ERROR_HANDLE_INVALID);
    dlclose(d.lib);
}

/* ---- an application through the loader ---- */

typedef struct t_app {
    XrInstance instance;
    XrSystemId system;
    PFN_xrGetVulkanGraphicsRequirements2KHR GetRequirements2;
    PFN_xrCreateVulkanInstanceKHR CreateVulkanInstance;
    PFN_xrGetVulkanGraphicsDevice2KHR GetDevice2;
    PFN_xrCreateVulkanDeviceKHR CreateVulkanDevice;
    VkInstance vk_instance;
    VkPhysicalDevice physical;
    VkDevice device;
    uint32_t family;
    VkQueue queue;
    VkCommandPool pool;
    VkCommandBuffer cmd;
    VkFence fence;
    VkDebugUtilsMessengerEXT messenger;
    uint32_t validation_errors;
} t_app;

static VKAPI_ATTR VkBool32 VKAPI_CALL on_vk_message(VkDebugUtilsMessageSeverityFlagBitsEXT sev,
                                                   VkDebugUtilsMessageTypeFlagsEXT type,
                                                   const VkDebugUtilsMessengerCallbackDataEXT *data,
                                                   void *user)
{
    (void)type;
    if (sev & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) {
        ((t_app *)user)->validation_errors++;
        fprintf(stderr, "validation: %s\n", data->pMessage);
    }
    return VK_FALSE;
}

static bool has_layer(const char *name)
{
    uint32_t n = 0;
    vkEnumerateInstanceLayerProperties(&n, NULL);
    VkLayerProperties *p = calloc(n ? n : 1, sizeof(*p));
    vkEnumerateInstanceLayerProperties(&n, p);
    bool found = false;
    for (uint32_t i = 0; i < n; i++)
        found |= !strcmp(p[i].layerName, name);
    free(p);
    return found;
}

static bool app_open(t_app *app)
{
    memset(app, 0, sizeof(*app));
    setenv("XR_RUNTIME_JSON", XRSC_RUNTIME_JSON, 1);
    const char *exts[] = {XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME,
                          XR_KHR_COMPOSITION_LAYER_DEPTH_EXTENSION_NAME};
    XrInstanceCreateInfo ci = {.type = XR_TYPE_INSTANCE_CREATE_INFO,
                               .enabledExtensionCount = 2,
                               .enabledExtensionNames = exts};
    snprintf(ci.applicationInfo.applicationName, sizeof(ci.applicationInfo.applicationName),
             "test_xr_runtime");
    ci.applicationInfo.apiVersion = XR_MAKE_VERSION(1, 0, 0);
    XrResult r = xrCreateInstance(&ci, &app->instance);
    CHECK_MSG(XR_SUCCEEDED(r), "xrCreateInstance -> %s", result_name(r));
    if (XR_FAILED(r))
        return false;
    XrInstanceProperties props = {.type = XR_TYPE_INSTANCE_PROPERTIES};
    XR_CHECK(xrGetInstanceProperties(app->instance, &props));
    CHECK(strstr(props.runtimeName, "xrsc") != NULL);
    XrSystemGetInfo gi = {.type = XR_TYPE_SYSTEM_GET_INFO,
                          .formFactor = XR_FORM_FACTOR_HANDHELD_DISPLAY};
    XR_EXPECT(xrGetSystem(app->instance, &gi, &app->system), XR_ERROR_FORM_FACTOR_UNSUPPORTED);
    gi.formFactor = XR_FORM_FACTOR_HEAD_MOUNTED_DISPLAY;
    XR_CHECK(xrGetSystem(app->instance, &gi, &app->system));
#define T_LOAD(field, name)                                                                        \
    XR_CHECK(xrGetInstanceProcAddr(app->instance, name, (PFN_xrVoidFunction *)&app->field));
    T_LOAD(GetRequirements2, "xrGetVulkanGraphicsRequirements2KHR");
    T_LOAD(CreateVulkanInstance, "xrCreateVulkanInstanceKHR");
    T_LOAD(GetDevice2, "xrGetVulkanGraphicsDevice2KHR");
    T_LOAD(CreateVulkanDevice, "xrCreateVulkanDeviceKHR");
#undef T_LOAD
    if (!app->GetRequirements2 || !app->CreateVulkanInstance || !app->GetDevice2 ||
        !app->CreateVulkanDevice)
        return false;
    /* without the graphics requirements, no session */
    XrGraphicsBindingVulkan2KHR nb = {.type = XR_TYPE_GRAPHICS_BINDING_VULKAN2_KHR};
    XrSessionCreateInfo sci = {.type = XR_TYPE_SESSION_CREATE_INFO, .next = &nb,
                               .systemId = app->system};
    XrSession none = XR_NULL_HANDLE;
    XR_EXPECT(xrCreateSession(app->instance, &sci, &none),
              XR_ERROR_GRAPHICS_REQUIREMENTS_CALL_MISSING);
    XrGraphicsRequirementsVulkan2KHR req = {.type = XR_TYPE_GRAPHICS_REQUIREMENTS_VULKAN2_KHR};
    XR_CHECK(app->GetRequirements2(app->instance, app->system, &req));
    CHECK(req.minApiVersionSupported <= XR_MAKE_VERSION(1, 1, 0));

    bool validate = getenv("XRSC_VALIDATION") && !strcmp(getenv("XRSC_VALIDATION"), "1") &&
                    has_layer("VK_LAYER_KHRONOS_validation");
    const char *layers[] = {"VK_LAYER_KHRONOS_validation"};
    const char *vexts[] = {VK_EXT_DEBUG_UTILS_EXTENSION_NAME};
    VkApplicationInfo ai = {.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO,
                            .pApplicationName = "test_xr_runtime",
                            .apiVersion = VK_API_VERSION_1_1};
    VkInstanceCreateInfo vci = {.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO,
                                .pApplicationInfo = &ai,
                                .enabledLayerCount = validate ? 1 : 0,
                                .ppEnabledLayerNames = layers,
                                .enabledExtensionCount = validate ? 1 : 0,
                                .ppEnabledExtensionNames = vexts};
    XrVulkanInstanceCreateInfoKHR xvci = {.type = XR_TYPE_VULKAN_INSTANCE_CREATE_INFO_KHR,
                                          .systemId = app->system,
                                          .pfnGetInstanceProcAddr = vkGetInstanceProcAddr,
                                          .vulkanCreateInfo = &vci};
    VkResult vr = VK_ERROR_UNKNOWN;
    XR_CHECK(app->CreateVulkanInstance(app->instance, &xvci, &app->vk_instance, &vr));
    CHECK_EQ_INT(vr, VK_SUCCESS);
    if (vr != VK_SUCCESS)
        return false;
    if (validate) {
        PFN_vkCreateDebugUtilsMessengerEXT cm = (PFN_vkCreateDebugUtilsMessengerEXT)
            vkGetInstanceProcAddr(app->vk_instance, "vkCreateDebugUtilsMessengerEXT");
        VkDebugUtilsMessengerCreateInfoEXT mci = {
            .sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT,
            .messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT,
            .messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT,
            .pfnUserCallback = on_vk_message,
            .pUserData = app};
        if (cm)
            VK_CHECK(cm(app->vk_instance, &mci, NULL, &app->messenger));
    }
    XrVulkanGraphicsDeviceGetInfoKHR dgi = {.type = XR_TYPE_VULKAN_GRAPHICS_DEVICE_GET_INFO_KHR,
                                            .systemId = app->system,
                                            .vulkanInstance = app->vk_instance};
    XR_CHECK(app->GetDevice2(app->instance, &dgi, &app->physical));
    if (!app->physical)
        return false;
    uint32_t nq = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(app->physical, &nq, NULL);
    VkQueueFamilyProperties qp[16];
    nq = nq > 16 ? 16 : nq;
    vkGetPhysicalDeviceQueueFamilyProperties(app->physical, &nq, qp);
    app->family = UINT32_MAX;
    for (uint32_t i = 0; i < nq && app->family == UINT32_MAX; i++)
        if (qp[i].queueFlags & VK_QUEUE_GRAPHICS_BIT)
            app->family = i;
    CHECK(app->family != UINT32_MAX);
    float prio = 1.0f;
    VkDeviceQueueCreateInfo qci = {.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO,
                                   .queueFamilyIndex = app->family,
                                   .queueCount = 1,
                                   .pQueuePriorities = &prio};
    VkDeviceCreateInfo dci = {.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO,
                              .queueCreateInfoCount = 1,
                              .pQueueCreateInfos = &qci};
    XrVulkanDeviceCreateInfoKHR xdci = {.type = XR_TYPE_VULKAN_DEVICE_CREATE_INFO_KHR,
                                        .systemId = app->system,
                                        .pfnGetInstanceProcAddr = vkGetInstanceProcAddr,
                                        .vulkanPhysicalDevice = app->physical,
                                        .vulkanCreateInfo = &dci};
    vr = VK_ERROR_UNKNOWN;
    XR_CHECK(app->CreateVulkanDevice(app->instance, &xdci, &app->device, &vr));
    CHECK_EQ_INT(vr, VK_SUCCESS);
    if (vr != VK_SUCCESS)
        return false;
    vkGetDeviceQueue(app->device, app->family, 0, &app->queue);
    VkCommandPoolCreateInfo pci = {.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO,
                                   .flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT,
                                   .queueFamilyIndex = app->family};
    VK_CHECK(vkCreateCommandPool(app->device, &pci, NULL, &app->pool));
    VkCommandBufferAllocateInfo cai = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO,
                                       .commandPool = app->pool,
                                       .level = VK_COMMAND_BUFFER_LEVEL_PRIMARY,
                                       .commandBufferCount = 1};
    VK_CHECK(vkAllocateCommandBuffers(app->device, &cai, &app->cmd));
    VkFenceCreateInfo fci = {.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    VK_CHECK(vkCreateFence(app->device, &fci, NULL, &app->fence));
    return true;
}

static void app_close(t_app *app)
{
    if (app->device) {
        vkDeviceWaitIdle(app->device);
        vkDestroyFence(app->device, app->fence, NULL);
        vkDestroyCommandPool(app->device, app->pool, NULL);
        vkDestroyDevice(app->device, NULL);
    }
    if (app->instance)
        XR_CHECK(xrDestroyInstance(app->instance));
    if (app->messenger) {
        PFN_vkDestroyDebugUtilsMessengerEXT dm = (PFN_vkDestroyDebugUtilsMessengerEXT)
            vkGetInstanceProcAddr(app->vk_instance, "vkDestroyDebugUtilsMessengerEXT");
        if (dm)
            dm(app->vk_instance, app->messenger, NULL);
    }
    if (app->vk_instance)
        vkDestroyInstance(app->vk_instance, NULL);
    CHECK_EQ_INT(app->validation_errors, 0);
}

/* ---- one session ---- */

#define T_W 64
#define T_H 48
#define T_MAX_EVENTS 32

typedef struct t_session {
    XrSession session;
    XrSessionState state;
    XrSessionState events[T_MAX_EVENTS];
    int event_count;
    bool lost;
    XrSpace local, stage, view;
    XrSwapchain color[2], depth[2];
    VkImage color_img[2][4], depth_img[2][4];
    XrActionSet set;
    XrAction select, aim;
} t_session;

static void poll(t_app *app, t_session *ts)
{
    XrEventDataBuffer ev = {.type = XR_TYPE_EVENT_DATA_BUFFER};
    while (xrPollEvent(app->instance, &ev) == XR_SUCCESS) {
        if (ev.type == XR_TYPE_EVENT_DATA_SESSION_STATE_CHANGED) {
            const XrEventDataSessionStateChanged *sc = (const XrEventDataSessionStateChanged *)&ev;
            CHECK(sc->session == ts->session);
            ts->state = sc->state;
            if (ts->event_count < T_MAX_EVENTS)
                ts->events[ts->event_count++] = sc->state;
            if (sc->state == XR_SESSION_STATE_LOSS_PENDING)
                ts->lost = true;
        }
        ev = (XrEventDataBuffer){.type = XR_TYPE_EVENT_DATA_BUFFER};
    }
}

static XrSwapchain make_swapchain(t_app *app, t_session *ts, int64_t format, XrSwapchainUsageFlags u,
                                  VkImage *images)
{
    (void)app;
    XrSwapchainCreateInfo ci = {.type = XR_TYPE_SWAPCHAIN_CREATE_INFO,
                                .usageFlags = u,
                                .format = format,
                                .sampleCount = 1,
                                .width = T_W,
                                .height = T_H,
                                .faceCount = 1,
                                .arraySize = 1,
                                .mipCount = 1};
    XrSwapchain sc = XR_NULL_HANDLE;
    XR_CHECK(xrCreateSwapchain(ts->session, &ci, &sc));
    uint32_t n = 0;
    XR_CHECK(xrEnumerateSwapchainImages(sc, 0, &n, NULL));
    CHECK(n >= 1 && n <= 4);
    XrSwapchainImageVulkan2KHR imgs[4];
    for (int i = 0; i < 4; i++)
        imgs[i] = (XrSwapchainImageVulkan2KHR){.type = XR_TYPE_SWAPCHAIN_IMAGE_VULKAN2_KHR};
    XR_CHECK(xrEnumerateSwapchainImages(sc, n, &n, (XrSwapchainImageBaseHeader *)imgs));
    for (uint32_t i = 0; i < n && i < 4; i++)
        images[i] = imgs[i].image;
    return sc;
}

static void session_open(t_app *app, t_session *ts)
{
    memset(ts, 0, sizeof(*ts));
    XrGraphicsBindingVulkan2KHR b = {.type = XR_TYPE_GRAPHICS_BINDING_VULKAN2_KHR,
                                     .instance = app->vk_instance,
                                     .physicalDevice = app->physical,
                                     .device = app->device,
                                     .queueFamilyIndex = app->family,
                                     .queueIndex = 0};
    XrSessionCreateInfo sci = {.type = XR_TYPE_SESSION_CREATE_INFO, .next = &b,
                               .systemId = app->system};
    XR_CHECK(xrCreateSession(app->instance, &sci, &ts->session));
    XrSession second = XR_NULL_HANDLE;
    XR_EXPECT(xrCreateSession(app->instance, &sci, &second), XR_ERROR_LIMIT_REACHED);
    XrReferenceSpaceCreateInfo rci = {.type = XR_TYPE_REFERENCE_SPACE_CREATE_INFO,
                                      .poseInReferenceSpace = {.orientation = {0, 0, 0, 1}}};
    rci.referenceSpaceType = XR_REFERENCE_SPACE_TYPE_LOCAL;
    XR_CHECK(xrCreateReferenceSpace(ts->session, &rci, &ts->local));
    rci.referenceSpaceType = XR_REFERENCE_SPACE_TYPE_STAGE;
    XR_CHECK(xrCreateReferenceSpace(ts->session, &rci, &ts->stage));
    rci.referenceSpaceType = XR_REFERENCE_SPACE_TYPE_VIEW;
    XR_CHECK(xrCreateReferenceSpace(ts->session, &rci, &ts->view));
    XrSpace unused;
    rci.referenceSpaceType = XR_REFERENCE_SPACE_TYPE_UNBOUNDED_MSFT;
    XR_EXPECT(xrCreateReferenceSpace(ts->session, &rci, &unused),
              XR_ERROR_REFERENCE_SPACE_UNSUPPORTED);
    rci.referenceSpaceType = XR_REFERENCE_SPACE_TYPE_LOCAL;
    rci.poseInReferenceSpace.orientation.w = 2.0f;
    XR_EXPECT(xrCreateReferenceSpace(ts->session, &rci, &unused), XR_ERROR_POSE_INVALID);
    uint32_t nf = 0;
    int64_t formats[16];
    XR_CHECK(xrEnumerateSwapchainFormats(ts->session, 16, &nf, formats));
    bool has_f16 = false, has_d32 = false;
    for (uint32_t i = 0; i < nf; i++) {
        has_f16 |= formats[i] == VK_FORMAT_R16G16B16A16_SFLOAT;
        has_d32 |= formats[i] == VK_FORMAT_D32_SFLOAT;
    }
    CHECK(has_f16 && has_d32);
    for (int e = 0; e < 2; e++) {
        ts->color[e] = make_swapchain(app, ts, VK_FORMAT_R16G16B16A16_SFLOAT,
                                      XR_SWAPCHAIN_USAGE_COLOR_ATTACHMENT_BIT |
                                          XR_SWAPCHAIN_USAGE_TRANSFER_DST_BIT,
                                      ts->color_img[e]);
        ts->depth[e] = make_swapchain(app, ts, VK_FORMAT_D32_SFLOAT,
                                      XR_SWAPCHAIN_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT |
                                          XR_SWAPCHAIN_USAGE_TRANSFER_DST_BIT,
                                      ts->depth_img[e]);
    }
    /* actions: bindings are accepted, nothing is ever active */
    XrActionSetCreateInfo asci = {.type = XR_TYPE_ACTION_SET_CREATE_INFO};
    snprintf(asci.actionSetName, sizeof(asci.actionSetName), "gameplay");
    snprintf(asci.localizedActionSetName, sizeof(asci.localizedActionSetName), "Gameplay");
    XR_CHECK(xrCreateActionSet(app->instance, &asci, &ts->set));
    XrActionCreateInfo aci = {.type = XR_TYPE_ACTION_CREATE_INFO,
                              .actionType = XR_ACTION_TYPE_BOOLEAN_INPUT};
    snprintf(aci.actionName, sizeof(aci.actionName), "select");
    snprintf(aci.localizedActionName, sizeof(aci.localizedActionName), "Select");
    XR_CHECK(xrCreateAction(ts->set, &aci, &ts->select));
    aci.actionType = XR_ACTION_TYPE_POSE_INPUT;
    snprintf(aci.actionName, sizeof(aci.actionName), "aim");
    /* localized names are unique within a set, as names are */
    snprintf(aci.localizedActionName, sizeof(aci.localizedActionName), "Aim");
    XR_CHECK(xrCreateAction(ts->set, &aci, &ts->aim));
    XrPath profile, click, pose, bad;
    XR_CHECK(xrStringToPath(app->instance, "/interaction_profiles/khr/simple_controller", &profile));
    XR_CHECK(xrStringToPath(app->instance, "/user/hand/left/input/select/click", &click));
    XR_CHECK(xrStringToPath(app->instance, "/user/hand/left/input/aim/pose", &pose));
    XR_EXPECT(xrStringToPath(app->instance, "/user//hand", &bad), XR_ERROR_PATH_FORMAT_INVALID);
    char buf[XR_MAX_PATH_LENGTH];
    uint32_t len = 0;
    XR_CHECK(xrPathToString(app->instance, click, sizeof(buf), &len, buf));
    CHECK(!strcmp(buf, "/user/hand/left/input/select/click"));
    XrActionSuggestedBinding sb[2] = {{ts->select, click}, {ts->aim, pose}};
    XrInteractionProfileSuggestedBinding isb = {.type = XR_TYPE_INTERACTION_PROFILE_SUGGESTED_BINDING,
                                                .interactionProfile = profile,
                                                .countSuggestedBindings = 2,
                                                .suggestedBindings = sb};
    XR_CHECK(xrSuggestInteractionProfileBindings(app->instance, &isb));
    XrSessionActionSetsAttachInfo att = {.type = XR_TYPE_SESSION_ACTION_SETS_ATTACH_INFO,
                                         .countActionSets = 1,
                                         .actionSets = &ts->set};
    XR_CHECK(xrAttachSessionActionSets(ts->session, &att));
    XR_EXPECT(xrAttachSessionActionSets(ts->session, &att), XR_ERROR_ACTIONSETS_ALREADY_ATTACHED);
    XrActionSpaceCreateInfo spi = {.type = XR_TYPE_ACTION_SPACE_CREATE_INFO,
                                   .action = ts->aim,
                                   .poseInActionSpace = {.orientation = {0, 0, 0, 1}}};
    XrSpace aim_space;
    XR_CHECK(xrCreateActionSpace(ts->session, &spi, &aim_space));
    poll(app, ts);
}

static void session_close(t_session *ts)
{
    for (int e = 0; e < 2; e++) {
        XR_CHECK(xrDestroySwapchain(ts->color[e]));
        XR_CHECK(xrDestroySwapchain(ts->depth[e]));
    }
    XR_CHECK(xrDestroySpace(ts->stage));
    XR_CHECK(xrDestroySession(ts->session));
    XR_CHECK(xrDestroyActionSet(ts->set));
}

static void image_barrier(VkCommandBuffer cmd, VkImage img, VkImageAspectFlags aspect,
                          VkImageLayout from, VkImageLayout to)
{
    VkImageMemoryBarrier b = {.sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER,
                              .srcAccessMask = VK_ACCESS_MEMORY_WRITE_BIT,
                              .dstAccessMask = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT,
                              .oldLayout = from,
                              .newLayout = to,
                              .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                              .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                              .image = img,
                              .subresourceRange = {aspect, 0, 1, 0, 1}};
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
                         VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, 0, 0, NULL, 0, NULL, 1, &b);
}

/** The HDR colour eye e shows in frame f (exact in half precision). */
static void frame_color(int f, int e, float out[4])
{
    out[0] = 0.25f + 0.5f * (float)e;
    out[1] = 0.125f * (float)(f % 8);
    out[2] = 2.0f + (float)f; /* above 1: the capture keeps it in the PFM */
    out[3] = 1.0f;
}

/** Renders (clears) and submits one frame; returns whether it was shown. */
static bool render_frame(t_app *app, t_session *ts, int frame, XrTime *io_last_time)
{
    XrFrameState fs = {.type = XR_TYPE_FRAME_STATE};
    XR_CHECK(xrWaitFrame(ts->session, NULL, &fs));
    if (*io_last_time && app->validation_errors == 0)
        CHECK_EQ_INT(fs.predictedDisplayTime - *io_last_time, fs.predictedDisplayPeriod);
    CHECK_NEAR(fs.predictedDisplayPeriod, 1e9 / 90.0, 1.0);
    *io_last_time = fs.predictedDisplayTime;
    XR_CHECK(xrBeginFrame(ts->session, NULL));
    XrViewLocateInfo vli = {.type = XR_TYPE_VIEW_LOCATE_INFO,
                            .viewConfigurationType = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO,
                            .displayTime = fs.predictedDisplayTime,
                            .space = ts->local};
    XrViewState vs = {.type = XR_TYPE_VIEW_STATE};
    XrView views[2] = {{.type = XR_TYPE_VIEW}, {.type = XR_TYPE_VIEW}};
    uint32_t nv = 0;
    XR_CHECK(xrLocateViews(ts->session, &vli, &vs, 2, &nv, views));
    CHECK_EQ_INT(nv, 2);
    CHECK(vs.viewStateFlags & XR_VIEW_STATE_POSITION_VALID_BIT);
    /* the eyes are one IPD apart and the FOVs are the simulated headset's */
    float dx = views[1].pose.position.x - views[0].pose.position.x,
          dy = views[1].pose.position.y - views[0].pose.position.y,
          dz = views[1].pose.position.z - views[0].pose.position.z;
    CHECK_NEAR(sqrtf(dx * dx + dy * dy + dz * dz), 0.063, 1e-4);
    CHECK(views[0].fov.angleLeft < -0.5f && views[1].fov.angleRight > 0.5f);
    XrCompositionLayerProjectionView pv[2];
    XrCompositionLayerDepthInfoKHR di[2];
    VkCommandBufferBeginInfo bi = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    VK_CHECK(vkBeginCommandBuffer(app->cmd, &bi));
    for (int e = 0; e < 2; e++) {
        uint32_t ci = 0, dix = 0;
        XR_CHECK(xrAcquireSwapchainImage(ts->color[e], NULL, &ci));
        XrSwapchainImageWaitInfo wi = {.type = XR_TYPE_SWAPCHAIN_IMAGE_WAIT_INFO,
                                       .timeout = XR_INFINITE_DURATION};
        XR_CHECK(xrWaitSwapchainImage(ts->color[e], &wi));
        XR_CHECK(xrAcquireSwapchainImage(ts->depth[e], NULL, &dix));
        XR_CHECK(xrWaitSwapchainImage(ts->depth[e], &wi));
        VkImage c = ts->color_img[e][ci], d = ts->depth_img[e][dix];
        float rgba[4];
        frame_color(frame, e, rgba);
        VkClearColorValue cv = {.float32 = {rgba[0], rgba[1], rgba[2], rgba[3]}};
        VkImageSubresourceRange cr = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
        image_barrier(app->cmd, c, VK_IMAGE_ASPECT_COLOR_BIT,
                      VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
        vkCmdClearColorImage(app->cmd, c, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &cv, 1, &cr);
        image_barrier(app->cmd, c, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                      VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
        VkClearDepthStencilValue dv = {.depth = 0.5f};
        VkImageSubresourceRange dr = {VK_IMAGE_ASPECT_DEPTH_BIT, 0, 1, 0, 1};
        image_barrier(app->cmd, d, VK_IMAGE_ASPECT_DEPTH_BIT,
                      VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL,
                      VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
        vkCmdClearDepthStencilImage(app->cmd, d, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &dv, 1, &dr);
        image_barrier(app->cmd, d, VK_IMAGE_ASPECT_DEPTH_BIT, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                      VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL);
        di[e] = (XrCompositionLayerDepthInfoKHR){
            .type = XR_TYPE_COMPOSITION_LAYER_DEPTH_INFO_KHR,
            .subImage = {ts->depth[e], {{0, 0}, {T_W, T_H}}, 0},
            .minDepth = 0.0f,
            .maxDepth = 1.0f,
            .nearZ = 0.05f,
            .farZ = 100.0f};
        pv[e] = (XrCompositionLayerProjectionView){
            .type = XR_TYPE_COMPOSITION_LAYER_PROJECTION_VIEW,
            .next = &di[e],
            .pose = views[e].pose,
            .fov = views[e].fov,
            .subImage = {ts->color[e], {{0, 0}, {T_W, T_H}}, 0}};
    }
    VK_CHECK(vkEndCommandBuffer(app->cmd));
    VkSubmitInfo si = {.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO,
                       .commandBufferCount = 1,
                       .pCommandBuffers = &app->cmd};
    VK_CHECK(vkQueueSubmit(app->queue, 1, &si, app->fence));
    VK_CHECK(vkWaitForFences(app->device, 1, &app->fence, VK_TRUE, UINT64_MAX));
    VK_CHECK(vkResetFences(app->device, 1, &app->fence));
    for (int e = 0; e < 2; e++) {
        XR_CHECK(xrReleaseSwapchainImage(ts->color[e], NULL));
        XR_CHECK(xrReleaseSwapchainImage(ts->depth[e], NULL));
    }
    XrCompositionLayerProjection layer = {.type = XR_TYPE_COMPOSITION_LAYER_PROJECTION,
                                          .space = ts->local,
                                          .viewCount = 2,
                                          .views = pv};
    const XrCompositionLayerBaseHeader *layers[] = {(const XrCompositionLayerBaseHeader *)&layer};
    XrFrameEndInfo fei = {.type = XR_TYPE_FRAME_END_INFO,
                          .displayTime = fs.predictedDisplayTime,
                          .environmentBlendMode = XR_ENVIRONMENT_BLEND_MODE_OPAQUE,
                          .layerCount = fs.shouldRender ? 1 : 0,
                          .layers = layers};
    XR_CHECK(xrEndFrame(ts->session, &fei));
    return fs.shouldRender;
}

static void check_capture(int frame)
{
    for (int e = 0; e < 2; e++) {
        char path[1024];
        snprintf(path, sizeof(path), "%s/loader/frame_%05d_%s.pfm", XRSC_TEST_OUT, frame,
                 e ? "right" : "left");
        float *rgba = NULL;
        uint32_t w = 0, h = 0;
        xrsc_diag diag = {0};
        if (hs_read_pfm(path, &rgba, &w, &h, &diag) != XRSC_OK) {
            CHECK_MSG(0, "%s cannot be read", path);
            continue;
        }
        CHECK_EQ_INT(w, T_W);
        CHECK_EQ_INT(h, T_H);
        float want[4];
        frame_color(frame, e, want);
        int bad = 0;
        for (size_t i = 0; i < (size_t)w * h; i++)
            for (int c = 0; c < 3; c++)
                bad += rgba[i * 4 + c] != want[c];
        CHECK_MSG(bad == 0, "%s: %d values differ from (%g, %g, %g), first (%g, %g, %g)", path,
                  bad, (double)want[0], (double)want[1], (double)want[2], (double)rgba[0],
                  (double)rgba[1], (double)rgba[2]);
        free(rgba);
    }
}

static const XrSessionState k_expected_run[] = {
    XR_SESSION_STATE_IDLE,    XR_SESSION_STATE_READY,        XR_SESSION_STATE_SYNCHRONIZED,
    XR_SESSION_STATE_VISIBLE, XR_SESSION_STATE_FOCUSED,      XR_SESSION_STATE_VISIBLE,
    XR_SESSION_STATE_SYNCHRONIZED, XR_SESSION_STATE_STOPPING, XR_SESSION_STATE_IDLE,
    XR_SESSION_STATE_EXITING};

/**
 * Runs one session to EXITING. request_exit_after > 0 calls xrRequestExitSession after that
 * many shown frames; otherwise XRSC_RT_FRAMES ends it.
 */
static void run_session(t_app *app, int request_exit_after, int *out_frames)
{
    t_session ts;
    session_open(app, &ts);
    CHECK_EQ_INT(ts.state, XR_SESSION_STATE_READY);
    XR_EXPECT(xrEndSession(ts.session), XR_ERROR_SESSION_NOT_RUNNING);
    XR_EXPECT(xrBeginFrame(ts.session, NULL), XR_ERROR_SESSION_NOT_RUNNING);
    XrSessionBeginInfo sbi = {.type = XR_TYPE_SESSION_BEGIN_INFO,
                              .primaryViewConfigurationType =
                                  XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO};
    XR_CHECK(xrBeginSession(ts.session, &sbi));
    XR_EXPECT(xrBeginSession(ts.session, &sbi), XR_ERROR_SESSION_RUNNING);
    XR_EXPECT(xrBeginFrame(ts.session, NULL), XR_ERROR_CALL_ORDER_INVALID);
    XR_EXPECT(xrEndSession(ts.session), XR_ERROR_SESSION_NOT_STOPPING);
    XrTime last = 0;
    int frames = 0, shown = 0;
    bool running = true, exit_requested = false, located = false;
    for (int guard = 0; guard < 100; guard++) {
        poll(app, &ts);
        if (ts.state == XR_SESSION_STATE_STOPPING && running) {
            XR_CHECK(xrEndSession(ts.session));
            running = false;
            continue;
        }
        if (ts.state == XR_SESSION_STATE_EXITING)
            break;
        if (!running)
            continue;
        XrActionsSyncInfo sync = {.type = XR_TYPE_ACTIONS_SYNC_INFO,
                                  .countActiveActionSets = 1,
                                  .activeActionSets = &(XrActiveActionSet){ts.set, XR_NULL_PATH}};
        XR_EXPECT(xrSyncActions(ts.session, &sync),
                  ts.state == XR_SESSION_STATE_FOCUSED ? XR_SUCCESS : XR_SESSION_NOT_FOCUSED);
        XrActionStateGetInfo gi = {.type = XR_TYPE_ACTION_STATE_GET_INFO, .action = ts.select};
        XrActionStateBoolean st = {.type = XR_TYPE_ACTION_STATE_BOOLEAN};
        XR_CHECK(xrGetActionStateBoolean(ts.session, &gi, &st));
        CHECK(!st.isActive);
        XrActionStateFloat stf = {.type = XR_TYPE_ACTION_STATE_FLOAT};
        XR_EXPECT(xrGetActionStateFloat(ts.session, &gi, &stf), XR_ERROR_ACTION_TYPE_MISMATCH);
        bool shown_now = render_frame(app, &ts, frames, &last);
        if (shown_now)
            check_capture(frames);
        if (!located) {
            /* LOCAL's origin is the stream's first pose; STAGE lies 1.6 m below it */
            XrSpaceLocation loc = {.type = XR_TYPE_SPACE_LOCATION};
            XR_CHECK(xrLocateSpace(ts.local, ts.stage, last, &loc));
            CHECK_NEAR(loc.pose.position.y, 1.6, 1e-5);
            CHECK_NEAR(loc.pose.orientation.w, 1.0, 1e-6);
            located = true;
        }
        frames++;
        shown += shown_now;
        if (request_exit_after > 0 && shown == request_exit_after && !exit_requested) {
            XR_CHECK(xrRequestExitSession(ts.session));
            exit_requested = true;
        }
    }
    CHECK_EQ_INT(ts.state, XR_SESSION_STATE_EXITING);
    int n = (int)(sizeof(k_expected_run) / sizeof(k_expected_run[0]));
    CHECK_EQ_INT(ts.event_count, n);
    for (int i = 0; i < n && i < ts.event_count; i++)
        CHECK_MSG(ts.events[i] == k_expected_run[i], "event %d: state %d, expected %d", i,
                  (int)ts.events[i], (int)k_expected_run[i]);
    session_close(&ts);
    *out_frames = frames;
}

static void sessions_end_and_start_again(void)
{
    char out[600];
    snprintf(out, sizeof(out), "%s/loader", XRSC_TEST_OUT);
    mkdir(XRSC_TEST_OUT, 0777);
    setenv("XRSC_RT_OUT", out, 1);
    setenv("XRSC_RT_FRAMES", "6", 1);
    setenv("XRSC_RT_PACE", "fast", 1);
    setenv("XRSC_RT_WRITE", "eyes,linear", 1);
    setenv("XRSC_RT_EYE_SIZE", "64x48", 1);
    unsetenv("XRSC_RT_LOSE_AFTER");
    unsetenv("XRSC_RT_POSES");
    t_app app;
    if (app_open(&app)) {
        int frames = 0;
        run_session(&app, 0, &frames); /* XRSC_RT_FRAMES ends it */
        CHECK_EQ_INT(frames, 6);
        run_session(&app, 2, &frames); /* the application ends it */
        CHECK_EQ_INT(frames, 3);       /* frame 0 is not shown; frames 1, 2 are */
    }
    app_close(&app);
}

static void lost_session_is_reported_and_a_new_one_works(void)
{
    setenv("XRSC_RT_LOSE_AFTER", "3", 1);
    unsetenv("XRSC_RT_OUT");
    unsetenv("XRSC_RT_FRAMES");
    t_app app;
    if (app_open(&app)) {
        for (int round = 0; round < 2; round++) {
            t_session ts;
            session_open(&app, &ts);
            XrSessionBeginInfo sbi = {.type = XR_TYPE_SESSION_BEGIN_INFO,
                                      .primaryViewConfigurationType =
                                          XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO};
            XR_CHECK(xrBeginSession(ts.session, &sbi));
            XrTime last = 0;
            bool focused = false;
            for (int f = 0; f < 10 && !ts.lost; f++) {
                render_frame(&app, &ts, f, &last);
                poll(&app, &ts);
                focused |= ts.state == XR_SESSION_STATE_FOCUSED;
            }
            CHECK(focused);
            CHECK(ts.lost);
            XrFrameState fs = {.type = XR_TYPE_FRAME_STATE};
            XR_EXPECT(xrWaitFrame(ts.session, NULL, &fs), XR_ERROR_SESSION_LOST);
            XR_EXPECT(xrEndSession(ts.session), XR_ERROR_SESSION_LOST);
            session_close(&ts);
        }
    }
    app_close(&app);
    unsetenv("XRSC_RT_LOSE_AFTER");
}

static void missing_manifest_is_an_error(void)
{
    setenv("XR_RUNTIME_JSON", XRSC_TEST_OUT "/no/such/runtime.json", 1);
    XrInstanceCreateInfo ci = {.type = XR_TYPE_INSTANCE_CREATE_INFO};
    snprintf(ci.applicationInfo.applicationName, sizeof(ci.applicationInfo.applicationName), "t");
    ci.applicationInfo.apiVersion = XR_MAKE_VERSION(1, 0, 0);
    XrInstance inst = XR_NULL_HANDLE;
    XrResult r = xrCreateInstance(&ci, &inst);
    CHECK_MSG(XR_FAILED(r), "xrCreateInstance -> %s", result_name(r));
    if (XR_SUCCEEDED(r))
        xrDestroyInstance(inst);
    setenv("XR_RUNTIME_JSON", XRSC_RUNTIME_JSON, 1);
}

int main(void)
{
    RUN(library_serves_every_core_function);
    RUN(runtime_applies_the_conformance_rules);
    RUN(sessions_end_and_start_again);
    RUN(lost_session_is_reported_and_a_new_one_works);
    RUN(missing_manifest_is_an_error);
    return t_finish();
}
