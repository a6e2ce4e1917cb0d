// SPDX-License-Identifier: MIT
/**
 * @file gpu_scene.h
 * @brief A ::sc_scene on the GPU: the xrsc_shared.h buffers, textures, one BLAS per mesh and a
 *        TLAS with one instance per scene instance (updatable for animation).
 *
 * Conventions (the contract with the shaders, see xrsc_shared.h):
 * - vertices[]: sc_scene.vertices in order, as xs_vertex; a deformed mesh's (skin, morph
 *   targets) hold its current pose (object space of its instance), written on the GPU by
 *   gpu_scene_cmd_deform;
 * - indices[]: ABSOLUTE vertex indices (as sc_scene stores them), so a shader reads
 *   vertices[indices[first_index + 3t + c]];
 * - instance i of sc_scene = TLAS instance i (instanceCustomIndex i, mask 0xFF, SBT offset 0,
 *   culling disabled, no facing flip) = instances[i];
 * - facing: gl_HitKindEXT (xs_hit.front_face) reports the glTF front side: the side from which
 *   the triangle's vertices appear counter-clockwise in object space (right-handed), for
 *   mirrored instances too (test_gpu_primary: test_front_face);
 * - emitters[]: for every instance with emissive triangles, ALL its triangles in order (those
 *   sc_scene does not list as emitters get power 0), so emitter_base + t is triangle t's
 *   emitter; pmf proportional to power (uniform when all are 0), cdf inclusive (last = 1);
 * - lights[] (XS_BIND_LIGHTS): sc_scene.lights in order at their nodes' world transforms
 *   (rewritten by gpu_scene_stage_instances when one is animated); pmf proportional to a
 *   power estimate (point 4 pi I, spot 2 pi (1 - cos((inner + outer) / 2)) I, directional
 *   E pi r^2 with r the radius of the scene's bounding sphere at load; uniform when all are
 *   0), cdf inclusive (last = 1); one zero entry when there are none;
 * - textures[]: sc_scene.textures in order (RGBA8, sRGB or UNORM per texture), the rest of the
 *   XS_MAX_TEXTURES entries hold a 1x1 white texture.
 */
#pragma once

#include "gpu_pipeline.h"
#include "gpu_timer.h"
#include "sc_scene.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct gpu_scene gpu_scene;

/** Uploads the scene and builds the acceleration structures (waits for completion). */
xrsc_result gpu_scene_create(gpu_context *ctx, const sc_scene *scene, gpu_scene **out,
                             xrsc_diag *diag);
void gpu_scene_destroy(gpu_context *ctx, gpu_scene **scene);

/**
 * Instance updates, in two halves so the GPU work joins the frame's command buffer:
 * - gpu_scene_stage_instances (CPU, after sc_scene_evaluate moved instances): copies each
 *   instance's current world matrix to its prev_object_to_world, writes the new world
 *   matrices into a host-visible staging copy of instances[] and the TLAS instance buffer,
 *   and marks an update pending. The caller guarantees that no submitted work still reads
 *   these (xrsc waits for every frame).
 * - gpu_scene_cmd_update records the pending update into cmd: instances[] copy, TLAS update
 *   (mode UPDATE) and the barriers before and after; returns false (records nothing) when
 *   none is pending.
 */
xrsc_result gpu_scene_stage_instances(gpu_context *ctx, gpu_scene *gs, const sc_scene *scene,
                                      xrsc_diag *diag);
bool gpu_scene_cmd_update(gpu_context *ctx, gpu_scene *gs, VkCommandBuffer cmd);
bool gpu_scene_update_pending(const gpu_scene *gs);
/** Stage + record + submit + wait in one call (outside a frame; tests). */
xrsc_result gpu_scene_update_instances(gpu_context *ctx, gpu_scene *gs, const sc_scene *scene,
                                       xrsc_diag *diag);
/** Sets prev_object_to_world = object_to_world for every instance (no motion). */
xrsc_result gpu_scene_clear_motion(gpu_context *ctx, gpu_scene *gs, xrsc_diag *diag);

