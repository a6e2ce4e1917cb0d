// SPDX-License-Identifier: MIT
/**
 * @file gpu_pipeline.c
 * @brief Descriptor sets, ray-tracing pipelines with their shader binding table, compute
 *        pipelines.
 */
#include "gpu_pipeline.h"

#include "u_diag.h"
#include "xrsc_shared.h"
#include "xs_spirv.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* Seconds of one clock (CLOCK_MONOTONIC or CLOCK_PROCESS_CPUTIME_ID). */
static double clock_s(clockid_t id)
{
    struct timespec ts;
    clock_gettime(id, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* XRSC_LOG=debug: each pipeline made, which variant, and what its creation cost, to see what a
 * test or a run compiles (issue 22). On lavapipe creation only translates to NIR; LLVM compiles
 * the pipeline at its first dispatch (tens of seconds for a ray-tracing pipeline on a cold
 * shader cache), which then shows in that frame's time. */
static void log_pipeline(const char *kind, const char *shader, const char *variant, double wall0,
                         double cpu0)
{
    U_LOG_D("pipeline %s %s%s: %.2f s wall, %.2f s CPU", kind, shader, variant,
            clock_s(CLOCK_MONOTONIC) - wall0, clock_s(CLOCK_PROCESS_CPUTIME_ID) - cpu0);
}

_Static_assert(XS_MISS_INDEX_PRIMARY == 0 && XS_MISS_INDEX_SHADOW == 1,
               "miss records are laid out in this order");

static VkDescriptorType descriptor_type(gpu_binding_kind k)
{
    switch (k) {
    case GPU_BINDING_UNIFORM_BUFFER:
        return VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
    case GPU_BINDING_STORAGE_BUFFER:
        return VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    case GPU_BINDING_STORAGE_IMAGE:
        return VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
    case GPU_BINDING_SAMPLED_IMAGES:
        return VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    case GPU_BINDING_ACCELERATION_STRUCTURE:
        return VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR;
    }
    return VK_DESCRIPTOR_TYPE_MAX_ENUM;
}

xrsc_result gpu_descriptors_create(gpu_context *ctx, const gpu_binding *bindings, uint32_t count,
                                   gpu_descriptors *out, xrsc_diag *diag)
{
    xrsc_result res = XRSC_OK;
    memset(out, 0, sizeof(*out));
    if (count > GPU_MAX_BINDINGS)
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "bindings",
                          "%u bindings > %u", count, GPU_MAX_BINDINGS);
    VkDescriptorSetLayoutBinding lb[GPU_MAX_BINDINGS];
    VkDescriptorBindingFlags flags[GPU_MAX_BINDINGS];
    VkDescriptorPoolSize sizes[GPU_MAX_BINDINGS];
    uint32_t size_count = 0;
    for (uint32_t i = 0; i < count; i++) {
        out->bindings[i] = bindings[i];
        if (out->bindings[i].count == 0)
            out->bindings[i].count = 1;
        VkDescriptorType type = descriptor_type(bindings[i].kind);
        lb[i] = (VkDescriptorSetLayoutBinding){
            .binding = bindings[i].binding,
            .descriptorType = type,
            .descriptorCount = out->bindings[i].count,
            .stageFlags = VK_SHADER_STAGE_ALL,
        };
        flags[i] = bindings[i].kind == GPU_BINDING_SAMPLED_IMAGES
                       ? VK_DESCRIPTOR_BINDING_PARTIALLY_BOUND_BIT
                       : 0;
        uint32_t s = 0;
        while (s < size_count && sizes[s].type != type)
            s++;
        if (s == size_count)
            sizes[size_count++] = (VkDescriptorPoolSize){type, 0};
        sizes[s].descriptorCount += out->bindings[i].count;
    }
    out->binding_count = count;
    VkDescriptorSetLayoutBindingFlagsCreateInfo fci = {
        .sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_BINDING_FLAGS_CREATE_INFO,
        .bindingCount = count,
        .pBindingFlags = flags,
    };
    VkDescriptorSetLayoutCreateInfo lci = {
        .sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO,
        .pNext = &fci,
        .bindingCount = count,
        .pBindings = lb,
    };
    GPU_CHECK(res, diag, fail, vkCreateDescriptorSetLayout(ctx->device, &lci, NULL, &out->layout));
    VkDescriptorPoolCreateInfo pci = {
        .sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO,
        .maxSets = 1,
        .poolSizeCount = size_count,
        .pPoolSizes = sizes,
    };
    GPU_CHECK(res, diag, fail, vkCreateDescriptorPool(ctx->device, &pci, NULL, &out->pool));
    VkDescriptorSetAllocateInfo ai = {
        .sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO,
        .descriptorPool = out->pool,
        .descriptorSetCount = 1,
        .pSetLayouts = &out->layout,
    };
    GPU_CHECK(res, diag, fail, vkAllocateDescriptorSets(ctx->device, &ai, &out->set));
    return XRSC_OK;
fail:
    gpu_descriptors_destroy(ctx, out);
    return res;
}

void gpu_descriptors_destroy(gpu_context *ctx, gpu_descriptors *d)
{
    if (!d)
        return;
    if (d->pool)
        vkDestroyDescriptorPool(ctx->device, d->pool, NULL); /* frees the set */
    if (d->layout)
        vkDestroyDescriptorSetLayout(ctx->device, d->layout, NULL);
    memset(d, 0, sizeof(*d));
}

static const gpu_binding *find_binding(const gpu_descriptors *d, uint32_t binding)
{
    for (uint32_t i = 0; i < d->binding_count; i++)
        if (d->bindings[i].binding == binding)
            return &d->bindings[i];
    U_LOG_E("descriptor binding %u is not in the set layout", binding);
    return NULL;
}

void gpu_descriptors_write_buffer(gpu_context *ctx, gpu_descriptors *d, uint32_t binding,
                                  const gpu_buffer *buf)
{
    const gpu_binding *b = find_binding(d, binding);
    if (!b)
        return;
    VkDescriptorBufferInfo bi = {.buffer = buf->buffer, .offset = 0, .range = VK_WHOLE_SIZE};
    VkWriteDescriptorSet w = {
        .sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET,
        .dstSet = d->set,
        .dstBinding = binding,
        .descriptorCount = 1,
        .descriptorType = descriptor_type(b->kind),
        .pBufferInfo = &bi,
    };
    vkUpdateDescriptorSets(ctx->device, 1, &w, 0, NULL);
}

void gpu_descriptors_write_storage_image(gpu_context *ctx, gpu_descriptors *d, uint32_t binding,
                                         const gpu_image *img)
{
    if (!find_binding(d, binding))
        return;
    VkDescriptorImageInfo ii = {.imageView = img->view, .imageLayout = VK_IMAGE_LAYOUT_GENERAL};
    VkWriteDescriptorSet w = {
        .sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET,
        .dstSet = d->set,
        .dstBinding = binding,
        .descriptorCount = 1,
        .descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
        .pImageInfo = &ii,
    };
    vkUpdateDescriptorSets(ctx->device, 1, &w, 0, NULL);
}

void gpu_descriptors_write_textures(gpu_context *ctx, gpu_descriptors *d, uint32_t binding,
                                    const gpu_image *textures, const VkSampler *samplers,
                                    uint32_t n, const gpu_image *fill, VkSampler fill_sampler)
{
    const gpu_binding *b = find_binding(d, binding);
    if (!b)
        return;
    VkDescriptorImageInfo *ii = calloc(b->count, sizeof(*ii));
    if (!ii)
        return;
    for (uint32_t i = 0; i < b->count; i++) {
        const gpu_image *img = i < n ? &textures[i] : fill;
        ii[i] = (VkDescriptorImageInfo){.sampler = i < n ? samplers[i] : fill_sampler,
                                        .imageView = img->view,
                                        .imageLayout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
    }
    VkWriteDescriptorSet w = {
        .sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET,
        .dstSet = d->set,
        .dstBinding = binding,
        .descriptorCount = b->count,
        .descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
        .pImageInfo = ii,
    };
    vkUpdateDescriptorSets(ctx->device, 1, &w, 0, NULL);
    free(ii);
}

void gpu_descriptors_write_tlas(gpu_context *ctx, gpu_descriptors *d, uint32_t binding,
                                VkAccelerationStructureKHR tlas)
{
    if (!find_binding(d, binding))
        return;
    VkWriteDescriptorSetAccelerationStructureKHR as = {
        .sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET_ACCELERATION_STRUCTURE_KHR,
        .accelerationStructureCount = 1,
        .pAccelerationStructures = &tlas,
    };
    VkWriteDescriptorSet w = {
        .sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET,
        .pNext = &as,
        .dstSet = d->set,
        .dstBinding = binding,
        .descriptorCount = 1,
        .descriptorType = VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR,
    };
    vkUpdateDescriptorSets(ctx->device, 1, &w, 0, NULL);
}

static const gpu_binding set0_bindings[] = {
    {XS_BIND_TLAS, GPU_BINDING_ACCELERATION_STRUCTURE, 1},
    {XS_BIND_FRAME, GPU_BINDING_UNIFORM_BUFFER, 1},
    {XS_BIND_VERTICES, GPU_BINDING_STORAGE_BUFFER, 1},
    {XS_BIND_INDICES, GPU_BINDING_STORAGE_BUFFER, 1},
    {XS_BIND_INSTANCES, GPU_BINDING_STORAGE_BUFFER, 1},
    {XS_BIND_MATERIALS, GPU_BINDING_STORAGE_BUFFER, 1},
    {XS_BIND_EMITTERS, GPU_BINDING_STORAGE_BUFFER, 1},
    {XS_BIND_TEXTURES, GPU_BINDING_SAMPLED_IMAGES, XS_MAX_TEXTURES},
    {XS_BIND_OUT_COLOR, GPU_BINDING_STORAGE_IMAGE, 1},
    {XS_BIND_OUT_ALBEDO, GPU_BINDING_STORAGE_IMAGE, 1},
    {XS_BIND_OUT_DEPTH, GPU_BINDING_STORAGE_IMAGE, 1},
    {XS_BIND_OUT_HITID, GPU_BINDING_STORAGE_IMAGE, 1},
    {XS_BIND_ACCUM, GPU_BINDING_STORAGE_IMAGE, 1},
    {XS_BIND_RAY_COUNTER, GPU_BINDING_STORAGE_BUFFER, 1},
    {XS_BIND_ENV_MAP, GPU_BINDING_STORAGE_BUFFER, 1},
    {XS_BIND_LIGHTS, GPU_BINDING_STORAGE_BUFFER, 1},
};

const gpu_binding *gpu_rt_set0_bindings(uint32_t *out_count)
{
    *out_count = sizeof(set0_bindings) / sizeof(set0_bindings[0]);
    return set0_bindings;
}

xrsc_result gpu_shader_module_create(gpu_context *ctx, const char *name, VkShaderModule *out,
                                     xrsc_diag *diag)
{
    xrsc_result res = XRSC_OK;
    *out = VK_NULL_HANDLE;
    size_t size = 0;
    const uint32_t *code = xs_spirv_find(name, &size);
    if (!code || size == 0)
        return u_diag_set(diag, XRSC_ERROR_SHADER, name, 0, "shader",
                          "no embedded SPIR-V module named %s", name);
    VkShaderModuleCreateInfo ci = {
        .sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO,
        .codeSize = size,
        .pCode = code,
    };
    GPU_CHECK(res, diag, fail, vkCreateShaderModule(ctx->device, &ci, NULL, out));
fail:
    return res;
}

static VkDeviceSize align_up(VkDeviceSize v, VkDeviceSize a) { return (v + a - 1) / a * a; }

static xrsc_result create_layout(gpu_context *ctx, const VkDescriptorSetLayout *sets,
                                 uint32_t set_count, uint32_t push_size, VkShaderStageFlags stages,
                                 VkPipelineLayout *out, xrsc_diag *diag)
{
    xrsc_result res = XRSC_OK;
    VkPushConstantRange pcr = {.stageFlags = stages, .offset = 0, .size = push_size};
    VkPipelineLayoutCreateInfo plci = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO,
        .setLayoutCount = set_count,
        .pSetLayouts = sets,
        .pushConstantRangeCount = push_size ? 1 : 0,
        .pPushConstantRanges = push_size ? &pcr : NULL,
    };
    GPU_CHECK(res, diag, fail, vkCreatePipelineLayout(ctx->device, &plci, NULL, out));
fail:
    return res;
}

#define GPU_RT_STAGES                                                                              \
    (VK_SHADER_STAGE_RAYGEN_BIT_KHR | VK_SHADER_STAGE_MISS_BIT_KHR |                               \
     VK_SHADER_STAGE_CLOSEST_HIT_BIT_KHR | VK_SHADER_STAGE_ANY_HIT_BIT_KHR)

/* Shader stages and groups of every ray-tracing program, in SBT order. */
enum { STAGE_RGEN, STAGE_MISS_PRIMARY, STAGE_MISS_SHADOW, STAGE_CHIT, STAGE_AHIT, STAGE_COUNT };
enum { GROUP_RGEN, GROUP_MISS_PRIMARY, GROUP_MISS_SHADOW, GROUP_HIT, GROUP_COUNT };

static xrsc_result create_sbt(gpu_context *ctx, gpu_rt_program *p, xrsc_diag *diag)
{
    xrsc_result res = XRSC_OK;
    const VkPhysicalDeviceRayTracingPipelinePropertiesKHR *rp = &ctx->rt_properties;
    VkDeviceSize hs = rp->shaderGroupHandleSize;
    VkDeviceSize ha = rp->shaderGroupHandleAlignment ? rp->shaderGroupHandleAlignment : 1;
    VkDeviceSize ba = rp->shaderGroupBaseAlignment ? rp->shaderGroupBaseAlignment : 1;
    VkDeviceSize rstride = align_up(hs, ba);
    VkDeviceSize stride = align_up(hs, ha);
    VkDeviceSize rgen_size = rstride;
    VkDeviceSize miss_size = align_up(2 * stride, ba);
    VkDeviceSize hit_size = align_up(stride, ba);
    VkDeviceSize total = rgen_size + miss_size + hit_size;

    uint8_t *handles = malloc(GROUP_COUNT * hs);
    uint8_t *table = calloc(1, total);
    if (!handles || !table) {
        res = u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, "", 0, "", "out of memory");
        goto done;
    }
    GPU_CHECK(res, diag, done,
              ctx->vk.GetRayTracingShaderGroupHandlesKHR(ctx->device, p->pipeline, 0, GROUP_COUNT,
                                                         GROUP_COUNT * hs, handles));
    memcpy(table, handles + GROUP_RGEN * hs, hs);
    memcpy(table + rgen_size + XS_MISS_INDEX_PRIMARY * stride, handles + GROUP_MISS_PRIMARY * hs,
           hs);
    memcpy(table + rgen_size + XS_MISS_INDEX_SHADOW * stride, handles + GROUP_MISS_SHADOW * hs,
           hs);
    memcpy(table + rgen_size + miss_size, handles + GROUP_HIT * hs, hs);

    /* Allocate `ba` extra bytes so the table can start at a base-aligned device address. */
    res = gpu_buffer_create(ctx, total + ba,
                            VK_BUFFER_USAGE_SHADER_BINDING_TABLE_BIT_KHR |
                                VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT |
                                VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                            GPU_MEMORY_DEVICE, &p->sbt, diag);
    if (res != XRSC_OK)
        goto done;
    VkDeviceAddress base = align_up(p->sbt.address, ba);
    res = gpu_buffer_upload(ctx, &p->sbt, base - p->sbt.address, table, total, diag);
    if (res != XRSC_OK)
        goto done;
    p->rgen = (VkStridedDeviceAddressRegionKHR){base, rstride, rgen_size};
    p->miss = (VkStridedDeviceAddressRegionKHR){base + rgen_size, stride, miss_size};
    p->hit = (VkStridedDeviceAddressRegionKHR){base + rgen_size + miss_size, stride, hit_size};
    p->call = (VkStridedDeviceAddressRegionKHR){0, 0, 0};
done:
    free(handles);
    free(table);
    return res;
}

