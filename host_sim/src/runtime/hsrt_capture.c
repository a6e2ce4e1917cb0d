// SPDX-License-Identifier: MIT
/**
 * @file hsrt_capture.c
 * @brief Swapchain formats the runtime offers, conversion of read-back texels into linear
 *        and display images, and writing captured frames (hs_image.h).
 */
#include "hsrt.h"

#include "hs_image.h"
#include "u_diag.h"

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

static float half_to_float(uint16_t h)
{
    uint32_t sign = (uint32_t)(h >> 15) << 31, exp = (h >> 10) & 0x1f, man = h & 0x3ff;
    uint32_t bits;
    if (exp == 0) {
        if (!man) {
            bits = sign;
        } else { /* subnormal */
            float f = ldexpf((float)man, -24);
            return sign ? -f : f;
        }
    } else if (exp == 31) {
        bits = sign | 0x7f800000u | (man << 13);
    } else {
        bits = sign | ((exp + 112) << 23) | (man << 13);
    }
    float f;
    memcpy(&f, &bits, sizeof(f));
    return f;
}

static float srgb_to_linear(float c)
{
    return c <= 0.04045f ? c / 12.92f : powf((c + 0.055f) / 1.055f, 2.4f);
}

static uint8_t linear_to_srgb8(float c)
{
    if (!(c > 0.0f))
        return 0;
    if (c >= 1.0f)
        return 255;
    float s = c <= 0.0031308f ? 12.92f * c : 1.055f * powf(c, 1.0f / 2.4f) - 0.055f;
    return (uint8_t)lrintf(s * 255.0f);
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
            lut[i] = srgb_to_linear((float)i / 255.0f);
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
                out->rgb[i * 3 + c] = linear_to_srgb8(v);
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
                out->rgba[i] = half_to_float(hv);
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

bool hsrt_write_frame(const hsrt_config *cfg, uint64_t frame, hsrt_eye_image eyes[2])
{
    static const char *const eye_name[2] = {"left", "right"};
    char path[1200], msg[1024];
    bool ok = true;
    xrsc_diag diag;
    for (int e = 0; e < 2; e++) {
        if (cfg->write_eyes) {
            snprintf(path, sizeof(path), "%s/frame_%05llu_%s.png", cfg->out_dir,
                     (unsigned long long)frame, eye_name[e]);
            memset(&diag, 0, sizeof(diag));
            if (hs_write_png(path, eyes[e].rgb, eyes[e].w, eyes[e].h, &diag) != XRSC_OK) {
                U_LOG_E("runtime: %s", xrsc_diag_format(&diag, msg, sizeof(msg)));
                ok = false;
            }
        }
        if (cfg->write_linear) {
            snprintf(path, sizeof(path), "%s/frame_%05llu_%s.pfm", cfg->out_dir,
                     (unsigned long long)frame, eye_name[e]);
            memset(&diag, 0, sizeof(diag));
            if (hs_write_pfm(path, eyes[e].rgba, eyes[e].w, eyes[e].h, &diag) != XRSC_OK) {
                U_LOG_E("runtime: %s", xrsc_diag_format(&diag, msg, sizeof(msg)));
                ok = false;
            }
        }
    }
    if (cfg->write_sbs) {
        if (eyes[0].w != eyes[1].w || eyes[0].h != eyes[1].h) {
            U_LOG_W("runtime: frame %llu: the eyes differ in size, no side-by-side image",
                    (unsigned long long)frame);
            return ok;
        }
        uint8_t *sbs = malloc((size_t)eyes[0].w * 2 * eyes[0].h * 3);
        if (!sbs)
            return false;
        hs_side_by_side(eyes[0].rgb, eyes[1].rgb, eyes[0].w, eyes[0].h, sbs);
        snprintf(path, sizeof(path), "%s/frame_%05llu_sbs.png", cfg->out_dir,
                 (unsigned long long)frame);
        memset(&diag, 0, sizeof(diag));
        if (hs_write_png(path, sbs, eyes[0].w * 2, eyes[0].h, &diag) != XRSC_OK) {
            U_LOG_E("runtime: %s", xrsc_diag_format(&diag, msg, sizeof(msg)));
            ok = false;
        }
        free(sbs);
    }
    return ok;
}
