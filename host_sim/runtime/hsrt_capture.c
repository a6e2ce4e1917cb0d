// SPDX-License-Identifier: MIT
/**
 * @file hsrt_capture.c
 * @brief Swapchain formats the runtime offers, conversion of read-back texels into linear
 *        and display images, and writing captured frames (hs_image.h).
 */
#include "hsrt.h"

#include "hs_file.h"
#include "hs_image.h"
#include "u_diag.h"
#include "u_half.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

const VkFormat hsrt_formats[] = {
    VK_FORMAT_R8G8B8A8_SRGB,       VK_FORMAT_B8G8R8A8_SRGB,       VK_FORMAT_R8G8B8A8_UNORM,
    VK_FORMAT_B8G8R8A8_UNORM,      VK_FORMAT_R16G16B16A16_SFLOAT, VK_FORMAT_R32G32B32A32_SFLOAT,
    VK_FORMAT_D32_SFLOAT,          VK_FORMAT_D16_UNORM,
};
const uint32_t hsrt_format_count = sizeof(hsrt_formats) / sizeof(hsrt_formats[0]);

uint32_t hsrt_format_size(VkFormat format)
{
    switch (format) {
    case VK_FORMAT_R8G8B8A8_SRGB:
    case VK_FORMAT_B8G8R8A8_SRGB:
    case VK_FORMAT_R8G8B8A8_UNORM:
    case VK_FORMAT_B8G8R8A8_UNORM:
    case VK_FORMAT_D32_SFLOAT:
        return 4;
    case VK_FORMAT_R16G16B16A16_SFLOAT:
        return 8;
    case VK_FORMAT_R32G32B32A32_SFLOAT:
        return 16;
    case VK_FORMAT_D16_UNORM:
        return 2;
    default:
        return 0;
    }
}

bool hsrt_format_is_depth(VkFormat format)
{
    return format == VK_FORMAT_D32_SFLOAT || format == VK_FORMAT_D16_UNORM;
}


void hsrt_eye_image_free(hsrt_eye_image *img)
{
    free(img->rgba);
    free(img->rgb);
    memset(img, 0, sizeof(*img));
}

bool hsrt_convert(VkFormat format, const void *texels, uint32_t w, uint32_t h, float exposure,
                  hsrt_eye_image *out)
{
    size_t n = (size_t)w * h;
    memset(out, 0, sizeof(*out));
    out->w = w;
    out->h = h;
    out->rgba = malloc(n * 4 * sizeof(float));
    out->rgb = malloc(n * 3);
    if (!out->rgba || !out->rgb) {
        hsrt_eye_image_free(out);
        return false;
    }
    const uint8_t *b = texels;
    bool bgr = format == VK_FORMAT_B8G8R8A8_SRGB || format == VK_FORMAT_B8G8R8A8_UNORM;
    switch (format) {
    case VK_FORMAT_R8G8B8A8_SRGB:
    case VK_FORMAT_B8G8R8A8_SRGB: {
        float lut[256];
        for (int i = 0; i < 256; i++)
            lut[i] = hs_srgb_to_linear((float)i / 255.0f);
        for (size_t i = 0; i < n; i++) {
            for (int c = 0; c < 3; c++) {
                uint8_t v = b[i * 4 + (bgr ? 2 - c : c)];
                out->rgb[i * 3 + c] = v;
                out->rgba[i * 4 + c] = lut[v];
            }
            out->rgba[i * 4 + 3] = (float)b[i * 4 + 3] / 255.0f;
        }
        break;
    }
    case VK_FORMAT_R8G8B8A8_UNORM:
    case VK_FORMAT_B8G8R8A8_UNORM:
        for (size_t i = 0; i < n; i++) {
            for (int c = 0; c < 3; c++) {
                float v = (float)b[i * 4 + (bgr ? 2 - c : c)] / 255.0f;
                out->rgba[i * 4 + c] = v;
                out->rgb[i * 3 + c] = hs_srgb8(v);
            }
            out->rgba[i * 4 + 3] = (float)b[i * 4 + 3] / 255.0f;
        }
        break;
    case VK_FORMAT_R16G16B16A16_SFLOAT:
    case VK_FORMAT_R32G32B32A32_SFLOAT: {
        for (size_t i = 0; i < n * 4; i++) {
            if (format == VK_FORMAT_R16G16B16A16_SFLOAT) {
                uint16_t hv;
                memcpy(&hv, b + i * 2, 2);
                out->rgba[i] = u_half_to_float(hv);
            } else {
                memcpy(&out->rgba[i], b + i * 4, 4);
            }
        }
        hs_tonemap tm = {.exposure = exposure};
        hs_tonemap_rgba(&tm, out->rgba, w, h, out->rgb);
        break;
    }
    default:
        hsrt_eye_image_free(out);
        return false;
    }
    return true;
}

