// SPDX-License-Identifier: MIT
/**
 * @file test_firefly.c
 * @brief The sample cache's firefly rule (issue 19 item 3, xrsc_samplecache_options
 *        .firefly_clamp), under the validation layer (zero errors asserted).
 *
 * scenes/cornell.gltf, 2 x T_W x T_H, T_FRAMES frames of a still view, `samplecache` without
 * a blend:
 * - k = 1 (every observation above its sample's mean is cut to it): the image changes and
 *   its mean luminance drops (clamping only removes energy);
 * - k in (0, 1): XRSC_ERROR_INVALID_ARGUMENT.
 */
#include "test_samplecache_util.h"
#include "testing.h"
#include "xrsc/xrsc.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define T_W 32u
#define T_H 32u
#define T_FRAMES 8u

static bool render(xrsc_context *ctx, xrsc_scene *scene, const xrsc_frame *f0, float k,
                   float *out)
{
    xrsc_renderer_options ro = {.width = T_W, .height = T_H, .method = XRSC_METHOD_SAMPLECACHE};
    ro.samplecache.firefly_clamp = k;
    xrsc_renderer *r = NULL;
    xrsc_diag diag = {0};
    xrsc_result res = xrsc_renderer_create(ctx, scene, &ro, &r, &diag);
    xrsc_frame f = *f0;
    for (uint32_t i = 0; i < T_FRAMES && res == XRSC_OK; i++) {
        f.frame_index = i;
        res = xrsc_renderer_render(r, &f);
    }
    size_t layer = (size_t)T_W * T_H * 4;
    for (uint32_t e = 0; e < 2 && res == XRSC_OK; e++)
        res = xrsc_renderer_read(r, e, XRSC_OUTPUT_COLOR, out + e * layer, layer * sizeof(float));
    CHECK_EQ_INT(res, XRSC_OK);
    if (res != XRSC_OK)
        tsc_print_diag(&diag);
    xrsc_renderer_destroy(&r);
    return res == XRSC_OK;
}

static double mean_luminance(const float *img, size_t pixels)
{
    double s = 0.0;
    for (size_t p = 0; p < pixels; p++)
        s += 0.2126 * img[4 * p] + 0.7152 * img[4 * p + 1] + 0.0722 * img[4 * p + 2];
    return s / (double)pixels;
}

static void test_firefly_rule(void)
{
    xrsc_context_options co = {.validation = true};
    xrsc_context *ctx = NULL;
    xrsc_diag diag = {0};
    CHECK_EQ_INT(xrsc_context_create(&co, &ctx, &diag), XRSC_OK);
    xrsc_scene *scene = NULL;
    if (ctx)
        CHECK_EQ_INT(xrsc_scene_load(ctx, t_source_path("scenes/cornell.gltf"), NULL, &scene,
                                     &diag),
                     XRSC_OK);
    if (!scene) {
        tsc_print_diag(&diag);
        xrsc_context_destroy(&ctx);
        return;
    }
    xrsc_scene_info info;
    xrsc_scene_get_info(scene, &info);
    xrsc_frame f = tsc_headset_frame(info.viewpoint, 0);
    size_t pixels = 2u * T_W * T_H;
    float *off = calloc(pixels * 4, sizeof(float)), *k1 = calloc(pixels * 4, sizeof(float));
    bool ok = render(ctx, scene, &f, 0.0f, off) && render(ctx, scene, &f, 1.0f, k1);
    if (ok) {
        double l_off = mean_luminance(off, pixels), l_k1 = mean_luminance(k1, pixels);
        printf("  mean luminance: off %.5f, k = 1 %.5f\n", l_off, l_k1);
        CHECK(memcmp(off, k1, pixels * 4 * sizeof(float)) != 0);
        CHECK(l_k1 < l_off);
    }
    xrsc_renderer_options bad = {.width = T_W, .height = T_H, .method = XRSC_METHOD_SAMPLECACHE};
    bad.samplecache.firefly_clamp = 0.5f;
    xrsc_renderer *r = NULL;
    CHECK_EQ_INT(xrsc_renderer_create(ctx, scene, &bad, &r, &diag), XRSC_ERROR_INVALID_ARGUMENT);
    CHECK(r == NULL);
    free(off);
    free(k1);
    xrsc_scene_destroy(&scene);
    CHECK_EQ_INT(xrsc_context_validation_errors(ctx), 0);
    xrsc_context_destroy(&ctx);
}

int main(void)
{
    RUN(test_firefly_rule);
    return t_finish();
}