/* The raygen's specialization constants: XS_SPEC_GLASS_ID, XS_SPEC_VISCACHE_ID. */
typedef struct rt_spec {
    VkBool32 data[2];
    VkSpecializationMapEntry entries[2];
    VkSpecializationInfo info;
} rt_spec;

static void rt_spec_init(const gpu_rt_program_desc *desc, rt_spec *s)
{
    s->data[0] = desc->glass ? VK_TRUE : VK_FALSE;
    s->data[1] = desc->viscache ? VK_TRUE : VK_FALSE;
    s->entries[0] = (VkSpecializationMapEntry){XS_SPEC_GLASS_ID, 0, sizeof(VkBool32)};
    s->entries[1] =
        (VkSpecializationMapEntry){XS_SPEC_VISCACHE_ID, sizeof(VkBool32), sizeof(VkBool32)};
    s->info = (VkSpecializationInfo){2, s->entries, sizeof(s->data), s->data};
}

/* The shader modules of desc's stages (raygen, both misses, closest and any hit). */
static xrsc_result rt_modules_create(gpu_context *ctx, const gpu_rt_program_desc *desc,
                                     VkShaderModule modules[STAGE_COUNT], xrsc_diag *diag)
{
    xrsc_result res = XRSC_OK;
    const char *names[STAGE_COUNT] = {desc->raygen, "primary.rmiss", "shadow.rmiss", "hit.rchit",
                                      "hit.rahit"};
    for (int i = 0; i < STAGE_COUNT; i++) {
        if (i == STAGE_RGEN && desc->raygen_spirv) {
            VkShaderModuleCreateInfo ci = {
                .sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO,
                .codeSize = desc->raygen_spirv_size,
                .pCode = desc->raygen_spirv,
            };
            GPU_CHECK(res, diag, done, vkCreateShaderModule(ctx->device, &ci, NULL, &modules[i]));
        } else if ((res = gpu_shader_module_create(ctx, names[i], &modules[i], diag)) !=
                   XRSC_OK) {
            return res;
        }
    }
done:
    return res;
}

