// SPDX-License-Identifier: MIT
/**
 * @file hsrt_vulkan.c
 * @brief XR_KHR_vulkan_enable and XR_KHR_vulkan_enable2, swapchains created on the
 *        application's VkDevice, and the read-back of submitted frames at xrEndFrame.
 *
 * The runtime needs no Vulkan extensions of its own: it only creates images and memory,
 * records layout transitions and image-to-buffer copies, and submits them on the
 * application's queue (XrGraphicsBindingVulkanKHR), waiting on a fence of its own, so nothing
 * of the runtime's is pending on the queue when a call returns. Images are in the layout the
 * spec ties to their first usage flag (colour attachment, depth attachment, storage, ...)
 * whenever the application holds them.
 */
#include "hsrt_instance.h"

#include "u_device.h"
#include "u_diag.h"

#include <stdlib.h>
#include <string.h>

#define VK_FAIL(fn, call, vr)                                                                      \
    hsrt_fail(XR_ERROR_RUNTIME_FAILURE, fn, "%s failed with VkResult %d", call, (int)(vr))

static PFN_vkGetInstanceProcAddr instance_gipa(const hsrt_instance *inst)
{
    return inst->vk_gipa ? inst->vk_gipa : vkGetInstanceProcAddr;
}

static XrResult check_system(XrSystemId id, const char *fn)
{
    if (id != HSRT_SYSTEM_ID)
        return hsrt_fail(XR_ERROR_SYSTEM_INVALID, fn, "systemId %llu", (unsigned long long)id);
    return XR_SUCCESS;
}

#define GET_INSTANCE(var, handle, fn)                                                              \
    hsrt_instance *var = hsrt_instance_from(handle);                                               \
    if (!var)                                                                                      \
        return hsrt_fail(XR_ERROR_HANDLE_INVALID, fn, "not an XrInstance of this runtime");

/* ---- graphics requirements, extensions, devices ---- */

static XrResult XRAPI_CALL hsrt_xrGetVulkanGraphicsRequirementsKHR(
    XrInstance instance, XrSystemId systemId, XrGraphicsRequirementsVulkanKHR *graphicsRequirements)
{
    const char *fn = "xrGetVulkanGraphicsRequirementsKHR";
    GET_INSTANCE(inst, instance, fn);
    XrResult r = check_system(systemId, fn);
    if (XR_FAILED(r))
        return r;
    if (!graphicsRequirements ||
        graphicsRequirements->type != XR_TYPE_GRAPHICS_REQUIREMENTS_VULKAN_KHR)
        return hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn, "bad graphicsRequirements");
    graphicsRequirements->minApiVersionSupported = XR_MAKE_VERSION(1, 0, 0);
    graphicsRequirements->maxApiVersionSupported = XR_MAKE_VERSION(1, 3, 0);
    pthread_mutex_lock(&inst->lock);
    inst->graphics_requirements_queried = true;
    pthread_mutex_unlock(&inst->lock);
    return XR_SUCCESS;
}

static XrResult XRAPI_CALL hsrt_xrGetVulkanGraphicsRequirements2KHR(
    XrInstance instance, XrSystemId systemId, XrGraphicsRequirementsVulkanKHR *graphicsRequirements)
{
    return hsrt_xrGetVulkanGraphicsRequirementsKHR(instance, systemId, graphicsRequirements);
}

static XrResult empty_extension_string(XrInstance instance, XrSystemId systemId, uint32_t cap,
                                       uint32_t *count, char *buffer, const char *fn)
{
    GET_INSTANCE(inst, instance, fn);
    (void)inst;
    XrResult r = check_system(systemId, fn);
    if (XR_FAILED(r))
        return r;
    if (!count)
        return hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn, "NULL count");
    *count = 1; /* "": the runtime needs no Vulkan extensions */
    if (!cap)
        return XR_SUCCESS;
    if (!buffer)
        return XR_ERROR_VALIDATION_FAILURE;
    buffer[0] = 0;
    return XR_SUCCESS;
}

static XrResult XRAPI_CALL hsrt_xrGetVulkanInstanceExtensionsKHR(XrInstance instance,
                                                                 XrSystemId systemId,
                                                                 uint32_t bufferCapacityInput,
                                                                 uint32_t *bufferCountOutput,
                                                                 char *buffer)
{
    return empty_extension_string(instance, systemId, bufferCapacityInput, bufferCountOutput,
                                  buffer, "xrGetVulkanInstanceExtensionsKHR");
}

static XrResult XRAPI_CALL hsrt_xrGetVulkanDeviceExtensionsKHR(XrInstance instance,
                                                               XrSystemId systemId,
                                                               uint32_t bufferCapacityInput,
                                                               uint32_t *bufferCountOutput,
                                                               char *buffer)
{
    return empty_extension_string(instance, systemId, bufferCapacityInput, bufferCountOutput,
                                  buffer, "xrGetVulkanDeviceExtensionsKHR");
}

/** Device extensions xrsc's renderer needs (gpu_context.c's required list). */
static const char *const k_ray_tracing_extensions[] = {
    VK_KHR_ACCELERATION_STRUCTURE_EXTENSION_NAME,
    VK_KHR_RAY_TRACING_PIPELINE_EXTENSION_NAME,
    VK_KHR_DEFERRED_HOST_OPERATIONS_EXTENSION_NAME,
};

/** Whether a device offers Vulkan 1.3 and the ray-tracing extensions xrsc renders with. */
static bool device_can_ray_trace(PFN_vkEnumerateDeviceExtensionProperties enum_ext,
                                 VkPhysicalDevice pd, const VkPhysicalDeviceProperties *p)
{
    if (!enum_ext || p->apiVersion < VK_API_VERSION_1_3)
        return false;
    uint32_t n = 0;
    if (enum_ext(pd, NULL, &n, NULL) != VK_SUCCESS || !n)
        return false;
    VkExtensionProperties *ext = calloc(n, sizeof(*ext));
    if (!ext)
        return false;
    VkResult vr = enum_ext(pd, NULL, &n, ext);
    size_t found = 0;
    for (size_t k = 0; vr >= 0 && k < sizeof(k_ray_tracing_extensions) / sizeof(char *); k++)
        for (uint32_t i = 0; i < n; i++)
            if (!strcmp(ext[i].extensionName, k_ray_tracing_extensions[k])) {
                found++;
                break;
            }
    free(ext);
    return found == sizeof(k_ray_tracing_extensions) / sizeof(char *);
}

