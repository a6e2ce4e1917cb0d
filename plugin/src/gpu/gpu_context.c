// SPDX-License-Identifier: MIT
/**
 * @file gpu_context.c
 * @brief Instance, validation messenger, device selection and feature enabling.
 */
#include "gpu_context.h"

#include "gpu_pipeline.h"
#include "u_device.h"
#include "u_diag.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char *gpu_vk_result_name(VkResult r)
{
    switch (r) {
#define GPU_R(x)                                                                                   \
    case x:                                                                                        \
        return #x;
        GPU_R(VK_SUCCESS)
        GPU_R(VK_NOT_READY)
        GPU_R(VK_TIMEOUT)
        GPU_R(VK_EVENT_SET)
        GPU_R(VK_EVENT_RESET)
        GPU_R(VK_INCOMPLETE)
        GPU_R(VK_ERROR_OUT_OF_HOST_MEMORY)
        GPU_R(VK_ERROR_OUT_OF_DEVICE_MEMORY)
        GPU_R(VK_ERROR_INITIALIZATION_FAILED)
        GPU_R(VK_ERROR_DEVICE_LOST)
        GPU_R(VK_ERROR_MEMORY_MAP_FAILED)
        GPU_R(VK_ERROR_LAYER_NOT_PRESENT)
        GPU_R(VK_ERROR_EXTENSION_NOT_PRESENT)
        GPU_R(VK_ERROR_FEATURE_NOT_PRESENT)
        GPU_R(VK_ERROR_INCOMPATIBLE_DRIVER)
        GPU_R(VK_ERROR_TOO_MANY_OBJECTS)
        GPU_R(VK_ERROR_FORMAT_NOT_SUPPORTED)
        GPU_R(VK_ERROR_FRAGMENTED_POOL)
        GPU_R(VK_ERROR_UNKNOWN)
        GPU_R(VK_ERROR_OUT_OF_POOL_MEMORY)
        GPU_R(VK_ERROR_INVALID_EXTERNAL_HANDLE)
        GPU_R(VK_ERROR_FRAGMENTATION)
        GPU_R(VK_ERROR_INVALID_OPAQUE_CAPTURE_ADDRESS)
        GPU_R(VK_PIPELINE_COMPILE_REQUIRED)
        GPU_R(VK_THREAD_IDLE_KHR)
        GPU_R(VK_THREAD_DONE_KHR)
        GPU_R(VK_OPERATION_DEFERRED_KHR)
        GPU_R(VK_OPERATION_NOT_DEFERRED_KHR)
#undef GPU_R
    default:
        return "VK_RESULT_UNKNOWN";
    }
}

xrsc_result gpu_vk_error(xrsc_diag *diag, VkResult r, const char *call, const char *file,
                         int line)
{
    U_LOG_E("%s:%d: %s failed: %s", file, line, call, gpu_vk_result_name(r));
    return u_diag_set(diag, XRSC_ERROR_VULKAN, file, line, call, "%s failed: %s", call,
                      gpu_vk_result_name(r));
}

uint32_t gpu_find_memory_type(const gpu_context *ctx, uint32_t type_bits,
                              VkMemoryPropertyFlags flags)
{
    for (uint32_t i = 0; i < ctx->memory_properties.memoryTypeCount; i++) {
        if ((type_bits & (1u << i)) &&
            (ctx->memory_properties.memoryTypes[i].propertyFlags & flags) == flags)
            return i;
    }
    return UINT32_MAX;
}

/* ---- validation messenger: counts ERROR-severity messages ---- */

static VKAPI_ATTR VkBool32 VKAPI_CALL debug_callback(
    VkDebugUtilsMessageSeverityFlagBitsEXT severity, VkDebugUtilsMessageTypeFlagsEXT types,
    const VkDebugUtilsMessengerCallbackDataEXT *data, void *user)
{
    gpu_context *ctx = user;
    const char *msg = data && data->pMessage ? data->pMessage : "";
    if (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) {
        ctx->validation_errors++;
        U_LOG_E("validation: %s", msg);
    } else if ((severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) &&
               !(types & VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT)) {
        /* Performance hints (e.g. GENERAL layout for copies, used on purpose for the storage
         * images) go to the debug log. */
        U_LOG_W("validation: %s", msg);
    } else {
        U_LOG_D("validation: %s", msg);
    }
    return VK_FALSE;
}

static bool has_layer(const char *name)
{
    uint32_t n = 0;
    vkEnumerateInstanceLayerProperties(&n, NULL);
    VkLayerProperties *props = calloc(n ? n : 1, sizeof(*props));
    if (!props)
        return false;
    vkEnumerateInstanceLayerProperties(&n, props);
    bool found = false;
    for (uint32_t i = 0; i < n && !found; i++)
        found = strcmp(props[i].layerName, name) == 0;
    free(props);
    return found;
}