/* A new ray-tracing pipeline of desc's shaders with the given layout. */
static xrsc_result rt_pipeline_create(gpu_context *ctx, const gpu_rt_program_desc *desc,
                                      VkPipelineLayout layout, VkPipeline *out, xrsc_diag *diag)
{
    static const VkShaderStageFlagBits stage_bits[STAGE_COUNT] = {
        VK_SHADER_STAGE_RAYGEN_BIT_KHR, VK_SHADER_STAGE_MISS_BIT_KHR,
        VK_SHADER_STAGE_MISS_BIT_KHR, VK_SHADER_STAGE_CLOSEST_HIT_BIT_KHR,
        VK_SHADER_STAGE_ANY_HIT_BIT_KHR};
    VkShaderModule modules[STAGE_COUNT] = {0};
    xrsc_result res = rt_modules_create(ctx, desc, modules, diag);
    if (res != XRSC_OK)
        goto done;
    rt_spec spec;
    rt_spec_init(desc, &spec);
    VkPipelineShaderStageCreateInfo stages[STAGE_COUNT];
    for (int i = 0; i < STAGE_COUNT; i++)
        stages[i] = (VkPipelineShaderStageCreateInfo){
            .sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO,
            .stage = stage_bits[i],
            .module = modules[i],
            .pName = "main",
            .pSpecializationInfo = i == STAGE_RGEN ? &spec.info : NULL,
        };
    VkRayTracingShaderGroupCreateInfoKHR groups[GROUP_COUNT];
    for (int g = 0; g < GROUP_COUNT; g++)
        groups[g] = (VkRayTracingShaderGroupCreateInfoKHR){
            .sType = VK_STRUCTURE_TYPE_RAY_TRACING_SHADER_GROUP_CREATE_INFO_KHR,
            .type = VK_RAY_TRACING_SHADER_GROUP_TYPE_GENERAL_KHR,
            .generalShader = VK_SHADER_UNUSED_KHR,
            .closestHitShader = VK_SHADER_UNUSED_KHR,
            .anyHitShader = VK_SHADER_UNUSED_KHR,
            .intersectionShader = VK_SHADER_UNUSED_KHR,
        };
    groups[GROUP_RGEN].generalShader = STAGE_RGEN;
    groups[GROUP_MISS_PRIMARY].generalShader = STAGE_MISS_PRIMARY;
    groups[GROUP_MISS_SHADOW].generalShader = STAGE_MISS_SHADOW;
    groups[GROUP_HIT].type = VK_RAY_TRACING_SHADER_GROUP_TYPE_TRIANGLES_HIT_GROUP_KHR;
    groups[GROUP_HIT].closestHitShader = STAGE_CHIT;
    /* alphaMode MASK / BLEND (hit.rahit): runs only for non-opaque instances (gpu_scene.c) */
    groups[GROUP_HIT].anyHitShader = STAGE_AHIT;
    VkRayTracingPipelineCreateInfoKHR pci = {
        .sType = VK_STRUCTURE_TYPE_RAY_TRACING_PIPELINE_CREATE_INFO_KHR,
        .stageCount = STAGE_COUNT,
        .pStages = stages,
        .groupCount = GROUP_COUNT,
        .pGroups = groups,
        .maxPipelineRayRecursionDepth = 1,
        .layout = layout,
    };
    double wall0 = clock_s(CLOCK_MONOTONIC), cpu0 = clock_s(CLOCK_PROCESS_CPUTIME_ID);
    GPU_CHECK(res, diag, done,
              ctx->vk.CreateRayTracingPipelinesKHR(ctx->device, VK_NULL_HANDLE, VK_NULL_HANDLE, 1,
                                                   &pci, NULL, out));
    static const char *const variants[4] = {"", " glass", " viscache", " glass viscache"};
    log_pipeline("rt", desc->raygen_spirv ? "(test raygen)" : desc->raygen,
                 variants[(desc->glass ? 1 : 0) + (desc->viscache ? 2 : 0)], wall0, cpu0);
done:
    for (int i = 0; i < STAGE_COUNT; i++)
        if (modules[i])
            vkDestroyShaderModule(ctx->device, modules[i], NULL);
    return res;
}

