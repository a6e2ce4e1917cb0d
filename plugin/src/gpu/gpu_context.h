// SPDX-License-Identifier: MIT
/**
 * @file gpu_context.h
 * @brief The Vulkan bundle: instance, device, queue, loaded extension functions, validation.
 *
 * Every Vulkan handle the gpu layer shares and every extension function it loads live in
 * ::gpu_context; the rest of the gpu layer takes a `gpu_context *`. Other layers never call
 * Vulkan object-creation functions: they go through gpu_* helpers.
 */
#pragma once

#include "xrsc/result.h"

#include <stdbool.h>
#include <stdint.h>
#include <vulkan/vulkan.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Extension functions, loaded with vkGetInstanceProcAddr / vkGetDeviceProcAddr. */
typedef struct gpu_vk_functions {
    PFN_vkCreateDebugUtilsMessengerEXT CreateDebugUtilsMessengerEXT;
    PFN_vkDestroyDebugUtilsMessengerEXT DestroyDebugUtilsMessengerEXT;
    PFN_vkCreateAccelerationStructureKHR CreateAccelerationStructureKHR;
    PFN_vkDestroyAccelerationStructureKHR DestroyAccelerationStructureKHR;
    PFN_vkGetAccelerationStructureBuildSizesKHR GetAccelerationStructureBuildSizesKHR;
    PFN_vkGetAccelerationStructureDeviceAddressKHR GetAccelerationStructureDeviceAddressKHR;
    PFN_vkCmdBuildAccelerationStructuresKHR CmdBuildAccelerationStructuresKHR;
    PFN_vkCreateRayTracingPipelinesKHR CreateRayTracingPipelinesKHR;
    PFN_vkGetRayTracingShaderGroupHandlesKHR GetRayTracingShaderGroupHandlesKHR;
    PFN_vkCmdTraceRaysKHR CmdTraceRaysKHR;
} gpu_vk_functions;

typedef struct gpu_context {
    VkInstance instance;
    VkDebugUtilsMessengerEXT messenger;
    VkPhysicalDevice physical_device;
    VkDevice device;
    VkQueue queue;
    uint32_t queue_family;
    VkCommandPool command_pool;
    VkFence fence; /**< for one-shot submissions */
    gpu_vk_functions vk;

    VkPhysicalDeviceProperties properties;
    VkPhysicalDeviceMemoryProperties memory_properties;
    VkPhysicalDeviceRayTracingPipelinePropertiesKHR rt_properties;
    VkPhysicalDeviceAccelerationStructurePropertiesKHR as_properties;
    uint32_t timestamp_valid_bits; /**< of the queue family; 0 = no timestamps */
    bool is_cpu;
    bool validation;
    bool atomic_float; /**< VK_EXT_shader_atomic_float enabled (buffer/image float32 add) */
    uint32_t validation_errors; /**< ERROR-severity validation messages seen */
    uint32_t device_index;      /**< physical-device index chosen */
    uint64_t submit_count;      /**< vkQueueSubmit calls so far (the only one is in
                                 *   gpu_cmd_submit_wait); tests count submissions per frame */
    /** Ray-tracing pipelines made so far, one per raygen, specialization and layout, shared by
     *  every gpu_rt_program that asks for the same one (gpu_pipeline.c) and destroyed with the
     *  context. lavapipe numbers each new pipeline's shader groups from a device-wide counter
     *  and compiles the numbers into the pipeline's code, so a second pipeline of the same
     *  shaders is another LLVM compile (20-30 s of CPU each for `spp` or the sample cache's
     *  shading) that no shader cache serves; a renderer made after another of the same
     *  method now reuses its pipelines (issue 22). */
    struct gpu_rt_pipeline_entry *rt_pipelines;
    uint32_t rt_pipeline_count;
} gpu_context;

/**
 * Context options. device: NULL/"" uses XRSC_DEVICE, else the first non-CPU device with ray
 * tracing, else lavapipe. "cpu", "gpu", a physical-device index or a name substring
 * (case-insensitive) select explicitly. validation: VK_LAYER_KHRONOS_validation on, with
 * synchronization validation (VkValidationFeaturesEXT) when the layer offers it (also when
 * XRSC_VALIDATION=1).
 */
typedef struct gpu_context_options {
    const char *device;
    bool validation;
} gpu_context_options;