/** Picks a physical device with the rule of the plugin's --device / XRSC_DEVICE (u_device.h):
 *  XRSC_RT_DEVICE (else XRSC_DEVICE) is cpu, gpu, an index or part of a name, and the first
 *  match that can ray trace is taken; unset, the first non-CPU device that can, else the CPU
 *  one. So `xrsc replay` through OpenXR renders on the device its --direct path would. When
 *  no matching device can ray trace (an application other than xrsc needs none), the first
 *  match is taken all the same. */
static XrResult pick_physical_device(hsrt_instance *inst, VkInstance vk, VkPhysicalDevice *out,
                                     const char *fn)
{
    PFN_vkGetInstanceProcAddr gipa = instance_gipa(inst);
    PFN_vkEnumeratePhysicalDevices enumerate =
        (PFN_vkEnumeratePhysicalDevices)gipa(vk, "vkEnumeratePhysicalDevices");
    PFN_vkGetPhysicalDeviceProperties props_fn =
        (PFN_vkGetPhysicalDeviceProperties)gipa(vk, "vkGetPhysicalDeviceProperties");
    PFN_vkEnumerateDeviceExtensionProperties enum_ext =
        (PFN_vkEnumerateDeviceExtensionProperties)gipa(vk, "vkEnumerateDeviceExtensionProperties");
    if (!enumerate || !props_fn)
        return hsrt_fail(XR_ERROR_RUNTIME_FAILURE, fn, "vkGetInstanceProcAddr gave no "
                                                       "vkEnumeratePhysicalDevices");
    uint32_t n = 0;
    VkResult vr = enumerate(vk, &n, NULL);
    if (vr != VK_SUCCESS || !n)
        return hsrt_fail(XR_ERROR_RUNTIME_FAILURE, fn, "no Vulkan physical devices (VkResult %d)",
                         (int)vr);
    VkPhysicalDevice *devs = calloc(n, sizeof(*devs));
    VkPhysicalDeviceProperties *props = calloc(n, sizeof(*props));
    const char **names = calloc(n, sizeof(*names));
    bool *is_cpu = calloc(n, sizeof(*is_cpu));
    bool *rt = calloc(n, sizeof(*rt));
    bool *all = calloc(n, sizeof(*all));
    XrResult r = XR_SUCCESS;
    int32_t best = -1;
    if (!devs || !props || !names || !is_cpu || !rt || !all) {
        r = hsrt_fail(XR_ERROR_OUT_OF_MEMORY, fn, "devices");
        goto done;
    }
    vr = enumerate(vk, &n, devs);
    if (vr != VK_SUCCESS && vr != VK_INCOMPLETE) {
        r = VK_FAIL(fn, "vkEnumeratePhysicalDevices", vr);
        goto done;
    }
    for (uint32_t i = 0; i < n; i++) {
        props_fn(devs[i], &props[i]);
        names[i] = props[i].deviceName;
        is_cpu[i] = props[i].deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
        rt[i] = device_can_ray_trace(enum_ext, devs[i], &props[i]);
        all[i] = true;
    }
    const char *want = inst->cfg.device;
    best = u_device_select(want, n, names, is_cpu, rt, NULL);
    if (best < 0) {
        best = u_device_select(want, n, names, is_cpu, all, NULL);
        if (best >= 0)
            U_LOG_I("runtime: no Vulkan device matching '%s' can ray trace; using %s", want,
                    names[best]);
    }
    if (best < 0) {
        r = hsrt_fail(XR_ERROR_RUNTIME_FAILURE, fn,
                      "no Vulkan device matches XRSC_RT_DEVICE='%s' (cpu, gpu, index, name part)",
                      want);
        goto done;
    }
    U_LOG_I("runtime: Vulkan device %s", names[best]);
    *out = devs[best];
    pthread_mutex_lock(&inst->lock);
    inst->vk_instance = vk;
    inst->vk_physical = *out;
    pthread_mutex_unlock(&inst->lock);
done:
    free(devs);
    free(props);
    free(names);
    free(is_cpu);
    free(rt);
    free(all);
    return r;
}

static XrResult XRAPI_CALL hsrt_xrGetVulkanGraphicsDeviceKHR(XrInstance instance,
                                                             XrSystemId systemId,
                                                             VkInstance vkInstance,
                                                             VkPhysicalDevice *vkPhysicalDevice)
{
    const char *fn = "xrGetVulkanGraphicsDeviceKHR";
    GET_INSTANCE(inst, instance, fn);
    XrResult r = check_system(systemId, fn);
    if (XR_FAILED(r))
        return r;
    if (!vkInstance || !vkPhysicalDevice)
        return hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn, "NULL argument");
    return pick_physical_device(inst, vkInstance, vkPhysicalDevice, fn);
}

static XrResult XRAPI_CALL hsrt_xrGetVulkanGraphicsDevice2KHR(
    XrInstance instance, const XrVulkanGraphicsDeviceGetInfoKHR *getInfo,
    VkPhysicalDevice *vulkanPhysicalDevice)
{
    const char *fn = "xrGetVulkanGraphicsDevice2KHR";
    GET_INSTANCE(inst, instance, fn);
    if (!getInfo || getInfo->type != XR_TYPE_VULKAN_GRAPHICS_DEVICE_GET_INFO_KHR ||
        !getInfo->vulkanInstance || !vulkanPhysicalDevice)
        return hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn, "bad getInfo");
    XrResult r = check_system(getInfo->systemId, fn);
    if (XR_FAILED(r))
        return r;
    return pick_physical_device(inst, getInfo->vulkanInstance, vulkanPhysicalDevice, fn);
}

static XrResult XRAPI_CALL hsrt_xrCreateVulkanInstanceKHR(XrInstance instance,
                                                          const XrVulkanInstanceCreateInfoKHR *createInfo,
                                                          VkInstance *vulkanInstance,
                                                          VkResult *vulkanResult)
{
    const char *fn = "xrCreateVulkanInstanceKHR";
    GET_INSTANCE(inst, instance, fn);
    if (!createInfo || createInfo->type != XR_TYPE_VULKAN_INSTANCE_CREATE_INFO_KHR ||
        !createInfo->pfnGetInstanceProcAddr || !createInfo->vulkanCreateInfo || !vulkanInstance ||
        !vulkanResult)
        return hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn, "bad createInfo");
    XrResult r = check_system(createInfo->systemId, fn);
    if (XR_FAILED(r))
        return r;
    /* No XR_ERROR_GRAPHICS_REQUIREMENTS_CALL_MISSING here: the spec does not list it for this
     * function (xrCreateSession checks the call). */
    PFN_vkCreateInstance create =
        (PFN_vkCreateInstance)createInfo->pfnGetInstanceProcAddr(NULL, "vkCreateInstance");
    if (!create)
        return hsrt_fail(XR_ERROR_RUNTIME_FAILURE, fn, "no vkCreateInstance");
    *vulkanResult = create(createInfo->vulkanCreateInfo, createInfo->vulkanAllocator, vulkanInstance);
    if (*vulkanResult != VK_SUCCESS) {
        U_LOG_E("runtime: %s: vkCreateInstance failed with VkResult %d", fn, (int)*vulkanResult);
        return XR_SUCCESS; /* the Vulkan error is reported through vulkanResult */
    }
    pthread_mutex_lock(&inst->lock);
    inst->vk_gipa = createInfo->pfnGetInstanceProcAddr;
    inst->vk_instance = *vulkanInstance;
    pthread_mutex_unlock(&inst->lock);
    return XR_SUCCESS;
}