/* One ray-tracing pipeline the context keeps (see gpu_context::rt_pipelines): what it was
 * made of, and the pipeline. */
typedef struct gpu_rt_pipeline_entry {
    char raygen[64];
    bool glass, viscache;
    uint32_t push_constant_size;
    uint32_t set1_count;
    gpu_binding set1[GPU_MAX_BINDINGS];
    VkPipeline pipeline;
} gpu_rt_pipeline_entry;

static bool rt_entry_matches(const gpu_rt_pipeline_entry *e, const gpu_rt_program_desc *d)
{
    return !strcmp(e->raygen, d->raygen) && e->glass == d->glass && e->viscache == d->viscache &&
           e->push_constant_size == d->push_constant_size && e->set1_count == d->set1_count &&
           (d->set1_count == 0 || !memcmp(e->set1, d->set1, d->set1_count * sizeof(gpu_binding)));
}

/* The context's pipeline for desc (embedded raygens only), made with layout the first time it
 * is asked for. *out_owned: the caller owns the pipeline (a test's own raygen, not kept). */
static xrsc_result rt_pipeline_get(gpu_context *ctx, const gpu_rt_program_desc *desc,
                                   VkPipelineLayout layout, VkPipeline *out, bool *out_owned,
                                   xrsc_diag *diag)
{
    *out_owned = desc->raygen_spirv != NULL || desc->set1_count > GPU_MAX_BINDINGS ||
                 strlen(desc->raygen) >= sizeof(((gpu_rt_pipeline_entry *)0)->raygen);
    if (*out_owned)
        return rt_pipeline_create(ctx, desc, layout, out, diag);
    for (uint32_t i = 0; i < ctx->rt_pipeline_count; i++)
        if (rt_entry_matches(&ctx->rt_pipelines[i], desc)) {
            U_LOG_D("pipeline rt %s: the context's (glass %d, viscache %d)", desc->raygen,
                    desc->glass, desc->viscache);
            *out = ctx->rt_pipelines[i].pipeline;
            return XRSC_OK;
        }
    gpu_rt_pipeline_entry *grown = realloc(
        ctx->rt_pipelines, (ctx->rt_pipeline_count + 1) * sizeof(gpu_rt_pipeline_entry));
    if (!grown)
        return u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, "", 0, "", "out of memory");
    ctx->rt_pipelines = grown;
    gpu_rt_pipeline_entry *e = &grown[ctx->rt_pipeline_count];
    memset(e, 0, sizeof(*e));
    snprintf(e->raygen, sizeof(e->raygen), "%s", desc->raygen);
    e->glass = desc->glass, e->viscache = desc->viscache;
    e->push_constant_size = desc->push_constant_size;
    e->set1_count = desc->set1_count;
    if (desc->set1_count)
        memcpy(e->set1, desc->set1, desc->set1_count * sizeof(gpu_binding));
    xrsc_result res = rt_pipeline_create(ctx, desc, layout, &e->pipeline, diag);
    if (res != XRSC_OK)
        return res;
    ctx->rt_pipeline_count++;
    *out = e->pipeline;
    return XRSC_OK;
}

