// SPDX-License-Identifier: MIT
/**
 * @file gpu_present.c
 * @brief Colour and depth copies into external (OpenXR swapchain) images.
 */
#include "gpu_present.h"

#include "u_diag.h"

#include <string.h>

#define GPU_PRESENT_COLOR_TEXEL 16u /* RGBA32F */
#define GPU_PRESENT_DEPTH_TEXEL 4u  /* D32_SFLOAT */

xrsc_result gpu_present_create(gpu_context *ctx, uint32_t width, uint32_t height,
                               gpu_present *out, xrsc_diag *diag)
{
    memset(out, 0, sizeof(*out));
    out->width = width;
    out->height = height;
    out->color_bytes = (VkDeviceSize)width * height * GPU_PRESENT_COLOR_TEXEL;
    out->depth_bytes = (VkDeviceSize)width * height * GPU_PRESENT_DEPTH_TEXEL;
    return gpu_buffer_create(ctx, 2 * (out->color_bytes + out->depth_bytes),
                             VK_BUFFER_USAGE_TRANSFER_SRC_BIT, GPU_MEMORY_UPLOAD, &out->staging,
                             diag);
}

void gpu_present_destroy(gpu_context *ctx, gpu_present *p)
{
    if (!p)
        return;
    gpu_buffer_destroy(ctx, &p->staging);
    memset(p, 0, sizeof(*p));
}

static VkDeviceSize color_offset(const gpu_present *p, uint32_t eye)
{
    return eye * p->color_bytes;
}

static VkDeviceSize depth_offset(const gpu_present *p, uint32_t eye)
{
    return 2 * p->color_bytes + eye * p->depth_bytes;
}

float *gpu_present_color_staging(gpu_present *p, uint32_t eye)
{
    return (float *)((char *)p->staging.mapped + color_offset(p, eye));
}

float *gpu_present_depth_staging(gpu_present *p, uint32_t eye)
{
    return (float *)((char *)p->staging.mapped + depth_offset(p, eye));
}

bool gpu_present_format_ok(const gpu_context *ctx, VkFormat src, VkFormat dst)
{
    if (src == dst)
        return true;
    VkFormatProperties sp, dp;
    vkGetPhysicalDeviceFormatProperties(ctx->physical_device, src, &sp);
    vkGetPhysicalDeviceFormatProperties(ctx->physical_device, dst, &dp);
    return (sp.optimalTilingFeatures & VK_FORMAT_FEATURE_BLIT_SRC_BIT) &&
           (dp.optimalTilingFeatures & VK_FORMAT_FEATURE_BLIT_DST_BIT);
}

static void image_barrier(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect,
                          VkImageLayout from, VkImageLayout to, VkAccessFlags src_access,
                          VkAccessFlags dst_access, VkPipelineStageFlags src_stage,
                          VkPipelineStageFlags dst_stage)
{
    VkImageMemoryBarrier b = {
        .sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER,
        .srcAccessMask = src_access,
        .dstAccessMask = dst_access,
        .oldLayout = from,
        .newLayout = to,
        .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
        .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
        .image = image,
        .subresourceRange = {aspect, 0, 1, 0, 1},
    };
    vkCmdPipelineBarrier(cmd, src_stage, dst_stage, 0, 0, NULL, 0, NULL, 1, &b);
}

xrsc_result gpu_present_submit(gpu_context *ctx, gpu_present *p, const gpu_present_eye eyes[2],
                               xrsc_diag *diag)
{
    VkCommandBuffer cmd;
    xrsc_result res = gpu_cmd_begin(ctx, &cmd, diag);
    if (res != XRSC_OK)
        return res;
    /* The render's writes (an earlier, waited-on submission) and the host's staging writes
     * become visible to the copies. */
    VkMemoryBarrier mb = {
        .sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
        .srcAccessMask = VK_ACCESS_MEMORY_WRITE_BIT | VK_ACCESS_HOST_WRITE_BIT,
        .dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT,
    };
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT | VK_PIPELINE_STAGE_HOST_BIT,
                         VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1, &mb, 0, NULL, 0, NULL);
    const VkExtent3D extent = {p->width, p->height, 1};
    for (uint32_t e = 0; e < 2; e++) {
        const gpu_present_eye *eye = &eyes[e];
        image_barrier(cmd, eye->color_dst, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                      VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 0, VK_ACCESS_TRANSFER_WRITE_BIT,
                      VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT);
        if (!eye->color_src) {
            VkBufferImageCopy c = {
                .bufferOffset = color_offset(p, e),
                .imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1},
                .imageExtent = extent,
            };
            vkCmdCopyBufferToImage(cmd, p->staging.buffer, eye->color_dst,
                                   VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &c);
        } else if (eye->color_src->format == eye->color_format) {
            /* Same format: a bit-exact copy (linear values stay linear and exact). */
            VkImageCopy c = {
                .srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, eye->color_layer, 1},
                .dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1},
                .extent = extent,
            };
            vkCmdCopyImage(cmd, eye->color_src->image, VK_IMAGE_LAYOUT_GENERAL, eye->color_dst,
                           VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &c);
        } else {
            /* Another format (half float, 8-bit sRGB): the blit converts. */
            VkImageBlit b = {
                .srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, eye->color_layer, 1},
                .srcOffsets = {{0, 0, 0}, {(int32_t)p->width, (int32_t)p->height, 1}},
                .dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1},
                .dstOffsets = {{0, 0, 0}, {(int32_t)p->width, (int32_t)p->height, 1}},
            };
            vkCmdBlitImage(cmd, eye->color_src->image, VK_IMAGE_LAYOUT_GENERAL, eye->color_dst,
                           VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &b, VK_FILTER_NEAREST);
        }
        image_barrier(cmd, eye->color_dst, VK_IMAGE_ASPECT_COLOR_BIT,
                      VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                      VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_ACCESS_TRANSFER_WRITE_BIT,
                      VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT,
                      VK_PIPELINE_STAGE_TRANSFER_BIT,
                      VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT);
        if (!eye->depth_dst)
            continue;
        image_barrier(cmd, eye->depth_dst, VK_IMAGE_ASPECT_DEPTH_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                      VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 0, VK_ACCESS_TRANSFER_WRITE_BIT,
                      VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT);
        VkBufferImageCopy c = {
            .bufferOffset = depth_offset(p, e),
            .imageSubresource = {VK_IMAGE_ASPECT_DEPTH_BIT, 0, 0, 1},
            .imageExtent = extent,
        };
        vkCmdCopyBufferToImage(cmd, p->staging.buffer, eye->depth_dst,
                               VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &c);
        image_barrier(cmd, eye->depth_dst, VK_IMAGE_ASPECT_DEPTH_BIT,
                      VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                      VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL, VK_ACCESS_TRANSFER_WRITE_BIT,
                      VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT |
                          VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
                      VK_PIPELINE_STAGE_TRANSFER_BIT,
                      VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT |
                          VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT);
    }
    return gpu_cmd_submit_wait(ctx, cmd, diag);
}