static XrResult XRAPI_CALL hsrt_xrCreateVulkanDeviceKHR(XrInstance instance,
                                                        const XrVulkanDeviceCreateInfoKHR *createInfo,
                                                        VkDevice *vulkanDevice, VkResult *vulkanResult)
{
    const char *fn = "xrCreateVulkanDeviceKHR";
    GET_INSTANCE(inst, instance, fn);
    if (!createInfo || createInfo->type != XR_TYPE_VULKAN_DEVICE_CREATE_INFO_KHR ||
        !createInfo->pfnGetInstanceProcAddr || !createInfo->vulkanCreateInfo ||
        !createInfo->vulkanPhysicalDevice || !vulkanDevice || !vulkanResult)
        return hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn, "bad createInfo");
    XrResult r = check_system(createInfo->systemId, fn);
    if (XR_FAILED(r))
        return r;
    if (!inst->vk_instance)
        return hsrt_fail(XR_ERROR_CALL_ORDER_INVALID, fn,
                         "call xrGetVulkanGraphicsDevice2KHR first (it names the VkInstance)");
    if (createInfo->vulkanPhysicalDevice != inst->vk_physical)
        U_LOG_W("runtime: %s: the physical device is not the one xrGetVulkanGraphicsDevice2KHR "
                "returned", fn);
    PFN_vkCreateDevice create =
        (PFN_vkCreateDevice)createInfo->pfnGetInstanceProcAddr(inst->vk_instance, "vkCreateDevice");
    if (!create)
        return hsrt_fail(XR_ERROR_RUNTIME_FAILURE, fn, "no vkCreateDevice");
    *vulkanResult = create(createInfo->vulkanPhysicalDevice, createInfo->vulkanCreateInfo,
                           createInfo->vulkanAllocator, vulkanDevice);
    if (*vulkanResult != VK_SUCCESS)
        U_LOG_E("runtime: %s: vkCreateDevice failed with VkResult %d", fn, (int)*vulkanResult);
    return XR_SUCCESS;
}

/* ---- the session's Vulkan objects ---- */

static int32_t memory_type(const hsrt_vk *vk, uint32_t bits, VkMemoryPropertyFlags want)
{
    for (uint32_t i = 0; i < vk->mem_props.memoryTypeCount; i++) {
        if ((bits & (1u << i)) && (vk->mem_props.memoryTypes[i].propertyFlags & want) == want)
            return (int32_t)i;
    }
    return -1;
}