/** Whether the loader (layer NULL) or the named layer offers the instance extension. */
static bool has_instance_extension_of(const char *layer, const char *name)
{
    uint32_t n = 0;
    vkEnumerateInstanceExtensionProperties(layer, &n, NULL);
    VkExtensionProperties *props = calloc(n ? n : 1, sizeof(*props));
    if (!props)
        return false;
    vkEnumerateInstanceExtensionProperties(layer, &n, props);
    bool found = false;
    for (uint32_t i = 0; i < n && !found; i++)
        found = strcmp(props[i].extensionName, name) == 0;
    free(props);
    return found;
}

static bool has_instance_extension(const char *name)
{
    return has_instance_extension_of(NULL, name);
}

/* ---- device capabilities ---- */

/** Device extensions xrsc needs (VK_KHR_acceleration_structure requires the deferred ops). */
static const char *const required_extensions[] = {
    VK_KHR_ACCELERATION_STRUCTURE_EXTENSION_NAME,
    VK_KHR_RAY_TRACING_PIPELINE_EXTENSION_NAME,
    VK_KHR_DEFERRED_HOST_OPERATIONS_EXTENSION_NAME,
};
#define GPU_REQUIRED_EXTENSION_COUNT (sizeof(required_extensions) / sizeof(required_extensions[0]))

typedef struct gpu_feature_chain {
    VkPhysicalDeviceFeatures2 f2;
    VkPhysicalDeviceVulkan11Features f11;
    VkPhysicalDeviceVulkan12Features f12;
    VkPhysicalDeviceVulkan13Features f13;
    VkPhysicalDeviceAccelerationStructureFeaturesKHR as;
    VkPhysicalDeviceRayTracingPipelineFeaturesKHR rt;
    VkPhysicalDeviceShaderAtomicFloatFeaturesEXT af;
} gpu_feature_chain;

static void feature_chain_init(gpu_feature_chain *c, bool with_atomic_float)
{
    memset(c, 0, sizeof(*c));
    c->f2.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2;
    c->f11.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_1_FEATURES;
    c->f12.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES;
    c->f13.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES;
    c->as.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_FEATURES_KHR;
    c->rt.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_TRACING_PIPELINE_FEATURES_KHR;
    c->af.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_ATOMIC_FLOAT_FEATURES_EXT;
    c->f2.pNext = &c->f11;
    c->f11.pNext = &c->f12;
    c->f12.pNext = &c->f13;
    c->f13.pNext = &c->as;
    c->as.pNext = &c->rt;
    c->rt.pNext = with_atomic_float ? &c->af : NULL;
}

typedef struct gpu_device_caps {
    char name[VK_MAX_PHYSICAL_DEVICE_NAME_SIZE];
    bool is_cpu;
    bool has_ext[GPU_REQUIRED_EXTENSION_COUNT];
    bool has_atomic_float_ext;
    gpu_feature_chain sup; /**< supported features */
    char lacks[256];       /**< what is missing for xrsc, "" when usable */
} gpu_device_caps;

static bool device_has_extension(VkPhysicalDevice pd, const char *name)
{
    uint32_t n = 0;
    vkEnumerateDeviceExtensionProperties(pd, NULL, &n, NULL);
    VkExtensionProperties *props = calloc(n ? n : 1, sizeof(*props));
    if (!props)
        return false;
    vkEnumerateDeviceExtensionProperties(pd, NULL, &n, props);
    bool found = false;
    for (uint32_t i = 0; i < n && !found; i++)
        found = strcmp(props[i].extensionName, name) == 0;
    free(props);
    return found;
}

static void append_lack(char *buf, size_t size, const char *what)
{
    size_t len = strlen(buf);
    snprintf(buf + len, size - len, "%s%s", len ? ", " : "", what);
}

