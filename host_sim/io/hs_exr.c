// SPDX-License-Identifier: MIT
/**
 * @file hs_exr.c
 * @brief OpenEXR writer (hs_exr.h) on OpenEXRCore's chunk encode pipeline; the reader is
 *        u_exr.h's (plugin/src/util), shared with the plugin's environment maps.
 */
#include "hs_exr.h"

#include "hs_file.h"
#include "u_diag.h"
#include "u_exr.h"
#include "u_exr_common.h"

#include <openexr.h>

#include <stdio.h>
#include <stdlib.h>

/** Largest side hs_write_exr accepts (the reader's, as hs_read_pfm). */
#define EXR_MAX_SIDE U_EXR_MAX_SIDE

/* Points each channel of a chunk at its rows in the caller's buffers (start row y0). */
static void bind_channels(exr_coding_channel_info_t *ch, int16_t count, const u_exr_plane *planes,
                          int nplanes, int32_t y0)
{
    for (int16_t c = 0; c < count; c++) {
        const u_exr_plane *p = u_exr_find_plane(planes, nplanes, ch[c].channel_name);
        ch[c].user_bytes_per_element = 4;
        ch[c].user_data_type = EXR_PIXEL_FLOAT;
        ch[c].user_pixel_stride = p ? p->pixel_stride : 4;
        ch[c].user_line_stride = p ? p->line_stride : 0;
        uint8_t *row = p ? p->base + (size_t)y0 * (size_t)p->line_stride : NULL;
        ch[c].encode_from_ptr = row;
    }
}

static exr_result_t write_chunks(exr_context_t ctx, uint32_t h, const u_exr_plane *planes,
                                 int nplanes)
{
    int32_t lines = 0;
    exr_result_t rv = exr_get_scanlines_per_chunk(ctx, 0, &lines);
    exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
    bool started = false;
    for (int32_t y = 0; rv == EXR_ERR_SUCCESS && y < (int32_t)h; y += lines) {
        exr_chunk_info_t ci;
        rv = exr_write_scanline_chunk_info(ctx, 0, y, &ci);
        if (rv == EXR_ERR_SUCCESS)
            rv = started ? exr_encoding_update(ctx, 0, &ci, &enc)
                         : exr_encoding_initialize(ctx, 0, &ci, &enc);
        if (rv != EXR_ERR_SUCCESS)
            break;
        started = true;
        bind_channels(enc.channels, enc.channel_count, planes, nplanes, ci.start_y);
        rv = exr_encoding_choose_default_routines(ctx, 0, &enc);
        if (rv == EXR_ERR_SUCCESS)
            rv = exr_encoding_run(ctx, 0, &enc);
    }
    if (started)
        exr_encoding_destroy(ctx, &enc);
    return rv;
}

static xrsc_result write_exr(const char *path, bool staged, const float *rgba, const float *depth,
                             uint32_t w, uint32_t h, xrsc_diag *diag)
{
    if (!path || !rgba || w == 0 || h == 0 || w > EXR_MAX_SIDE || h > EXR_MAX_SIDE)
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, path ? path : "", 0, "exr",
                          "no image, or a side outside 1..%d", EXR_MAX_SIDE);
    /* Written as PATH.tmp and renamed into place (hs_file.h), like the PNG and PFM files. */
    char tmp[HS_OUT_PATH_MAX + sizeof(HS_TEMP_SUFFIX)];
    if (!hs_temp_path(path, tmp, sizeof(tmp)))
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, path, 0, "exr", "path too long");
    u_exr_msg msg = {{0}};
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = u_exr_on_error;
    init.user_data = &msg;
    exr_context_t ctx = NULL;
    /* "Directly" to the temporary name: the library deletes it itself when writing fails. */
    exr_result_t rv = exr_start_write(&ctx, tmp, EXR_WRITE_FILE_DIRECTLY, &init);
    if (rv != EXR_ERR_SUCCESS)
        return u_exr_fail(diag, XRSC_ERROR_IO, path, "cannot create", rv, &msg);
    int part = 0;
    rv = exr_add_part(ctx, "rgbz", EXR_STORAGE_SCANLINE, &part);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_initialize_required_attr_simple(ctx, part, (int32_t)w, (int32_t)h,
                                                 EXR_COMPRESSION_ZIP);
    /* Linear radiance and metric depth: neither is perceptually encoded. */
    static const char *const names[4] = {"R", "G", "B", "Z"};
    for (int c = 0; c < (depth ? 4 : 3) && rv == EXR_ERR_SUCCESS; c++)
        rv = exr_add_channel(ctx, part, names[c], EXR_PIXEL_FLOAT, EXR_PERCEPTUALLY_LINEAR, 1, 1);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_write_header(ctx);
    if (rv == EXR_ERR_SUCCESS) {
        const int32_t rgba_px = 4 * sizeof(float), rgba_line = (int32_t)w * rgba_px;
        u_exr_plane planes[4] = {
            {"R", (uint8_t *)(uintptr_t)(rgba + 0), rgba_px, rgba_line},
            {"G", (uint8_t *)(uintptr_t)(rgba + 1), rgba_px, rgba_line},
            {"B", (uint8_t *)(uintptr_t)(rgba + 2), rgba_px, rgba_line},
            {"Z", (uint8_t *)(uintptr_t)depth, sizeof(float), (int32_t)(w * sizeof(float))},
        };
        rv = write_chunks(ctx, h, planes, 4);
    }
    if (rv != EXR_ERR_SUCCESS) {
        xrsc_result res = u_exr_fail(diag, XRSC_ERROR_IO, path, "writing failed", rv, &msg);
        exr_finish(&ctx); /* removes the temporary file; path is left as it was */
        remove(tmp);
        return res;
    }
    rv = exr_finish(&ctx);
    if (rv != EXR_ERR_SUCCESS) {
        remove(tmp);
        return u_exr_fail(diag, XRSC_ERROR_IO, path, "finishing failed", rv, &msg);
    }
    return staged ? XRSC_OK : hs_out_rename(tmp, path, diag);
}

xrsc_result hs_write_exr(const char *path, const float *rgba, const float *depth, uint32_t w,
                         uint32_t h, xrsc_diag *diag)
{
    return write_exr(path, false, rgba, depth, w, h, diag);
}

xrsc_result hs_stage_exr(const char *path, const float *rgba, const float *depth, uint32_t w,
                         uint32_t h, xrsc_diag *diag)
{
    return write_exr(path, true, rgba, depth, w, h, diag);
}

/* Reading lives in the plugin's util (u_exr.h), which environment maps use as well. */
xrsc_result hs_read_exr(const char *path, float **out_rgba, float **out_depth, uint32_t *out_w,
                        uint32_t *out_h, xrsc_diag *diag)
{
    *out_rgba = NULL;
    if (out_depth)
        *out_depth = NULL;
    u_exr_options opt = {.want_depth = out_depth != NULL};
    u_exr_image img;
    xrsc_result r = u_exr_read(path, &opt, &img, diag);
    if (r != XRSC_OK)
        return r;
    *out_rgba = img.rgba;
    if (out_depth)
        *out_depth = img.depth;
    *out_w = img.width;
    *out_h = img.height;
    return XRSC_OK;
}