/**
 * Creation through someone else's Vulkan creation functions: an OpenXR runtime's
 * XR_KHR_vulkan_enable2 (xrCreateVulkanInstanceKHR, xrGetVulkanGraphicsDevice2KHR,
 * xrCreateVulkanDeviceKHR) wraps vkCreateInstance / vkCreateDevice, adding what it needs.
 * The gpu layer still builds every create-info (layers, extensions, features, queues) and
 * owns the objects it gets back (gpu_context_destroy destroys them); the hooks only forward
 * the calls. Each hook returns the VkResult of the wrapped call, or a Vulkan error code when
 * the wrapper itself failed (it logs why).
 */
typedef struct gpu_context_hooks {
    void *user;
    VkResult (*create_instance)(void *user, const VkInstanceCreateInfo *info,
                                VkInstance *out_instance);
    /** The physical device the wrapper requires (it is not chosen by the gpu layer). */
    VkResult (*physical_device)(void *user, VkInstance instance,
                                VkPhysicalDevice *out_physical_device);
    VkResult (*create_device)(void *user, VkPhysicalDevice physical_device,
                              const VkDeviceCreateInfo *info, VkDevice *out_device);
} gpu_context_hooks;

/**
 * Creates the instance and device. Errors: XRSC_ERROR_DEVICE_NOT_FOUND (selector matches no
 * device), XRSC_ERROR_NO_RAY_TRACING_DEVICE (message names what each device lacks),
 * XRSC_ERROR_VULKAN.
 */
xrsc_result gpu_context_create(const gpu_context_options *options, gpu_context **out,
                               xrsc_diag *diag);
/**
 * As gpu_context_create, with the instance and device created through hooks (see
 * ::gpu_context_hooks); the hooks' device is used. A selector (options->device, else
 * XRSC_DEVICE) is checked first against the hooked instance's devices, with
 * gpu_context_create's errors (XRSC_ERROR_DEVICE_NOT_FOUND naming it when it matches none),
 * and the hooks' device must match it (else XRSC_ERROR_DEVICE_NOT_FOUND naming both). A
 * device that lacks what xrsc needs is XRSC_ERROR_NO_RAY_TRACING_DEVICE. The queue family
 * prefers one with graphics and compute (a compositor's queue), else compute.
 */
xrsc_result gpu_context_create_hooked(const gpu_context_options *options,
                                      const gpu_context_hooks *hooks, gpu_context **out,
                                      xrsc_diag *diag);
/** Waits for the device to go idle and destroys everything; accepts NULL, sets *ctx NULL. */
void gpu_context_destroy(gpu_context **ctx);

/** "VK_ERROR_OUT_OF_DEVICE_MEMORY" etc. */
const char *gpu_vk_result_name(VkResult r);

/** Logs a failed Vulkan call with its name, VkResult and the caller's file/line; fills diag
 *  with XRSC_ERROR_VULKAN and returns it. */
xrsc_result gpu_vk_error(xrsc_diag *diag, VkResult r, const char *call, const char *file,
                         int line);

/** Runs `call`; on failure logs it (call text, VkResult name, file, line), fills diag and
 *  jumps to `label` with `res` = XRSC_ERROR_VULKAN. */
#define GPU_CHECK(res, diag, label, call)                                                          \
    do {                                                                                           \
        VkResult gpu_check_r_ = (call);                                                            \
        if (gpu_check_r_ != VK_SUCCESS) {                                                          \
            (res) = gpu_vk_error((diag), gpu_check_r_, #call, __FILE__, __LINE__);                 \
            goto label;                                                                            \
        }                                                                                          \
    } while (0)

/** Index of a memory type with all `flags` among `type_bits`, or UINT32_MAX. */
uint32_t gpu_find_memory_type(const gpu_context *ctx, uint32_t type_bits,
                              VkMemoryPropertyFlags flags);

/** Begins a one-shot primary command buffer from the context's pool. */
xrsc_result gpu_cmd_begin(gpu_context *ctx, VkCommandBuffer *out_cmd, xrsc_diag *diag);
/** Ends, submits and waits for cmd, then frees it (also on failure). */
xrsc_result gpu_cmd_submit_wait(gpu_context *ctx, VkCommandBuffer cmd, xrsc_diag *diag);
/** A full memory barrier between everything before and after (simple and correct). */
void gpu_cmd_barrier_all(VkCommandBuffer cmd);

#ifdef __cplusplus
}
#endif
