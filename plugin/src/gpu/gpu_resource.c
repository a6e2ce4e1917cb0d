// SPDX-License-Identifier: MIT
/**
 * @file gpu_resource.c
 * @brief Buffers, images, textures, samplers and read-back.
 */
#include "gpu_resource.h"

#include "u_diag.h"

#include <string.h>

static xrsc_result alloc_memory(gpu_context *ctx, VkMemoryRequirements req, gpu_memory kind,
                                bool device_address, VkDeviceMemory *out, bool *out_coherent,
                                xrsc_diag *diag)
{
    xrsc_result res = XRSC_OK;
    uint32_t type = UINT32_MAX;
    bool coherent = true;
    if (kind == GPU_MEMORY_DEVICE) {
        type = gpu_find_memory_type(ctx, req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    } else if (kind == GPU_MEMORY_READBACK) {
        type = gpu_find_memory_type(ctx, req.memoryTypeBits,
                                    VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT |
                                        VK_MEMORY_PROPERTY_HOST_CACHED_BIT |
                                        VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
        if (type == UINT32_MAX) {
            type = gpu_find_memory_type(ctx, req.memoryTypeBits,
                                        VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT |
                                            VK_MEMORY_PROPERTY_HOST_CACHED_BIT);
            coherent = false;
        }
    }
    if (type == UINT32_MAX) {
        type = gpu_find_memory_type(ctx, req.memoryTypeBits,
                                    kind == GPU_MEMORY_DEVICE
                                        ? 0
                                        : VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT |
                                              VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
        coherent = true;
    }
    if (type == UINT32_MAX)
        return u_diag_set(diag, XRSC_ERROR_VULKAN, __FILE__, __LINE__, "memory",
                          "no suitable memory type (bits 0x%x)", req.memoryTypeBits);
    VkMemoryAllocateFlagsInfo flags = {
        .sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_FLAGS_INFO,
        .flags = VK_MEMORY_ALLOCATE_DEVICE_ADDRESS_BIT,
    };
    VkMemoryAllocateInfo ai = {
        .sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO,
        .pNext = device_address ? &flags : NULL,
        .allocationSize = req.size,
        .memoryTypeIndex = type,
    };
    GPU_CHECK(res, diag, fail, vkAllocateMemory(ctx->device, &ai, NULL, out));
    if (out_coherent)
        *out_coherent = coherent;
fail:
    return res;
}

xrsc_result gpu_buffer_create(gpu_context *ctx, VkDeviceSize size, VkBufferUsageFlags usage,
                              gpu_memory memory, gpu_buffer *out, xrsc_diag *diag)
{
    xrsc_result res = XRSC_OK;
    memset(out, 0, sizeof(*out));
    if (size == 0)
        size = 16;
    out->size = size;
    VkBufferCreateInfo bci = {
        .sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO,
        .size = size,
        .usage = usage,
        .sharingMode = VK_SHARING_MODE_EXCLUSIVE,
    };
    GPU_CHECK(res, diag, fail, vkCreateBuffer(ctx->device, &bci, NULL, &out->buffer));
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(ctx->device, out->buffer, &req);
    bool bda = (usage & VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT) != 0;
    res = alloc_memory(ctx, req, memory, bda, &out->memory, &out->coherent, diag);
    if (res != XRSC_OK)
        goto fail;
    GPU_CHECK(res, diag, fail, vkBindBufferMemory(ctx->device, out->buffer, out->memory, 0));
    if (memory != GPU_MEMORY_DEVICE)
        GPU_CHECK(res, diag, fail,
                  vkMapMemory(ctx->device, out->memory, 0, VK_WHOLE_SIZE, 0, &out->mapped));
    if (bda) {
        VkBufferDeviceAddressInfo ai = {.sType = VK_STRUCTURE_TYPE_BUFFER_DEVICE_ADDRESS_INFO,
                                        .buffer = out->buffer};
        out->address = vkGetBufferDeviceAddress(ctx->device, &ai);
    }
    return XRSC_OK;
fail:
    gpu_buffer_destroy(ctx, out);
    return res;
}

void gpu_buffer_destroy(gpu_context *ctx, gpu_buffer *buf)
{
    if (!buf)
        return;
    if (buf->buffer)
        vkDestroyBuffer(ctx->device, buf->buffer, NULL);
    if (buf->memory)
        vkFreeMemory(ctx->device, buf->memory, NULL); /* unmaps implicitly */
    memset(buf, 0, sizeof(*buf));
}

void gpu_buffer_flush(gpu_context *ctx, gpu_buffer *buf)
{
    if (buf->mapped && !buf->coherent) {
        VkMappedMemoryRange r = {.sType = VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE,
                                 .memory = buf->memory,
                                 .size = VK_WHOLE_SIZE};
        vkFlushMappedMemoryRanges(ctx->device, 1, &r);
    }
}

void gpu_buffer_invalidate(gpu_context *ctx, gpu_buffer *buf)
{
    if (buf->mapped && !buf->coherent) {
        VkMappedMemoryRange r = {.sType = VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE,
                                 .memory = buf->memory,
                                 .size = VK_WHOLE_SIZE};
        vkInvalidateMappedMemoryRanges(ctx->device, 1, &r);
    }
}

xrsc_result gpu_buffer_upload(gpu_context *ctx, gpu_buffer *buf, VkDeviceSize offset,
                              const void *data, VkDeviceSize size, xrsc_diag *diag)
{
    if (size == 0)
        return XRSC_OK;
    if (buf->mapped) {
        memcpy((char *)buf->mapped + offset, data, size);
        gpu_buffer_flush(ctx, buf);
        return XRSC_OK;
    }
    /* A staging buffer of at most GPU_UPLOAD_CHUNK_BYTES, reused: a big scene's vertices
     * are not held twice more in host memory (lavapipe's device memory is host memory). */
    VkDeviceSize chunk = size < GPU_UPLOAD_CHUNK_BYTES ? size : GPU_UPLOAD_CHUNK_BYTES;
    gpu_buffer staging;
    xrsc_result res = gpu_buffer_create(ctx, chunk, VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                                        GPU_MEMORY_UPLOAD, &staging, diag);
    if (res != XRSC_OK)
        return res;
    for (VkDeviceSize done = 0; res == XRSC_OK && done < size; done += chunk) {
        VkDeviceSize n = size - done < chunk ? size - done : chunk;
        memcpy(staging.mapped, (const char *)data + done, n);
        gpu_buffer_flush(ctx, &staging);
        VkCommandBuffer cmd;
        res = gpu_cmd_begin(ctx, &cmd, diag);
        if (res == XRSC_OK) {
            VkBufferCopy region = {.srcOffset = 0, .dstOffset = offset + done, .size = n};
            vkCmdCopyBuffer(cmd, staging.buffer, buf->buffer, 1, &region);
            /* A fence only makes the copy available; this makes it visible to every later
             * command on the queue (the BLAS builds read vertices and indices in a submission
             * of their own, which starts with no barrier). */
            gpu_cmd_barrier_all(cmd);
            res = gpu_cmd_submit_wait(ctx, cmd, diag);
        }
    }
    gpu_buffer_destroy(ctx, &staging);
    return res;
}

xrsc_result gpu_buffer_download(gpu_context *ctx, const gpu_buffer *buf, VkDeviceSize offset,
                                void *dst, VkDeviceSize size, xrsc_diag *diag)
{
    gpu_buffer rb = {0};
    xrsc_result res = gpu_buffer_create(ctx, size, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                        GPU_MEMORY_READBACK, &rb, diag);
    VkCommandBuffer cmd;
    if (res == XRSC_OK && (res = gpu_cmd_begin(ctx, &cmd, diag)) == XRSC_OK) {
        gpu_cmd_barrier_all(cmd);
        VkBufferCopy region = {offset, 0, size};
        vkCmdCopyBuffer(cmd, buf->buffer, rb.buffer, 1, &region);
        gpu_cmd_barrier_all(cmd);
        if ((res = gpu_cmd_submit_wait(ctx, cmd, diag)) == XRSC_OK) {
            gpu_buffer_invalidate(ctx, &rb);
            memcpy(dst, rb.mapped, size);
        }
    }
    gpu_buffer_destroy(ctx, &rb);
    return res;
}

xrsc_result gpu_buffer_create_storage(gpu_context *ctx, VkDeviceSize size, gpu_buffer *out,
                                      xrsc_diag *diag)
{
    return gpu_buffer_create(ctx, size,
                             VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT |
                                 VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                             GPU_MEMORY_DEVICE, out, diag);
}

xrsc_result gpu_buffer_create_with_data(gpu_context *ctx, const void *data, VkDeviceSize size,
                                        VkBufferUsageFlags usage, gpu_buffer *out,
                                        xrsc_diag *diag)
{
    xrsc_result res = gpu_buffer_create(ctx, size, usage | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                        GPU_MEMORY_DEVICE, out, diag);
    if (res != XRSC_OK)
        return res;
    if (data && size) {
        res = gpu_buffer_upload(ctx, out, 0, data, size, diag);
        if (res != XRSC_OK)
            gpu_buffer_destroy(ctx, out);
    }
    return res;
}

/* ---- images ---- */

static uint32_t texel_size_of(VkFormat f)
{
    switch (f) {
    case VK_FORMAT_R32G32B32A32_SFLOAT:
    case VK_FORMAT_R32G32B32A32_UINT:
        return 16;
    case VK_FORMAT_R16G16B16A16_SFLOAT:
    case VK_FORMAT_R32G32_SFLOAT:
    case VK_FORMAT_R32G32_UINT:
        return 8;
    case VK_FORMAT_R32_SFLOAT:
    case VK_FORMAT_R32_UINT:
    case VK_FORMAT_R8G8B8A8_UNORM:
    case VK_FORMAT_R8G8B8A8_SRGB:
        return 4;
    default:
        return 0;
    }
}

static void cmd_layout(VkCommandBuffer cmd, VkImage image, uint32_t layers, VkImageLayout from,
                       VkImageLayout to)
{
    VkImageMemoryBarrier b = {
        .sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER,
        .srcAccessMask = from == VK_IMAGE_LAYOUT_UNDEFINED ? 0 : VK_ACCESS_MEMORY_WRITE_BIT,
        .dstAccessMask = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT,
        .oldLayout = from,
        .newLayout = to,
        .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
        .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
        .image = image,
        .subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, layers},
    };
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
                         VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, 0, 0, NULL, 0, NULL, 1, &b);
}

static xrsc_result image_create(gpu_context *ctx, VkFormat format, uint32_t width,
                                uint32_t height, uint32_t layers, VkImageUsageFlags usage,
                                gpu_image *out, xrsc_diag *diag)
{
    xrsc_result res = XRSC_OK;
    memset(out, 0, sizeof(*out));
    out->format = format;
    out->width = width;
    out->height = height;
    out->layers = layers;
    out->texel_size = texel_size_of(format);
    VkImageCreateInfo ici = {
        .sType = VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO,
        .imageType = VK_IMAGE_TYPE_2D,
        .format = format,
        .extent = {width, height, 1},
        .mipLevels = 1,
        .arrayLayers = layers,
        .samples = VK_SAMPLE_COUNT_1_BIT,
        .tiling = VK_IMAGE_TILING_OPTIMAL,
        .usage = usage,
        .sharingMode = VK_SHARING_MODE_EXCLUSIVE,
        .initialLayout = VK_IMAGE_LAYOUT_UNDEFINED,
    };
    GPU_CHECK(res, diag, fail, vkCreateImage(ctx->device, &ici, NULL, &out->image));
    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(ctx->device, out->image, &req);
    res = alloc_memory(ctx, req, GPU_MEMORY_DEVICE, false, &out->memory, NULL, diag);
    if (res != XRSC_OK)
        goto fail;
    GPU_CHECK(res, diag, fail, vkBindImageMemory(ctx->device, out->image, out->memory, 0));
    VkImageViewCreateInfo vci = {
        .sType = VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO,
        .image = out->image,
        .viewType = layers > 1 || (usage & VK_IMAGE_USAGE_STORAGE_BIT)
                        ? VK_IMAGE_VIEW_TYPE_2D_ARRAY
                        : VK_IMAGE_VIEW_TYPE_2D,
        .format = format,
        .subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, layers},
    };
    GPU_CHECK(res, diag, fail, vkCreateImageView(ctx->device, &vci, NULL, &out->view));
    return XRSC_OK;
fail:
    gpu_image_destroy(ctx, out);
    return res;
}

