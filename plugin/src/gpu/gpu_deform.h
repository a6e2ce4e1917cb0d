// SPDX-License-Identifier: MIT
/**
 * @file gpu_deform.h
 * @brief The GPU deformation pass: skins and morph targets of a ::sc_scene posed each frame
 *        by deform.comp into the scene's vertex buffer (xrsc_shared.h XS_DEFORM_*).
 *
 * It owns the rest copy of the deformed meshes' vertices, their influences and morph deltas,
 * the host-visible pose (joint matrices, morph weights) and prev[], the last frame's posed
 * position of every scene vertex (object space; rigid meshes' vertices keep their positions).
 * gpu_scene owns one when the scene has deformed meshes and runs it before its BLAS update.
 */
#pragma once

#include "gpu_pipeline.h"
#include "sc_scene.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct gpu_deform gpu_deform;

/** Creates the pass for scene's deformed meshes writing into vertices (the scene's
 *  xs_vertex[] buffer, kept by the caller); *out stays NULL when there are none. */
xrsc_result gpu_deform_create(gpu_context *ctx, const sc_scene *scene, const gpu_buffer *vertices,
                              gpu_deform **out, xrsc_diag *diag);
void gpu_deform_destroy(gpu_context *ctx, gpu_deform **d);
/** Copies the scene's current pose (sc_scene.pose_matrices, pose_weights) to the GPU copy,
 *  which the next recorded pass reads. No submitted work may still read it. */
void gpu_deform_stage(gpu_context *ctx, gpu_deform *d, const sc_scene *scene);
/**
 * Records one dispatch per deformed mesh with the barriers around it: earlier reads of
 * vertices[] (shaders, AS builds) before the writes, and the writes before later AS builds,
 * ray-tracing and compute shaders. keep_prev: prev[] takes the positions the pass overwrites
 * (one frame step); false: prev[] = the new pose (no motion).
 */
void gpu_deform_cmd(gpu_deform *d, VkCommandBuffer cmd, bool keep_prev);
/** How far the pose moved since the last gpu_deform_mark_built, relative to each mesh's size:
 *  max over meshes of (max over joints of |dt| + R ||dA||_F, plus sum |dw_k| x the longest
 *  morph delta) / r, with dA and dt the change of a joint matrix's linear part and
 *  translation, R the farthest rest vertex from the origin and r half the rest box's
 *  diagonal. A cheap bound of how far a vertex moved; 0 = the pose the BLAS was built for. */
float gpu_deform_drift(const gpu_deform *d, const sc_scene *scene);
/** Records that the BLAS were (re)built for the scene's current pose. */
void gpu_deform_mark_built(gpu_deform *d, const sc_scene *scene);
/** prev[] (vec4 per scene vertex). */
const gpu_buffer *gpu_deform_prev(const gpu_deform *d);

#ifdef __cplusplus
}
#endif
