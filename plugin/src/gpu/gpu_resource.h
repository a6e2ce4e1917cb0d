// SPDX-License-Identifier: MIT
/**
 * @file gpu_resource.h
 * @brief Buffers (device-local with staging upload, host-visible, device addresses), storage
 *        image arrays, sampled textures, a sampler, and image/buffer read-back.
 *
 * Each resource owns its own VkDeviceMemory (xrsc allocates few, large resources). Destroy
 * functions accept zeroed structs and zero them again.
 */
#pragma once

#include "gpu_context.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum gpu_memory {
    GPU_MEMORY_DEVICE,   /**< device-local; filled with gpu_buffer_upload */
    GPU_MEMORY_UPLOAD,   /**< host-visible, coherent, persistently mapped (UBOs, staging) */
    GPU_MEMORY_READBACK, /**< host-visible (cached when available), persistently mapped */
} gpu_memory;

typedef struct gpu_buffer {
    VkBuffer buffer;
    VkDeviceMemory memory;
    VkDeviceSize size;
    VkDeviceAddress address; /**< 0 unless created with SHADER_DEVICE_ADDRESS usage */
    void *mapped;            /**< non-NULL for UPLOAD/READBACK */
    bool coherent;
} gpu_buffer;

/** Creates a buffer of size bytes (0 is rounded up to 16 so bindings are never empty). */
xrsc_result gpu_buffer_create(gpu_context *ctx, VkDeviceSize size, VkBufferUsageFlags usage,
                              gpu_memory memory, gpu_buffer *out, xrsc_diag *diag);
void gpu_buffer_destroy(gpu_context *ctx, gpu_buffer *buf);
/** A device-local storage buffer of size bytes, also a copy source and destination (fills,
 *  read-back copies). */
xrsc_result gpu_buffer_create_storage(gpu_context *ctx, VkDeviceSize size, gpu_buffer *out,
                                      xrsc_diag *diag);
/** Largest staging buffer of ::gpu_buffer_upload: bigger uploads go in chunks of this size. */
#define GPU_UPLOAD_CHUNK_BYTES ((VkDeviceSize)16 << 20)
/** Copies size bytes into buf at offset through a temporary staging buffer of at most
 *  GPU_UPLOAD_CHUNK_BYTES, one submission per chunk (waits). */
xrsc_result gpu_buffer_upload(gpu_context *ctx, gpu_buffer *buf, VkDeviceSize offset,
                              const void *data, VkDeviceSize size, xrsc_diag *diag);
/** Copies size bytes at offset of buf (created with TRANSFER_SRC usage) into dst: one
 *  submission after all earlier work, waited for (read-backs for tests and self-tests). */
xrsc_result gpu_buffer_download(gpu_context *ctx, const gpu_buffer *buf, VkDeviceSize offset,
                                void *dst, VkDeviceSize size, xrsc_diag *diag);
/** Creates a device-local buffer and uploads data (usage gets TRANSFER_DST added). */
xrsc_result gpu_buffer_create_with_data(gpu_context *ctx, const void *data, VkDeviceSize size,
                                        VkBufferUsageFlags usage, gpu_buffer *out,
                                        xrsc_diag *diag);
/** Makes host writes to a mapped non-coherent buffer visible / device writes readable. */
void gpu_buffer_flush(gpu_context *ctx, gpu_buffer *buf);
void gpu_buffer_invalidate(gpu_context *ctx, gpu_buffer *buf);

typedef struct gpu_image {
    VkImage image;
    VkDeviceMemory memory;
    VkImageView view;
    VkFormat format;
    uint32_t width, height, layers;
    uint32_t texel_size; /**< bytes per texel */
} gpu_image;

/** A storage image 2D array (layers = eyes), usable as storage image, copy source/destination
 *  and clear target, left in VK_IMAGE_LAYOUT_GENERAL (and cleared to zero). */
xrsc_result gpu_image_create_storage(gpu_context *ctx, VkFormat format, uint32_t width,
                                     uint32_t height, uint32_t layers, gpu_image *out,
                                     xrsc_diag *diag);
/** A sampled RGBA8 texture (sRGB or UNORM) filled from rgba8 (rows top to bottom), left in
 *  SHADER_READ_ONLY_OPTIMAL. */
xrsc_result gpu_image_create_texture(gpu_context *ctx, uint32_t width, uint32_t height,
                                     bool srgb, const uint8_t *rgba8, gpu_image *out,
                                     xrsc_diag *diag);
void gpu_image_destroy(gpu_context *ctx, gpu_image *img);
/** Records a clear of every layer to zero (image in GENERAL). */
void gpu_image_cmd_clear(VkCommandBuffer cmd, const gpu_image *img);
/** Copies one layer into dst (tightly packed rows, top to bottom); waits. */
xrsc_result gpu_image_read_layer(gpu_context *ctx, const gpu_image *img, uint32_t layer,
                                 void *dst, size_t dst_size, xrsc_diag *diag);

/** A linear, repeating sampler for textures. */
xrsc_result gpu_sampler_create(gpu_context *ctx, VkSampler *out, xrsc_diag *diag);
/** A texture sampler with the given address modes (u, v) and filters, without mipmaps. */
xrsc_result gpu_sampler_create_mode(gpu_context *ctx, VkSamplerAddressMode u,
                                    VkSamplerAddressMode v, VkFilter mag, VkFilter min,
                                    VkSampler *out, xrsc_diag *diag);
void gpu_sampler_destroy(gpu_context *ctx, VkSampler *sampler);

#ifdef __cplusplus
}
#endif