void gpu_image_cmd_clear(VkCommandBuffer cmd, const gpu_image *img)
{
    VkClearColorValue zero;
    memset(&zero, 0, sizeof(zero));
    VkImageSubresourceRange range = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, img->layers};
    vkCmdClearColorImage(cmd, img->image, VK_IMAGE_LAYOUT_GENERAL, &zero, 1, &range);
}

xrsc_result gpu_image_create_storage(gpu_context *ctx, VkFormat format, uint32_t width,
                                     uint32_t height, uint32_t layers, gpu_image *out,
                                     xrsc_diag *diag)
{
    xrsc_result res = image_create(ctx, format, width, height, layers,
                                   VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
                                       VK_IMAGE_USAGE_TRANSFER_DST_BIT,
                                   out, diag);
    if (res != XRSC_OK)
        return res;
    VkCommandBuffer cmd;
    res = gpu_cmd_begin(ctx, &cmd, diag);
    if (res == XRSC_OK) {
        cmd_layout(cmd, out->image, layers, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL);
        gpu_image_cmd_clear(cmd, out);
        gpu_cmd_barrier_all(cmd); /* the clear visible to later submissions, as above */
        res = gpu_cmd_submit_wait(ctx, cmd, diag);
    }
    if (res != XRSC_OK)
        gpu_image_destroy(ctx, out);
    return res;
}

