// SPDX-License-Identifier: MIT
/**
 * @file hs_run_dir.c
 * @brief Frame-name patterns, the first frame of a run folder, and PFM/PNG frame reading
 *        (hs_run_dir.h).
 */
#include "hs_run_dir.h"

#include "hs_exr.h"
#include "hs_image.h"
#include "u_diag.h"

#include <dirent.h>
#include <math.h>
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static bool append_char(char *buf, size_t size, size_t *len, char c)
{
    if (*len + 1 >= size)
        return false;
    buf[(*len)++] = c;
    buf[*len] = '\0';
    return true;
}

bool hs_frame_pattern_parse(const char *fmt, hs_frame_pattern *out)
{
    memset(out, 0, sizeof(*out));
    size_t plen = 0, slen = 0;
    int conversions = 0;
    for (const char *p = fmt; *p; p++) {
        char *buf = conversions ? out->suffix : out->prefix;
        size_t *len = conversions ? &slen : &plen;
        if (*p != '%') {
            if (!append_char(buf, sizeof(out->prefix), len, *p))
                return false;
            continue;
        }
        p++;
        if (*p == '%') {
            if (!append_char(buf, sizeof(out->prefix), len, '%'))
                return false;
            continue;
        }
        if (*p == '0') {
            out->zero_pad = true;
            p++;
        }
        while (*p >= '0' && *p <= '9') {
            out->width = out->width * 10 + (*p - '0');
            if (out->width > 20)
                return false;
            p++;
        }
        if (*p != 'u' || ++conversions > 1)
            return false;
    }
    return conversions == 1;
}

bool hs_frame_pattern_path(const char *dir, const hs_frame_pattern *pat, uint32_t frame, char *out,
                           size_t size)
{
    int n =
        pat->zero_pad
            ? snprintf(out, size, "%s/%s%0*u%s", dir, pat->prefix, pat->width, frame, pat->suffix)
            : snprintf(out, size, "%s/%s%*u%s", dir, pat->prefix, pat->width, frame, pat->suffix);
    return n > 0 && (size_t)n < size;
}

/* The frame number of a file name that matches the pattern (spaces of a padded %Nu allowed). */
static bool match_name(const char *name, const hs_frame_pattern *pat, uint32_t *out)
{
    size_t pl = strlen(pat->prefix), sl = strlen(pat->suffix), nl = strlen(name);
    if (nl <= pl + sl || strncmp(name, pat->prefix, pl) || strcmp(name + nl - sl, pat->suffix))
        return false;
    uint64_t v = 0;
    size_t digits = 0;
    for (size_t i = pl; i < nl - sl; i++) {
        char c = name[i];
        if (c == ' ' && digits == 0 && !pat->zero_pad)
            continue;
        if (c < '0' || c > '9' || (v = v * 10 + (uint64_t)(c - '0')) > UINT32_MAX)
            return false;
        digits++;
    }
    if (!digits)
        return false;
    *out = (uint32_t)v;
    return true;
}

bool hs_frame_pattern_first(const char *dir, const hs_frame_pattern *pat, uint32_t *out_first)
{
    DIR *d = opendir(dir);
    if (!d)
        return false;
    bool found = false;
    uint32_t best = 0, v;
    for (struct dirent *e = readdir(d); e; e = readdir(d)) {
        if (match_name(e->d_name, pat, &v) && (!found || v < best)) {
            best = v;
            found = true;
        }
    }
    closedir(d);
    if (found)
        *out_first = best;
    return found;
}

const char *hs_run_pattern(hs_run_kind kind, int eye)
{
    static const char *const names[3][2] = {{"frame_%05u_left.pfm", "frame_%05u_right.pfm"},
                                            {"frame_%05u_left.exr", "frame_%05u_right.exr"},
                                            {"frame_%05u_left.png", "frame_%05u_right.png"}};
    return names[kind == HS_RUN_PNG ? 2 : kind == HS_RUN_EXR ? 1 : 0][eye ? 1 : 0];
}