void gpu_rt_pipelines_destroy(gpu_context *ctx)
{
    for (uint32_t i = 0; i < ctx->rt_pipeline_count; i++)
        vkDestroyPipeline(ctx->device, ctx->rt_pipelines[i].pipeline, NULL);
    free(ctx->rt_pipelines);
    ctx->rt_pipelines = NULL;
    ctx->rt_pipeline_count = 0;
}

xrsc_result gpu_rt_program_create(gpu_context *ctx, const gpu_rt_program_desc *desc,
                                  gpu_rt_program *out, xrsc_diag *diag)
{
    xrsc_result res = XRSC_OK;
    memset(out, 0, sizeof(*out));
    uint32_t n0;
    const gpu_binding *b0 = gpu_rt_set0_bindings(&n0);
    res = gpu_descriptors_create(ctx, b0, n0, &out->set0, diag);
    if (res != XRSC_OK)
        goto fail;
    VkDescriptorSetLayout sets[2] = {out->set0.layout, VK_NULL_HANDLE};
    uint32_t set_count = 1;
    if (desc->set1_count) {
        res = gpu_descriptors_create(ctx, desc->set1, desc->set1_count, &out->set1, diag);
        if (res != XRSC_OK)
            goto fail;
        sets[set_count++] = out->set1.layout;
    }
    out->push_constant_size = desc->push_constant_size;
    res = create_layout(ctx, sets, set_count, desc->push_constant_size, GPU_RT_STAGES,
                        &out->layout, diag);
    if (res != XRSC_OK)
        goto fail;
    /* A kept pipeline was made with another program's layout: an identically defined one,
     * which Vulkan's pipeline layout compatibility lets this program's sets bind with. */
    res = rt_pipeline_get(ctx, desc, out->layout, &out->pipeline, &out->owns_pipeline, diag);
    if (res != XRSC_OK)
        goto fail;
    res = create_sbt(ctx, out, diag);
    if (res != XRSC_OK)
        goto fail;
    return XRSC_OK;
fail:
    gpu_rt_program_destroy(ctx, out);
    return res;
}