static void query_caps(VkPhysicalDevice pd, gpu_device_caps *caps)
{
    memset(caps, 0, sizeof(*caps));
    VkPhysicalDeviceProperties props;
    vkGetPhysicalDeviceProperties(pd, &props);
    snprintf(caps->name, sizeof(caps->name), "%s", props.deviceName);
    caps->is_cpu = props.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
    for (size_t i = 0; i < GPU_REQUIRED_EXTENSION_COUNT; i++) {
        caps->has_ext[i] = device_has_extension(pd, required_extensions[i]);
        if (!caps->has_ext[i])
            append_lack(caps->lacks, sizeof(caps->lacks), required_extensions[i]);
    }
    caps->has_atomic_float_ext =
        device_has_extension(pd, VK_EXT_SHADER_ATOMIC_FLOAT_EXTENSION_NAME);
    if (props.apiVersion < VK_API_VERSION_1_3) {
        append_lack(caps->lacks, sizeof(caps->lacks), "Vulkan 1.3");
        return;
    }
    feature_chain_init(&caps->sup, caps->has_atomic_float_ext);
    if (!caps->has_ext[0] || !caps->has_ext[1])
        caps->sup.f13.pNext = NULL; /* do not chain structs of absent extensions */
    vkGetPhysicalDeviceFeatures2(pd, &caps->sup.f2);
    const gpu_feature_chain *s = &caps->sup;
    if (caps->has_ext[0] && !s->as.accelerationStructure)
        append_lack(caps->lacks, sizeof(caps->lacks), "accelerationStructure");
    if (caps->has_ext[1] && !s->rt.rayTracingPipeline)
        append_lack(caps->lacks, sizeof(caps->lacks), "rayTracingPipeline");
    if (!s->f12.bufferDeviceAddress)
        append_lack(caps->lacks, sizeof(caps->lacks), "bufferDeviceAddress");
    if (!s->f12.shaderBufferInt64Atomics || !s->f2.features.shaderInt64)
        append_lack(caps->lacks, sizeof(caps->lacks), "shaderBufferInt64Atomics");
    if (!s->f12.vulkanMemoryModel || !s->f12.vulkanMemoryModelDeviceScope)
        append_lack(caps->lacks, sizeof(caps->lacks), "vulkanMemoryModelDeviceScope");
    if (!s->f12.runtimeDescriptorArray || !s->f12.descriptorBindingPartiallyBound ||
        !s->f12.shaderSampledImageArrayNonUniformIndexing)
        append_lack(caps->lacks, sizeof(caps->lacks), "descriptorIndexing");
}

/** Picks a physical device per the selector (u_device.h, the rule XRSC_RT_DEVICE shares);
 *  fills *out_index. */
static xrsc_result select_device(const char *selector, const gpu_device_caps *caps, uint32_t n,
                                 uint32_t *out_index, xrsc_diag *diag)
{
    char summary[1024] = "";
    for (uint32_t i = 0; i < n; i++) {
        size_t len = strlen(summary);
        snprintf(summary + len, sizeof(summary) - len, "%s[%u] %s: %s", i ? "; " : "", i,
                 caps[i].name, caps[i].lacks[0] ? caps[i].lacks : "ok");
    }
    const char **names = calloc(n ? n : 1, sizeof(*names));
    bool *is_cpu = calloc(n ? n : 1, sizeof(*is_cpu));
    bool *usable = calloc(n ? n : 1, sizeof(*usable));
    if (!names || !is_cpu || !usable) {
        free(names);
        free(is_cpu);
        free(usable);
        return u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, "", 0, "device", "out of memory");
    }
    for (uint32_t i = 0; i < n; i++) {
        names[i] = caps[i].name;
        is_cpu[i] = caps[i].is_cpu;
        usable[i] = !caps[i].lacks[0];
    }
    bool any_match = false;
    int32_t match = u_device_select(selector, n, names, is_cpu, usable, &any_match);
    free(names);
    free(is_cpu);
    free(usable);
    if (match >= 0) {
        *out_index = (uint32_t)match;
        return XRSC_OK;
    }
    if (!selector || !*selector)
        return u_diag_set(diag, XRSC_ERROR_NO_RAY_TRACING_DEVICE, "", 0, "device",
                          "no Vulkan device has what xrsc needs (%s)",
                          n ? summary : "no devices");
    if (any_match)
        return u_diag_set(diag, XRSC_ERROR_NO_RAY_TRACING_DEVICE, "", 0, "device",
                          "device \"%s\" lacks what xrsc needs (%s)", selector, summary);
    return u_diag_set(diag, XRSC_ERROR_DEVICE_NOT_FOUND, "", 0, "device",
                      "no Vulkan device matches \"%s\" (devices: %s)", selector,
                      n ? summary : "none");
}

static void load_device_functions(gpu_context *ctx)
{
#define GPU_LOAD(name) ctx->vk.name = (PFN_vk##name)vkGetDeviceProcAddr(ctx->device, "vk" #name)
    GPU_LOAD(CreateAccelerationStructureKHR);
    GPU_LOAD(DestroyAccelerationStructureKHR);
    GPU_LOAD(GetAccelerationStructureBuildSizesKHR);
    GPU_LOAD(GetAccelerationStructureDeviceAddressKHR);
    GPU_LOAD(CmdBuildAccelerationStructuresKHR);
    GPU_LOAD(CreateRayTracingPipelinesKHR);
    GPU_LOAD(GetRayTracingShaderGroupHandlesKHR);
    GPU_LOAD(CmdTraceRaysKHR);
#undef GPU_LOAD
}

