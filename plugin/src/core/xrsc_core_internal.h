// SPDX-License-Identifier: MIT
/**
 * @file xrsc_core_internal.h
 * @brief What other plugin modules (the OpenXR front end, src/xr/) reach below the public API:
 *        a context created through Vulkan creation hooks, its gpu_context, and a renderer's
 *        output images and size.
 */
#pragma once

#include "gpu_context.h"
#include "gpu_resource.h"
#include "xrsc/xrsc.h"

#ifdef __cplusplus
extern "C" {
#endif

/** xrsc_context_create with the instance and device made through hooks (gpu_context.h):
 *  the hooks decide the device; options->device (else XRSC_DEVICE) is checked against it
 *  (gpu_context_create_hooked). */
xrsc_result xrsc_context_create_hooked(const xrsc_context_options *options,
                                       const gpu_context_hooks *hooks, xrsc_context **out_ctx,
                                       xrsc_diag *out_diag);
/** The context's Vulkan bundle (borrowed). */
gpu_context *xrsc_context_gpu(xrsc_context *ctx);
/** The renderer's per-eye size in pixels. */
void xrsc_renderer_size(const xrsc_renderer *renderer, uint32_t *out_width,
                        uint32_t *out_height);
/** The GPU image of an output (layer = eye, GENERAL), NULL if the method offers none. */
const gpu_image *xrsc_renderer_output_image(const xrsc_renderer *renderer, xrsc_output output);
/** The scene's GPU side (borrowed; tests read its BLAS update counts, gpu_scene.h). */
struct gpu_scene *xrsc_scene_gpu(const xrsc_scene *scene);

#ifdef __cplusplus
}
#endif