/**
 * Skins and morph targets (sc_mesh deformation): gpu_scene_stage_instances also stages the
 * scene's pose; gpu_scene_cmd_deform then records pass GPU_PASS_SKIN (deform.comp poses the
 * deformed meshes into vertices[], keeping the last frame's positions, gpu_deform.h) and pass
 * GPU_PASS_BLAS_UPDATE (their BLAS refitted or rebuilt from vertices[]), with the barriers
 * between and after; returns false when no pose is pending (a scene with deformed meshes
 * still records both passes, empty, so every frame has the same passes). Record it before
 * gpu_scene_cmd_update, whose TLAS update takes the new BLAS bounds. Scenes without deformed
 * meshes record nothing and their BLAS are built as before (no ALLOW_UPDATE).
 * BLAS mode: GPU_BLAS_AUTO (zero, the default) refits until the pose drifted more than
 * GPU_BLAS_REBUILD_DRIFT (gpu_deform_drift: displacement bound / mesh radius) from the pose
 * of the last build, then rebuilds; REFIT and REBUILD force one (for measurements).
 */
typedef enum gpu_blas_mode { GPU_BLAS_AUTO = 0, GPU_BLAS_REFIT, GPU_BLAS_REBUILD } gpu_blas_mode;
#define GPU_BLAS_REBUILD_DRIFT 0.5f
#define GPU_PASS_SKIN "skin"
#define GPU_PASS_BLAS_UPDATE "blas"
/** timer may be NULL (no passes timed). */
bool gpu_scene_cmd_deform(gpu_context *ctx, gpu_scene *gs, VkCommandBuffer cmd, gpu_timer *timer);
void gpu_scene_set_blas_mode(gpu_scene *gs, gpu_blas_mode mode);
/** Tests: false stops posing on the GPU (vertices[] and the BLAS keep the last pose). */
void gpu_scene_set_deform_enabled(gpu_scene *gs, bool enabled);
uint32_t gpu_scene_deform_mesh_count(const gpu_scene *gs);
/** BLAS updates recorded so far: rebuilds and refits. */
void gpu_scene_blas_update_counts(const gpu_scene *gs, uint32_t *out_rebuilds,
                                  uint32_t *out_refits);
/** Last frame's posed object-space position per scene vertex (vec4), NULL without deformed
 *  meshes (see gpu_deform.h). */
const gpu_buffer *gpu_scene_prev_positions(const gpu_scene *gs);
/** Reads count xs_vertex of vertices[] from first into dst (tests; waits). */
xrsc_result gpu_scene_download_vertices(gpu_context *ctx, const gpu_scene *gs, uint32_t first,
                                        uint32_t count, void *dst, xrsc_diag *diag);

/** Writes the scene bindings of set 0 (TLAS, vertices, indices, instances, materials,
 *  emitters, environment map, lights, textures) into d. */
void gpu_scene_write_descriptors(gpu_context *ctx, const gpu_scene *gs, gpu_descriptors *d);

/** Whether an instance has animated transforms (instances[]'s prev_object_to_world can differ
 *  from object_to_world); without, the sample cache's moving-sample rule is off
 *  (XS_SC_MOVING_ALPHA_MIN). */
bool gpu_scene_animated(const gpu_scene *gs);
/** Number of entries in the GPU emitter array (see the conventions above). */
uint32_t gpu_scene_emitter_count(const gpu_scene *gs);
/** Number of punctual lights in lights[] (xs_frame.light_count). */
uint32_t gpu_scene_light_count(const gpu_scene *gs);
/** Number of instances in XS_CULL_GLASS (xs_frame.glass_instances). */
uint32_t gpu_scene_glass_count(const gpu_scene *gs);
/** GPU time of the BLAS builds and of the TLAS build at load (updates are timed by the
 *  frame that records them, pass "tlas"). */
double gpu_scene_blas_build_ms(const gpu_scene *gs);
double gpu_scene_tlas_build_ms(const gpu_scene *gs);

#ifdef __cplusplus
}
#endif
