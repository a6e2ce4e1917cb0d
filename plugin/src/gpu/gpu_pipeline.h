// SPDX-License-Identifier: MIT
/**
 * @file gpu_pipeline.h
 * @brief Descriptor sets described by binding tables, ray-tracing programs (pipeline + shader
 *        binding table + set 0) built from embedded SPIR-V, and compute programs.
 *
 * Callers describe bindings with ::gpu_binding (never VkDescriptorSetLayoutBinding).
 * Ray-tracing programs share one layout for descriptor set 0, the scene and frame bindings of
 * xrsc_shared.h (XS_BIND_*), given by ::gpu_rt_set0_bindings.
 *
 * Shader binding table (one record per group, no shader-record data):
 *   raygen region: 1 record (the program's .rgen);
 *   miss region:   record XS_MISS_INDEX_PRIMARY = primary.rmiss, XS_MISS_INDEX_SHADOW =
 *                  shadow.rmiss;
 *   hit region:    1 triangle hit group (closest hit hit.rchit, any-hit hit.rahit for glTF
 *                  alphaMode MASK / BLEND, run only for the non-opaque instances), so every
 *                  instance uses sbt offset 0 and traceRayEXT uses sbtRecordOffset 0,
 *                  sbtRecordStride 0 (or 1).
 * Regions start at shaderGroupBaseAlignment; strides are the handle size rounded to
 * shaderGroupHandleAlignment (raygen: to shaderGroupBaseAlignment, as its size must equal its
 * stride).
 */
#pragma once

#include "gpu_resource.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum gpu_binding_kind {
    GPU_BINDING_UNIFORM_BUFFER,
    GPU_BINDING_STORAGE_BUFFER,
    GPU_BINDING_STORAGE_IMAGE,
    GPU_BINDING_SAMPLED_IMAGES, /**< combined image samplers, array of `count`, partially bound */
    GPU_BINDING_ACCELERATION_STRUCTURE,
} gpu_binding_kind;

typedef struct gpu_binding {
    uint32_t binding;
    gpu_binding_kind kind;
    uint32_t count; /**< array size (0 means 1) */
} gpu_binding;

#define GPU_MAX_BINDINGS 48 /* hybrid's reconstruct program: set 0 + cache + moments + hash table */

/** One descriptor set layout, a pool sized for one set, and that set. */
typedef struct gpu_descriptors {
    VkDescriptorSetLayout layout;
    VkDescriptorPool pool;
    VkDescriptorSet set;
    gpu_binding bindings[GPU_MAX_BINDINGS];
    uint32_t binding_count;
} gpu_descriptors;

xrsc_result gpu_descriptors_create(gpu_context *ctx, const gpu_binding *bindings, uint32_t count,
                                   gpu_descriptors *out, xrsc_diag *diag);
void gpu_descriptors_destroy(gpu_context *ctx, gpu_descriptors *d);
/** Writes a whole buffer to a UNIFORM_BUFFER or STORAGE_BUFFER binding. */
void gpu_descriptors_write_buffer(gpu_context *ctx, gpu_descriptors *d, uint32_t binding,
                                  const gpu_buffer *buf);
/** Writes a storage image (layout GENERAL, all layers) to a STORAGE_IMAGE binding. */
void gpu_descriptors_write_storage_image(gpu_context *ctx, gpu_descriptors *d, uint32_t binding,
                                         const gpu_image *img);
/** Writes textures[0..n) with samplers[0..n) to a COMBINED_IMAGE_SAMPLER array binding and
 *  `fill` with fill_sampler to the remaining elements. */
void gpu_descriptors_write_textures(gpu_context *ctx, gpu_descriptors *d, uint32_t binding,
                                    const gpu_image *textures, const VkSampler *samplers,
                                    uint32_t n, const gpu_image *fill, VkSampler fill_sampler);
void gpu_descriptors_write_tlas(gpu_context *ctx, gpu_descriptors *d, uint32_t binding,
                                VkAccelerationStructureKHR tlas);