static xrsc_result context_create(const gpu_context_options *options,
                                  const gpu_context_hooks *hooks, gpu_context **out,
                                  xrsc_diag *diag);

xrsc_result gpu_context_create(const gpu_context_options *options, gpu_context **out,
                               xrsc_diag *diag)
{
    return context_create(options, NULL, out, diag);
}

xrsc_result gpu_context_create_hooked(const gpu_context_options *options,
                                      const gpu_context_hooks *hooks, gpu_context **out,
                                      xrsc_diag *diag)
{
    if (!hooks || !hooks->create_instance || !hooks->physical_device || !hooks->create_device)
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "hooks",
                          "a creation hook is NULL");
    return context_create(options, hooks, out, diag);
}

/** The caller's options with the environment applied (XRSC_VALIDATION=1, XRSC_DEVICE). */
static gpu_context_options resolve_options(const gpu_context_options *options)
{
    gpu_context_options opt = {0};
    if (options)
        opt = *options;
    const char *env_val = getenv("XRSC_VALIDATION");
    if (env_val && !strcmp(env_val, "1"))
        opt.validation = true;
    if (!opt.device || !*opt.device)
        opt.device = getenv("XRSC_DEVICE");
    return opt;
}

/** Instance layers and extensions to enable: the validation layer and debug utils, or none. */
typedef struct gpu_instance_layers {
    const char *layers[1];
    uint32_t layer_count;
    const char *ext[2];
    uint32_t ext_count;
    bool sync_validation; /**< VK_EXT_validation_features enabled: chain sync validation */
} gpu_instance_layers;

#define GPU_VALIDATION_LAYER "VK_LAYER_KHRONOS_validation"

/** Validation needs both the layer and VK_EXT_debug_utils (the messenger counts its errors);
 *  sets ctx->validation when both are installed. Synchronization validation comes with it
 *  when the layer offers VK_EXT_validation_features: lavapipe runs commands one after another
 *  and hides a missing barrier that a GPU running passes concurrently would not (issue 20). */
static void choose_instance_layers(gpu_context *ctx, bool validation, gpu_instance_layers *il)
{
    memset(il, 0, sizeof(*il));
    if (!validation)
        return;
    if (has_layer(GPU_VALIDATION_LAYER) &&
        has_instance_extension(VK_EXT_DEBUG_UTILS_EXTENSION_NAME)) {
        il->layers[il->layer_count++] = GPU_VALIDATION_LAYER;
        il->ext[il->ext_count++] = VK_EXT_DEBUG_UTILS_EXTENSION_NAME;
        ctx->validation = true;
        if (has_instance_extension_of(GPU_VALIDATION_LAYER,
                                      VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME)) {
            il->ext[il->ext_count++] = VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME;
            il->sync_validation = true;
        } else {
            U_LOG_W("validation: the layer offers no %s: synchronization validation off",
                    VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME);
        }
    } else {
        U_LOG_W("validation requested but VK_LAYER_KHRONOS_validation or "
                "VK_EXT_debug_utils is not installed");
    }
}

/** Errors and warnings go to debug_callback, which counts the errors in ctx. */
static VkDebugUtilsMessengerCreateInfoEXT messenger_info(gpu_context *ctx)
{
    return (VkDebugUtilsMessengerCreateInfoEXT){
        .sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT,
        .messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT |
                           VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT,
        .messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                       VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                       VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT,
        .pfnUserCallback = debug_callback,
        .pUserData = ctx,
    };
}