XrResult hsrt_vk_session_init(hsrt_session *s, const XrGraphicsBindingVulkanKHR *b)
{
    const char *fn = "xrCreateSession";
    hsrt_vk *vk = &s->vk;
    if (!b->instance || !b->physicalDevice || !b->device)
        return hsrt_fail(XR_ERROR_GRAPHICS_DEVICE_INVALID, fn, "NULL handle in the Vulkan binding");
    PFN_vkGetInstanceProcAddr gipa = instance_gipa(s->instance);
    vk->instance = b->instance;
    vk->physical = b->physicalDevice;
    vk->device = b->device;
    vk->queue_family = b->queueFamilyIndex;
    vk->GetDeviceProcAddr = (PFN_vkGetDeviceProcAddr)gipa(b->instance, "vkGetDeviceProcAddr");
    PFN_vkGetPhysicalDeviceMemoryProperties mem =
        (PFN_vkGetPhysicalDeviceMemoryProperties)gipa(b->instance,
                                                      "vkGetPhysicalDeviceMemoryProperties");
    if (!vk->GetDeviceProcAddr || !mem)
        return hsrt_fail(XR_ERROR_GRAPHICS_DEVICE_INVALID, fn,
                         "the binding's VkInstance gives no vkGetDeviceProcAddr");
    mem(b->physicalDevice, &vk->mem_props);
#define HSRT_X_LOAD(name)                                                                          \
    vk->name = (PFN_vk##name)vk->GetDeviceProcAddr(b->device, "vk" #name);                         \
    if (!vk->name)                                                                                 \
        return hsrt_fail(XR_ERROR_GRAPHICS_DEVICE_INVALID, fn, "no vk" #name " on the device");
    HSRT_VK_DEVICE_FUNCS(HSRT_X_LOAD)
#undef HSRT_X_LOAD
    vk->GetDeviceQueue(b->device, b->queueFamilyIndex, b->queueIndex, &vk->queue);
    if (!vk->queue)
        return hsrt_fail(XR_ERROR_GRAPHICS_DEVICE_INVALID, fn, "no queue %u of family %u",
                         b->queueIndex, b->queueFamilyIndex);
    VkCommandPoolCreateInfo pci = {.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO,
                                   .flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT,
                                   .queueFamilyIndex = b->queueFamilyIndex};
    VkResult vr = vk->CreateCommandPool(vk->device, &pci, NULL, &vk->pool);
    if (vr != VK_SUCCESS)
        return VK_FAIL(fn, "vkCreateCommandPool", vr);
    VkCommandBufferAllocateInfo ai = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO,
                                      .commandPool = vk->pool,
                                      .level = VK_COMMAND_BUFFER_LEVEL_PRIMARY,
                                      .commandBufferCount = 1};
    vr = vk->AllocateCommandBuffers(vk->device, &ai, &vk->cmd);
    if (vr == VK_SUCCESS) {
        VkFenceCreateInfo fci = {.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
        vr = vk->CreateFence(vk->device, &fci, NULL, &vk->fence);
        if (vr != VK_SUCCESS) {
            vk->DestroyCommandPool(vk->device, vk->pool, NULL);
            return VK_FAIL(fn, "vkCreateFence", vr);
        }
        return XR_SUCCESS;
    }
    vk->DestroyCommandPool(vk->device, vk->pool, NULL);
    return VK_FAIL(fn, "vkAllocateCommandBuffers", vr);
}

void hsrt_swapchain_free(hsrt_swapchain *sc)
{
    if (!sc)
        return;
    hsrt_vk *vk = &sc->session->vk;
    for (uint32_t i = 0; i < HSRT_MAX_SWAPCHAIN_IMAGES; i++) {
        if (sc->images[i])
            vk->DestroyImage(vk->device, sc->images[i], NULL);
        if (sc->memory[i])
            vk->FreeMemory(vk->device, sc->memory[i], NULL);
    }
    if (sc->retire_fence)
        vk->DestroyFence(vk->device, sc->retire_fence, NULL);
    hsrt_handle_revoke(sc->handle);
    free(sc);
}

void hsrt_swapchain_retire(hsrt_session *s, hsrt_swapchain *sc)
{
    hsrt_vk *vk = &s->vk;
    hsrt_handle_revoke(sc->handle);
    sc->handle = 0;
    VkFenceCreateInfo fci = {.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    VkResult vr = vk->CreateFence(vk->device, &fci, NULL, &sc->retire_fence);
    if (vr == VK_SUCCESS)
        vr = vk->QueueSubmit(vk->queue, 0, NULL, sc->retire_fence);
    if (vr != VK_SUCCESS) {
        U_LOG_W("runtime: xrDestroySwapchain: no fence to defer the free (VkResult %d): waiting "
                "for the device to go idle",
                (int)vr);
        vk->DeviceWaitIdle(vk->device);
        hsrt_swapchain_free(sc);
        return;
    }
    sc->next_in_session = s->retired;
    s->retired = sc;
}

void hsrt_swapchains_reap(hsrt_session *s, bool wait)
{
    hsrt_vk *vk = &s->vk;
    for (hsrt_swapchain **p = &s->retired; *p;) {
        hsrt_swapchain *sc = *p;
        VkResult vr = wait
                          ? vk->WaitForFences(vk->device, 1, &sc->retire_fence, VK_TRUE, UINT64_MAX)
                          : vk->GetFenceStatus(vk->device, sc->retire_fence);
        if (vr == VK_NOT_READY) {
            p = &sc->next_in_session;
            continue;
        }
        if (vr != VK_SUCCESS) /* device lost: nothing runs any more */
            U_LOG_W("runtime: waiting for a destroyed swapchain's fence: VkResult %d", (int)vr);
        *p = sc->next_in_session;
        hsrt_swapchain_free(sc);
    }
}

static void readback_free(hsrt_vk *vk)
{
    if (vk->readback_map)
        vk->UnmapMemory(vk->device, vk->readback_mem);
    if (vk->readback)
        vk->DestroyBuffer(vk->device, vk->readback, NULL);
    if (vk->readback_mem)
        vk->FreeMemory(vk->device, vk->readback_mem, NULL);
    vk->readback_map = NULL;
    vk->readback = VK_NULL_HANDLE;
    vk->readback_mem = VK_NULL_HANDLE;
    vk->readback_size = 0;
}

void hsrt_vk_session_fini(hsrt_session *s)
{
    hsrt_vk *vk = &s->vk;
    if (!vk->device)
        return;
    while (s->swapchains) {
        hsrt_swapchain *sc = s->swapchains;
        s->swapchains = sc->next_in_session;
        hsrt_swapchain_retire(s, sc);
    }
    hsrt_swapchains_reap(s, true);
    readback_free(vk);
    if (vk->fence)
        vk->DestroyFence(vk->device, vk->fence, NULL);
    if (vk->pool)
        vk->DestroyCommandPool(vk->device, vk->pool, NULL); /* frees vk->cmd */
    memset(vk, 0, sizeof(*vk));
}

/** Records into vk->cmd (begun by the caller) nothing; submits it and waits. */
static VkResult submit_and_wait(hsrt_vk *vk)
{
    VkResult vr = vk->EndCommandBuffer(vk->cmd);
    if (vr != VK_SUCCESS)
        return vr;
    VkSubmitInfo si = {.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO,
                       .commandBufferCount = 1,
                       .pCommandBuffers = &vk->cmd};
    vr = vk->QueueSubmit(vk->queue, 1, &si, vk->fence);
    if (vr != VK_SUCCESS)
        return vr;
    vr = vk->WaitForFences(vk->device, 1, &vk->fence, VK_TRUE, UINT64_MAX);
    if (vr != VK_SUCCESS)
        return vr;
    return vk->ResetFences(vk->device, 1, &vk->fence);
}

static VkResult begin_cmd(hsrt_vk *vk)
{
    VkResult vr = vk->ResetCommandBuffer(vk->cmd, 0);
    if (vr != VK_SUCCESS)
        return vr;
    VkCommandBufferBeginInfo bi = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO,
                                   .flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT};
    return vk->BeginCommandBuffer(vk->cmd, &bi);
}

/* ---- swapchains ---- */

static hsrt_session *session_of(XrSession handle)
{
    return hsrt_handle_get(HSRT_VALUE(handle), HSRT_HANDLE_SESSION);
}

static hsrt_swapchain *swapchain_of(XrSwapchain handle)
{
    return hsrt_handle_get(HSRT_VALUE(handle), HSRT_HANDLE_SWAPCHAIN);
}

#define LOCK_SESSION(var, handle, fn)                                                              \
    hsrt_session *var = session_of(handle);                                                        \
    if (!var)                                                                                      \
        return hsrt_fail(XR_ERROR_HANDLE_INVALID, fn, "not an XrSession of this runtime");         \
    pthread_mutex_lock(&var->instance->lock);                                                      \
    if (var->lost) {                                                                               \
        pthread_mutex_unlock(&var->instance->lock);                                                \
        return hsrt_fail(XR_ERROR_SESSION_LOST, fn, "the session was lost");                       \
    }
#define UNLOCK(var) pthread_mutex_unlock(&var->instance->lock)

static XrResult XRAPI_CALL hsrt_xrEnumerateSwapchainFormats(XrSession session,
                                                            uint32_t formatCapacityInput,
                                                            uint32_t *formatCountOutput,
                                                            int64_t *formats)
{
    const char *fn = "xrEnumerateSwapchainFormats";
    LOCK_SESSION(s, session, fn);
    XrResult r = XR_SUCCESS;
    if (!formatCountOutput) {
        r = hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn, "NULL count");
    } else {
        *formatCountOutput = hsrt_format_count;
        if (formatCapacityInput) {
            if (formatCapacityInput < hsrt_format_count || !formats)
                r = XR_ERROR_SIZE_INSUFFICIENT;
            else
                for (uint32_t i = 0; i < hsrt_format_count; i++)
                    formats[i] = (int64_t)hsrt_formats[i];
        }
    }
    UNLOCK(s);
    return r;
}

/** The layout the spec ties to a swapchain's usage (the first matching flag). */
static VkImageLayout usage_layout(XrSwapchainUsageFlags u)
{
    if (u & XR_SWAPCHAIN_USAGE_COLOR_ATTACHMENT_BIT)
        return VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    if (u & XR_SWAPCHAIN_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT)
        return VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
    if (u & XR_SWAPCHAIN_USAGE_UNORDERED_ACCESS_BIT)
        return VK_IMAGE_LAYOUT_GENERAL;
    if (u & XR_SWAPCHAIN_USAGE_TRANSFER_SRC_BIT)
        return VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
    if (u & XR_SWAPCHAIN_USAGE_TRANSFER_DST_BIT)
        return VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
    if (u & XR_SWAPCHAIN_USAGE_SAMPLED_BIT)
        return VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
    return VK_IMAGE_LAYOUT_GENERAL;
}

static VkImageAspectFlags aspect_of(VkFormat f)
{
    if (f == VK_FORMAT_D24_UNORM_S8_UINT || f == VK_FORMAT_D32_SFLOAT_S8_UINT)
        return VK_IMAGE_ASPECT_DEPTH_BIT | VK_IMAGE_ASPECT_STENCIL_BIT;
    return hsrt_format_is_depth(f) ? VK_IMAGE_ASPECT_DEPTH_BIT : VK_IMAGE_ASPECT_COLOR_BIT;
}

static XrResult create_images(hsrt_session *s, hsrt_swapchain *sc, const char *fn)
{
    hsrt_vk *vk = &s->vk;
    const XrSwapchainCreateInfo *ci = &sc->info;
    XrSwapchainUsageFlags u = ci->usageFlags;
    VkImageUsageFlags usage = VK_IMAGE_USAGE_TRANSFER_SRC_BIT; /* for the capture */
    if (u & XR_SWAPCHAIN_USAGE_COLOR_ATTACHMENT_BIT)
        usage |= VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT;
    if (u & XR_SWAPCHAIN_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT)
        usage |= VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT;
    if (u & XR_SWAPCHAIN_USAGE_UNORDERED_ACCESS_BIT)
        usage |= VK_IMAGE_USAGE_STORAGE_BIT;
    if (u & XR_SWAPCHAIN_USAGE_TRANSFER_DST_BIT)
        usage |= VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    if (u & XR_SWAPCHAIN_USAGE_SAMPLED_BIT)
        usage |= VK_IMAGE_USAGE_SAMPLED_BIT;
    VkImageCreateInfo ici = {
        .sType = VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO,
        .flags = (u & XR_SWAPCHAIN_USAGE_MUTABLE_FORMAT_BIT) ? VK_IMAGE_CREATE_MUTABLE_FORMAT_BIT : 0,
        .imageType = VK_IMAGE_TYPE_2D,
        .format = (VkFormat)ci->format,
        .extent = {ci->width, ci->height, 1},
        .mipLevels = ci->mipCount,
        .arrayLayers = ci->arraySize,
        .samples = (VkSampleCountFlagBits)ci->sampleCount,
        .tiling = VK_IMAGE_TILING_OPTIMAL,
        .usage = usage,
        .sharingMode = VK_SHARING_MODE_EXCLUSIVE,
        .initialLayout = VK_IMAGE_LAYOUT_UNDEFINED};
    for (uint32_t i = 0; i < sc->image_count; i++) {
        VkResult vr = vk->CreateImage(vk->device, &ici, NULL, &sc->images[i]);
        if (vr != VK_SUCCESS)
            return hsrt_fail(XR_ERROR_SWAPCHAIN_FORMAT_UNSUPPORTED, fn,
                             "vkCreateImage (format %lld, %ux%u) failed with VkResult %d",
                             (long long)ci->format, ci->width, ci->height, (int)vr);
        VkMemoryRequirements req;
        vk->GetImageMemoryRequirements(vk->device, sc->images[i], &req);
        int32_t type = memory_type(vk, req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
        if (type < 0)
            type = memory_type(vk, req.memoryTypeBits, 0);
        VkMemoryAllocateInfo mai = {.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO,
                                    .allocationSize = req.size,
                                    .memoryTypeIndex = (uint32_t)type};
        vr = vk->AllocateMemory(vk->device, &mai, NULL, &sc->memory[i]);
        if (vr != VK_SUCCESS)
            return VK_FAIL(fn, "vkAllocateMemory", vr);
        vr = vk->BindImageMemory(vk->device, sc->images[i], sc->memory[i], 0);
        if (vr != VK_SUCCESS)
            return VK_FAIL(fn, "vkBindImageMemory", vr);
    }
    /* Bring every image into the layout the application expects. */
    VkResult vr = begin_cmd(vk);
    if (vr != VK_SUCCESS)
        return VK_FAIL(fn, "vkBeginCommandBuffer", vr);
    for (uint32_t i = 0; i < sc->image_count; i++) {
        VkImageMemoryBarrier b = {.sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER,
                                  .srcAccessMask = 0,
                                  .dstAccessMask = VK_ACCESS_MEMORY_READ_BIT |
                                                   VK_ACCESS_MEMORY_WRITE_BIT,
                                  .oldLayout = VK_IMAGE_LAYOUT_UNDEFINED,
                                  .newLayout = sc->layout,
                                  .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                                  .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                                  .image = sc->images[i],
                                  .subresourceRange = {aspect_of((VkFormat)ci->format), 0,
                                                       ci->mipCount, 0, ci->arraySize}};
        vk->CmdPipelineBarrier(vk->cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT,
                               VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, 0, 0, NULL, 0, NULL, 1, &b);
    }
    vr = submit_and_wait(vk);
    if (vr != VK_SUCCESS)
        return VK_FAIL(fn, "initial layout transition", vr);
    return XR_SUCCESS;
}

static XrResult XRAPI_CALL hsrt_xrCreateSwapchain(XrSession session,
                                                  const XrSwapchainCreateInfo *createInfo,
                                                  XrSwapchain *swapchain)
{
    const char *fn = "xrCreateSwapchain";
    LOCK_SESSION(s, session, fn);
    XrResult r = XR_SUCCESS;
    hsrt_swapchains_reap(s, false);
    hsrt_swapchain *sc = NULL;
    if (!createInfo || !swapchain || createInfo->type != XR_TYPE_SWAPCHAIN_CREATE_INFO) {
        r = hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn, "bad createInfo");
        goto out;
    }
    if (!hsrt_format_size((VkFormat)createInfo->format)) {
        r = hsrt_fail(XR_ERROR_SWAPCHAIN_FORMAT_UNSUPPORTED, fn, "VkFormat %lld",
                      (long long)createInfo->format);
        goto out;
    }
    if (createInfo->createFlags & XR_SWAPCHAIN_CREATE_PROTECTED_CONTENT_BIT) {
        r = hsrt_fail(XR_ERROR_FEATURE_UNSUPPORTED, fn, "protected content");
        goto out;
    }
    if (createInfo->faceCount != 1 || createInfo->sampleCount != 1) {
        r = hsrt_fail(XR_ERROR_FEATURE_UNSUPPORTED, fn,
                      "faceCount %u, sampleCount %u (only 1 and 1 are supported)",
                      createInfo->faceCount, createInfo->sampleCount);
        goto out;
    }
    if (!createInfo->width || !createInfo->height || createInfo->width > 8192 ||
        createInfo->height > 8192 || !createInfo->arraySize || !createInfo->mipCount) {
        r = hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn, "size %ux%u, %u layers, %u mips",
                      createInfo->width, createInfo->height, createInfo->arraySize,
                      createInfo->mipCount);
        goto out;
    }
    sc = calloc(1, sizeof(*sc));
    if (!sc) {
        r = hsrt_fail(XR_ERROR_OUT_OF_MEMORY, fn, "swapchain");
        goto out;
    }
    sc->session = s;
    sc->info = *createInfo;
    sc->info.next = NULL;
    sc->layout = usage_layout(createInfo->usageFlags);
    sc->image_count = (createInfo->createFlags & XR_SWAPCHAIN_CREATE_STATIC_IMAGE_BIT)
                          ? 1
                          : HSRT_MAX_SWAPCHAIN_IMAGES;
    sc->last_released = -1;
    r = create_images(s, sc, fn);
    if (XR_FAILED(r)) {
        hsrt_swapchain_free(sc);
        goto out;
    }
    sc->handle = hsrt_handle_issue(sc, HSRT_HANDLE_SWAPCHAIN);
    if (!sc->handle) {
        hsrt_swapchain_free(sc);
        r = hsrt_fail(XR_ERROR_OUT_OF_MEMORY, fn, "handle table");
        goto out;
    }
    sc->next_in_session = s->swapchains;
    s->swapchains = sc;
    *swapchain = HSRT_XR(XrSwapchain, sc->handle);
out:
    UNLOCK(s);
    return r;
}