xrsc_result gpu_image_create_texture(gpu_context *ctx, uint32_t width, uint32_t height,
                                     bool srgb, const uint8_t *rgba8, gpu_image *out,
                                     xrsc_diag *diag)
{
    VkFormat format = srgb ? VK_FORMAT_R8G8B8A8_SRGB : VK_FORMAT_R8G8B8A8_UNORM;
    xrsc_result res =
        image_create(ctx, format, width, height, 1,
                     VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT, out, diag);
    if (res != XRSC_OK)
        return res;
    VkDeviceSize bytes = (VkDeviceSize)width * height * 4;
    gpu_buffer staging;
    res = gpu_buffer_create(ctx, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, GPU_MEMORY_UPLOAD,
                            &staging, diag);
    if (res != XRSC_OK) {
        gpu_image_destroy(ctx, out);
        return res;
    }
    memcpy(staging.mapped, rgba8, bytes);
    gpu_buffer_flush(ctx, &staging);
    VkCommandBuffer cmd;
    res = gpu_cmd_begin(ctx, &cmd, diag);
    if (res == XRSC_OK) {
        cmd_layout(cmd, out->image, 1, VK_IMAGE_LAYOUT_UNDEFINED,
                   VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
        VkBufferImageCopy region = {
            .imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1},
            .imageExtent = {width, height, 1},
        };
        vkCmdCopyBufferToImage(cmd, staging.buffer, out->image,
                               VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
        cmd_layout(cmd, out->image, 1, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                   VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
        res = gpu_cmd_submit_wait(ctx, cmd, diag);
    }
    gpu_buffer_destroy(ctx, &staging);
    if (res != XRSC_OK)
        gpu_image_destroy(ctx, out);
    return res;
}

void gpu_image_destroy(gpu_context *ctx, gpu_image *img)
{
    if (!img)
        return;
    if (img->view)
        vkDestroyImageView(ctx->device, img->view, NULL);
    if (img->image)
        vkDestroyImage(ctx->device, img->image, NULL);
    if (img->memory)
        vkFreeMemory(ctx->device, img->memory, NULL);
    memset(img, 0, sizeof(*img));
}

xrsc_result gpu_image_read_layer(gpu_context *ctx, const gpu_image *img, uint32_t layer,
                                 void *dst, size_t dst_size, xrsc_diag *diag)
{
    size_t bytes = (size_t)img->width * img->height * img->texel_size;
    if (layer >= img->layers || !dst || dst_size < bytes)
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "dst",
                          "layer %u of %u, dst_size %zu < %zu", layer, img->layers, dst_size,
                          bytes);
    gpu_buffer rb;
    xrsc_result res = gpu_buffer_create(ctx, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                        GPU_MEMORY_READBACK, &rb, diag);
    if (res != XRSC_OK)
        return res;
    VkCommandBuffer cmd;
    res = gpu_cmd_begin(ctx, &cmd, diag);
    if (res == XRSC_OK) {
        gpu_cmd_barrier_all(cmd);
        VkBufferImageCopy region = {
            .imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, layer, 1},
            .imageExtent = {img->width, img->height, 1},
        };
        vkCmdCopyImageToBuffer(cmd, img->image, VK_IMAGE_LAYOUT_GENERAL, rb.buffer, 1, &region);
        VkMemoryBarrier mb = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
                              .srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT,
                              .dstAccessMask = VK_ACCESS_HOST_READ_BIT};
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0,
                             1, &mb, 0, NULL, 0, NULL);
        res = gpu_cmd_submit_wait(ctx, cmd, diag);
    }
    if (res == XRSC_OK) {
        gpu_buffer_invalidate(ctx, &rb);
        memcpy(dst, rb.mapped, bytes);
    }
    gpu_buffer_destroy(ctx, &rb);
    return res;
}