void gpu_rt_program_destroy(gpu_context *ctx, gpu_rt_program *prog)
{
    if (!prog)
        return;
    gpu_buffer_destroy(ctx, &prog->sbt);
    if (prog->pipeline && prog->owns_pipeline)
        vkDestroyPipeline(ctx->device, prog->pipeline, NULL);
    if (prog->layout)
        vkDestroyPipelineLayout(ctx->device, prog->layout, NULL);
    gpu_descriptors_destroy(ctx, &prog->set1);
    gpu_descriptors_destroy(ctx, &prog->set0);
    memset(prog, 0, sizeof(*prog));
}

void gpu_rt_program_cmd_trace(gpu_context *ctx, VkCommandBuffer cmd, const gpu_rt_program *prog,
                              const void *push, uint32_t width, uint32_t height, uint32_t depth)
{
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_RAY_TRACING_KHR, prog->pipeline);
    VkDescriptorSet sets[2] = {prog->set0.set, prog->set1.set};
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_RAY_TRACING_KHR, prog->layout, 0,
                            prog->set1.set ? 2 : 1, sets, 0, NULL);
    if (push && prog->push_constant_size)
        vkCmdPushConstants(cmd, prog->layout, GPU_RT_STAGES, 0, prog->push_constant_size, push);
    ctx->vk.CmdTraceRaysKHR(cmd, &prog->rgen, &prog->miss, &prog->hit, &prog->call, width, height,
                            depth);
}