static XrResult XRAPI_CALL hsrt_xrDestroySwapchain(XrSwapchain swapchain)
{
    hsrt_swapchain *sc = swapchain_of(swapchain);
    if (!sc)
        return hsrt_fail(XR_ERROR_HANDLE_INVALID, "xrDestroySwapchain", "not an XrSwapchain");
    hsrt_session *s = sc->session;
    pthread_mutex_lock(&s->instance->lock);
    for (hsrt_swapchain **p = &s->swapchains; *p; p = &(*p)->next_in_session) {
        if (*p == sc) {
            *p = sc->next_in_session;
            break;
        }
    }
    hsrt_swapchain_retire(s, sc);
    hsrt_swapchains_reap(s, false);
    UNLOCK(s);
    return XR_SUCCESS;
}

static XrResult XRAPI_CALL hsrt_xrEnumerateSwapchainImages(XrSwapchain swapchain,
                                                           uint32_t imageCapacityInput,
                                                           uint32_t *imageCountOutput,
                                                           XrSwapchainImageBaseHeader *images)
{
    const char *fn = "xrEnumerateSwapchainImages";
    hsrt_swapchain *sc = swapchain_of(swapchain);
    if (!sc)
        return hsrt_fail(XR_ERROR_HANDLE_INVALID, fn, "not an XrSwapchain");
    LOCK_SESSION(s, HSRT_XR(XrSession, sc->session->handle), fn);
    XrResult r = XR_SUCCESS;
    if (!imageCountOutput) {
        r = hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn, "NULL count");
    } else {
        *imageCountOutput = sc->image_count;
        if (imageCapacityInput) {
            XrSwapchainImageVulkanKHR *out = (XrSwapchainImageVulkanKHR *)images;
            if (imageCapacityInput < sc->image_count || !images)
                r = XR_ERROR_SIZE_INSUFFICIENT;
            for (uint32_t i = 0; XR_SUCCEEDED(r) && i < sc->image_count; i++) {
                if (out[i].type != XR_TYPE_SWAPCHAIN_IMAGE_VULKAN_KHR)
                    r = hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn,
                                  "images[%u].type is not XR_TYPE_SWAPCHAIN_IMAGE_VULKAN_KHR", i);
                else
                    out[i].image = sc->images[i];
            }
        }
    }
    UNLOCK(s);
    return r;
}