/** The bindings of set 0 (XS_BIND_TLAS .. XS_BIND_RAY_COUNTER); count in *out_count. */
const gpu_binding *gpu_rt_set0_bindings(uint32_t *out_count);

/**
 * A ray-tracing program. raygen: embedded shader name, e.g. "primary.rgen" (or raygen_spirv).
 * set1/set1_count:
 * optional method-specific descriptor set 1. push_constant_size: bytes (0 = none), visible to
 * all ray-tracing stages.
 */
typedef struct gpu_rt_program_desc {
    const char *raygen;
    /** Optional: SPIR-V of the raygen shader used instead of the embedded `raygen` (tests with
     *  their own raygen and the library's miss/hit shaders); size in bytes. */
    const uint32_t *raygen_spirv;
    size_t raygen_spirv_size;
    const gpu_binding *set1;
    uint32_t set1_count;
    uint32_t push_constant_size;
    /** The scene has smooth thin glass (XS_CULL_GLASS instances): the raygen's specialization
     *  constant XS_SPEC_GLASS_ID. Without it the driver compiles no glass walk into shadow
     *  rays (xs_path.glsl), which halves lavapipe's cold compile of the shading pipelines. */
    bool glass;
    /** The visibility cache is on (sc_shade.rgen's specialization constant
     *  XS_SPEC_VISCACHE_ID; other raygens have none). Off, its lookups are not compiled. */
    bool viscache;
} gpu_rt_program_desc;

typedef struct gpu_rt_program {
    gpu_descriptors set0, set1;
    VkPipelineLayout layout;
    /** The context's pipeline for this program's shaders and specialization (shared with
     *  every program of the same ones, see gpu_context::rt_pipelines), or, for a test's own
     *  raygen (raygen_spirv), one of its own (owns_pipeline). */
    VkPipeline pipeline;
    bool owns_pipeline;
    gpu_buffer sbt;
    VkStridedDeviceAddressRegionKHR rgen, miss, hit, call;
    uint32_t push_constant_size;
} gpu_rt_program;

xrsc_result gpu_rt_program_create(gpu_context *ctx, const gpu_rt_program_desc *desc,
                                  gpu_rt_program *out, xrsc_diag *diag);
void gpu_rt_program_destroy(gpu_context *ctx, gpu_rt_program *prog);
/** Destroys the ray-tracing pipelines the context keeps (gpu_context_destroy calls it). */
void gpu_rt_pipelines_destroy(gpu_context *ctx);
/** Binds the pipeline and sets, pushes constants (may be NULL) and traces w x h x d rays. */
void gpu_rt_program_cmd_trace(gpu_context *ctx, VkCommandBuffer cmd, const gpu_rt_program *prog,
                              const void *push, uint32_t width, uint32_t height, uint32_t depth);

/** A compute program: one shader (embedded name, e.g. "reproject.comp"), set 0 from bindings,
 *  push constants of push_constant_size bytes. */
typedef struct gpu_compute_program {
    gpu_descriptors set0;
    VkPipelineLayout layout;
    VkPipeline pipeline;
    uint32_t push_constant_size;
} gpu_compute_program;

xrsc_result gpu_compute_program_create(gpu_context *ctx, const char *shader,
                                       const gpu_binding *bindings, uint32_t binding_count,
                                       uint32_t push_constant_size, gpu_compute_program *out,
                                       xrsc_diag *diag);
void gpu_compute_program_destroy(gpu_context *ctx, gpu_compute_program *prog);
void gpu_compute_program_cmd_dispatch(VkCommandBuffer cmd, const gpu_compute_program *prog,
                                      const void *push, uint32_t gx, uint32_t gy, uint32_t gz);

/** Creates a shader module from the embedded SPIR-V `name` (XRSC_ERROR_SHADER if absent). */
xrsc_result gpu_shader_module_create(gpu_context *ctx, const char *name, VkShaderModule *out,
                                     xrsc_diag *diag);

#ifdef __cplusplus
}
#endif
