// SPDX-License-Identifier: MIT
/**
 * @file gpu_present.h
 * @brief Copies a rendered stereo frame into images owned by someone else (OpenXR swapchain
 *        images): colour from the method's output image (or host pixels), depth from host
 *        values already converted to the projection's depth.
 *
 * One submission per frame (waited on). Destination images are taken in any layout (their
 * contents are replaced) and left in COLOR_ATTACHMENT_OPTIMAL / DEPTH_STENCIL_ATTACHMENT_OPTIMAL,
 * the layouts an OpenXR Vulkan runtime expects released swapchain images in.
 */
#pragma once

#include "gpu_resource.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Host-visible staging for both eyes: RGBA32F colour (when there is no source image) and
 *  D32 depth, tightly packed rows, top to bottom. */
typedef struct gpu_present {
    gpu_buffer staging;
    uint32_t width, height;
    VkDeviceSize color_bytes, depth_bytes; /**< per eye */
} gpu_present;

xrsc_result gpu_present_create(gpu_context *ctx, uint32_t width, uint32_t height,
                               gpu_present *out, xrsc_diag *diag);
void gpu_present_destroy(gpu_context *ctx, gpu_present *p);
/** Where to write one eye's RGBA32F colour (used when the eye has no color_src). */
float *gpu_present_color_staging(gpu_present *p, uint32_t eye);
/** Where to write one eye's depth values (D32, already in [0, 1]). */
float *gpu_present_depth_staging(gpu_present *p, uint32_t eye);

/** True if colour of format `src` can be copied (same format) or blitted into `dst`. */
bool gpu_present_format_ok(const gpu_context *ctx, VkFormat src, VkFormat dst);

typedef struct gpu_present_eye {
    const gpu_image *color_src; /**< the method's colour image (GENERAL), NULL: staging */
    uint32_t color_layer;       /**< layer of color_src (the eye) */
    VkImage color_dst;
    VkFormat color_format;      /**< of color_dst: a copy when equal to color_src's, else a blit */
    VkImage depth_dst;          /**< D32_SFLOAT, or VK_NULL_HANDLE: no depth */
} gpu_present_eye;

/** Records and submits the copies of both eyes and waits. */
xrsc_result gpu_present_submit(gpu_context *ctx, gpu_present *p, const gpu_present_eye eyes[2],
                               xrsc_diag *diag);

#ifdef __cplusplus
}
#endif
