// SPDX-License-Identifier: MIT
/**
 * @file xs_bindings.glsl
 * @brief Descriptor set 0 of every ray-tracing method, declared from xrsc_shared.h.
 *
 * Binding numbers and struct layouts come from xrsc_shared.h only (compiled with -DXRSC_GLSL).
 * Storage buffers use std430 and the frame uniform std140; both equal the C layouts checked by
 * the _Static_asserts there (every member is 4-byte scalar or 16-byte vector/matrix aligned).
 *
 * Device features this set needs on the C side: runtimeDescriptorArray and
 * shaderSampledImageArrayNonUniformIndexing (textures[]), shaderInt64 and
 * shaderBufferInt64Atomics (the ray counter), vulkanMemoryModel + vulkanMemoryModelDeviceScope
 * (glslang emits device-scope atomics).
 */
#ifndef XS_BINDINGS_GLSL
#define XS_BINDINGS_GLSL

/* Compute shaders define XS_NO_TLAS before including this file: the TLAS type needs a
 * ray-tracing capability there (spirv-val), and they trace nothing. */
#ifndef XS_NO_TLAS
#extension GL_EXT_ray_tracing : require
#endif
#extension GL_EXT_nonuniform_qualifier : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require

#include "xrsc_shared.h"

#ifndef XS_NO_TLAS
layout(set = 0, binding = XS_BIND_TLAS) uniform accelerationStructureEXT xs_tlas;

/* Ray flags. No ray forces opacity: the any-hit shader (hit.rahit, glTF alphaMode MASK /
 * BLEND) runs for the instances the TLAS marks non-opaque, and only for them. Camera rays (and
 * the sample cache's retraces of camera-ray hits) cull the back faces of single-sided
 * materials (glTF doubleSided = false), as glTF viewers do; bounce and shadow rays see both
 * sides (a single-sided wall still casts its shadow). */
#define XS_RAY_FLAGS_CAMERA gl_RayFlagsCullBackFacingTrianglesEXT
#define XS_RAY_FLAGS_BOUNCE gl_RayFlagsNoneEXT
#define XS_RAY_FLAGS_SHADOW (gl_RayFlagsTerminateOnFirstHitEXT | gl_RayFlagsSkipClosestHitShaderEXT)
#endif

layout(set = 0, binding = XS_BIND_FRAME, std140) uniform XsFrameBlock
{
    xs_frame frame;
};

layout(set = 0, binding = XS_BIND_VERTICES, std430) readonly buffer XsVertexBlock
{
    xs_vertex vertices[];
};

/* 3 entries per triangle, each an absolute index into vertices[] (the mesh's first vertex is
 * already added on the C side). */
layout(set = 0, binding = XS_BIND_INDICES, std430) readonly buffer XsIndexBlock
{
    uint indices[];
};

layout(set = 0, binding = XS_BIND_INSTANCES, std430) readonly buffer XsInstanceBlock
{
    xs_instance instances[];
};

layout(set = 0, binding = XS_BIND_MATERIALS, std430) readonly buffer XsMaterialBlock
{
    xs_material materials[];
};

layout(set = 0, binding = XS_BIND_EMITTERS, std430) readonly buffer XsEmitterBlock
{
    xs_emitter emitters[];
};

/* Runtime-sized and partially bound: only indices named by a material are ever read, always
 * through nonuniformEXT (neighbouring invocations hit different materials). */
layout(set = 0, binding = XS_BIND_TEXTURES) uniform sampler2D textures[];

layout(set = 0, binding = XS_BIND_OUT_COLOR, rgba32f) uniform writeonly image2DArray out_color;
layout(set = 0, binding = XS_BIND_OUT_ALBEDO, rgba32f) uniform writeonly image2DArray out_albedo;
layout(set = 0, binding = XS_BIND_OUT_DEPTH, r32f) uniform writeonly image2DArray out_depth;
layout(set = 0, binding = XS_BIND_OUT_HITID, rgba32ui) uniform writeonly uimage2DArray out_hitid;
layout(set = 0, binding = XS_BIND_ACCUM, rgba32f) uniform image2DArray accum;

/* The environment map and its sampling tables (XS_ENV_* layout of xrsc_shared.h). */
layout(set = 0, binding = XS_BIND_ENV_MAP, std430) readonly buffer XsEnvMapBlock
{
    float env_map[];
};

/* KHR_lights_punctual's lights besides the sun (xs_light of xrsc_shared.h, frame.light_count
 * entries; gpu_scene.h). */
layout(set = 0, binding = XS_BIND_LIGHTS, std430) readonly buffer XsLightBlock
{
    xs_light lights[];
};

/* One 64-bit counter of all rays traced (primary, bounce and shadow); one atomicAdd per pixel. */
layout(set = 0, binding = XS_BIND_RAY_COUNTER, std430) buffer XsRayCounterBlock
{
    uint64_t ray_count;
};

#endif