/** Creates ctx->instance (directly or through hooks) and, with validation, the messenger. */
static xrsc_result instance_create(gpu_context *ctx, bool validation,
                                   const gpu_context_hooks *hooks, xrsc_diag *diag)
{
    xrsc_result res = XRSC_OK;
    gpu_instance_layers il;
    choose_instance_layers(ctx, validation, &il);
    /* Request 1.3 (lavapipe reports 1.4 against Debian's 1.3.239 loader). */
    VkApplicationInfo app = {
        .sType = VK_STRUCTURE_TYPE_APPLICATION_INFO,
        .pApplicationName = "xrsc",
        .applicationVersion = 1,
        .pEngineName = "xrsc",
        .engineVersion = 1,
        .apiVersion = VK_API_VERSION_1_3,
    };
    VkDebugUtilsMessengerCreateInfoEXT msg_info = messenger_info(ctx);
    static const VkValidationFeatureEnableEXT sync_enable =
        VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT;
    VkValidationFeaturesEXT features = {
        .sType = VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT,
        .pNext = &msg_info,
        .enabledValidationFeatureCount = 1,
        .pEnabledValidationFeatures = &sync_enable,
    };
    const void *chain = NULL; /* msg_info (pNext NULL) also creates the messenger below */
    if (ctx->validation)
        chain = il.sync_validation ? (const void *)&features : (const void *)&msg_info;
    VkInstanceCreateInfo ici = {
        .sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO,
        /* also catches messages from vkCreateInstance / vkDestroyInstance */
        .pNext = chain,
        .pApplicationInfo = &app,
        .enabledLayerCount = il.layer_count,
        .ppEnabledLayerNames = il.layers,
        .enabledExtensionCount = il.ext_count,
        .ppEnabledExtensionNames = il.ext,
    };
    if (hooks)
        GPU_CHECK(res, diag, done, hooks->create_instance(hooks->user, &ici, &ctx->instance));
    else
        GPU_CHECK(res, diag, done, vkCreateInstance(&ici, NULL, &ctx->instance));
    if (ctx->validation) {
        ctx->vk.CreateDebugUtilsMessengerEXT = (PFN_vkCreateDebugUtilsMessengerEXT)
            vkGetInstanceProcAddr(ctx->instance, "vkCreateDebugUtilsMessengerEXT");
        ctx->vk.DestroyDebugUtilsMessengerEXT = (PFN_vkDestroyDebugUtilsMessengerEXT)
            vkGetInstanceProcAddr(ctx->instance, "vkDestroyDebugUtilsMessengerEXT");
        if (ctx->vk.CreateDebugUtilsMessengerEXT)
            GPU_CHECK(res, diag, done,
                      ctx->vk.CreateDebugUtilsMessengerEXT(ctx->instance, &msg_info, NULL,
                                                           &ctx->messenger));
    }
done:
    return res;
}

/** The instance's physical devices and what each has. */
typedef struct gpu_device_list {
    VkPhysicalDevice *pds;
    gpu_device_caps *caps;
    uint32_t n;
} gpu_device_list;

/** Fills list; device_list_free frees it, also after a failure. */
static xrsc_result device_list_query(const gpu_context *ctx, gpu_device_list *list, xrsc_diag *diag)
{
    xrsc_result res = XRSC_OK;
    uint32_t n = 0;
    VkPhysicalDevice *pds = NULL;
    GPU_CHECK(res, diag, done, vkEnumeratePhysicalDevices(ctx->instance, &n, NULL));
    pds = calloc(n ? n : 1, sizeof(*pds));
    list->pds = pds;
    list->caps = calloc(n ? n : 1, sizeof(*list->caps));
    if (!pds || !list->caps) {
        res = u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, "", 0, "", "out of memory");
        goto done;
    }
    GPU_CHECK(res, diag, done, vkEnumeratePhysicalDevices(ctx->instance, &n, pds));
    list->n = n;
    for (uint32_t i = 0; i < n; i++)
        query_caps(pds[i], &list->caps[i]);
done:
    return res;
}

static void device_list_free(gpu_device_list *list)
{
    free(list->pds);
    free(list->caps);
    memset(list, 0, sizeof(*list));
}

/** Through hooks the XR runtime names the device: checks it against the selector and against
 *  what xrsc needs; fills *out_index. */
static xrsc_result select_hooked_device(const gpu_context *ctx, const gpu_context_hooks *hooks,
                                        const char *selector, const gpu_device_list *list,
                                        uint32_t *out_index, xrsc_diag *diag)
{
    xrsc_result res = XRSC_OK;
    const gpu_device_caps *caps = list->caps;
    uint32_t n = list->n;
    /* A selector is checked against the wrapper's instance before the wrapper is asked:
     * one that matches nothing is the direct path's XRSC_ERROR_DEVICE_NOT_FOUND naming
     * it, not the failure of a runtime given the same selector (XRSC_RT_DEVICE). */
    bool selected = selector && *selector;
    uint32_t pick = 0;
    if (selected && (res = select_device(selector, caps, n, &pick, diag)) != XRSC_OK)
        return res;
    VkPhysicalDevice want = VK_NULL_HANDLE;
    GPU_CHECK(res, diag, done, hooks->physical_device(hooks->user, ctx->instance, &want));
    uint32_t index = UINT32_MAX;
    for (uint32_t i = 0; i < n && index == UINT32_MAX; i++)
        if (list->pds[i] == want)
            index = i;
    if (index == UINT32_MAX)
        return u_diag_set(diag, XRSC_ERROR_DEVICE_NOT_FOUND, "", 0, "device",
                          "the required physical device is not one of the instance's %u", n);
    if (selected && !u_device_matches(selector, index, caps[index].name, caps[index].is_cpu))
        return u_diag_set(diag, XRSC_ERROR_DEVICE_NOT_FOUND, "", 0, "device",
                          "the XR runtime requires device [%u] %s, which \"%s\" does not "
                          "select (the runtime chooses the device: set its selector too)",
                          index, caps[index].name, selector);
    if (caps[index].lacks[0])
        return u_diag_set(diag, XRSC_ERROR_NO_RAY_TRACING_DEVICE, "", 0, "device",
                          "the device the XR runtime requires, %s, lacks what xrsc needs (%s)",
                          caps[index].name, caps[index].lacks);
    *out_index = index;
done:
    return res;
}