/* Stages one eye's files into set. */
static xrsc_result stage_eye(const hsrt_config *cfg, uint64_t frame, int e,
                             const hsrt_eye_image *eye, hs_frame_set *set, xrsc_diag *diag)
{
    static const char *const eye_name[2] = {"left", "right"};
    char path[HS_OUT_PATH_MAX];
    xrsc_result res = XRSC_OK;
    if (cfg->write_eyes) {
        snprintf(path, sizeof(path), "%s/frame_%05llu_%s.png", cfg->out_dir,
                 (unsigned long long)frame, eye_name[e]);
        if ((res = hs_frame_set_add(set, path, diag)) != XRSC_OK ||
            (res = hs_stage_png(path, eye->rgb, eye->w, eye->h, diag)) != XRSC_OK)
            return res;
    }
    if (cfg->write_linear) {
        snprintf(path, sizeof(path), "%s/frame_%05llu_%s.pfm", cfg->out_dir,
                 (unsigned long long)frame, eye_name[e]);
        if ((res = hs_frame_set_add(set, path, diag)) != XRSC_OK ||
            (res = hs_stage_pfm(path, eye->rgba, eye->w, eye->h, diag)) != XRSC_OK)
            return res;
    }
    return res;
}

static xrsc_result stage_sbs(const hsrt_config *cfg, uint64_t frame, hsrt_eye_image eyes[2],
                             hs_frame_set *set, xrsc_diag *diag)
{
    if (eyes[0].w != eyes[1].w || eyes[0].h != eyes[1].h) {
        U_LOG_W("runtime: frame %llu: the eyes differ in size, no side-by-side image",
                (unsigned long long)frame);
        return XRSC_OK;
    }
    char path[HS_OUT_PATH_MAX];
    snprintf(path, sizeof(path), "%s/frame_%05llu_sbs.png", cfg->out_dir,
             (unsigned long long)frame);
    xrsc_result res = hs_frame_set_add(set, path, diag);
    if (res != XRSC_OK)
        return res;
    uint8_t *sbs = malloc((size_t)eyes[0].w * 2 * eyes[0].h * 3);
    if (!sbs)
        return u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, path, 0, "", "side-by-side image");
    hs_side_by_side(eyes[0].rgb, eyes[1].rgb, eyes[0].w, eyes[0].h, sbs);
    res = hs_stage_png(path, sbs, eyes[0].w * 2, eyes[0].h, diag);
    free(sbs);
    return res;
}

xrsc_result hsrt_write_frame(const hsrt_config *cfg, uint64_t frame, hsrt_eye_image eyes[2],
                             xrsc_diag *diag)
{
    hs_frame_set set = {0};
    xrsc_result res = XRSC_OK;
    for (int e = 0; e < 2 && res == XRSC_OK; e++)
        res = stage_eye(cfg, frame, e, &eyes[e], &set, diag);
    if (res == XRSC_OK && cfg->write_sbs)
        res = stage_sbs(cfg, frame, eyes, &set, diag);
    if (res != XRSC_OK) {
        hs_frame_set_abort(&set);
        return res;
    }
    return hs_frame_set_commit(&set, diag);
}

/* Depth within this fraction of the far end of the depth range is background (the plugin and
 * most applications clear to, or clamp at, the far end where nothing was hit). */
#define HSRT_DEPTH_FAR_FRACTION 1e-6

float *hsrt_depth_to_metres(VkFormat format, const void *texels, uint32_t w, uint32_t h,
                            const XrCompositionLayerDepthInfoKHR *info)
{
    if (!info || !hsrt_format_is_depth(format))
        return NULL;
    size_t n = (size_t)w * h;
    float *out = malloc(n * sizeof(float));
    if (!out)
        return NULL;
    double lo = info->minDepth, range = (double)info->maxDepth - info->minDepth;
    double zn = info->nearZ, zf = info->farZ;
    bool far_is_max = !(zn > zf); /* the depth value at the far end: maxDepth, or minDepth */
    for (size_t i = 0; i < n; i++) {
        double d = format == VK_FORMAT_D32_SFLOAT ? (double)((const float *)texels)[i]
                                                  : ((const uint16_t *)texels)[i] / 65535.0;
        double t = range > 0.0 ? (d - lo) / range : 0.0;
        double to_far = far_is_max ? 1.0 - t : t;
        if (!(to_far > HSRT_DEPTH_FAR_FRACTION) || !isfinite(t)) {
            out[i] = 0.0f;
            continue;
        }
        double z = isinf(zf) ? zn / (1.0 - t) : zn * zf / (zf - t * (zf - zn));
        out[i] = z > 0.0 && isfinite(z) ? (float)z : 0.0f;
    }
    return out;
}

void hsrt_preview_frame_free(hsrt_preview_frame *f)
{
    if (!f)
        return;
    for (int e = 0; e < 2; e++) {
        hsrt_eye_image_free(&f->eyes[e]);
        free(f->depth_m[e]);
    }
    memset(f, 0, sizeof(*f));
}