hs_run_kind hs_run_kind_of(const char *dir)
{
    static const hs_run_kind kinds[3] = {HS_RUN_LINEAR, HS_RUN_EXR, HS_RUN_PNG};
    for (int k = 0; k < 3; k++) {
        hs_frame_pattern pat;
        uint32_t first;
        if (hs_frame_pattern_parse(hs_run_pattern(kinds[k], 0), &pat) &&
            hs_frame_pattern_first(dir, &pat, &first))
            return kinds[k];
    }
    return HS_RUN_NONE;
}

static xrsc_result read_png(const char *path, float **out_rgba, uint32_t *out_w, uint32_t *out_h,
                            xrsc_diag *diag)
{
    png_image img;
    memset(&img, 0, sizeof(img));
    img.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file(&img, path))
        return u_diag_set(diag, XRSC_ERROR_IO, path, 0, "", "cannot read PNG: %s", img.message);
    img.format = PNG_FORMAT_RGB;
    size_t n = (size_t)img.width * img.height;
    uint8_t *rgb = malloc(PNG_IMAGE_SIZE(img));
    float *rgba = malloc(n * 4 * sizeof(float));
    if (!rgb || !rgba || !png_image_finish_read(&img, NULL, rgb, 0, NULL)) {
        xrsc_result res = u_diag_set(diag, rgb && rgba ? XRSC_ERROR_IO : XRSC_ERROR_OUT_OF_MEMORY,
                                     path, 0, "", "cannot decode PNG: %s", img.message);
        png_image_free(&img);
        free(rgb);
        free(rgba);
        return res;
    }
    for (size_t i = 0; i < n; i++) {
        for (int c = 0; c < 3; c++)
            rgba[i * 4 + c] = hs_srgb_to_linear((float)rgb[i * 3 + c] / 255.0f);
        rgba[i * 4 + 3] = 1.0f;
    }
    free(rgb);
    *out_rgba = rgba;
    *out_w = img.width;
    *out_h = img.height;
    return XRSC_OK;
}

xrsc_result hs_read_frame(const char *path, float **out_rgba, uint32_t *out_w, uint32_t *out_h,
                          bool *out_tonemapped, xrsc_diag *diag)
{
    size_t n = strlen(path);
    bool png = n > 4 && !strcmp(path + n - 4, ".png");
    bool exr = n > 4 && !strcmp(path + n - 4, ".exr");
    if (out_tonemapped)
        *out_tonemapped = png;
    if (exr)
        return hs_read_exr(path, out_rgba, NULL, out_w, out_h, diag);
    return png ? read_png(path, out_rgba, out_w, out_h, diag)
               : hs_read_pfm(path, out_rgba, out_w, out_h, diag);
}

static bool has_kind(const char *dir, hs_run_kind kind)
{
    hs_frame_pattern pat;
    uint32_t first;
    return hs_frame_pattern_parse(hs_run_pattern(kind, 0), &pat) &&
           hs_frame_pattern_first(dir, &pat, &first);
}

hs_run_kind hs_run_common_kind(const char *a, const char *b, xrsc_diag *diag)
{
    if (has_kind(a, HS_RUN_LINEAR) && has_kind(b, HS_RUN_LINEAR))
        return HS_RUN_LINEAR;
    if (has_kind(a, HS_RUN_EXR) && has_kind(b, HS_RUN_EXR))
        return HS_RUN_EXR;
    if (has_kind(a, HS_RUN_PNG) && has_kind(b, HS_RUN_PNG))
        return HS_RUN_PNG;
    const char *lacking = hs_run_kind_of(a) == HS_RUN_NONE ? a : b;
    if (hs_run_kind_of(lacking) == HS_RUN_NONE)
        u_diag_set(diag, XRSC_ERROR_IO, lacking, 0, "",
                   "no frame_NNNNN_left.pfm, .exr or .png in this folder");
    else
        u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, lacking, 0, "",
                   "the runs hold no frames of one kind (PFM, EXR or PNG) in common: write "
                   "both with --write linear (or the same kind)");
    return HS_RUN_NONE;
}