/** Fills ctx's properties, ray tracing / AS properties and memory properties. */
static void read_properties(gpu_context *ctx)
{
    ctx->rt_properties.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_TRACING_PIPELINE_PROPERTIES_KHR;
    ctx->as_properties.sType =
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_PROPERTIES_KHR;
    ctx->rt_properties.pNext = &ctx->as_properties;
    VkPhysicalDeviceProperties2 p2 = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2,
                                      .pNext = &ctx->rt_properties};
    vkGetPhysicalDeviceProperties2(ctx->physical_device, &p2);
    ctx->rt_properties.pNext = NULL;
    ctx->as_properties.pNext = NULL;
    ctx->properties = p2.properties;
    vkGetPhysicalDeviceMemoryProperties(ctx->physical_device, &ctx->memory_properties);
}

/** One queue family with compute (ray tracing runs on compute-capable queues). */
static xrsc_result pick_queue_family(gpu_context *ctx, bool hooked, const char *device_name,
                                     xrsc_diag *diag)
{
    uint32_t qn = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(ctx->physical_device, &qn, NULL);
    VkQueueFamilyProperties qf[16];
    if (qn > 16)
        qn = 16;
    vkGetPhysicalDeviceQueueFamilyProperties(ctx->physical_device, &qn, qf);
    ctx->queue_family = UINT32_MAX;
    /* Through XR the queue is also the runtime's (XrGraphicsBindingVulkan2KHR): prefer one
     * that has graphics too. */
    const VkQueueFlags gc = VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT;
    for (uint32_t i = 0; hooked && i < qn && ctx->queue_family == UINT32_MAX; i++)
        if ((qf[i].queueFlags & gc) == gc)
            ctx->queue_family = i;
    for (uint32_t i = 0; i < qn && ctx->queue_family == UINT32_MAX; i++)
        if (qf[i].queueFlags & VK_QUEUE_COMPUTE_BIT)
            ctx->queue_family = i;
    if (ctx->queue_family == UINT32_MAX)
        return u_diag_set(diag, XRSC_ERROR_NO_RAY_TRACING_DEVICE, "", 0, "device",
                          "%s has no compute queue", device_name);
    ctx->timestamp_valid_bits = qf[ctx->queue_family].timestampValidBits;
    return XRSC_OK;
}

/** Fills en with the required features plus the optional ones the device has; returns
 *  whether VK_EXT_shader_atomic_float is enabled. */
static bool enable_features(const gpu_device_caps *cap, gpu_feature_chain *en)
{
    const gpu_feature_chain *s = &cap->sup;
    bool af = cap->has_atomic_float_ext &&
              (s->af.shaderBufferFloat32AtomicAdd || s->af.shaderImageFloat32AtomicAdd);
    feature_chain_init(en, af);
    en->f2.features.shaderInt64 = VK_TRUE;
    en->f2.features.shaderStorageImageWriteWithoutFormat =
        s->f2.features.shaderStorageImageWriteWithoutFormat;
    en->f2.features.shaderStorageImageReadWithoutFormat =
        s->f2.features.shaderStorageImageReadWithoutFormat;
    en->f2.features.shaderFloat64 = s->f2.features.shaderFloat64;
    en->f2.features.samplerAnisotropy = s->f2.features.samplerAnisotropy;
    en->f12.bufferDeviceAddress = VK_TRUE;
    en->f12.shaderBufferInt64Atomics = VK_TRUE;
    en->f12.shaderSharedInt64Atomics = s->f12.shaderSharedInt64Atomics;
    en->f12.vulkanMemoryModel = VK_TRUE;
    en->f12.vulkanMemoryModelDeviceScope = VK_TRUE;
    en->f12.descriptorIndexing = s->f12.descriptorIndexing;
    en->f12.runtimeDescriptorArray = VK_TRUE;
    en->f12.descriptorBindingPartiallyBound = VK_TRUE;
    en->f12.descriptorBindingVariableDescriptorCount =
        s->f12.descriptorBindingVariableDescriptorCount;
    en->f12.shaderSampledImageArrayNonUniformIndexing = VK_TRUE;
    en->f12.scalarBlockLayout = s->f12.scalarBlockLayout;
    en->f12.hostQueryReset = s->f12.hostQueryReset;
    en->f12.shaderFloat16 = s->f12.shaderFloat16;
    en->f12.shaderInt8 = s->f12.shaderInt8;
    en->f12.uniformAndStorageBuffer8BitAccess = s->f12.uniformAndStorageBuffer8BitAccess;
    en->f12.storageBuffer8BitAccess = s->f12.storageBuffer8BitAccess;
    en->f11.storageBuffer16BitAccess = s->f11.storageBuffer16BitAccess;
    en->f13.synchronization2 = s->f13.synchronization2;
    en->f13.maintenance4 = s->f13.maintenance4;
    en->as.accelerationStructure = VK_TRUE;
    en->rt.rayTracingPipeline = VK_TRUE;
    if (af) {
        en->af.shaderBufferFloat32AtomicAdd = s->af.shaderBufferFloat32AtomicAdd;
        en->af.shaderBufferFloat32Atomics = s->af.shaderBufferFloat32Atomics;
        en->af.shaderImageFloat32AtomicAdd = s->af.shaderImageFloat32AtomicAdd;
        en->af.shaderImageFloat32Atomics = s->af.shaderImageFloat32Atomics;
        en->af.shaderSharedFloat32AtomicAdd = s->af.shaderSharedFloat32AtomicAdd;
        en->af.shaderSharedFloat32Atomics = s->af.shaderSharedFloat32Atomics;
    }
    return af;
}