xrsc_result gpu_compute_program_create(gpu_context *ctx, const char *shader,
                                       const gpu_binding *bindings, uint32_t binding_count,
                                       uint32_t push_constant_size, gpu_compute_program *out,
                                       xrsc_diag *diag)
{
    xrsc_result res = XRSC_OK;
    memset(out, 0, sizeof(*out));
    VkShaderModule module = VK_NULL_HANDLE;
    res = gpu_descriptors_create(ctx, bindings, binding_count, &out->set0, diag);
    if (res != XRSC_OK)
        goto fail;
    out->push_constant_size = push_constant_size;
    res = create_layout(ctx, &out->set0.layout, 1, push_constant_size,
                        VK_SHADER_STAGE_COMPUTE_BIT, &out->layout, diag);
    if (res != XRSC_OK)
        goto fail;
    res = gpu_shader_module_create(ctx, shader, &module, diag);
    if (res != XRSC_OK)
        goto fail;
    VkComputePipelineCreateInfo ci = {
        .sType = VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO,
        .stage =
            {
                .sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO,
                .stage = VK_SHADER_STAGE_COMPUTE_BIT,
                .module = module,
                .pName = "main",
            },
        .layout = out->layout,
    };
    double wall0 = clock_s(CLOCK_MONOTONIC), cpu0 = clock_s(CLOCK_PROCESS_CPUTIME_ID);
    GPU_CHECK(res, diag, fail,
              vkCreateComputePipelines(ctx->device, VK_NULL_HANDLE, 1, &ci, NULL, &out->pipeline));
    log_pipeline("compute", shader, "", wall0, cpu0);
    vkDestroyShaderModule(ctx->device, module, NULL);
    return XRSC_OK;
fail:
    if (module)
        vkDestroyShaderModule(ctx->device, module, NULL);
    gpu_compute_program_destroy(ctx, out);
    return res;
}

void gpu_compute_program_destroy(gpu_context *ctx, gpu_compute_program *prog)
{
    if (!prog)
        return;
    if (prog->pipeline)
        vkDestroyPipeline(ctx->device, prog->pipeline, NULL);
    if (prog->layout)
        vkDestroyPipelineLayout(ctx->device, prog->layout, NULL);
    gpu_descriptors_destroy(ctx, &prog->set0);
    memset(prog, 0, sizeof(*prog));
}

void gpu_compute_program_cmd_dispatch(VkCommandBuffer cmd, const gpu_compute_program *prog,
                                      const void *push, uint32_t gx, uint32_t gy, uint32_t gz)
{
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, prog->pipeline);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, prog->layout, 0, 1,
                            &prog->set0.set, 0, NULL);
    if (push && prog->push_constant_size)
        vkCmdPushConstants(cmd, prog->layout, VK_SHADER_STAGE_COMPUTE_BIT, 0,
                           prog->push_constant_size, push);
    vkCmdDispatch(cmd, gx, gy, gz);
}