xrsc_result gpu_sampler_create(gpu_context *ctx, VkSampler *out, xrsc_diag *diag)
{
    return gpu_sampler_create_mode(ctx, VK_SAMPLER_ADDRESS_MODE_REPEAT,
                                   VK_SAMPLER_ADDRESS_MODE_REPEAT, VK_FILTER_LINEAR,
                                   VK_FILTER_LINEAR, out, diag);
}

xrsc_result gpu_sampler_create_mode(gpu_context *ctx, VkSamplerAddressMode u,
                                    VkSamplerAddressMode v, VkFilter mag, VkFilter min,
                                    VkSampler *out, xrsc_diag *diag)
{
    xrsc_result res = XRSC_OK;
    VkSamplerCreateInfo sci = {
        .sType = VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO,
        .magFilter = mag,
        .minFilter = min,
        .mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST,
        .addressModeU = u,
        .addressModeV = v,
        .addressModeW = VK_SAMPLER_ADDRESS_MODE_REPEAT,
        .maxLod = 0.0f,
    };
    *out = VK_NULL_HANDLE;
    GPU_CHECK(res, diag, fail, vkCreateSampler(ctx->device, &sci, NULL, out));
fail:
    return res;
}

void gpu_sampler_destroy(gpu_context *ctx, VkSampler *sampler)
{
    if (sampler && *sampler) {
        vkDestroySampler(ctx->device, *sampler, NULL);
        *sampler = VK_NULL_HANDLE;
    }
}