/** Creates ctx->device (directly or through hooks) with the features en and one queue of
 *  ctx->queue_family, then gets the queue and loads the device functions. */
static xrsc_result device_create(gpu_context *ctx, const gpu_context_hooks *hooks,
                                 const gpu_feature_chain *en, xrsc_diag *diag)
{
    xrsc_result res = XRSC_OK;
    const char *dev_ext[GPU_REQUIRED_EXTENSION_COUNT + 1];
    uint32_t dev_ext_count = 0;
    for (size_t i = 0; i < GPU_REQUIRED_EXTENSION_COUNT; i++)
        dev_ext[dev_ext_count++] = required_extensions[i];
    if (ctx->atomic_float)
        dev_ext[dev_ext_count++] = VK_EXT_SHADER_ATOMIC_FLOAT_EXTENSION_NAME;

    float prio = 1.0f;
    VkDeviceQueueCreateInfo qci = {
        .sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO,
        .queueFamilyIndex = ctx->queue_family,
        .queueCount = 1,
        .pQueuePriorities = &prio,
    };
    VkDeviceCreateInfo dci = {
        .sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO,
        .pNext = &en->f2,
        .queueCreateInfoCount = 1,
        .pQueueCreateInfos = &qci,
        .enabledExtensionCount = dev_ext_count,
        .ppEnabledExtensionNames = dev_ext,
    };
    if (hooks)
        GPU_CHECK(res, diag, done,
                  hooks->create_device(hooks->user, ctx->physical_device, &dci, &ctx->device));
    else
        GPU_CHECK(res, diag, done, vkCreateDevice(ctx->physical_device, &dci, NULL, &ctx->device));
    vkGetDeviceQueue(ctx->device, ctx->queue_family, 0, &ctx->queue);
    load_device_functions(ctx);
done:
    return res;
}

/** The command pool and fence of gpu_cmd_begin / gpu_cmd_submit_wait. */
static xrsc_result command_objects_create(gpu_context *ctx, xrsc_diag *diag)
{
    xrsc_result res = XRSC_OK;
    VkCommandPoolCreateInfo cpci = {
        .sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO,
        .flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT |
                 VK_COMMAND_POOL_CREATE_TRANSIENT_BIT,
        .queueFamilyIndex = ctx->queue_family,
    };
    GPU_CHECK(res, diag, done, vkCreateCommandPool(ctx->device, &cpci, NULL, &ctx->command_pool));
    VkFenceCreateInfo fci = {.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    GPU_CHECK(res, diag, done, vkCreateFence(ctx->device, &fci, NULL, &ctx->fence));
done:
    return res;
}

static xrsc_result context_create(const gpu_context_options *options,
                                  const gpu_context_hooks *hooks, gpu_context **out,
                                  xrsc_diag *diag)
{
    if (!out)
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "out", "out is NULL");
    *out = NULL;
    gpu_context_options opt = resolve_options(options);

    xrsc_result res = XRSC_OK;
    gpu_device_list list = {0};
    gpu_context *ctx = calloc(1, sizeof(*ctx));
    if (!ctx)
        return u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, "", 0, "", "out of memory");
    if ((res = instance_create(ctx, opt.validation, hooks, diag)) != XRSC_OK ||
        (res = device_list_query(ctx, &list, diag)) != XRSC_OK)
        goto fail;
    uint32_t index = 0;
    if (hooks)
        res = select_hooked_device(ctx, hooks, opt.device, &list, &index, diag);
    else
        res = select_device(opt.device, list.caps, list.n, &index, diag);
    if (res != XRSC_OK)
        goto fail;
    const gpu_device_caps *cap = &list.caps[index];
    ctx->device_index = index;
    ctx->physical_device = list.pds[index];
    ctx->is_cpu = cap->is_cpu;
    read_properties(ctx);
    if ((res = pick_queue_family(ctx, hooks != NULL, cap->name, diag)) != XRSC_OK)
        goto fail;
    gpu_feature_chain en; /* holds pointers into itself: filled in place, never copied */
    ctx->atomic_float = enable_features(cap, &en);
    if ((res = device_create(ctx, hooks, &en, diag)) != XRSC_OK ||
        (res = command_objects_create(ctx, diag)) != XRSC_OK)
        goto fail;

    U_LOG_D("device [%u] %s (validation %s)", index, ctx->properties.deviceName,
            ctx->validation ? "on" : "off");
    device_list_free(&list);
    *out = ctx;
    return XRSC_OK;