static XrResult XRAPI_CALL hsrt_xrAcquireSwapchainImage(XrSwapchain swapchain,
                                                        const XrSwapchainImageAcquireInfo *acquireInfo,
                                                        uint32_t *index)
{
    const char *fn = "xrAcquireSwapchainImage";
    hsrt_swapchain *sc = swapchain_of(swapchain);
    if (!sc)
        return hsrt_fail(XR_ERROR_HANDLE_INVALID, fn, "not an XrSwapchain");
    LOCK_SESSION(s, HSRT_XR(XrSession, sc->session->handle), fn);
    XrResult r = XR_SUCCESS;
    if ((acquireInfo && acquireInfo->type != XR_TYPE_SWAPCHAIN_IMAGE_ACQUIRE_INFO) || !index)
        r = hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn, "bad arguments");
    else if (sc->acquired == sc->image_count)
        r = hsrt_fail(XR_ERROR_CALL_ORDER_INVALID, fn, "every image is acquired already");
    else if ((sc->info.createFlags & XR_SWAPCHAIN_CREATE_STATIC_IMAGE_BIT) && sc->last_released >= 0)
        r = hsrt_fail(XR_ERROR_CALL_ORDER_INVALID, fn, "a static swapchain is acquired once");
    if (XR_SUCCEEDED(r)) {
        *index = sc->next_acquire;
        sc->acquired_order[sc->acquired++] = sc->next_acquire;
        sc->next_acquire = (sc->next_acquire + 1) % sc->image_count;
    }
    UNLOCK(s);
    return r;
}