fail:
    device_list_free(&list);
    gpu_context_destroy(&ctx);
    return res;
}

void gpu_context_destroy(gpu_context **pctx)
{
    if (!pctx || !*pctx)
        return;
    gpu_context *ctx = *pctx;
    if (ctx->device) {
        vkDeviceWaitIdle(ctx->device);
        gpu_rt_pipelines_destroy(ctx);
        if (ctx->fence)
            vkDestroyFence(ctx->device, ctx->fence, NULL);
        if (ctx->command_pool)
            vkDestroyCommandPool(ctx->device, ctx->command_pool, NULL);
        vkDestroyDevice(ctx->device, NULL);
    }
    if (ctx->messenger && ctx->vk.DestroyDebugUtilsMessengerEXT)
        ctx->vk.DestroyDebugUtilsMessengerEXT(ctx->instance, ctx->messenger, NULL);
    if (ctx->instance)
        vkDestroyInstance(ctx->instance, NULL);
    free(ctx);
    *pctx = NULL;
}

xrsc_result gpu_cmd_begin(gpu_context *ctx, VkCommandBuffer *out_cmd, xrsc_diag *diag)
{
    xrsc_result res = XRSC_OK;
    *out_cmd = VK_NULL_HANDLE;
    VkCommandBufferAllocateInfo ai = {
        .sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO,
        .commandPool = ctx->command_pool,
        .level = VK_COMMAND_BUFFER_LEVEL_PRIMARY,
        .commandBufferCount = 1,
    };
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    GPU_CHECK(res, diag, fail, vkAllocateCommandBuffers(ctx->device, &ai, &cmd));
    VkCommandBufferBeginInfo bi = {
        .sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO,
        .flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT,
    };
    GPU_CHECK(res, diag, fail, vkBeginCommandBuffer(cmd, &bi));
    *out_cmd = cmd;
    return XRSC_OK;
fail:
    if (cmd)
        vkFreeCommandBuffers(ctx->device, ctx->command_pool, 1, &cmd);
    return res;
}

xrsc_result gpu_cmd_submit_wait(gpu_context *ctx, VkCommandBuffer cmd, xrsc_diag *diag)
{
    xrsc_result res = XRSC_OK;
    GPU_CHECK(res, diag, done, vkEndCommandBuffer(cmd));
    VkSubmitInfo si = {
        .sType = VK_STRUCTURE_TYPE_SUBMIT_INFO,
        .commandBufferCount = 1,
        .pCommandBuffers = &cmd,
    };
    GPU_CHECK(res, diag, done, vkResetFences(ctx->device, 1, &ctx->fence));
    ctx->submit_count++;
    GPU_CHECK(res, diag, done, vkQueueSubmit(ctx->queue, 1, &si, ctx->fence));
    GPU_CHECK(res, diag, done, vkWaitForFences(ctx->device, 1, &ctx->fence, VK_TRUE, UINT64_MAX));
done:
    vkFreeCommandBuffers(ctx->device, ctx->command_pool, 1, &cmd);
    return res;
}

void gpu_cmd_barrier_all(VkCommandBuffer cmd)
{
    VkMemoryBarrier mb = {
        .sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
        .srcAccessMask = VK_ACCESS_MEMORY_WRITE_BIT,
        .dstAccessMask = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT,
    };
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
                         VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, 0, 1, &mb, 0, NULL, 0, NULL);
}