static XrResult XRAPI_CALL hsrt_xrWaitSwapchainImage(XrSwapchain swapchain,
                                                     const XrSwapchainImageWaitInfo *waitInfo)
{
    const char *fn = "xrWaitSwapchainImage";
    hsrt_swapchain *sc = swapchain_of(swapchain);
    if (!sc)
        return hsrt_fail(XR_ERROR_HANDLE_INVALID, fn, "not an XrSwapchain");
    LOCK_SESSION(s, HSRT_XR(XrSession, sc->session->handle), fn);
    XrResult r = XR_SUCCESS;
    if (!waitInfo || waitInfo->type != XR_TYPE_SWAPCHAIN_IMAGE_WAIT_INFO)
        r = hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn, "bad waitInfo");
    else if (!sc->acquired || sc->waited)
        r = hsrt_fail(XR_ERROR_CALL_ORDER_INVALID, fn, "no acquired image waits");
    else
        sc->waited = true; /* the runtime's reads finish inside xrEndFrame: always ready */
    UNLOCK(s);
    return r;
}

static XrResult XRAPI_CALL hsrt_xrReleaseSwapchainImage(XrSwapchain swapchain,
                                                        const XrSwapchainImageReleaseInfo *releaseInfo)
{
    const char *fn = "xrReleaseSwapchainImage";
    hsrt_swapchain *sc = swapchain_of(swapchain);
    if (!sc)
        return hsrt_fail(XR_ERROR_HANDLE_INVALID, fn, "not an XrSwapchain");
    LOCK_SESSION(s, HSRT_XR(XrSession, sc->session->handle), fn);
    XrResult r = XR_SUCCESS;
    if (releaseInfo && releaseInfo->type != XR_TYPE_SWAPCHAIN_IMAGE_RELEASE_INFO)
        r = hsrt_fail(XR_ERROR_VALIDATION_FAILURE, fn, "bad releaseInfo");
    else if (!sc->acquired || !sc->waited)
        r = hsrt_fail(XR_ERROR_CALL_ORDER_INVALID, fn, "no waited image to release");
    if (XR_SUCCEEDED(r)) {
        sc->last_released = (int32_t)sc->acquired_order[0];
        memmove(sc->acquired_order, sc->acquired_order + 1,
                (HSRT_MAX_SWAPCHAIN_IMAGES - 1) * sizeof(sc->acquired_order[0]));
        sc->acquired--;
        sc->waited = false;
    }
    UNLOCK(s);
    return r;
}

/* ---- capture ---- */

static XrResult ensure_readback(hsrt_vk *vk, VkDeviceSize size, const char *fn)
{
    if (vk->readback_size >= size)
        return XR_SUCCESS;
    readback_free(vk);
    VkBufferCreateInfo bci = {.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO,
                              .size = size,
                              .usage = VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                              .sharingMode = VK_SHARING_MODE_EXCLUSIVE};
    VkResult vr = vk->CreateBuffer(vk->device, &bci, NULL, &vk->readback);
    if (vr != VK_SUCCESS)
        return VK_FAIL(fn, "vkCreateBuffer", vr);
    VkMemoryRequirements req;
    vk->GetBufferMemoryRequirements(vk->device, vk->readback, &req);
    int32_t type = memory_type(vk, req.memoryTypeBits,
                               VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT |
                                   VK_MEMORY_PROPERTY_HOST_CACHED_BIT);
    if (type < 0)
        type = memory_type(vk, req.memoryTypeBits, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT);
    if (type < 0) {
        readback_free(vk);
        return hsrt_fail(XR_ERROR_RUNTIME_FAILURE, fn, "no host-visible memory for read-back");
    }
    VkMemoryAllocateInfo mai = {.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO,
                                .allocationSize = req.size,
                                .memoryTypeIndex = (uint32_t)type};
    vr = vk->AllocateMemory(vk->device, &mai, NULL, &vk->readback_mem);
    if (vr == VK_SUCCESS)
        vr = vk->BindBufferMemory(vk->device, vk->readback, vk->readback_mem, 0);
    if (vr == VK_SUCCESS)
        vr = vk->MapMemory(vk->device, vk->readback_mem, 0, VK_WHOLE_SIZE, 0, &vk->readback_map);
    if (vr != VK_SUCCESS) {
        readback_free(vk);
        return VK_FAIL(fn, "read-back buffer memory", vr);
    }
    vk->readback_size = size;
    return XR_SUCCESS;
}

/** The depth info chained to a projection view, NULL if none. */
static const XrCompositionLayerDepthInfoKHR *depth_info(const XrCompositionLayerProjectionView *pv)
{
    for (const XrBaseInStructure *n = pv->next; n; n = n->next) {
        if (n->type == XR_TYPE_COMPOSITION_LAYER_DEPTH_INFO_KHR)
            return (const XrCompositionLayerDepthInfoKHR *)n;
    }
    return NULL;
}

/** One image region copied to the read-back buffer. */
typedef struct capture_copy {
    const XrSwapchainSubImage *si;
    hsrt_swapchain *sc;
    VkImageAspectFlags aspect;
    VkDeviceSize offset;
} capture_copy;

static void record_copy(hsrt_vk *vk, const capture_copy *c)
{
    VkImage img = c->sc->images[c->sc->last_released];
    VkImageSubresourceRange range = {c->aspect, 0, 1, c->si->imageArrayIndex, 1};
    VkImageMemoryBarrier to_src = {.sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER,
                                   .srcAccessMask = VK_ACCESS_MEMORY_WRITE_BIT,
                                   .dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT,
                                   .oldLayout = c->sc->layout,
                                   .newLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                                   .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                                   .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                                   .image = img,
                                   .subresourceRange = range};
    vk->CmdPipelineBarrier(vk->cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
                           VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, NULL, 0, NULL, 1, &to_src);
    VkBufferImageCopy copy = {
        .bufferOffset = c->offset,
        .imageSubresource = {c->aspect, 0, c->si->imageArrayIndex, 1},
        .imageOffset = {c->si->imageRect.offset.x, c->si->imageRect.offset.y, 0},
        .imageExtent = {(uint32_t)c->si->imageRect.extent.width,
                        (uint32_t)c->si->imageRect.extent.height, 1}};
    vk->CmdCopyImageToBuffer(vk->cmd, img, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, vk->readback, 1,
                             &copy);
    VkImageMemoryBarrier back = to_src;
    back.srcAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
    back.dstAccessMask = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT;
    back.oldLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
    back.newLayout = c->sc->layout;
    vk->CmdPipelineBarrier(vk->cmd, VK_PIPELINE_STAGE_TRANSFER_BIT,
                           VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, 0, 0, NULL, 0, NULL, 1, &back);
}

/* The copies of a capture: the two colour views, then (out_depth_m given) each view's depth
 * when its depth info names a depth swapchain region of the colour region's size. */
static uint32_t plan_copies(const XrCompositionLayerProjection *layer, bool want_depth,
                            capture_copy out[4], int out_depth_index[2], VkDeviceSize *out_total)
{
    uint32_t n = 0;
    VkDeviceSize total = 0;
    for (int pass = 0; pass < (want_depth ? 2 : 1); pass++) {
        for (int v = 0; v < 2; v++) {
            const XrCompositionLayerProjectionView *pv = &layer->views[v];
            const XrSwapchainSubImage *si = &pv->subImage;
            if (pass == 1) {
                out_depth_index[v] = -1;
                const XrCompositionLayerDepthInfoKHR *d = depth_info(pv);
                if (!d || d->subImage.imageRect.extent.width != si->imageRect.extent.width ||
                    d->subImage.imageRect.extent.height != si->imageRect.extent.height)
                    continue;
                si = &d->subImage;
                out_depth_index[v] = (int)n;
            }
            hsrt_swapchain *sc = swapchain_of(si->swapchain);
            VkFormat f = (VkFormat)sc->info.format;
            out[n] = (capture_copy){si, sc,
                                    hsrt_format_is_depth(f) ? VK_IMAGE_ASPECT_DEPTH_BIT
                                                            : VK_IMAGE_ASPECT_COLOR_BIT,
                                    total};
            total += (VkDeviceSize)si->imageRect.extent.width * si->imageRect.extent.height *
                     hsrt_format_size(f);
            total = (total + 15) & ~(VkDeviceSize)15;
            n++;
        }
    }
    *out_total = total;
    return n;
}

XrResult hsrt_vk_capture(hsrt_session *s, const XrCompositionLayerProjection *layer,
                         hsrt_eye_image out_eyes[2], float *out_depth_m[2])
{
    const char *fn = "xrEndFrame (capture)";
    hsrt_vk *vk = &s->vk;
    for (int v = 0; v < 2; v++) {
        hsrt_swapchain *sc = swapchain_of(layer->views[v].subImage.swapchain);
        if (hsrt_format_is_depth((VkFormat)sc->info.format))
            return hsrt_fail(XR_ERROR_LAYER_INVALID, fn, "view %d shows a depth swapchain", v);
    }
    capture_copy copies[4];
    int depth_index[2] = {-1, -1};
    VkDeviceSize total = 0;
    uint32_t n = plan_copies(layer, out_depth_m != NULL, copies, depth_index, &total);
    XrResult r = ensure_readback(vk, total, fn);
    if (XR_FAILED(r))
        return r;
    VkResult vr = begin_cmd(vk);
    if (vr != VK_SUCCESS)
        return VK_FAIL(fn, "vkBeginCommandBuffer", vr);
    for (uint32_t i = 0; i < n; i++)
        record_copy(vk, &copies[i]);
    VkBufferMemoryBarrier host = {.sType = VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER,
                                  .srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT,
                                  .dstAccessMask = VK_ACCESS_HOST_READ_BIT,
                                  .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                                  .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                                  .buffer = vk->readback,
                                  .offset = 0,
                                  .size = VK_WHOLE_SIZE};
    vk->CmdPipelineBarrier(vk->cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0,
                           0, NULL, 1, &host, 0, NULL);
    vr = submit_and_wait(vk);
    if (vr != VK_SUCCESS)
        return VK_FAIL(fn, "read-back submit", vr);
    VkMappedMemoryRange mr = {.sType = VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE,
                              .memory = vk->readback_mem,
                              .offset = 0,
                              .size = VK_WHOLE_SIZE};
    vk->InvalidateMappedMemoryRanges(vk->device, 1, &mr);
    for (int v = 0; v < 2; v++) {
        const capture_copy *c = &copies[v];
        if (!hsrt_convert((VkFormat)c->sc->info.format,
                          (const uint8_t *)vk->readback_map + c->offset,
                          (uint32_t)c->si->imageRect.extent.width,
                          (uint32_t)c->si->imageRect.extent.height, s->instance->cfg.exposure,
                          &out_eyes[v]))
            return hsrt_fail(XR_ERROR_OUT_OF_MEMORY, fn, "converting view %d", v);
        if (!out_depth_m || depth_index[v] < 0)
            continue;
        const capture_copy *d = &copies[depth_index[v]];
        out_depth_m[v] = hsrt_depth_to_metres(
            (VkFormat)d->sc->info.format, (const uint8_t *)vk->readback_map + d->offset,
            (uint32_t)d->si->imageRect.extent.width, (uint32_t)d->si->imageRect.extent.height,
            depth_info(&layer->views[v]));
    }
    /* automatic exposure of linear (float) swapchains: one exposure for the stereo frame */
    VkFormat f0 = (VkFormat)copies[0].sc->info.format;
    bool linear = f0 == VK_FORMAT_R16G16B16A16_SFLOAT || f0 == VK_FORMAT_R32G32B32A32_SFLOAT;
    if (s->instance->cfg.exposure <= 0.0f && linear && out_eyes[0].w == out_eyes[1].w &&
        out_eyes[0].h == out_eyes[1].h) {
        const float *const rgba[2] = {out_eyes[0].rgba, out_eyes[1].rgba};
        hs_tonemap tm = {.exposure = hs_autoexposure_update(&s->autoexp, rgba, 2,
                                                            out_eyes[0].w, out_eyes[0].h)};
        for (int v = 0; v < 2; v++)
            hs_tonemap_rgba(&tm, out_eyes[v].rgba, out_eyes[v].w, out_eyes[v].h, out_eyes[v].rgb);
    }
    return XR_SUCCESS;
}

/* ---- lookup ---- */

PFN_xrVoidFunction hsrt_vulkan_proc(const char *name, int *out_ext)
{
    static const struct {
        const char *name;
        PFN_xrVoidFunction fn;
        int ext;
    } procs[] = {
#define HSRT_X_PROC0(n) {"xr" #n, (PFN_xrVoidFunction)hsrt_xr##n, 0},
#define HSRT_X_PROC1(n) {"xr" #n, (PFN_xrVoidFunction)hsrt_xr##n, 1},
#define HSRT_X_PROC2(n) {"xr" #n, (PFN_xrVoidFunction)hsrt_xr##n, 2},
        HSRT_SWAPCHAIN_FUNCS(HSRT_X_PROC0) HSRT_VULKAN_FUNCS(HSRT_X_PROC1)
            HSRT_VULKAN2_FUNCS(HSRT_X_PROC2)
#undef HSRT_X_PROC0
#undef HSRT_X_PROC1
#undef HSRT_X_PROC2
    };
    for (size_t i = 0; i < sizeof(procs) / sizeof(procs[0]); i++) {
        if (!strcmp(procs[i].name, name)) {
            *out_ext = procs[i].ext;
            return procs[i].fn;
        }
    }
    return NULL;
}
